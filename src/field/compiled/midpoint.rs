//! f at the point of a cell where the bisection wants it next (the
//! mean-value form's midpoint), computed in the cell enclosure's own pass:
//! `let pv{id}` in the scalar domain beside each `v{id}`.
//!
//! A term loop's step is mostly overhead (table reads, the step's
//! branches, the loop), which a scalar evaluation pays again in full: for
//! a polynomial of thousands of monomials the midpoints cost most of what
//! the cells do. In the enclosure's loop a point adds a step's scalar
//! operations only (for a Horner step, one product and sum). The values
//! are the scalar field's own operations in its order (`eval_s`) on the
//! same f32 constants (an enclosure's first float in the table is the
//! rounded constant), so f there is the number a separate evaluation
//! gives, which the traversal relies on when a child cell reuses it as an
//! end.

use super::Hook;
use super::emit::{Names, named_rhs};
use super::term_loops;
use crate::ir::{Domain, Ir, NodeId};
use std::fmt::Write;

/// The names of the point's values; the point is `pm`, at the traversal's
/// `g_cell_s_mid` on the ray.
const NAMES: Names = Names {
    node: "pv",
    temp: "pw",
    vars: ["pm.x", "pm.y", "pm.z", "F.time"],
};

/// Whether the cell enclosure of `ir` computes f at the midpoint: a
/// formula with term loops (written-out code has no loop overhead to
/// share, and a second copy of it would lengthen the driver's compile)
/// whose tables give their constants' values
/// ([`term_loops::Loop::point_first`]: not a run of terms that are costly
/// at a point).
pub(crate) fn fused(ir: &Ir) -> bool {
    let plan = term_loops::plan(ir);
    !ir.is_csg() && !plan.is_empty() && plan.loops.iter().all(|l| l.point_first)
}

/// The statements that start the point's evaluation.
pub(crate) const HEAD: &str = "    let pm = o + dir * g_cell_s_mid;\n";

/// What ends it: the traversal's `g_cell_f_mid` takes f at the point.
pub(crate) fn tail(root: NodeId) -> String {
    format!("    g_cell_f_mid = pv{root};\n")
}

/// The point's statement for what the evaluator just wrote.
pub(crate) fn emit(out: &mut String, ir: &Ir, nn: &[bool], hook: &Hook) {
    match hook {
        Hook::Node(id, op) => {
            let rhs = named_rhs(out, Domain::Scalar, *id, *op, ir, nn, &NAMES);
            let _ = writeln!(out, "    let pv{id} = {rhs};");
        }
        Hook::Slot { id, point } => {
            let point = point.as_deref().expect("a fused formula's loops give their constants' values");
            let _ = writeln!(out, "    let pv{id} = {point};");
        }
        Hook::Begin { acc, seed } => {
            let init = seed.map_or_else(|| "0.0".to_string(), |s| format!("pv{s}"));
            let _ = writeln!(out, "    var pv{acc} = {init};");
        }
        Hook::Step { acc, next } => {
            let _ = writeln!(out, "    pv{acc} = pv{next};");
        }
        Hook::End { acc, end } => {
            let _ = writeln!(out, "    let pv{end} = pv{acc};");
        }
    }
}

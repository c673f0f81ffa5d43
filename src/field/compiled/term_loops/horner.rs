//! A polynomial of many monomials as one loop over its Horner form. The
//! semantic pass writes a long collected sum nested in x, then y, then z
//! (`sema::terms`), and a program may write one term by term; either way
//! no two terms have one shape, so no run forms, and written out such a
//! polynomial is a kernel lavapipe builds for minutes. Here its monomials,
//! sorted by powers, become steps of a three-register machine over a
//! table:
//!
//! - `C c`: r ← r · z + c (the innermost level, one power down);
//! - `Z k`: r ← r · z^k;
//! - `Y k`: q ← q · y^k + r, r ← 0 (a z-polynomial folded into the y level);
//! - `X k`: p ← p · x^k + q, q ← 0.
//!
//! which is the Horner form x^a(… y^b(… z^e(… + c) …) …) step by step: the
//! nested form's enclosures, one product a step. Most steps are `C`, whose
//! slot of a texel is the coefficient's enclosure, so a texel holds two
//! steps; the others are marked by a NaN in the slot's first word, its
//! payload the kind and the power. A step's kind is the same for every lane
//! (all read one texel), so lavapipe runs one arm. The slope along the ray
//! follows the same steps, through the derivative hooks of their
//! operations.

use super::emit::LoopEmitter;
use crate::field::compiled::{value_rhs, Hook};
use crate::analysis::monomials::{Monomial, Polynomial};
use crate::codegen::f32_enclosure;
use crate::ir::{Func2, NodeId, Op, Var};
use std::fmt::Write;

/// Fewest monomials of a polynomial made a Horner loop. A step costs
/// several times what the written-out form's multiply-add does (a texel
/// read, a product of intervals, the step's branches), so a polynomial that
/// compiles quickly written out (`mono3000`'s collected 339 monomials,
/// scripts/big-formulas.py) renders much faster so. From this many, the
/// written-out form is past what `auto` compiles rather than runs as a tape
/// (`choice::CROSSOVER_BISECT_IA` instructions), and the loop is several
/// times faster than the tape (docs/notes/2026-12-07-fixed-costs.md).
pub const MIN_MONOMIALS: usize = 1024;

/// Most monomials the expansions of all nodes hold together (a Horner
/// form's nodes each hold the monomials below them).
pub const EXPANSION_BUDGET: usize = 1 << 21;

/// Steps an iteration runs: fewer made the loop faster down to 8 (a
/// smaller body for the core to run), and 4 would double the iterations
/// the work limit counts for no gain (docs/notes/2026-12-07-fixed-costs.md).
const UNROLL: usize = 8;

/// Nodes a step's arms hold (the weight `auto` gives an unrolled step).
const STEP_NODES: usize = 12;

/// One polynomial computed by a Horner loop.
#[derive(Debug, Clone)]
pub struct Horner {
    /// The node whose value the loop computes.
    pub end: NodeId,
    /// Its monomials.
    pub monomials: usize,
    /// The nodes of x, y and z (`None` for a variable the polynomial lacks).
    pub vars: [Option<NodeId>; 3],
    /// Steps an iteration runs.
    pub unroll: usize,
    /// Iterations.
    pub iterations: usize,
    /// First texel of the steps.
    pub base: u32,
}

impl Horner {
    /// What the generated code holds, in nodes.
    pub fn weight(&self) -> usize {
        self.unroll * STEP_NODES
    }
}

/// A step of the nested form: r ← r · z^k + c, and the folds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Step {
    Z(u32, f64),
    Y(u32),
    X(u32),
}

/// A step of the machine ([`Step`]s as the table holds them).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Instr {
    C(f64),
    Z(u32),
    Y(u32),
    X(u32),
}

/// The machine's steps for `steps`. `Z k c` is `C c` where k is 1, and
/// also where k is 0: r is 0 there (a group's first monomial), so r · z is
/// too. A larger k takes a `Z` to k − 1 first.
fn instructions(steps: &[Step]) -> Vec<Instr> {
    let mut out = Vec::with_capacity(steps.len() + steps.len() / 8);
    for &s in steps {
        match s {
            Step::Z(k, c) if k <= 1 => out.push(Instr::C(c)),
            Step::Z(k, c) if c == 0.0 => out.push(Instr::Z(k)),
            Step::Z(2, c) => out.extend([Instr::C(0.0), Instr::C(c)]),
            Step::Z(k, c) => out.extend([Instr::Z(k - 1), Instr::C(c)]),
            Step::Y(k) => out.push(Instr::Y(k)),
            Step::X(k) => out.push(Instr::X(k)),
        }
    }
    out
}

/// The first word of a step that is not `C`: a quiet NaN, its payload the
/// kind and the power.
const MARK: u32 = 0x7fc0_0000;

/// The steps that compute `poly`: its monomials by decreasing powers of x,
/// then y, then z; each z-polynomial shifted to z^0 and folded into the y
/// level, each y-polynomial shifted and folded into the x level, the last
/// shifted to x^0.
fn steps(poly: &Polynomial) -> Vec<Step> {
    let mut monos: Vec<Monomial> = poly.monomials().collect();
    monos.sort_by(|a, b| b.exps.cmp(&a.exps));
    let mut out = Vec::with_capacity(monos.len() * 5 / 4 + 8);
    // The powers of the monomial before, and of the groups last folded.
    let (mut prev, mut folded_b, mut folded_a): (Option<[u32; 3]>, Option<u32>, Option<u32>) = (None, None, None);
    let close_z = |out: &mut Vec<Step>, p: [u32; 3], folded_b: &mut Option<u32>| {
        if p[2] > 0 {
            out.push(Step::Z(p[2], 0.0));
        }
        out.push(Step::Y(folded_b.map_or(0, |b| b - p[1])));
        *folded_b = Some(p[1]);
    };
    let close_y = |out: &mut Vec<Step>, p: [u32; 3], folded_b: &mut Option<u32>, folded_a: &mut Option<u32>| {
        if p[1] > 0 {
            out.push(Step::Y(p[1]));
        }
        out.push(Step::X(folded_a.map_or(0, |a| a - p[0])));
        *folded_a = Some(p[0]);
        *folded_b = None;
    };
    for m in &monos {
        let [a, b, e] = m.exps;
        match prev {
            Some(p) if p[0] == a && p[1] == b => out.push(Step::Z(p[2] - e, m.coef)),
            Some(p) => {
                close_z(&mut out, p, &mut folded_b);
                if p[0] != a {
                    close_y(&mut out, p, &mut folded_b, &mut folded_a);
                }
                out.push(Step::Z(0, m.coef));
            }
            None => out.push(Step::Z(0, m.coef)),
        }
        prev = Some(m.exps);
    }
    if let Some(p) = prev {
        close_z(&mut out, p, &mut folded_b);
        close_y(&mut out, p, &mut folded_b, &mut folded_a);
        if p[0] > 0 {
            out.push(Step::X(p[0]));
        }
    }
    out
}

/// Lays out the steps of `poly` (node `end`) at the end of `table` and
/// returns the loop: two steps a texel, a `C` step as its coefficient's
/// enclosure with the nearest f32 first (the scalar domain's), the others
/// as their mark.
pub(super) fn lay_out(table: &mut Vec<[u32; 4]>, end: NodeId, vars: [Option<NodeId>; 3], poly: &Polynomial) -> Horner {
    let mut s = instructions(&steps(poly));
    let unroll = UNROLL;
    // Padded with steps that change nothing: r is 0 at the end.
    s.resize(s.len().div_ceil(unroll) * unroll, Instr::C(0.0));
    let base = table.len() as u32;
    let slot = |i: &Instr| -> [u32; 2] {
        let mark = |kind: u32, k: u32| [MARK | kind << 8 | k, 0];
        match *i {
            Instr::C(c) => {
                let (near, lo, hi) = f32_enclosure(c);
                let other = if near == lo { hi } else { lo };
                [near.to_bits(), other.to_bits()]
            }
            Instr::Z(k) => mark(0, k),
            Instr::Y(k) => mark(1, k),
            Instr::X(k) => mark(2, k),
        }
    };
    for pair in s.chunks(2) {
        let (a, b) = (slot(&pair[0]), slot(&pair[1]));
        table.push([a[0], a[1], b[0], b[1]]);
    }
    Horner { end, monomials: poly.terms.len(), vars, unroll, iterations: s.len() / unroll, base }
}

impl LoopEmitter<'_> {
    /// The Horner loop `h`: three accumulators, each step's arm by its
    /// kind, the polynomial's value into `v{end}`.
    pub fn emit_horner(&mut self, out: &mut String, h: &Horner, hook: &mut impl FnMut(&mut String, Hook)) {
        let p = self.domain.prefix();
        let regs = [self.fresh_id(), self.fresh_id(), self.fresh_id()];
        for &r in &regs {
            let _ = writeln!(out, "    var v{r} = {p}_const(0.0);");
            hook(out, Hook::Begin { acc: r, seed: None });
        }
        let [r, q, x_level] = regs;
        let _ = writeln!(out, "    for (var i{r} = 0u; i{r} < select(0u, {}u, admitted); i{r} = i{r} + 1u) {{", h.iterations);
        for k in 0..h.unroll {
            let (t, first, second) = (format!("t{r}_{}", k / 2), ["x", "z"][k % 2], ["y", "w"][k % 2]);
            if k % 2 == 0 {
                let _ = writeln!(out, "    let {t} = field_table({}u + i{r} * {}u + {}u);", h.base, h.unroll / 2, k / 2);
            }
            let _ = writeln!(out, "    let u{r}_{k} = bitcast<u32>({t}.{first});");
            let _ = writeln!(out, "    if ((u{r}_{k} & {MARK}u) != {MARK}u) {{");
            // A coefficient's slot is its enclosure, the nearest f32 first.
            let c = super::slot_read(p, &format!("{t}.{first}"), &format!("{t}.{second}"), None);
            let added = self.emit_constant(out, &c.expr, &format!("{t}.{first}"), hook);
            let z = match h.vars[2] {
                Some(v) => v,
                None => self.emit_constant(out, &format!("{p}_const(1.0)"), "1.0", hook),
            };
            self.emit_horner_step(out, r, z, added, hook);
            let power = format!("(u{r}_{k} & 255u)");
            let _ = writeln!(out, "    }} else if ((u{r}_{k} & 0xff00u) == 0u) {{");
            let raised = self.emit_power(out, h.vars[2], &power, hook);
            let product = self.emit_op(out, Op::Mul(r, raised), hook);
            let _ = writeln!(out, "    v{r} = v{product};");
            hook(out, Hook::Step { acc: r, next: product });
            let _ = writeln!(out, "    }} else if ((u{r}_{k} & 0xff00u) == 0x100u) {{");
            self.emit_fold(out, q, h.vars[1], &power, r, hook);
            self.emit_reset(out, r, hook);
            out.push_str("    } else {\n");
            self.emit_fold(out, x_level, h.vars[0], &power, q, hook);
            self.emit_reset(out, q, hook);
            out.push_str("    }\n");
        }
        out.push_str("    }\n");
        let _ = writeln!(out, "    let v{} = v{x_level};", h.end);
        hook(out, Hook::End { acc: x_level, end: h.end });
    }

    /// `acc ← acc · var^power + v{added}` (`power` a WGSL `u32`). The
    /// power 1, a step to the next power down, is most of a polynomial's
    /// steps: it multiplies by the variable itself, without a power by
    /// squaring (and its slope without the power's slope).
    fn emit_fold(&mut self, out: &mut String, acc: NodeId, var: Option<NodeId>, power: &str, added: NodeId, hook: &mut impl FnMut(&mut String, Hook)) {
        if let Some(v) = var {
            let _ = writeln!(out, "    if ({power} == 1u) {{");
            self.emit_horner_step(out, acc, v, added, hook);
            out.push_str("    } else {\n");
        }
        let raised = self.emit_power(out, var, power, hook);
        self.emit_horner_step(out, acc, raised, added, hook);
        if var.is_some() {
            out.push_str("    }\n");
        }
    }

    /// `acc ← acc · v{raised} + v{added}`.
    fn emit_horner_step(&mut self, out: &mut String, acc: NodeId, raised: NodeId, added: NodeId, hook: &mut impl FnMut(&mut String, Hook)) {
        let product = self.emit_op(out, Op::Mul(acc, raised), hook);
        let sum = self.emit_op(out, Op::Add(product, added), hook);
        let _ = writeln!(out, "    v{acc} = v{sum};");
        hook(out, Hook::Step { acc, next: sum });
    }

    /// `var^power` by squaring (`power` a WGSL `u32`); 1 for a variable the
    /// polynomial lacks.
    fn emit_power(&mut self, out: &mut String, var: Option<NodeId>, power: &str, hook: &mut impl FnMut(&mut String, Hook)) -> NodeId {
        let p = self.domain.prefix();
        match var {
            Some(v) => {
                let k = self.emit_constant(out, &format!("{p}_const(f32({power}))"), &format!("f32({power})"), hook);
                self.emit_op(out, Op::Call2(Func2::PowN, v, k), hook)
            }
            None => self.emit_constant(out, &format!("{p}_const(1.0)"), "1.0", hook),
        }
    }

    /// `acc ← 0`.
    fn emit_reset(&mut self, out: &mut String, acc: NodeId, hook: &mut impl FnMut(&mut String, Hook)) {
        let zero = self.emit_constant(out, &format!("{}_const(0.0)", self.domain.prefix()), "0.0", hook);
        let _ = writeln!(out, "    v{acc} = v{zero};");
        hook(out, Hook::Step { acc, next: zero });
    }

    /// A value the loop reads (its slope is 0) under a fresh name; `point`
    /// is its f32 value.
    fn emit_constant(&mut self, out: &mut String, expr: &str, point: &str, hook: &mut impl FnMut(&mut String, Hook)) -> NodeId {
        let f = self.fresh_id();
        let _ = writeln!(out, "    let v{f} = {expr};");
        hook(out, Hook::Slot { id: f, point: Some(point.to_string()) });
        f
    }

    /// An operation on named values under a fresh name.
    fn emit_op(&mut self, out: &mut String, op: Op, hook: &mut impl FnMut(&mut String, Hook)) -> NodeId {
        let f = self.fresh_id();
        let rhs = value_rhs(out, self.domain, f, op, self.ir, self.nn);
        let _ = writeln!(out, "    let v{f} = {rhs};");
        hook(out, Hook::Node(f, op));
        f
    }
}

/// The nodes of x, y and z among `ir`'s live nodes.
pub(super) fn variables(ir: &crate::ir::Ir, live: &[NodeId]) -> [Option<NodeId>; 3] {
    let mut vars = [None; 3];
    for &n in live {
        if let Op::Var(v @ (Var::X | Var::Y | Var::Z)) = ir.nodes[n as usize] {
            vars[v as usize].get_or_insert(n);
        }
    }
    vars
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The machine's steps run on f64 numbers give the polynomial's value.
    #[test]
    fn the_steps_compute_the_polynomial() {
        let f = crate::Formula::compile("<t>", "0.5*x^3*y^2*z + 2*x^3*z^4 - x*y^5 + 3*y^2 + 7*z^3 - 1.25 + 0.1*x^2*y^2*z^2").unwrap();
        let live = f.ir.live();
        let poly = crate::analysis::monomials::polynomials(&f.ir, &live, 1 << 16)[f.ir.root as usize].clone().expect("a polynomial");
        let s = instructions(&steps(&poly));
        assert!(s.iter().filter(|i| matches!(i, Instr::C(_))).count() >= poly.terms.len());
        for pt in [[0.3f64, -1.2, 0.7], [1.5, 0.25, 2.0], [-0.8, 0.9, -1.1]] {
            let (mut r, mut q, mut p) = (0.0f64, 0.0f64, 0.0f64);
            for step in &s {
                match *step {
                    Instr::C(c) => r = r * pt[2] + c,
                    Instr::Z(k) => r *= pt[2].powi(k as i32),
                    Instr::Y(k) => (q, r) = (q * pt[1].powi(k as i32) + r, 0.0),
                    Instr::X(k) => (p, q) = (p * pt[0].powi(k as i32) + q, 0.0),
                }
            }
            let want = crate::reference::eval_scalar(&f.ir, [pt[0], pt[1], pt[2], 0.0], &[]);
            assert!((p - want).abs() < 1e-12 * (1.0 + want.abs()), "{p} against {want} at {pt:?}");
            assert_eq!((r, q), (0.0, 0.0));
        }
    }
}

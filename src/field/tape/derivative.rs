//! The derivative along the ray of a tape's formula, built symbolically on
//! the host as more tape nodes by the rules of the generated `evald_*`
//! functions (`derivative::rule`, written once for both), so the tape's
//! monotonicity test proves exactly what the compiled one proves; the
//! interpreter only runs `op_*` operations and the same derivative helpers
//! (`dmin`, `dmax`, `dsign`, `dfloor`, `whole`). Building it here rather than
//! carrying a derivative through the interpreter (forward mode) keeps one
//! set of cases in the shader, whose compile time is what the tape exists to cap.

use crate::field::compiled::derivative::{rule, Terms, D};
use super::{Builder, Code, INPUT_DX};
use crate::ir::{Ir, NodeId};

/// Appends the derivative nodes of every live IR node to `b` (`values` maps
/// IR nodes to their value nodes) and returns the root's derivative node (a
/// constant 0 when it is identically 0).
pub(crate) fn derivative_program(ir: &Ir, values: &[u32], b: &mut Builder) -> u32 {
    let mut d: Vec<Option<u32>> = vec![None; ir.nodes.len()];
    for id in ir.live() {
        d[id as usize] = rule(&mut Tape { b, values }, id, ir.nodes[id as usize], &d);
        if let Some(n) = d[id as usize] {
            b.partner.entry(n).or_insert(values[id as usize]);
        }
    }
    match d[ir.root as usize] {
        Some(n) => n,
        None => b.konst(0.0),
    }
}

/// The tape's terms: nodes appended to the builder.
struct Tape<'a> {
    b: &'a mut Builder,
    values: &'a [u32],
}

impl Terms for Tape<'_> {
    type T = u32;
    fn value(&mut self, n: NodeId) -> u32 {
        self.values[n as usize]
    }
    fn konst(&mut self, c: f32) -> u32 {
        self.b.konst(f64::from(c))
    }
    fn direction(&mut self, axis: u32) -> u32 {
        self.b.input(INPUT_DX + axis)
    }
    fn un(&mut self, op: D, a: u32) -> u32 {
        self.b.un(code(op), a)
    }
    fn bin(&mut self, op: D, a: u32, b: u32) -> u32 {
        self.b.bin(code(op), a, b)
    }
    fn dminmax(&mut self, max: bool, args: [u32; 4]) -> u32 {
        self.b.push(if max { Code::Dmax } else { Code::Dmin }, args, 0.0)
    }
    fn odd_power(&mut self, _id: NodeId, q: u32, m: u32) -> u32 {
        self.b.chain(q, m)
    }
    fn bind(&mut self, _id: NodeId, _tag: &str, x: u32) -> u32 {
        x // a node is computed once already
    }
    fn whole(&mut self) -> u32 {
        unreachable!("user functions are refused before flattening")
    }
    fn pown_slope(&mut self, _a: u32, _n: u32) -> u32 {
        unreachable!("pown is never in an IR, only in the compiled field's generated code")
    }
}

/// The tape operation of a derivative term's operation.
fn code(op: D) -> Code {
    match op {
        D::Neg => Code::Neg,
        D::Sqr => Code::Sqr,
        D::Sin => Code::Sin,
        D::Cos => Code::Cos,
        D::Log => Code::Log,
        D::Sinh => Code::Sinh,
        D::Cosh => Code::Cosh,
        D::Sign => Code::Sign,
        D::Add => Code::Add,
        D::Sub => Code::Sub,
        D::Mul => Code::Mul,
        D::Div => Code::Div,
        D::Max => Code::Max,
        D::Dsign => Code::Dsign,
        D::Dfloor => Code::Dfloor,
    }
}

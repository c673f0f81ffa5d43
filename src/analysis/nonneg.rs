//! Which nodes of a formula are never negative.

use crate::ir::{Ir, NodeId, Op};

/// Which nodes are never negative, by their form: even powers, |a|,
/// sqrt, exp and cosh, non-negative constants, and sums, products, minima
/// and quotients by positive constants of such nodes (a maximum needs one).
/// An interval product of two such values is [lo·lo, hi·hi], and of any
/// interval d by such a v two products, not four and six comparisons
/// (`ia_mul_nonneg`, `ia_mul_by_nonneg`): the decocube's three factors,
/// sums of squares, and their product's slope.
pub(crate) fn nonneg(ir: &Ir) -> Vec<bool> {
    use crate::ir::{Func1, Func2};
    let mut nn: Vec<bool> = Vec::with_capacity(ir.nodes.len());
    for op in &ir.nodes {
        let g = |n: &NodeId| nn.get(*n as usize).copied().unwrap_or(false);
        let konst = |n: &NodeId| match ir.nodes.get(*n as usize) {
            Some(Op::Const(c)) => Some(*c),
            _ => None,
        };
        let v = match op {
            Op::Const(c) => *c >= 0.0,
            Op::PowI(a, n) => n % 2 == 0 || g(a),
            Op::Add(a, b) | Op::Mul(a, b) => g(a) && g(b),
            Op::Div(a, b) => g(a) && konst(b).is_some_and(|c| c > 0.0),
            Op::Call1(Func1::Abs | Func1::Sqrt | Func1::Exp | Func1::Cosh, _) => true,
            Op::Call2(Func2::Min, a, b) => g(a) && g(b),
            Op::Call2(Func2::Max, a, b) => g(a) || g(b),
            _ => false,
        };
        nn.push(v);
    }
    nn
}

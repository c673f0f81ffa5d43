//! CPU reference evaluation of the IR in f64: the test oracle and the
//! backend of `isotrace eval --cpu`.
//!
//! Three number domains, each with the same rules as its WGSL library in
//! `templates/domains/` (so device and CPU results agree up to f32
//! rounding), but computed in f64 without the libraries' padding:
//!
//! * scalar ([`eval_scalar`]): a point value, NaN where the formula is undefined;
//! * interval ([`eval_interval`], module [`interval`]): mirrors `interval.wgsl`;
//! * reduced affine ([`eval_affine`], module [`affine`]): mirrors `affine.wgsl`.
//!
//! Every domain is *strict* like the generated evaluators: when a sqrt, log
//! or real-power node is undefined (NaN, or an empty enclosure), the whole
//! formula is undefined, even if that node's value is later discarded (by
//! `min`, `0 * …`, `sign`, …).
//!
//! [`scalar_op`] is also the constant folder of the semantic pass, so folding
//! and evaluation can never disagree.

pub mod affine;
pub mod interval;

pub use affine::{affine_from_interval, affine_range, eval_affine};
pub use interval::eval_interval;

use crate::ir::{Func1, Func2, Func3, Ir, NodeId, Op, Var};

/// Applies one operation to scalar arguments (in operand order).
/// Undefined points (sqrt of a negative, log of a negative, a real power of
/// a negative) give NaN; `log(0)` is −∞.
pub fn scalar_op(op: &Op, a: &[f64]) -> f64 {
    match *op {
        Op::Const(c) => c,
        // Inline WGSL functions exist only on the device.
        Op::Var(_) | Op::Param(_) | Op::User(..) => f64::NAN,
        Op::Neg(_) => -a[0],
        Op::Add(..) => a[0] + a[1],
        Op::Sub(..) => a[0] - a[1],
        Op::Mul(..) => a[0] * a[1],
        Op::Div(..) => a[0] / a[1],
        Op::PowI(_, n) => a[0].powi(n as i32),
        Op::Call1(f, _) => {
            let x = a[0];
            match f {
                Func1::Sqrt => x.sqrt(),
                Func1::Exp => x.exp(),
                Func1::Log => if x > 0.0 { x.ln() } else if x == 0.0 { f64::NEG_INFINITY } else { f64::NAN },
                Func1::Sin => x.sin(),
                Func1::Cos => x.cos(),
                Func1::Tan => x.tan(),
                Func1::Atan => x.atan(),
                Func1::Sinh => x.sinh(),
                Func1::Cosh => x.cosh(),
                Func1::Tanh => x.tanh(),
                Func1::Abs => x.abs(),
                Func1::Sign => if x > 0.0 { 1.0 } else if x < 0.0 { -1.0 } else { 0.0 },
                Func1::Floor => x.floor(),
            }
        }
        Op::Call2(f, ..) => {
            let (x, y) = (a[0], a[1]);
            match f {
                Func2::Pow => pow_pos(x, y),
                Func2::PowN => x.powi(y as i32),
                Func2::Atan2 => x.atan2(y),
                Func2::Min => x.min(y),
                Func2::Max => x.max(y),
            }
        }
        Op::Call3(f, ..) => match f {
            Func3::Clamp => a[0].max(a[1]).min(a[2]),
            Func3::Mix => a[0] + (a[1] - a[0]) * a[2],
        },
    }
}

/// `a^b` for a real exponent: defined for a ≥ 0 only.
pub fn pow_pos(a: f64, b: f64) -> f64 {
    if a < 0.0 { f64::NAN } else { a.powf(b) }
}

/// Evaluates the formula at a point `[x, y, z, t]`; `params` in parameter
/// order. Strict: NaN when any live sqrt / log / real-power node is NaN
/// (the point is outside that function's domain), matching the generated
/// evaluators, which return empty in that case.
pub fn eval_scalar(ir: &Ir, p: [f64; 4], params: &[f64]) -> f64 {
    evaluate::<f64>(ir, p, params)
}

/// Position of a variable in `[x, y, z, t]`.
pub fn var_index(v: Var) -> usize {
    match v {
        Var::X => 0,
        Var::Y => 1,
        Var::Z => 2,
        Var::T => 3,
    }
}

/// A number domain of the reference evaluator.
pub(crate) trait Value: Copy {
    /// A literal or parameter value.
    fn constant(c: f64) -> Self;
    /// One operation on already computed operands (in operand order).
    fn apply(op: &Op, args: &[Self]) -> Self;
    /// Undefined: NaN for points, empty for enclosures.
    fn is_undefined(&self) -> bool;
    /// The canonical undefined value.
    fn undefined() -> Self;
}

impl Value for f64 {
    fn constant(c: f64) -> f64 {
        c
    }
    fn apply(op: &Op, args: &[f64]) -> f64 {
        scalar_op(op, args)
    }
    fn is_undefined(&self) -> bool {
        self.is_nan()
    }
    fn undefined() -> f64 {
        f64::NAN
    }
}

/// The operands of `op`, copied out of `vals` without allocating.
pub(crate) fn operands<V: Value>(op: &Op, vals: &[V]) -> ([V; 3], usize) {
    let g = |n: NodeId| vals[n as usize];
    let u = V::undefined();
    match *op {
        Op::Const(_) | Op::Var(_) | Op::Param(_) => ([u, u, u], 0),
        Op::Neg(a) | Op::PowI(a, _) | Op::Call1(_, a) => ([g(a), u, u], 1),
        Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Call2(_, a, b) => ([g(a), g(b), u], 2),
        Op::Call3(_, a, b, c) => ([g(a), g(b), g(c)], 3),
        Op::User(..) => ([u, u, u], 0),
    }
}

/// Walks the live nodes once in `V`, with the generated evaluators'
/// strictness rule.
pub(crate) fn evaluate<V: Value>(ir: &Ir, vars: [V; 4], params: &[f64]) -> V {
    let mut vals: Vec<V> = vec![V::undefined(); ir.nodes.len()];
    let mut undefined = false;
    for id in ir.live() {
        let op = &ir.nodes[id as usize];
        let r = match *op {
            Op::Const(c) => V::constant(c),
            Op::Var(v) => vars[var_index(v)],
            Op::Param(i) => V::constant(params.get(i as usize).copied().unwrap_or(f64::NAN)),
            _ => {
                let (args, n) = operands(op, &vals);
                V::apply(op, &args[..n])
            }
        };
        undefined |= op.restricts_domain() && r.is_undefined();
        vals[id as usize] = r;
    }
    if undefined { V::undefined() } else { vals[ir.root as usize] }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ir(src: &str) -> Ir {
        crate::Formula::compile("<test>", src).unwrap().ir
    }

    #[test]
    fn scalar_is_strict() {
        // min discards the undefined operand, but the formula is still undefined.
        let f = ir("min(sqrt(x), 1)");
        assert!(eval_scalar(&f, [-1.0, 0.0, 0.0, 0.0], &[]).is_nan());
        assert_eq!(eval_scalar(&f, [4.0, 0.0, 0.0, 0.0], &[]), 1.0);
        let g = ir("0 * log(x) + y");
        assert!(eval_scalar(&g, [-1.0, 2.0, 0.0, 0.0], &[]).is_nan());
        assert_eq!(eval_scalar(&g, [1.0, 2.0, 0.0, 0.0], &[]), 2.0);
    }

    #[test]
    fn scalar_uses_params() {
        let f = ir("x^2 + r");
        assert_eq!(eval_scalar(&f, [3.0, 0.0, 0.0, 0.0], &[0.5]), 9.5);
    }
}

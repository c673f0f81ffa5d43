//! CPU reference evaluation of the IR in f64: the test oracle and the
//! backend of `isotrace eval --cpu`.
//!
//! [`scalar_op`] is also the constant folder of the semantic pass, so folding
//! and evaluation can never disagree.

use crate::ir::{Func1, Func2, Func3, Ir, Op, Var};

/// Applies one operation to scalar arguments (in operand order).
/// Undefined points (sqrt of a negative, log of ≤ 0, a real power of a
/// negative) give NaN.
pub fn scalar_op(op: &Op, a: &[f64]) -> f64 {
    match *op {
        Op::Const(c) => c,
        Op::Var(_) | Op::Param(_) => f64::NAN,
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

/// Evaluates the formula at a point. `params` in parameter order.
pub fn eval_scalar(ir: &Ir, p: [f64; 4], params: &[f64]) -> f64 {
    let mut v: Vec<f64> = Vec::with_capacity(ir.nodes.len());
    for op in &ir.nodes {
        let r = match *op {
            Op::Var(var) => p[var_index(var)],
            Op::Param(i) => params.get(i as usize).copied().unwrap_or(f64::NAN),
            _ => {
                let args: Vec<f64> = op.operands().iter().map(|&o| v[o as usize]).collect();
                scalar_op(op, &args)
            }
        };
        v.push(r);
    }
    v[ir.root as usize]
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

//! The derivative along the ray of a tape's formula, built symbolically on
//! the host as more tape nodes. The rules are those of the generated
//! `evald_*` functions (`derivative.rs`), term for term, so the tape's
//! monotonicity test proves exactly what the compiled one proves; the
//! interpreter only runs `op_*` operations and the same derivative helpers
//! (`dmin`, `dmax`, `dsign`, `dfloor`, `whole`). Building it here rather than
//! carrying a derivative through the interpreter (forward mode) keeps one
//! switch in the shader, whose compile time is what the tape exists to cap.

use super::tape::{Builder, Code, INPUT_DX};
use crate::ir::{Func1, Func2, Func3, Ir, NodeId, Op, Var};

/// Appends the derivative nodes of every live IR node to `b` (`values` maps
/// IR nodes to their value nodes) and returns the root's derivative node (a
/// constant 0 when it is identically 0).
pub(crate) fn derivative_program(ir: &Ir, values: &[u32], b: &mut Builder) -> u32 {
    let mut d: Vec<Option<u32>> = vec![None; ir.nodes.len()];
    for id in ir.live() {
        d[id as usize] = derivative(b, values, &d, id, ir.nodes[id as usize]);
        if let Some(n) = d[id as usize] {
            b.partner.entry(n).or_insert(values[id as usize]);
        }
    }
    match d[ir.root as usize] {
        Some(n) => n,
        None => b.konst(0.0),
    }
}

/// The derivative node of one IR node, `None` when it is identically 0.
fn derivative(b: &mut Builder, values: &[u32], d: &[Option<u32>], id: NodeId, op: Op) -> Option<u32> {
    let v = |n: NodeId| values[n as usize];
    let dv = |n: NodeId| d[n as usize];
    Some(match op {
        Op::Const(_) | Op::Param(_) | Op::Var(Var::T) => return None,
        Op::Var(Var::X) => b.input(INPUT_DX),
        Op::Var(Var::Y) => b.input(INPUT_DX + 1),
        Op::Var(Var::Z) => b.input(INPUT_DX + 2),
        Op::Neg(a) => {
            let da = dv(a)?;
            b.un(Code::Neg, da)
        }
        Op::Add(a, c) => match (dv(a), dv(c)) {
            (None, None) => return None,
            (Some(x), None) | (None, Some(x)) => x,
            (Some(x), Some(y)) => b.bin(Code::Add, x, y),
        },
        Op::Sub(a, c) => match (dv(a), dv(c)) {
            (None, None) => return None,
            (Some(x), None) => x,
            (None, Some(y)) => b.un(Code::Neg, y),
            (Some(x), Some(y)) => b.bin(Code::Sub, x, y),
        },
        Op::Mul(a, c) => product(b, v(a), v(c), dv(a), dv(c))?,
        Op::Div(a, c) => match (dv(a), dv(c)) {
            (None, None) => return None,
            (Some(da), None) => b.bin(Code::Div, da, v(c)),
            (da, Some(dc)) => {
                // (a'b − ab') / b², written as (a' − q·b') / b with q = a/b.
                let qd = b.bin(Code::Mul, v(id), dc);
                let num = match da {
                    None => b.un(Code::Neg, qd),
                    Some(da) => b.bin(Code::Sub, da, qd),
                };
                b.bin(Code::Div, num, v(c))
            }
        },
        Op::PowI(a, n) => {
            let da = dv(a)?;
            let pow = if n == 2 {
                let two = b.konst(2.0);
                let m = b.bin(Code::Mul, two, v(a));
                return Some(b.bin(Code::Mul, m, da));
            } else {
                // n·a^(n−1)·a' with a^(n−1) = (a²)^((n−1)/2), a non-negative base.
                let q = b.un(Code::Sqr, v(a));
                let m = (n - 1) / 2;
                if m == 1 { q } else { b.push(Code::PowChain, [q, 0, 0, 0], f64::from(m)) }
            };
            let k = b.konst(f64::from(n as f32));
            let m = b.bin(Code::Mul, k, pow);
            b.bin(Code::Mul, m, da)
        }
        Op::Call1(f, a) => {
            let da = dv(a)?;
            call1(b, f, v(a), v(id), da)
        }
        Op::Call2(f, a, c) => {
            if dv(a).is_none() && dv(c).is_none() {
                return None;
            }
            call2(b, f, [v(a), v(c), v(id)], [dv(a), dv(c)])?
        }
        Op::Call3(f, a, c, e) => {
            if dv(a).is_none() && dv(c).is_none() && dv(e).is_none() {
                return None;
            }
            let mut dd = |n: NodeId| dv(n).unwrap_or_else(|| b.konst(0.0));
            let (da, dc, de) = (dd(a), dd(c), dd(e));
            match f {
                Func3::Clamp => {
                    let m = b.bin(Code::Max, v(a), v(c));
                    let inner = b.push(Code::Dmax, [v(a), v(c), da, dc], 0.0);
                    b.push(Code::Dmin, [m, v(e), inner, de], 0.0)
                }
                Func3::Mix => {
                    // (a + (b − a)·s)' = a' + (b' − a')·s + (b − a)·s'
                    let slope = b.bin(Code::Sub, dc, da);
                    let t1 = b.bin(Code::Mul, slope, v(e));
                    let s1 = b.bin(Code::Add, da, t1);
                    let w = b.bin(Code::Sub, v(c), v(a));
                    let t2 = b.bin(Code::Mul, w, de);
                    b.bin(Code::Add, s1, t2)
                }
            }
        }
        Op::User(..) => unreachable!("user functions are refused before flattening"),
    })
}

/// a'·b + a·b' with zero terms dropped.
fn product(b: &mut Builder, va: u32, vb: u32, da: Option<u32>, db: Option<u32>) -> Option<u32> {
    Some(match (da, db) {
        (None, None) => return None,
        (Some(da), None) => b.bin(Code::Mul, da, vb),
        (None, Some(db)) => b.bin(Code::Mul, va, db),
        (Some(da), Some(db)) => {
            let l = b.bin(Code::Mul, da, vb);
            let r = b.bin(Code::Mul, va, db);
            b.bin(Code::Add, l, r)
        }
    })
}

/// f(a)' for the one-argument functions (`vid` is f(a)'s value node).
fn call1(b: &mut Builder, f: Func1, va: u32, vid: u32, da: u32) -> u32 {
    let one = |b: &mut Builder| b.konst(1.0);
    match f {
        Func1::Sqrt => {
            let two = b.konst(2.0);
            let m = b.bin(Code::Mul, two, vid);
            b.bin(Code::Div, da, m)
        }
        Func1::Exp => b.bin(Code::Mul, vid, da),
        Func1::Log => b.bin(Code::Div, da, va),
        Func1::Sin => {
            let c = b.un(Code::Cos, va);
            b.bin(Code::Mul, c, da)
        }
        Func1::Cos => {
            let s = b.un(Code::Sin, va);
            let m = b.bin(Code::Mul, s, da);
            b.un(Code::Neg, m)
        }
        Func1::Tan => {
            let o = one(b);
            let s = b.un(Code::Sqr, vid);
            let a = b.bin(Code::Add, o, s);
            b.bin(Code::Mul, a, da)
        }
        Func1::Atan => {
            let o = one(b);
            let s = b.un(Code::Sqr, va);
            let a = b.bin(Code::Add, o, s);
            b.bin(Code::Div, da, a)
        }
        Func1::Sinh => {
            let c = b.un(Code::Cosh, va);
            b.bin(Code::Mul, c, da)
        }
        Func1::Cosh => {
            let s = b.un(Code::Sinh, va);
            b.bin(Code::Mul, s, da)
        }
        Func1::Tanh => {
            let o = one(b);
            let s = b.un(Code::Sqr, vid);
            let a = b.bin(Code::Sub, o, s);
            b.bin(Code::Mul, a, da)
        }
        Func1::Abs => {
            let s = b.un(Code::Sign, va);
            b.bin(Code::Mul, s, da)
        }
        Func1::Sign => b.bin(Code::Dsign, va, da),
        Func1::Floor => b.bin(Code::Dfloor, va, da),
    }
}

/// f(a, c)' for the two-argument functions; `v` holds the value nodes of
/// a, c and f(a, c), `d` the derivatives of a and c (not both zero).
fn call2(b: &mut Builder, f: Func2, v: [u32; 3], d: [Option<u32>; 2]) -> Option<u32> {
    let [va, vc, vid] = v;
    let mut dd = |n: Option<u32>| n.unwrap_or_else(|| b.konst(0.0));
    Some(match f {
        Func2::Min => {
            let (da, dc) = (dd(d[0]), dd(d[1]));
            b.push(Code::Dmin, [va, vc, da, dc], 0.0)
        }
        Func2::Max => {
            let (da, dc) = (dd(d[0]), dd(d[1]));
            b.push(Code::Dmax, [va, vc, da, dc], 0.0)
        }
        Func2::Pow => {
            // (a^b)' = a^b·(b'·log a + b·a'/a)
            let t1 = d[1].map(|dc| {
                let l = b.un(Code::Log, va);
                b.bin(Code::Mul, dc, l)
            });
            let t2 = d[0].map(|da| {
                let m = b.bin(Code::Mul, vc, da);
                b.bin(Code::Div, m, va)
            });
            let inner = match (t1, t2) {
                (Some(x), Some(y)) => b.bin(Code::Add, x, y),
                (Some(x), None) | (None, Some(x)) => x,
                (None, None) => return None,
            };
            b.bin(Code::Mul, vid, inner)
        }
        Func2::Atan2 => {
            // (x·y' − y·x') / (x² + y²) for atan2(y, x)
            let (da, dc) = (dd(d[0]), dd(d[1]));
            let l = b.bin(Code::Mul, vc, da);
            let r = b.bin(Code::Mul, va, dc);
            let num = b.bin(Code::Sub, l, r);
            let sa = b.un(Code::Sqr, va);
            let sc = b.un(Code::Sqr, vc);
            let den = b.bin(Code::Add, sa, sc);
            b.bin(Code::Div, num, den)
        }
    })
}

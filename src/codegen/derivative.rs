//! Forward-mode differentiation of the formula along a ray, in the interval
//! and affine domains: `fn evald_<p>(x, y, z, t, dx, dy, dz) -> vec4<f32>`
//! returns the enclosure of f and of its derivative d f(o + s·dir)/ds over a
//! cell (`dx dy dz` are the ray direction). A derivative enclosure that
//! excludes 0 proves f monotone on the cell: then the cell holds a root iff
//! f changes sign across it, and that root is unique, so the traversal can
//! reject the cell or finish with scalar root finding instead of bisecting
//! with inclusion evaluations.
//!
//! Nodes whose derivative is identically 0 (constants, parameters, time)
//! are tracked so their terms are not emitted.

use super::{emit_body, emit_odd_power, Domain};
use crate::ir::{Func1, Func2, Func3, Ir, NodeId, Op, Var};
use std::fmt::Write;

/// The derivative helper library for `domain` (interval or affine: the
/// affine helpers build on the interval ones).
pub fn library(domain: Domain) -> String {
    let base = include_str!("../../templates/domains/derivative.wgsl");
    match domain {
        Domain::Affine => format!("{base}\n{}", include_str!("../../templates/domains/derivative_affine.wgsl")),
        _ => base.to_string(),
    }
}

/// Emits `evald_<p>` for `domain` (not the scalar domain).
pub fn emit_evaluator_d(ir: &Ir, domain: Domain) -> String {
    let p = domain.prefix();
    let ty = domain.ty();
    let mut out = String::new();
    let _ = writeln!(out, "fn evald_{p}(x: {ty}, y: {ty}, z: {ty}, t: {ty}, dx: {ty}, dy: {ty}, dz: {ty}) -> vec4<f32> {{");
    let mut zero = vec![true; ir.nodes.len()];
    let empty = emit_body(&mut out, ir, domain, |out, id, op| {
        if let Some(d) = derivative(out, p, id, op, &zero) {
            let _ = writeln!(out, "    let d{id} = {d};");
            zero[id as usize] = false;
        }
    });
    if let Some(empty) = empty {
        let _ = writeln!(out, "    if ({empty}) {{ return vec4<f32>({p}_range({p}_empty()), 0.0, 0.0); }}");
    }
    let r = ir.root;
    let d = if zero[r as usize] { format!("{p}_const(0.0)") } else { format!("d{r}") };
    let _ = writeln!(out, "    return vec4<f32>({p}_range(v{r}), {p}_range({d}));");
    out.push_str("}\n");
    out
}

/// The derivative expression of one node, `None` when it is identically 0.
fn derivative(out: &mut String, p: &str, id: NodeId, op: Op, zero: &[bool]) -> Option<String> {
    let z = |n: NodeId| zero[n as usize];
    let v = |n: NodeId| format!("v{n}");
    let d = |n: NodeId| format!("d{n}");
    let c = |x: f32| format!("{p}_const({x:?})");
    let mul = |a: String, b: String| format!("{p}_mul({a}, {b})");
    let add = |a: String, b: String| format!("{p}_add({a}, {b})");
    let sub = |a: String, b: String| format!("{p}_sub({a}, {b})");
    let div = |a: String, b: String| format!("{p}_div({a}, {b})");
    let f1 = |name: &str, a: String| format!("{p}_{name}({a})");
    // a'·b + a·b' with zero terms dropped.
    let product = |a: NodeId, b: NodeId| match (z(a), z(b)) {
        (true, true) => None,
        (false, true) => Some(mul(d(a), v(b))),
        (true, false) => Some(mul(v(a), d(b))),
        (false, false) => Some(add(mul(d(a), v(b)), mul(v(a), d(b)))),
    };
    Some(match op {
        Op::Const(_) | Op::Param(_) | Op::Var(Var::T) => return None,
        Op::Var(Var::X) => "dx".into(),
        Op::Var(Var::Y) => "dy".into(),
        Op::Var(Var::Z) => "dz".into(),
        Op::Neg(a) if !z(a) => format!("{p}_neg({})", d(a)),
        Op::Add(a, b) | Op::Sub(a, b) if z(a) && z(b) => return None,
        Op::Add(a, b) => match (z(a), z(b)) {
            (false, true) => d(a),
            (true, false) => d(b),
            _ => add(d(a), d(b)),
        },
        Op::Sub(a, b) => match (z(a), z(b)) {
            (false, true) => d(a),
            (true, false) => format!("{p}_neg({})", d(b)),
            _ => sub(d(a), d(b)),
        },
        Op::Mul(a, b) => return product(a, b),
        Op::Div(a, b) => match (z(a), z(b)) {
            (true, true) => return None,
            (false, true) => div(d(a), v(b)),
            _ => {
                // (a'b − ab') / b², written as (a' − q·b') / b with q = a/b.
                let num = if z(a) { format!("{p}_neg({})", mul(v(id), d(b))) } else { sub(d(a), mul(v(id), d(b))) };
                div(num, v(b))
            }
        },
        Op::PowI(a, _) if z(a) => return None,
        Op::PowI(a, 2) => mul(mul(c(2.0), v(a)), d(a)),
        Op::PowI(a, n) => {
            // n·a^(n−1)·a' with a^(n−1) = (a²)^((n−1)/2), a non-negative base.
            let _ = writeln!(out, "    let q{id} = {p}_sqr({});", v(a));
            let m = (n - 1) / 2;
            let pow = if m == 1 { format!("q{id}") } else { emit_odd_power(out, p, &format!("dw{id}"), &format!("q{id}"), m) };
            mul(mul(c(n as f32), pow), d(a))
        }
        Op::Call1(_, a) if z(a) => return None,
        Op::Call1(f, a) => {
            let (va, da) = (v(a), d(a));
            match f {
                Func1::Sqrt => div(da, mul(c(2.0), v(id))),
                Func1::Exp => mul(v(id), da),
                Func1::Log => div(da, va),
                Func1::Sin => mul(f1("cos", va), da),
                Func1::Cos => format!("{p}_neg({})", mul(f1("sin", va), da)),
                Func1::Tan => mul(add(c(1.0), f1("sqr", v(id))), da),
                Func1::Atan => div(da, add(c(1.0), f1("sqr", va))),
                Func1::Sinh => mul(f1("cosh", va), da),
                Func1::Cosh => mul(f1("sinh", va), da),
                Func1::Tanh => mul(sub(c(1.0), f1("sqr", v(id))), da),
                Func1::Abs => mul(f1("sign", va), da),
                Func1::Sign => format!("{p}_dsign({va}, {da})"),
                Func1::Floor => format!("{p}_dfloor({va}, {da})"),
            }
        }
        Op::Call2(_, a, b) if z(a) && z(b) => return None,
        Op::Call2(f, a, b) => {
            let dd = |n: NodeId| if z(n) { format!("{p}_const(0.0)") } else { d(n) };
            match f {
                Func2::Min => format!("{p}_dmin({}, {}, {}, {})", v(a), v(b), dd(a), dd(b)),
                Func2::Max => format!("{p}_dmax({}, {}, {}, {})", v(a), v(b), dd(a), dd(b)),
                Func2::Pow => {
                    // (a^b)' = a^b·(b'·log a + b·a'/a)
                    let t1 = if z(b) { None } else { Some(mul(d(b), f1("log", v(a)))) };
                    let t2 = if z(a) { None } else { Some(div(mul(v(b), d(a)), v(a))) };
                    let inner = match (t1, t2) {
                        (Some(x), Some(y)) => add(x, y),
                        (Some(x), None) | (None, Some(x)) => x,
                        (None, None) => return None,
                    };
                    mul(v(id), inner)
                }
                Func2::Atan2 => {
                    // (x·y' − y·x') / (x² + y²) for atan2(y, x)
                    let num = sub(mul(v(b), dd(a)), mul(v(a), dd(b)));
                    div(num, add(f1("sqr", v(a)), f1("sqr", v(b))))
                }
            }
        }
        Op::Call3(_, a, b, e) if z(a) && z(b) && z(e) => return None,
        Op::Call3(f, a, b, e) => {
            let dd = |n: NodeId| if z(n) { format!("{p}_const(0.0)") } else { d(n) };
            match f {
                Func3::Clamp => {
                    let _ = writeln!(out, "    let m{id} = {p}_max({}, {});", v(a), v(b));
                    let inner = format!("{p}_dmax({}, {}, {}, {})", v(a), v(b), dd(a), dd(b));
                    format!("{p}_dmin(m{id}, {}, {inner}, {})", v(e), dd(e))
                }
                Func3::Mix => {
                    // (a + (b − a)·s)' = a' + (b' − a')·s + (b − a)·s'
                    let slope = sub(dd(b), dd(a));
                    add(add(dd(a), mul(slope, v(e))), mul(sub(v(b), v(a)), dd(e)))
                }
            }
        }
        // The slope of a user function is unknown: the whole line (so a
        // cell that depends on one is never taken for monotone).
        Op::User(_, args, n) if args[..n as usize].iter().all(|&a| z(a)) => return None,
        Op::User(..) => format!("{p}_whole()"),
        _ => return None,
    })
}

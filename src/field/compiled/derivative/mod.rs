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
//!
//! The rules are written once (`rule`) against `Terms`, which the
//! generated code implements with WGSL expressions (`wgsl_terms`) and the tape with
//! tape nodes (`tape_derivative.rs`), so both prove the same monotonicity.

use super::ray_forms::RayForms;
use super::emit::emit_body_tiled;
use super::{midpoint, Hook};
use crate::ir::Domain;
use crate::ir::{Func1, Func2, Func3, Ir, NodeId, Op, Var};
use std::fmt::Write;
use wgsl_terms::{Term, Wgsl};

mod wgsl_terms;

/// The derivative helper library for `domain` (interval or affine: the
/// affine helpers build on the interval ones).
pub fn library(domain: Domain) -> String {
    let base = include_str!("../../../../templates/domains/derivative.wgsl");
    match domain {
        Domain::Affine => format!("{base}\n{}", include_str!("../../../../templates/domains/derivative_affine.wgsl")),
        _ => base.to_string(),
    }
}

/// The domain the slope program of `evald_<p>` computes in, for values in
/// `domain`. Affine slopes pay only where their terms cancel, as the
/// product rule's terms of a polynomial of moderate degree do (the Barth
/// decic needs fewer evaluations a pixel with affine slopes than with
/// interval ones). Every min, max, abs, sign, floor and transcendental
/// function turns the affine slope into an interval and back, and a
/// power's slope beyond f32 is the whole line in the affine domain where
/// an interval keeps its sign (the degree-200 superquadric needs an order
/// of magnitude more evaluations a pixel with affine slopes). There the
/// slopes are intervals of the values' ranges: on the Knoll suite as few
/// or fewer evaluations a pixel, and a per-pixel kernel whose NIR after
/// inlining is about a quarter smaller (`@city`), which lavapipe's
/// pipeline creation is proportional to.
pub fn slope_domain(ir: &Ir, domain: Domain) -> Domain {
    match domain {
        Domain::Affine if ir.degree().is_some_and(|d| d <= AFFINE_SLOPES_MAX_DEGREE) => Domain::Affine,
        Domain::Affine => Domain::Interval,
        d => d,
    }
}

/// The highest polynomial degree whose slopes are computed in the affine
/// domain ([`slope_domain`]).
const AFFINE_SLOPES_MAX_DEGREE: u32 = 10;

/// Emits `evald_<p>` for `domain` (not the scalar domain). Its slopes are
/// in [`slope_domain`]; with interval slopes for affine values, a value
/// enters a slope term as its range (`ra_range(v12)`).
#[cfg(test)]
pub fn emit_evaluator_d(ir: &Ir, domain: Domain) -> String {
    let (vp, ty) = (domain.prefix(), domain.ty());
    let head = format!("fn evald_{vp}(x: {ty}, y: {ty}, z: {ty}, t: {ty}, dx: f32, dy: f32, dz: f32) -> vec4<f32> {{\n");
    emit_slopes(ir, domain, head, None, super::Tiles::Off, false, |result| format!("    return {result};\n}}\n"))
}

/// Emits the bisection's `cell_enclosure(o, dir, s0, s1, slope)` with
/// `evald_<p>`'s code as its own body: `forms` lifts the ray segment into
/// `X`, `Y`, `Z` ([`super::compiled::segment_forms`]), and `ray`'s nodes
/// come from their polynomials along the ray over the cell's `t0, t1`
/// (value and slope); the slope is the whole line without `slope`. Where
/// [`midpoint::fused`], it also sets `g_cell_f_mid` to f at `g_cell_s_mid`.
/// lavapipe inlines the field into every function on the path from the
/// entry point, so an `evald_<p>` called from here was one more copy of it
/// to clone (150,000 NIR instructions for `@city` in RAA).
pub(crate) fn emit_cell_enclosure(ir: &Ir, domain: Domain, forms: &str, ray: Option<&RayForms>, safe: bool, tiles: super::Tiles) -> String {
    let p = domain.prefix();
    let cell = if ray.is_some() { "    let t0 = s0 - g_ray_ref;\n    let t1 = s1 - g_ray_ref;\n" } else { "" };
    let mid = midpoint::fused(ir);
    let point = if mid { midpoint::HEAD } else { "" };
    let head = format!(
        "fn cell_enclosure(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32, slope: bool) -> vec4<f32> {{\n{forms}\n{cell}{point}    \
         let x = X;\n    let y = Y;\n    let z = Z;\n    let t = {p}_const(F.time);\n    let dx = dir.x;\n    let dy = dir.y;\n    let dz = dir.z;\n"
    );
    // Inputs past the bound of a kernel without the NaN test (`ra_safe`): the whole line.
    let q = match safe {
        true => "select(vec4<f32>(-F.inf, F.inf, -F.inf, F.inf), q0, ra_safe(x, y, z, t))",
        false => "q0",
    };
    emit_slopes(ir, domain, head, ray, tiles, mid, |q0| format!("    let q0 = {q0};\n    let q = {q};\n    return select(vec4<f32>(q.xy, -F.inf, F.inf), q, slope);\n}}\n"))
}

/// A function whose body computes f and its slope along the ray in
/// `domain`, from `x y z t` (values) and `dx dy dz` (the ray direction)
/// that `head` declares, and ends with `tail` of the result (the value's
/// range and the slope's, a `vec4<f32>`); with `mid`, also f at the
/// point `pm` ([`midpoint`]).
fn emit_slopes(ir: &Ir, domain: Domain, head: String, ray: Option<&RayForms>, tiles: super::Tiles, mid: bool, tail: impl FnOnce(&str) -> String) -> String {
    let vp = domain.prefix();
    let slopes = slope_domain(ir, domain);
    let p = slopes.prefix();
    let ranged = (slopes != domain).then_some(vp);
    let mut out = head;
    let mut d: Vec<Option<Term>> = vec![None; ir.nodes.len()];
    let nn = crate::analysis::nonneg::nonneg(ir);
    let at = |d: &mut Vec<Option<Term>>, id: NodeId| {
        if d.len() <= id as usize {
            d.resize(id as usize + 1, None);
        }
        id as usize
    };
    let body = emit_body_tiled(&mut out, ir, domain, ray.map(|r| (r, "t0, t1")), tiles, |out, hook| {
        if mid {
            midpoint::emit(out, ir, &nn, &hook);
        }
        match hook {
            // A node taken from the ray has its slope from there (an interval:
            // ray forms are for interval values, whose slopes are intervals).
            Hook::Node(id, _) if ray.is_some_and(|r| r.has(id)) => {
                let i = at(&mut d, id);
                let _ = writeln!(out, "    let d{id} = {};", ray.expect("tested").slope(id));
                d[i] = Some(Term::Form(format!("d{id}")));
            }
            Hook::Node(id, op) => {
                let i = at(&mut d, id);
                if let Some(e) = rule(&mut Wgsl { out, p, domain: slopes, ir, ranged, nn: &nn }, id, op, &d) {
                    let _ = writeln!(out, "    let d{id} = {};", e.text());
                    d[i] = Some(e.renamed(format!("d{id}")));
                }
            }
            // A rerolled loop's accumulator carries its derivative as a value of the domain.
            Hook::Begin { acc, seed } => {
                let init = seed.and_then(|s| d[s as usize].as_ref()).map_or_else(|| format!("{p}_const(0.0)"), |t| t.lift(p));
                let _ = writeln!(out, "    var d{acc} = {init};");
                let i = at(&mut d, acc);
                d[i] = Some(Term::Form(format!("d{acc}")));
            }
            Hook::Step { acc, next } => {
                let v = d[next as usize].as_ref().map_or_else(|| format!("{p}_const(0.0)"), |t| t.lift(p));
                let _ = writeln!(out, "    d{acc} = {v};");
            }
            Hook::End { acc, end } => {
                let _ = writeln!(out, "    let d{end} = d{acc};");
                d[end as usize] = Some(Term::Form(format!("d{end}")));
            }
            Hook::Slot { id, .. } => {
                at(&mut d, id);
            }
        }
    });
    let root = d[ir.root as usize].clone().map_or_else(|| format!("{p}_const(0.0)"), |t| t.lift(p));
    let mut result = format!("vec4<f32>({vp}_range(v{}), {p}_range({root}))", ir.root);
    if let Some(empty) = body.empty {
        result = format!("select({result}, vec4<f32>({vp}_range({vp}_empty()), 0.0, 0.0), {empty})");
    }
    if body.looped {
        result = format!("select({result}, vec4<f32>(-iso_inf(), iso_inf(), -iso_inf(), iso_inf()), !admitted)");
    }
    if mid {
        out.push_str(&midpoint::tail(ir.root));
    }
    out.push_str(&tail(&result));
    out
}

/// The operations the derivative rules build terms with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum D {
    Neg,
    Sqr,
    Sin,
    Cos,
    Log,
    Sinh,
    Cosh,
    Sign,
    Add,
    Sub,
    Mul,
    Div,
    Max,
    /// sign(a)' (derivative helper): (a, a').
    Dsign,
    /// floor(a)' (derivative helper): (a, a').
    Dfloor,
}

/// Where the rules put their terms: a WGSL expression writer or a tape.
pub(crate) trait Terms {
    /// A term.
    type T: Clone;
    /// The value of IR node `n`.
    fn value(&mut self, n: NodeId) -> Self::T;
    /// A constant.
    fn konst(&mut self, c: f32) -> Self::T;
    /// The ray direction's component `axis` (the derivative of x, y, z).
    fn direction(&mut self, axis: u32) -> Self::T;
    /// A one-argument operation.
    fn un(&mut self, op: D, a: Self::T) -> Self::T;
    /// A two-argument operation.
    fn bin(&mut self, op: D, a: Self::T, b: Self::T) -> Self::T;
    /// min(a, b)' or max(a, b)' (derivative helpers): (a, b, a', b').
    fn dminmax(&mut self, max: bool, args: [Self::T; 4]) -> Self::T;
    /// q^m for an odd m >= 3 and q >= 0 (node `id`'s power chain).
    fn odd_power(&mut self, id: NodeId, q: Self::T, m: u32) -> Self::T;
    /// `x` computed once and named (node `id`, role `tag`) where a term
    /// uses it more than once.
    fn bind(&mut self, id: NodeId, tag: &str, x: Self::T) -> Self::T;
    /// The whole line (the slope of a user function is unknown).
    fn whole(&mut self) -> Self::T;
    /// n·a^(n−1) for a [`Func2::PowN`] of `a` and the constant `n`.
    fn pown_slope(&mut self, a: Self::T, n: Self::T) -> Self::T;
    /// `a` divided by the value of node `c`, which does not depend on the ray.
    fn divide(&mut self, a: Self::T, c: NodeId) -> Self::T {
        let vc = self.value(c);
        self.bin(D::Div, a, vc)
    }
    /// A slope `d` times the value of node `c` (the product rule's terms).
    fn times(&mut self, d: Self::T, c: NodeId) -> Self::T {
        let vc = self.value(c);
        self.bin(D::Mul, d, vc)
    }
    /// (a²)' = 2·a·a' from a's slope `d` (node `a`).
    fn twice_times(&mut self, d: Self::T, a: NodeId) -> Self::T {
        let (two, va) = (self.konst(2.0), self.value(a));
        let m = self.bin(D::Mul, two, va);
        self.bin(D::Mul, m, d)
    }
    /// A slope `d` divided by `m`, a term that is never negative (sqrt's 2·√a).
    fn over_nonneg(&mut self, d: Self::T, m: Self::T) -> Self::T {
        self.bin(D::Div, d, m)
    }
    /// |a|' from the value `a` and its slope `da`: sign(a)·a'.
    fn dabs(&mut self, a: Self::T, da: Self::T) -> Self::T {
        let s = self.un(D::Sign, a);
        self.bin(D::Mul, s, da)
    }
}

/// The derivative of IR node `id` (operation `op`) from its operands'
/// derivatives `d` (`None`: identically 0); `None` when it is identically 0.
pub(crate) fn rule<B: Terms>(b: &mut B, id: NodeId, op: Op, d: &[Option<B::T>]) -> Option<B::T> {
    let dv = |n: NodeId| d[n as usize].clone();
    Some(match op {
        Op::Const(_) | Op::Param(_) | Op::Var(Var::T) => return None,
        Op::Var(Var::X) => b.direction(0),
        Op::Var(Var::Y) => b.direction(1),
        Op::Var(Var::Z) => b.direction(2),
        Op::Neg(a) => {
            let da = dv(a)?;
            b.un(D::Neg, da)
        }
        Op::Add(a, c) => match (dv(a), dv(c)) {
            (None, None) => return None,
            (Some(x), None) | (None, Some(x)) => x,
            (Some(x), Some(y)) => b.bin(D::Add, x, y),
        },
        Op::Sub(a, c) => match (dv(a), dv(c)) {
            (None, None) => return None,
            (Some(x), None) => x,
            (None, Some(y)) => b.un(D::Neg, y),
            (Some(x), Some(y)) => b.bin(D::Sub, x, y),
        },
        // a'·b + a·b' with zero terms dropped.
        Op::Mul(a, c) => match (dv(a), dv(c)) {
            (None, None) => return None,
            (Some(da), None) => b.times(da, c),
            (None, Some(dc)) => b.times(dc, a),
            (Some(da), Some(dc)) => {
                let l = b.times(da, c);
                let r = b.times(dc, a);
                b.bin(D::Add, l, r)
            }
        },
        Op::Div(a, c) => match (dv(a), dv(c)) {
            (None, None) => return None,
            (Some(da), None) => b.divide(da, c),
            (da, Some(dc)) => {
                // (a'b − ab') / b², written as (a' − q·b') / b with q = a/b.
                let q = b.value(id);
                let qd = b.bin(D::Mul, q, dc);
                let num = match da {
                    None => b.un(D::Neg, qd),
                    Some(da) => b.bin(D::Sub, da, qd),
                };
                let vc = b.value(c);
                b.bin(D::Div, num, vc)
            }
        },
        Op::PowI(a, 2) => {
            let da = dv(a)?;
            b.twice_times(da, a)
        }
        Op::PowI(a, n) => {
            // n·a^(n−1)·a' with a^(n−1) = (a²)^((n−1)/2), a non-negative base.
            let da = dv(a)?;
            let va = b.value(a);
            let sq = b.un(D::Sqr, va);
            let q = b.bind(id, "q", sq);
            let m = (n - 1) / 2;
            let pow = if m == 1 { q } else { b.odd_power(id, q, m) };
            let k = b.konst(n as f32);
            let kp = b.bin(D::Mul, k, pow);
            b.bin(D::Mul, kp, da)
        }
        Op::Call1(f, a) => {
            let da = dv(a)?;
            call1(b, f, a, id, da)
        }
        Op::Call2(f, a, c) => {
            let (da, dc) = (dv(a), dv(c));
            if da.is_none() && dc.is_none() {
                return None;
            }
            call2(b, f, id, [a, c], [da, dc])?
        }
        Op::Call3(f, a, c, e) => {
            if dv(a).is_none() && dv(c).is_none() && dv(e).is_none() {
                return None;
            }
            let (da, dc, de) = (zero(b, dv(a)), zero(b, dv(c)), zero(b, dv(e)));
            call3(b, f, id, [a, c, e], [da, dc, de])
        }
        // The slope of a user function is unknown: the whole line (so a
        // cell that depends on one is never taken for monotone).
        Op::User(_, args, n) if args[..n as usize].iter().all(|&a| dv(a).is_none()) => return None,
        Op::User(..) => b.whole(),
    })
}

/// A missing slope (the operand is constant along the ray) as zero.
fn zero<B: Terms>(b: &mut B, x: Option<B::T>) -> B::T {
    x.unwrap_or_else(|| b.konst(0.0))
}

/// The slope of a function of two arguments `a, c` with slopes `da, dc`
/// (not both missing).
fn call2<B: Terms>(b: &mut B, f: Func2, id: NodeId, [a, c]: [NodeId; 2], [da, dc]: [Option<B::T>; 2]) -> Option<B::T> {
    let (va, vc) = (b.value(a), b.value(c));
    Some(match f {
        Func2::Min | Func2::Max => {
            let (da, dc) = (zero(b, da), zero(b, dc));
            b.dminmax(f == Func2::Max, [va, vc, da, dc])
        }
        Func2::Pow => {
            // (a^b)' = a^b·(b'·log a + b·a'/a)
            let t1 = dc.map(|dc| {
                let l = b.un(D::Log, va.clone());
                b.bin(D::Mul, dc, l)
            });
            let t2 = da.map(|da| {
                let m = b.bin(D::Mul, vc.clone(), da);
                b.bin(D::Div, m, va.clone())
            });
            let inner = match (t1, t2) {
                (Some(x), Some(y)) => b.bin(D::Add, x, y),
                (Some(x), None) | (None, Some(x)) => x,
                (None, None) => return None,
            };
            let vid = b.value(id);
            b.bin(D::Mul, vid, inner)
        }
        // (a^n)' = n·a^(n−1)·a', n a constant (its slope is 0).
        Func2::PowN => match (da, dc) {
            (Some(da), None) => {
                let slope = b.pown_slope(va, vc);
                b.bin(D::Mul, slope, da)
            }
            _ => b.whole(),
        },
        Func2::Atan2 => {
            // (x·y' − y·x') / (x² + y²) for atan2(y, x)
            let (da, dc) = (zero(b, da), zero(b, dc));
            let l = b.bin(D::Mul, vc.clone(), da);
            let r = b.bin(D::Mul, va.clone(), dc);
            let num = b.bin(D::Sub, l, r);
            let (sa, sc) = (b.un(D::Sqr, va), b.un(D::Sqr, vc));
            let den = b.bin(D::Add, sa, sc);
            b.bin(D::Div, num, den)
        }
    })
}

/// The slope of a function of three arguments with slopes `da, dc, de`.
fn call3<B: Terms>(b: &mut B, f: Func3, id: NodeId, [a, c, e]: [NodeId; 3], [da, dc, de]: [B::T; 3]) -> B::T {
    let (va, vc, ve) = (b.value(a), b.value(c), b.value(e));
    match f {
        Func3::Clamp => {
            let mx = b.bin(D::Max, va.clone(), vc.clone());
            let m = b.bind(id, "m", mx);
            let inner = b.dminmax(true, [va, vc, da, dc]);
            b.dminmax(false, [m, ve, inner, de])
        }
        Func3::Mix => {
            // (a + (b − a)·s)' = a' + (b' − a')·s + (b − a)·s'
            let slope = b.bin(D::Sub, dc, da.clone());
            let t1 = b.bin(D::Mul, slope, ve);
            let s1 = b.bin(D::Add, da, t1);
            let w = b.bin(D::Sub, vc, va);
            let t2 = b.bin(D::Mul, w, de);
            b.bin(D::Add, s1, t2)
        }
    }
}

/// f(a)' for the one-argument functions (node `id` is f(a)), a' = `da`.
fn call1<B: Terms>(b: &mut B, f: Func1, a: NodeId, id: NodeId, da: B::T) -> B::T {
    let (va, vid) = (b.value(a), b.value(id));
    // 1 ± v² for tan, atan and tanh.
    let one_and = |b: &mut B, op: D, v: B::T| {
        let (one, s) = (b.konst(1.0), b.un(D::Sqr, v));
        b.bin(op, one, s)
    };
    match f {
        Func1::Sqrt => {
            let two = b.konst(2.0);
            let m = b.bin(D::Mul, two, vid);
            b.over_nonneg(da, m)
        }
        Func1::Exp => b.bin(D::Mul, vid, da),
        Func1::Log => b.bin(D::Div, da, va),
        Func1::Sin => {
            let c = b.un(D::Cos, va);
            b.bin(D::Mul, c, da)
        }
        Func1::Cos => {
            let s = b.un(D::Sin, va);
            let m = b.bin(D::Mul, s, da);
            b.un(D::Neg, m)
        }
        Func1::Tan => {
            let a1 = one_and(b, D::Add, vid);
            b.bin(D::Mul, a1, da)
        }
        Func1::Atan => {
            let a1 = one_and(b, D::Add, va);
            b.bin(D::Div, da, a1)
        }
        Func1::Sinh => {
            let c = b.un(D::Cosh, va);
            b.bin(D::Mul, c, da)
        }
        Func1::Cosh => {
            let s = b.un(D::Sinh, va);
            b.bin(D::Mul, s, da)
        }
        Func1::Tanh => {
            let a1 = one_and(b, D::Sub, vid);
            b.bin(D::Mul, a1, da)
        }
        Func1::Abs => b.dabs(va, da),
        Func1::Sign => b.bin(D::Dsign, va, da),
        Func1::Floor => b.bin(D::Dfloor, va, da),
    }
}

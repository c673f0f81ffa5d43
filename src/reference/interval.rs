//! Interval arithmetic (IA) in f64 with the rules of
//! `templates/domains/interval.wgsl`.
//!
//! An interval is `[lo, hi]`; empty is any `lo > hi`, canonically `[1, -1]`.
//! Ends may be ±∞. Where IEEE arithmetic would give a NaN end (∞ − ∞,
//! 0 · ∞), the reference takes the limit that keeps the result an enclosure:
//! a NaN low end becomes −∞, a NaN high end +∞, and 0 · ±∞ is 0 for the ends
//! of a product (an unbounded interval never contains ∞ itself).
//!
//! Unlike the WGSL library nothing is padded: f64 rounding is far below the
//! f32 rounding the device has, and the tests compare against f64 samples
//! with a margin (see `src/tests/conformance/oracle.rs`).

use super::{evaluate, Value};
use crate::ir::{Func1, Func2, Func3, Ir, Op};
use std::f64::consts::{FRAC_PI_2, PI};

/// `[lo, hi]`; empty when `lo > hi`.
pub type Interval = [f64; 2];

/// The canonical empty interval.
pub const EMPTY: Interval = [1.0, -1.0];
/// The whole real line.
pub const WHOLE: Interval = [f64::NEG_INFINITY, f64::INFINITY];

/// Largest |end| for which sin, cos and tan look for extrema and poles; the
/// WGSL library gives up there (f32 argument reduction), and so does this
/// mirror, so both return the same shape of result.
const TRIG_LIMIT: f64 = 1e6;

/// Evaluates the formula over a box: `boxes` holds `[lo, hi]` of x, y, z and
/// t. Returns the enclosure, or an empty interval (`lo > hi`, canonically
/// `[1, -1]`) when some sqrt / log / real power is undefined on the whole box.
pub fn eval_interval(ir: &Ir, boxes: [[f64; 2]; 4], params: &[f64]) -> [f64; 2] {
    let r = evaluate::<Iv>(ir, boxes.map(|b| norm(Iv(b))), params).0;
    if is_empty(r) { EMPTY } else { r }
}

/// True for an empty interval.
pub fn is_empty(a: Interval) -> bool {
    a[0] > a[1]
}

/// Newtype so [`Value`] can be implemented for intervals.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Iv(pub Interval);

impl Value for Iv {
    fn constant(c: f64) -> Iv {
        Iv([c, c])
    }
    fn apply(op: &Op, args: &[Iv]) -> Iv {
        let mut a = [EMPTY; 3];
        for (i, v) in args.iter().enumerate() {
            a[i] = v.0;
        }
        Iv(interval_op(op, &a[..args.len()]))
    }
    fn is_undefined(&self) -> bool {
        is_empty(self.0)
    }
    fn undefined() -> Iv {
        Iv(EMPTY)
    }
}

/// NaN ends mean "unbounded on that side".
fn norm(a: Iv) -> Iv {
    let [lo, hi] = a.0;
    Iv([if lo.is_nan() { f64::NEG_INFINITY } else { lo }, if hi.is_nan() { f64::INFINITY } else { hi }])
}

/// Applies one operation to interval arguments (in operand order), with the
/// WGSL library's rule for that operation.
pub fn interval_op(op: &Op, a: &[Interval]) -> Interval {
    let r = match *op {
        Op::Const(c) => [c, c],
        Op::Var(_) | Op::Param(_) | Op::User(..) => WHOLE,
        Op::Neg(_) => neg(a[0]),
        Op::Add(..) => [a[0][0] + a[1][0], a[0][1] + a[1][1]],
        Op::Sub(..) => [a[0][0] - a[1][1], a[0][1] - a[1][0]],
        Op::Mul(..) => mul(a[0], a[1]),
        Op::Div(..) => div(a[0], a[1]),
        Op::PowI(_, n) => powi(a[0], n),
        Op::Call1(f, _) => call1(f, a[0]),
        Op::Call2(f, ..) => call2(f, a[0], a[1]),
        Op::Call3(Func3::Clamp, ..) => [a[0][0].max(a[1][0]).min(a[2][0]), a[0][1].max(a[1][1]).min(a[2][1])],
        Op::Call3(Func3::Mix, ..) => {
            // a*(1 - s) + b*s: an inclusion for any s.
            let (x, y, s) = (a[0], a[1], a[2]);
            let p = mul(x, [1.0 - s[1], 1.0 - s[0]]);
            let q = mul(y, s);
            [p[0] + q[0], p[1] + q[1]]
        }
    };
    if is_empty(r) { r } else { norm(Iv(r)).0 }
}

fn neg(a: Interval) -> Interval {
    [-a[1], -a[0]]
}

/// An end of a product: 0 · ±∞ is 0.
fn pmul(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 { 0.0 } else { a * b }
}

pub(crate) fn mul(a: Interval, b: Interval) -> Interval {
    let p = [pmul(a[0], b[0]), pmul(a[0], b[1]), pmul(a[1], b[0]), pmul(a[1], b[1])];
    [p.iter().copied().fold(f64::INFINITY, f64::min), p.iter().copied().fold(f64::NEG_INFINITY, f64::max)]
}

/// Division: a divisor that contains 0 gives a half-line when 0 is one of
/// its ends and the numerator keeps one sign, else the whole line.
pub(crate) fn div(a: Interval, b: Interval) -> Interval {
    let inf = f64::INFINITY;
    if b[0] > 0.0 || b[1] < 0.0 {
        return mul(a, [1.0 / b[1], 1.0 / b[0]]);
    }
    if b[0] == 0.0 && b[1] > 0.0 {
        if a[0] >= 0.0 {
            return [a[0] / b[1], inf];
        }
        if a[1] <= 0.0 {
            return [-inf, a[1] / b[1]];
        }
    }
    if b[1] == 0.0 && b[0] < 0.0 {
        if a[0] >= 0.0 {
            return [-inf, a[0] / b[0]];
        }
        if a[1] <= 0.0 {
            return [a[1] / b[0], inf];
        }
    }
    WHOLE
}

fn straddles(a: Interval) -> bool {
    a[0] < 0.0 && a[1] > 0.0
}

/// Even-power rule for squares.
pub(crate) fn sqr(a: Interval) -> Interval {
    let s = [a[0] * a[0], a[1] * a[1]];
    if straddles(a) { [0.0, s[0].max(s[1])] } else { [s[0].min(s[1]), s[0].max(s[1])] }
}

/// a^n: odd powers are monotone (the WGSL chain raises both ends); even
/// powers use the even rule (the front end only emits n = 2 for those).
pub(crate) fn powi(a: Interval, n: u32) -> Interval {
    let p = [a[0].powi(n as i32), a[1].powi(n as i32)];
    if n % 2 == 1 {
        p
    } else if straddles(a) {
        [0.0, p[0].max(p[1])]
    } else {
        [p[0].min(p[1]), p[0].max(p[1])]
    }
}

fn call1(f: Func1, a: Interval) -> Interval {
    let [lo, hi] = a;
    match f {
        Func1::Sqrt => {
            if hi < 0.0 { EMPTY } else { [lo.max(0.0).sqrt(), hi.sqrt()] }
        }
        Func1::Log => {
            if hi <= 0.0 { EMPTY } else { [if lo > 0.0 { lo.ln() } else { f64::NEG_INFINITY }, hi.ln()] }
        }
        Func1::Exp => [lo.exp(), hi.exp()],
        Func1::Sinh => [lo.sinh(), hi.sinh()],
        Func1::Tanh => [lo.tanh(), hi.tanh()],
        Func1::Atan => [lo.atan(), hi.atan()],
        Func1::Cosh => {
            let c = [lo.cosh(), hi.cosh()];
            if straddles(a) { [1.0, c[0].max(c[1])] } else { [c[0].min(c[1]), c[0].max(c[1])] }
        }
        Func1::Abs => {
            let m = [lo.abs(), hi.abs()];
            if straddles(a) { [0.0, m[0].max(m[1])] } else { [m[0].min(m[1]), m[0].max(m[1])] }
        }
        Func1::Sign => [sign(lo), sign(hi)],
        Func1::Floor => [lo.floor(), hi.floor()],
        Func1::Cos => cos(a),
        // sin x = cos(x - pi/2), but written out like the WGSL rule.
        Func1::Sin => sin(a),
        Func1::Tan => tan(a),
    }
}

fn sign(x: f64) -> f64 {
    if x > 0.0 { 1.0 } else if x < 0.0 { -1.0 } else { 0.0 }
}

/// Slack of the extremum / pole tests: rounding in (lo - c) / period can
/// only make a test include an extremum, never skip one.
fn slack(lo: f64) -> f64 {
    1e-12 + lo.abs() * 1e-14
}

fn trig_hopeless(a: Interval, period: f64) -> bool {
    !(a[1] - a[0] < period) || !(a[0].abs() < TRIG_LIMIT) || !(a[1].abs() < TRIG_LIMIT)
}

/// Is there a point `offset + k * period` (k an integer) in `a` (with slack)?
fn hits(a: Interval, offset: f64, period: f64) -> bool {
    let s = slack(a[0]);
    let k = ((a[0] - offset - s) / period).ceil();
    k * period + offset <= a[1] + s
}

/// cos over [lo, hi]: the ends, plus +1 if a multiple of 2π lies inside and
/// −1 if an odd multiple of π does.
fn cos(a: Interval) -> Interval {
    if trig_hopeless(a, 2.0 * PI) {
        return [-1.0, 1.0];
    }
    let c = [a[0].cos(), a[1].cos()];
    let mut r = [c[0].min(c[1]), c[0].max(c[1])];
    if hits(a, 0.0, 2.0 * PI) {
        r[1] = 1.0;
    }
    if hits(a, PI, 2.0 * PI) {
        r[0] = -1.0;
    }
    r
}

/// sin: maxima at π/2 + 2kπ, minima at −π/2 + 2kπ.
fn sin(a: Interval) -> Interval {
    if trig_hopeless(a, 2.0 * PI) {
        return [-1.0, 1.0];
    }
    let s = [a[0].sin(), a[1].sin()];
    let mut r = [s[0].min(s[1]), s[0].max(s[1])];
    if hits(a, FRAC_PI_2, 2.0 * PI) {
        r[1] = 1.0;
    }
    if hits(a, -FRAC_PI_2, 2.0 * PI) {
        r[0] = -1.0;
    }
    r
}

/// tan is increasing between its poles π/2 + kπ; a pole inside gives the
/// whole line.
fn tan(a: Interval) -> Interval {
    if trig_hopeless(a, PI) || hits(a, FRAC_PI_2, PI) {
        return WHOLE;
    }
    [a[0].tan(), a[1].tan()]
}

fn call2(f: Func2, a: Interval, b: Interval) -> Interval {
    match f {
        Func2::Min => [a[0].min(b[0]), a[1].min(b[1])],
        Func2::Max => [a[0].max(b[0]), a[1].max(b[1])],
        Func2::Atan2 => atan2(a, b),
        Func2::Pow => pow(a, b),
        Func2::PowN => match b[0] {
            n if n >= 1.0 => powi(a, n as u32),
            _ => [1.0, 1.0],
        },
    }
}

/// atan2(y, x) by half-planes: right (x > 0), upper (y > 0), lower (y < 0);
/// anything else may wrap around the branch cut.
fn atan2(y: Interval, x: Interval) -> Interval {
    let atan = |i: Interval| [i[0].atan(), i[1].atan()];
    if x[0] > 0.0 {
        return atan(div(y, x));
    }
    if y[0] > 0.0 {
        let r = atan(div(x, y));
        return [FRAC_PI_2 - r[1], FRAC_PI_2 - r[0]];
    }
    if y[1] < 0.0 {
        let r = atan(div(x, y));
        return [-FRAC_PI_2 - r[1], -FRAC_PI_2 - r[0]];
    }
    [-PI, PI]
}

/// a^b for real b, defined for a ≥ 0: b·ln a is bilinear in (b, ln a), so
/// the extremes are at the corners of the (a, b) box.
fn pow(a: Interval, b: Interval) -> Interval {
    if a[1] < 0.0 {
        return EMPTY;
    }
    let lo = a[0].max(0.0);
    let c = [super::pow_pos(lo, b[0]), super::pow_pos(lo, b[1]), super::pow_pos(a[1], b[0]), super::pow_pos(a[1], b[1])];
    let r = [c.iter().copied().fold(f64::INFINITY, f64::min), c.iter().copied().fold(f64::NEG_INFINITY, f64::max)];
    [r[0].max(0.0), r[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(src: &str) -> Ir {
        crate::Formula::compile("<test>", src).unwrap().ir
    }
    fn x(lo: f64, hi: f64) -> [[f64; 2]; 4] {
        [[lo, hi], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]
    }

    #[test]
    fn basic_rules() {
        assert_eq!(eval_interval(&f("x^2"), x(-1.0, 2.0), &[]), [0.0, 4.0]);
        assert_eq!(eval_interval(&f("x^3"), x(-1.0, 2.0), &[]), [-1.0, 8.0]);
        assert_eq!(eval_interval(&f("x*x"), x(-1.0, 2.0), &[]), [-2.0, 4.0]);
        assert_eq!(eval_interval(&f("sqrt(x)"), x(-1.0, 4.0), &[]), [0.0, 2.0]);
        assert_eq!(eval_interval(&f("sin(x)"), x(0.0, 3.0), &[])[1], 1.0);
        assert_eq!(eval_interval(&f("1/x"), x(0.0, 2.0), &[]), [0.5, f64::INFINITY]);
        assert_eq!(eval_interval(&f("tan(x)"), x(1.0, 2.0), &[]), WHOLE);
    }

    #[test]
    fn strict_emptiness() {
        assert_eq!(eval_interval(&f("x + sqrt(-1 - x^2)"), x(-1.0, 2.0), &[]), EMPTY);
        assert_eq!(eval_interval(&f("min(x, log(x))"), x(-2.0, -1.0), &[]), EMPTY);
        assert_eq!(eval_interval(&f("min(x, log(x))"), x(-2.0, 1.0), &[]), [f64::NEG_INFINITY, 0.0]);
    }

    #[test]
    fn infinities_stay_enclosures() {
        // (x - x itself is 0: the semantic pass collects like terms.)
        assert_eq!(eval_interval(&f("x - sqrt(x^2)"), x(1.0, f64::INFINITY), &[]), WHOLE);
        assert_eq!(eval_interval(&f("0 * x"), x(1.0, f64::INFINITY), &[]), [0.0, 0.0]);
    }
}

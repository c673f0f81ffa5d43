//! Reduced affine arithmetic (RAA, Knoll et al.'s AF1 with n = 1) in f64 with
//! the rules of `templates/domains/affine.wgsl`.
//!
//! A form `[x0, x1, x2]` stands for `x0 + x1·e1 + x2·e2` with e1, e2 in
//! [−1, 1]; e1 is the ray parameter, e2 gathers every other error and
//! `x2 ≥ 0`. Empty: `x2 < 0`, canonically `[0, 0, −1]`. A form that cannot
//! be represented with finite centre and e1 coefficient (an unbounded
//! interval, ∞ − ∞) becomes the whole line `[0, 0, +∞]`.
//!
//! Operations without a safe affine rule go through [`super::interval`] and
//! convert back, as in the WGSL library.

use super::interval::{self, interval_op, Interval, EMPTY};
use super::{evaluate, Value};
use crate::ir::{Func1, Func2, Func3, Ir, Op};

/// `[x0, x1, x2]`: `x0 + x1·e1 + x2·e2`.
pub type Form = [f64; 3];

/// The canonical empty form.
pub const EMPTY_FORM: Form = [0.0, 0.0, -1.0];
/// The whole real line.
pub const WHOLE_FORM: Form = [0.0, 0.0, f64::INFINITY];

/// Evaluates the formula on affine forms of x, y, z and t. For a box, lift
/// each side with [`affine_from_interval`] (as the device's eval kernel
/// does); for a ray segment p + d·[t0, t1] pass `[p + d·tc, d·tr, 0]` per
/// coordinate (tc, tr: centre and radius of [t0, t1]), as the render
/// kernel does. Returns the result form, [`EMPTY_FORM`] when some sqrt /
/// log / real power is undefined everywhere; [`affine_range`] turns it into
/// an interval.
pub fn eval_affine(ir: &Ir, forms: [[f64; 3]; 4], params: &[f64]) -> [f64; 3] {
    let r = evaluate::<Af>(ir, forms.map(|f| Af(fix(f))), params).0;
    if is_empty(r) { EMPTY_FORM } else { r }
}

/// The interval a form stands for: `x0 ± (|x1| + x2)`; `[1, −1]` when empty.
pub fn affine_range(a: Form) -> [f64; 2] {
    if is_empty(a) {
        return EMPTY;
    }
    let r = radius(a);
    let i = [a[0] - r, a[0] + r];
    [if i[0].is_nan() { f64::NEG_INFINITY } else { i[0] }, if i[1].is_nan() { f64::INFINITY } else { i[1] }]
}

/// The form of an interval: centre, no e1 part, half-width on e2.
/// Empty stays empty, a point (even ±∞) is exact, any other unbounded
/// interval becomes [`WHOLE_FORM`].
pub fn affine_from_interval(i: [f64; 2]) -> [f64; 3] {
    if interval::is_empty(i) {
        return EMPTY_FORM;
    }
    if i[0] == i[1] {
        return [i[0], 0.0, 0.0]; // exact, even ±inf
    }
    if !(i[0].is_finite() && i[1].is_finite()) {
        return WHOLE_FORM;
    }
    fix([0.5 * i[0] + 0.5 * i[1], 0.0, 0.5 * i[1] - 0.5 * i[0]])
}

/// True for an empty form.
pub fn is_empty(a: Form) -> bool {
    a[2] < 0.0
}

fn radius(a: Form) -> f64 {
    a[1].abs() + a[2]
}

/// Keeps a non-empty form representable: NaN anywhere, or an infinite centre
/// or e1 coefficient, makes it the whole line (an infinite point ±∞ stays).
fn fix(a: Form) -> Form {
    if is_empty(a) || (a[0].is_infinite() && a[1] == 0.0 && a[2] == 0.0) {
        a
    } else if !(a[0].is_finite() && a[1].is_finite()) || a[2].is_nan() {
        WHOLE_FORM
    } else {
        a
    }
}

/// Newtype so [`Value`] can be implemented for forms.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Af(pub Form);

impl Value for Af {
    fn constant(c: f64) -> Af {
        Af(fix([c, 0.0, 0.0]))
    }
    fn apply(op: &Op, args: &[Af]) -> Af {
        let mut a = [EMPTY_FORM; 3];
        for (i, v) in args.iter().enumerate() {
            a[i] = v.0;
        }
        Af(affine_op(op, &a[..args.len()]))
    }
    fn is_undefined(&self) -> bool {
        is_empty(self.0)
    }
    fn undefined() -> Af {
        Af(EMPTY_FORM)
    }
}

/// Applies one operation to forms (in operand order) with the WGSL
/// library's rule for that operation.
pub fn affine_op(op: &Op, a: &[Form]) -> Form {
    let r = match *op {
        Op::Const(c) => [c, 0.0, 0.0],
        Op::Var(_) | Op::Param(_) | Op::User(..) => WHOLE_FORM,
        Op::Neg(_) => neg(a[0]),
        Op::Add(..) => [a[0][0] + a[1][0], a[0][1] + a[1][1], a[0][2] + a[1][2]],
        Op::Sub(..) => [a[0][0] - a[1][0], a[0][1] - a[1][1], a[0][2] + a[1][2]],
        Op::Mul(..) => mul(a[0], a[1]),
        Op::Div(..) => div(a[0], a[1]),
        Op::PowI(_, 2) => sqr(a[0]),
        Op::PowI(_, n) => powi(a[0], n),
        Op::Call1(Func1::Abs, _) => abs(a[0]),
        Op::Call2(Func2::Min, ..) => min(a[0], a[1]),
        Op::Call2(Func2::Max, ..) => max(a[0], a[1]),
        Op::Call3(Func3::Clamp, ..) => min(max(a[0], a[1]), a[2]),
        Op::Call3(Func3::Mix, ..) => {
            let (x, y, s) = (a[0], a[1], a[2]);
            let d = [y[0] - x[0], y[1] - x[1], y[2] + x[2]];
            let p = mul(d, s);
            [x[0] + p[0], x[1] + p[1], x[2] + p[2]]
        }
        // No affine rule: through the interval library.
        Op::Call1(..) | Op::Call2(..) => {
            let mut i = [EMPTY; 2];
            for (k, f) in a.iter().enumerate() {
                i[k] = affine_range(*f);
            }
            affine_from_interval(interval_op(op, &i[..a.len()]))
        }
    };
    fix(r)
}

fn neg(a: Form) -> Form {
    [-a[0], -a[1], a[2]]
}

/// A product term: 0 · ±∞ is 0.
fn pmul(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 { 0.0 } else { a * b }
}

/// Knoll et al. eq. (14), with the e1·e1 term made exact: x1·y1·e1² lies in
/// [0, x1·y1] (or [x1·y1, 0]), so half of it moves into the centre and half
/// into e2; the other products of noise symbols go to e2.
fn mul(a: Form, b: Form) -> Form {
    let q = 0.5 * pmul(a[1], b[1]);
    [
        pmul(a[0], b[0]) + q,
        pmul(a[0], b[1]) + pmul(b[0], a[1]),
        pmul(a[0], b[2]).abs() + pmul(b[0], a[2]).abs() + q.abs() + pmul(a[1], b[2]).abs() + pmul(a[2], b[1]).abs() + pmul(a[2], b[2]),
    ]
}

/// AF1 square: (x1 e1 + x2 e2)² lies in [0, r²], so half of r² moves into
/// the centre.
fn sqr_affine(a: Form) -> Form {
    let r = radius(a);
    let h = 0.5 * r * r;
    [a[0] * a[0] + h, 2.0 * a[0] * a[1], 2.0 * pmul(a[0].abs(), a[2]) + h]
}

/// The affine square, unless it reaches below 0 (the form straddles 0 and
/// the square has lost its sign) and the interval even-power rule is not
/// wider.
fn sqr(a: Form) -> Form {
    let s = sqr_affine(a);
    let i = interval::sqr(affine_range(a));
    if !(s[0].is_finite() && s[2].is_finite()) {
        return affine_from_interval(i);
    }
    if s[0] - radius(s) < 0.0 && i[1] - i[0] <= 2.0 * radius(s) { affine_from_interval(i) } else { s }
}

/// Of two valid enclosures keep the affine one (its e1 term carries the
/// correlation later cancellations need) unless the interval is less than
/// half as wide (high powers): then the interval.
fn narrower(a: Form, i: Interval) -> Form {
    if i[1] - i[0] < radius(a) { affine_from_interval(i) } else { a }
}

/// a^n (odd n from the front end): the affine square-and-multiply chain of
/// the emitter, and the interval power; the narrower wins.
fn powi(a: Form, n: u32) -> Form {
    let bits = 32 - n.leading_zeros();
    let mut w = a;
    for bit in (0..bits - 1).rev() {
        w = fix(sqr_affine(w));
        if n >> bit & 1 == 1 {
            w = fix(mul(w, a));
        }
    }
    narrower(w, interval::powi(affine_range(a), n))
}

/// a · (1/b) keeps a's correlation when b has one sign; 1/b is an interval.
fn div(a: Form, b: Form) -> Form {
    let bi = affine_range(b);
    if bi[0] > 0.0 || bi[1] < 0.0 {
        return mul(a, affine_from_interval([1.0 / bi[1], 1.0 / bi[0]]));
    }
    affine_from_interval(interval::div(affine_range(a), bi))
}

/// abs keeps the form when the sign is known.
fn abs(a: Form) -> Form {
    let i = affine_range(a);
    if i[0] >= 0.0 {
        a
    } else if i[1] <= 0.0 {
        neg(a)
    } else {
        affine_from_interval([0.0, (-i[0]).max(i[1])])
    }
}

/// min keeps a form when one operand is certainly smaller.
fn min(a: Form, b: Form) -> Form {
    let (i, j) = (affine_range(a), affine_range(b));
    if i[1] <= j[0] {
        a
    } else if j[1] <= i[0] {
        b
    } else {
        affine_from_interval([i[0].min(j[0]), i[1].min(j[1])])
    }
}

fn max(a: Form, b: Form) -> Form {
    let (i, j) = (affine_range(a), affine_range(b));
    if i[0] >= j[1] {
        a
    } else if j[0] >= i[1] {
        b
    } else {
        affine_from_interval([i[0].max(j[0]), i[1].max(j[1])])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(src: &str) -> Ir {
        crate::Formula::compile("<test>", src).unwrap().ir
    }

    #[test]
    fn linear_forms_are_exact() {
        // Along a ray segment x = y = e1 in [-1, 1]: x - y is exactly 0.
        let e1 = [0.0, 1.0, 0.0];
        let r = eval_affine(&f("x - y"), [e1, e1, [0.0; 3], [0.0; 3]], &[]);
        assert_eq!(affine_range(r), [0.0, 0.0]);
        // x*y with x = y = 1 + e1: (1 + e1)² = 1.5 + 2·e1 + 0.5·e2 (e1² in [0, 1]).
        let c = [1.0, 1.0, 0.0];
        let r = eval_affine(&f("x*y"), [c, c, [0.0; 3], [0.0; 3]], &[]);
        assert_eq!(r, [1.5, 2.0, 0.5]);
    }

    #[test]
    fn conversions() {
        assert_eq!(affine_from_interval([1.0, 3.0]), [2.0, 0.0, 1.0]);
        assert_eq!(affine_range([2.0, -0.5, 1.0]), [0.5, 3.5]);
        assert_eq!(affine_range(affine_from_interval([1.0, -1.0])), [1.0, -1.0]);
        assert_eq!(affine_from_interval([0.0, f64::INFINITY]), WHOLE_FORM);
    }

    #[test]
    fn strict_emptiness() {
        let b = affine_from_interval([-1.0, 2.0]);
        let r = eval_affine(&f("max(x, sqrt(-1 - x^2))"), [b, b, b, b], &[]);
        assert!(is_empty(r));
        assert_eq!(affine_range(r), [1.0, -1.0]);
    }
}

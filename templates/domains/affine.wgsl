// isotrace reduced affine domain (RAA): Knoll et al.'s AF1 with n = 1.
// A form (x0, x1, x2) in a vec3<f32> stands for x0 + x1*e1 + x2*e2 with
// e1, e2 in [-1, 1]. e1 is the ray parameter (x, y, z along a ray segment are
// exact forms); e2 gathers every other error and its coefficient x2 is
// always >= 0, which is what makes AF1 an inclusion for every composition.
//
// Empty: x2 < 0; the canonical form (0, 0, -1) converts to the empty interval
// (1, -1). Operations without a safe affine rule (division, transcendental
// functions, sqrt, real powers, floor, sign) go through the interval library
// and convert back, as Knoll et al. do. Branch-free, as interval.wgsl is
// (its header says why). Requires interval.wgsl.

fn ra_const(c: f32) -> vec3<f32> { return vec3<f32>(c, 0.0, 0.0); }
// A literal from its nearest f32 and its enclosing f32 interval, as the
// generated code writes one (exact: a constant form; else the interval).
fn ra_lit(n: f32, lo: f32, hi: f32) -> vec3<f32> {
    return select(ra_from_ia(vec2<f32>(lo, hi)), ra_const(n), lo == hi);
}
fn ra_empty() -> vec3<f32> { return vec3<f32>(0.0, 0.0, -1.0); }
fn ra_is_empty(a: vec3<f32>) -> bool { return a.z < 0.0; }
fn ra_radius(a: vec3<f32>) -> f32 { return abs(a.y) + a.z; }
// ra_range(a), the interval a form stands for, is in affine_range.wgsl
// (or affine_range_bounded.wgsl), spliced before this library.
// The whole line: an unbounded interval has no centre.
fn ra_whole() -> vec3<f32> { return vec3<f32>(0.0, 0.0, iso_inf()); }
// Neither infinite nor NaN (tested on the bits: lavapipe folds NaN compares).
fn ra_finite(a: f32) -> bool { return (bitcast<u32>(a) & 0x7f800000u) != 0x7f800000u; }
// The form of an interval. Only a point needs a case of its own: an
// overflowed one (inf, inf) stays exact, where d would be NaN. Everything
// else is arithmetic, because this runs in every op that converts, hundreds
// of times in a big formula, and each select and test here cost lavapipe's
// compiler and the unoptimised frame more than the op around it (a big RAA
// formula's cold first frame comes markedly sooner without finite tests
// and a second centre rule). What the cases left out give:
// - an unbounded interval: d = inf, and a centre of inf or NaN; ra_range, the
//   only way a form's bounds are read, turns any NaN end into the whole line,
//   so it still reads as the whole line, and NaN or inf propagate through
//   the arithmetic ops to the next ra_range;
// - finite ends beyond f32::MAX / 2: c = i.x + d cannot overflow where the
//   ends have one sign, and where they straddle 0, d is inf (the whole line
//   again) exactly when i.y - i.x overflows;
// - empty (i.x > i.y): d < 0, which is what ra_is_empty tests, and its
//   range is again inverted (empty).
fn ra_from_ia(i: vec2<f32>) -> vec3<f32> {
    let d = 0.5 * (i.y - i.x);
    let point = i.x == i.y;
    return vec3<f32>(select(i.x + d, i.x, point), 0.0, select(d, 0.0, point));
}
// Of two valid enclosures, keep the affine one (its e1 term carries the
// correlation that later cancellations need) unless the interval is less
// than half as wide: then the affine form has lost its value (high powers,
// the even-power rule across 0) and the interval is used.
fn ra_narrower(a: vec3<f32>, i: vec2<f32>) -> vec3<f32> {
    return select(a, ra_from_ia(i), i.y - i.x < ra_radius(a));
}

fn ra_neg(a: vec3<f32>) -> vec3<f32> { return vec3<f32>(-a.x, -a.y, a.z); }
fn ra_add(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> { return a + b; }
fn ra_sub(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> { return vec3<f32>(a.x - b.x, a.y - b.y, a.z + b.z); }
// A product with an exact f32 (ra_mul with ra_const(p), its zero terms
// dropped; a zero factor gives 0).
fn ra_scale(a: vec3<f32>, p: f32) -> vec3<f32> {
    return select(vec3<f32>(a.x * p, a.y * p, abs(a.z * p)), vec3<f32>(0.0), p == 0.0);
}
// Knoll et al. eq. (14), sharpened where both forms depend on the ray
// symbol: the x1*y1*e1^2 part of the product lies in [0, x1*y1] (e1^2 is in
// [0, 1]), so half of it moves into the centre and only |x1*y1|/2 (not
// |x1*y1|) goes to the error term; the other cross terms are bounded as in
// (14), whose rad(x)*rad(y) is |x1 y1| + |x1| y2 + x2 |y1| + x2 y2. Along a
// ray, where x, y, z are pure e1 forms, this halves the error of x*y and
// saves evaluations (the Barth decic takes about a tenth fewer).
fn ra_mul(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let q = 0.5 * a.y * b.y;
    return vec3<f32>(
        a.x * b.x + q,
        a.x * b.y + b.x * a.y,
        abs(a.x * b.z) + abs(b.x * a.z) + abs(q) + abs(a.y * b.z) + abs(a.z * b.y) + a.z * b.z);
}
// AF1 square: (x1 e1 + x2 e2)^2 lies in [0, r^2], so half of r^2 moves into
// the centre. When the affine square reaches below 0 (the form straddles 0)
// it has lost the sign: the interval even-power rule is used if it is not wider.
fn ra_sqr_affine(a: vec3<f32>) -> vec3<f32> {
    let r = ra_radius(a);
    let h = 0.5 * r * r;
    return vec3<f32>(a.x * a.x + h, 2.0 * a.x * a.y, 2.0 * abs(a.x) * a.z + h);
}
fn ra_sqr(a: vec3<f32>) -> vec3<f32> {
    let s = ra_sqr_affine(a);
    let i = ia_sqr(ra_range(a));
    // An overflowed affine square (inf centre or radius) has lost everything.
    let lost = s.x - ra_radius(s) < 0.0 && i.y - i.x <= 2.0 * ra_radius(s);
    return select(s, ra_from_ia(i), !ra_finite(s.x) || !ra_finite(s.z) || lost);
}
// Odd powers: the affine chain and the interval ends are carried together and
// the narrower result is kept at the end.
struct RaPow { a: vec3<f32>, e: vec2<f32> }
fn ra_pw_lift(a: vec3<f32>) -> RaPow { return RaPow(a, ra_range(a)); }
fn ra_pw_sq(w: RaPow) -> RaPow { return RaPow(ra_sqr_affine(w.a), w.e * w.e); }
fn ra_pw_mul(u: RaPow, v: RaPow) -> RaPow { return RaPow(ra_mul(u.a, v.a), u.e * v.e); }
fn ra_pw_odd(a: vec3<f32>, w: RaPow) -> vec3<f32> { return ra_narrower(w.a, w.e); }
// a^n for an integer n in [0, 31] known only at run time (s_pown): the odd
// power's chain of a, or of a's square for an even n (to n/2), as the
// written-out powers do; the chain multiplies the powers 2^i that the
// exponent's bits select.
fn ra_pw_times(r: RaPow, w: RaPow, on: bool) -> RaPow {
    let p = ra_pw_mul(r, w);
    return RaPow(select(r.a, p.a, on), select(r.e, p.e, on));
}
fn ra_pown(a: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let k = u32(n.x);
    let even = (k & 1u) == 0u;
    let b = select(a, ra_sqr(a), even);
    let m = select(k, k >> 1u, even);
    let w1 = ra_pw_lift(b);
    let w2 = ra_pw_sq(w1);
    let w4 = ra_pw_sq(w2);
    let w8 = ra_pw_sq(w4);
    var r = RaPow(ra_const(1.0), vec2<f32>(1.0));
    r = ra_pw_times(r, w1, (m & 1u) != 0u);
    r = ra_pw_times(r, w2, (m & 2u) != 0u);
    r = ra_pw_times(r, w4, (m & 4u) != 0u);
    r = ra_pw_times(r, w8, (m & 8u) != 0u);
    r = ra_pw_times(r, ra_pw_sq(w8), (m & 16u) != 0u);
    return ra_pw_odd(b, r);
}

fn ra_div(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let bi = ra_range(b);
    // a * (1/b) keeps a's correlation; 1/b itself is an interval.
    let q = ra_mul(a, ra_from_ia(vec2<f32>(1.0 / bi.y, 1.0 / bi.x)));
    return select(ra_from_ia(ia_div_by_zero(ra_range(a), bi)), q, bi.x > 0.0 || bi.y < 0.0);
}
// abs keeps the form when the sign is known.
fn ra_abs(a: vec3<f32>) -> vec3<f32> {
    let i = ra_range(a);
    return select(select(ra_from_ia(ia_abs(i)), ra_neg(a), i.y <= 0.0), a, i.x >= 0.0);
}
// min/max keep the form when one operand is certainly smaller. Otherwise
// the result is the interval of the two ranges' min or max, converted as
// ra_from_ia does but without its point case: an interval that neither
// operand dominates is never a single point (if max(i, j) were [m, m],
// the operand whose lower end is m would be a point at or above the
// other's upper end, and so dominate).
fn ra_min(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let i = ra_range(a);
    let j = ra_range(b);
    let lo = min(i.x, j.x);
    let d = 0.5 * (min(i.y, j.y) - lo);
    return select(select(vec3<f32>(lo + d, 0.0, d), b, j.y <= i.x), a, i.y <= j.x);
}
fn ra_max(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let i = ra_range(a);
    let j = ra_range(b);
    let lo = max(i.x, j.x);
    let d = 0.5 * (max(i.y, j.y) - lo);
    return select(select(vec3<f32>(lo + d, 0.0, d), b, j.x >= i.y), a, i.x >= j.y);
}
fn ra_clamp(v: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> vec3<f32> { return ra_min(ra_max(v, lo), hi); }
fn ra_mix(a: vec3<f32>, b: vec3<f32>, s: vec3<f32>) -> vec3<f32> { return ra_add(a, ra_mul(ra_sub(b, a), s)); }

fn ra_sqrt(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_sqrt(ra_range(a))); }
fn ra_exp(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_exp(ra_range(a))); }
fn ra_log(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_log(ra_range(a))); }
fn ra_sin(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_sin(ra_range(a))); }
fn ra_cos(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_cos(ra_range(a))); }
fn ra_tan(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_tan(ra_range(a))); }
fn ra_atan(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_atan(ra_range(a))); }
fn ra_sinh(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_sinh(ra_range(a))); }
fn ra_cosh(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_cosh(ra_range(a))); }
fn ra_tanh(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_tanh(ra_range(a))); }
fn ra_sign(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_sign(ra_range(a))); }
fn ra_floor(a: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_floor(ra_range(a))); }
fn ra_pow(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_pow(ra_range(a), ra_range(b))); }
fn ra_atan2(y: vec3<f32>, x: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_atan2(ra_range(y), ra_range(x))); }

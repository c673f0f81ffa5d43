// isotrace interval domain (IA): an interval [lo, hi] is a vec2<f32> (lo, hi).
//
// Empty interval: any value with lo > hi; the canonical one is (1, -1). It
// comes only from sqrt, log and pow on arguments entirely outside their
// domain. The generated evaluator ORs ia_is_empty over those results and
// returns ia_empty() for the whole function, because every operation is
// strict (an undefined argument makes the result undefined); so the other
// operations need not test for it.
//
// NaN: lavapipe drops NaN operands in min/max and folds x != x to false, so
// NaN ends are never compared for emptiness and the zero test used by the
// traversal, !(lo > 0 || hi < 0), treats a NaN end as "may contain zero".
//
// Branch-free: every case is computed and the result chosen with select().
// lavapipe runs both sides of an `if` under a lane mask anyway, and
// branches (early returns most of all) cost its compiler far more than
// selects: with the affine library written this way, a big RAA formula
// compiles several times sooner.
// A discarded case may compute inf or NaN; select() never lets it through.
//
// Rounding: like Knoll et al. we do not round arithmetic outward (the
// traversal's eps dominates f32 rounding); transcendental functions, whose
// WGSL accuracy is only a few ulp (sin/cos 2^-11 absolute), are padded.

const IA_PI: f32 = 3.14159265358979;
const IA_TWO_PI: f32 = 6.28318530717959;
const IA_HALF_PI: f32 = 1.57079632679490;

fn ia_const(c: f32) -> vec2<f32> { return vec2<f32>(c, c); }
// A literal from its nearest f32 and its enclosing f32 interval (the tape
// interpreter's constants carry all three).
fn ia_lit(n: f32, lo: f32, hi: f32) -> vec2<f32> { return vec2<f32>(lo, hi); }
fn ia_empty() -> vec2<f32> { return vec2<f32>(1.0, -1.0); }
fn ia_is_empty(a: vec2<f32>) -> bool { return a.x > a.y; }
fn ia_range(a: vec2<f32>) -> vec2<f32> { return a; }
fn ia_whole() -> vec2<f32> { return vec2<f32>(-iso_inf(), iso_inf()); }
fn ia_straddles(a: vec2<f32>) -> bool { return a.x < 0.0 && a.y > 0.0; }

// Outward padding of a computed interval by an absolute and relative margin.
fn ia_pad(r: vec2<f32>, abs_err: f32, rel_err: f32) -> vec2<f32> {
    return vec2<f32>(r.x - abs_err - abs(r.x) * rel_err, r.y + abs_err + abs(r.y) * rel_err);
}

fn ia_neg(a: vec2<f32>) -> vec2<f32> { return -a.yx; }
fn ia_add(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> { return a + b; }
fn ia_sub(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> { return a - b.yx; }
// A product with an exact f32 (a constant, a ray direction): two products
// instead of four. A zero factor gives 0, also with an unbounded a (its
// function is finite everywhere), as ia_mul does.
fn ia_scale(a: vec2<f32>, p: f32) -> vec2<f32> {
    let q = a * p;
    return select(vec2<f32>(min(q.x, q.y), max(q.x, q.y)), vec2<f32>(0.0), p == 0.0);
}
fn ia_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    // 0 * inf is 0 for the ends of a product (an unbounded interval never
    // contains inf itself). IEEE gives NaN, which lavapipe's min/max drop:
    // [0, 0] * [-inf, inf] came out as NaN and max(that, c) as c alone.
    let zero = (a.xxyy == vec4<f32>(0.0)) | (b.xyxy == vec4<f32>(0.0));
    let p = select(a.xxyy * b.xyxy, vec4<f32>(0.0), zero);
    return vec2<f32>(min(min(p.x, p.y), min(p.z, p.w)), max(max(p.x, p.y), max(p.z, p.w)));
}
// a·b for a and b whose functions are never negative (src/analysis/nonneg.rs
// `nonneg`): [lo·lo, hi·hi], two products where ia_mul takes four and six
// comparisons. Their enclosures may reach below 0 by a pad (a node taken
// from the ray); the product's values are not negative all the same.
fn ia_mul_nonneg(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let lo = max(a.x, 0.0) * max(b.x, 0.0);
    // 0 * inf: a factor whose range ends at 0 is 0 there.
    return vec2<f32>(lo, select(a.y * b.y, 0.0, a.y <= 0.0 || b.y <= 0.0));
}
// d·v for a v whose function is never negative and any d: each end of d
// times the end of v that makes it extreme (v's upper end for d's negative
// lower end and positive upper end, else v's lower end, at least 0).
fn ia_mul_by_nonneg(d: vec2<f32>, v: vec2<f32>) -> vec2<f32> {
    let vl = max(v.x, 0.0);
    let fl = select(vl, v.y, d.x < 0.0);
    let fh = select(vl, v.y, d.y > 0.0);
    return vec2<f32>(select(d.x * fl, 0.0, d.x == 0.0 || fl == 0.0), select(d.y * fh, 0.0, d.y == 0.0 || fh == 0.0));
}
// Division: a divisor that contains 0 gives a half-line when 0 is one of its
// ends and the numerator keeps one sign, else the whole line.
fn ia_div(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return select(ia_div_by_zero(a, b), ia_mul(a, vec2<f32>(1.0 / b.y, 1.0 / b.x)), b.x > 0.0 || b.y < 0.0);
}
// a / b for a divisor whose function is never negative (sqrt's slope
// 1 / (2 sqrt(u))): the same quotient as ia_div, where b > 0 as the product
// with ia_mul_by_nonneg's two multiplications, where b's range reaches 0 the
// half-line or whole line of ia_div_by_zero. ia_div's general product is
// not compiled into it: @city has a sqrt in each of its 37 distances.
fn ia_div_by_nonneg(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return select(ia_div_by_zero(a, b), ia_mul_by_nonneg(a, vec2<f32>(1.0 / b.y, 1.0 / b.x)), b.x > 0.0);
}
// The quotient for a divisor that contains 0 (or a NaN end), on its own so
// that ra_div, which has an affine form for every other divisor, does not
// also carry ia_div's product (lavapipe compiles both sides of a select).
// A divisor [0, b] (from_zero) or [b, 0] (to_zero) and a numerator of one
// sign give a half-line bounded by one quotient: a.x / den if a >= 0, else
// a.y / den if a <= 0, where den is the divisor's other end. The ray is
// [q, inf) for a >= 0 over [0, b] and for a <= 0 over [b, 0], else
// (-inf, q]. Every other case is the whole line. (One division, where four
// were written out: this is compiled into every ra_div and ia_div.)
fn ia_div_by_zero(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let inf = iso_inf();
    let from_zero = b.x == 0.0 && b.y > 0.0;
    let to_zero = b.y == 0.0 && b.x < 0.0;
    let pos = a.x >= 0.0;
    let q = select(a.y, a.x, pos) / select(b.x, b.y, from_zero);
    let half = (from_zero || to_zero) && (pos || a.y <= 0.0);
    let r = select(vec2<f32>(-inf, q), vec2<f32>(q, inf), pos == from_zero);
    return select(ia_whole(), r, half);
}
// Even-power rule for squares: tight when the interval straddles 0.
fn ia_sqr(a: vec2<f32>) -> vec2<f32> {
    let s = a * a;
    return vec2<f32>(select(min(s.x, s.y), 0.0, ia_straddles(a)), max(s.x, s.y));
}
// Odd powers are monotone: raise both ends by squaring and multiplying.
fn ia_pw_lift(a: vec2<f32>) -> vec2<f32> { return a; }
fn ia_pw_sq(w: vec2<f32>) -> vec2<f32> { return w * w; }
fn ia_pw_mul(u: vec2<f32>, v: vec2<f32>) -> vec2<f32> { return u * v; }
fn ia_pw_odd(a: vec2<f32>, w: vec2<f32>) -> vec2<f32> { return w; }
// a^n for an integer n in [0, 31] known only at run time (s_pown): an odd
// power raises both ends (monotone), an even one raises the ends of the
// square's range to n/2, as the written-out powers do. Each end is the
// product of the powers 2^i that the exponent's bits select.
fn ia_pown(a: vec2<f32>, n: vec2<f32>) -> vec2<f32> {
    let k = u32(n.x);
    let even = (k & 1u) == 0u;
    let b = select(a, ia_sqr(a), even);
    let m = select(k, k >> 1u, even);
    let b2 = b * b;
    let b4 = b2 * b2;
    let b8 = b4 * b4;
    let b16 = b8 * b8;
    let one = vec2<f32>(1.0);
    let lo = select(one, b, (m & 1u) != 0u) * select(one, b2, (m & 2u) != 0u);
    let hi = select(one, b4, (m & 4u) != 0u) * select(one, b8, (m & 8u) != 0u);
    return lo * hi * select(one, b16, (m & 16u) != 0u);
}

fn ia_sqrt(a: vec2<f32>) -> vec2<f32> {
    return select(ia_pad(sqrt(vec2<f32>(max(a.x, 0.0), a.y)), 0.0, 3e-7), ia_empty(), a.y < 0.0);
}
// The pads below are twice the largest error measured on lavapipe (20 000
// points per function and range, against f64; see the conformance suite):
// log 1.5e-7 absolute near 1 and 1.5e-6 relative; exp, sinh and cosh a
// relative error that grows with |x| (3.9e-6 at |x| = 88: exp is computed
// as exp2(x log2 e)), sinh 1.2e-7 absolute near 0, tanh 1.4e-7 absolute,
// atan 3.1e-6 absolute (174 ulp near 0).
fn ia_log(a: vec2<f32>) -> vec2<f32> {
    let lo = select(-iso_inf(), log(a.x), a.x > 0.0);
    return select(ia_pad(vec2<f32>(lo, log(a.y)), 3e-7, 4e-7), ia_empty(), a.y <= 0.0);
}
// Pads a result of exp / sinh / cosh at a: relative 4e-7 + |a| 1e-7 per end.
fn ia_pad_exp(r: vec2<f32>, a: vec2<f32>, abs_err: f32) -> vec2<f32> {
    let rel = 4e-7 + abs(a) * 1e-7;
    return vec2<f32>(r.x - abs_err - abs(r.x) * rel.x, r.y + abs_err + abs(r.y) * rel.y);
}
fn ia_exp(a: vec2<f32>) -> vec2<f32> {
    let r = ia_pad_exp(exp(a), a, 0.0);
    return vec2<f32>(max(r.x, 0.0), r.y);
}
// sinh and cosh for |x| > 80 as 0.5 e^(x/2) e^(x/2): lavapipe's builtins
// overflow to inf from |x| = 88.72 on, where exp(x) does, although the
// results stay finite up to 89.41.
fn iso_sinh(x: vec2<f32>) -> vec2<f32> {
    let h = exp(0.5 * abs(x));
    return select(sinh(x), sign(x) * (0.5 * h) * h, abs(x) > vec2<f32>(80.0));
}
fn iso_cosh(x: vec2<f32>) -> vec2<f32> {
    let h = exp(0.5 * abs(x));
    return select(cosh(x), (0.5 * h) * h, abs(x) > vec2<f32>(80.0));
}
fn ia_sinh(a: vec2<f32>) -> vec2<f32> { return ia_pad_exp(iso_sinh(a), a, 2.5e-7); }
fn ia_tanh(a: vec2<f32>) -> vec2<f32> { return clamp(ia_pad(tanh(a), 2.5e-7, 2e-6), vec2<f32>(-1.0), vec2<f32>(1.0)); }
fn ia_atan(a: vec2<f32>) -> vec2<f32> {
    return clamp(ia_pad(atan(a), 6.5e-6, 0.0), vec2<f32>(-IA_HALF_PI), vec2<f32>(IA_HALF_PI));
}
fn ia_cosh(a: vec2<f32>) -> vec2<f32> {
    let c = iso_cosh(a);
    var r = vec2<f32>(min(c.x, c.y), max(c.x, c.y));
    var m = vec2<f32>(max(abs(a.x), abs(a.y)));
    r.x = select(r.x, 1.0, ia_straddles(a));
    r = ia_pad_exp(r, m, 0.0);
    return vec2<f32>(max(r.x, 1.0), r.y);
}
fn ia_abs(a: vec2<f32>) -> vec2<f32> {
    let m = abs(a);
    return vec2<f32>(select(min(m.x, m.y), 0.0, ia_straddles(a)), max(m.x, m.y));
}
fn ia_sign(a: vec2<f32>) -> vec2<f32> { return sign(a); }
fn ia_floor(a: vec2<f32>) -> vec2<f32> { return floor(a); }
fn ia_min(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> { return min(a, b); }
fn ia_max(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> { return max(a, b); }
fn ia_clamp(v: vec2<f32>, lo: vec2<f32>, hi: vec2<f32>) -> vec2<f32> { return min(max(v, lo), hi); }
fn ia_mix(a: vec2<f32>, b: vec2<f32>, s: vec2<f32>) -> vec2<f32> {
    // a*(1 - s) + b*s: an inclusion for any s (not only s in [0, 1]).
    return ia_add(ia_mul(a, ia_sub(ia_const(1.0), s)), ia_mul(b, s));
}

// Whether the trigonometric enclosures give up on a: wider than one period
// (or NaN), or too far out for lo / period to place the extrema.
fn ia_trig_wide(a: vec2<f32>, period: f32) -> bool {
    return !(a.y - a.x < period) || !(abs(a.x) < 1e6) || !(abs(a.y) < 1e6);
}
// cos over [lo, hi]: the ends, plus +1 if a multiple of 2*pi lies inside and
// -1 if an odd multiple of pi does. The tests use a small slack so rounding
// in lo / 2pi can only include an extremum, never skip one.
fn ia_cos(a: vec2<f32>) -> vec2<f32> {
    let c = cos(a);
    var r = vec2<f32>(min(c.x, c.y), max(c.x, c.y));
    let slack = 1e-6 + abs(a.x) * 2e-7;
    let k_max = ceil((a.x - slack) / IA_TWO_PI);
    r.y = select(r.y, 1.0, k_max * IA_TWO_PI <= a.y + slack);
    let k_min = ceil((a.x - IA_PI - slack) / IA_TWO_PI);
    r.x = select(r.x, -1.0, k_min * IA_TWO_PI + IA_PI <= a.y + slack);
    r = ia_pad(r, 2e-6 + abs(a.x) * 1e-7, 0.0);
    return select(clamp(r, vec2<f32>(-1.0), vec2<f32>(1.0)), vec2<f32>(-1.0, 1.0), ia_trig_wide(a, IA_TWO_PI));
}
fn ia_sin(a: vec2<f32>) -> vec2<f32> {
    let s = sin(a);
    var r = vec2<f32>(min(s.x, s.y), max(s.x, s.y));
    let slack = 1e-6 + abs(a.x) * 2e-7;
    // maxima at pi/2 + 2k*pi, minima at -pi/2 + 2k*pi
    let k_max = ceil((a.x - IA_HALF_PI - slack) / IA_TWO_PI);
    r.y = select(r.y, 1.0, k_max * IA_TWO_PI + IA_HALF_PI <= a.y + slack);
    let k_min = ceil((a.x + IA_HALF_PI - slack) / IA_TWO_PI);
    r.x = select(r.x, -1.0, k_min * IA_TWO_PI - IA_HALF_PI <= a.y + slack);
    r = ia_pad(r, 2e-6 + abs(a.x) * 1e-7, 0.0);
    return select(clamp(r, vec2<f32>(-1.0), vec2<f32>(1.0)), vec2<f32>(-1.0, 1.0), ia_trig_wide(a, IA_TWO_PI));
}
// tan is increasing between its poles pi/2 + k*pi; a pole inside gives the whole line.
fn ia_tan(a: vec2<f32>) -> vec2<f32> {
    let slack = 1e-6 + abs(a.x) * 2e-7;
    let k = ceil((a.x - IA_HALF_PI - slack) / IA_PI);
    let pole = k * IA_PI + IA_HALF_PI <= a.y + slack;
    return select(ia_pad(tan(a), 1e-6, 4e-6), ia_whole(), ia_trig_wide(a, IA_PI) || pole);
}
fn ia_atan2(y: vec2<f32>, x: vec2<f32>) -> vec2<f32> {
    let q = ia_atan(ia_div(x, y));
    var r = vec2<f32>(-IA_PI - 1e-6, IA_PI + 1e-6);
    r = select(r, ia_sub(ia_const(-IA_HALF_PI), q), y.y < 0.0);
    r = select(r, ia_sub(ia_const(IA_HALF_PI), q), y.x > 0.0);
    return select(r, ia_atan(ia_div(y, x)), x.x > 0.0);
}
// a^b for real b, defined for a >= 0: monotone in each argument, so the
// extremes are at the corners of the (a, b) box.
fn ia_pow(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let lo = max(a.x, 0.0);
    let c = vec4<f32>(iso_pow_pos(lo, b.x), iso_pow_pos(lo, b.y), iso_pow_pos(a.y, b.x), iso_pow_pos(a.y, b.y));
    let r = vec2<f32>(min(min(c.x, c.y), min(c.z, c.w)), max(max(c.x, c.y), max(c.z, c.w)));
    // exp2(b log2 a): log2's absolute error scaled by |b|, and exp2's
    // relative error growing with |b log2 a| = |log2 result| (lavapipe: up
    // to 9e-6 relative for results near 1e34).
    var k = 2e-6 + max(abs(b.x), abs(b.y)) * 3e-7;
    let l = abs(log2(r));
    k = k + select(0.0, l.x * 1.5e-7, r.x > 0.0 && l.x < 200.0);
    k = k + select(0.0, l.y * 1.5e-7, r.y > 0.0 && l.y < 200.0);
    let r2 = ia_pad(r, 1e-7, k);
    return select(vec2<f32>(max(r2.x, 0.0), r2.y), ia_empty(), a.y < 0.0);
}

// isotrace scalar domain: plain f32 evaluation of the formula.
// Every number domain (scalar s_, interval ia_, affine ra_) defines the same
// operations with its own prefix, so one emitter serves all three.
// The kernel that includes this library provides iso_inf() and iso_param(i).

fn s_const(c: f32) -> f32 { return c; }
fn s_neg(a: f32) -> f32 { return -a; }
fn s_add(a: f32, b: f32) -> f32 { return a + b; }
fn s_sub(a: f32, b: f32) -> f32 { return a - b; }
fn s_mul(a: f32, b: f32) -> f32 { return a * b; }
fn s_scale(a: f32, p: f32) -> f32 { return a * p; }
fn s_div(a: f32, b: f32) -> f32 { return a / b; }
fn s_sqr(a: f32) -> f32 { return a * a; }
// Odd integer powers: a chain of squarings and products (Russian peasant).
fn s_pw_lift(a: f32) -> f32 { return a; }
fn s_pw_sq(w: f32) -> f32 { return w * w; }
fn s_pw_mul(u: f32, v: f32) -> f32 { return u * v; }
fn s_pw_odd(a: f32, w: f32) -> f32 { return w; }
// a^n for an integer n in [0, 31] known only at run time (an exponent a
// rerolled sum of monomials reads from its table, as an exact float): the
// product of the powers a^(2^i) that n's bits select. Written out, not a
// loop, so it adds nothing to the invocation's loop count.
fn s_pown(a: f32, n: f32) -> f32 {
    let k = u32(n);
    let a2 = a * a;
    let a4 = a2 * a2;
    let a8 = a4 * a4;
    let a16 = a8 * a8;
    let lo = select(1.0, a, (k & 1u) != 0u) * select(1.0, a2, (k & 2u) != 0u);
    let hi = select(1.0, a4, (k & 4u) != 0u) * select(1.0, a8, (k & 8u) != 0u);
    return lo * hi * select(1.0, a16, (k & 16u) != 0u);
}
fn s_sqrt(a: f32) -> f32 { return sqrt(a); }
fn s_exp(a: f32) -> f32 { return exp(a); }
fn s_log(a: f32) -> f32 { return log(a); }
fn s_sin(a: f32) -> f32 { return sin(a); }
fn s_cos(a: f32) -> f32 { return cos(a); }
fn s_tan(a: f32) -> f32 { return tan(a); }
fn s_atan(a: f32) -> f32 { return atan(a); }
fn s_sinh(a: f32) -> f32 { return sinh(a); }
fn s_cosh(a: f32) -> f32 { return cosh(a); }
fn s_tanh(a: f32) -> f32 { return tanh(a); }
fn s_abs(a: f32) -> f32 { return abs(a); }
fn s_sign(a: f32) -> f32 { return sign(a); }
fn s_floor(a: f32) -> f32 { return floor(a); }
fn s_pow(a: f32, b: f32) -> f32 { return iso_pow_pos(a, b); }
fn s_atan2(y: f32, x: f32) -> f32 { return atan2(y, x); }
fn s_min(a: f32, b: f32) -> f32 { return min(a, b); }
fn s_max(a: f32, b: f32) -> f32 { return max(a, b); }
fn s_clamp(v: f32, lo: f32, hi: f32) -> f32 { return min(max(v, lo), hi); }
fn s_mix(a: f32, b: f32, s: f32) -> f32 { return a + (b - a) * s; }
// A point value is never empty; NaN marks points outside a function's domain.
fn s_is_empty(a: f32) -> bool { return false; }
fn s_empty() -> f32 { return iso_nan(); }
fn s_range(a: f32) -> vec2<f32> { return vec2<f32>(a, a); }

// a^b for a >= 0 with the limits IEEE pow gives (0^b = 0, 1 or inf);
// NaN for a < 0 (outside the domain of a real exponent).
fn iso_pow_pos(a: f32, b: f32) -> f32 {
    let at_zero = select(select(iso_inf(), 1.0, b == 0.0), 0.0, b > 0.0);
    return select(select(exp2(b * log2(a)), at_zero, a == 0.0), iso_nan(), a < 0.0);
}
fn iso_nan() -> f32 { return bitcast<f32>(bitcast<u32>(iso_inf()) | 0x00400000u); }
fn iso_is_nan(a: f32) -> bool { return (bitcast<u32>(a) & 0x7fffffffu) > 0x7f800000u; }
// A literal with its enclosing f32 interval: the point value (the tape
// interpreter's constants carry all three; each domain takes its own).
fn s_lit(n: f32, lo: f32, hi: f32) -> f32 { return n; }
// The derivative helpers in the scalar domain: the tape interpreter runs
// one instruction set in every domain, though scalar programs never hold
// derivative instructions.
fn s_whole() -> f32 { return iso_nan(); }
fn s_dmin(a: f32, b: f32, da: f32, db: f32) -> f32 { return select(db, da, a <= b); }
fn s_dmax(a: f32, b: f32, da: f32, db: f32) -> f32 { return select(db, da, a >= b); }
fn s_dsign(a: f32, da: f32) -> f32 { return 0.0; }
fn s_dfloor(a: f32, da: f32) -> f32 { return 0.0; }

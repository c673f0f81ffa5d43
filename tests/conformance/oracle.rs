//! The sampling oracle of the conformance suites: sample points of a box,
//! the strict f64 scalar function there, and the rounding margin allowed
//! between a sample and an enclosure.

use super::{Box8, Rng};
use isotrace::ir::{Func1, Func2, Func3, Ir, Op};
use isotrace::reference::affine::affine_op;
use isotrace::reference::interval::interval_op;
use isotrace::reference::{self, scalar_op, var_index};
use std::f64::consts::{FRAC_PI_2, PI};

/// Floating-point format an enclosure was computed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// The device (WGSL f32; lavapipe flushes subnormals).
    F32,
    /// The CPU reference.
    F64,
}

impl Precision {
    /// Unit roundoff.
    pub fn unit(self) -> f64 {
        match self {
            Precision::F32 => f64::from(f32::EPSILON) / 2.0,
            Precision::F64 => f64::EPSILON / 2.0,
        }
    }
    /// Smallest normal number: results below it may be flushed to 0.
    pub fn tiny(self) -> f64 {
        match self {
            Precision::F32 => f64::from(f32::MIN_POSITIVE),
            Precision::F64 => f64::MIN_POSITIVE,
        }
    }
    /// Largest finite number.
    pub fn max(self) -> f64 {
        match self {
            Precision::F32 => f64::from(f32::MAX),
            Precision::F64 => f64::MAX,
        }
    }
}

/// The scalar function at one point, with a bound on how far an evaluation
/// in the backend's precision can stray from it.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// [x, y, z, t].
    pub p: [f64; 4],
    /// `reference::eval_scalar` (strict: NaN when some sqrt / log / pow is undefined).
    pub v: f64,
    /// First-order bound of the rounding error of evaluating `v` in the
    /// backend's precision (see [`margin`]); +∞ when unknown.
    pub err: f64,
    /// Some sqrt / log / real power has its argument within `err` of the
    /// edge of its domain: rounding may decide whether it is defined.
    pub marginal: bool,
}

/// Rounding error (in units of the unit roundoff) the libraries can make in
/// one operation: a few roundings relative to `size`, the magnitude of the
/// node's values over the box (see [`node_scales`]). Arithmetic: the
/// operation and, in RAA, the centre ± radius of the result. Library
/// functions count as one correctly rounded step plus RAA's conversion to
/// and from an interval: their extra inaccuracy must be covered by the WGSL
/// library's own padding, which is what the suite checks. clamp and mix
/// round at the magnitude of their operands (`arg_size`).
fn rounding(op: &Op, size: f64, arg_size: &[f64]) -> f64 {
    match *op {
        Op::Const(_) | Op::Var(_) | Op::Param(_) | Op::Neg(_) => 0.0,
        Op::Add(..) | Op::Sub(..) | Op::Mul(..) => 3.0 * size,
        Op::Div(..) => 4.0 * size,
        Op::PowI(_, n) => 2.0 * f64::from(32 - n.leading_zeros()) * size,
        Op::Call1(..) | Op::Call2(..) => 3.0 * size,
        // min(max(v, lo), hi): the inner max is converted at its own size.
        Op::Call3(Func3::Clamp, ..) => 3.0 * size + 3.0 * arg_size.iter().fold(0.0f64, |m, &a| m.max(a)),
        // a + (b - a)·s and a·(1 - s) + b·s.
        Op::Call3(Func3::Mix, ..) => 3.0 * size + 4.0 * (arg_size[0] + arg_size[1]) * (1.0 + arg_size[2]),
    }
}

/// How far `op` can move when its arguments move by up to `errs`: the
/// largest change over the corners of the argument error box (exact for
/// functions monotone in each argument; close enough for the others, whose
/// extremum inside the box moves the value less than the far corner does),
/// +∞ across a singularity. The flag says a restricted function's argument
/// reaches the edge of its domain.
fn deviation(op: &Op, args: &[f64], errs: &[f64], val: f64) -> (f64, bool) {
    let n = args.len();
    let edge = match *op {
        Op::Call1(Func1::Sqrt, _) | Op::Call2(Func2::Pow, ..) => args[0] - errs[0] < 0.0,
        Op::Call1(Func1::Log, _) => args[0] - errs[0] <= 0.0,
        _ => false,
    };
    if !val.is_finite() || args.iter().any(|a| a.is_nan()) || errs.iter().any(|e| e.is_infinite()) {
        // Past an overflow, a pole or a NaN (that min/max may have dropped): unknown.
        return (f64::INFINITY, edge);
    }
    let singular = match *op {
        // Also an exact 0: x/0 is ±inf by the sign of the zero alone.
        Op::Div(..) => args[1].abs() <= errs[1],
        Op::Call1(Func1::Tan, _) => {
            let k = |x: f64| ((x - FRAC_PI_2) / PI).floor();
            k(args[0] - errs[0]) != k(args[0] + errs[0])
        }
        _ => false,
    };
    if singular {
        return (f64::INFINITY, edge);
    }
    if errs.iter().all(|&e| e == 0.0) {
        return (0.0, edge);
    }
    let mut dev: f64 = 0.0;
    let mut c = [0.0; 3];
    for mask in 0..(1u32 << n) {
        for i in 0..n {
            let s = if mask >> i & 1 == 1 { 1.0 } else { -1.0 };
            c[i] = args[i] + s * errs[i];
        }
        if edge {
            c[0] = c[0].max(0.0); // the edge value itself (sqrt(0), 0^b, log(0))
        }
        let f = scalar_op(op, &c[..n]);
        if f.is_nan() {
            return (f64::INFINITY, edge);
        }
        dev = dev.max((f - val).abs());
    }
    (if dev.is_nan() { f64::INFINITY } else { dev }, edge)
}

/// Magnitude of the values the backend computes at each node over a box:
/// the largest finite |end| of the node's IA and RAA enclosures (f64
/// reference, no strictness), at least 0. Rounding at a node is relative to
/// these, not to the node's value at one sample: an enclosure end of
/// `sinh` over [-4, 0.002] converted to an RAA form and back loses
/// u·sinh(4), however small sinh(0.002) is.
/// `inputs` are extra magnitudes of x, y, z, t: a ray segment's coordinates
/// are computed from |o| + |d·s|, however small they are on the segment.
pub fn node_scales(ir: &Ir, b: &Box8, params: &[f64], inputs: [f64; 4]) -> Vec<f64> {
    let mut iv = vec![[0.0; 2]; ir.nodes.len()];
    let mut af = vec![[0.0; 3]; ir.nodes.len()];
    let mut scale = vec![0.0; ir.nodes.len()];
    for id in ir.live() {
        let op = ir.nodes[id as usize];
        let (i, a) = match op {
            Op::Var(v) => {
                let k = var_index(v);
                let i = [f64::from(b[2 * k]), f64::from(b[2 * k + 1])];
                (i, reference::affine_from_interval(i))
            }
            Op::Param(k) => {
                let c = params[k as usize];
                ([c, c], [c, 0.0, 0.0])
            }
            _ => {
                let o = op.operands();
                let ia: Vec<[f64; 2]> = o.iter().map(|&k| iv[k as usize]).collect();
                let aa: Vec<[f64; 3]> = o.iter().map(|&k| af[k as usize]).collect();
                (interval_op(&op, &ia), affine_op(&op, &aa))
            }
        };
        let r = reference::affine_range(a);
        let extra = if let Op::Var(v) = op { inputs[var_index(v)] } else { 0.0 };
        scale[id as usize] = [i[0], i[1], r[0], r[1]].iter().filter(|e| e.is_finite()).fold(extra, |m, e| m.max(e.abs()));
        iv[id as usize] = i;
        af[id as usize] = a;
    }
    scale
}

/// Evaluates the scalar function at `p` and bounds the error the backend's
/// arithmetic can make there (see [`margin`]); `scale` from [`node_scales`].
/// `lifted`: the inputs x, y, z, t are rounded on the way in (RAA's centre ±
/// radius of a box side; o + d·s of a ray segment), not exact box ends.
pub fn sample(ir: &Ir, p: [f64; 4], params: &[f64], scale: &[f64], prec: Precision, lifted: bool) -> Sample {
    let (u, tiny, max) = (prec.unit(), prec.tiny(), prec.max());
    let mut val = vec![f64::NAN; ir.nodes.len()];
    let mut err = vec![0.0; ir.nodes.len()];
    let mut marginal = false;
    for id in ir.live() {
        let op = ir.nodes[id as usize];
        let o = op.operands();
        let args: Vec<f64> = o.iter().map(|&i| val[i as usize]).collect();
        let errs: Vec<f64> = o.iter().map(|&i| err[i as usize]).collect();
        let (v, mut e) = match op {
            Op::Const(c) => (c, u * c.abs()),
            // RAA lifts a box side to centre ± radius, a segment computes
            // o + d·s: two roundings. IA takes box ends as they are.
            Op::Var(x) => (p[var_index(x)], if lifted { 2.0 * u * scale[id as usize] } else { 0.0 }),
            Op::Param(i) => (params[i as usize], 0.0),
            _ => {
                let v = scalar_op(&op, &args);
                let (d, edge) = deviation(&op, &args, &errs, v);
                marginal |= edge && op.restricts_domain();
                let size = v.abs().max(scale[id as usize]);
                let arg_size: Vec<f64> = o.iter().map(|&i| val[i as usize].abs().max(scale[i as usize])).collect();
                (v, d + u * rounding(&op, size, &arg_size) + tiny)
            }
        };
        if v.abs() > max {
            // Overflow: the backend holds ±inf; what follows is not comparable.
            e = f64::INFINITY;
        }
        val[id as usize] = v;
        err[id as usize] = e;
    }
    let v = reference::eval_scalar(ir, p, params);
    let raw = val[ir.root as usize];
    assert!(v.to_bits() == raw.to_bits() || v.is_nan(), "eval_scalar disagrees with the op-by-op walk at {p:?}: {v} vs {raw}");
    Sample { p, v, err: err[ir.root as usize], marginal }
}

/// The margin allowed between a finite sample value and an enclosure end
/// `[lo, hi]` computed in `prec`: `4 · s.err + 4u · max(|lo|, |hi|)`.
///
/// The WGSL libraries, like Knoll et al.'s, do not round outward, so an end
/// computed in f32 can miss the exact value by the rounding error the
/// arithmetic accumulates on the way. `s.err` is a first-order bound of that
/// error at the sample ([`sample`]):
///
/// * each operation rounds a few times (see `rounding`: 3 for + − × and
///   library functions, 4 for ÷, 2 per step of an integer-power chain) at
///   u = 2^-24 relative to the *magnitude of its values over the box* — the
///   largest end of the node's f64 IA / RAA enclosure — not to its value at
///   the sample, because the device computes enclosure ends, and RAA's
///   centre ± radius conversions lose u·|end| however small the sample's
///   value is;
/// * the inputs are exact for IA on a box; RAA's centre ± radius of a box
///   side and a ray segment's o + d·s round twice relative to the
///   coordinates' magnitude;
/// * plus the smallest normal f32 (lavapipe flushes subnormals to 0);
/// * arguments' errors propagate through the operation's variation over the
///   arguments' error box, so cancellation, poles and the jumps of floor /
///   sign are accounted for; a sample whose evaluation overflows f32::MAX
///   anywhere, or passes an infinity, a NaN or a division by an exact 0
///   (whose sign decides ±∞), has an infinite margin, i.e. is not checked
///   (only its sign, against an end that overflowed: see [`check`]).
///
/// The factor 4 is a safety factor for the first-order model; the term in
/// the enclosure's own ends covers the rounding of the final centre ±
/// radius. The libraries' inaccurate transcendental functions are *not* in
/// the margin: the WGSL pads them itself, and that padding is part of what
/// is tested. For the CPU reference the same model runs with u = 2^-53.
pub fn margin(s: &Sample, lo: f64, hi: f64, prec: Precision) -> f64 {
    let ends = [lo, hi].iter().filter(|e| e.is_finite()).fold(0.0f64, |m, e| m.max(e.abs()));
    4.0 * s.err + 4.0 * prec.unit() * ends
}

/// Special values of one coordinate inside [lo, hi]: 0, ±1, multiples of
/// π/2 (extrema of sin/cos, poles of tan), a few integers (jumps of floor).
pub(super) fn specials(lo: f64, hi: f64) -> Vec<f64> {
    let mut s: Vec<f64> = [0.0, 1.0, -1.0].into_iter().filter(|v| (lo..=hi).contains(v)).collect();
    // Enumerate multiples of `step` in [lo, hi] when there are only a few
    // (and they are still distinct numbers).
    let mut multiples = |step: f64, most: f64| {
        let (k0, k1) = ((lo / step).ceil(), (hi / step).floor());
        if lo.is_finite() && hi.is_finite() && k1 - k0 < most && k0.abs() < 1e12 {
            for j in 0..=((k1 - k0).max(-1.0) as i64) {
                let v = (k0 + j as f64) * step;
                if (lo..=hi).contains(&v) {
                    s.push(v);
                }
            }
        }
    };
    multiples(FRAC_PI_2, 8.0);
    multiples(1.0, 4.0);
    s
}

/// A random point of [lo, hi] (log-spread along an infinite side).
fn inside(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    match (lo.is_finite(), hi.is_finite()) {
        (true, true) => rng.range(lo, hi).clamp(lo, hi),
        (true, false) => lo + rng.log_range(1e-3, 1e30),
        (false, true) => hi - rng.log_range(1e-3, 1e30),
        (false, false) => rng.sign() * rng.log_range(1e-3, 1e30),
    }
}

/// Sample points of a box: the corners (over the variables the formula
/// uses), random interior points, and each variable at its special values.
pub fn sample_points(rng: &mut Rng, ir: &Ir, b: &Box8) -> Vec<[f64; 4]> {
    let vars: Vec<usize> = ir.variables().into_iter().map(var_index).collect();
    let side = |v: usize| (f64::from(b[2 * v]), f64::from(b[2 * v + 1]));
    let mut base = [0.0; 4];
    for (v, x) in base.iter_mut().enumerate() {
        *x = side(v).0.clamp(-1e30, 1e30);
    }
    let mut pts = Vec::new();
    for mask in 0..(1u32 << vars.len()) {
        let mut p = base;
        for (k, &v) in vars.iter().enumerate() {
            let (lo, hi) = side(v);
            // Points are real numbers: an infinite side is sampled far out.
            p[v] = if mask >> k & 1 == 1 { hi.min(1e30) } else { lo.max(-1e30) };
        }
        pts.push(p);
    }
    let random = |rng: &mut Rng| {
        let mut p = base;
        for &v in &vars {
            let (lo, hi) = side(v);
            p[v] = inside(rng, lo, hi);
        }
        p
    };
    for _ in 0..8 {
        pts.push(random(rng));
    }
    for &v in &vars {
        let (lo, hi) = side(v);
        for s in specials(lo, hi) {
            for _ in 0..2 {
                let mut p = random(rng);
                p[v] = s;
                pts.push(p);
            }
        }
    }
    pts
}


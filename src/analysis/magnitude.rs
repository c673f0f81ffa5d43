//! How large a formula's values can get: the input radius within which no
//! node of the formula can overflow f32, so that its affine forms are
//! always finite.
//!
//! Why. The RAA library's `ra_range` turns a NaN end into the whole line,
//! because lavapipe's min and max silently drop a NaN (an overflowed or
//! unbounded form would otherwise read as a wrong finite interval). That
//! test runs for every range an op reads, hundreds of times in a big
//! formula, and it is a large part of what lavapipe compiles and runs
//! (a big RAA formula's cold first frame is markedly cheaper without it;
//! docs/benchmarks.md). A form can only be NaN after an overflow
//! or an unbounded operation (a division, log, tan, a real power), so for
//! a formula of bounded operations whose values stay below f32::MAX for
//! every input within a radius B, the test is not needed within B.
//!
//! The bound. For an affine form (x0, x1, x2) let R = |x0| + |x1| + x2, the
//! largest magnitude its range reaches. Each op of the library keeps R
//! below the natural bound of its operands' R: a sum below R_a + R_b, a
//! product below R_a·R_b (every term of `ra_mul` is one of the products of
//! (|x0| + |x1| + x2)(|y0| + |y1| + y2)), a square below R_a², min, max and
//! abs below the larger R, clamp below its bounds' R, and an op through an
//! interval below the interval function's bound on [-R, R]. [`bounds`]
//! computes such bounds per node in f64 with a rounding allowance (signed
//! where an op keeps a sign), and [`safe_radius`] finds the
//! largest power of two B for which every node stays below [`LIMIT`], far
//! under f32::MAX. The kernel checks its inputs against B (`ra_safe`) and
//! gives the whole line past it, so the result is sound for any input.

use crate::ir::{Func1, Func2, Func3, Ir, Op};

/// The largest bound a node may reach: 2^100, 2^28 below f32::MAX, so the
/// intermediate products inside an op (and its rounding) stay finite.
pub const LIMIT: f64 = 1.2676506002282294e30;

/// The smallest input radius of a kernel without the NaN test: 2^20. Past
/// the radius an enclosure is the whole line, which leaves pixels
/// unresolved where the guarded kernel would have drawn them, so the radius
/// must hold every domain box (and the frustum slabs the tile pass
/// encloses around it) a user may give: a million units, where f32 depths
/// are already coarse. (At 2^12, sq.csg's x^8 and a sextic under a min
/// would also qualify.)
pub const MIN_RADIUS: f64 = 1048576.0;

/// Rounding allowance per operation, relative to its result's bound (or,
/// for a product, to its operands' product, of which a sum in `ra_mul` can
/// cancel most): f32 rounds to 2^-24, and an op rounds up to six times in
/// a row (`ra_mul`'s error term). The interval functions' pads are added
/// where they are larger. (It matters only to the small end of a bound that
/// keeps its sign, such as exp's argument: the magnitudes are far within
/// f32 at [`LIMIT`].)
const ROUNDING: f64 = 1.0 / (1u64 << 21) as f64;

/// Bounds [lo, hi] on the range of a node's form.
type Span = (f64, f64);

fn mag((lo, hi): Span) -> f64 {
    lo.abs().max(hi.abs())
}

const UNBOUNDED: Span = (f64::NEG_INFINITY, f64::INFINITY);

/// Per node: bounds on the range of its affine form for inputs (x, y, z,
/// t and every parameter) of magnitude at most `b` (the whole line for a
/// node that may be unbounded whatever `b` is). Signed where the library's
/// rule keeps a sign (sums, min, max, abs, a square, a clamp), so that
/// max(k - |u|, 0)³ or exp(-u²) stay small; a product of two forms may
/// reach past the product of their ranges (AF1), so it is bounded by the
/// product of magnitudes, both signs.
pub fn bounds(ir: &Ir, b: f64) -> Vec<(f64, f64)> {
    let mut m: Vec<Span> = Vec::with_capacity(ir.nodes.len());
    for op in &ir.nodes {
        let g = |n: &u32| m[*n as usize];
        let konst = |n: &u32| match ir.nodes[*n as usize] {
            Op::Const(k) => Some(k),
            _ => None,
        };
        let sym = |x: f64| (-x, x);
        let (v, scale) = match *op {
            Op::Const(c) => ((c, c), 0.0),
            Op::Var(_) | Op::Param(_) => ((-b, b), 0.0),
            Op::Neg(a) => ((-g(&a).1, -g(&a).0), 0.0),
            Op::Add(a, c) => ((g(&a).0 + g(&c).0, g(&a).1 + g(&c).1), 0.0),
            Op::Sub(a, c) => ((g(&a).0 - g(&c).1, g(&a).1 - g(&c).0), 0.0),
            Op::Mul(a, c) => match (konst(&a), konst(&c)) {
                (Some(k), _) => (scaled(g(&c), k), 0.0),
                (_, Some(k)) => (scaled(g(&a), k), 0.0),
                _ => (sym(mag(g(&a)) * mag(g(&c))), mag(g(&a)) * mag(g(&c))),
            },
            // Only a division by a constant is bounded (by its reciprocal).
            Op::Div(a, c) => match konst(&c) {
                Some(k) if k != 0.0 && (1.0 / k).is_finite() => (scaled(g(&a), 1.0 / k), 0.0),
                _ => (UNBOUNDED, 0.0),
            },
            // ra_sqr keeps the affine square only while its range stays at
            // or above 0; higher powers square forms without that check.
            Op::PowI(a, 2) => ((0.0, mag(g(&a)).powi(2)), 0.0),
            Op::PowI(a, n) => (sym(mag(g(&a)).powi(n as i32)), 0.0),
            Op::Call1(f, a) => (call1(f, g(&a)), 0.0),
            Op::Call2(Func2::Min, a, c) => ((g(&a).0.min(g(&c).0), g(&a).1.min(g(&c).1)), 0.0),
            Op::Call2(Func2::Max, a, c) => ((g(&a).0.max(g(&c).0), g(&a).1.max(g(&c).1)), 0.0),
            Op::Call2(Func2::Atan2, ..) => ((-4.0, 4.0), 0.0),
            Op::Call2(Func2::Pow, ..) => (UNBOUNDED, 0.0),
            // Never in an IR (generated code only): bounded by nothing here.
            Op::Call2(Func2::PowN, ..) => (UNBOUNDED, 0.0),
            // Every form clamp can give (v's where its range lies between
            // the bounds, a bound's, or an interval between them) stays
            // between the bounds. (v's own bounds hold inside ra_clamp.)
            Op::Call3(Func3::Clamp, _, lo, hi) => ((g(&lo).0.min(g(&hi).0), g(&lo).1.max(g(&hi).1)), 0.0),
            Op::Call3(Func3::Mix, a, c, s) => {
                let x = mag(g(&a)) + (mag(g(&a)) + mag(g(&c))) * mag(g(&s));
                (sym(x), mag(g(&a)).max(mag(g(&c))) * mag(g(&s)))
            }
            Op::User(..) => (UNBOUNDED, 0.0),
        };
        // Rounding, both ways.
        let e = ROUNDING * scale.max(mag(v));
        m.push((v.0 - e, v.1 + e));
    }
    m
}

/// `(lo, hi)` times `k`.
fn scaled((lo, hi): Span, k: f64) -> Span {
    if k >= 0.0 { (lo * k, hi * k) } else { (hi * k, lo * k) }
}

/// The bounds of f(a) for a's within `a`.
fn call1(f: Func1, a: Span) -> Span {
    let m = mag(a);
    match f {
        Func1::Sqrt => (0.0, a.1.max(0.0).sqrt()),
        Func1::Abs => (0.0, m),
        Func1::Floor => (a.0 - 1.0, a.1),
        Func1::Sin | Func1::Cos | Func1::Tanh | Func1::Sign => (-1.001, 1.001),
        Func1::Atan => (-2.0, 2.0),
        // e^a overflows f32 from a = 88.7: bounded only well below it.
        Func1::Exp if a.1 < 80.0 => (0.0, 1.001 * a.1.exp()),
        Func1::Cosh if m < 80.0 => (0.999, 1.001 * m.exp()),
        Func1::Sinh if m < 80.0 => (-1.001 * m.exp(), 1.001 * m.exp()),
        Func1::Exp | Func1::Sinh | Func1::Cosh | Func1::Log | Func1::Tan => UNBOUNDED,
    }
}

/// The largest power of two B (at least [`MIN_RADIUS`], at most 2^60) for
/// which every live node's bound stays within [`LIMIT`]; `None` where
/// there is none (an unbounded operation, or values that outgrow the limit
/// within [`MIN_RADIUS`]).
pub fn safe_radius(ir: &Ir) -> Option<f64> {
    let live = ir.live();
    let fits = |b: f64| {
        let m = bounds(ir, b);
        live.iter().all(|&n| mag(m[n as usize]) <= LIMIT)
    };
    if !fits(MIN_RADIUS) {
        return None;
    }
    let (mut lo, mut hi) = (MIN_RADIUS.log2() as i32, 60);
    while lo < hi {
        let mid = (lo + hi + 1) / 2;
        if fits(2f64.powi(mid)) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    Some(2f64.powi(lo))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn radius(src: &str) -> Option<f64> {
        safe_radius(&crate::Formula::compile("<test>", src).unwrap().ir)
    }

    #[test]
    fn polynomials_are_bounded_by_their_degree() {
        // x² + y² + z² - 1 < 2^100 needs 3·B² below it: B = 2^49.
        assert_eq!(radius("x^2 + y^2 + z^2 - 1"), Some(2f64.powi(49)));
        // A quartic: 3·B^4 below 2^100: B = 2^24.
        assert_eq!(radius("x^4 + y^4 + z^4 - 1"), Some(2f64.powi(24)));
        // A sextic would need B = 2^16, under the smallest radius.
        assert_eq!(radius("(x^2 + y^2)^3 - 4*x^2*y^2"), None);
        let f = crate::Formula::compile("<test>", "(x^2 + y^2)^3 - 4*x^2*y^2").unwrap();
        assert!(mag(bounds(&f.ir, 2f64.powi(16))[f.ir.root as usize]) <= LIMIT);
        assert!(mag(bounds(&f.ir, 2f64.powi(17))[f.ir.root as usize]) > LIMIT);
    }

    #[test]
    fn distance_forms_are_bounded_and_unbounded_operations_are_not() {
        let city = crate::catalog::lookup("city").unwrap().compile().unwrap();
        assert!(safe_radius(&city.ir).is_some_and(|b| b >= 2f64.powi(40)));
        assert!(radius("min(sqrt(x^2 + y^2) - 1, abs(z) - 0.5) + sin(t)").is_some());
        for src in ["x / y - 1", "log(x^2 + 1) - y", "tan(x) - y", "pow(x^2, y) - 1", "exp(x) - y"] {
            assert_eq!(radius(src), None, "{src}");
        }
        // Division by a constant and exp of a bounded argument are bounded,
        // and so are exp(-u²) and max(k - |u|, 0)³ (a smooth blend's
        // weight), whose signs the bounds keep.
        assert!(radius("x / 3 + exp(sin(y)) - z").is_some());
        let f = crate::Formula::compile("<test>", "exp(-(x^2 + y^2)) - z").unwrap();
        assert!(mag(bounds(&f.ir, 4096.0)[f.ir.root as usize]) <= LIMIT);
        let creature = crate::catalog::lookup("creature").unwrap().compile().unwrap();
        assert_eq!(safe_radius(&creature.ir), Some(2f64.powi(27)));
    }
}

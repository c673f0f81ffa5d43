//! Blends beyond the smooth ones, and the normalized density primitive.
//!
//! Each blend equals the sharp operator outside an operator range r_o
//! (Zanni's compactness: both operands below r_o for a union, above −r_o
//! for an intersection), so a blobtree can bound where its operands matter:
//! - chamfer: min(a, b, (a + b − r)/√2), a 45° bevel of width r. It differs
//!   from min(a, b) only where both operands are below r/(2 − √2);
//!   |∇| ≤ (|∇a| + |∇b|)/√2 ≤ √2 times the operands' bound.
//! - round: a circular fillet of radius r (Mercury's hg_sdf fOpUnionRound):
//!   max(r, min(a, b)) − |(max(r − a, 0), max(r − b, 0))|; it differs from
//!   min only where both are below r; |∇| ≤ √2 times the operands' bound
//!   (the gradient is a combination u₁∇a + u₂∇b with |u| = 1).
//! - sum: min(a, b) + min(max(a, b), T) − T, which is a + b − T where both
//!   are below T and min(a, b) elsewhere. On normalized density fields with
//!   the same T it is the summation blend of density fields (below).
//!   |∇| ≤ |∇a| + |∇b| where both are below T.
//!
//! **Normalized density.** A compactly supported kernel K(t) = (1 − t²)³
//! (t = d/R, 0 beyond the support radius R) of the distance d to a skeleton
//! (a segment of half length h along z; a point for h = 0), with isovalue c,
//! written as a field in length units:
//! T·(1 − K/c) + max(d − R, 0). It is ≤ 0 where K ≥ c, exactly T on the
//! edge of the support and grows like a distance beyond it, so it is
//! bounded (its {f ≤ r} is the ball of radius R + max(r − T, 0) around the
//! skeleton) and blends with distance fields. Summing such fields with
//! the same T by `sum` is T·(1 − ΣK/c): the density blend. Its slope within
//! the support is at most T·K'ₘₐₓ/(c·R), K'ₘₐₓ = 96/(25√5) ([`DENSITY_SLOPE`],
//! at t = 1/√5), so T = c·R/K'ₘₐₓ makes it 1-Lipschitz, and since the
//! surface (t ≈ 0.45 for c = ½) lies near the steepest point, it is then
//! close to a distance near the surface.
//!
//! The formula forms expand to these functions in their order of
//! operations (squares as `PowI(·, 2)` and k·k·k as `PowI(k, 3)`, which the
//! reference evaluator computes as the same products), so a compiled
//! formula and a scene agree to rounding.

use super::{Form, Sink, B};
use crate::ir::NodeId;

/// max over t of |d/dt (1 − t²)³| = 6t(1 − t²)² at t = 1/√5: 96/(25√5).
pub const DENSITY_SLOPE: f64 = 1.717_300_206_719_838_4;

/// 1/√2, the chamfer's diagonal.
const DIAGONAL: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The operator range of a chamfer of width r: r/(2 − √2).
pub fn chamfer_range(r: f64) -> f64 {
    r / (2.0 - std::f64::consts::SQRT_2)
}

/// chamfer_union(a, b, r) = min(min(a, b), (a + b − r)/√2).
pub fn chamfer_union(a: f64, b: f64, r: f64) -> f64 {
    a.min(b).min((a + b - r) * DIAGONAL)
}

/// chamfer_intersect(a, b, r) = max(max(a, b), (a + b + r)/√2).
pub fn chamfer_intersect(a: f64, b: f64, r: f64) -> f64 {
    a.max(b).max((a + b + r) * DIAGONAL)
}

/// round_union(a, b, r) = max(r, min(a, b)) − |(max(r − a, 0), max(r − b, 0))|,
/// which is r − |(r − a, r − b)| where both operands are below r and
/// min(a, b) elsewhere: written so, it is min(a, b) to the bit there, as a
/// blobtree's pruned evaluation (which drops an operand beyond r) needs.
pub fn round_union(a: f64, b: f64, r: f64) -> f64 {
    if a.max(b) < r {
        let (u, v) = (r - a, r - b);
        r - (u * u + v * v).sqrt()
    } else {
        a.min(b)
    }
}

/// round_intersect(a, b, r) = min(−r, max(a, b)) + |(max(r + a, 0), max(r + b, 0))|,
/// as [`round_union`]: −r + |(r + a, r + b)| where both are above −r, else max(a, b).
pub fn round_intersect(a: f64, b: f64, r: f64) -> f64 {
    if a.min(b) > -r {
        let (u, v) = (r + a, r + b);
        (u * u + v * v).sqrt() - r
    } else {
        a.max(b)
    }
}

/// sum_union(a, b, T) = min(a, b) + (min(max(a, b), T) − T): the bracket is
/// exactly 0 where an operand is at or beyond T, so the value is min(a, b)
/// to the bit there.
pub fn sum_union(a: f64, b: f64, t: f64) -> f64 {
    a.min(b) + (a.max(b).min(t) - t)
}

/// The normalized density at distance `d` from the skeleton:
/// T·(1 − K/c) + max(d − R, 0), K = max(1 − (d/R)², 0)³.
pub fn density(d: f64, radius: f64, iso: f64, range: f64) -> f64 {
    let t = d / radius;
    let k = (1.0 - t * t).max(0.0);
    range * (1.0 - k * k * k / iso) + (d - radius).max(0.0)
}

/// The range T that makes a density primitive 1-Lipschitz: c·R/K'ₘₐₓ.
pub fn density_default_range(radius: f64, iso: f64) -> f64 {
    iso * radius / DENSITY_SLOPE
}

/// The density primitive's Lipschitz bound: max(1, T·K'ₘₐₓ/(c·R)).
pub fn density_lipschitz(radius: f64, iso: f64, range: f64) -> f64 {
    (range * DENSITY_SLOPE / (iso * radius)).max(1.0)
}

/// Expands the chamfer, round and sum blends (`v`: the lowered arguments).
pub(super) fn lower<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    match form {
        Form::ChamferUnion | Form::ChamferIntersect | Form::ChamferSubtract => {
            b.positive(v, 2, "the chamfer width r")?;
            let (a, o) = operands(b, form == Form::ChamferSubtract, v)?;
            chamfer(b, form == Form::ChamferUnion, a, o, v[2])
        }
        Form::RoundUnion | Form::RoundIntersect | Form::RoundSubtract => {
            b.positive(v, 2, "the fillet radius r")?;
            let (a, o) = operands(b, form == Form::RoundSubtract, v)?;
            round(b, form == Form::RoundUnion, a, o, v[2])
        }
        // min(a, b) + (min(max(a, b), T) − T), as [`sum_union`].
        Form::SumUnion => {
            b.positive(v, 2, "the range T")?;
            let lo = b.min(v[0], v[1])?;
            let hi = b.max(v[0], v[1])?;
            let hi = b.min(hi, v[2])?;
            let excess = b.sub(hi, v[2])?;
            b.add(lo, excess)
        }
        _ => unreachable!("{form:?} is not a blend"),
    }
}

/// (a, b), or (a, −b) for a subtraction: a minus b is a ∩ not-b.
fn operands<S: Sink>(b: &mut B<'_, S>, subtract: bool, v: &[NodeId]) -> Result<(NodeId, NodeId), S::Error> {
    Ok((v[0], if subtract { b.neg(v[1])? } else { v[1] }))
}

/// min(min(a, b), (a + b − r)/√2) for a union, max(max(a, b), (a + b + r)/√2)
/// otherwise, as [`chamfer_union`] and [`chamfer_intersect`].
fn chamfer<S: Sink>(b: &mut B<'_, S>, union: bool, a: NodeId, o: NodeId, r: NodeId) -> Result<NodeId, S::Error> {
    let sum = b.add(a, o)?;
    let bevel = if union { b.sub(sum, r)? } else { b.add(sum, r)? };
    let diagonal = b.c(DIAGONAL)?;
    let bevel = b.mul(bevel, diagonal)?;
    if union {
        let m = b.min(a, o)?;
        b.min(m, bevel)
    } else {
        let m = b.max(a, o)?;
        b.max(m, bevel)
    }
}

/// max(r, min(a, b)) − |(max(r − a, 0), max(r − b, 0))| for a union,
/// min(−r, max(a, b)) + |(max(r + a, 0), max(r + b, 0))| otherwise: the
/// same function as [`round_union`] and [`round_intersect`], which branch
/// (the IR has no branch) so as to be min or max to the bit beyond r; here
/// r − (r − a) may differ from a in the last bit.
fn round<S: Sink>(b: &mut B<'_, S>, union: bool, a: NodeId, o: NodeId, r: NodeId) -> Result<NodeId, S::Error> {
    let zero = b.c(0.0)?;
    let mut uv = [0; 2];
    for (k, &n) in [a, o].iter().enumerate() {
        let e = if union { b.sub(r, n)? } else { b.add(r, n)? };
        uv[k] = b.max(e, zero)?;
    }
    let corner = b.length(&uv)?;
    if union {
        let m = b.min(a, o)?;
        let m = b.max(r, m)?;
        b.sub(m, corner)
    } else {
        let m = b.max(a, o)?;
        let nr = b.neg(r)?;
        let m = b.min(nr, m)?;
        b.add(m, corner)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slope_constant_is_the_kernels_steepest_slope() {
        assert!((DENSITY_SLOPE - 96.0 / (25.0 * 5f64.sqrt())).abs() < 1e-15);
        let worst = (0..100_000).map(|i| i as f64 / 100_000.0).map(|t| 6.0 * t * (1.0 - t * t).powi(2)).fold(0.0, f64::max);
        assert!(worst <= DENSITY_SLOPE && worst > DENSITY_SLOPE - 1e-9);
    }

    #[test]
    fn blends_are_sharp_outside_their_ranges() {
        let r = 0.3;
        let (co, ro) = (chamfer_range(r), r);
        for i in 0..200 {
            for j in 0..200 {
                let (a, b) = (-2.0 + i as f64 * 0.02, -2.0 + j as f64 * 0.02);
                if a.max(b) >= co {
                    assert_eq!(chamfer_union(a, b, r), a.min(b), "{a} {b}");
                }
                if a.min(b) <= -co {
                    assert_eq!(chamfer_intersect(a, b, r), a.max(b), "{a} {b}");
                }
                if a.max(b) >= ro {
                    assert_eq!(round_union(a, b, r), a.min(b), "{a} {b}");
                    assert_eq!(sum_union(a, b, r), a.min(b), "{a} {b}");
                }
                if a.min(b) <= -ro {
                    assert_eq!(round_intersect(a, b, r), a.max(b), "{a} {b}");
                }
                // Continuous across the edge of the range (the fillet meets min).
                let e = 1e-9;
                assert!((round_union(a, r - e, r) - round_union(a, r + e, r)).abs() < 1e-6);
                assert!((round_intersect(a, -r - e, r) - round_intersect(a, -r + e, r)).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn density_is_continuous_at_the_support_and_its_default_range_is_1_lipschitz() {
        let (r, c) = (1.3, 0.5);
        let t = density_default_range(r, c);
        assert!((density(r, r, c, t) - t).abs() < 1e-15);
        let mut worst: f64 = 0.0;
        for i in 0..20_000 {
            let d = i as f64 * 2.0 * r / 20_000.0;
            worst = worst.max((density(d + 1e-7, r, c, t) - density(d, r, c, t)).abs() / 1e-7);
        }
        assert!(worst <= 1.0 + 1e-6 && worst > 0.999, "{worst}");
        // The surface of a lone primitive: K = c.
        let d0 = r * (1.0 - c.powf(1.0 / 3.0)).sqrt();
        assert!(density(d0, r, c, t).abs() < 1e-12);
    }
}

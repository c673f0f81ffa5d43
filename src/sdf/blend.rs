//! The normalized density primitive's functions (its descriptor is
//! `primitive::density`). The blends beside the smooth ones (chamfer,
//! round, sum) are the joins, [`super::join`], a file each.
//!
//! **Normalized density.** A compactly supported kernel K(t) = (1 − t²)³
//! (t = d/R, 0 beyond the support radius R) of the distance d to a skeleton
//! (a segment of half length h along z; a point for h = 0), with isovalue c,
//! written as a field in length units:
//! T·(1 − K/c) + max(d − R, 0). It is ≤ 0 where K ≥ c, exactly T on the
//! edge of the support and grows like a distance beyond it, so it is
//! bounded (its {f ≤ r} is the ball of radius R + max(r − T, 0) around the
//! skeleton) and blends with distance fields. Summing such fields with
//! the same T by `sum_union` is T·(1 − ΣK/c): the density blend. Its slope within
//! the support is at most T·K'ₘₐₓ/(c·R), K'ₘₐₓ = 96/(25√5) ([`DENSITY_SLOPE`],
//! at t = 1/√5), so T = c·R/K'ₘₐₓ makes it 1-Lipschitz, and since the
//! surface (t ≈ 0.45 for c = ½) lies near the steepest point, it is then
//! close to a distance near the surface.
//!
//! The formula form expands to these functions in their order of
//! operations (squares as `PowI(·, 2)` and k·k·k as `PowI(k, 3)`, which the
//! reference evaluator computes as the same products), so a compiled
//! formula and a scene agree to rounding.

/// max over t of |d/dt (1 − t²)³| = 6t(1 − t²)² at t = 1/√5: 96/(25√5).
pub const DENSITY_SLOPE: f64 = 1.717_300_206_719_838_4;

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

//! Domain warps: `twist` and `bend`. Both rotate the xy plane of the point
//! by an angle that grows along one axis, so both keep a point's distance
//! from the z axis, ρ = √(x² + y²), and its z: a warped shape stays in the
//! cylinder (ρ, z range) of the shape it warps. That is what bounds it.
//!
//! **Lipschitz.** Warping multiplies the operand's bound by the largest
//! singular value of the warp's Jacobian, which grows with a = |k|·ρ:
//! - twist, (x, y, z) → (R(−kz)(x, y), z): the Jacobian is a rotation plus
//!   the column k·R'(−kz)(x, y) (length a) in the z direction, orthogonal
//!   to the rotation's columns, so σ_max = (a + √(a² + 4))/2 exactly;
//! - bend, (x, y, z) → (R(kx)(x, y), z): a rotation times I + u·e_xᵀ with
//!   |u| = a, whose σ_max is at most 1 + a (reached where (x, y) ∥ e_y).
//!
//! The bound is unbounded in ρ: a warp is only Lipschitz within a radius.
//! A blobtree scene bounds ρ by the warped leaf's bounding cylinder and
//! scales the field down outside it (`scene::warp`); a formula needs
//! `--lipschitz` from the user.
//!
//! The formula forms expand to [`twist_point`] and [`bend_point`] in their
//! order of operations, so a compiled formula and a scene agree to rounding.

use super::{Form, Sink, B};
use crate::ir::{Func1, NodeId};

/// twist(k, ·) at `p`: the point the operand is evaluated at. The shape
/// turns by +k·z radians about the z axis at height z (right-handed for
/// k > 0), so the point turns by −k·z: (c·x + s·y, −s·x + c·y, z) with
/// c = cos(kz), s = sin(kz).
pub fn twist_point(k: f64, p: [f64; 3]) -> [f64; 3] {
    let a = k * p[2];
    let (s, c) = (a.sin(), a.cos());
    [c * p[0] + s * p[1], c * p[1] - s * p[0], p[2]]
}

/// bend(k, ·) at `p`: the xy plane turned by k·x radians,
/// (c·x − s·y, s·x + c·y, z) with c = cos(kx), s = sin(kx). A bar along x
/// curls into an arc of radius 1/k in the xy plane.
pub fn bend_point(k: f64, p: [f64; 3]) -> [f64; 3] {
    let a = k * p[0];
    let (s, c) = (a.sin(), a.cos());
    [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]]
}

/// The twist's Lipschitz factor within radius ρ of the axis: (a + √(a² + 4))/2, a = |k|ρ.
pub fn twist_lipschitz(k: f64, rho: f64) -> f64 {
    let a = k.abs() * rho;
    (a + (a * a + 4.0).sqrt()) / 2.0
}

/// The bend's Lipschitz factor within radius ρ of the z axis: 1 + |k|ρ.
pub fn bend_lipschitz(k: f64, rho: f64) -> f64 {
    1.0 + k.abs() * rho
}

/// Expands `twist(k, shape)` or `bend(k, shape)`: the shape rebuilt over
/// the warped point. k is not checked: any k (0 too, where the sine and
/// cosine fold to 0 and 1 and the identities of [`B`] leave x, y, z) gives
/// a warp, only its Lipschitz factor grows with |k|.
pub(super) fn lower<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    let [x, y, z] = b.xyz()?;
    // The angle grows along z for a twist, along x for a bend.
    let along = if form == Form::Twist { z } else { x };
    let a = b.mul(v[0], along)?;
    let (s, c) = (b.f1(Func1::Sin, a)?, b.f1(Func1::Cos, a)?);
    let (cx, sy) = (b.mul(c, x)?, b.mul(s, y)?);
    let (cy, sx) = (b.mul(c, y)?, b.mul(s, x)?);
    let q = match form {
        // (c·x + s·y, c·y − s·x, z)
        Form::Twist => [b.add(cx, sy)?, b.sub(cy, sx)?, z],
        // (c·x − s·y, s·x + c·y, z)
        Form::Bend => [b.sub(cx, sy)?, b.add(sx, cy)?, z],
        _ => unreachable!("{form:?} is not a warp"),
    };
    b.0.substitute(v[1], q)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest ratio |w(p) − w(q)| / |p − q| over close random pairs
    /// within radius ρ stays below the stated factor and comes near it.
    fn worst_stretch(w: impl Fn([f64; 3]) -> [f64; 3], rho: f64) -> f64 {
        let mut seed = 0x2545f4914f6cdd1du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut worst: f64 = 0.0;
        for _ in 0..200_000 {
            let p = [rnd() * rho / 2f64.sqrt(), rnd() * rho / 2f64.sqrt(), rnd() * 2.0];
            let d = [rnd() * 1e-6, rnd() * 1e-6, rnd() * 1e-6];
            let q = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
            let (a, b) = (w(p), w(q));
            let num = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
            let den = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            worst = worst.max(num / den);
        }
        worst
    }

    #[test]
    fn the_warps_stretch_no_more_than_their_factors() {
        for k in [0.5, 2.0] {
            let t = worst_stretch(|p| twist_point(k, p), 1.0);
            assert!(t <= twist_lipschitz(k, 1.0) * (1.0 + 1e-6) && t > 0.97 * twist_lipschitz(k, 1.0), "twist {k}: {t}");
            let b = worst_stretch(|p| bend_point(k, p), 1.0);
            assert!(b <= bend_lipschitz(k, 1.0) * (1.0 + 1e-6) && b > 0.9 * bend_lipschitz(k, 1.0), "bend {k}: {b}");
        }
    }

    #[test]
    fn the_warps_keep_the_distance_from_the_z_axis_and_z() {
        for p in [[0.3, -0.7, 1.1], [2.0, 0.5, -0.4]] {
            for w in [twist_point(1.3, p), bend_point(1.3, p)] {
                assert!((w[0].hypot(w[1]) - p[0].hypot(p[1])).abs() < 1e-12);
                assert_eq!(w[2], p[2]);
            }
        }
    }
}

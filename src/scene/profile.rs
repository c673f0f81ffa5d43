//! 2D profiles, the cross-sections of extruded and revolved primitives
//! (Zanni et al. 2024, Fig. 12: "extruded and revolved 2D SDFs").
//!
//! A profile is an exact signed distance in its plane, u = (u.x, u.y). An
//! extrusion along z with half height h combines it with |z| − h; a
//! revolution around z evaluates it at (√(x² + y²) − R, z). Both maps are
//! 1-Lipschitz, so an exact profile gives an exact (extrusion) or
//! 1-Lipschitz (revolution) 3D field, and the formula language's forms
//! `extrude`, `revolve`, `circle`, `rect`, `roundrect`, `capsule2d` and
//! `polygon` (`src/sdf.rs`) compute the same functions.
//!
//! What each profile computes is its descriptor's (`crate::sdf::profile`,
//! a file a profile); this is the scene model's data, a variant a profile
//! with its two conversions to and from the descriptor's parameters.

use crate::sdf::profile::{self as types, ProfileType};
use glam::DVec2;

pub use crate::sdf::profile::MAX_POLYGON;

/// A cross-section in the profile plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// |u| − r, r > 0.
    Circle {
        /// r.
        radius: f64,
    },
    /// The rectangle of half extents `half` > 0, centred.
    Rect {
        /// Half extents.
        half: [f64; 2],
    },
    /// The same rectangle with corners rounded by r, 0 ≤ r ≤ min(half).
    RoundRect {
        /// Half extents including the rounding.
        half: [f64; 2],
        /// Corner radius.
        radius: f64,
    },
    /// The segment a–b thickened by r > 0.
    Capsule {
        /// One end.
        a: [f64; 2],
        /// The other end.
        b: [f64; 2],
        /// r.
        radius: f64,
    },
    /// A closed polygon of 3 to `MAX_POLYGON` vertices; the sign is the
    /// even-odd rule, so the inside of a simple polygon is negative.
    Polygon {
        /// Vertices used.
        count: u8,
        /// The vertices, `count` of them, then zeros.
        points: [[f64; 2]; MAX_POLYGON],
    },
}

/// A profile's parameters, in its descriptor's order (module doc of
/// `crate::sdf::profile`), without an allocation.
pub struct Params {
    len: usize,
    v: [f64; 2 * MAX_POLYGON],
}

impl Params {
    fn new(given: &[f64]) -> Params {
        let mut v = [0.0; 2 * MAX_POLYGON];
        v[..given.len()].copy_from_slice(given);
        Params { len: given.len(), v }
    }
}

impl std::ops::Deref for Params {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.v[..self.len]
    }
}

impl Profile {
    /// Its descriptor.
    pub fn kind(&self) -> &'static ProfileType {
        match self {
            Profile::Circle { .. } => &types::CIRCLE,
            Profile::Rect { .. } => &types::RECT,
            Profile::RoundRect { .. } => &types::ROUND_RECT,
            Profile::Capsule { .. } => &types::CAPSULE,
            Profile::Polygon { .. } => &types::POLYGON,
        }
    }

    /// Its descriptor and parameters.
    pub fn typed(&self) -> (&'static ProfileType, Params) {
        let p = match *self {
            Profile::Circle { radius } => Params::new(&[radius]),
            Profile::Rect { half } => Params::new(&half),
            Profile::RoundRect { half, radius } => Params::new(&[half[0], half[1], radius]),
            Profile::Capsule { a, b, radius } => Params::new(&[a[0], a[1], b[0], b[1], radius]),
            Profile::Polygon { .. } => Params::new(self.vertices().as_flattened()),
        };
        (self.kind(), p)
    }

    /// The profile of type `t` with the parameters `v` (as many as it takes).
    pub fn from_params(t: &ProfileType, v: &[f64]) -> Profile {
        match t.scene_name {
            "circle" => Profile::Circle { radius: v[0] },
            "rect" => Profile::Rect { half: [v[0], v[1]] },
            "round_rect" => Profile::RoundRect { half: [v[0], v[1]], radius: v[2] },
            "capsule" => Profile::Capsule { a: [v[0], v[1]], b: [v[2], v[3]], radius: v[4] },
            "polygon" => Profile::polygon(&v.chunks(2).map(|c| [c[0], c[1]]).collect::<Vec<_>>()),
            other => unreachable!("profile {other} has no variant"),
        }
    }

    /// The profile's `type` in a scene file.
    pub fn name(&self) -> &'static str {
        self.kind().scene_name
    }

    /// Every profile type name (those of `crate::sdf::profile::TYPES`, as
    /// a test checks).
    pub const NAMES: [&'static str; 5] = ["circle", "rect", "round_rect", "capsule", "polygon"];

    /// A polygon of the given vertices (at most `MAX_POLYGON`; checked by
    /// [`Profile::check`], which also wants at least 3).
    pub fn polygon(vertices: &[[f64; 2]]) -> Profile {
        let mut points = [[0.0; 2]; MAX_POLYGON];
        let count = vertices.len().min(MAX_POLYGON);
        points[..count].copy_from_slice(&vertices[..count]);
        Profile::Polygon { count: vertices.len().min(255) as u8, points }
    }

    /// The polygon's vertices (empty for other profiles).
    pub fn vertices(&self) -> &[[f64; 2]] {
        match self {
            Profile::Polygon { count, points } => &points[..(*count as usize).min(MAX_POLYGON)],
            _ => &[],
        }
    }

    /// The profile reflected across its u.y axis (u.x ↦ −u.x).
    pub fn mirror_x(&self) -> Profile {
        let (t, v) = self.typed();
        Profile::from_params(t, &t.mirror_x(&v))
    }

    /// The signed distance at `u`.
    pub fn distance(&self, u: DVec2) -> f64 {
        let (t, v) = self.typed();
        (t.distance)(&v, u)
    }

    /// The bounding rectangle (min, max) of the region {distance ≤ 0}.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let (t, v) = self.typed();
        (t.bounds)(&v)
    }

    /// Every number with its field name under `profile.` (`profile.half[1]`).
    pub fn fields(&self) -> Vec<(String, f64)> {
        let (t, v) = self.typed();
        t.param_names(&v).into_iter().zip(v.iter()).map(|(n, &x)| (format!("profile.{n}"), x)).collect()
    }

    /// Checks the parameters; the error names the field under `profile.`.
    pub fn check(&self) -> Result<(), (String, String)> {
        for (name, v) in self.fields() {
            if !v.is_finite() {
                return Err((name, "must be finite".into()));
            }
        }
        let prefixed = |(name, why): (String, String)| (format!("profile.{name}"), why);
        if let Profile::Polygon { count, .. } = *self {
            // A polygon built with more vertices than it keeps.
            if count as usize > MAX_POLYGON {
                return Err(prefixed(("points".into(), format!("a polygon has 3 to {MAX_POLYGON} vertices, found {count}"))));
            }
        }
        let (t, v) = self.typed();
        (t.check)(&v).map_err(prefixed)
    }
}

/// The extrusion of a profile value `d2` along z with half height `h` at
/// local height `z`: exact when d2 is.
pub fn extrude(d2: f64, z: f64, h: f64) -> f64 {
    let wz = z.abs() - h;
    let (ox, oz) = (d2.max(0.0), wz.max(0.0));
    d2.max(wz).min(0.0) + (ox * ox + oz * oz).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polygon_square_is_the_rectangle() {
        let sq = Profile::polygon(&[[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]);
        let rect = Profile::Rect { half: [0.5, 0.5] };
        let mut rng = crate::scene::generate::Rng::new(4);
        for _ in 0..2000 {
            let u = DVec2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            assert!((sq.distance(u) - rect.distance(u)).abs() < 1e-12, "{u}");
        }
    }

    #[test]
    fn polygon_checks_name_the_field() {
        let e = |v: &[[f64; 2]]| Profile::polygon(v).check().unwrap_err();
        assert_eq!(e(&[[0.0, 0.0], [1.0, 0.0]]), ("profile.points".into(), "a polygon has 3 to 16 vertices, found 2".into()));
        assert_eq!(e(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]]).0, "profile.points[2]");
        assert_eq!(e(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]).1, "the polygon has no area");
    }
}

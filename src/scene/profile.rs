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
//! On the GPU every profile but the polygon is one branch-free formula,
//! box₂(u − a − (b − a)·h, e) − r with h the clamped projection of u − a
//! on the segment a–b: a circle is e = 0, a rectangle r = 0, a capsule
//! e = 0 with its segment; the polygon loops over its vertices
//! (`scene_profile` in templates/fields/scene.wgsl).

use glam::DVec2;

/// The most vertices of a polygon profile: a GPU record holds two a row,
/// so 16 vertices are 8 rows.
pub const MAX_POLYGON: usize = 16;

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

impl Profile {
    /// The profile's `type` in a scene file.
    pub fn name(&self) -> &'static str {
        match self {
            Profile::Circle { .. } => "circle",
            Profile::Rect { .. } => "rect",
            Profile::RoundRect { .. } => "round_rect",
            Profile::Capsule { .. } => "capsule",
            Profile::Polygon { .. } => "polygon",
        }
    }

    /// Every profile type name.
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
        let flip = |v: [f64; 2]| [-v[0], v[1]];
        match *self {
            Profile::Capsule { a, b, radius } => Profile::Capsule { a: flip(a), b: flip(b), radius },
            Profile::Polygon { .. } => Profile::polygon(&self.vertices().iter().map(|&v| flip(v)).collect::<Vec<_>>()),
            p => p,
        }
    }

    /// The signed distance at `u`.
    pub fn distance(&self, u: DVec2) -> f64 {
        match *self {
            Profile::Circle { radius } => u.length() - radius,
            Profile::Rect { half } => box2(u, DVec2::from(half)),
            Profile::RoundRect { half, radius } => box2(u, DVec2::from(half) - DVec2::splat(radius)) - radius,
            Profile::Capsule { a, b, radius } => segment(u, DVec2::from(a), DVec2::from(b)) - radius,
            Profile::Polygon { .. } => polygon(u, self.vertices()),
        }
    }

    /// The bounding rectangle (min, max) of the region {distance ≤ 0}.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        match *self {
            Profile::Circle { radius } => ([-radius; 2], [radius; 2]),
            Profile::Rect { half } | Profile::RoundRect { half, .. } => ([-half[0], -half[1]], half),
            Profile::Capsule { a, b, radius } => ([a[0].min(b[0]) - radius, a[1].min(b[1]) - radius], [a[0].max(b[0]) + radius, a[1].max(b[1]) + radius]),
            Profile::Polygon { .. } => {
                let v = self.vertices();
                let lo = v.iter().fold([f64::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
                let hi = v.iter().fold([f64::NEG_INFINITY; 2], |m, p| [m[0].max(p[0]), m[1].max(p[1])]);
                (lo, hi)
            }
        }
    }

    /// Every number with its field name under `profile.` (`profile.half[1]`).
    pub fn fields(&self) -> Vec<(String, f64)> {
        let one = |n: &str, v: f64| vec![(format!("profile.{n}"), v)];
        let two = |n: &str, v: [f64; 2]| (0..2).map(|k| (format!("profile.{n}[{k}]"), v[k])).collect::<Vec<_>>();
        match *self {
            Profile::Circle { radius } => one("radius", radius),
            Profile::Rect { half } => two("half", half),
            Profile::RoundRect { half, radius } => [two("half", half), one("radius", radius)].concat(),
            Profile::Capsule { a, b, radius } => [two("a", a), two("b", b), one("radius", radius)].concat(),
            Profile::Polygon { .. } => {
                self.vertices().iter().enumerate().flat_map(|(i, p)| (0..2).map(move |k| (format!("profile.points[{i}][{k}]"), p[k]))).collect()
            }
        }
    }

    /// Checks the parameters; the error names the field under `profile.`.
    pub fn check(&self) -> Result<(), (String, String)> {
        for (name, v) in self.fields() {
            if !v.is_finite() {
                return Err((name, "must be finite".into()));
            }
        }
        let positive = |name: &str, v: f64| if v > 0.0 { Ok(()) } else { Err((format!("profile.{name}"), "must be > 0".to_string())) };
        match *self {
            Profile::Circle { radius } => positive("radius", radius),
            Profile::Rect { half } => positive("half[0]", half[0]).and(positive("half[1]", half[1])),
            Profile::RoundRect { half, radius } => {
                positive("half[0]", half[0])?;
                positive("half[1]", half[1])?;
                let smallest = half[0].min(half[1]);
                if !(radius >= 0.0 && radius <= smallest) {
                    return Err(("profile.radius".into(), format!("must be >= 0 and <= the smallest half extent ({smallest})")));
                }
                Ok(())
            }
            Profile::Capsule { radius, .. } => positive("radius", radius),
            Profile::Polygon { count, .. } => check_polygon(count as usize, self.vertices()),
        }
    }
}

fn check_polygon(count: usize, v: &[[f64; 2]]) -> Result<(), (String, String)> {
    if !(3..=MAX_POLYGON).contains(&count) {
        return Err(("profile.points".into(), format!("a polygon has 3 to {MAX_POLYGON} vertices, found {count}")));
    }
    for i in 0..count {
        let j = (i + count - 1) % count;
        if v[i] == v[j] {
            return Err((format!("profile.points[{i}]"), format!("repeats points[{j}]: an edge needs two distinct ends")));
        }
    }
    let area: f64 = (0..count).map(|i| {
        let (p, q) = (v[i], v[(i + 1) % count]);
        p[0] * q[1] - q[0] * p[1]
    }).sum();
    if area == 0.0 {
        return Err(("profile.points".into(), "the polygon has no area".into()));
    }
    Ok(())
}

/// The exact 2D box distance, half extents `h`.
pub fn box2(u: DVec2, h: DVec2) -> f64 {
    let q = u.abs() - h;
    let qp = q.max(DVec2::ZERO);
    (qp.x * qp.x + qp.y * qp.y).sqrt() + q.x.max(q.y).min(0.0)
}

/// Distance from `u` to the segment a–b (to a when a = b).
pub fn segment(u: DVec2, a: DVec2, b: DVec2) -> f64 {
    let (pa, ba) = (u - a, b - a);
    let bb = ba.dot(ba);
    let h = if bb > 0.0 { (pa.dot(ba) / bb).clamp(0.0, 1.0) } else { 0.0 };
    (pa - ba * h).length()
}

/// Signed distance to a closed polygon, even-odd sign (after Quilez's
/// sdPolygon): the smallest distance to an edge, negated where a ray
/// towards +x crosses the edges an odd number of times.
pub fn polygon(u: DVec2, v: &[[f64; 2]]) -> f64 {
    let n = v.len();
    let v0 = DVec2::from(v[0]);
    let mut d = (u - v0).dot(u - v0);
    let mut s = 1.0;
    for i in 0..n {
        let (vi, vj) = (DVec2::from(v[i]), DVec2::from(v[(i + n - 1) % n]));
        let (e, w) = (vj - vi, u - vi);
        let b = w - e * (w.dot(e) / e.dot(e)).clamp(0.0, 1.0);
        d = d.min(b.dot(b));
        let c = [u.y >= vi.y, u.y < vj.y, e.x * w.y > e.y * w.x];
        if c.iter().all(|&x| x) || c.iter().all(|&x| !x) {
            s = -s;
        }
    }
    s * d.sqrt()
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

//! Twisted and bent primitives: a domain warp ([`crate::sdf`]'s
//! `twist_point` and `bend_point`) in a frame of its own.
//!
//! A warp is kept on each primitive below it (a formula's `twist(k, s)` or
//! a file's `twist` node puts it on every primitive of s), so the
//! interpreter stays a post-order stack machine: a warped primitive's value
//! is s_A · d(w(A⁻¹p)), with A the warp's frame (where its axis is: its
//! local z) and d the primitive as it would be without the warp, in that
//! frame.
//!
//! **Bounded.** Both warps keep the distance ρ from the frame's z axis and
//! z, so the warped primitive's region {f ≤ r} lies in the cylinder of the
//! unwarped one's: its ABV is that cylinder's box.
//!
//! **Lipschitz.** Within radius ρ the warp stretches by at most
//! σ(kρ) (twist (a + √(a² + 4))/2, bend 1 + a, a = |k|ρ), which grows
//! without bound away from the axis, where a sphere tracer could step
//! through the shape. So a primitive in a scene carries a [`Clamp`]: beyond
//! the radius ρ_c of the cylinder that holds its {f ≤ h} (h its range of
//! interest's top), its value f is replaced by min(f, max(f·σ(kρ_c)/σ(kρ), h)):
//! equal inside the cylinder, of the same sign outside, ≥ h there (so the
//! ABV contract holds), and a step f/L with L = σ(kρ_c) never reaches the
//! surface, because any path from a point outside to it crosses the
//! cylinder, where f ≥ h, and within it f falls no faster than L. The scene
//! is traced with σ(kρ_c) ([`super::roi::field_lipschitz`]).

use super::primitive::{Primitive, Transform};
use super::roi::{self, Abv};
use glam::DVec3;

/// Which warp.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WarpKind {
    /// (x, y) turned by −k·z: the shape turns by k·z at height z.
    Twist = 1,
    /// (x, y) turned by k·x: a bar along x curls in the xy plane.
    Bend = 2,
}

impl WarpKind {
    /// The scene file's and the formula's name.
    pub fn name(self) -> &'static str {
        match self {
            WarpKind::Twist => "twist",
            WarpKind::Bend => "bend",
        }
    }

    /// The kind called `name`.
    pub fn parse(name: &str) -> Option<WarpKind> {
        [WarpKind::Twist, WarpKind::Bend].into_iter().find(|k| k.name() == name)
    }
}

/// Where the warped field is exact, and what it is clamped to beyond (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clamp {
    /// ρ_c: the radius (in the warp's frame) of the cylinder holding {f ≤ floor}.
    pub radius: f64,
    /// h ≥ 0: the primitive's range of interest's top.
    pub floor: f64,
    /// The cylinder's z range in the warp's frame.
    pub z: [f64; 2],
}

/// A warp over one primitive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Warp {
    /// Twist or bend.
    pub kind: WarpKind,
    /// k, radians per unit of the frame's length.
    pub rate: f64,
    /// A: world from the warp's frame.
    pub frame: Transform,
    /// Set when the primitive is part of a scene ([`fit`]).
    pub clamp: Option<Clamp>,
}

impl Warp {
    /// The warped point of frame point `q`.
    pub fn point(&self, q: DVec3) -> DVec3 {
        let w = match self.kind {
            WarpKind::Twist => crate::sdf::twist_point(self.rate, q.to_array()),
            WarpKind::Bend => crate::sdf::bend_point(self.rate, q.to_array()),
        };
        DVec3::from(w)
    }

    /// σ(kρ): how much the warp stretches within radius ρ of its axis.
    pub fn stretch(&self, rho: f64) -> f64 {
        match self.kind {
            WarpKind::Twist => crate::sdf::twist_lipschitz(self.rate, rho),
            WarpKind::Bend => crate::sdf::bend_lipschitz(self.rate, rho),
        }
    }

    /// The warped field at world point `p`, `unwarped` the primitive's field
    /// in the warp's frame.
    pub fn distance(&self, p: DVec3, unwarped: impl Fn(DVec3) -> f64) -> f64 {
        let q = self.frame.to_local(p);
        let f = self.frame.scale * unwarped(self.point(q));
        match self.clamp {
            None => f,
            Some(c) => {
                let rho = (q.x * q.x + q.y * q.y).sqrt();
                if rho <= c.radius {
                    f
                } else {
                    f.min((f * (self.stretch(c.radius) / self.stretch(rho))).max(c.floor))
                }
            }
        }
    }

    /// Checks the rate and the frame; the error names the field.
    pub fn check(&self) -> Result<(), (String, String)> {
        if !self.rate.is_finite() {
            return Err(("warp.rate".into(), "must be finite".into()));
        }
        self.frame.check().map_err(|(f, r)| (format!("warp.{f}"), r))
    }

    /// The Lipschitz factor the scene is traced with for this warp (1
    /// before [`fit`]).
    pub fn lipschitz(&self) -> f64 {
        self.clamp.map_or(1.0, |c| self.stretch(c.radius))
    }
}

/// The cylinder (radius, z range) in the warp's frame holding {f ≤ level}
/// of warped primitive `p` (whose own transform places it in that frame).
fn cylinder(p: &Primitive, w: &Warp, level: f64) -> (f64, [f64; 2]) {
    let inner = Primitive { shape: p.shape.clone(), transform: p.transform, warp: None };
    let b = roi::abv(&inner, level.max(0.0) / w.frame.scale).aabb();
    let far = |lo: f64, hi: f64| lo.abs().max(hi.abs());
    let radius = far(b.min[0], b.max[0]).hypot(far(b.min[1], b.max[1]));
    (radius, [b.min[2], b.max[2]])
}

/// `p`'s warp clamped for a range of interest reaching `level`.
pub fn fit(p: &Primitive, level: f64) -> Option<Warp> {
    let w = p.warp?;
    let floor = level.max(0.0);
    let (radius, z) = cylinder(p, &w, floor);
    Some(Warp { clamp: Some(Clamp { radius, floor, z }), ..w })
}

/// The ABV of warped primitive `p` at `r_plus`: the box of its cylinder.
pub fn abv(p: &Primitive, w: &Warp, r_plus: f64) -> Abv {
    let (radius, z) = cylinder(p, w, r_plus);
    let a = &w.frame;
    let s = a.scale;
    Abv::Box {
        centre: a.to_world(DVec3::new(0.0, 0.0, 0.5 * (z[0] + z[1]))).to_array(),
        axes: [DVec3::X, DVec3::Y, DVec3::Z].map(|e| a.world_direction(e).to_array()),
        half: [s * radius, s * radius, s * 0.5 * (z[1] - z[0])],
    }
}

/// The inverse of a similarity transform: world → its frame, as a transform.
pub fn inverse(t: &Transform) -> Transform {
    let rotate = t.rotate.map(|r| super::Rotation { axis: r.axis, angle: -r.angle });
    let inv = Transform { translate: [0.0; 3], rotate, scale: 1.0 / t.scale };
    let translate = (-inv.to_world(DVec3::from(t.translate))).to_array();
    Transform { translate, ..inv }
}

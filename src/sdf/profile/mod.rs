//! The 2D profiles, each described once, in a file of its own, by a
//! [`ProfileType`]: its formula form (name, arguments, expansion into IR
//! operations), its f64 reference, its parameters as a scene file names
//! them with their constraints, its bounding rectangle and its row of the
//! GPU layout; and the forms that make solids of them (`extrude`,
//! `revolve`).
//!
//! A profile is a field of x and y alone. As a 3D field it is the exact
//! distance to an infinite prism along z (a profile's gradient has no z
//! part, so its length is the 2D one, 1), which is why no form of its own
//! is needed for "2D": `extrude` uses the profile's value at the same
//! point and `revolve` evaluates it at (distance from the z axis − R, z).
//! Both maps are 1-Lipschitz in p, so the solids keep the profile's bound.
//!
//! On the GPU every profile but the polygon is one branch-free formula,
//! box₂(u − a − (b − a)·h, e) − r with h the clamped projection of u − a
//! on the segment a–b (its [`SegmentBox`]); a profile with a list of
//! points (the polygon) loops over them (`scene_profile` in
//! templates/fields/scene_shapes.wgsl).
//!
//! The formula language ([`super::lower`]) and blobtree scenes
//! (`crate::scene`: file format, validation, rows, bounding volumes,
//! formula text, lowering) read [`TYPES`] instead of matching on profile
//! types. Adding a profile is a file here, its line in [`TYPES`], and its
//! variant of `scene::Profile` (the scene model's data, with its two
//! conversions to and from numbers).
//!
//! Every number a type takes is a parameter, in one order: the formula's
//! arguments, the scene file's fields (a pair counts as two, a list of
//! points as two a point) and the functions of the descriptor use it.

use super::primitive::{Invalid, Ir, Stopped};
use super::{Form, Info, Sink, B};
use crate::ir::{Func1, NodeId, Var};
use glam::DVec2;

mod capsule;
mod circle;
mod polygon;
mod rect;
mod round_rect;

pub use capsule::CAPSULE;
pub use circle::CIRCLE;
pub use polygon::{MAX_POLYGON, POLYGON};
pub use rect::RECT;
pub use round_rect::ROUND_RECT;

/// Every profile type, in documentation order.
pub static TYPES: [&ProfileType; 5] = [&CIRCLE, &RECT, &ROUND_RECT, &CAPSULE, &POLYGON];

/// One profile type (module doc). Types are compared by scene name.
pub struct ProfileType {
    /// The formula form: name, arity, signature and its one-line definition.
    pub info: Info,
    /// The `type` of a scene file's profile object (`round_rect`; the
    /// formula says `roundrect`).
    pub scene_name: &'static str,
    /// The parameters, as the scene file names them (under `profile.`).
    pub fields: &'static [Field],
    /// Checks finite parameters; the error names the field (without `profile.`).
    pub check: fn(&[f64]) -> Result<(), Invalid>,
    /// The signed distance at u, written as the formula form expands.
    pub distance: fn(&[f64], DVec2) -> f64,
    /// The bounding rectangle (min, max) of the region {distance ≤ 0}.
    pub bounds: fn(&[f64]) -> ([f64; 2], [f64; 2]),
    /// Its numbers for the interpreter's shared formula (zeros for a
    /// profile of points, whose points have rows of their own).
    pub row: fn(&[f64]) -> SegmentBox,
    /// The formula form's expansion of the lowered arguments `v`.
    pub(in crate::sdf) expand: fn(&mut Ir<'_, '_>, &[NodeId]) -> Result<NodeId, Stopped>,
}

/// box₂(u − a − (b − a)·h, e) − r: the GPU's one formula for the profiles
/// that are not lists of points.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SegmentBox {
    /// Half extents of the box.
    pub e: [f64; 2],
    /// Rounding.
    pub r: f64,
    /// One end of the segment.
    pub a: [f64; 2],
    /// The other end.
    pub b: [f64; 2],
}

/// A parameter field of a scene file's profile object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Field {
    /// The JSON key.
    pub name: &'static str,
    /// What it holds.
    pub kind: FieldKind,
}

/// What a profile field holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldKind {
    /// A number.
    Number,
    /// `[x, y]`; `mirrored`: a point, whose x mirroring the profile negates
    /// (extents are kept).
    Pair {
        /// Whether it is a point.
        mirrored: bool,
    },
    /// `[[x, y], …]`: 3 to [`MAX_POLYGON`] points, the rest of the parameters.
    Points,
}

impl ProfileType {
    /// Whether it takes a list of points (which have GPU rows of their own).
    pub fn has_points(&self) -> bool {
        self.fields.iter().any(|f| f.kind == FieldKind::Points)
    }

    /// The parameters' names, a pair as `half[0]`, `half[1]`, a list of
    /// points as `points[i][k]`, for the parameters `v`.
    pub fn param_names(&self, v: &[f64]) -> Vec<String> {
        let mut out = Vec::with_capacity(v.len());
        for f in self.fields {
            match f.kind {
                FieldKind::Number => out.push(f.name.to_string()),
                FieldKind::Pair { .. } => out.extend((0..2).map(|k| format!("{}[{k}]", f.name))),
                FieldKind::Points => {
                    let n = (v.len() - out.len()) / 2;
                    out.extend((0..n).flat_map(|i| (0..2).map(move |k| format!("{}[{i}][{k}]", f.name))));
                }
            }
        }
        out
    }

    /// The parameters of the profile reflected across its u.y axis
    /// (u.x ↦ −u.x): the x of every point negated.
    pub fn mirror_x(&self, v: &[f64]) -> Vec<f64> {
        let mut out = v.to_vec();
        let mut at = 0;
        for f in self.fields {
            match f.kind {
                FieldKind::Number => at += 1,
                FieldKind::Pair { mirrored } => {
                    if mirrored {
                        out[at] = -out[at];
                    }
                    at += 2;
                }
                FieldKind::Points => {
                    for k in (at..out.len()).step_by(2) {
                        out[k] = -out[k];
                    }
                    at = out.len();
                }
            }
        }
        out
    }
}

impl PartialEq for ProfileType {
    fn eq(&self, o: &ProfileType) -> bool {
        self.scene_name == o.scene_name
    }
}

impl Eq for ProfileType {}

impl std::hash::Hash for ProfileType {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.scene_name.hash(h)
    }
}

impl std::fmt::Debug for ProfileType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.scene_name)
    }
}

/// `name` must be > 0.
fn positive(name: &str, v: f64) -> Result<(), Invalid> {
    if v > 0.0 { Ok(()) } else { Err((name.to_string(), "must be > 0".to_string())) }
}

/// The point (x, y) of the profile plane.
fn plane_point(b: &mut Ir<'_, '_>) -> Result<[NodeId; 2], Stopped> {
    Ok([b.var(Var::X)?, b.var(Var::Y)?])
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

/// Expands `extrude` or `revolve` (`v`: the lowered arguments).
pub(super) fn lower_solid<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    match form {
        // With w = (shape, |z| − h): min(max(w.x, w.y), 0) + length(max(w, 0)),
        // the capped cylinder's formula with the profile in place of
        // |(x, y)| − r. Exact when the shape is an exact 2D distance.
        Form::Extrude => {
            b.positive(v, 0, "the half height h")?;
            let z = b.var(Var::Z)?;
            let az = b.f1(Func1::Abs, z)?;
            let dz = b.sub(az, v[0])?;
            b.capped(v[1], dz)
        }
        // The shape at x' = sqrt(x² + y²) − R, y' = z, z' = 0: the profile
        // drawn in a half plane through the axis, at distance R from it.
        // Exact for an exact 2D distance whose shape stays in x' ≥ −R (does
        // not cross the axis); a shape that crosses it is a bound.
        Form::Revolve => {
            b.non_negative(v, 0, "the distance R from the axis")?;
            let [x, y, z] = b.xyz()?;
            let radial = b.length(&[x, y])?;
            let u = b.sub(radial, v[0])?;
            let zero = b.c(0.0)?;
            b.0.substitute(v[1], [u, z, zero])
        }
        _ => unreachable!("{form:?} is not a solid of a profile"),
    }
}

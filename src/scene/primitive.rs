//! Primitives: the distance forms of [`crate::sdf`], each under a rigid
//! transform with uniform scale.
//!
//! A shape given by numbers is one of the primitive types of
//! [`crate::sdf::primitive`], which describe everything about it (its
//! field, constraints, bounds, rows and formula form); [`Shape`] holds its
//! numbers by name, and [`Shape::analytic`] and [`Shape::from_analytic`]
//! convert them to the type's parameters and back. Profiles and voxel
//! grids, which hold more than numbers, are described here and in
//! [`super::profile`] and [`super::grid`].
//!
//! Every local distance is the same function, written the same way, as the
//! formula language's form of the same name, so a scene and the formula
//! `translate(t, rotate(axis, angle, scale(s, form)))` give the same field
//! up to rounding (src/tests/scene_model.rs checks it at random points with
//! `reference::eval_scalar`).
//!
//! **Transform.** A primitive's field is d(p) = s · f_local(Rᵀ(p − t) / s):
//! translate by t, rotate by R, scale by s > 0, applied to the shape in that
//! order (scale first). R is given as an axis and an angle in radians,
//! right-handed, as `rotate(ax, ay, az, angle, shape)` takes them; an axis
//! and angle rather than a quaternion because that is what a formula says,
//! so a scene and its formula can be compared without a conversion. The
//! transform is an isometry times s, so an exact distance stays exact and a
//! 1-Lipschitz bound stays 1-Lipschitz.

use super::grid::{Grid, Placement};
use super::leaf::FormulaLeaf;
use super::profile::{self, Profile};
use crate::sdf::primitive::{self as types, Params, PrimitiveType};
use glam::{DVec2, DVec3};
use std::sync::Arc;

/// The shape of a primitive, in its local frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// `sphere(r)`: |p| − r.
    Sphere {
        /// r > 0.
        radius: f64,
    },
    /// `box(bx, by, bz)`: axis-aligned, half extents b > 0.
    Box {
        /// Half extents.
        half: [f64; 3],
    },
    /// `roundbox(bx, by, bz, r)`: box(b − r) − r, the same extents with
    /// edges rounded by r, 0 ≤ r ≤ min(b).
    RoundBox {
        /// Half extents including the rounding.
        half: [f64; 3],
        /// Rounding radius.
        radius: f64,
    },
    /// `capsule(a, b, r)`: the segment a–b thickened by r > 0.
    Capsule {
        /// One end.
        a: [f64; 3],
        /// The other end.
        b: [f64; 3],
        /// r > 0.
        radius: f64,
    },
    /// `torus(R, r)`: the ring of major radius R around the local z axis,
    /// minor radius r.
    Torus {
        /// R > 0.
        major: f64,
        /// r > 0.
        minor: f64,
    },
    /// `cylinder(r, h)`: capped, along the local z axis.
    Cylinder {
        /// r > 0.
        radius: f64,
        /// Half height h > 0.
        half_height: f64,
    },
    /// `octahedron(s)`: the bound (|x| + |y| + |z| − s)/√3 (exact on the faces).
    Octahedron {
        /// s > 0.
        size: f64,
    },
    /// `plane(n, d)`: the half-space n·p ≤ d, n normalised when evaluated.
    /// Unbounded: it has no bounding volume and is always active.
    Plane {
        /// Outward normal, not zero.
        normal: [f64; 3],
        /// Offset along the unit normal.
        offset: f64,
    },
    /// A 2D profile in the local xy plane extruded along z: exact for the
    /// exact profiles of [`Profile`] (`extrude(h, profile)`).
    Extrude {
        /// The cross-section.
        profile: Profile,
        /// Half height h > 0.
        half_height: f64,
    },
    /// A 2D profile revolved around the local z axis: the profile's u.x is
    /// the distance from the axis minus `offset`, u.y is z
    /// (`revolve(R, profile)`).
    Revolve {
        /// The cross-section.
        profile: Profile,
        /// R ≥ 0: where the profile's origin sits from the axis.
        offset: f64,
    },
    /// A voxel grid of signed distances from a file, trilinearly
    /// interpolated (`super::grid`), in the local frame.
    Grid(GridRef),
    /// A normalized density field (`crate::sdf::density`): the kernel
    /// (1 − (d/R)²)³ of the distance d to a segment along the local z axis,
    /// at isovalue c, in length units T·(1 − K/c) + max(d − R, 0). Summed
    /// with others of the same T by the `sum_union` operator.
    Density {
        /// R > 0: the support radius.
        radius: f64,
        /// h ≥ 0: the skeleton segment's half length (0: a point).
        half_length: f64,
        /// 0 < c < 1: the isovalue.
        iso: f64,
        /// T > 0: the value at the support's edge (the sum's range).
        range: f64,
    },
    /// A formula of the language within a box of the local frame
    /// (`super::leaf`): max(f/L, box distance).
    Formula(Arc<FormulaLeaf>),
    /// `cone(r, h, rt)`: the capped cone along the local z axis, radius r
    /// at z = −h and rt at z = h.
    Cone {
        /// r > 0: the radius at the base, z = −h.
        radius: f64,
        /// h > 0.
        half_height: f64,
        /// rt ≥ 0: the radius at the top, z = h (0: pointed).
        top_radius: f64,
    },
    /// `maxbox(bx, by, bz)`: max(|x| − bx, |y| − by, |z| − bz), half
    /// extents b > 0.
    MaxBox {
        /// Half extents.
        half: [f64; 3],
    },
}

impl Shape {
    /// The primitive type of a shape given by numbers, with its parameters;
    /// `None` for profiles and voxel grids.
    pub fn analytic(&self) -> Option<(&'static PrimitiveType, Params)> {
        let of = |t: &'static PrimitiveType, v: &[f64]| Some((t, Params::new(v)));
        match *self {
            Shape::Sphere { radius } => of(&types::SPHERE, &[radius]),
            Shape::Box { half } => of(&types::BOX, &half),
            Shape::RoundBox { half: [x, y, z], radius } => of(&types::ROUND_BOX, &[x, y, z, radius]),
            Shape::Capsule { a: [ax, ay, az], b: [bx, by, bz], radius } => of(&types::CAPSULE, &[ax, ay, az, bx, by, bz, radius]),
            Shape::Torus { major, minor } => of(&types::TORUS, &[major, minor]),
            Shape::Cylinder { radius, half_height } => of(&types::CYLINDER, &[radius, half_height]),
            Shape::Octahedron { size } => of(&types::OCTAHEDRON, &[size]),
            Shape::Plane { normal: [x, y, z], offset } => of(&types::PLANE, &[x, y, z, offset]),
            Shape::Density { radius, half_length, iso, range } => of(&types::DENSITY, &[radius, half_length, iso, range]),
            Shape::Cone { radius, half_height, top_radius } => of(&types::CONE, &[radius, half_height, top_radius]),
            Shape::MaxBox { half } => of(&types::MAX_BOX, &half),
            Shape::Extrude { .. } | Shape::Revolve { .. } | Shape::Grid(_) | Shape::Formula(_) => None,
        }
    }

    /// The shape of primitive type `t` with parameters `v` (all of them, in
    /// its parameter order).
    pub fn from_analytic(t: &PrimitiveType, v: &[f64]) -> Shape {
        let v3 = |k: usize| [v[k], v[k + 1], v[k + 2]];
        match t.scene_name {
            "sphere" => Shape::Sphere { radius: v[0] },
            "box" => Shape::Box { half: v3(0) },
            "round_box" => Shape::RoundBox { half: v3(0), radius: v[3] },
            "capsule" => Shape::Capsule { a: v3(0), b: v3(3), radius: v[6] },
            "torus" => Shape::Torus { major: v[0], minor: v[1] },
            "cylinder" => Shape::Cylinder { radius: v[0], half_height: v[1] },
            "octahedron" => Shape::Octahedron { size: v[0] },
            "plane" => Shape::Plane { normal: v3(0), offset: v[3] },
            "density" => Shape::Density { radius: v[0], half_length: v[1], iso: v[2], range: v[3] },
            "cone" => Shape::Cone { radius: v[0], half_height: v[1], top_radius: v[2] },
            "max_box" => Shape::MaxBox { half: v3(0) },
            other => unreachable!("every primitive type has a variant of Shape; {other} has none"),
        }
    }
}

/// A loaded voxel grid and where it came from (a scene file names the
/// file; several nodes naming the same file share one grid).
#[derive(Clone)]
pub struct GridRef {
    /// The file as the scene names it (relative to the scene file).
    pub file: String,
    /// Origin and spacing for a `.npy` (a `.vdb` has its own).
    pub placement: Option<Placement>,
    /// The samples.
    pub grid: Arc<Grid>,
}

impl PartialEq for GridRef {
    fn eq(&self, o: &GridRef) -> bool {
        self.file == o.file && self.placement == o.placement && (Arc::ptr_eq(&self.grid, &o.grid) || self.grid == o.grid)
    }
}

impl std::fmt::Debug for GridRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "GridRef {{ file: {:?}, dims: {:?} }}", self.file, self.grid.dims())
    }
}

/// The primitive types, with the type codes of the linear form
/// ([`crate::scene::linear`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShapeKind {
    /// A type given by numbers (`sphere`, `torus`, …).
    Analytic(&'static PrimitiveType),
    /// `extrude`
    Extrude,
    /// `revolve`
    Revolve,
    /// `grid`
    Grid,
    /// `formula`
    Formula,
}

impl ShapeKind {
    /// Every kind, in type-code order.
    pub fn all() -> Vec<ShapeKind> {
        let mut all: Vec<ShapeKind> = types::TYPES.iter().map(|&t| ShapeKind::Analytic(t)).chain([ShapeKind::Extrude, ShapeKind::Revolve, ShapeKind::Grid, ShapeKind::Formula]).collect();
        all.sort_by_key(|k| k.code());
        all
    }

    /// The type code of a node word.
    pub fn code(self) -> u32 {
        match self {
            ShapeKind::Analytic(t) => t.code,
            ShapeKind::Extrude => super::codes::EXTRUDE,
            ShapeKind::Revolve => super::codes::REVOLVE,
            ShapeKind::Grid => super::codes::GRID,
            ShapeKind::Formula => super::codes::FORMULA,
        }
    }

    /// The `type` of a scene file node.
    pub fn name(self) -> &'static str {
        match self {
            ShapeKind::Analytic(t) => t.scene_name,
            ShapeKind::Extrude => "extrude",
            ShapeKind::Revolve => "revolve",
            ShapeKind::Grid => "grid",
            ShapeKind::Formula => "formula",
        }
    }

    /// The kind named `name` in a scene file.
    pub fn parse(name: &str) -> Option<ShapeKind> {
        Self::all().into_iter().find(|k| k.name() == name)
    }
}

impl Shape {
    /// Its kind.
    pub fn kind(&self) -> ShapeKind {
        match self {
            Shape::Extrude { .. } => ShapeKind::Extrude,
            Shape::Revolve { .. } => ShapeKind::Revolve,
            Shape::Grid(_) => ShapeKind::Grid,
            Shape::Formula(_) => ShapeKind::Formula,
            shape => ShapeKind::Analytic(shape.analytic().expect("a shape given by numbers").0),
        }
    }

    /// The distance (or, for the octahedron and the density, the bound) at
    /// local point `q`.
    pub fn local_distance(&self, q: DVec3) -> f64 {
        match self {
            Shape::Grid(g) => g.grid.eval(q.to_array()),
            Shape::Formula(f) => f.local_value(q),
            Shape::Extrude { profile, half_height } => profile::extrude(profile.distance(DVec2::new(q.x, q.y)), q.z, *half_height),
            Shape::Revolve { profile, offset } => profile.distance(DVec2::new((q.x * q.x + q.y * q.y).sqrt() - offset, q.z)),
            shape => {
                let (t, v) = shape.analytic().expect("a shape given by numbers");
                (t.distance)(&v, q)
            }
        }
    }

    /// Checks the parameters; the error names the field (`radius`,
    /// `half[1]`) and says what is wrong.
    pub fn check(&self) -> Result<(), (String, String)> {
        for (name, v) in self.fields() {
            if !v.is_finite() {
                return Err((name, "must be finite".into()));
            }
        }
        match *self {
            // Checked when its file was read, or when it was compiled.
            Shape::Grid(_) | Shape::Formula(_) => Ok(()),
            Shape::Extrude { profile, half_height } => {
                profile.check()?;
                if half_height > 0.0 { Ok(()) } else { Err(("half_height".into(), "must be > 0".into())) }
            }
            Shape::Revolve { profile, offset } => {
                profile.check()?;
                if !(offset >= 0.0) {
                    return Err(("offset".into(), "must be >= 0".into()));
                }
                if !(profile.bounds().1[0] + offset > 0.0) {
                    return Err(("offset".into(), "the profile lies on the far side of the axis (u.x <= -offset everywhere): nothing is revolved".into()));
                }
                Ok(())
            }
            ref shape => {
                let (t, v) = shape.analytic().expect("a shape given by numbers");
                (t.check)(&v)
            }
        }
    }

    /// The shape reflected across its local yz plane (x ↦ −x), as a shape
    /// of the same type; `None` for a voxel grid, whose samples a scene file
    /// names by file. A revolution is symmetric about every plane through
    /// its axis, so it is itself.
    pub fn mirror_x(&self) -> Option<Shape> {
        Some(match *self {
            Shape::Extrude { profile, half_height } => Shape::Extrude { profile: profile.mirror_x(), half_height },
            Shape::Grid(_) | Shape::Formula(_) => return None,
            Shape::Revolve { .. } => self.clone(),
            ref shape => {
                let (t, mut v) = shape.analytic().expect("a shape given by numbers");
                let mut at = 0;
                for f in t.fields {
                    if f.mirrored {
                        v[at] = -v[at];
                    }
                    at += f.len;
                }
                Shape::from_analytic(t, &v)
            }
        })
    }

    /// Every number of the shape with its field name (`half[1]`).
    pub fn fields(&self) -> Vec<(String, f64)> {
        let one = |n: &str, v: f64| vec![(n.to_string(), v)];
        match *self {
            Shape::Extrude { profile, half_height } => [profile.fields(), one("half_height", half_height)].concat(),
            Shape::Revolve { profile, offset } => [profile.fields(), one("offset", offset)].concat(),
            Shape::Grid(_) => Vec::new(),
            Shape::Formula(ref f) => f.bounds().iter().enumerate().map(|(k, &v)| (format!("bounds[{k}]"), v)).collect(),
            ref shape => {
                let (t, v) = shape.analytic().expect("a shape given by numbers");
                t.param_names().into_iter().zip(v.iter().copied()).collect()
            }
        }
    }
}

/// A rotation: `angle` radians, right-handed, about `axis` (not zero; it is
/// normalised when used).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rotation {
    /// The axis through the origin.
    pub axis: [f64; 3],
    /// Radians.
    pub angle: f64,
}

impl Rotation {
    /// Rᵀv: v rotated by −angle (Rodrigues, written as `sdf`'s `rotate`).
    pub fn inverse_apply(&self, v: DVec3) -> DVec3 {
        let a = DVec3::from(self.axis);
        let k = a / a.length();
        let (sin, cos) = self.angle.sin_cos();
        v * cos - k.cross(v) * sin + k * (k.dot(v) * (1.0 - cos))
    }

    /// Rv: v rotated by +angle.
    pub fn apply(&self, v: DVec3) -> DVec3 {
        Rotation { axis: self.axis, angle: -self.angle }.inverse_apply(v)
    }
}

/// A rigid transform with uniform scale: p ↦ t + R(s·q).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// t.
    pub translate: [f64; 3],
    /// R; `None` is the identity.
    pub rotate: Option<Rotation>,
    /// s > 0.
    pub scale: f64,
}

impl Default for Transform {
    fn default() -> Self {
        Transform { translate: [0.0; 3], rotate: None, scale: 1.0 }
    }
}

impl Transform {
    /// The local point Rᵀ(p − t)/s of world point `p`.
    pub fn to_local(&self, p: DVec3) -> DVec3 {
        let q = p - DVec3::from(self.translate);
        let q = match &self.rotate {
            Some(r) => r.inverse_apply(q),
            None => q,
        };
        q / self.scale
    }

    /// The world point t + R(s·q) of local point `q`.
    pub fn to_world(&self, q: DVec3) -> DVec3 {
        let v = q * self.scale;
        let v = match &self.rotate {
            Some(r) => r.apply(v),
            None => v,
        };
        v + DVec3::from(self.translate)
    }

    /// The world direction R·e of a local unit direction `e`.
    pub fn world_direction(&self, e: DVec3) -> DVec3 {
        match &self.rotate {
            Some(r) => r.apply(e),
            None => e,
        }
    }

    /// The 3×4 matrix M = [Rᵀ/s | −Rᵀt/s], so that the local point is
    /// M·(p, 1); rows in order.
    pub fn matrix(&self) -> [[f64; 4]; 3] {
        let col = |e: DVec3| self.to_local(e + DVec3::from(self.translate));
        let (c0, c1, c2) = (col(DVec3::X), col(DVec3::Y), col(DVec3::Z));
        let c3 = self.to_local(DVec3::ZERO);
        [[c0.x, c1.x, c2.x, c3.x], [c0.y, c1.y, c2.y, c3.y], [c0.z, c1.z, c2.z, c3.z]]
    }

    /// Checks the transform; the error names the field.
    pub fn check(&self) -> Result<(), (String, String)> {
        for k in 0..3 {
            if !self.translate[k].is_finite() {
                return Err((format!("translate[{k}]"), "must be finite".into()));
            }
        }
        if let Some(r) = &self.rotate {
            for k in 0..4 {
                let v = if k < 3 { r.axis[k] } else { r.angle };
                if !v.is_finite() {
                    return Err((format!("rotate[{k}]"), "must be finite".into()));
                }
            }
        }
        if !self.scale.is_finite() {
            return Err(("scale".into(), "must be finite".into()));
        }
        if !(self.scale > 0.0) {
            return Err(("scale".into(), "must be > 0".into()));
        }
        if let Some(r) = &self.rotate {
            if !(DVec3::from(r.axis).length() > 0.0) {
                return Err(("rotate".into(), "the rotation axis must not be zero".into()));
            }
        }
        Ok(())
    }
}

/// A shape placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct Primitive {
    /// The local shape.
    pub shape: Shape,
    /// Where it is (in the warp's frame when it has a warp).
    pub transform: Transform,
    /// A twist or a bend over it (`super::warp`).
    pub warp: Option<super::warp::Warp>,
}

impl Primitive {
    /// A primitive with the identity transform.
    pub fn new(shape: Shape) -> Primitive {
        Primitive { shape, transform: Transform::default(), warp: None }
    }

    /// Moved by `t`.
    pub fn translated(mut self, t: [f64; 3]) -> Primitive {
        self.transform.translate = t;
        self
    }

    /// Rotated by `angle` radians about `axis`.
    pub fn rotated(mut self, axis: [f64; 3], angle: f64) -> Primitive {
        self.transform.rotate = Some(Rotation { axis, angle });
        self
    }

    /// Scaled by `s`.
    pub fn scaled(mut self, s: f64) -> Primitive {
        self.transform.scale = s;
        self
    }

    /// The field s · f_local(Rᵀ(p − t)/s) at world point `p`.
    /// Warped: s_A · that field at w(A⁻¹p), clamped far from the warp's
    /// axis (`super::warp`).
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        match &self.warp {
            None => self.unwarped(DVec3::from(p)),
            Some(w) => w.distance(DVec3::from(p), |q| self.unwarped(q)),
        }
    }

    /// The field without the warp, in the warp's frame.
    fn unwarped(&self, p: DVec3) -> f64 {
        self.transform.scale * self.shape.local_distance(self.transform.to_local(p))
    }

    /// Checks shape, transform and warp; the error names the field.
    pub fn check(&self) -> Result<(), (String, String)> {
        self.shape.check()?;
        self.transform.check()?;
        if let Some(w) = &self.warp {
            w.check()?;
            if let Some((t, _)) = self.shape.analytic().filter(|(t, v)| !t.bounded(v)) {
                return Err(("warp".into(), format!("a {} cannot be warped: it is unbounded, and a warp is bounded by its operand's cylinder", t.scene_name)));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;

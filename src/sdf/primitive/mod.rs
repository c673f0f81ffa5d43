//! The primitive types, each described once, in a file of its own, by a
//! [`PrimitiveType`]: its formula form (name, arguments, expansion into IR
//! operations), its f64 reference, its parameters as a scene file names
//! them with their constraints, its Lipschitz bound, the bounding volume of
//! its sublevel sets, its row in the GPU layout and, for a type the scene
//! interpreter's shared formula does not cover, its case of that
//! interpreter (WGSL).
//!
//! The formula language ([`super::lower`]) and blobtree scenes
//! (`crate::scene`: file format, validation, rows, bounding volumes,
//! Lipschitz bounds, formula text, lowering, the interpreter's cases) read
//! [`TYPES`] instead of matching on primitive types. Adding a primitive is
//! a file here, its line in [`TYPES`], and its variant of `scene::Shape`
//! (the scene model's data, with its two conversions to and from numbers).
//!
//! Every number a type takes is a parameter, in one order: the formula's
//! arguments, the scene file's fields (a field of three numbers counts as
//! three) and the functions of the descriptor's slices all use it.

use super::build::B;
use super::{Info, Sink};
use crate::ir::{NodeId, Op};
use glam::DVec3;
use std::cell::RefCell;

mod capsule;
mod cone;
mod cuboid;
mod cylinder;
pub mod density;
mod max_box;
mod octahedron;
mod plane;
mod round_box;
mod sphere;
mod torus;

pub use capsule::CAPSULE;
pub use cone::CONE;
pub use cuboid::BOX;
pub use cylinder::CYLINDER;
pub use density::DENSITY;
pub use max_box::MAX_BOX;
pub use octahedron::OCTAHEDRON;
pub use plane::PLANE;
pub use round_box::ROUND_BOX;
pub use sphere::SPHERE;
pub use torus::TORUS;

/// Every primitive type given by numbers, in type-code order (profiles and
/// voxel grids, which are not, are the scene's own: `scene::Shape`).
pub static TYPES: [&PrimitiveType; 11] = [&SPHERE, &BOX, &ROUND_BOX, &CAPSULE, &TORUS, &CYLINDER, &OCTAHEDRON, &PLANE, &DENSITY, &CONE, &MAX_BOX];

/// Primitive form: a rounded box in local q (sphere, box, round box,
/// capsule in its own frame): row 2 is (half extents, rounding).
pub const FORM_BOX: u32 = 0;
/// Primitive form: a rounded box in (ρ − R, 0, z), ρ = |q.xy| (torus,
/// cylinder): row 2 is (hx, R, hz, rounding).
pub const FORM_REVOLVED: u32 = 1;
/// Primitive form: the octahedron's bound (|x| + |y| + |z| − size)/√3.
pub const FORM_OCTAHEDRON: u32 = 2;
/// Primitive form: the half-space n·q − d.
pub const FORM_PLANE: u32 = 3;

/// The most parameters a type has (the capsule's seven).
pub const MAX_PARAMS: usize = 8;

/// A field's name and what is wrong with its value: `("half[1]", "must be > 0")`.
pub type Invalid = (String, String);

/// One primitive type (module doc). Types are compared by type code.
pub struct PrimitiveType {
    /// The formula form: name, arity, signature and its one-line definition.
    pub info: Info,
    /// The `type` of a scene file node (`round_box`; the formula says `roundbox`).
    pub scene_name: &'static str,
    /// The type code of a node word in the GPU layout (`scene::codes`).
    pub code: u32,
    /// The parameters, as the scene file names them.
    pub fields: &'static [Field],
    /// Checks finite parameters; the error names the field.
    pub check: fn(&[f64]) -> Result<(), Invalid>,
    /// The local field at local point q, written as the formula form
    /// expands (so the two agree to rounding).
    pub distance: fn(&[f64], DVec3) -> f64,
    /// The local field's Lipschitz bound.
    pub lipschitz: Lipschitz,
    /// Where the local field's sublevel sets lie.
    pub bound: fn(&[f64]) -> Bound,
    /// Its row in the GPU layout, after its frame; may move the frame's
    /// matrix (the local point is m·(p, 1)).
    pub rows: fn(&[f64], &mut [[f64; 4]; 3]) -> Rows,
    /// Its own case of the scene interpreter; `None` for a type its shared
    /// formula (the `FORM_*` above) evaluates.
    pub wgsl: Option<WgslCase>,
    /// The formula form's expansion of the lowered arguments `v`.
    pub(in crate::sdf) expand: Expand,
}

impl PartialEq for PrimitiveType {
    fn eq(&self, o: &PrimitiveType) -> bool {
        self.code == o.code
    }
}

impl Eq for PrimitiveType {}

impl std::hash::Hash for PrimitiveType {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.code.hash(h)
    }
}

impl std::fmt::Debug for PrimitiveType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.scene_name)
    }
}

impl PrimitiveType {
    /// The number of parameters.
    pub fn param_count(&self) -> usize {
        self.fields.iter().map(|f| f.len).sum()
    }

    /// The parameters' names, a field of three numbers as `half[0]` …
    /// `half[2]`, in parameter order.
    pub fn param_names(&self) -> Vec<String> {
        let mut out = Vec::with_capacity(self.param_count());
        for f in self.fields {
            if f.len == 1 {
                out.push(f.name.to_string());
            } else {
                out.extend((0..f.len).map(|k| format!("{}[{k}]", f.name)));
            }
        }
        out
    }

    /// `given` (the leading parameters, as a formula may leave trailing
    /// ones out) completed with the defaults of the fields after them.
    pub fn with_defaults(&self, given: &[f64]) -> Params {
        let mut v = Params::new(given);
        let mut at = 0;
        for f in self.fields {
            if at >= given.len() {
                if let Some(d) = f.default {
                    let value = d.value(&v);
                    v.push(value);
                }
            }
            at += f.len;
        }
        v
    }

    /// Whether a scene may place it under a twist or bend (a warp is
    /// bounded by its operand's cylinder).
    pub fn bounded(&self, v: &[f64]) -> bool {
        !matches!((self.bound)(v), Bound::Unbounded)
    }
}

/// A parameter field of a scene file node.
#[derive(Debug, Clone, Copy)]
pub struct Field {
    /// The JSON key.
    pub name: &'static str,
    /// 1: a number; 3: `[x, y, z]`.
    pub len: usize,
    /// The value a scene file (and, for trailing parameters, a formula) may
    /// leave out; numbers only.
    pub default: Option<Default>,
    /// A point or direction of the local frame: mirroring the shape
    /// (x ↦ −x) negates its x.
    pub mirrored: bool,
}

impl Field {
    /// A number.
    pub const fn number(name: &'static str) -> Field {
        Field { name, len: 1, default: None, mirrored: false }
    }

    /// Three numbers: extents, which mirroring keeps.
    pub const fn extents(name: &'static str) -> Field {
        Field { name, len: 3, default: None, mirrored: false }
    }

    /// Three numbers: a point or direction, which mirroring reflects.
    pub const fn point(name: &'static str) -> Field {
        Field { name, len: 3, default: None, mirrored: true }
    }

    /// A number with a default value.
    pub const fn or(self, v: f64) -> Field {
        Field { default: Some(Default::Value(v)), ..self }
    }

    /// A number with a default worked out from the parameters before it.
    pub const fn or_else(self, f: fn(&[f64]) -> f64) -> Field {
        Field { default: Some(Default::Of(f)), ..self }
    }
}

/// A field's default.
#[derive(Debug, Clone, Copy)]
pub enum Default {
    /// This value.
    Value(f64),
    /// A function of the parameters before the field.
    Of(fn(&[f64]) -> f64),
}

impl Default {
    /// The value, given the parameters before the field.
    pub fn value(self, before: &[f64]) -> f64 {
        match self {
            Default::Value(v) => v,
            Default::Of(f) => f(before),
        }
    }
}

/// A type's parameters, in parameter order (without an allocation: scenes
/// evaluate primitives by the million).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    len: usize,
    v: [f64; MAX_PARAMS],
}

impl Params {
    /// These numbers (at most [`MAX_PARAMS`]).
    pub fn new(v: &[f64]) -> Params {
        let mut p = Params { len: 0, v: [0.0; MAX_PARAMS] };
        for &x in v {
            p.push(x);
        }
        p
    }

    fn push(&mut self, x: f64) {
        assert!(self.len < MAX_PARAMS, "a primitive type has at most {MAX_PARAMS} parameters");
        self.v[self.len] = x;
        self.len += 1;
    }
}

impl std::ops::Deref for Params {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.v[..self.len]
    }
}

impl std::ops::DerefMut for Params {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.v[..self.len]
    }
}

/// A type's Lipschitz bound.
#[derive(Debug, Clone, Copy)]
pub enum Lipschitz {
    /// 1: an exact distance or a bound that is 1-Lipschitz.
    One,
    /// A function of the parameters, which may overflow (then refused,
    /// naming `field`).
    Of {
        /// The bound.
        bound: fn(&[f64]) -> f64,
        /// The field an infinite bound is blamed on.
        field: &'static str,
    },
}

impl Lipschitz {
    /// The bound for parameters `v`.
    pub fn of(self, v: &[f64]) -> f64 {
        match self {
            Lipschitz::One => 1.0,
            Lipschitz::Of { bound, .. } => bound(v),
        }
    }
}

/// Where a type's local sublevel set {f ≤ r} lies (r ≥ 0, local units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// The box of these half extents about the local origin, grown by r.
    Box([f64; 3]),
    /// The ball about the local origin of radius `radius + slope·r`.
    Ball {
        /// Radius at r = 0.
        radius: f64,
        /// Growth per unit of r.
        slope: f64,
    },
    /// The points within `radius + max(r − allowance, 0)` of the segment a–b.
    Capsule {
        /// One end.
        a: [f64; 3],
        /// The other end.
        b: [f64; 3],
        /// Radius at r = 0.
        radius: f64,
        /// How far r may rise before the set grows.
        allowance: f64,
    },
    /// Everywhere (a half-space): always active, never warped.
    Unbounded,
}

/// A type's row in the GPU layout, after its frame's two.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rows {
    /// The form the interpreter evaluates (row 1's w).
    pub form: u32,
    /// Row 2 (what the form reads there).
    pub row: [f64; 4],
}

/// A type's own case of the scene interpreter (`scene_shape` in
/// templates/fields/scene.wgsl), compiled into the kernels of scenes that
/// have the type.
#[derive(Debug, Clone, Copy)]
pub struct WgslCase {
    /// Its row 1 form ([`Rows::form`]): `FORM_<NAME>` in WGSL, NAME the
    /// scene type in capitals. Below 16 (the warp kind takes the bits above).
    pub form: u32,
    /// The interpreter feature bit of scenes with the type: `FEATURE_<NAME>`.
    pub feature: u32,
    /// The statements, indented by 8: they set `d` where `form ==
    /// FORM_<NAME>`, reading the local point `q`, row 2 `r2`, the record's
    /// first row `o` and whether the node is a `leaf`.
    pub code: &'static str,
    /// For a type whose local field is not 1-Lipschitz (the others are
    /// enclosed by their value at a box's centre plus or minus its
    /// half-diagonal), its interval enclosure for bisection
    /// (templates/fields/scene_enclosure.wgsl, `scene_shape_ia`): statements,
    /// indented by 8, that set the range `e` where `form == FORM_<NAME>`,
    /// reading the box `b` (a `SceneBox` in the frame's input), the rows
    /// `r0`, `r1`, `r2` and `o`; `scene_local_box(r0, r1, b)` is the local box.
    pub enclosure: Option<&'static str>,
}

/// Where an expansion stopped: the semantic pass's error is kept aside
/// (by [`expand`]), so a primitive's expansion is a plain function, one
/// entry of a table, rather than generic over the sink.
pub(in crate::sdf) struct Stopped;

/// The expansion of a primitive's formula form.
pub(in crate::sdf) type Expand = fn(&mut Ir<'_, '_>, &[NodeId]) -> Result<NodeId, Stopped>;

/// The node builder a primitive's expansion gets.
pub(in crate::sdf) type Ir<'b, 's> = B<'b, DynSink<'s>>;

/// The semantic pass behind a `dyn`.
pub(in crate::sdf) struct DynSink<'s>(&'s mut dyn ErasedSink);

trait ErasedSink {
    fn push(&mut self, op: Op) -> Result<NodeId, Stopped>;
    fn konst(&self, n: NodeId) -> Option<f64>;
    fn op(&self, n: NodeId) -> Op;
    fn substitute(&mut self, shape: NodeId, xyz: [NodeId; 3]) -> Result<NodeId, Stopped>;
    fn bad_argument(&self, index: usize, message: String) -> Stopped;
}

/// A sink whose first error is kept.
struct Keep<'a, S: Sink> {
    sink: &'a mut S,
    error: RefCell<Option<S::Error>>,
}

impl<S: Sink> Keep<'_, S> {
    fn kept<T>(&self, r: Result<T, S::Error>) -> Result<T, Stopped> {
        r.map_err(|e| {
            self.error.borrow_mut().get_or_insert(e);
            Stopped
        })
    }
}

impl<S: Sink> ErasedSink for Keep<'_, S> {
    fn push(&mut self, op: Op) -> Result<NodeId, Stopped> {
        let r = self.sink.push(op);
        self.kept(r)
    }
    fn konst(&self, n: NodeId) -> Option<f64> {
        self.sink.konst(n)
    }
    fn op(&self, n: NodeId) -> Op {
        self.sink.op(n)
    }
    fn substitute(&mut self, shape: NodeId, xyz: [NodeId; 3]) -> Result<NodeId, Stopped> {
        let r = self.sink.substitute(shape, xyz);
        self.kept(r)
    }
    fn bad_argument(&self, index: usize, message: String) -> Stopped {
        let e = self.sink.bad_argument(index, message);
        self.kept::<()>(Err(e)).unwrap_err()
    }
}

impl Sink for DynSink<'_> {
    type Error = Stopped;
    fn push(&mut self, op: Op) -> Result<NodeId, Stopped> {
        self.0.push(op)
    }
    fn konst(&self, n: NodeId) -> Option<f64> {
        self.0.konst(n)
    }
    fn op(&self, n: NodeId) -> Op {
        self.0.op(n)
    }
    fn substitute(&mut self, shape: NodeId, xyz: [NodeId; 3]) -> Result<NodeId, Stopped> {
        self.0.substitute(shape, xyz)
    }
    fn bad_argument(&self, index: usize, message: String) -> Stopped {
        self.0.bad_argument(index, message)
    }
}

/// Runs expansion `f` (of a primitive type, a join or a unary type) over
/// the semantic pass `sink`.
pub(super) fn expand<S: Sink, F>(sink: &mut S, f: F) -> Result<NodeId, S::Error>
where
    F: FnOnce(&mut Ir<'_, '_>) -> Result<NodeId, Stopped>,
{
    let mut keep = Keep { sink, error: RefCell::new(None) };
    let mut dyn_sink = DynSink(&mut keep);
    let r = f(&mut B(&mut dyn_sink));
    match r {
        Ok(n) => Ok(n),
        Err(Stopped) => Err(keep.error.into_inner().expect("an expansion stops only on an error it kept")),
    }
}

/// An error unless `v > 0`.
fn positive(name: &str, v: f64) -> Result<(), Invalid> {
    if v > 0.0 { Ok(()) } else { Err((name.to_string(), "must be > 0".to_string())) }
}

/// An error unless `v ≥ 0`.
fn non_negative(name: &str, v: f64) -> Result<(), Invalid> {
    if v >= 0.0 { Ok(()) } else { Err((name.to_string(), "must be >= 0".to_string())) }
}

/// An error unless every component of `v` is > 0, naming it (`half[1]`).
fn positive3(name: &str, v: &[f64]) -> Result<(), Invalid> {
    for (k, c) in v.iter().enumerate() {
        if !(*c > 0.0) {
            return Err((format!("{name}[{k}]"), "must be > 0".to_string()));
        }
    }
    Ok(())
}

/// sqrt(a² + b²) written as the formula language writes `length`, so the
/// two paths round alike (`f64::hypot` rounds differently).
fn hypot(a: f64, b: f64) -> f64 {
    (a * a + b * b).sqrt()
}

/// The exact box distance at p for half extents b, as the formula's `boxd`.
fn box_distance(p: DVec3, b: DVec3) -> f64 {
    let q = p.abs() - b;
    let qp = q.max(DVec3::ZERO);
    let outside = (qp.x * qp.x + qp.y * qp.y + qp.z * qp.z).sqrt();
    outside + q.x.max(q.y.max(q.z)).min(0.0)
}

/// The three numbers from `v[k]`.
fn vec3(v: &[f64], k: usize) -> DVec3 {
    DVec3::new(v[k], v[k + 1], v[k + 2])
}

#[cfg(test)]
mod tests;

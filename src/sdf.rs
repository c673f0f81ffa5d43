//! The distance-field language: SDF primitives, rigid transforms, scaling
//! and (smooth) CSG operators as built-in functions of the formula language.
//!
//! Nothing here is a new kind of node. Every form expands, in the semantic
//! pass, into ordinary IR operations of x, y and z, so the interval and
//! affine evaluators, `--method bisect` and `isotrace eval` all work on
//! distance fields unchanged, and sphere tracing sees one scalar function.
//! Transforms substitute coordinates: `translate(1, 0, 0, s)` is `s` with x
//! replaced by `x - 1`, done by rebuilding the already lowered `s` over new
//! x, y, z nodes (the [`Sink::substitute`] hook), so definitions and any
//! expression (not only primitives) can be transformed.
//!
//! **Lipschitz bounds.** Sphere tracing needs |f(p)| ≤ distance(p, f = 0),
//! which holds when f is 1-Lipschitz (|∇f| ≤ 1). Every primitive here is
//! an exact Euclidean distance except `octahedron` (a bound, exact on the
//! faces); translate and rotate are isometries and `scale(s, f)` is
//! s·f(p/s), so all three keep the bound; min and max keep the larger bound
//! of their operands; and the smooth operators of Zanni et al. (eq. 8-11),
//! g = min(a, b) - k/6·max(1 - |a - b|/k, 0)^3, have gradient
//! (1 - w)∇a + w∇b with w ∈ [0, ½] in the blend zone, a convex combination,
//! so they keep it too. The chamfer and round blends (module `join`) have
//! √2 times the operands' bound, `sum_union` their sum where both are below
//! T, `density` max(1, T·1.7173/(c·R)) (1 at its default T); `twist` and
//! `bend` (module `warp`) multiply it by (a + √(a² + 4))/2 and 1 + a,
//! a = |k|·ρ with ρ the distance from the z axis, unbounded far from it.
//! These, and anything else that raises the bound (adding a displacement,
//! multiplying, scaling one axis), need `--lipschitz L`.
//!
//! **Profiles and modifiers.** `circle`, `rect`, `roundrect`, `capsule2d`
//! and `polygon` are exact 2D distances in x and y (module `profile`):
//! valid 3D fields (prisms along z) that `extrude` and `revolve` turn into
//! bounded solids, both keeping the bound. `offset`, `shell` and `infill`
//! wrap any shape and keep it too; `displace` adds a fixed noise whose
//! gradient raises it by 1.92·a·f (module `unary`). A blobtree scene
//! implements the same definitions, so each is stated once, in the
//! [`FORMS`] table and the doc comment of its expansion; a primitive in
//! its descriptor ([`primitive::TYPES`], a file each), which scenes read
//! too, and so is a unary form ([`unary::TYPES`]) and an operator style
//! ([`operator::STYLES`]).

use crate::ir::{Func1, NodeId, Op};

mod blend;
mod build;
pub mod join;
pub mod operator;
pub mod primitive;
pub mod profile;
pub mod unary;
mod warp;

use build::B;
pub use blend::{density, density_default_range, density_lipschitz, DENSITY_SLOPE};
pub use unary::NOISE_WAVES;
#[cfg(test)]
pub use join::{chamfer_intersect, chamfer_range, chamfer_union, round_intersect, round_union, sum_union};
#[cfg(test)]
pub use unary::{noise, NOISE_GRADIENT};
pub use warp::{bend_lipschitz, bend_point, twist_lipschitz, twist_point};

/// A distance-field form (primitive, transform or operator).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Form {
    /// A primitive: `sphere(r)`, `torus(R, r)`, … ([`primitive::TYPES`]).
    Primitive(&'static primitive::PrimitiveType),
    /// A unary form: `offset(d, shape)`, `shell(t, shape)`, … ([`unary::TYPES`]).
    Unary(&'static unary::UnaryType),
    /// An operator style's operation: `union(a, b, ...)`,
    /// `smooth_union(a, b, k)`, … ([`operator::STYLES`]).
    Operator(&'static operator::OperatorStyle, join::OpKind),
    /// A join of an operation: `chamfer_union(a, b, r)`, … ([`join::TYPES`]).
    Join(&'static join::JoinType, join::OpKind),
    /// `translate(dx, dy, dz, shape)`
    Translate,
    /// `rotate(ax, ay, az, angle, shape)`: about the axis through the origin, radians
    Rotate,
    /// `scale(s, shape)`, uniform, s > 0
    Scale,
    /// A 2D profile: `circle(r)`, `rect(hx, hy)`, … ([`profile::TYPES`]).
    Profile(&'static profile::ProfileType),
    /// `extrude(h, shape)`: a 2D shape extruded along z
    Extrude,
    /// `revolve(R, shape)`: a 2D shape revolved around the z axis
    Revolve,
    /// `repeat(sx, sy, sz, nx, ny, nz, shape)`: a centred grid of copies
    Repeat,
    /// `mirror(nx, ny, nz, shape)`: with its reflection across a plane
    Mirror,
    /// `twist(k, shape)`: turned by k·z about the z axis
    Twist,
    /// `bend(k, shape)`: the xy plane turned by k·x
    Bend,
}

/// How many arguments a form takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arity {
    /// Exactly n.
    Exactly(usize),
    /// n or more.
    AtLeast(usize),
    /// From the first to the second, inclusive.
    Between(usize, usize),
    /// x, y pairs: an even number from twice the first to twice the second.
    Pairs(usize, usize),
}

/// One row of the language reference: name, form, arity, signature and
/// what it computes (the user documentation's table of functions is
/// written from this).
pub struct Info {
    /// The name users write.
    pub name: &'static str,
    /// The form.
    pub form: Form,
    /// Arguments.
    pub arity: Arity,
    /// `sphere(r)`
    pub signature: &'static str,
    /// One line: the definition and its Lipschitz bound.
    pub doc: &'static str,
}

/// Every form but the primitives, the profiles, the operators, the joins
/// and the unary forms ([`primitive::TYPES`], [`profile::TYPES`],
/// [`operator::STYLES`], [`join::TYPES`] and [`unary::TYPES`] describe
/// those), in documentation order.
pub const FORMS: &[Info] = &[
    Info { name: "extrude", form: Form::Extrude, arity: Arity::Exactly(2), signature: "extrude(h, shape)", doc: "min(max(w.x, w.y), 0) + length(max(w, 0)), w = (shape, |z| - h), h > 0: a 2D shape extruded along z; exact for an exact 2D distance, L = 1 (the shape's)" },
    Info { name: "revolve", form: Form::Revolve, arity: Arity::Exactly(2), signature: "revolve(R, shape)", doc: "shape(sqrt(x^2 + y^2) - R, z, 0), R >= 0: a 2D shape revolved around the z axis; exact for an exact 2D distance not crossing the axis, L = 1 (the shape's)" },
    Info { name: "translate", form: Form::Translate, arity: Arity::Exactly(4), signature: "translate(dx, dy, dz, shape)", doc: "shape(p - d); an isometry, keeps L" },
    Info { name: "rotate", form: Form::Rotate, arity: Arity::Exactly(5), signature: "rotate(ax, ay, az, angle, shape)", doc: "shape rotated by angle (radians, right-handed) about the axis a through the origin; keeps L" },
    Info { name: "scale", form: Form::Scale, arity: Arity::Exactly(2), signature: "scale(s, shape)", doc: "s * shape(p / s), s > 0; keeps L" },
    Info { name: "repeat", form: Form::Repeat, arity: Arity::Exactly(7), signature: "repeat(sx, sy, sz, nx, ny, nz, shape)", doc: "the union of nx ny nz copies of shape translated by s (i - (n - 1)/2), a centred grid; n constant whole numbers >= 1, at most 4096 copies; keeps L" },
    Info { name: "mirror", form: Form::Mirror, arity: Arity::Exactly(4), signature: "mirror(nx, ny, nz, shape)", doc: "the union of shape and its reflection across the plane through the origin with normal n (n not zero); keeps L" },
    Info { name: "twist", form: Form::Twist, arity: Arity::Exactly(2), signature: "twist(k, shape)", doc: "shape(c x + s y, c y - s x, z), c = cos(k z), s = sin(k z): turned by k z radians about the z axis; L = the shape's times (a + sqrt(a^2 + 4))/2, a = |k| rho, rho the distance from the z axis: unbounded far from the axis, give --lipschitz" },
    Info { name: "bend", form: Form::Bend, arity: Arity::Exactly(2), signature: "bend(k, shape)", doc: "shape(c x - s y, s x + c y, z), c = cos(k x), s = sin(k x): a bar along x curls into an arc of radius 1/k; L = the shape's times (1 + a), a = |k| rho, rho the distance from the z axis: unbounded far from the axis, give --lipschitz" },
];

/// Every form: the primitives, the profiles, then [`FORMS`], then the
/// operators', the joins' and the unary forms.
pub fn forms() -> impl Iterator<Item = &'static Info> {
    let operators = operator::STYLES.iter().flat_map(|t| &t.forms);
    let joins = join::TYPES.iter().flat_map(|t| t.forms);
    let profiles = profile::TYPES.iter().map(|t| &t.info);
    primitive::TYPES.iter().map(|t| &t.info).chain(profiles).chain(FORMS).chain(operators).chain(joins).chain(unary::TYPES.iter().map(|t| &t.info))
}

/// The form called `name`, if any.
pub fn lookup(name: &str) -> Option<&'static Info> {
    forms().find(|i| i.name == name)
}

/// Every form name (for suggestions).
pub fn names() -> impl Iterator<Item = &'static str> {
    forms().map(|i| i.name)
}

/// What the semantic pass provides to expand a form: node creation (with
/// folding and sharing), constant inspection, coordinate substitution, and
/// an error for a bad argument.
pub trait Sink {
    /// The semantic pass's error type.
    type Error;
    /// Adds (or finds) a node.
    fn push(&mut self, op: Op) -> Result<NodeId, Self::Error>;
    /// The value of a constant node.
    fn konst(&self, n: NodeId) -> Option<f64>;
    /// The operation of a node.
    fn op(&self, n: NodeId) -> Op;
    /// `shape` rebuilt with x, y, z replaced by the given nodes.
    fn substitute(&mut self, shape: NodeId, xyz: [NodeId; 3]) -> Result<NodeId, Self::Error>;
    /// An error pointing at argument `index`.
    fn bad_argument(&self, index: usize, message: String) -> Self::Error;
}


/// Expands a call of `form` whose arguments are already lowered (`v`, in
/// order; a transform's shape was lowered over the plain x, y, z).
pub fn lower<S: Sink>(sink: &mut S, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    match form {
        Form::Primitive(t) => return primitive::expand(sink, |b| (t.expand)(b, v)),
        Form::Unary(t) => return primitive::expand(sink, |b| (t.expand)(b, v)),
        Form::Operator(t, kind) => return primitive::expand(sink, |b| (t.expand)(b, kind, v)),
        Form::Join(t, kind) => return primitive::expand(sink, |b| (t.expand)(b, kind, v)),
        Form::Profile(t) => return primitive::expand(sink, |b| (t.expand)(b, v)),
        _ => {}
    }
    let mut b = B(sink);
    let b = &mut b;
    match form {
        Form::Primitive(_) | Form::Unary(_) | Form::Operator(..) | Form::Join(..) | Form::Profile(_) => unreachable!("expanded above"),
        Form::Translate | Form::Rotate | Form::Scale => transform(b, form, v),
        Form::Extrude | Form::Revolve => profile::lower_solid(b, form, v),
        Form::Repeat => repeat(b, v),
        Form::Mirror => mirror(b, v),
        Form::Twist | Form::Bend => warp::lower(b, form, v),
    }
}

/// `mirror`: min(shape(p), shape(p − 2(n·p)n/|n|²)).
fn mirror<S: Sink>(b: &mut B<'_, S>, v: &[NodeId]) -> Result<NodeId, S::Error> {
    let n = [v[0], v[1], v[2]];
    let nn = b.dot(&n, &n)?;
    if b.0.konst(nn) == Some(0.0) {
        return Err(b.0.bad_argument(0, "the mirror plane's normal (nx, ny, nz) must not be zero".into()));
    }
    let p = b.xyz()?;
    let np = b.dot(&n, &p)?;
    let two = b.c(2.0)?;
    let k = b.mul(two, np)?;
    let k = b.div(k, nn)?;
    let mut q = [0; 3];
    for a in 0..3 {
        let o = b.mul(k, n[a])?;
        q[a] = b.sub(p[a], o)?;
    }
    let image = b.0.substitute(v[3], q)?;
    b.min(v[3], image)
}

/// The most copies `repeat` makes: each is the whole shape again, in the
/// IR and in a lowered scene.
pub const MAX_REPEAT: u64 = 4096;

/// The copy counts of `repeat(sx, sy, sz, nx, ny, nz, shape)` (arguments 3
/// to 5), checked: constant whole numbers ≥ 1, at most [`MAX_REPEAT`]
/// copies in all. `konst` gives an argument's constant value.
pub fn repeat_counts<E>(konst: impl Fn(usize) -> Option<f64>, bad: impl Fn(usize, String) -> E) -> Result<[u64; 3], E> {
    let mut n = [0u64; 3];
    for k in 0..3 {
        match konst(3 + k) {
            Some(c) if c >= 1.0 && c.fract() == 0.0 && c <= MAX_REPEAT as f64 => n[k] = c as u64,
            Some(c) => return Err(bad(3 + k, format!("a copy count must be a whole number from 1 to {MAX_REPEAT}, got {c}"))),
            None => return Err(bad(3 + k, "a copy count must be a constant".into())),
        }
    }
    if n[0] * n[1] * n[2] > MAX_REPEAT {
        return Err(bad(3, format!("{} copies, above the limit of {MAX_REPEAT}", n[0] * n[1] * n[2])));
    }
    Ok(n)
}

/// The centred offset of copy `i` of `n` along an axis, in spacings.
pub fn repeat_offset(i: u64, n: u64) -> f64 {
    i as f64 - (n as f64 - 1.0) / 2.0
}

/// `repeat`: the min over the copies, each the shape over coordinates
/// shifted by its offset.
fn repeat<S: Sink>(b: &mut B<'_, S>, v: &[NodeId]) -> Result<NodeId, S::Error> {
    let n = repeat_counts(|k| b.0.konst(v[k]), |k, m| b.0.bad_argument(k, m))?;
    let p = b.xyz()?;
    let mut acc: Option<NodeId> = None;
    for i in 0..n[0] {
        for j in 0..n[1] {
            for k in 0..n[2] {
                let mut q = [0; 3];
                for (a, idx) in [i, j, k].into_iter().enumerate() {
                    let c = b.c(repeat_offset(idx, n[a]))?;
                    let o = b.mul(v[a], c)?;
                    q[a] = b.sub(p[a], o)?;
                }
                let copy = b.0.substitute(v[6], q)?;
                acc = Some(match acc {
                    Some(a) => b.min(a, copy)?,
                    None => copy,
                });
            }
        }
    }
    Ok(acc.expect("at least one copy"))
}

/// `translate`, `rotate` and `scale`: the shape rebuilt over substituted
/// coordinates (the inverse motion applied to p).
fn transform<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    match form {
        Form::Translate => {
            let p = b.xyz()?;
            let mut q = [0; 3];
            for k in 0..3 {
                q[k] = b.sub(p[k], v[k])?;
            }
            b.0.substitute(v[3], q)
        }
        Form::Rotate => {
            let a = [v[0], v[1], v[2]];
            let len = b.length(&a)?;
            if b.0.konst(len) == Some(0.0) {
                return Err(b.0.bad_argument(0, "the rotation axis (ax, ay, az) must not be zero".into()));
            }
            let mut k = a;
            if !b.is(len, 1.0) {
                for c in &mut k {
                    *c = b.div(*c, len)?;
                }
            }
            // The shape rotated by +angle is the shape at p rotated by -angle
            // (Rodrigues): p cos - (k × p) sin + k (k·p)(1 - cos).
            let p = b.xyz()?;
            let cos = b.f1(Func1::Cos, v[3])?;
            let cos = b.snap(cos)?;
            let sin = b.f1(Func1::Sin, v[3])?;
            let sin = b.snap(sin)?;
            let one = b.c(1.0)?;
            let oc = b.sub(one, cos)?;
            let kp = b.dot(&k, &p)?;
            let kpoc = b.mul(kp, oc)?;
            let mut q = [0; 3];
            for i in 0..3 {
                let (j, l) = ((i + 1) % 3, (i + 2) % 3);
                let c1 = b.mul(k[j], p[l])?;
                let c2 = b.mul(k[l], p[j])?;
                let cross = b.sub(c1, c2)?;
                let t1 = b.mul(p[i], cos)?;
                let t2 = b.mul(cross, sin)?;
                let t3 = b.mul(k[i], kpoc)?;
                let s = b.sub(t1, t2)?;
                q[i] = b.add(s, t3)?;
            }
            b.0.substitute(v[4], q)
        }
        Form::Scale => {
            let s = v[0];
            if let Some(c) = b.0.konst(s) {
                if !(c > 0.0) {
                    return Err(b.0.bad_argument(0, format!("the scale factor must be positive, got {c}")));
                }
            }
            let p = b.xyz()?;
            let mut q = [0; 3];
            for k in 0..3 {
                q[k] = b.div(p[k], s)?;
            }
            let d = b.0.substitute(v[1], q)?;
            b.mul(d, s)
        }
        _ => unreachable!("{form:?} is not a transform"),
    }
}

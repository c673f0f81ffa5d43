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
//! so they keep it too. Anything else (adding a displacement, multiplying,
//! scaling one axis) can raise the bound: then pass `--lipschitz L`.

use crate::ir::{Func1, Func2, Func3, NodeId, Op, Var};

/// A distance-field form (primitive, transform or operator).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Form {
    /// `sphere(r)`
    Sphere,
    /// `box(bx, by, bz)`, half extents
    Box,
    /// `roundbox(bx, by, bz, r)`, half extents including the rounding
    RoundBox,
    /// `torus(R, r)` around the z axis
    Torus,
    /// `cylinder(r, h)`, capped, along z, half height h
    Cylinder,
    /// `capsule(ax, ay, az, bx, by, bz, r)`
    Capsule,
    /// `plane(nx, ny, nz, d)`: the half-space n·p ≤ d (n normalised)
    Plane,
    /// `octahedron(s)`: |x| + |y| + |z| ≤ s
    Octahedron,
    /// `translate(dx, dy, dz, shape)`
    Translate,
    /// `rotate(ax, ay, az, angle, shape)`: about the axis through the origin, radians
    Rotate,
    /// `scale(s, shape)`, uniform, s > 0
    Scale,
    /// `union(a, b, ...)`
    Union,
    /// `intersect(a, b, ...)`
    Intersect,
    /// `subtract(a, b, ...)`: a minus the others
    Subtract,
    /// `smooth_union(a, b, k)`
    SmoothUnion,
    /// `smooth_intersect(a, b, k)`
    SmoothIntersect,
    /// `smooth_subtract(a, b, k)`: a minus b
    SmoothSubtract,
    /// `compact_union(a, b, beta[, r_o])`: Zanni's compact G∪ (eq. 12, 17, 18)
    CompactUnion,
    /// `compact_intersect(a, b, beta[, r_o])`: G∩
    CompactIntersect,
    /// `compact_subtract(a, b, beta[, r_o])`: G\, a minus b
    CompactSubtract,
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
}

/// One row of the language reference: name, form, arity, signature and
/// what it computes (the README's table is written from this).
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

/// Every form, in documentation order.
pub const FORMS: &[Info] = &[
    Info { name: "sphere", form: Form::Sphere, arity: Arity::Exactly(1), signature: "sphere(r)", doc: "|p| - r; exact, L = 1" },
    Info { name: "box", form: Form::Box, arity: Arity::Exactly(3), signature: "box(bx, by, bz)", doc: "axis-aligned box with half extents b; exact, L = 1" },
    Info { name: "roundbox", form: Form::RoundBox, arity: Arity::Exactly(4), signature: "roundbox(bx, by, bz, r)", doc: "box(b - r) - r: same extents, edges rounded by r; exact, L = 1" },
    Info { name: "torus", form: Form::Torus, arity: Arity::Exactly(2), signature: "torus(R, r)", doc: "ring around the z axis; exact, L = 1" },
    Info { name: "cylinder", form: Form::Cylinder, arity: Arity::Exactly(2), signature: "cylinder(r, h)", doc: "capped, axis z, radius r, half height h; exact, L = 1" },
    Info { name: "capsule", form: Form::Capsule, arity: Arity::Exactly(7), signature: "capsule(ax, ay, az, bx, by, bz, r)", doc: "segment a-b thickened by r; exact, L = 1" },
    Info { name: "plane", form: Form::Plane, arity: Arity::Exactly(4), signature: "plane(nx, ny, nz, d)", doc: "half-space n.p <= d, n normalised; exact, L = 1" },
    Info { name: "octahedron", form: Form::Octahedron, arity: Arity::Exactly(1), signature: "octahedron(s)", doc: "(|x| + |y| + |z| - s)/sqrt(3); a bound (exact on the faces), L = 1" },
    Info { name: "translate", form: Form::Translate, arity: Arity::Exactly(4), signature: "translate(dx, dy, dz, shape)", doc: "shape(p - d); an isometry, keeps L" },
    Info { name: "rotate", form: Form::Rotate, arity: Arity::Exactly(5), signature: "rotate(ax, ay, az, angle, shape)", doc: "shape rotated by angle (radians, right-handed) about the axis a through the origin; keeps L" },
    Info { name: "scale", form: Form::Scale, arity: Arity::Exactly(2), signature: "scale(s, shape)", doc: "s * shape(p / s), s > 0; keeps L" },
    Info { name: "union", form: Form::Union, arity: Arity::AtLeast(2), signature: "union(a, b, ...)", doc: "min; L = max of the operands'" },
    Info { name: "intersect", form: Form::Intersect, arity: Arity::AtLeast(2), signature: "intersect(a, b, ...)", doc: "max; L = max of the operands'" },
    Info { name: "subtract", form: Form::Subtract, arity: Arity::AtLeast(2), signature: "subtract(a, b, ...)", doc: "max(a, -b, ...): a minus the others; L = max of the operands'" },
    Info { name: "smooth_union", form: Form::SmoothUnion, arity: Arity::Exactly(3), signature: "smooth_union(a, b, k)", doc: "min(a, b) - d(a, b, k), d = k/6 max(1 - |a - b|/k, 0)^3 (Zanni eq. 8-9), k > 0; L = max of the operands'" },
    Info { name: "smooth_intersect", form: Form::SmoothIntersect, arity: Arity::Exactly(3), signature: "smooth_intersect(a, b, k)", doc: "max(a, b) + d(a, b, k) (eq. 10); L = max of the operands'" },
    Info { name: "smooth_subtract", form: Form::SmoothSubtract, arity: Arity::Exactly(3), signature: "smooth_subtract(a, b, k)", doc: "max(a, -b) + d(a, -b, k) (eq. 11); L = max of the operands'" },
    Info { name: "compact_union", form: Form::CompactUnion, arity: Arity::Between(3, 4), signature: "compact_union(a, b, beta[, r_o])", doc: "Zanni's compact G (eq. 12, 17, 18): the blend of smooth_union, closed beyond r_o (default 2 beta, at least 7/6 beta); the same field as a scene's smooth_union; L = the operands' times 6 r_o/(6 r_o - beta)" },
    Info { name: "compact_intersect", form: Form::CompactIntersect, arity: Arity::Between(3, 4), signature: "compact_intersect(a, b, beta[, r_o])", doc: "compact G of smooth_intersect, sharp unless |a|, |b| <= r_o; L = the operands' times 6 r_o/(6 r_o - beta)" },
    Info { name: "compact_subtract", form: Form::CompactSubtract, arity: Arity::Between(3, 4), signature: "compact_subtract(a, b, beta[, r_o])", doc: "compact G of smooth_subtract, sharp unless |a|, |b| <= r_o; L = the operands' times 6 r_o/(6 r_o - beta)" },
];

/// The form called `name`, if any.
pub fn lookup(name: &str) -> Option<&'static Info> {
    FORMS.iter().find(|i| i.name == name)
}

/// Every form name (for suggestions).
pub fn names() -> impl Iterator<Item = &'static str> {
    FORMS.iter().map(|i| i.name)
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

/// Node-building shorthands over a [`Sink`], with the algebraic identities
/// (0·a = 0, 1·a = a, a + 0 = a) that keep rotations about coordinate axes
/// and zero translations from adding dead arithmetic to every evaluation.
struct B<'s, S: Sink>(&'s mut S);

impl<S: Sink> B<'_, S> {
    fn c(&mut self, v: f64) -> Result<NodeId, S::Error> {
        self.0.push(Op::Const(v))
    }
    fn is(&self, n: NodeId, v: f64) -> bool {
        self.0.konst(n) == Some(v)
    }
    /// A constant within 1e-12 of an integer becomes that integer, so
    /// cos(pi/2) is 0 and a quarter turn costs no arithmetic.
    fn snap(&mut self, n: NodeId) -> Result<NodeId, S::Error> {
        match self.0.konst(n) {
            Some(c) if c != c.round() && (c - c.round()).abs() < 1e-12 => self.c(c.round()),
            _ => Ok(n),
        }
    }
    fn var(&mut self, v: Var) -> Result<NodeId, S::Error> {
        self.0.push(Op::Var(v))
    }
    fn add(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        if self.is(a, 0.0) {
            return Ok(b);
        }
        if self.is(b, 0.0) {
            return Ok(a);
        }
        self.0.push(Op::Add(a, b))
    }
    fn sub(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        if self.is(b, 0.0) {
            return Ok(a);
        }
        if self.is(a, 0.0) {
            return self.neg(b);
        }
        self.0.push(Op::Sub(a, b))
    }
    fn mul(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        if self.is(a, 0.0) || self.is(b, 0.0) {
            return self.c(0.0);
        }
        if self.is(a, 1.0) {
            return Ok(b);
        }
        if self.is(b, 1.0) {
            return Ok(a);
        }
        self.0.push(Op::Mul(a, b))
    }
    fn div(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::Div(a, b))
    }
    fn neg(&mut self, a: NodeId) -> Result<NodeId, S::Error> {
        if let Op::Neg(inner) = self.0.op(a) {
            return Ok(inner);
        }
        self.0.push(Op::Neg(a))
    }
    fn sqr(&mut self, a: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::PowI(a, 2))
    }
    fn f1(&mut self, f: Func1, a: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::Call1(f, a))
    }
    fn min(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::Call2(Func2::Min, a, b))
    }
    fn max(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::Call2(Func2::Max, a, b))
    }
    /// sqrt(a² + b² [+ c²]).
    fn length(&mut self, v: &[NodeId]) -> Result<NodeId, S::Error> {
        let mut acc = self.sqr(v[0])?;
        for &n in &v[1..] {
            let s = self.sqr(n)?;
            acc = self.add(acc, s)?;
        }
        self.f1(Func1::Sqrt, acc)
    }
    fn xyz(&mut self) -> Result<[NodeId; 3], S::Error> {
        Ok([self.var(Var::X)?, self.var(Var::Y)?, self.var(Var::Z)?])
    }
    /// a·u + b·v + c·w.
    fn dot(&mut self, a: [NodeId; 3], b: [NodeId; 3]) -> Result<NodeId, S::Error> {
        let mut acc = self.mul(a[0], b[0])?;
        for k in 1..3 {
            let m = self.mul(a[k], b[k])?;
            acc = self.add(acc, m)?;
        }
        Ok(acc)
    }
    /// The exact box distance for half extents `b` at coordinates `p`.
    fn boxd(&mut self, p: [NodeId; 3], b: [NodeId; 3]) -> Result<NodeId, S::Error> {
        let zero = self.c(0.0)?;
        let mut q = [0; 3];
        let mut qp = [0; 3];
        for k in 0..3 {
            let a = self.f1(Func1::Abs, p[k])?;
            q[k] = self.sub(a, b[k])?;
            qp[k] = self.max(q[k], zero)?;
        }
        let outside = self.length(&qp)?;
        let m = self.max(q[1], q[2])?;
        let m = self.max(q[0], m)?;
        let inside = self.min(m, zero)?;
        self.add(outside, inside)
    }
    /// d(a, b, k) written NaN-free, as the scene operators compute it:
    /// h³ / (6 · max(k², 1e-30)) with h = max(k − |a − b|, 0).
    fn blend_nan_free(&mut self, a: NodeId, b: NodeId, k: NodeId) -> Result<NodeId, S::Error> {
        let diff = self.sub(a, b)?;
        let ad = self.f1(Func1::Abs, diff)?;
        let h = self.sub(k, ad)?;
        let zero = self.c(0.0)?;
        let h = self.max(h, zero)?;
        let h3 = self.0.push(Op::PowI(h, 3))?;
        let k2 = self.sqr(k)?;
        let tiny = self.c(1e-30)?;
        let k2 = self.max(k2, tiny)?;
        let six = self.c(6.0)?;
        let den = self.mul(six, k2)?;
        self.div(h3, den)
    }

    /// Zanni's blend d(a, b, k) = k/6 · max(1 - |a - b|/k, 0)^3 (eq. 9).
    fn blend(&mut self, a: NodeId, b: NodeId, k: NodeId) -> Result<NodeId, S::Error> {
        let diff = self.sub(a, b)?;
        let ad = self.f1(Func1::Abs, diff)?;
        let r = self.div(ad, k)?;
        let one = self.c(1.0)?;
        let h = self.sub(one, r)?;
        let zero = self.c(0.0)?;
        let h = self.max(h, zero)?;
        let h3 = self.0.push(Op::PowI(h, 3))?;
        let six = self.c(6.0)?;
        let k6 = self.div(k, six)?;
        self.mul(k6, h3)
    }
}

/// Zanni's compact operator G (eq. 12, 17, 18; `crate::scene::operator`)
/// from ordinary operations. The IR has no branch, so "both operands in
/// R_o" becomes a blend range forced to 0 outside R_o:
/// β'' = min(b_r(x), 1e30 · max(r_o − m, 0)) with m = max(a, b) for ∪ and
/// max(|a|, |b|) for ∩ and \. That is eq. 12 everywhere but on the edge of
/// R_o itself, where G is continuous (r_o ≥ 7β/6) so both sides are sharp.
/// The blend d is the NaN-free h³ / (6 max(k², 1e-30)), h = max(k − |a − b|, 0).
fn compact<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    let beta = v[2];
    let kb = b.0.konst(beta);
    if let Some(k) = kb {
        if !(k > 0.0) {
            return Err(b.0.bad_argument(2, format!("the blend range beta must be positive, got {k}")));
        }
    }
    let ro = match v.get(3) {
        Some(&r) => r,
        None => {
            let two = b.c(2.0)?;
            b.mul(two, beta)?
        }
    };
    if let (Some(k), Some(r)) = (kb, b.0.konst(ro)) {
        let min = 7.0 * k / 6.0;
        if !(r >= min * (1.0 - 1e-12)) {
            return Err(b.0.bad_argument(3, format!("r_o must be at least 7/6 of beta ({}), got {r}: below it the compact blend is discontinuous", crate::diag::short_number(min))));
        }
    }
    let union = form == Form::CompactUnion;
    let (a, o) = if form == Form::CompactSubtract { (v[0], b.neg(v[1])?) } else { (v[0], v[1]) };
    let sharp = if union { b.min(a, o)? } else { b.max(a, o)? };
    let d = b.blend_nan_free(a, o, beta)?;
    let x = if union { b.sub(sharp, d)? } else { let s = b.add(sharp, d)?; b.f1(Func1::Abs, s)? };
    // b_r(x) = beta · max(1 − 6x / (6 r_o − beta), 0)
    let six = b.c(6.0)?;
    let six_ro = b.mul(six, ro)?;
    let den = b.sub(six_ro, beta)?;
    let six_x = b.mul(six, x)?;
    let q = b.div(six_x, den)?;
    let one = b.c(1.0)?;
    let t = b.sub(one, q)?;
    let zero = b.c(0.0)?;
    let t = b.max(t, zero)?;
    let br = b.mul(beta, t)?;
    let m = if union {
        b.max(a, o)?
    } else {
        let (aa, ao) = (b.f1(Func1::Abs, a)?, b.f1(Func1::Abs, o)?);
        b.max(aa, ao)?
    };
    let room = b.sub(ro, m)?;
    let room = b.max(room, zero)?;
    let big = b.c(1e30)?;
    let gate = b.mul(big, room)?;
    let k = b.min(br, gate)?;
    let d = b.blend_nan_free(a, o, k)?;
    if union { b.sub(sharp, d) } else { b.add(sharp, d) }
}

/// Expands a call of `form` whose arguments are already lowered (`v`, in
/// order; a transform's shape was lowered over the plain x, y, z).
pub fn lower<S: Sink>(sink: &mut S, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    let mut b = B(sink);
    match form {
        Form::Sphere => {
            let p = b.xyz()?;
            let l = b.length(&p)?;
            b.sub(l, v[0])
        }
        Form::Box => {
            let p = b.xyz()?;
            b.boxd(p, [v[0], v[1], v[2]])
        }
        Form::RoundBox => {
            let p = b.xyz()?;
            let mut inner = [0; 3];
            for k in 0..3 {
                inner[k] = b.sub(v[k], v[3])?;
            }
            let d = b.boxd(p, inner)?;
            b.sub(d, v[3])
        }
        Form::Torus => {
            let [x, y, z] = b.xyz()?;
            let ring = b.length(&[x, y])?;
            let q = b.sub(ring, v[0])?;
            let l = b.length(&[q, z])?;
            b.sub(l, v[1])
        }
        Form::Cylinder => {
            let [x, y, z] = b.xyz()?;
            let radial = b.length(&[x, y])?;
            let dx = b.sub(radial, v[0])?;
            let az = b.f1(Func1::Abs, z)?;
            let dz = b.sub(az, v[1])?;
            let zero = b.c(0.0)?;
            let m = b.max(dx, dz)?;
            let inside = b.min(m, zero)?;
            let ox = b.max(dx, zero)?;
            let oz = b.max(dz, zero)?;
            let outside = b.length(&[ox, oz])?;
            b.add(inside, outside)
        }
        Form::Capsule => {
            let p = b.xyz()?;
            let mut pa = [0; 3];
            let mut ba = [0; 3];
            for k in 0..3 {
                pa[k] = b.sub(p[k], v[k])?;
                ba[k] = b.sub(v[3 + k], v[k])?;
            }
            let bb = b.dot(ba, ba)?;
            let konst = b.0.konst(bb);
            let along = match konst {
                // a = b: a sphere around a.
                Some(c) if c == 0.0 => b.length(&pa)?,
                _ => {
                    // A non-constant |b - a|² may reach 0: keep the division finite.
                    let bb = if konst.is_some() { bb } else { let tiny = b.c(1e-12)?; b.max(bb, tiny)? };
                    let pb = b.dot(pa, ba)?;
                    let h = b.div(pb, bb)?;
                    let (zero, one) = (b.c(0.0)?, b.c(1.0)?);
                    let h = b.0.push(Op::Call3(Func3::Clamp, h, zero, one))?;
                    let mut w = [0; 3];
                    for k in 0..3 {
                        let s = b.mul(ba[k], h)?;
                        w[k] = b.sub(pa[k], s)?;
                    }
                    b.length(&w)?
                }
            };
            b.sub(along, v[6])
        }
        Form::Plane => {
            let p = b.xyz()?;
            let n = [v[0], v[1], v[2]];
            let len = b.length(&n)?;
            if b.0.konst(len) == Some(0.0) {
                return Err(b.0.bad_argument(0, "the plane's normal (nx, ny, nz) must not be zero".into()));
            }
            let np = b.dot(n, p)?;
            let np = if b.is(len, 1.0) { np } else { b.div(np, len)? };
            b.sub(np, v[3])
        }
        Form::Octahedron => {
            let p = b.xyz()?;
            let mut s = b.f1(Func1::Abs, p[0])?;
            for &c in &p[1..] {
                let a = b.f1(Func1::Abs, c)?;
                s = b.add(s, a)?;
            }
            let d = b.sub(s, v[0])?;
            let k = b.c(1.0 / 3f64.sqrt())?;
            b.mul(d, k)
        }
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
            let kp = b.dot(k, p)?;
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
        Form::Union | Form::Intersect | Form::Subtract => {
            let mut acc = v[0];
            for &n in &v[1..] {
                acc = match form {
                    Form::Union => b.min(acc, n)?,
                    Form::Intersect => b.max(acc, n)?,
                    _ => {
                        let m = b.neg(n)?;
                        b.max(acc, m)?
                    }
                };
            }
            Ok(acc)
        }
        Form::CompactUnion | Form::CompactIntersect | Form::CompactSubtract => compact(&mut b, form, v),
        Form::SmoothUnion | Form::SmoothIntersect | Form::SmoothSubtract => {
            if let Some(k) = b.0.konst(v[2]) {
                if !(k > 0.0) {
                    return Err(b.0.bad_argument(2, format!("the blend range k must be positive, got {k}")));
                }
            }
            let (a, o) = match form {
                Form::SmoothSubtract => (v[0], b.neg(v[1])?),
                _ => (v[0], v[1]),
            };
            let d = b.blend(a, o, v[2])?;
            match form {
                Form::SmoothUnion => {
                    let m = b.min(a, o)?;
                    b.sub(m, d)
                }
                _ => {
                    let m = b.max(a, o)?;
                    b.add(m, d)
                }
            }
        }
    }
}

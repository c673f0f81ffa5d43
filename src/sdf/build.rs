//! The node builder the form expansions share: shorthands over the
//! semantic pass's [`Sink`] with the identities that keep dead arithmetic
//! out of every evaluation, and the argument checks that point at an
//! argument.

use super::Sink;
use crate::ir::{Func1, Func2, Func3, NodeId, Op, Var};

/// Node-building shorthands over a [`Sink`], with the algebraic identities
/// (0·a = 0, 1·a = a, a + 0 = a) that keep rotations about coordinate axes
/// and zero translations from adding dead arithmetic to every evaluation.
pub(super) struct B<'s, S: Sink>(pub(super) &'s mut S);

impl<S: Sink> B<'_, S> {
    pub(super) fn c(&mut self, v: f64) -> Result<NodeId, S::Error> {
        self.0.push(Op::Const(v))
    }
    pub(super) fn is(&self, n: NodeId, v: f64) -> bool {
        self.0.konst(n) == Some(v)
    }
    /// A constant within 1e-12 of an integer becomes that integer, so
    /// cos(pi/2) is 0 and a quarter turn costs no arithmetic.
    pub(super) fn snap(&mut self, n: NodeId) -> Result<NodeId, S::Error> {
        match self.0.konst(n) {
            Some(c) if c != c.round() && (c - c.round()).abs() < 1e-12 => self.c(c.round()),
            _ => Ok(n),
        }
    }
    pub(super) fn var(&mut self, v: Var) -> Result<NodeId, S::Error> {
        self.0.push(Op::Var(v))
    }
    pub(super) fn add(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        if self.is(a, 0.0) {
            return Ok(b);
        }
        if self.is(b, 0.0) {
            return Ok(a);
        }
        self.0.push(Op::Add(a, b))
    }
    pub(super) fn sub(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        if self.is(b, 0.0) {
            return Ok(a);
        }
        if self.is(a, 0.0) {
            return self.neg(b);
        }
        self.0.push(Op::Sub(a, b))
    }
    pub(super) fn mul(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
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
    pub(super) fn div(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::Div(a, b))
    }
    pub(super) fn neg(&mut self, a: NodeId) -> Result<NodeId, S::Error> {
        if let Op::Neg(inner) = self.0.op(a) {
            return Ok(inner);
        }
        self.0.push(Op::Neg(a))
    }
    pub(super) fn sqr(&mut self, a: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::PowI(a, 2))
    }
    pub(super) fn f1(&mut self, f: Func1, a: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::Call1(f, a))
    }
    pub(super) fn min(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::Call2(Func2::Min, a, b))
    }
    pub(super) fn max(&mut self, a: NodeId, b: NodeId) -> Result<NodeId, S::Error> {
        self.0.push(Op::Call2(Func2::Max, a, b))
    }
    /// sqrt(a² + b² [+ c²]).
    pub(super) fn length(&mut self, v: &[NodeId]) -> Result<NodeId, S::Error> {
        let mut acc = self.sqr(v[0])?;
        for &n in &v[1..] {
            let s = self.sqr(n)?;
            acc = self.add(acc, s)?;
        }
        self.f1(Func1::Sqrt, acc)
    }
    pub(super) fn xyz(&mut self) -> Result<[NodeId; 3], S::Error> {
        Ok([self.var(Var::X)?, self.var(Var::Y)?, self.var(Var::Z)?])
    }
    /// a₀b₀ + a₁b₁ [+ a₂b₂], summed left to right.
    pub(super) fn dot(&mut self, a: &[NodeId], b: &[NodeId]) -> Result<NodeId, S::Error> {
        let mut acc = self.mul(a[0], b[0])?;
        for k in 1..a.len() {
            let m = self.mul(a[k], b[k])?;
            acc = self.add(acc, m)?;
        }
        Ok(acc)
    }
    /// The exact box distance for half extents `b` at coordinates `p`, in
    /// 3D (`box`) or 2D (`rect`): with q = |p| − b,
    /// length(max(q, 0)) + min(max(q₀, max(q₁[, q₂])), 0).
    pub(super) fn boxd(&mut self, p: &[NodeId], b: &[NodeId]) -> Result<NodeId, S::Error> {
        let zero = self.c(0.0)?;
        let n = p.len();
        let mut q = [0; 3];
        let mut qp = [0; 3];
        for k in 0..n {
            let a = self.f1(Func1::Abs, p[k])?;
            q[k] = self.sub(a, b[k])?;
            qp[k] = self.max(q[k], zero)?;
        }
        let outside = self.length(&qp[..n])?;
        let mut m = q[n - 1];
        for k in (0..n - 1).rev() {
            m = self.max(q[k], m)?;
        }
        let inside = self.min(m, zero)?;
        self.add(outside, inside)
    }
    /// pa − ba·h, h = clamp(dot(pa, ba)/dot(ba, ba), 0, 1): the offset from
    /// the segment a–b to the point (pa = p − a, ba = b − a). For a = b
    /// (|ba|² the constant 0) it is pa; a |ba|² that is not constant may
    /// still reach 0, so it is kept at 1e-12 or above to keep h finite.
    pub(super) fn segment_offset(&mut self, pa: &[NodeId], ba: &[NodeId]) -> Result<Vec<NodeId>, S::Error> {
        let bb = self.dot(ba, ba)?;
        let konst = self.0.konst(bb);
        if konst == Some(0.0) {
            return Ok(pa.to_vec());
        }
        let bb = if konst.is_some() { bb } else { let tiny = self.c(1e-12)?; self.max(bb, tiny)? };
        let pb = self.dot(pa, ba)?;
        let h = self.div(pb, bb)?;
        let (zero, one) = (self.c(0.0)?, self.c(1.0)?);
        let h = self.0.push(Op::Call3(Func3::Clamp, h, zero, one))?;
        let mut w = Vec::with_capacity(pa.len());
        for k in 0..pa.len() {
            let s = self.mul(ba[k], h)?;
            w.push(self.sub(pa[k], s)?);
        }
        Ok(w)
    }
    /// min(max(u, v), 0) + length(max(u, 0), max(v, 0)): the exact distance
    /// to a capped prism from the distances u across and v along its axis
    /// (`cylinder`, `extrude`).
    pub(super) fn capped(&mut self, u: NodeId, v: NodeId) -> Result<NodeId, S::Error> {
        let zero = self.c(0.0)?;
        let m = self.max(u, v)?;
        let inside = self.min(m, zero)?;
        let ou = self.max(u, zero)?;
        let ov = self.max(v, zero)?;
        let outside = self.length(&[ou, ov])?;
        self.add(inside, outside)
    }
    /// An error at argument `i` unless it is positive (when it is constant).
    pub(super) fn positive(&self, v: &[NodeId], i: usize, what: &str) -> Result<(), S::Error> {
        match self.0.konst(v[i]) {
            Some(c) if !(c > 0.0) => Err(self.0.bad_argument(i, format!("{what} must be positive, got {c}"))),
            _ => Ok(()),
        }
    }
    /// An error at argument `i` if it is a negative constant.
    pub(super) fn non_negative(&self, v: &[NodeId], i: usize, what: &str) -> Result<(), S::Error> {
        match self.0.konst(v[i]) {
            Some(c) if !(c >= 0.0) => Err(self.0.bad_argument(i, format!("{what} must not be negative, got {c}"))),
            _ => Ok(()),
        }
    }
    /// d(a, b, k) written NaN-free, as the scene operators compute it:
    /// h³ / (6 · max(k², 1e-30)) with h = max(k − |a − b|, 0).
    pub(super) fn blend_nan_free(&mut self, a: NodeId, b: NodeId, k: NodeId) -> Result<NodeId, S::Error> {
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

    /// [`Self::blend_nan_free`] for a blend range k that may be 0 (the
    /// compact operator's gated range), written k/6 · u³ with
    /// u = max(1 − |a − b| / max(k, 1e-30), 0): the same number, but an
    /// enclosure stays within [0, k/6] where k's range reaches 0, where
    /// h³ / (6 max(k², 1e-30)) divides a bounded h³ by a divisor as small as
    /// 1e-30 (interval arithmetic then could not exclude 0 on the edge of
    /// the operator's range, and drew a surface there).
    pub(super) fn blend_gated(&mut self, a: NodeId, b: NodeId, k: NodeId) -> Result<NodeId, S::Error> {
        let diff = self.sub(a, b)?;
        let ad = self.f1(Func1::Abs, diff)?;
        let tiny = self.c(1e-30)?;
        let kk = self.max(k, tiny)?;
        let r = self.div(ad, kk)?;
        let one = self.c(1.0)?;
        let u = self.sub(one, r)?;
        let zero = self.c(0.0)?;
        let u = self.max(u, zero)?;
        let u3 = self.0.push(Op::PowI(u, 3))?;
        let six = self.c(6.0)?;
        let k6 = self.div(k, six)?;
        self.mul(k6, u3)
    }

    /// Zanni's blend d(a, b, k) = k/6 · max(1 - |a - b|/k, 0)^3 (eq. 9).
    pub(super) fn blend(&mut self, a: NodeId, b: NodeId, k: NodeId) -> Result<NodeId, S::Error> {
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

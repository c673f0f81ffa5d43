//! The CSG operators: sharp (`union`, `intersect`, `subtract`), smooth
//! (Zanni et al. eq. 8-11) and compact (eq. 12, 17, 18).

use super::{Form, Sink, B};
use crate::ir::{Func1, NodeId};

/// min, max, or max(a, −b, …), folded left to right.
pub(super) fn sharp<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
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

/// min(a, b) − d(a, b, k), max(a, b) + d(a, b, k) or max(a, −b) + d(a, −b, k).
pub(super) fn smooth<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
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

/// Zanni's compact operator G (eq. 12, 17, 18; `crate::scene::operator`)
/// from ordinary operations. The IR has no branch, so "both operands in
/// R_o" becomes a blend range forced to 0 outside R_o:
/// β'' = min(b_r(x), 1e30 · max(r_o − m, 0)) with m = max(a, b) for ∪ and
/// max(|a|, |b|) for ∩ and \. That is eq. 12 everywhere but on the edge of
/// R_o itself, where G is continuous (r_o ≥ 7β/6) so both sides are sharp.
/// The blend d is the NaN-free h³ / (6 max(k², 1e-30)), h = max(k − |a − b|, 0).
pub(super) fn compact<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
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

//! Zanni's compact operators G (eq. 12, 17, 18 of Zanni et al. 2024;
//! `../shared/guide/blobtree-brief.md` §1.1): the smooth operator g whose
//! blend range is b_r of g's own value while both operands lie in the
//! operator range R_o (∪: (−∞, r_o]; ∩ and \: [−r_o, r_o]), sharp CSG
//! outside it, so a primitive can influence the field only up to a value
//! fixed by the tree (its range of interest, `scene::roi`). A scene's
//! `smooth_union`, `smooth_intersection` and `smooth_difference` are these.
//!
//! Everything is written NaN-free: the blend d uses h³/(6·max(β², 1e-30))
//! with h = max(β − |a − b|, 0), and r_o < 7β/6, where G would be
//! discontinuous, is refused (so 6r_o − β > 0 in b_r). G can raise its
//! operands' Lipschitz bound by the factor 6r_o/(6r_o − β) (measured in the
//! brief, §1.1).

use super::smooth::g;
use super::{operands, InScene, OpKind, OperatorStyle};
use crate::sdf::Sink;
use crate::ir::{Func1, NodeId};
use crate::sdf::primitive::{Field, Invalid, Ir, Stopped};
use crate::sdf::{Arity, Form, Info};

/// The compact operators G.
pub static COMPACT: OperatorStyle = OperatorStyle {
    forms: [
        Info { name: "compact_union", form: Form::Operator(&COMPACT, OpKind::Union), arity: Arity::Between(3, 4), signature: "compact_union(a, b, beta[, r_o])", doc: "Zanni's compact G (eq. 12, 17, 18): the blend of smooth_union, closed beyond r_o (default 2 beta, at least 7/6 beta); the same field as a scene's smooth_union; L = the operands' times 6 r_o/(6 r_o - beta)" },
        Info { name: "compact_intersect", form: Form::Operator(&COMPACT, OpKind::Intersection), arity: Arity::Between(3, 4), signature: "compact_intersect(a, b, beta[, r_o])", doc: "compact G of smooth_intersect, sharp unless |a|, |b| <= r_o; L = the operands' times 6 r_o/(6 r_o - beta)" },
        Info { name: "compact_subtract", form: Form::Operator(&COMPACT, OpKind::Difference), arity: Arity::Between(3, 4), signature: "compact_subtract(a, b, beta[, r_o])", doc: "compact G of smooth_subtract, sharp unless |a|, |b| <= r_o; L = the operands' times 6 r_o/(6 r_o - beta)" },
    ],
    params: &[Field::number("beta"), Field::number("r_o").or_else(|v| DEFAULT_RANGE_FACTOR * v[0])],
    scene: InScene::Nodes { names: ["smooth_union", "smooth_intersection", "smooth_difference"], code: 35 },
    check,
    apply: |kind, a, b, v| compact(kind, a, b, v[0], v[1]),
    blend: |v| v[0],
    range: |v| v[1],
    lipschitz: |v| 6.0 * v[1] / (6.0 * v[1] - v[0]),
    expand,
};

/// The default operator range relative to β (the brief's choice; the
/// Lipschitz factor 6r_o/(6r_o − β) is then 12/11).
pub const DEFAULT_RANGE_FACTOR: f64 = 2.0;

/// Checks β and r_o; the error names the field (`beta`, `r_o`).
///
/// r_o is compared with 7β/6 with a relative slack of 1e-12, so a range
/// written as 7/6 of β in decimal is not refused for its rounding.
fn check(v: &[f64]) -> Result<(), Invalid> {
    let (beta, range) = (v[0], v[1]);
    for (name, v) in [("beta", beta), ("r_o", range)] {
        if !v.is_finite() {
            return Err((name.into(), "must be finite".into()));
        }
    }
    if !(beta > 0.0) {
        return Err(("beta".into(), "must be > 0".into()));
    }
    let min = 7.0 * beta / 6.0;
    if !(range >= min * (1.0 - 1e-12)) {
        return Err(("r_o".into(), format!("must be >= 7/6 of beta ({}): below it the compact blend is discontinuous", crate::diag::short_number(min))));
    }
    Ok(())
}

/// The transition b_r(x, β, r_o) = β · max(1 − 6x/(6r_o − β), 0) (eq. 18).
/// The caller guarantees 6r_o − β > 0.
pub fn b_r(x: f64, beta: f64, range: f64) -> f64 {
    beta * (1.0 - 6.0 * x / (6.0 * range - beta)).max(0.0)
}

/// The compact operator G (eq. 12 and 17): g with the blend range b_r of
/// the plain blend's value while both operands are in R_o (∪: (−∞, r_o];
/// ∩ and \: [−r_o, r_o]), sharp CSG otherwise.
pub fn compact(kind: OpKind, a: f64, b: f64, beta: f64, range: f64) -> f64 {
    let inside = match kind {
        OpKind::Union => a <= range && b <= range,
        _ => a.abs() <= range && b.abs() <= range,
    };
    if !inside {
        return g(kind, a, b, 0.0);
    }
    let x = g(kind, a, b, beta);
    let x = if kind == OpKind::Union { x } else { x.abs() };
    g(kind, a, b, b_r(x, beta, range))
}

/// G from ordinary operations, as [`compact`]. The IR has no branch, so
/// "both operands in R_o" becomes a blend range forced to 0 outside R_o:
/// β'' = min(b_r(x), 1e30 · max(r_o − m, 0)) with m = max(a, b) for ∪ and
/// max(|a|, |b|) for ∩ and \. That is eq. 12 everywhere but on the edge of
/// R_o itself, where G is continuous (r_o ≥ 7β/6) so both sides are sharp.
/// The first blend d is the NaN-free h³ / (6 max(k², 1e-30)), h = max(k − |a − b|, 0);
/// the gated one, whose k may be 0, is k/6 · max(1 − |a − b| / max(k, 1e-30), 0)³
/// (`blend_gated`: its enclosures stay bounded).
fn expand(b: &mut Ir<'_, '_>, kind: OpKind, v: &[NodeId]) -> Result<NodeId, Stopped> {
    let beta = v[2];
    b.positive(v, 2, "the blend range beta")?;
    let ro = match v.get(3) {
        Some(&r) => r,
        None => {
            let two = b.c(DEFAULT_RANGE_FACTOR)?;
            b.mul(two, beta)?
        }
    };
    if let (Some(k), Some(r)) = (b.0.konst(beta), b.0.konst(ro)) {
        let min = 7.0 * k / 6.0;
        if !(r >= min * (1.0 - 1e-12)) {
            return Err(b.0.bad_argument(3, format!("r_o must be at least 7/6 of beta ({}), got {r}: below it the compact blend is discontinuous", crate::diag::short_number(min))));
        }
    }
    let union = kind == OpKind::Union;
    let (a, o) = operands(b, kind, v)?;
    let sharp = if union { b.min(a, o)? } else { b.max(a, o)? };
    let d = b.blend_nan_free(a, o, beta)?;
    let x = if union { b.sub(sharp, d)? } else { let s = b.add(sharp, d)?; b.f1(Func1::Abs, s)? };
    let br = blend_range(b, x, beta, ro)?;
    let zero = b.c(0.0)?;
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
    let d = b.blend_gated(a, o, k)?;
    if union { b.sub(sharp, d) } else { b.add(sharp, d) }
}

/// b_r(x) = β · max(1 − 6x / (6 r_o − β), 0), as [`b_r`].
fn blend_range(b: &mut Ir<'_, '_>, x: NodeId, beta: NodeId, ro: NodeId) -> Result<NodeId, Stopped> {
    let six = b.c(6.0)?;
    let six_ro = b.mul(six, ro)?;
    let den = b.sub(six_ro, beta)?;
    let six_x = b.mul(six, x)?;
    let q = b.div(six_x, den)?;
    let one = b.c(1.0)?;
    let t = b.sub(one, q)?;
    let zero = b.c(0.0)?;
    let t = b.max(t, zero)?;
    b.mul(beta, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blends_are_nan_free_and_ranges_are_checked() {
        assert_eq!(super::super::smooth::blend_d(1.0, 1.0, 0.0), 0.0);
        assert!((g(OpKind::Union, 0.0, 0.0, 0.6) + 0.1).abs() < 1e-15);
        assert_eq!(check(&[0.6, 0.7]), Ok(()));
        assert_eq!(check(&[1.0, 1.0]).unwrap_err().0, "r_o");
        assert_eq!(check(&[0.0, 1.0]).unwrap_err(), ("beta".into(), "must be > 0".into()));
        assert!(((COMPACT.lipschitz)(&[1.0, 2.0]) - 12.0 / 11.0).abs() < 1e-15);
    }
}

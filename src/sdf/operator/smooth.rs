//! The smooth operators of Zanni et al. (eq. 8-11): g∪ = min(a, b) −
//! d(a, b, k), g∩ = max(a, b) + d(a, b, k), g\ = max(a, −b) + d(a, −b, k),
//! with the blend d(a, b, k) = k/6 · max(1 − |a − b|/k, 0)³. The gradient
//! is (1 − w)∇a + w∇b with w ∈ [0, ½] in the blend zone, a convex
//! combination, so each keeps the larger Lipschitz bound of its operands.
//!
//! A scene has no node of its own for them: it keeps each as Zanni's
//! compact G with β = k and r_o = 2k, the same zero set (`scene::lower`'s
//! module doc gives the argument).

use super::compact::{COMPACT, DEFAULT_RANGE_FACTOR};
use super::{operands, InScene, OpKind, OperatorStyle};
use crate::ir::NodeId;
use crate::sdf::primitive::{Field, Ir, Params, Stopped};
use crate::sdf::{Arity, Form, Info};

/// The smooth operators.
pub static SMOOTH: OperatorStyle = OperatorStyle {
    forms: [
        Info { name: "smooth_union", form: Form::Operator(&SMOOTH, OpKind::Union), arity: Arity::Exactly(3), signature: "smooth_union(a, b, k)", doc: "min(a, b) - d(a, b, k), d = k/6 max(1 - |a - b|/k, 0)^3 (Zanni eq. 8-9), k > 0; L = max of the operands'" },
        Info { name: "smooth_intersect", form: Form::Operator(&SMOOTH, OpKind::Intersection), arity: Arity::Exactly(3), signature: "smooth_intersect(a, b, k)", doc: "max(a, b) + d(a, b, k) (eq. 10); L = max of the operands'" },
        Info { name: "smooth_subtract", form: Form::Operator(&SMOOTH, OpKind::Difference), arity: Arity::Exactly(3), signature: "smooth_subtract(a, b, k)", doc: "max(a, -b) + d(a, -b, k) (eq. 11); L = max of the operands'" },
    ],
    params: &[Field::number("k")],
    scene: InScene::As { style: &COMPACT, params: |v| Params::new(&[v[0], DEFAULT_RANGE_FACTOR * v[0]]) },
    check: |v| if v[0] > 0.0 { Ok(()) } else { Err(("k".into(), "must be > 0".into())) },
    apply: |kind, a, b, v| g(kind, a, b, v[0]),
    blend: |v| v[0],
    // Not compact: it blends wherever the operands are within k.
    range: |_| f64::INFINITY,
    lipschitz: |_| 1.0,
    expand,
};

/// d(a, b, β) = β/6 · max(1 − |a − b|/β, 0)³ (eq. 9), NaN-free:
/// h³ / (6 · max(β², 1e-30)) with h = max(β − |a − b|, 0).
pub fn blend_d(a: f64, b: f64, beta: f64) -> f64 {
    let h = (beta - (a - b).abs()).max(0.0);
    h * h * h / (6.0 * (beta * beta).max(1e-30))
}

/// The bounded operators g (eq. 8, 10, 11); β = 0 is sharp CSG.
pub fn g(kind: OpKind, a: f64, b: f64, beta: f64) -> f64 {
    match kind {
        OpKind::Union => a.min(b) - blend_d(a, b, beta),
        OpKind::Intersection => a.max(b) + blend_d(a, b, beta),
        OpKind::Difference => a.max(-b) + blend_d(a, -b, beta),
    }
}

/// min(a, b) − d(a, b, k), max(a, b) + d(a, b, k) or max(a, −b) + d(a, −b, k).
fn expand(b: &mut Ir<'_, '_>, kind: OpKind, v: &[NodeId]) -> Result<NodeId, Stopped> {
    b.positive(v, 2, "the blend range k")?;
    let (a, o) = operands(b, kind, v)?;
    let d = b.blend(a, o, v[2])?;
    if kind == OpKind::Union {
        let m = b.min(a, o)?;
        b.sub(m, d)
    } else {
        let m = b.max(a, o)?;
        b.add(m, d)
    }
}

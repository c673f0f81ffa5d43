//! The chamfer: min(a, b, (a + b − r)/√2), a 45° bevel of width r. It
//! differs from min(a, b) only where both operands are below r/(2 − √2);
//! |∇| ≤ (|∇a| + |∇b|)/√2 ≤ √2 times the operands' bound.

use super::{operands, JoinType, OpKind};
use crate::ir::NodeId;
use crate::sdf::primitive::{Ir, Stopped};
use crate::sdf::{Arity, Form, Info};

/// 1/√2, the chamfer's diagonal.
const DIAGONAL: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The chamfer.
pub static CHAMFER: JoinType = JoinType {
    scene_names: &["chamfer_union", "chamfer_intersection", "chamfer_difference"],
    forms: &[
        Info { name: "chamfer_union", form: Form::Join(&CHAMFER, OpKind::Union), arity: Arity::Exactly(3), signature: "chamfer_union(a, b, r)", doc: "min(min(a, b), (a + b - r)/sqrt(2)), r > 0: a 45 degree bevel of width r, min(a, b) where either is above r/(2 - sqrt(2)); L = sqrt(2) times the operands'"  },
        Info { name: "chamfer_intersect", form: Form::Join(&CHAMFER, OpKind::Intersection), arity: Arity::Exactly(3), signature: "chamfer_intersect(a, b, r)", doc: "max(max(a, b), (a + b + r)/sqrt(2)), r > 0; L = sqrt(2) times the operands'"  },
        Info { name: "chamfer_subtract", form: Form::Join(&CHAMFER, OpKind::Difference), arity: Arity::Exactly(3), signature: "chamfer_subtract(a, b, r)", doc: "chamfer_intersect(a, -b, r): a minus b; L = sqrt(2) times the operands'"  },
    ],
    code: 38,
    field: "radius",
    range: chamfer_range,
    union: chamfer_union,
    intersect: Some(chamfer_intersect),
    lipschitz: |la, lb| std::f64::consts::SQRT_2 * la.max(lb),
    wgsl: "    j = select(j, min(min(x, y), (x + y - s) * 0.70710678), ty >= NODE_CHAMFER_UNION && ty <= NODE_CHAMFER_DIFFERENCE);\n",
    expand,
};

/// The operator range of a chamfer of width r: r/(2 − √2).
pub fn chamfer_range(r: f64) -> f64 {
    r / (2.0 - std::f64::consts::SQRT_2)
}

/// chamfer_union(a, b, r) = min(min(a, b), (a + b − r)/√2).
pub fn chamfer_union(a: f64, b: f64, r: f64) -> f64 {
    a.min(b).min((a + b - r) * DIAGONAL)
}

/// chamfer_intersect(a, b, r) = max(max(a, b), (a + b + r)/√2).
pub fn chamfer_intersect(a: f64, b: f64, r: f64) -> f64 {
    a.max(b).max((a + b + r) * DIAGONAL)
}

/// min(min(a, b), (a + b − r)/√2) for a union, max(max(a, b), (a + b + r)/√2)
/// otherwise, as [`chamfer_union`] and [`chamfer_intersect`].
fn expand(b: &mut Ir<'_, '_>, kind: OpKind, v: &[NodeId]) -> Result<NodeId, Stopped> {
    b.positive(v, 2, "the chamfer width r")?;
    let (a, o) = operands(b, kind, v)?;
    let (union, r) = (kind == OpKind::Union, v[2]);
    let sum = b.add(a, o)?;
    let bevel = if union { b.sub(sum, r)? } else { b.add(sum, r)? };
    let diagonal = b.c(DIAGONAL)?;
    let bevel = b.mul(bevel, diagonal)?;
    if union {
        let m = b.min(a, o)?;
        b.min(m, bevel)
    } else {
        let m = b.max(a, o)?;
        b.max(m, bevel)
    }
}

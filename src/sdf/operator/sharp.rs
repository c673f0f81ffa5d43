//! Sharp CSG: min (union), max (intersection) and max(a, −b) (difference),
//! of any number of operands in a formula, folded left to right. Each keeps
//! the larger Lipschitz bound of its operands.

use super::{OpKind, OperatorStyle, InScene};
use crate::ir::NodeId;
use crate::sdf::primitive::{Ir, Stopped};
use crate::sdf::{Arity, Form, Info};

/// Sharp CSG.
pub static SHARP: OperatorStyle = OperatorStyle {
    forms: [
        Info { name: "union", form: Form::Operator(&SHARP, OpKind::Union), arity: Arity::AtLeast(2), signature: "union(a, b, ...)", doc: "min; L = max of the operands'" },
        Info { name: "intersect", form: Form::Operator(&SHARP, OpKind::Intersection), arity: Arity::AtLeast(2), signature: "intersect(a, b, ...)", doc: "max; L = max of the operands'" },
        Info { name: "subtract", form: Form::Operator(&SHARP, OpKind::Difference), arity: Arity::AtLeast(2), signature: "subtract(a, b, ...)", doc: "max(a, -b, ...): a minus the others; L = max of the operands'" },
    ],
    params: &[],
    scene: InScene::Nodes { names: ["union", "intersection", "difference"], code: 32 },
    check: |_| Ok(()),
    // Zanni's g with β = 0 (eq. 8, 10, 11), which is sharp CSG.
    apply: |kind, a, b, _| super::g(kind, a, b, 0.0),
    blend: |_| 0.0,
    range: |_| 0.0,
    lipschitz: |_| 1.0,
    expand,
};

/// min, max, or max(a, −b, …), folded left to right.
fn expand(b: &mut Ir<'_, '_>, kind: OpKind, v: &[NodeId]) -> Result<NodeId, Stopped> {
    let mut acc = v[0];
    for &n in &v[1..] {
        acc = match kind {
            OpKind::Union => b.min(acc, n)?,
            OpKind::Intersection => b.max(acc, n)?,
            OpKind::Difference => {
                let m = b.neg(n)?;
                b.max(acc, m)?
            }
        };
    }
    Ok(acc)
}

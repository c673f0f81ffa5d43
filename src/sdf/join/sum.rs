//! The sum blend: min(a, b) + min(max(a, b), T) − T, which is a + b − T
//! where both are below T and min(a, b) elsewhere (r_o = T); unions only.
//! On normalized density fields with the same T it is the summation blend
//! of density fields (`sdf::blend`). |∇| ≤ |∇a| + |∇b| where both are below
//! T (a scene bounds groups of sums more tightly: `scene::roi`).

use super::{JoinType, OpKind};
use crate::ir::NodeId;
use crate::sdf::primitive::{Ir, Stopped};
use crate::sdf::{Arity, Form, Info};

/// The sum blend.
pub static SUM: JoinType = JoinType {
    scene_names: &["sum_union"],
    forms: &[
        Info { name: "sum_union", form: Form::Join(&SUM, OpKind::Union), arity: Arity::Exactly(3), signature: "sum_union(a, b, T)", doc: "min(a, b) + (min(max(a, b), T) - T), T > 0: a + b - T where both are below T, else min(a, b); on densities with the same T the density blend; L = the sum of the operands' where both are below T, else the larger"  },
    ],
    code: 44,
    field: "range",
    range: |t| t,
    union: sum_union,
    intersect: None,
    lipschitz: |la, lb| la + lb,
    wgsl: "    j = select(j, min(x, y) + (min(max(x, y), s) - s), ty == NODE_SUM_UNION);\n",
    expand,
};

/// sum_union(a, b, T) = min(a, b) + (min(max(a, b), T) − T): the bracket is
/// exactly 0 where an operand is at or beyond T, so the value is min(a, b)
/// to the bit there.
pub fn sum_union(a: f64, b: f64, t: f64) -> f64 {
    a.min(b) + (a.max(b).min(t) - t)
}

/// min(a, b) + (min(max(a, b), T) − T), as [`sum_union`].
fn expand(b: &mut Ir<'_, '_>, _: OpKind, v: &[NodeId]) -> Result<NodeId, Stopped> {
    b.positive(v, 2, "the range T")?;
    let lo = b.min(v[0], v[1])?;
    let hi = b.max(v[0], v[1])?;
    let hi = b.min(hi, v[2])?;
    let excess = b.sub(hi, v[2])?;
    b.add(lo, excess)
}

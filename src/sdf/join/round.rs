//! The round fillet (Mercury's hg_sdf fOpUnionRound): max(r, min(a, b)) −
//! |(max(r − a, 0), max(r − b, 0))|, a circular fillet of radius r; it
//! differs from min only where both are below r (r_o = r); |∇| ≤ √2 times
//! the operands' bound (the gradient is a combination u₁∇a + u₂∇b with
//! |u| = 1).

use super::{operands, JoinType, OpKind};
use crate::ir::NodeId;
use crate::sdf::primitive::{Ir, Stopped};
use crate::sdf::{Arity, Form, Info};

/// The round fillet.
pub static ROUND: JoinType = JoinType {
    scene_names: &["round_union", "round_intersection", "round_difference"],
    forms: &[
        Info { name: "round_union", form: Form::Join(&ROUND, OpKind::Union), arity: Arity::Exactly(3), signature: "round_union(a, b, r)", doc: "max(r, min(a, b)) - length(max(r - a, 0), max(r - b, 0)), r > 0: a circular fillet of radius r, min(a, b) where either is above r; L = sqrt(2) times the operands'"  },
        Info { name: "round_intersect", form: Form::Join(&ROUND, OpKind::Intersection), arity: Arity::Exactly(3), signature: "round_intersect(a, b, r)", doc: "min(-r, max(a, b)) + length(max(r + a, 0), max(r + b, 0)), r > 0; L = sqrt(2) times the operands'"  },
        Info { name: "round_subtract", form: Form::Join(&ROUND, OpKind::Difference), arity: Arity::Exactly(3), signature: "round_subtract(a, b, r)", doc: "round_intersect(a, -b, r): a minus b; L = sqrt(2) times the operands'"  },
    ],
    code: 41,
    field: "radius",
    range: |r| r,
    union: round_union,
    intersect: Some(round_intersect),
    lipschitz: |la, lb| std::f64::consts::SQRT_2 * la.max(lb),
    wgsl: "    // Exactly min(x, y) where an operand is beyond s, as on the host.
    j = select(j, select(min(x, y), s - length(vec2<f32>(s - x, s - y)), max(x, y) < s), ty >= NODE_ROUND_UNION && ty <= NODE_ROUND_DIFFERENCE);
",
    expand,
};

/// round_union(a, b, r) = max(r, min(a, b)) − |(max(r − a, 0), max(r − b, 0))|,
/// which is r − |(r − a, r − b)| where both operands are below r and
/// min(a, b) elsewhere: written so, it is min(a, b) to the bit there, as a
/// blobtree's pruned evaluation (which drops an operand beyond r) needs.
pub fn round_union(a: f64, b: f64, r: f64) -> f64 {
    if a.max(b) < r {
        let (u, v) = (r - a, r - b);
        r - (u * u + v * v).sqrt()
    } else {
        a.min(b)
    }
}

/// round_intersect(a, b, r) = min(−r, max(a, b)) + |(max(r + a, 0), max(r + b, 0))|,
/// as [`round_union`]: −r + |(r + a, r + b)| where both are above −r, else max(a, b).
pub fn round_intersect(a: f64, b: f64, r: f64) -> f64 {
    if a.min(b) > -r {
        let (u, v) = (r + a, r + b);
        (u * u + v * v).sqrt() - r
    } else {
        a.max(b)
    }
}

/// max(r, min(a, b)) − |(max(r − a, 0), max(r − b, 0))| for a union,
/// min(−r, max(a, b)) + |(max(r + a, 0), max(r + b, 0))| otherwise: the
/// same function as [`round_union`] and [`round_intersect`], which branch
/// (the IR has no branch) so as to be min or max to the bit beyond r; here
/// r − (r − a) may differ from a in the last bit.
fn expand(b: &mut Ir<'_, '_>, kind: OpKind, v: &[NodeId]) -> Result<NodeId, Stopped> {
    b.positive(v, 2, "the fillet radius r")?;
    let (a, o) = operands(b, kind, v)?;
    let (union, r) = (kind == OpKind::Union, v[2]);
    let zero = b.c(0.0)?;
    let mut uv = [0; 2];
    for (k, &n) in [a, o].iter().enumerate() {
        let e = if union { b.sub(r, n)? } else { b.add(r, n)? };
        uv[k] = b.max(e, zero)?;
    }
    let corner = b.length(&uv)?;
    if union {
        let m = b.min(a, o)?;
        let m = b.max(r, m)?;
        b.sub(m, corner)
    } else {
        let m = b.max(a, o)?;
        let nr = b.neg(r)?;
        let m = b.min(nr, m)?;
        b.add(m, corner)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fillet_meets_the_sharp_operator_continuously() {
        let (r, e) = (0.3, 1e-9);
        for i in 0..200 {
            let a = -2.0 + i as f64 * 0.02;
            assert!((round_union(a, r - e, r) - round_union(a, r + e, r)).abs() < 1e-6);
            assert!((round_intersect(a, -r - e, r) - round_intersect(a, -r + e, r)).abs() < 1e-6);
        }
    }
}

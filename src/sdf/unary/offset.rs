//! `offset(d, shape)`: shape − d, a rounding or dilation (d > 0) or an
//! erosion (d < 0): the level set d of the shape, gradient unchanged, so
//! it keeps the Lipschitz bound. Its operand's range of interest is the
//! node's shifted by d.

use super::{scaled, UnaryCase, UnaryType};
use crate::ir::NodeId;
use crate::sdf::{Arity, Form, Info};

/// The offset.
pub static OFFSET: UnaryType = UnaryType {
    info: Info {
        name: "offset",
        form: Form::Unary(&OFFSET),
        arity: Arity::Exactly(2),
        signature: "offset(d, shape)",
        doc: "shape - d: dilates by d > 0, erodes by d < 0; keeps L",
    },
    code: 48,
    fields: &["distance"],
    check: |_| Ok(()),
    apply: |v, f, _| f - v[0],
    operand_range: |v, lo, hi| (lo + v[0], hi + v[0]),
    operand_level: |v, l| Some(l + v[0]),
    lipschitz_increase: |_| 0.0,
    moved: Some(scaled),
    row: |v| [v[0], 0.0, 0.0, 0.0],
    wgsl: UnaryCase { feature: 0, code: "    r = select(r, v - k.x, ty == NODE_OFFSET);\n", enclosure: "    r = select(r, v - k.x, ty == NODE_OFFSET);\n" },
    expand,
};

fn expand(b: &mut crate::sdf::primitive::Ir<'_, '_>, v: &[NodeId]) -> Result<NodeId, crate::sdf::primitive::Stopped> {
    b.sub(v[1], v[0])
}

//! `shell(t, shape)`: |shape| − t/2, a wall of thickness t centred on the
//! surface: it hollows a solid out (Zanni et al. 2024, Fig. 14's carved
//! cavities). |·| keeps the gradient's length, so the Lipschitz bound too.
//! Its operand's range of interest is ±(r⁺ + t/2), and no one level of the
//! operand decides its surface (both sides do).

use super::{positive, scaled, UnaryCase, UnaryType};
use crate::ir::{Func1, NodeId};
use crate::sdf::{Arity, Form, Info};

/// The shell.
pub static SHELL: UnaryType = UnaryType {
    info: Info {
        name: "shell",
        form: Form::Unary(&SHELL),
        arity: Arity::Exactly(2),
        signature: "shell(t, shape)",
        doc: "|shape| - t/2, t > 0: a wall of thickness t centred on the surface; keeps L",
    },
    code: 49,
    fields: &["thickness"],
    check: |v| positive("thickness", v[0]),
    apply: |v, f, _| f.abs() - 0.5 * v[0],
    operand_range: |v, _, hi| {
        let r = (hi + 0.5 * v[0]).max(0.0);
        (-r, r)
    },
    operand_level: |_, _| None,
    lipschitz_increase: |_| 0.0,
    moved: Some(scaled),
    row: |v| [0.5 * v[0], 0.0, 0.0, 0.0],
    wgsl: UnaryCase { feature: 0, code: "    r = select(r, abs(v) - k.x, ty == NODE_SHELL);\n", enclosure: "    r = select(r, ia_abs(v) - k.x, ty == NODE_SHELL);\n" },
    expand,
};

fn expand(b: &mut crate::sdf::primitive::Ir<'_, '_>, v: &[NodeId]) -> Result<NodeId, crate::sdf::primitive::Stopped> {
    b.positive(v, 0, "the wall thickness t")?;
    let a = b.f1(Func1::Abs, v[1])?;
    let two = b.c(2.0)?;
    let half = b.div(v[0], two)?;
    b.sub(a, half)
}

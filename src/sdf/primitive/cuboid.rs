//! `box(bx, by, bz)`: the axis-aligned box of half extents b, exact.

use super::{box_distance, positive3, vec3, Bound, Field, Lipschitz, PrimitiveType, Rows, FORM_BOX};
use crate::sdf::{Arity, Form, Info};

/// The box.
pub static BOX: PrimitiveType = PrimitiveType {
    info: Info { name: "box", form: Form::Primitive(&BOX), arity: Arity::Exactly(3), signature: "box(bx, by, bz)", doc: "axis-aligned box with half extents b; exact, L = 1" },
    scene_name: "box",
    code: 2,
    fields: &[Field::extents("half")],
    check: |v| positive3("half", v),
    distance: |v, q| box_distance(q, vec3(v, 0)),
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Box([v[0], v[1], v[2]]),
    rows: |v, _| Rows { form: FORM_BOX, row: [v[0], v[1], v[2], 0.0] },
    wgsl: None,
    expand: |b, v| {
        let p = b.xyz()?;
        b.boxd(&p, &v[..3])
    },
};

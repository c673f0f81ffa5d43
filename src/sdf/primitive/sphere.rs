//! `sphere(r)`: |p| − r, exact.

use super::{positive, Bound, Field, Lipschitz, PrimitiveType, Rows, FORM_BOX};
use crate::sdf::{Arity, Form, Info};

/// The sphere.
pub static SPHERE: PrimitiveType = PrimitiveType {
    info: Info { name: "sphere", form: Form::Primitive(&SPHERE), arity: Arity::Exactly(1), signature: "sphere(r)", doc: "|p| - r; exact, L = 1" },
    scene_name: "sphere",
    code: 1,
    fields: &[Field::number("radius")],
    check: |v| positive("radius", v[0]),
    distance: |v, q| q.length() - v[0],
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Ball { radius: v[0], slope: 1.0 },
    // A box of no extent rounded by the radius.
    rows: |v, _| Rows { form: FORM_BOX, row: [0.0, 0.0, 0.0, v[0]] },
    wgsl: None,
    expand: |b, v| {
        let p = b.xyz()?;
        let l = b.length(&p)?;
        b.sub(l, v[0])
    },
};

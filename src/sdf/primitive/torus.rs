//! `torus(R, r)`: the ring of major radius R around the local z axis,
//! minor radius r, exact.

use super::{hypot, positive, Bound, Field, Lipschitz, PrimitiveType, Rows, FORM_REVOLVED};
use crate::sdf::{Arity, Form, Info};

/// The torus.
pub static TORUS: PrimitiveType = PrimitiveType {
    info: Info { name: "torus", form: Form::Primitive(&TORUS), arity: Arity::Exactly(2), signature: "torus(R, r)", doc: "ring around the z axis; exact, L = 1" },
    scene_name: "torus",
    code: 5,
    fields: &[Field::number("major"), Field::number("minor")],
    check: |v| {
        positive("major", v[0])?;
        positive("minor", v[1])
    },
    distance: |v, q| hypot(hypot(q.x, q.y) - v[0], q.z) - v[1],
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Box([v[0] + v[1], v[0] + v[1], v[1]]),
    // A point at distance R from the axis, rounded by r.
    rows: |v, _| Rows { form: FORM_REVOLVED, row: [0.0, v[0], 0.0, v[1]] },
    wgsl: None,
    expand: |b, v| {
        let [x, y, z] = b.xyz()?;
        let ring = b.length(&[x, y])?;
        let q = b.sub(ring, v[0])?;
        let l = b.length(&[q, z])?;
        b.sub(l, v[1])
    },
};

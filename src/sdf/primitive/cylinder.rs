//! `cylinder(r, h)`: capped, along the local z axis, radius r, half height
//! h, exact.

use super::{hypot, positive, Bound, Field, Lipschitz, PrimitiveType, Rows, FORM_REVOLVED};
use crate::ir::Func1;
use crate::sdf::{Arity, Form, Info};

/// The capped cylinder.
pub static CYLINDER: PrimitiveType = PrimitiveType {
    info: Info {
        name: "cylinder",
        form: Form::Primitive(&CYLINDER),
        arity: Arity::Exactly(2),
        signature: "cylinder(r, h)",
        doc: "capped, axis z, radius r, half height h; exact, L = 1",
    },
    scene_name: "cylinder",
    code: 6,
    fields: &[Field::number("radius"), Field::number("half_height")],
    check: |v| {
        positive("radius", v[0])?;
        positive("half_height", v[1])
    },
    distance: |v, q| {
        let dx = hypot(q.x, q.y) - v[0];
        let dz = q.z.abs() - v[1];
        dx.max(dz).min(0.0) + hypot(dx.max(0.0), dz.max(0.0))
    },
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Box([v[0], v[0], v[1]]),
    // A box of half extents (r, h) in the (ρ, z) plane.
    rows: |v, _| Rows { form: FORM_REVOLVED, row: [v[0], 0.0, v[1], 0.0] },
    wgsl: None,
    expand: |b, v| {
        let [x, y, z] = b.xyz()?;
        let radial = b.length(&[x, y])?;
        let dx = b.sub(radial, v[0])?;
        let az = b.f1(Func1::Abs, z)?;
        let dz = b.sub(az, v[1])?;
        b.capped(dx, dz)
    },
};

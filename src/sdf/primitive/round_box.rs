//! `roundbox(bx, by, bz, r)`: box(b − r) − r, the same extents with edges
//! rounded by r (0 ≤ r ≤ min(b)), exact.

use super::{box_distance, positive3, vec3, Bound, Field, Lipschitz, PrimitiveType, Rows, FORM_BOX};
use crate::sdf::{Arity, Form, Info};
use glam::DVec3;

/// The rounded box.
pub static ROUND_BOX: PrimitiveType = PrimitiveType {
    info: Info {
        name: "roundbox",
        form: Form::Primitive(&ROUND_BOX),
        arity: Arity::Exactly(4),
        signature: "roundbox(bx, by, bz, r)",
        doc: "box(b - r) - r: same extents, edges rounded by r; exact, L = 1",
    },
    scene_name: "round_box",
    code: 3,
    fields: &[Field::extents("half"), Field::number("radius")],
    check: |v| {
        positive3("half", &v[..3])?;
        let smallest = v[0].min(v[1]).min(v[2]);
        if !(v[3] >= 0.0 && v[3] <= smallest) {
            return Err(("radius".into(), format!("must be >= 0 and <= the smallest half extent ({smallest})")));
        }
        Ok(())
    },
    distance: |v, q| box_distance(q, vec3(v, 0) - DVec3::splat(v[3])) - v[3],
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Box([v[0], v[1], v[2]]),
    rows: |v, _| Rows { form: FORM_BOX, row: [v[0] - v[3], v[1] - v[3], v[2] - v[3], v[3]] },
    wgsl: None,
    expand: |b, v| {
        let p = b.xyz()?;
        let mut inner = [0; 3];
        for k in 0..3 {
            inner[k] = b.sub(v[k], v[3])?;
        }
        let d = b.boxd(&p, &inner)?;
        b.sub(d, v[3])
    },
};

//! `maxbox(bx, by, bz)`: max(|x| − bx, |y| − by, |z| − bz), the distance to
//! the box of half extents b in the max norm: the box's exact distance
//! inside and on the faces' slabs, a bound of it outside, and 1-Lipschitz.
//! It is how programs often write a box, so a formula that writes its boxes
//! so lowers to a scene with the same field. Its sublevel set {f ≤ r} is
//! the box of half extents b + r.

use super::{positive3, vec3, Bound, Field, Lipschitz, PrimitiveType, Rows, WgslCase};
use crate::ir::Func1;
use crate::sdf::{Arity, Form, Info};

const FORM_MAX_BOX: u32 = 10;
const FEATURE_MAX_BOX: u32 = 1 << 14;

/// The box in the max norm.
pub static MAX_BOX: PrimitiveType = PrimitiveType {
    info: Info {
        name: "maxbox",
        form: Form::Primitive(&MAX_BOX),
        arity: Arity::Exactly(3),
        signature: "maxbox(bx, by, bz)",
        doc: "max(|x| - bx, |y| - by, |z| - bz): a box's distance in the max norm (exact inside); L = 1",
    },
    scene_name: "max_box",
    code: 15,
    fields: &[Field::extents("half")],
    check: |v| positive3("half", v),
    distance: |v, q| {
        let a = q.abs() - vec3(v, 0);
        a.x.max(a.y).max(a.z)
    },
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Box([v[0], v[1], v[2]]),
    rows: |v, _| Rows { form: FORM_MAX_BOX, row: [v[0], v[1], v[2], 0.0] },
    wgsl: Some(WgslCase {
        form: FORM_MAX_BOX,
        feature: FEATURE_MAX_BOX,
        code: "        // r2 = (bx, by, bz, 0) (src/sdf/primitive/max_box.rs).
        let am = abs(q) - r2.xyz;
        d = select(d, max(am.x, max(am.y, am.z)), form == FORM_MAX_BOX);
",
        enclosure: None,
    }),
    expand: |b, v| {
        let p = b.xyz()?;
        let mut d = p;
        for k in 0..3 {
            let a = b.f1(Func1::Abs, p[k])?;
            d[k] = b.sub(a, v[k])?;
        }
        let m = b.max(d[0], d[1])?;
        b.max(m, d[2])
    },
};

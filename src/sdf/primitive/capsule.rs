//! `capsule(ax, ay, az, bx, by, bz, r)`: the segment a–b thickened by r,
//! exact (a sphere around a when a = b).

use super::{positive, vec3, Bound, Field, Lipschitz, PrimitiveType, Rows, FORM_BOX};
use crate::sdf::{Arity, Form, Info};
use glam::DVec3;

/// The capsule.
pub static CAPSULE: PrimitiveType = PrimitiveType {
    info: Info {
        name: "capsule",
        form: Form::Primitive(&CAPSULE),
        arity: Arity::Exactly(7),
        signature: "capsule(ax, ay, az, bx, by, bz, r)",
        doc: "segment a-b thickened by r; exact, L = 1",
    },
    scene_name: "capsule",
    code: 4,
    fields: &[Field::point("a"), Field::point("b"), Field::number("radius")],
    check: |v| positive("radius", v[6]),
    distance: |v, q| segment_distance(q, vec3(v, 0), vec3(v, 3)) - v[6],
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Capsule { a: [v[0], v[1], v[2]], b: [v[3], v[4], v[5]], radius: v[6], allowance: 0.0 },
    rows,
    wgsl: None,
    expand: |b, v| {
        let p = b.xyz()?;
        let mut pa = [0; 3];
        let mut ba = [0; 3];
        for k in 0..3 {
            pa[k] = b.sub(p[k], v[k])?;
            ba[k] = b.sub(v[3 + k], v[k])?;
        }
        // a = b is a sphere around a.
        let w = b.segment_offset(&pa, &ba)?;
        let along = b.length(&w)?;
        b.sub(along, v[6])
    },
};

/// Distance to the segment a–b (to a when a = b), as the formula's
/// `segment_offset`.
fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let pa = p - a;
    let ba = b - a;
    let bb = ba.dot(ba);
    if bb == 0.0 {
        return pa.length();
    }
    let h = (pa.dot(ba) / bb).max(0.0).min(1.0);
    (pa - ba * h).length()
}

/// A rounded box in a frame of the segment's own: centred on it, z along
/// it, right-handed (the frame stays a rotation), composed into the
/// primitive's matrix.
fn rows(v: &[f64], m: &mut [[f64; 4]; 3]) -> Rows {
    let (a, b) = (vec3(v, 0), vec3(v, 3));
    let (c, len) = ((a + b) * 0.5, (b - a).length());
    let u = if len > 0.0 { (b - a) / len } else { DVec3::Z };
    let (e1, e2) = u.any_orthonormal_pair();
    let e1 = if e1.cross(e2).dot(u) < 0.0 { -e1 } else { e1 };
    let old = *m;
    *m = [e1, e2, u].map(|e| {
        let row = |j: usize| e.x * old[0][j] + e.y * old[1][j] + e.z * old[2][j];
        [row(0), row(1), row(2), row(3) - e.dot(c)]
    });
    Rows { form: FORM_BOX, row: [0.0, 0.0, len * 0.5, v[6]] }
}

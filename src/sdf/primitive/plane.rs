//! `plane(nx, ny, nz, d)`: the half-space n·p ≤ d, n normalised when
//! evaluated, exact. Unbounded: it has no bounding volume, is always
//! active, and cannot be warped.

use super::{vec3, Bound, Field, Lipschitz, PrimitiveType, Rows, FORM_PLANE};
use crate::sdf::{Arity, Form, Info, Sink};

/// The half-space.
pub static PLANE: PrimitiveType = PrimitiveType {
    info: Info { name: "plane", form: Form::Primitive(&PLANE), arity: Arity::Exactly(4), signature: "plane(nx, ny, nz, d)", doc: "half-space n.p <= d, n normalised; exact, L = 1" },
    scene_name: "plane",
    code: 8,
    fields: &[Field::point("normal"), Field::number("offset")],
    check: |v| if vec3(v, 0).length() > 0.0 { Ok(()) } else { Err(("normal".into(), "must not be zero".into())) },
    distance: |v, q| {
        let n = vec3(v, 0);
        n.dot(q) / n.length() - v[3]
    },
    lipschitz: Lipschitz::One,
    bound: |_| Bound::Unbounded,
    rows,
    wgsl: None,
    expand: |b, v| {
        let p = b.xyz()?;
        let n = [v[0], v[1], v[2]];
        let len = b.length(&n)?;
        if b.0.konst(len) == Some(0.0) {
            return Err(b.0.bad_argument(0, "the plane's normal (nx, ny, nz) must not be zero".into()));
        }
        let np = b.dot(&n, &p)?;
        let np = if b.is(len, 1.0) { np } else { b.div(np, len)? };
        b.sub(np, v[3])
    },
};

/// (n/|n|, 0): n·q − offset is n·q' with the origin moved by offset along
/// n (m's last column is the local point of the world origin).
fn rows(v: &[f64], m: &mut [[f64; 4]; 3]) -> Rows {
    let n = vec3(v, 0) / vec3(v, 0).length();
    for (r, nk) in m.iter_mut().zip(n.to_array()) {
        r[3] -= v[3] * nk;
    }
    Rows { form: FORM_PLANE, row: [n.x, n.y, n.z, 0.0] }
}

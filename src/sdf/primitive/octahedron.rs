//! `octahedron(s)`: the bound (|x| + |y| + |z| − s)/√3 of the octahedron
//! |x| + |y| + |z| ≤ s, exact on the faces and 1-Lipschitz. Its sublevel
//! set {f ≤ r} is the octahedron of size s + √3·r, within the ball of that
//! radius.

use super::{positive, Bound, Field, Lipschitz, PrimitiveType, Rows, FORM_OCTAHEDRON};
use crate::ir::Func1;
use crate::sdf::{Arity, Form, Info};

/// The octahedron.
pub static OCTAHEDRON: PrimitiveType = PrimitiveType {
    info: Info {
        name: "octahedron",
        form: Form::Primitive(&OCTAHEDRON),
        arity: Arity::Exactly(1),
        signature: "octahedron(s)",
        doc: "(|x| + |y| + |z| - s)/sqrt(3); a bound (exact on the faces), L = 1",
    },
    scene_name: "octahedron",
    code: 7,
    fields: &[Field::number("size")],
    check: |v| positive("size", v[0]),
    distance: |v, q| (q.x.abs() + q.y.abs() + q.z.abs() - v[0]) * (1.0 / 3f64.sqrt()),
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Ball { radius: v[0], slope: 3f64.sqrt() },
    rows: |v, _| Rows { form: FORM_OCTAHEDRON, row: [v[0], 0.0, 0.0, 0.0] },
    wgsl: None,
    expand: |b, v| {
        let p = b.xyz()?;
        let mut s = b.f1(Func1::Abs, p[0])?;
        for &c in &p[1..] {
            let a = b.f1(Func1::Abs, c)?;
            s = b.add(s, a)?;
        }
        let d = b.sub(s, v[0])?;
        let k = b.c(1.0 / 3f64.sqrt())?;
        b.mul(d, k)
    },
};

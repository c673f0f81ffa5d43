//! The 3D primitives: `sphere`, `box`, `roundbox`, `torus`, `cylinder`,
//! `capsule`, `plane` and `octahedron`, each an exact distance but the
//! octahedron (a bound, exact on the faces).

use super::{Form, Sink, B};
use crate::ir::{Func1, NodeId};

/// Expands a primitive (`v`: the lowered arguments).
pub(super) fn lower<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    match form {
        Form::Sphere => {
            let p = b.xyz()?;
            let l = b.length(&p)?;
            b.sub(l, v[0])
        }
        Form::Box => {
            let p = b.xyz()?;
            b.boxd(&p, &v[..3])
        }
        Form::RoundBox => {
            let p = b.xyz()?;
            let mut inner = [0; 3];
            for k in 0..3 {
                inner[k] = b.sub(v[k], v[3])?;
            }
            let d = b.boxd(&p, &inner)?;
            b.sub(d, v[3])
        }
        Form::Torus => {
            let [x, y, z] = b.xyz()?;
            let ring = b.length(&[x, y])?;
            let q = b.sub(ring, v[0])?;
            let l = b.length(&[q, z])?;
            b.sub(l, v[1])
        }
        Form::Cylinder => {
            let [x, y, z] = b.xyz()?;
            let radial = b.length(&[x, y])?;
            let dx = b.sub(radial, v[0])?;
            let az = b.f1(Func1::Abs, z)?;
            let dz = b.sub(az, v[1])?;
            b.capped(dx, dz)
        }
        Form::Capsule => {
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
        }
        Form::Plane => {
            let p = b.xyz()?;
            let n = [v[0], v[1], v[2]];
            let len = b.length(&n)?;
            if b.0.konst(len) == Some(0.0) {
                return Err(b.0.bad_argument(0, "the plane's normal (nx, ny, nz) must not be zero".into()));
            }
            let np = b.dot(&n, &p)?;
            let np = if b.is(len, 1.0) { np } else { b.div(np, len)? };
            b.sub(np, v[3])
        }
        Form::Octahedron => {
            let p = b.xyz()?;
            let mut s = b.f1(Func1::Abs, p[0])?;
            for &c in &p[1..] {
                let a = b.f1(Func1::Abs, c)?;
                s = b.add(s, a)?;
            }
            let d = b.sub(s, v[0])?;
            let k = b.c(1.0 / 3f64.sqrt())?;
            b.mul(d, k)
        }
        _ => unreachable!("{form:?} is not a primitive"),
    }
}

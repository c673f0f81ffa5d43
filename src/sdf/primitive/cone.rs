//! `cone(r, h[, rt])`: the capped cone (a frustum) along the local z axis,
//! radius r at z = −h, rt (default 0: a pointed cone) at z = +h, exact.
//!
//! In the half-plane (ρ, z), ρ = |q.xy|, the solid is the trapezoid
//! (0, ±h), (r, −h), (rt, h), and the nearest surface point of a solid of
//! revolution lies in the point's own half-plane: the distance is the
//! nearest of the bottom disc, the top disc and the slanted side (Quilez's
//! exact capped cone, with both discs measured rather than one picked by
//! the sign of z, so that no comparison selects a value), negative inside:
//! where |z| ≤ h and the point is on the axis's side of the slanted line
//! (n·w ≤ 0 with w = (ρ − r, z + h) and n = (2h, r − rt) pointing out).
//! An exact distance: L = 1.

use super::{hypot, non_negative, positive, Bound, Field, Lipschitz, PrimitiveType, Rows, WgslCase};
use crate::ir::{Func1, Func3, NodeId, Op};
use crate::sdf::{Arity, Form, Info, Sink};

const FORM_CONE: u32 = 8;
const FEATURE_CONE: u32 = 1 << 10;

/// The capped cone.
pub static CONE: PrimitiveType = PrimitiveType {
    info: Info {
        name: "cone",
        form: Form::Primitive(&CONE),
        arity: Arity::Between(2, 3),
        signature: "cone(r, h[, rt])",
        doc: "capped cone along z, radius r at z = -h, rt (default 0: pointed) at z = h; r > 0, h > 0, rt >= 0; exact, L = 1",
    },
    scene_name: "cone",
    code: 13,
    fields: &[Field::number("radius"), Field::number("half_height"), Field::number("top_radius").or(0.0)],
    check: |v| {
        positive("radius", v[0])?;
        positive("half_height", v[1])?;
        non_negative("top_radius", v[2])
    },
    distance,
    lipschitz: Lipschitz::One,
    bound: |v| Bound::Box([v[0].max(v[2]), v[0].max(v[2]), v[1]]),
    rows: |v, _| Rows { form: FORM_CONE, row: [v[0], v[2], v[1], 0.0] },
    wgsl: Some(WgslCase {
        form: FORM_CONE,
        feature: FEATURE_CONE,
        code: "        // r2 = (r, rt, h, 0) (src/sdf/primitive/cone.rs): the nearest of the
        // two discs and the slanted side, negative inside.
        let rho = length(q.xy);
        let cw = vec2<f32>(rho - r2.x, q.z + r2.z);
        let ce = vec2<f32>(r2.y - r2.x, 2.0 * r2.z);
        let bottom = vec2<f32>(max(cw.x, 0.0), cw.y);
        let top = vec2<f32>(max(rho - r2.y, 0.0), q.z - r2.z);
        let side = cw - ce * clamp(dot(cw, ce) / dot(ce, ce), 0.0, 1.0);
        let outside = max(abs(q.z) - r2.z, ce.y * cw.x - ce.x * cw.y);
        let dc = sign(outside) * sqrt(min(min(dot(bottom, bottom), dot(top, top)), dot(side, side)));
        d = select(d, dc, form == FORM_CONE);
",
        enclosure: None,
    }),
    expand,
};

/// The local field, in the expansion's order of operations.
fn distance(v: &[f64], q: glam::DVec3) -> f64 {
    let (r, h, rt) = (v[0], v[1], v[2]);
    let rho = hypot(q.x, q.y);
    let (wx, wz) = (rho - r, q.z + h);
    let bx = wx.max(0.0);
    let bottom = bx * bx + wz * wz;
    let (tx, tz) = ((rho - rt).max(0.0), q.z - h);
    let top = tx * tx + tz * tz;
    let (ex, ez) = (rt - r, 2.0 * h);
    let t = ((wx * ex + wz * ez) / (ex * ex + ez * ez)).clamp(0.0, 1.0);
    let (sx, sz) = (wx - ex * t, wz - ez * t);
    let side = sx * sx + sz * sz;
    let out = (q.z.abs() - h).max(ez * wx - ex * wz);
    sign(out) * bottom.min(top).min(side).sqrt()
}

/// The formula language's `sign`: 0 at 0.
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

fn expand(b: &mut super::Ir<'_, '_>, v: &[NodeId]) -> Result<NodeId, super::Stopped> {
    b.positive(v, 0, "the base radius r")?;
    b.positive(v, 1, "the half height h")?;
    let (r, h) = (v[0], v[1]);
    let rt = match v.get(2) {
        Some(&rt) => {
            b.non_negative(v, 2, "the top radius rt")?;
            rt
        }
        None => b.c(0.0)?,
    };
    let [x, y, z] = b.xyz()?;
    let zero = b.c(0.0)?;
    let rho = b.length(&[x, y])?;
    let wx = b.sub(rho, r)?;
    let wz = b.add(z, h)?;
    let bx = b.max(wx, zero)?;
    let bottom = sum_of_squares(b, bx, wz)?;
    let tx = b.sub(rho, rt)?;
    let tx = b.max(tx, zero)?;
    let tz = b.sub(z, h)?;
    let top = sum_of_squares(b, tx, tz)?;
    let ex = b.sub(rt, r)?;
    let two = b.c(2.0)?;
    let ez = b.mul(two, h)?;
    let a1 = b.mul(wx, ex)?;
    let a2 = b.mul(wz, ez)?;
    let along = b.add(a1, a2)?;
    let ee = sum_of_squares(b, ex, ez)?;
    let t = b.div(along, ee)?;
    let one = b.c(1.0)?;
    let t = b.0.push(Op::Call3(Func3::Clamp, t, zero, one))?;
    let ext = b.mul(ex, t)?;
    let sx = b.sub(wx, ext)?;
    let ezt = b.mul(ez, t)?;
    let sz = b.sub(wz, ezt)?;
    let side = sum_of_squares(b, sx, sz)?;
    let az = b.f1(Func1::Abs, z)?;
    let cap = b.sub(az, h)?;
    let n1 = b.mul(ez, wx)?;
    let n2 = b.mul(ex, wz)?;
    let slant = b.sub(n1, n2)?;
    let out = b.max(cap, slant)?;
    let near = b.min(bottom, top)?;
    let near = b.min(near, side)?;
    let dist = b.f1(Func1::Sqrt, near)?;
    let s = b.f1(Func1::Sign, out)?;
    b.mul(s, dist)
}

/// a² + b².
fn sum_of_squares(b: &mut super::Ir<'_, '_>, x: NodeId, y: NodeId) -> Result<NodeId, super::Stopped> {
    let xx = b.sqr(x)?;
    let yy = b.sqr(y)?;
    b.add(xx, yy)
}

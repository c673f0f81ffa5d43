//! `infill(period, thickness, shape)`: max(shape, g) with g a gyroid sheet
//! at least `thickness` thick, clipped by the operand (Zanni et al. 2024,
//! Fig. 17's heat exchanger): g = |G(k p)| / (k√6) − thickness/2,
//! k = 2π/period, G the gyroid sin x cos y + sin y cos z + sin z cos x
//! (summed left to right).
//!
//! Each partial derivative of G is k times a difference of two products
//! like cos(q.x)cos(q.y) − sin(q.z)sin(q.x), at most √2 by Cauchy–Schwarz,
//! so |∇G| ≤ k√6: g is 1-Lipschitz, and since G = 0 on the gyroid, g ≤ 0
//! within thickness/2 of it: the sheet is at least `thickness` thick. On
//! the gyroid |∇G| is between k√2 and k√3 (by sampling), so in fact the
//! sheet is about 1.4 to 1.7 times as thick. The node keeps its operand's
//! bound and range of interest (a sharp intersection with a field that is
//! not a primitive); the gyroid is fixed in the world.

use super::{positive, UnaryCase, UnaryType};
use crate::ir::{Func1, NodeId};
use crate::sdf::{Arity, Form, Info};
use glam::DVec3;

/// Feature bit of the interpreter: gyroid infill.
pub const FEATURE_INFILL: u32 = 8;

/// The gyroid infill.
pub static INFILL: UnaryType = UnaryType {
    info: Info {
        name: "infill",
        form: Form::Unary(&INFILL),
        arity: Arity::Exactly(3),
        signature: "infill(period, thickness, shape)",
        doc: "max(shape, |G|/(k sqrt 6) - thickness/2), G = sin(kx) cos(ky) + sin(ky) cos(kz) + sin(kz) cos(kx), k = 2 pi/period: the shape cut to a gyroid sheet at least thickness thick; L = max(the shape's, 1)",
    },
    code: 50,
    fields: &["period", "thickness"],
    check: |v| positive("period", v[0]).and(positive("thickness", v[1])),
    apply: |v, f, p| f.max(gyroid_sheet(DVec3::from(p), v[0], v[1])),
    operand_range: |_, lo, hi| (lo, hi),
    operand_level: |_, l| Some(l),
    lipschitz_increase: |_| 0.0,
    moved: None,
    row: |v| {
        let k = std::f64::consts::TAU / v[0];
        [k, 0.5 * v[1], 1.0 / (k * 6f64.sqrt()), 0.0]
    },
    wgsl: UnaryCase {
        feature: FEATURE_INFILL,
        code: "        // k = (2 pi/period, thickness/2, 1/(k sqrt 6), 0) (src/sdf/unary/infill.rs).
        let q = p * k.x;
        let g = sin(q.x) * cos(q.y) + sin(q.y) * cos(q.z) + sin(q.z) * cos(q.x);
        r = select(r, max(v, abs(g) * k.z - k.y), ty == NODE_INFILL);
",
        // The gyroid over the box by interval sines and cosines (k.x > 0).
        enclosure: "        let lo = scene_lo(b) * k.x;
        let hi = scene_hi(b) * k.x;
        let gx = vec2<f32>(lo.x, hi.x);
        let gy = vec2<f32>(lo.y, hi.y);
        let gz = vec2<f32>(lo.z, hi.z);
        let g = ia_mul(ia_sin(gx), ia_cos(gy)) + ia_mul(ia_sin(gy), ia_cos(gz)) + ia_mul(ia_sin(gz), ia_cos(gx));
        r = select(r, max(v, ia_pad(ia_abs(g) * k.z - k.y, 1e-6, 1e-6)), ty == NODE_INFILL);
",
    },
    expand,
};

/// The gyroid sheet g of the module doc at `p`.
pub fn gyroid_sheet(p: DVec3, period: f64, thickness: f64) -> f64 {
    let k = std::f64::consts::TAU / period;
    let q = p * k;
    let g = q.x.sin() * q.y.cos() + q.y.sin() * q.z.cos() + q.z.sin() * q.x.cos();
    g.abs() / (k * 6f64.sqrt()) - 0.5 * thickness
}

fn expand(b: &mut crate::sdf::primitive::Ir<'_, '_>, v: &[NodeId]) -> Result<NodeId, crate::sdf::primitive::Stopped> {
    // Checked before k = 2π/period is built: a constant 0 would fold to ∞.
    b.positive(v, 0, "the period")?;
    b.positive(v, 1, "the sheet thickness")?;
    let tau = b.c(std::f64::consts::TAU)?;
    let k = b.div(tau, v[0])?;
    let p = b.xyz()?;
    let mut sin = [0; 3];
    let mut cos = [0; 3];
    for i in 0..3 {
        let q = b.mul(k, p[i])?;
        sin[i] = b.f1(Func1::Sin, q)?;
        cos[i] = b.f1(Func1::Cos, q)?;
    }
    let mut g = b.mul(sin[0], cos[1])?;
    for i in 1..3 {
        let t = b.mul(sin[i], cos[(i + 1) % 3])?;
        g = b.add(g, t)?;
    }
    let g = b.f1(Func1::Abs, g)?;
    let root6 = b.c(6f64.sqrt())?;
    let den = b.mul(k, root6)?;
    let g = b.div(g, den)?;
    let two = b.c(2.0)?;
    let half = b.div(v[1], two)?;
    let g = b.sub(g, half)?;
    b.max(v[2], g)
}

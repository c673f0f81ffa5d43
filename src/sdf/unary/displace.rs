//! `displace(a, f, shape)`: shape + a·n(p) with the fixed pseudo-noise n
//! of [`noise`], |n| ≤ 1, |∇n| ≤ [`NOISE_GRADIENT`]·f: the node adds
//! a·f·NOISE_GRADIENT to its operand's Lipschitz bound, and its operand's
//! range of interest is the node's widened by a. The noise is fixed in the
//! world.
//!
//! The noise is a constant table here, [`NOISE_WAVES`], with an f64
//! [`noise`] in the lowered form's order of operations, so a blobtree
//! scene's displacement is the very same function (and the interpreter's
//! `scene_noise` is written from the same table, `scene::codes`).

use super::{positive, UnaryCase, UnaryType};
use crate::ir::{Func1, NodeId};
use crate::sdf::{Arity, Form, Info};

/// Feature bit of the interpreter: noise displacement.
pub const FEATURE_DISPLACE: u32 = 16;

/// The displacement.
pub static DISPLACE: UnaryType = UnaryType {
    info: Info {
        name: "displace",
        form: Form::Unary(&DISPLACE),
        arity: Arity::Exactly(3),
        signature: "displace(a, f, shape)",
        doc: "shape + a n(p), a >= 0, f > 0, n = sum of w_k sin(f m_k (a_k.p) + phi_k) (sdf::NOISE_WAVES), |n| <= 1; L = the shape's + 1.92 a f: give --lipschitz",
    },
    code: 51,
    fields: &["amplitude", "frequency"],
    check: |v| {
        if !(v[0] >= 0.0) {
            return Err(("amplitude".into(), "must be >= 0".into()));
        }
        positive("frequency", v[1])
    },
    apply: |v, f, p| f + v[0] * noise(p, v[1]),
    operand_range: |v, lo, hi| (lo - v[0], hi + v[0]),
    operand_level: |v, l| Some(l - v[0]),
    lipschitz_increase: |v| v[0] * v[1] * NOISE_GRADIENT,
    moved: None,
    row: |v| [v[0], v[1], 0.0, 0.0],
    wgsl: UnaryCase {
        feature: FEATURE_DISPLACE,
        code: "        r = select(r, v + k.x * scene_noise(p, k.y), ty == NODE_DISPLACE);\n",
        // a >= 0: the noise's range scaled keeps its order.
        enclosure: "        r = select(r, v + k.x * scene_noise_ia(b, k.y), ty == NODE_DISPLACE);\n",
    },
    expand,
};

/// The waves of [`noise`], each (unit direction a_k, frequency multiplier
/// m_k, weight w_k, phase φ_k). The weights sum to 1, so |n| ≤ 1; the
/// multipliers are far from small integer ratios and the directions
/// differ, so the sum does not repeat along a short period in any
/// direction.
pub const NOISE_WAVES: [([f64; 3], f64, f64, f64); 4] = [
    ([0.6, 0.8, 0.0], 1.0, 0.4, 0.0),
    ([0.0, 0.6, 0.8], 1.7, 0.3, 1.3),
    ([0.8, 0.0, 0.6], 2.9, 0.2, 2.1),
    ([0.48, 0.64, 0.6], 4.3, 0.1, 4.2),
];

/// Σ w_k·m_k over [`NOISE_WAVES`]: the directions are unit vectors, so
/// |∇n| ≤ `NOISE_GRADIENT`·f, and `displace(a, f, s)` raises the
/// Lipschitz bound of `s` by `NOISE_GRADIENT`·a·f.
pub const NOISE_GRADIENT: f64 = 1.92;

/// The pseudo-noise of `displace` at frequency `f`: n(p) =
/// Σ_k w_k·sin((f·m_k)·(a_k·p) + φ_k), in the order the formula computes
/// it: a_k·p = (a.x·x + a.y·y) + a.z·z, the terms summed from k = 0 on.
pub fn noise(p: [f64; 3], f: f64) -> f64 {
    let wave = |k: usize| {
        let (a, m, w, phase) = NOISE_WAVES[k];
        let along = a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
        w * ((f * m) * along + phase).sin()
    };
    wave(0) + wave(1) + wave(2) + wave(3)
}

/// shape + a·n(p), n as in [`noise`].
fn expand(b: &mut crate::sdf::primitive::Ir<'_, '_>, v: &[NodeId]) -> Result<NodeId, crate::sdf::primitive::Stopped> {
    b.non_negative(v, 0, "the amplitude a")?;
    b.positive(v, 1, "the frequency f")?;
    let p = b.xyz()?;
    let mut n = None;
    for (a, m, w, phase) in NOISE_WAVES {
        let m = b.c(m)?;
        let fm = b.mul(v[1], m)?;
        let a = [b.c(a[0])?, b.c(a[1])?, b.c(a[2])?];
        let along = b.dot(&a, &p)?;
        let arg = b.mul(fm, along)?;
        let phase = b.c(phase)?;
        let arg = b.add(arg, phase)?;
        let sin = b.f1(Func1::Sin, arg)?;
        let w = b.c(w)?;
        let t = b.mul(w, sin)?;
        n = Some(match n {
            None => t,
            Some(acc) => b.add(acc, t)?,
        });
    }
    let an = b.mul(v[0], n.expect("four waves"))?;
    b.add(v[2], an)
}

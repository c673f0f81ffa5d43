//! Modifiers of any shape: `offset`, `shell`, `infill` (a gyroid sheet
//! lattice) and `displace` (a fixed pseudo-noise).
//!
//! The noise is a constant table here, [`NOISE_WAVES`], with an f64
//! [`noise`] in the lowered form's order of operations, so a blobtree
//! scene's displacement is the very same function.

use super::{Form, Sink, B};
use crate::ir::{Func1, NodeId};

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

/// Expands `offset`, `shell`, `infill` or `displace` (`v`: the lowered
/// arguments, the shape last).
pub(super) fn lower<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    match form {
        // shape − d: the level set d of the shape, gradient unchanged.
        Form::Offset => b.sub(v[1], v[0]),
        // |shape| − t/2: |·| keeps the gradient's length, so the bound too.
        Form::Shell => {
            b.positive(v, 0, "the wall thickness t")?;
            let a = b.f1(Func1::Abs, v[1])?;
            let two = b.c(2.0)?;
            let half = b.div(v[0], two)?;
            b.sub(a, half)
        }
        Form::Infill => infill(b, v),
        // shape + a·n(p), n as in [`noise`].
        Form::Displace => {
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
        _ => unreachable!("{form:?} is not a modifier"),
    }
}

/// max(shape, g), g = |G|/(k·√6) − thickness/2 with k = 2π/period, q = k·p
/// and the gyroid G = sin(q.x)cos(q.y) + sin(q.y)cos(q.z) + sin(q.z)cos(q.x)
/// (summed left to right). Each partial derivative of G is k times a
/// difference of two products like cos(q.x)cos(q.y) − sin(q.z)sin(q.x),
/// at most √2 by Cauchy–Schwarz, so |∇G| ≤ k√6: g is 1-Lipschitz, and
/// since G = 0 on the gyroid, g ≤ 0 within thickness/2 of it: the sheet is
/// at least `thickness` thick. On the gyroid |∇G| is between k√2 and k√3
/// (by sampling), so in fact the sheet is about 1.4 to 1.7 times as thick.
fn infill<S: Sink>(b: &mut B<'_, S>, v: &[NodeId]) -> Result<NodeId, S::Error> {
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

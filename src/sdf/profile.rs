//! The 2D profiles (`circle`, `rect`, `roundrect`, `capsule2d`, `polygon`)
//! and the forms that make solids of them (`extrude`, `revolve`).
//!
//! A profile is a field of x and y alone. As a 3D field it is the exact
//! distance to an infinite prism along z (a profile's gradient has no z
//! part, so its length is the 2D one, 1), which is why no form of its own
//! is needed for "2D": `extrude` uses the profile's value at the same
//! point and `revolve` evaluates it at (distance from the z axis − R, z).
//! Both maps are 1-Lipschitz in p, so the solids keep the profile's bound.

use super::{Form, Sink, B};
use crate::ir::{Func1, NodeId, Var};

/// Expands a profile, `extrude` or `revolve` (`v`: the lowered arguments).
pub(super) fn lower<S: Sink>(b: &mut B<'_, S>, form: Form, v: &[NodeId]) -> Result<NodeId, S::Error> {
    match form {
        Form::Circle => {
            b.positive(v, 0, "the radius r")?;
            let u = [b.var(Var::X)?, b.var(Var::Y)?];
            let l = b.length(&u)?;
            b.sub(l, v[0])
        }
        // The 2D case of `box`'s expansion.
        Form::Rect => {
            let u = [b.var(Var::X)?, b.var(Var::Y)?];
            b.boxd(&u, &v[..2])
        }
        Form::RoundRect => {
            let u = [b.var(Var::X)?, b.var(Var::Y)?];
            let inner = [b.sub(v[0], v[2])?, b.sub(v[1], v[2])?];
            let d = b.boxd(&u, &inner)?;
            b.sub(d, v[2])
        }
        // The 2D case of `capsule`'s expansion, with its a = b guards.
        Form::Capsule2d => {
            let u = [b.var(Var::X)?, b.var(Var::Y)?];
            let pa = [b.sub(u[0], v[0])?, b.sub(u[1], v[1])?];
            let ba = [b.sub(v[2], v[0])?, b.sub(v[3], v[1])?];
            let w = b.segment_offset(&pa, &ba)?;
            let l = b.length(&w)?;
            b.sub(l, v[4])
        }
        Form::Polygon => polygon(b, v),
        // With w = (shape, |z| − h): min(max(w.x, w.y), 0) + length(max(w, 0)),
        // the capped cylinder's formula with the profile in place of
        // |(x, y)| − r. Exact when the shape is an exact 2D distance.
        Form::Extrude => {
            b.positive(v, 0, "the half height h")?;
            let z = b.var(Var::Z)?;
            let az = b.f1(Func1::Abs, z)?;
            let dz = b.sub(az, v[0])?;
            b.capped(v[1], dz)
        }
        // The shape at x' = sqrt(x² + y²) − R, y' = z, z' = 0: the profile
        // drawn in a half plane through the axis, at distance R from it.
        // Exact for an exact 2D distance whose shape stays in x' ≥ −R (does
        // not cross the axis); a shape that crosses it is a bound.
        Form::Revolve => {
            b.non_negative(v, 0, "the distance R from the axis")?;
            let [x, y, z] = b.xyz()?;
            let radial = b.length(&[x, y])?;
            let u = b.sub(radial, v[0])?;
            let zero = b.c(0.0)?;
            b.0.substitute(v[1], [u, z, zero])
        }
        _ => unreachable!("{form:?} is not a profile form"),
    }
}

/// step(a) = (1 + sign(a))/2: 1 for a > 0, 0 for a < 0 and ½ at a = 0.
/// The IR has no comparison; this is the one a scene's polygon must use
/// too, so both agree even on the measure-zero set where a = 0.
fn step<S: Sink>(b: &mut B<'_, S>, a: NodeId) -> Result<NodeId, S::Error> {
    let s = b.f1(Func1::Sign, a)?;
    let one = b.c(1.0)?;
    let t = b.add(one, s)?;
    let two = b.c(2.0)?;
    b.div(t, two)
}

/// Quilez's sdPolygon for the vertices `v` = (x0, y0, x1, y1, …), in this
/// order of operations: d = dot(u − v0, u − v0); for each edge i (from
/// v_j = v[i − 1], cyclically, to v_i), e = v_j − v_i, w = u − v_i,
/// b = w − e·clamp(dot(w, e)/dot(e, e), 0, 1), d = min(d, dot(b, b)) and,
/// with c1 = step(u.y − v_i.y), c2 = step(v_j.y − u.y),
/// c3 = step(e.x·w.y − e.y·w.x), flip = c1c2c3 + (1 − c1)(1 − c2)(1 − c3),
/// s = s·(1 − 2 flip) from s = 1; the value is s·sqrt(d).
///
/// flip is 1 when the ray from u towards +x crosses edge i (the crossing
/// rule of a point-in-polygon test), so s = −1 inside. Where a step is at
/// its ½: c3 = ½ changes flip only when c1 = c2, i.e. for u on the edge
/// itself, where d = 0 and the value is 0 as it should be; c1 or c2 = ½
/// (u.y equal to a vertex's y, a set of measure zero) makes that edge's
/// factor 0 or ½ where sdPolygon has −1 or 1 (0 for −1 and for 1, ½ for 1).
/// So there the value is the exact one scaled by 1, a power of ½ or 0:
/// never of the wrong sign, never larger than the distance (sphere
/// tracing cannot overstep); everywhere else it is exact.
fn polygon<S: Sink>(b: &mut B<'_, S>, v: &[NodeId]) -> Result<NodeId, S::Error> {
    let n = v.len() / 2;
    let vertex = |i: usize| [v[2 * i], v[2 * i + 1]];
    let u = [b.var(Var::X)?, b.var(Var::Y)?];
    let w0 = [b.sub(u[0], v[0])?, b.sub(u[1], v[1])?];
    let mut d = b.dot(&w0, &w0)?;
    let (one, two) = (b.c(1.0)?, b.c(2.0)?);
    let mut s = one;
    for i in 0..n {
        let (vi, vj) = (vertex(i), vertex((i + n - 1) % n));
        let e = [b.sub(vj[0], vi[0])?, b.sub(vj[1], vi[1])?];
        let w = [b.sub(u[0], vi[0])?, b.sub(u[1], vi[1])?];
        // A repeated vertex (e = 0) is a distance to that vertex.
        let off = b.segment_offset(&w, &e)?;
        let dd = b.dot(&off, &off)?;
        d = b.min(d, dd)?;
        let a1 = b.sub(u[1], vi[1])?;
        let c1 = step(b, a1)?;
        let a2 = b.sub(vj[1], u[1])?;
        let c2 = step(b, a2)?;
        let (l, r) = (b.mul(e[0], w[1])?, b.mul(e[1], w[0])?);
        let a3 = b.sub(l, r)?;
        let c3 = step(b, a3)?;
        let all = b.mul(c1, c2)?;
        let all = b.mul(all, c3)?;
        let (n1, n2, n3) = (b.sub(one, c1)?, b.sub(one, c2)?, b.sub(one, c3)?);
        let none = b.mul(n1, n2)?;
        let none = b.mul(none, n3)?;
        let flip = b.add(all, none)?;
        let twice = b.mul(two, flip)?;
        let factor = b.sub(one, twice)?;
        s = b.mul(s, factor)?;
    }
    let dist = b.f1(Func1::Sqrt, d)?;
    b.mul(s, dist)
}

//! `polygon(x0, y0, x1, y1, …)`: a closed polygon of 3 to [`MAX_POLYGON`]
//! vertices, even-odd sign (after Quilez's sdPolygon), so the inside of a
//! simple polygon is negative; exact but where y equals a vertex's y.

use super::{plane_point, Field, FieldKind, ProfileType, SegmentBox};
use crate::ir::{Func1, NodeId};
use crate::sdf::primitive::{Invalid, Ir, Stopped};
use crate::sdf::{Arity, Form, Info};
use glam::DVec2;

/// The most vertices of a polygon profile: a GPU record holds two a row,
/// so 16 vertices are 8 rows.
pub const MAX_POLYGON: usize = 16;

/// The polygon.
pub static POLYGON: ProfileType = ProfileType {
    info: Info { name: "polygon", form: Form::Profile(&POLYGON), arity: Arity::Pairs(3, 16), signature: "polygon(x0, y0, x1, y1, ...)", doc: "2D profile: simple closed polygon of 3 to 16 vertices, s * sqrt(min over edges of the squared distance), s = -1 inside (Quilez's sdPolygon); exact except where y equals a vertex's y (there |f| <= the distance), L = 1" },
    scene_name: "polygon",
    fields: &[Field { name: "points", kind: FieldKind::Points }],
    check: |v| check(&pairs(v)),
    distance,
    bounds,
    // Its vertices have rows of their own.
    row: |_| SegmentBox::default(),
    expand: polygon,
};

/// The vertices of the parameters (x0, y0, x1, y1, …).
fn pairs(v: &[f64]) -> Vec<[f64; 2]> {
    v.chunks(2).map(|c| [c[0], c[1]]).collect()
}

/// Checks the vertex count, that no edge has equal ends and that the
/// polygon has an area.
pub(crate) fn check(v: &[[f64; 2]]) -> Result<(), Invalid> {
    let count = v.len();
    if !(3..=MAX_POLYGON).contains(&count) {
        return Err(("points".into(), format!("a polygon has 3 to {MAX_POLYGON} vertices, found {count}")));
    }
    for i in 0..count {
        let j = (i + count - 1) % count;
        if v[i] == v[j] {
            return Err((format!("points[{i}]"), format!("repeats points[{j}]: an edge needs two distinct ends")));
        }
    }
    let area: f64 = (0..count).map(|i| {
        let (p, q) = (v[i], v[(i + 1) % count]);
        p[0] * q[1] - q[0] * p[1]
    }).sum();
    if area == 0.0 {
        return Err(("points".into(), "the polygon has no area".into()));
    }
    Ok(())
}

fn bounds(v: &[f64]) -> ([f64; 2], [f64; 2]) {
    let v = pairs(v);
    let lo = v.iter().fold([f64::INFINITY; 2], |m, p| [m[0].min(p[0]), m[1].min(p[1])]);
    let hi = v.iter().fold([f64::NEG_INFINITY; 2], |m, p| [m[0].max(p[0]), m[1].max(p[1])]);
    (lo, hi)
}

/// Signed distance at `u` to the closed polygon of the vertices `v` =
/// (x0, y0, x1, y1, …), even-odd sign (after Quilez's sdPolygon): the
/// smallest distance to an edge, negated where a ray towards +x crosses
/// the edges an odd number of times.
pub fn distance(v: &[f64], u: DVec2) -> f64 {
    let n = v.len() / 2;
    let vertex = |i: usize| DVec2::new(v[2 * i], v[2 * i + 1]);
    let v0 = vertex(0);
    let mut d = (u - v0).dot(u - v0);
    let mut s = 1.0;
    for i in 0..n {
        let (vi, vj) = (vertex(i), vertex((i + n - 1) % n));
        let (e, w) = (vj - vi, u - vi);
        let b = w - e * (w.dot(e) / e.dot(e)).clamp(0.0, 1.0);
        d = d.min(b.dot(b));
        let c = [u.y >= vi.y, u.y < vj.y, e.x * w.y > e.y * w.x];
        if c.iter().all(|&x| x) || c.iter().all(|&x| !x) {
            s = -s;
        }
    }
    s * d.sqrt()
}
/// step(a) = (1 + sign(a))/2: 1 for a > 0, 0 for a < 0 and ½ at a = 0.
/// The IR has no comparison; this is the one a scene's polygon must use
/// too, so both agree even on the measure-zero set where a = 0.
fn step(b: &mut Ir<'_, '_>, a: NodeId) -> Result<NodeId, Stopped> {
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
fn polygon(b: &mut Ir<'_, '_>, v: &[NodeId]) -> Result<NodeId, Stopped> {
    let n = v.len() / 2;
    let vertex = |i: usize| [v[2 * i], v[2 * i + 1]];
    let u = plane_point(b)?;
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

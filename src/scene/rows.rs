//! The parameter rows of the GPU layout (linear.rs's module doc): each
//! primitive's transform and shape, each unary node's parameters, and the
//! bounding volumes the tile passes test. Written here, read by
//! templates/fields/scene.wgsl and scene_tiles.wgsl.

use super::linear::{ABV_BOX, ABV_CAPSULE, ABV_SPHERE, FORM_BOX, FORM_EXTRUDE, FORM_FORMULA, FORM_GRID, FORM_REVOLVE, FORM_WARP_SHIFT};
use super::roi::Abv;
use super::{Primitive, Profile, Shape, Unary};
use crate::sdf::profile::SegmentBox;
use glam::{DMat3, DQuat, DVec3};

/// A unary node's parameter row, its type's (`crate::sdf::unary`; its
/// type code tells the interpreter which).
pub fn unary_row(op: &Unary) -> [f32; 4] {
    let (t, v) = op.typed();
    (t.row)(&v).map(|x| x as f32)
}

/// A primitive's rows in `params` (the layout of linear.rs's module doc):
/// its frame (two rows), then its parameters. A warped primitive's form
/// says which warp, in bits 4 and 5 (`FORM_WARP_SHIFT`); its warp's rows
/// come before these ([`warp_rows`]).
pub fn primitive_rows(p: &Primitive) -> Vec<[f32; 4]> {
    let mut rows = shape_rows(p);
    if let Some(w) = &p.warp {
        rows[1][3] += ((w.kind as u32) << FORM_WARP_SHIFT) as f32;
    }
    rows
}

/// A warped primitive's rows before its own (`WARP_ROWS` of them): the
/// matrix of A⁻¹ (world to the warp's frame), then (s_A, rate, clamp
/// radius, clamp floor). None for another primitive.
pub fn warp_rows(p: &Primitive) -> Vec<[f32; 4]> {
    let Some(w) = &p.warp else { return Vec::new() };
    let c = w.clamp.expect("a scene's warps are fitted");
    let m = w.frame.matrix();
    let mut rows: Vec<[f32; 4]> = m.iter().map(|r| r.map(|v| v as f32)).collect();
    rows.push([w.frame.scale as f32, w.rate as f32, c.radius as f32, c.floor as f32]);
    rows
}

/// The two frame rows of the local point q = A(p − c)/s given as the
/// matrix m = [A/s | −A·c/s] (A a rotation): the quaternion of A divided
/// by √s, which turns p − c into q with the rotation formula for an
/// unnormalised quaternion (and gives s back as 1/|Q|²), then (c, form).
/// Two rows where the matrix and s took four: a node's texel fetches are
/// most of an evaluation on lavapipe.
fn frame_rows(m: [[f64; 4]; 3], s: f64, form: u32) -> [[f32; 4]; 2] {
    let a = DMat3::from_cols(DVec3::from_slice(&m[0]), DVec3::from_slice(&m[1]), DVec3::from_slice(&m[2])).transpose() * s;
    let c = -(a.transpose() * (DVec3::new(m[0][3], m[1][3], m[2][3]) * s));
    let q = DQuat::from_mat3(&a).normalize() / s.sqrt();
    [[q.x, q.y, q.z, q.w].map(|v| v as f32), [c.x as f32, c.y as f32, c.z as f32, form as f32]]
}

fn shape_rows(p: &Primitive) -> Vec<[f32; 4]> {
    if let Shape::Extrude { profile, .. } | Shape::Revolve { profile, .. } = p.shape {
        return profile_rows(p, &profile);
    }
    if let Shape::Grid(g) = &p.shape {
        return grid_rows(p, &g.grid);
    }
    if let Shape::Formula(f) = &p.shape {
        return formula_rows(p, f);
    }
    let mut m = p.transform.matrix();
    let s = p.transform.scale;
    let f = |v: f64| v as f32;
    let (t, v) = p.shape.analytic().expect("profiles and grids have rows of their own");
    if let (Shape::Sphere { radius }, None) = (&p.shape, &p.warp) {
        // A plain sphere needs no frame: |p − c| − s·radius (the kernel of
        // a scene of spheres reads only the last two rows).
        let c = p.transform.translate.map(|v| v as f32);
        return vec![[0.0, 0.0, 0.0, 1.0], [c[0], c[1], c[2], FORM_BOX as f32], [0.0, 0.0, 0.0, f(s * radius)]];
    }
    let rows = (t.rows)(&v, &mut m);
    let [r0, r1] = frame_rows(m, s, rows.form);
    vec![r0, r1, rows.row.map(f)]
}

/// An extruded or revolved profile's rows: the frame, (e.x, e.y, half
/// height, r), (R, polygon vertices, 0, 0), the segment (a, b), then the
/// polygon's vertices two a row. Every profile but the polygon is
/// box₂(u − a − (b − a)·h, e) − r (profile.rs).
fn profile_rows(p: &Primitive, profile: &Profile) -> Vec<[f32; 4]> {
    let f = |v: f64| v as f32;
    let (t, v) = profile.typed();
    let SegmentBox { e, r, a, b } = (t.row)(&v);
    let (h, major, form) = match p.shape {
        Shape::Extrude { half_height, .. } => (half_height, 0.0, FORM_EXTRUDE),
        Shape::Revolve { offset, .. } => (0.0, offset, FORM_REVOLVE),
        _ => unreachable!("a profile primitive"),
    };
    let vertices = profile.vertices();
    let mut rows = frame_rows(p.transform.matrix(), p.transform.scale, form).to_vec();
    rows.push([f(e[0]), f(e[1]), f(h), f(r)]);
    rows.push([f(major), vertices.len() as f32, 0.0, 0.0]);
    rows.push([f(a[0]), f(a[1]), f(b[0]), f(b[1])]);
    for pair in vertices.chunks(2) {
        let q = pair.get(1).copied().unwrap_or([0.0; 2]);
        rows.push([f(pair[0][0]), f(pair[0][1]), f(q[0]), f(q[1])]);
    }
    rows
}

/// A voxel grid's rows: the frame, (nx, ny, nz, 1/spacing), (origin,
/// spacing), then the samples four a row, x fastest (`scene_grid` in
/// templates/fields/scene.wgsl interpolates them as `Grid::eval` does).
fn grid_rows(p: &Primitive, g: &super::grid::Grid) -> Vec<[f32; 4]> {
    let f = |v: f64| v as f32;
    let (d, o) = (g.dims(), g.origin());
    let mut rows = frame_rows(p.transform.matrix(), p.transform.scale, FORM_GRID).to_vec();
    rows.push([d[0] as f32, d[1] as f32, d[2] as f32, f(1.0 / g.spacing())]);
    rows.push([f(o[0]), f(o[1]), f(o[2]), f(g.spacing())]);
    rows.extend(g.values().chunks(4).map(|c| [0, 1, 2, 3].map(|k| c.get(k).copied().unwrap_or(0.0))));
    rows
}

/// A formula leaf's rows: the frame, (box centre, leaf index), (box half
/// extents, 1/L). The leaf index, the leaf's tape in the scene's tape
/// texture, is written by the layout ([`LEAF_INDEX_ROW`]).
fn formula_rows(p: &Primitive, f: &super::leaf::FormulaLeaf) -> Vec<[f32; 4]> {
    let [c, h] = [f.centre(), f.half()].map(|v| v.map(|x| x as f32));
    let mut rows = frame_rows(p.transform.matrix(), p.transform.scale, FORM_FORMULA).to_vec();
    rows.push([c[0], c[1], c[2], 0.0]);
    rows.push([h[0], h[1], h[2], f.scale() as f32]);
    rows
}

/// The row of a formula leaf's rows whose w holds its leaf index.
pub const LEAF_INDEX_ROW: usize = 2;

/// `v` as an f32 no smaller than `v`.
fn up(v: f64) -> f32 {
    let f = v as f32;
    if (f as f64) < v { f.next_up() } else { f }
}

/// An ABV's [`ABV_STRIDE`](super::linear::ABV_STRIDE) rows (module doc).
pub fn abv_rows(a: &Abv) -> [[f32; 4]; 4] {
    let mut rows = [[0.0f32; 4]; 4];
    let pad = |size: f64, at: &[f64]| size + (size + at.iter().fold(0.0f64, |m, c| m.max(c.abs()))) * (1.0 / (1 << 20) as f64);
    let v = |p: [f64; 3], w: f32| [p[0] as f32, p[1] as f32, p[2] as f32, w];
    match *a {
        Abv::Always => {}
        Abv::Sphere { centre, radius } => {
            rows[0] = v(centre, ABV_SPHERE as f32);
            rows[1] = [0.0, 0.0, 0.0, up(pad(radius, &centre))];
        }
        Abv::Box { centre, axes, half } => {
            rows[0] = v(centre, ABV_BOX as f32);
            for k in 0..3 {
                rows[k + 1] = v(axes[k], up(pad(half[k], &centre)));
            }
        }
        Abv::Capsule { a, b, radius } => {
            rows[0] = v(a, ABV_CAPSULE as f32);
            let ends = [a[0], a[1], a[2], b[0], b[1], b[2]];
            rows[1] = v(b, up(pad(radius, &ends)));
        }
    }
    rows
}

/// The bounding ball of an ABV as the tile pre-pass reads it (centre,
/// radius), rounded outwards: f32 must not shrink the ball. An unbounded
/// primitive has an infinite radius and is active everywhere.
pub fn ball(a: &Abv) -> [f32; 4] {
    let (c, r) = match *a {
        Abv::Always => ([0.0; 3], f64::INFINITY),
        Abv::Sphere { centre, radius } => (centre, radius),
        Abv::Box { centre, half, .. } => (centre, DVec3::from(half).length()),
        Abv::Capsule { a, b, radius } => {
            let (a, b) = (DVec3::from(a), DVec3::from(b));
            ((0.5 * (a + b)).to_array(), 0.5 * (b - a).length() + radius)
        }
    };
    let r32 = r as f32;
    [c[0] as f32, c[1] as f32, c[2] as f32, if (r32 as f64) < r { r32.next_up() * (1.0 + 1e-6) } else { r32 * (1.0 + 1e-6) }]
}

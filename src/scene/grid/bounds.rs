//! The grid's Lipschitz bound and bounding box, with their proofs.
//!
//! **Gradient of a cell.** In a cell with corner samples c[a][b][d]
//! (a, b, d ∈ {0, 1} along x, y, z) and fractions t, the interpolant's
//! partial derivative along x is (1/spacing) times the bilinear blend, in
//! (t.y, t.z), of the 4 x-edge differences ex[b][d] = c[1][b][d] − c[0][b][d]
//! (likewise y and z). So |∂x| ≤ max|ex|/spacing, which bounds the gradient
//! by sqrt(Σ_axes max²), but that mixes edges that never meet. Exactly:
//! |∇f|² = ∂x² + ∂y² + ∂z² is, in any one of t.x, t.y, t.z with the others
//! fixed, a sum of squares of affine functions, so convex; a function
//! convex in each variable separately takes its maximum over [0, 1]³ at a
//! vertex, and at vertex (a, b, d) the partials are ex[b][d], ey[a][d],
//! ez[a][b]. [`Cell::max_gradient`] is that maximum, the exact supremum of
//! |∇f| over the cell.
//!
//! **Outside.** With q the nearest box point and h = |p − q|, the
//! extension's gradient is built from ∇(g∘clamp) = P∇g (P keeps the axes
//! not clamped, the face's tangent axes) and ∇h = (p − q)/h (along the
//! clamped axes only), which are orthogonal. Where g(q) ≥ 0, f =
//! sqrt(g² + h²) and |∇f|² = (g²|P∇g|² + h²)/(g² + h²) ≤ max(|P∇g|², 1).
//! Where g(q) < 0, f = g + h and |∇f|² = |P∇g|² + 1. |P∇g| is bounded on a
//! face patch (the face of a boundary cell, a bilinear patch) by the
//! maximum over its 4 corners of its two tangential edge differences, by
//! the same argument in 2D; g(q) < 0 is possible only on a patch with a
//! negative corner.
//!
//! **Bounding box.** Let C_r be the cells with a corner ≤ r and B their
//! hull (cell indices [imin, imax]). Inside the grid's box, the interpolant
//! in a cell is a convex combination of its corners, so a point with
//! f ≤ r lies in a cell of C_r: in B. Outside, f(p) ≤ r needs g(q) ≤ r
//! (sqrt(g² + h²) ≥ g, and g + h ≥ g), so q lies in a boundary cell of
//! C_r, so in B. p − q is nonzero only along the clamped axes; along such
//! an axis, say beyond the high x face, q lies on that face, in a face
//! patch (a boundary cell's face, whose bilinear interpolant is ≥ its
//! smallest corner m) with m ≤ g(q) ≤ r. There h ≤ sqrt(r² − m²) if m ≥ 0
//! (sqrt(g² + h²) ≤ r with g ≥ m), and h ≤ r − g(q) ≤ r − m if m < 0 (the
//! g ≥ 0 branch gives h ≤ r ≤ r − m). So p lies in B grown, on each face
//! of the grid's box, by the largest such bound over that face's patches
//! with m ≤ r (0 when there is none: no outside point projects there).
//! When C_r is empty, g > r on the whole box, and both parts are empty.

use super::Grid;
use crate::scene::roi::Aabb;

/// The 8 samples of a cell, `c[a][b][d]` at offset (a, b, d) from its low
/// corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell(pub [[[f64; 2]; 2]; 2]);

impl Cell {
    /// The smallest corner: the interpolant is ≥ it in the cell.
    pub fn min(&self) -> f64 {
        self.0.iter().flatten().flatten().fold(f64::INFINITY, |m, &v| m.min(v))
    }

    /// The largest corner: the interpolant is ≤ it in the cell.
    pub fn max(&self) -> f64 {
        self.0.iter().flatten().flatten().fold(f64::NEG_INFINITY, |m, &v| m.max(v))
    }

    /// max over the cell of |∇f|·spacing: the largest, over the 8 corners,
    /// of the length of (x-edge, y-edge, z-edge difference) meeting there
    /// (exact, see the module doc).
    pub fn max_gradient(&self) -> f64 {
        let c = &self.0;
        let mut m: f64 = 0.0;
        for a in 0..2 {
            for b in 0..2 {
                for d in 0..2 {
                    let ex = c[1][b][d] - c[0][b][d];
                    let ey = c[a][1][d] - c[a][0][d];
                    let ez = c[a][b][1] - c[a][b][0];
                    m = m.max(ex * ex + ey * ey + ez * ez);
                }
            }
        }
        m.sqrt()
    }
}

/// Every cell's low corner, x fastest.
fn cells(g: &Grid) -> impl Iterator<Item = (usize, usize, usize)> {
    let [nx, ny, nz] = g.dims.map(|d| d as usize - 1);
    (0..nz).flat_map(move |z| (0..ny).flat_map(move |y| (0..nx).map(move |x| (x, y, z))))
}

/// See [`Grid::lipschitz_above`].
pub(super) fn lipschitz_above(g: &Grid, level: f64) -> f64 {
    let mut m: f64 = 0.0;
    for (x, y, z) in cells(g) {
        let c = g.cell(x, y, z);
        if c.max() >= level {
            m = m.max(c.max_gradient());
        }
    }
    (m / g.spacing).max(outside_lipschitz(g))
}

/// Every boundary face patch (the face of a boundary cell on the grid's
/// box): its axis, whether it is on the high side, and its 4 samples
/// `p[u][v]` along the face's two tangent axes (axis + 1, axis + 2 mod 3).
fn face_patches(g: &Grid) -> impl Iterator<Item = (usize, bool, [[f64; 2]; 2])> + '_ {
    (0..3).flat_map(move |axis| {
        let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
        let (nb, nc) = (g.dims[b] as usize - 1, g.dims[c] as usize - 1);
        [false, true].into_iter().flat_map(move |high| {
            let side = if high { g.dims[axis] as usize - 1 } else { 0 };
            (0..nb).flat_map(move |j| {
                (0..nc).map(move |k| {
                    let s = |u: usize, v: usize| {
                        let mut i = [0usize; 3];
                        (i[axis], i[b], i[c]) = (side, j + u, k + v);
                        f64::from(g.values[g.index(i[0], i[1], i[2])])
                    };
                    (axis, high, [[s(0, 0), s(0, 1)], [s(1, 0), s(1, 1)]])
                })
            })
        })
    })
}

/// The extension's gradient bound: over the boundary face patches,
/// sqrt(T² + 1) where the patch has a negative corner, else max(T, 1), T
/// the patch's largest tangential gradient (module doc).
fn outside_lipschitz(g: &Grid) -> f64 {
    let mut m: f64 = 1.0;
    for (_, _, p) in face_patches(g) {
        let mut t2: f64 = 0.0;
        for u in 0..2 {
            for v in 0..2 {
                let (eb, ec) = (p[1][v] - p[0][v], p[u][1] - p[u][0]);
                t2 = t2.max(eb * eb + ec * ec);
            }
        }
        let t = t2.sqrt() / g.spacing;
        let negative = p.iter().flatten().any(|&v| v < 0.0);
        m = m.max(if negative { (t * t + 1.0).sqrt() } else { t });
    }
    m
}

/// See [`Grid::bounding_box`] and the proof in the module doc.
pub(super) fn bounding_box(g: &Grid, r: f64) -> Option<Aabb> {
    let mut imin = [usize::MAX; 3];
    let mut imax = [0usize; 3];
    for (x, y, z) in cells(g) {
        if g.cell(x, y, z).min() <= r {
            for (k, i) in [x, y, z].into_iter().enumerate() {
                imin[k] = imin[k].min(i);
                imax[k] = imax[k].max(i);
            }
        }
    }
    if imin[0] == usize::MAX {
        return None;
    }
    // How far past each face (low, high per axis) a point with f ≤ r can be.
    let mut grow = [[0.0f64; 2]; 3];
    for (axis, high, p) in face_patches(g) {
        let m = p.iter().flatten().fold(f64::INFINITY, |a, &v| a.min(v));
        if m <= r {
            let h = if m >= 0.0 { (r * r - m * m).max(0.0).sqrt() } else { r - m };
            grow[axis][usize::from(high)] = grow[axis][usize::from(high)].max(h);
        }
    }
    let at = |k: usize, i: usize| g.origin[k] + i as f64 * g.spacing;
    let mut b = Aabb { min: [0.0; 3], max: [0.0; 3] };
    for k in 0..3 {
        b.min[k] = at(k, imin[k]) - grow[k][0];
        b.max[k] = at(k, imax[k] + 1) + grow[k][1];
    }
    Some(b)
}

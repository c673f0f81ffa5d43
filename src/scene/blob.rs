//! A tighter slope bound for a blob: a group of sum blends whose operands
//! are density kernels (`roi::field_lipschitz` calls it).
//!
//! Where the supports of several kernels overlap, the sum's gradient is the
//! sum of theirs, so its slope is at most Σ_j g_j(d_j(p)), g_j the slope of
//! kernel j at distance d_j from its skeleton. Adding each kernel's
//! steepest slope wherever supports overlap (the sweep in `roi`) assumes
//! every kernel is at its steepest at once, which it never is: g peaks on
//! one shell (t = 1/√5 of the support). This finds the maximum over space
//! of the sum by branch and bound on boxes: over a box, each kernel's
//! distance lies in an interval, over which g has a known maximum (it rises
//! to the peak and falls after), and the box's bound is the sum of those.
//! The largest bound of the boxes left when the search stops is an upper
//! bound of the slope everywhere; the search stops when it is within 3 % of
//! a value actually reached at a box's centre, or after a fixed number of
//! boxes (then the bound is looser, never wrong).

use super::roi::Aabb;
use glam::DVec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Where a blob's operand adds slope.
pub enum Part {
    /// A density kernel: its skeleton (a segment, world), support radius
    /// (world) and steepest slope (at t = 1/√5).
    Kernel {
        /// Skeleton ends.
        a: DVec3,
        /// Skeleton ends.
        b: DVec3,
        /// Support radius.
        radius: f64,
        /// T·K′ₘₐₓ/(c·R), the slope at the peak.
        peak: f64,
    },
    /// Anything else: this slope anywhere in this box.
    Other {
        /// Where it can be below the sum's range.
        region: Aabb,
        /// Its bound.
        slope: f64,
    },
}

/// The most boxes one search looks at.
const MAX_BOXES: usize = 16384;
/// The most part evaluations the searches of one scene make together (a
/// box evaluates the parts that can add slope in it): past it a blob keeps
/// a looser bound.
pub const SCENE_EVALS: usize = 1 << 24;
/// The most parts the search takes; a larger blob keeps the sweep's bound.
pub const MAX_PARTS: usize = 1 << 16;

fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let h = if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (p - a - ab * h).length()
}

/// The kernel's slope shape 6t(1 − t²)² / K′ₘₐₓ: 1 at the peak t = 1/√5.
fn shape(t: f64) -> f64 {
    if t >= 1.0 {
        return 0.0;
    }
    6.0 * t * (1.0 - t * t).powi(2) / crate::sdf::DENSITY_SLOPE
}

impl Part {
    /// The slope at point p (a lower bound of the maximum).
    fn at(&self, p: DVec3) -> f64 {
        match self {
            Part::Kernel { a, b, radius, peak } => peak * shape(segment_distance(p, *a, *b) / radius),
            Part::Other { region, slope } => {
                if (0..3).all(|k| region.min[k] <= p[k] && p[k] <= region.max[k]) {
                    *slope
                } else {
                    0.0
                }
            }
        }
    }

    /// An upper bound of the slope over box `bx` (centre c, half diagonal h).
    fn over(&self, bx: &Aabb) -> f64 {
        match self {
            Part::Kernel { a, b, radius, peak } => {
                let lo = DVec3::from(bx.min);
                let hi = DVec3::from(bx.max);
                let c = (lo + hi) * 0.5;
                let half = (hi - lo).length() * 0.5;
                // The distance to a segment is convex: its maximum over the
                // box is at a corner; it changes no faster than the point.
                let near = (segment_distance(c, *a, *b) - half).max(0.0) / radius;
                let far = (0..8)
                    .map(|i| DVec3::new([lo.x, hi.x][i & 1], [lo.y, hi.y][(i >> 1) & 1], [lo.z, hi.z][i >> 2]))
                    .map(|q| segment_distance(q, *a, *b))
                    .fold(0.0, f64::max)
                    / radius;
                let top = 1.0 / 5f64.sqrt();
                let t = if near <= top && top <= far { top } else if far < top { far } else { near };
                peak * shape(t)
            }
            Part::Other { region, slope } => {
                let meets = (0..3).all(|k| region.min[k] <= bx.max[k] && bx.min[k] <= region.max[k]);
                if meets {
                    *slope
                } else {
                    0.0
                }
            }
        }
    }
}

/// A box of the search: its bound, and the parts that can add slope in it
/// (a smaller box keeps a subset of its parent's).
struct Cell(f64, Aabb, Vec<u32>);

impl PartialEq for Cell {
    fn eq(&self, o: &Cell) -> bool {
        self.0 == o.0
    }
}
impl Eq for Cell {}
impl PartialOrd for Cell {
    fn partial_cmp(&self, o: &Cell) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cell {
    fn cmp(&self, o: &Cell) -> Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// An upper bound of Σ parts' slopes over all of space (outside `bounds`
/// every kernel is 0 and every other part's region is left out), or `None`
/// when the bounds are not finite. `budget` counts part evaluations (spent
/// here); when it runs out the search stops with a looser bound, never a
/// wrong one (the largest bound of the boxes left).
pub fn slope_bound(parts: &[Part], bounds: Aabb, budget: &mut usize) -> Option<f64> {
    if !bounds.is_bounded() || *budget < parts.len() {
        return None;
    }
    let cell = |bx: Aabb, of: &[u32], budget: &mut usize| {
        *budget = budget.saturating_sub(of.len());
        let mut up = 0.0;
        let mut keep = Vec::new();
        for &i in of {
            let v = parts[i as usize].over(&bx);
            if v > 0.0 {
                up += v;
                keep.push(i);
            }
        }
        Cell(up, bx, keep)
    };
    let all: Vec<u32> = (0..parts.len() as u32).collect();
    let mut best: f64 = 0.0;
    let mut heap = BinaryHeap::new();
    heap.push(cell(bounds, &all, budget));
    for _ in 0..MAX_BOXES {
        let Some(Cell(up, bx, of)) = heap.pop() else { return Some(best) };
        let c = DVec3::from(bx.min).lerp(DVec3::from(bx.max), 0.5);
        best = best.max(of.iter().map(|&i| parts[i as usize].at(c)).sum());
        if up <= best * 1.03 + 1e-12 || *budget < 2 * of.len() {
            return Some(up.max(best));
        }
        // Split along the longest side.
        let size = DVec3::from(bx.max) - DVec3::from(bx.min);
        let k = if size.x >= size.y && size.x >= size.z { 0 } else if size.y >= size.z { 1 } else { 2 };
        let mid = 0.5 * (bx.min[k] + bx.max[k]);
        let (mut a, mut b) = (bx, bx);
        a.max[k] = mid;
        b.min[k] = mid;
        for h in [a, b] {
            heap.push(cell(h, &of, budget));
        }
    }
    heap.peek().map(|c| c.0.max(best))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lone_kernels_bound_is_its_peak_and_two_apart_do_not_add_up() {
        let k = |x: f64| Part::Kernel { a: DVec3::new(x, 0.0, 0.0), b: DVec3::new(x, 0.0, 0.0), radius: 1.0, peak: 1.0 };
        let bounds = Aabb { min: [-3.0; 3], max: [4.0, 3.0, 3.0] };
        let mut budget = SCENE_EVALS;
        let one = slope_bound(&[k(0.0)], bounds, &mut budget).unwrap();
        assert!((0.99..=1.031).contains(&one), "{one}");
        // Supports overlap (centres 1.5 apart), peaks are 0.45 from each centre: far apart.
        let two = slope_bound(&[k(0.0), k(1.5)], bounds, &mut budget).unwrap();
        let sampled = (0..3000).map(|i| -2.0 + i as f64 * 0.0015).map(|x| k(0.0).at(DVec3::new(x, 0.0, 0.0)) + k(1.5).at(DVec3::new(x, 0.0, 0.0))).fold(0.0, f64::max);
        // The sweep would say 2 (both peaks added).
        assert!(two >= sampled && two < 1.1, "{two} against {sampled} sampled on the axis");
        assert_eq!(slope_bound(&[k(0.0), k(1.0)], bounds, &mut 1), None);
    }
}

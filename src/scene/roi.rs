//! Ranges of interest and augmented bounding volumes (Zanni et al. 2024,
//! §4; the brief §1.2-1.3).
//!
//! A node's range of interest [r⁻, r⁺] is the part of its codomain where a
//! pruned evaluation must equal the full one for the root's zero set to be
//! unchanged; outside it, only the side (above r⁺, below r⁻) must be kept.
//! The root's range is [0, 0]; one top-down pass gives every node's, with
//! r_o = 0 for sharp operators:
//! - ∪: both children [r⁻, max(r⁺, r_o)] (eq. 13);
//! - ∩: both children [min(r⁻, −r_o), r⁺] (eq. 14);
//! - \: left [min(r⁻, −r_o), r⁺], right [−r⁺, max(−r⁻, r_o)] (eq. 15-16).
//!
//! So r⁺ is the largest r_o on the path, and it depends only on the tree:
//! moving a primitive changes no range.
//!
//! A primitive p matters only where f_p ≤ r_p⁺. Its augmented bounding
//! volume (ABV) contains that set: the bounding volume of the primitive's
//! zero set grown by r_p⁺, which is exact for exact distances (f_p ≥ the
//! distance outside). The octahedron's bound (|q|₁ − s)/√3 ≤ r is the
//! octahedron of size s + √3·r, so its ABV is the sphere of that radius.
//! Planes are unbounded: they have no ABV and are always active.

use super::{Node, Primitive, Scene, Shape};
use crate::sdf::primitive::Bound;
use glam::DVec3;

/// A node's range of interest [lo, hi], lo ≤ 0 ≤ hi.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Roi {
    /// r⁻.
    pub lo: f64,
    /// r⁺.
    pub hi: f64,
}

/// Every node's range of interest, indexed by node.
pub fn ranges(scene: &Scene) -> Vec<Roi> {
    let nodes = scene.nodes();
    let mut roi = vec![Roi { lo: 0.0, hi: 0.0 }; nodes.len()];
    for &i in scene.post_order().iter().rev() {
        if let Node::Unary { op, child } = nodes[i] {
            let (lo, hi) = op.operand_range(roi[i].lo, roi[i].hi);
            roi[child] = Roi { lo, hi };
        }
        if let Node::Operator { op, left, right } = nodes[i] {
            let Roi { lo, hi } = roi[i];
            let ro = op.range();
            let (l, r) = match op.kind {
                super::OpKind::Union => (Roi { lo, hi: hi.max(ro) }, Roi { lo, hi: hi.max(ro) }),
                super::OpKind::Intersection => (Roi { lo: lo.min(-ro), hi }, Roi { lo: lo.min(-ro), hi }),
                super::OpKind::Difference => (Roi { lo: lo.min(-ro), hi }, Roi { lo: -hi, hi: (-lo).max(ro) }),
            };
            roi[left] = l;
            roi[right] = r;
        }
    }
    roi
}

/// Every node's Lipschitz factor from the operators above it: the product
/// of 6r_o/(6r_o − β) along the path from the root (1 for sharp ones).
/// Loose: the brief measured max |∇f| ≤ 1.23 where this product is larger.
/// A displacement above a node adds to the bound of its operand's field,
/// which is then at most the sum, so it is carried as a separate term:
/// see [`field_lipschitz`].
pub fn path_lipschitz(scene: &Scene) -> Vec<f64> {
    let nodes = scene.nodes();
    let mut lip = vec![1.0; nodes.len()];
    for &i in scene.post_order().iter().rev() {
        let l = match nodes[i] {
            Node::Operator { op, .. } => lip[i] * op.lipschitz_factor(),
            _ => lip[i],
        };
        for &c in nodes[i].children().iter() {
            lip[c] = l;
        }
    }
    lip
}

/// A Lipschitz bound of the whole field where it is ≥ 0 (what sphere
/// tracing steps on), ignoring the compact operators' factors (which the
/// renderer covers with its empirical 1.45): bottom up, an exact primitive
/// is 1, a voxel grid the bound of its interpolant where it can decide the
/// field ([`trace_levels`]), a binary operator the larger of its operands'
/// (√2 times it for a chamfer or round join, their sum for a sum blend),
/// a displacement its operand's plus a·f·NOISE_GRADIENT, other unary nodes
/// their operand's; a warped primitive's is multiplied by its warp's
/// stretch within its clamp radius (`warp`).
pub fn field_lipschitz(scene: &Scene) -> f64 {
    let nodes = scene.nodes();
    let levels = trace_levels(scene);
    let mut groups = nodes.iter().any(is_sum).then(|| SumGroups::new(scene));
    let mut lip = vec![1.0f64; nodes.len()];
    for &i in scene.post_order() {
        lip[i] = match &nodes[i] {
            Node::Primitive(p) => {
                let scale = p.transform.scale * p.warp.map_or(1.0, |w| w.frame.scale);
                let own = match p.shape {
                    Shape::Grid(ref g) => levels[i].map_or(g.grid.lipschitz(), |l| g.grid.lipschitz_above(l / scale)),
                    ref shape => shape.analytic().map_or(1.0, |(t, v)| t.lipschitz.of(&v)),
                };
                own * p.warp.map_or(1.0, |w| w.lipschitz())
            }
            Node::Operator { op, left, right } => {
                let sum = op.combine_lipschitz(lip[*left], lip[*right]);
                match &mut groups {
                    Some(g) if g.is_top(scene, i) => sum.min(g.bound(scene, i, &lip)),
                    _ => sum,
                }
            }
            Node::Unary { op, child } => lip[*child] + op.lipschitz_increase(),
        };
    }
    lip[scene.root()]
}

fn is_sum(n: &Node) -> bool {
    matches!(n, Node::Operator { op, .. } if matches!(op.join, Some(super::Join::Sum { .. })))
}

/// What bounds a group of sum blends (a maximal subtree of `sum_union`
/// nodes, a blob of density fields) more tightly than the sum of its
/// operands' bounds, which holds everywhere: an operand adds its slope only
/// where it is below the group's range (elsewhere the sum leaves it out),
/// which is inside the box of its primitives' ABVs (they hold where each
/// primitive is below its range of interest, at least the sum's range). At
/// a point, the operands below their range all have boxes holding it, so
/// they all meet the box of any one of them: the bound is the largest, over
/// the operands, of the sum of the bounds of those whose boxes meet its own.
struct SumGroups {
    boxes: Vec<Aabb>,
    parent: Vec<usize>,
    /// Kernel evaluations the blobs' slope searches may still make.
    budget: usize,
}

impl SumGroups {
    fn new(scene: &Scene) -> SumGroups {
        let nodes = scene.nodes();
        let roi = ranges(scene);
        let mut boxes = vec![Aabb::EMPTY; nodes.len()];
        let mut parent = vec![usize::MAX; nodes.len()];
        for &i in scene.post_order() {
            boxes[i] = match &nodes[i] {
                Node::Primitive(p) => abv(p, roi[i].hi).aabb(),
                n => n.children().iter().fold(Aabb::EMPTY, |b, &c| b.hull(&boxes[c])),
            };
            for &c in nodes[i].children().iter() {
                parent[c] = i;
            }
        }
        SumGroups { boxes, parent, budget: super::blob::SCENE_EVALS }
    }

    /// Whether node `i` is a sum whose parent is not.
    fn is_top(&self, scene: &Scene, i: usize) -> bool {
        let nodes = scene.nodes();
        is_sum(&nodes[i]) && (self.parent[i] == usize::MAX || !is_sum(&nodes[self.parent[i]]))
    }

    /// The bound of the group under `top`, its operands' bounds in `lip`.
    fn bound(&mut self, scene: &Scene, top: usize, lip: &[f64]) -> f64 {
        let nodes = scene.nodes();
        let (mut operands, mut todo) = (Vec::new(), vec![top]);
        while let Some(n) = todo.pop() {
            if is_sum(&nodes[n]) {
                todo.extend(nodes[n].children().iter());
            } else {
                operands.push(n);
            }
        }
        // Below its range a density primitive's slope is its kernel's, not
        // the 1 of its outside (where the sum leaves it out); where every
        // operand is above the range the group is their min.
        let below = |o: usize| match &nodes[o] {
            Node::Primitive(p) => match p.shape {
                Shape::Density { radius, iso, range, .. } => range * crate::sdf::DENSITY_SLOPE / (iso * radius) * p.warp.map_or(1.0, |w| w.lipschitz()),
                _ => lip[o],
            },
            _ => lip[o],
        };
        let outside = operands.iter().map(|&o| lip[o]).fold(0.0, f64::max);
        // A sweep along x: operands in order of their boxes' low x.
        let boxes = &self.boxes;
        operands.sort_by(|&a, &b| boxes[a].min[0].total_cmp(&boxes[b].min[0]));
        let slope: Vec<f64> = operands.iter().map(|&o| below(o)).collect();
        let mut reach = slope.clone();
        for i in 0..operands.len() {
            let a = &boxes[operands[i]];
            for j in i + 1..operands.len() {
                let b = &boxes[operands[j]];
                if b.min[0] > a.max[0] {
                    break;
                }
                if (1..3).all(|k| b.min[k] <= a.max[k] && a.min[k] <= b.max[k]) {
                    reach[i] += slope[j];
                    reach[j] += slope[i];
                }
            }
        }
        let swept = reach.into_iter().fold(0.0, f64::max);
        // Kernels are not at their steepest all at once: search space for
        // the largest sum of slopes (`blob`).
        let mut searched = None;
        if operands.len() <= super::blob::MAX_PARTS {
            let parts: Vec<super::blob::Part> = operands.iter().map(|&o| self.part(scene, o, below(o))).collect();
            let hull = operands.iter().fold(Aabb::EMPTY, |b, &o| b.hull(&self.boxes[o]));
            searched = super::blob::slope_bound(&parts, hull, &mut self.budget);
        }
        swept.min(searched.unwrap_or(f64::INFINITY)).max(outside)
    }

    /// Operand `o` of a blob as the slope search sees it.
    fn part(&self, scene: &Scene, o: usize, slope: f64) -> super::blob::Part {
        if let Node::Primitive(p) = &scene.nodes()[o] {
            if let (Shape::Density { radius, half_length, .. }, None) = (&p.shape, &p.warp) {
                let t = &p.transform;
                return super::blob::Part::Kernel {
                    a: t.to_world(DVec3::new(0.0, 0.0, -half_length)),
                    b: t.to_world(DVec3::new(0.0, 0.0, *half_length)),
                    radius: t.scale * radius,
                    peak: slope,
                };
            }
        }
        super::blob::Part::Other { region: self.boxes[o], slope }
    }
}

/// For every node, a level at or above which its value must be where it
/// decides the root's value and the root is ≥ 0 (where sphere tracing
/// steps), or `None` when no such level exists (its values below any
/// level can decide it). The root: 0. ∪ (sharp or G∪ ≤ min): both
/// operands the node's level; ∩: the deciding operand is at least the
/// level and the other, in a blend, within β of it, so the level − 2β;
/// \: the left likewise, the right `None` (−b decides where b is low);
/// offset d: the level + d; shell: `None` (|f| reads both sides);
/// infill: the level; displace a: the level − a. A voxel grid's gradient
/// only matters above its level, where its interpolant is much tamer than
/// at its kinks (`Grid::lipschitz_above`).
pub fn trace_levels(scene: &Scene) -> Vec<Option<f64>> {
    let nodes = scene.nodes();
    let mut level: Vec<Option<f64>> = vec![None; nodes.len()];
    level[scene.root()] = Some(0.0);
    for &i in scene.post_order().iter().rev() {
        let l = level[i];
        match nodes[i] {
            Node::Operator { op, left, right } => {
                let beta = op.blend_range();
                let (a, b) = match op.kind {
                    super::OpKind::Union => (l, l),
                    super::OpKind::Intersection => (l.map(|v| v - 2.0 * beta), l.map(|v| v - 2.0 * beta)),
                    super::OpKind::Difference => (l.map(|v| v - 2.0 * beta), None),
                };
                level[left] = a;
                level[right] = b;
            }
            Node::Unary { op, child } => {
                let (t, v) = op.typed();
                level[child] = l.and_then(|l| (t.operand_level)(&v, l));
            }
            Node::Primitive(_) => {}
        }
    }
    level
}

/// An augmented bounding volume, in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Abv {
    /// No bound (a plane): always active.
    Always,
    /// A ball.
    Sphere {
        /// Centre.
        centre: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// An oriented box.
    Box {
        /// Centre.
        centre: [f64; 3],
        /// Unit axes (the primitive's rotated x, y, z).
        axes: [[f64; 3]; 3],
        /// Half extents along the axes.
        half: [f64; 3],
    },
    /// The points within `radius` of the segment a–b.
    Capsule {
        /// One end.
        a: [f64; 3],
        /// The other end.
        b: [f64; 3],
        /// Radius.
        radius: f64,
    },
}

/// The ABV of primitive `p` whose range of interest reaches `r_plus`.
pub fn abv(p: &Primitive, r_plus: f64) -> Abv {
    // Below an erosion r⁺ may be negative; a volume grown by 0 still holds
    // the smaller set.
    let r_plus = r_plus.max(0.0);
    if let Some(w) = &p.warp {
        return super::warp::abv(p, w, r_plus);
    }
    let t = &p.transform;
    let s = t.scale;
    let centre = t.to_world(DVec3::ZERO).to_array();
    let obb = |h: [f64; 3]| Abv::Box {
        centre,
        axes: [DVec3::X, DVec3::Y, DVec3::Z].map(|e| t.world_direction(e).to_array()),
        half: h.map(|c| s * c + r_plus),
    };
    match p.shape {
        // The grid's box of {g ≤ r⁺/s} in its local frame (an empty set: a
        // point, never active).
        Shape::Grid(ref g) => match g.grid.bounding_box(r_plus / s) {
            Some(b) => {
                let c = [0, 1, 2].map(|k| 0.5 * (b.min[k] + b.max[k]));
                profile_box(p, c, [0, 1, 2].map(|k| 0.5 * (b.max[k] - b.min[k])), 0.0)
            }
            None => Abv::Sphere { centre, radius: 0.0 },
        },
        // Outside its box a leaf is at least the distance to the box.
        Shape::Formula(ref f) => profile_box(p, f.centre(), f.half(), r_plus),
        Shape::Extrude { profile, half_height } => {
            let (lo, hi) = profile.bounds();
            let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.0];
            profile_box(p, c, [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1]), half_height], r_plus)
        }
        Shape::Revolve { profile, offset } => {
            // The profile's (u.x, u.y) is (distance from the axis − R, z).
            let (lo, hi) = profile.bounds();
            let radius = offset + hi[0];
            profile_box(p, [0.0, 0.0, 0.5 * (lo[1] + hi[1])], [radius, radius, 0.5 * (hi[1] - lo[1])], r_plus)
        }
        ref shape => {
            let (ty, v) = shape.analytic().expect("a shape given by numbers");
            match (ty.bound)(&v) {
                Bound::Box(h) => obb(h),
                Bound::Ball { radius, slope } => Abv::Sphere { centre, radius: s * radius + slope * r_plus },
                Bound::Capsule { a, b, radius, allowance } => Abv::Capsule {
                    a: t.to_world(DVec3::from(a)).to_array(),
                    b: t.to_world(DVec3::from(b)).to_array(),
                    radius: s * radius + (r_plus - s * allowance).max(0.0),
                },
                Bound::Unbounded => Abv::Always,
            }
        }
    }
}

/// The oriented box of local centre `c` and local half extents `h`, grown
/// by `r_plus` in world units.
fn profile_box(p: &Primitive, c: [f64; 3], h: [f64; 3], r_plus: f64) -> Abv {
    let t = &p.transform;
    Abv::Box {
        centre: t.to_world(DVec3::from(c)).to_array(),
        axes: [DVec3::X, DVec3::Y, DVec3::Z].map(|e| t.world_direction(e).to_array()),
        half: h.map(|v| t.scale * v + r_plus),
    }
}

impl Abv {
    /// Whether `p` is inside (boundary included).
    pub fn contains(&self, p: [f64; 3]) -> bool {
        let p = DVec3::from(p);
        match *self {
            Abv::Always => true,
            Abv::Sphere { centre, radius } => (p - DVec3::from(centre)).length() <= radius,
            Abv::Box { centre, axes, half } => {
                let d = p - DVec3::from(centre);
                (0..3).all(|k| d.dot(DVec3::from(axes[k])).abs() <= half[k])
            }
            Abv::Capsule { a, b, radius } => {
                let (a, b) = (DVec3::from(a), DVec3::from(b));
                let (pa, ba) = (p - a, b - a);
                let bb = ba.dot(ba);
                let h = if bb > 0.0 { (pa.dot(ba) / bb).clamp(0.0, 1.0) } else { 0.0 };
                (pa - ba * h).length() <= radius
            }
        }
    }

    /// Its axis-aligned bounding box (everything for [`Abv::Always`]).
    pub fn aabb(&self) -> Aabb {
        match *self {
            Abv::Always => Aabb::EVERYTHING,
            Abv::Sphere { centre, radius } => Aabb { min: centre.map(|c| c - radius), max: centre.map(|c| c + radius) },
            Abv::Box { centre, axes, half } => {
                let mut r = [0.0; 3];
                for (k, rk) in r.iter_mut().enumerate() {
                    *rk = (0..3).map(|a| axes[a][k].abs() * half[a]).sum();
                }
                Aabb { min: [0, 1, 2].map(|k| centre[k] - r[k]), max: [0, 1, 2].map(|k| centre[k] + r[k]) }
            }
            Abv::Capsule { a, b, radius } => Aabb {
                min: [0, 1, 2].map(|k| a[k].min(b[k]) - radius),
                max: [0, 1, 2].map(|k| a[k].max(b[k]) + radius),
            },
        }
    }
}

/// An axis-aligned box; infinite coordinates for unbounded sides. Empty
/// when some min exceeds its max.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Low corner.
    pub min: [f64; 3],
    /// High corner.
    pub max: [f64; 3],
}

impl Aabb {
    /// All of space.
    pub const EVERYTHING: Aabb = Aabb { min: [f64::NEG_INFINITY; 3], max: [f64::INFINITY; 3] };
    /// Nothing (the hull of it and a box is the box).
    pub const EMPTY: Aabb = Aabb { min: [f64::INFINITY; 3], max: [f64::NEG_INFINITY; 3] };

    /// The smallest box holding both.
    pub fn hull(&self, o: &Aabb) -> Aabb {
        Aabb { min: [0, 1, 2].map(|k| self.min[k].min(o.min[k])), max: [0, 1, 2].map(|k| self.max[k].max(o.max[k])) }
    }

    /// The common part.
    pub fn intersection(&self, o: &Aabb) -> Aabb {
        Aabb { min: [0, 1, 2].map(|k| self.min[k].max(o.min[k])), max: [0, 1, 2].map(|k| self.max[k].min(o.max[k])) }
    }

    /// Every side finite.
    pub fn is_bounded(&self) -> bool {
        self.min.iter().chain(&self.max).all(|c| c.is_finite())
    }

    /// No point inside.
    pub fn is_empty(&self) -> bool {
        (0..3).any(|k| self.min[k] > self.max[k])
    }

    /// The box grown by 5 % of its largest side on every side, as
    /// [x0, x1, y0, y1, z0, z1]: a scene's default domain, which does not
    /// cut its silhouettes. `None` when unbounded or empty.
    pub fn padded(&self) -> Option<[f64; 6]> {
        if !self.is_bounded() || self.is_empty() {
            return None;
        }
        let pad = 0.05 * (0..3).map(|k| self.max[k] - self.min[k]).fold(0.0, f64::max).max(1e-6);
        Some([self.min[0] - pad, self.max[0] + pad, self.min[1] - pad, self.max[1] + pad, self.min[2] - pad, self.max[2] + pad])
    }
}

/// `bounds` (a box holding the solid) shrunk to the cells of an n³ grid over
/// it that can hold a point of the solid: a cell whose centre has f > L·h
/// (h its half diagonal, L the bound the scene is traced with) has none,
/// since a sphere-tracing step of f/L from the centre is safe. For framing:
/// the ABVs' box is loose around smooth blends and warps (a bent bar's box
/// is its disc's). `None` when the scene is too large to sample (more than
/// `max_evals` node evaluations, a formula leaf's operations counted as
/// nodes) or `bounds` is not finite.
pub fn sampled_bounds(scene: &Scene, bounds: &Aabb, lipschitz: f64, n: usize, max_evals: usize) -> Option<Aabb> {
    if !bounds.is_bounded() || bounds.is_empty() || n.pow(3).saturating_mul(scene.eval_cost()) > max_evals {
        return None;
    }
    let size: [f64; 3] = [0, 1, 2].map(|k| (bounds.max[k] - bounds.min[k]) / n as f64);
    let half = 0.5 * (size[0] * size[0] + size[1] * size[1] + size[2] * size[2]).sqrt();
    let mut out = Aabb::EMPTY;
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let cell = [i, j, k];
                let lo = [0, 1, 2].map(|a| bounds.min[a] + cell[a] as f64 * size[a]);
                let centre = [0, 1, 2].map(|a| lo[a] + 0.5 * size[a]);
                if scene.eval(centre) <= lipschitz * half {
                    out = out.hull(&Aabb { min: lo, max: [0, 1, 2].map(|a| lo[a] + size[a]) });
                }
            }
        }
    }
    // Clamp to the ABVs' box (a cell may stick out of it).
    Some(if out.is_empty() { *bounds } else { out.intersection(bounds) })
}

/// A box holding the solid {f ≤ 0} (so the surface), from the ABVs by the
/// tree: ∪ the hull of its operands' boxes, ∩ their intersection, \ its
/// left operand's. Each node's box holds {f_n ≤ r_n⁺}: G∪ ≤ r⁺ needs an
/// operand ≤ max(r⁺, r_o); G∩ ≥ max(a, b) and G\ ≥ a. Unbounded (infinite
/// sides) when a plane is not cut off by an intersection or difference.
pub fn bounds(scene: &Scene, roi: &[Roi]) -> Aabb {
    let nodes = scene.nodes();
    let mut b = vec![Aabb::EVERYTHING; nodes.len()];
    for &i in scene.post_order() {
        b[i] = match &nodes[i] {
            Node::Primitive(p) => abv(p, roi[i].hi).aabb(),
            Node::Operator { op, left, right } => match op.kind {
                super::OpKind::Union => b[*left].hull(&b[*right]),
                super::OpKind::Intersection => b[*left].intersection(&b[*right]),
                super::OpKind::Difference => b[*left],
            },
            // The operand's box holds {operand ≤ its r⁺}, which holds
            // {node ≤ r⁺} (operand_range): the same box.
            Node::Unary { child, .. } => b[*child],
        };
    }
    b[scene.root()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Blend, Builder, OpKind, Operator};

    #[test]
    fn ranges_follow_eq_13_to_16() {
        let mut b = Builder::default();
        let s = |b: &mut Builder| b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }));
        let (p0, p1, p2) = (s(&mut b), s(&mut b), s(&mut b));
        let u = b.operator(Operator::smooth(OpKind::Union, Blend { beta: 0.3, range: 0.5 }), p0, p1);
        let d = b.operator(Operator::smooth(OpKind::Difference, Blend { beta: 0.3, range: 0.4 }), u, p2);
        let scene = b.finish(d).unwrap();
        let r = ranges(&scene);
        assert_eq!(r[d], Roi { lo: 0.0, hi: 0.0 });
        assert_eq!(r[u], Roi { lo: -0.4, hi: 0.0 });
        assert_eq!(r[p2], Roi { lo: 0.0, hi: 0.4 });
        assert_eq!(r[p0], Roi { lo: -0.4, hi: 0.5 });
    }

    #[test]
    fn octahedron_abv_is_the_sphere_of_the_grown_octahedron() {
        let p = Primitive::new(Shape::Octahedron { size: 1.0 }).scaled(2.0).translated([1.0, 0.0, 0.0]);
        assert_eq!(abv(&p, 0.5), Abv::Sphere { centre: [1.0, 0.0, 0.0], radius: 2.0 + 3f64.sqrt() * 0.5 });
    }
}

//! The paper's synthetic scenes (Zanni et al. 2024, Fig. 16 and Fig. 18),
//! as the brief reconstructs them: the primitive counts are the paper's,
//! the geometry is ours (the paper shows pictures only). Deterministic for
//! a seed; every primitive but a sphere has a random rotation.
//!
//! - [`Kind::Aggregate`] (Fig. 16): a base aggregate of 10 primitives, plus
//!   10 copies of the level − 1 aggregate at 0.3 of the scale around it:
//!   N(L) = 10 + 10·N(L − 1) = 10, 110, 1110, 11110, 111110. Combined as a
//!   left comb from largest to smallest (the paper: "to limit ROI
//!   propagation and detail over-smoothing"); β = 0.15 × the scale. Smooth
//!   everywhere is one comb of all primitives sorted by scale, the others
//!   keep the aggregate's hierarchy (see `aggregate`).
//! - [`Kind::Boxes`] (Fig. 18 a-f): 16 rotated boxes, instanced uniformly on
//!   a 2^L × 2^L grid over [−1, 1]² at scale 2^−L: 16 · 4^L = 16 … 4096.
//! - [`Kind::SpherePairs`] (Fig. 18 g-l): 12 lenses, each the sharp
//!   intersection of two spheres that overlap by a quarter of their radius
//!   (99 % of the spheres' volume is cut away, the case that challenges
//!   ABVs), instanced the same way: 24 · 4^L = 24 … 6144.
//!
//! Blending ([`Blending`]): sharp unions everywhere; compact smooth unions
//! inside each aggregate or instance and sharp unions between them (the
//! paper's "smooth inside + min between"); or smooth unions everywhere.
//! β is proportional to the scale of the aggregate or instance, r_o = 2β.

use super::{Blend, Builder, NodeId, OpKind, Operator, Primitive, Scene, SceneError, Shape};
use glam::DVec3;

/// SplitMix64: a small, fast, well-mixed generator, so scenes are the same
/// on every platform and version (no dependency's algorithm can change).
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    /// A uniformly distributed unit vector.
    pub fn direction(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// A point uniformly in the ball of radius `r`.
    pub fn in_ball(&mut self, r: f64) -> DVec3 {
        self.direction() * (r * self.unit().cbrt())
    }
}

/// Which synthetic scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Fig. 16: recursive aggregates.
    Aggregate,
    /// Fig. 18: instanced rotated boxes.
    Boxes,
    /// Fig. 18: instanced lenses (intersected sphere pairs).
    SpherePairs,
}

/// How the parts are combined.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Blending {
    /// min everywhere.
    Sharp,
    /// G∪ inside an aggregate or instance, min between them.
    SmoothInside,
    /// G∪ everywhere.
    Smooth,
}

/// The highest level generated: level 5 of the aggregate (1,111,110
/// primitives) would not fit the 64 MiB file limit.
pub const MAX_LEVEL: u32 = 4;

impl Kind {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Aggregate => "aggregate",
            Kind::Boxes => "boxes",
            Kind::SpherePairs => "sphere-pairs",
        }
    }

    /// The number of primitives at `level`.
    pub fn primitives(self, level: u32) -> usize {
        match self {
            Kind::Aggregate => (0..=level).map(|k| 10usize.pow(k + 1)).sum(),
            Kind::Boxes => 16 * 4usize.pow(level),
            Kind::SpherePairs => 24 * 4usize.pow(level),
        }
    }

    /// The level with `count` primitives, if any.
    pub fn level_for(self, count: usize) -> Option<u32> {
        (0..=MAX_LEVEL).find(|&l| self.primitives(l) == count)
    }
}

/// The scene `kind` at `level` (0..=[`MAX_LEVEL`]).
pub fn generate(kind: Kind, level: u32, blending: Blending, seed: u64) -> Result<Scene, SceneError> {
    if level > MAX_LEVEL {
        return Err(SceneError::new("level", format!("{level} is above the highest level, {MAX_LEVEL}")));
    }
    let mut rng = Rng::new(seed);
    let mut b = Builder::default();
    let root = match kind {
        Kind::Aggregate => aggregate(&mut b, &mut rng, level, DVec3::ZERO, 1.0, blending),
        Kind::Boxes | Kind::SpherePairs => instances(&mut b, &mut rng, kind, level, blending),
    };
    b.finish(root)
}

fn smooth_union(beta: f64) -> Operator {
    Operator::smooth(OpKind::Union, Blend::new(sig(beta)))
}

/// `v` to 7 significant digits: generated files carry no more precision
/// than f32 can use, so they stay smaller (the 111,110-primitive aggregate
/// is 30 MB instead of 39) and still read back exactly.
fn sig(v: f64) -> f64 {
    format!("{v:.6e}").parse().unwrap_or(v)
}

/// Every number of `p` to 7 significant digits (profiles and grids, which
/// generated scenes do not have, keep theirs).
fn rounded(mut p: Primitive) -> Primitive {
    let r3 = |v: [f64; 3]| v.map(sig);
    if let Some((t, mut v)) = p.shape.analytic() {
        v.iter_mut().for_each(|x| *x = sig(*x));
        p.shape = Shape::from_analytic(t, &v);
    }
    let t = &mut p.transform;
    t.translate = r3(t.translate);
    t.scale = sig(t.scale);
    if let Some(r) = &mut t.rotate {
        r.axis = r3(r.axis);
        r.angle = sig(r.angle);
    }
    p
}

/// The operators inside a part and between parts at `scale`.
fn ops(blending: Blending, beta: f64) -> (Operator, Operator) {
    match blending {
        Blending::Sharp => (Operator::UNION, Operator::UNION),
        Blending::SmoothInside => (smooth_union(beta), Operator::UNION),
        Blending::Smooth => (smooth_union(beta), smooth_union(beta)),
    }
}

/// A random rotation: uniform axis, angle in [0, π).
fn rotation(rng: &mut Rng) -> ([f64; 3], f64) {
    (rng.direction().to_array(), rng.range(0.0, std::f64::consts::PI))
}

/// One of the base aggregate's shapes, by position in the base.
fn base_shape(rng: &mut Rng, k: usize) -> Shape {
    let u = rng.range(0.25, 0.45);
    let half = |rng: &mut Rng| [u, u * rng.range(0.5, 1.0), u * rng.range(0.5, 1.0)];
    match k {
        0 => Shape::Sphere { radius: 0.55 },
        5 => Shape::Sphere { radius: u },
        1 | 9 => Shape::Box { half: half(rng) },
        3 => {
            let h = half(rng);
            Shape::RoundBox { half: h, radius: 0.3 * h[0].min(h[1]).min(h[2]) }
        }
        2 | 8 => Shape::Capsule { a: [0.0, 0.0, -u], b: [0.0, 0.0, u], radius: 0.35 * u },
        4 => Shape::Torus { major: u, minor: 0.35 * u },
        6 => Shape::Cylinder { radius: 0.6 * u, half_height: u },
        _ => Shape::Octahedron { size: 1.3 * u },
    }
}

/// Places `shape` at `pos` (base units) in a part at `centre`, `scale`,
/// with a random rotation unless it is a sphere.
fn place(rng: &mut Rng, shape: Shape, pos: DVec3, centre: DVec3, scale: f64) -> Primitive {
    let mut p = Primitive::new(shape.clone());
    if !matches!(shape, Shape::Sphere { .. }) {
        let (axis, angle) = rotation(rng);
        p = p.rotated(axis, angle);
    }
    p.scaled(scale).translated((centre + pos * scale).to_array())
}

/// The ten directions of the sub-aggregates (a Fibonacci sphere).
fn directions() -> [DVec3; 10] {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    std::array::from_fn(|i| {
        let z = 1.0 - (2 * i + 1) as f64 / 10.0;
        let r = (1.0 - z * z).sqrt();
        let phi = golden * i as f64;
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

/// Fig. 16: the aggregate of `level` at `centre` and `scale`. Sharp and
/// smooth-inside keep the aggregate's hierarchy: a part's base combined
/// inside, then its ten sub-aggregates one by one. Smooth everywhere is one
/// left comb of every primitive from the largest scale to the smallest,
/// each joined with β of its own scale (the paper's order "to limit ROI
/// propagation"): a node's r⁺ is the largest r_o above it (`roi`), so in a
/// hierarchy every small primitive would inherit the top blends' range
/// (at level 3, 0.09 against primitives of size 0.01), while in the sorted
/// comb the ops above a primitive are never wider than its own.
fn aggregate(b: &mut Builder, rng: &mut Rng, level: u32, centre: DVec3, scale: f64, blending: Blending) -> NodeId {
    if blending == Blending::Smooth {
        let mut parts = Vec::new();
        aggregate_parts(b, rng, level, centre, scale, &mut parts);
        // Stable: within a scale, the order of generation.
        parts.sort_by(|a, b| b.1.total_cmp(&a.1));
        let mut acc = parts[0].0;
        for &(p, s) in &parts[1..] {
            acc = b.operator(smooth_union(0.15 * s), acc, p);
        }
        return acc;
    }
    let prims = aggregate_base(b, rng, centre, scale);
    let (inside, _) = ops(blending, 0.15 * scale);
    let mut acc = b.fold(inside, &prims);
    if level > 0 {
        let sub = 0.3 * scale;
        let (_, between) = ops(blending, 0.15 * sub);
        for d in directions() {
            let child = aggregate(b, rng, level - 1, centre + d * (1.6 * scale), sub, blending);
            acc = b.operator(between, acc, child);
        }
    }
    acc
}

/// The ten primitives of an aggregate's base at `centre` and `scale`.
fn aggregate_base(b: &mut Builder, rng: &mut Rng, centre: DVec3, scale: f64) -> Vec<NodeId> {
    (0..10)
        .map(|k| {
            let shape = base_shape(rng, k);
            let pos = if k == 0 { DVec3::ZERO } else { rng.in_ball(0.55) };
            b.primitive(rounded(place(rng, shape, pos, centre, scale)))
        })
        .collect()
}

/// Every primitive of the aggregate of `level`, with its scale, in the
/// order (and so with the random numbers) of the hierarchical aggregate.
fn aggregate_parts(b: &mut Builder, rng: &mut Rng, level: u32, centre: DVec3, scale: f64, out: &mut Vec<(NodeId, f64)>) {
    out.extend(aggregate_base(b, rng, centre, scale).into_iter().map(|p| (p, scale)));
    if level > 0 {
        for d in directions() {
            aggregate_parts(b, rng, level - 1, centre + d * (1.6 * scale), 0.3 * scale, out);
        }
    }
}

/// A part of the Fig. 18 base shape, in base units.
enum Part {
    Box(Primitive),
    Lens(Primitive, Primitive),
}

/// The base shape of Fig. 18: 16 rotated boxes or 12 lenses.
fn base_parts(rng: &mut Rng, kind: Kind) -> Vec<Part> {
    if kind == Kind::Boxes {
        return (0..16)
            .map(|_| {
                let pos = rng.in_ball(0.6);
                let half = [0, 1, 2].map(|_| rng.range(0.12, 0.3));
                let (axis, angle) = rotation(rng);
                Part::Box(Primitive::new(Shape::Box { half }).rotated(axis, angle).translated(pos.to_array()))
            })
            .collect();
    }
    (0..12)
        .map(|_| {
            let pos = rng.in_ball(0.6);
            let radius = rng.range(0.3, 0.5);
            let u = rng.direction() * (radius - 0.125 * radius);
            let s = |c: DVec3| Primitive::new(Shape::Sphere { radius }).translated(c.to_array());
            Part::Lens(s(pos - u), s(pos + u))
        })
        .collect()
}

/// `p` (base units) in the instance at `centre`, `scale`.
fn instance_of(p: &Primitive, centre: DVec3, scale: f64) -> Primitive {
    let mut q = p.clone();
    q.transform.scale = p.transform.scale * scale;
    q.transform.translate = (centre + DVec3::from(p.transform.translate) * scale).to_array();
    q
}

/// Fig. 18: the base shape on a 2^level × 2^level grid.
fn instances(b: &mut Builder, rng: &mut Rng, kind: Kind, level: u32, blending: Blending) -> NodeId {
    let parts = base_parts(rng, kind);
    let side = 1usize << level;
    let scale = 1.0 / side as f64;
    let (inside, between) = ops(blending, 0.1 * scale);
    let mut acc = None;
    for j in 0..side {
        for i in 0..side {
            let centre = DVec3::new((2 * i + 1) as f64 * scale - 1.0, (2 * j + 1) as f64 * scale - 1.0, 0.0);
            let items: Vec<NodeId> = parts
                .iter()
                .map(|part| match part {
                    Part::Box(p) => b.primitive(rounded(instance_of(p, centre, scale))),
                    Part::Lens(p, q) => {
                        let (l, r) = (b.primitive(rounded(instance_of(p, centre, scale))), b.primitive(rounded(instance_of(q, centre, scale))));
                        b.operator(Operator::INTERSECTION, l, r)
                    }
                })
                .collect();
            let inst = b.fold(inside, &items);
            acc = Some(match acc {
                None => inst,
                Some(a) => b.operator(between, a, inst),
            });
        }
    }
    acc.expect("at least one instance")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_the_papers() {
        let c = |k: Kind| (0..=MAX_LEVEL).map(|l| k.primitives(l)).collect::<Vec<_>>();
        assert_eq!(c(Kind::Aggregate), [10, 110, 1110, 11110, 111110]);
        assert_eq!(c(Kind::Boxes), [16, 64, 256, 1024, 4096]);
        assert_eq!(c(Kind::SpherePairs), [24, 96, 384, 1536, 6144]);
        assert_eq!(Kind::Boxes.level_for(256), Some(2));
        assert_eq!(Kind::Boxes.level_for(100), None);
    }

    #[test]
    fn small_levels_have_those_counts_and_are_deterministic() {
        for kind in [Kind::Aggregate, Kind::Boxes, Kind::SpherePairs] {
            for level in 0..=1 {
                let s = generate(kind, level, Blending::Smooth, 7).unwrap();
                assert_eq!(s.primitive_count(), kind.primitives(level));
                assert_eq!(s, generate(kind, level, Blending::Smooth, 7).unwrap());
            }
        }
    }

    /// The smooth aggregate is sorted so that no blend above a primitive is
    /// wider than its own: r⁺ = 2β = 0.3 × its scale. The hierarchy gave a
    /// level-2 primitive (scale 0.09) the top blends' 0.09, over three times.
    #[test]
    fn a_smooth_aggregate_keeps_each_range_of_interest_to_its_own_blend() {
        let s = generate(Kind::Aggregate, 2, Blending::Smooth, 5).unwrap();
        let roi = super::super::roi::ranges(&s);
        let mut smallest = f64::MAX;
        for (i, n) in s.nodes().iter().enumerate() {
            if let super::super::Node::Primitive(p) = n {
                let own = 0.3 * p.transform.scale;
                assert!(roi[i].hi <= own * (1.0 + 1e-6), "primitive {i}: r+ {} above {own}", roi[i].hi);
                smallest = smallest.min(p.transform.scale);
            }
        }
        assert!((smallest - 0.09).abs() < 1e-6);
        // The same primitives as the hierarchical variants, in the same order.
        let h = generate(Kind::Aggregate, 2, Blending::Sharp, 5).unwrap();
        let prims = |s: &Scene| s.nodes().iter().filter_map(|n| match n {
            super::super::Node::Primitive(p) => Some(p.clone()),
            _ => None,
        }).collect::<Vec<_>>();
        assert_eq!(prims(&s), prims(&h));
    }
}

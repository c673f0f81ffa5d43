//! Random blobtrees for the scene tests (after `scenes.py` and
//! `test_sparse.py` of the Python reference) and an f32 evaluator of the
//! `params` rows, written as the GPU interpreter reads them.
#![allow(dead_code)]

use glam::Vec3;
use crate::scene::generate::Rng;
use crate::scene::{Blend, Builder, Join, NodeId, OpKind, Operator, Primitive, Scene, Shape};

/// How leaves are combined.
#[derive(Clone, Copy, Debug)]
pub enum TreeShape {
    /// Adjacent pairs merged at random.
    Random,
    /// A left comb.
    Left,
    /// Pairs level by level.
    Balanced,
}

/// A primitive of kind `k` (0 sphere … 7 plane) near `centre`, size about
/// `scale`, randomly rotated and scaled.
pub fn primitive_of_kind(rng: &mut Rng, k: u64, centre: [f64; 3], scale: f64) -> Primitive {
    let u = |rng: &mut Rng, lo: f64, hi: f64| scale * rng.range(lo, hi);
    let shape = match k {
        0 => Shape::Sphere { radius: u(rng, 0.3, 1.0) },
        1 => Shape::Box { half: [0, 1, 2].map(|_| u(rng, 0.2, 0.8)) },
        2 => {
            let half = [0, 1, 2].map(|_| u(rng, 0.2, 0.8));
            Shape::RoundBox { half, radius: rng.range(0.0, 1.0) * half[0].min(half[1]).min(half[2]) }
        }
        3 => Shape::Capsule { a: [0, 1, 2].map(|_| u(rng, -0.5, 0.5)), b: [0, 1, 2].map(|_| u(rng, -0.5, 0.5)), radius: u(rng, 0.15, 0.4) },
        4 => Shape::Torus { major: u(rng, 0.3, 0.8), minor: u(rng, 0.1, 0.3) },
        5 => Shape::Cylinder { radius: u(rng, 0.2, 0.6), half_height: u(rng, 0.2, 0.8) },
        6 => Shape::Octahedron { size: u(rng, 0.3, 1.0) },
        _ => Shape::Plane { normal: rng.direction().to_array(), offset: rng.range(-0.5, 0.5) },
    };
    let axis = rng.direction().to_array();
    let angle = rng.range(-3.0, 3.0);
    let s = rng.range(0.6, 1.4);
    Primitive::new(shape).rotated(axis, angle).scaled(s).translated(centre)
}

/// A random primitive (planes only if `plane`).
pub fn random_primitive(rng: &mut Rng, centre: [f64; 3], scale: f64, plane: bool) -> Primitive {
    let k = rng.below(if plane { 8 } else { 7 });
    primitive_of_kind(rng, k, centre, scale)
}

/// A random tree of `n` primitives. `cluster`: centres on a random walk
/// and mostly unions (scenes.py's `cluster_tree`); else uniform centres in
/// [−3, 3]³, the three operators alike, and a plane now and then
/// (test_sparse.py's `rand_tree`). Operators are compact smooth with
/// probability `smooth`, r_o ∈ [7β/6, 3β].
pub fn random_tree(rng: &mut Rng, n: usize, shape: TreeShape, smooth: f64, cluster: bool) -> Scene {
    let mut b = Builder::default();
    let mut c = [0.0f64; 3];
    let mut leaves: Vec<NodeId> = Vec::new();
    for _ in 0..n {
        let (centre, scale) = if cluster {
            c = c.map(|x| x + rng.range(-1.0, 1.0) * 0.6);
            (c, rng.range(0.4, 1.0))
        } else {
            ([0, 1, 2].map(|_| rng.range(-3.0, 3.0)), rng.range(0.4, 1.2))
        };
        let plane = !cluster && rng.unit() < 0.05;
        let p = if plane { primitive_of_kind(rng, 7, centre, scale) } else { random_primitive(rng, centre, scale, false) };
        leaves.push(b.primitive(p));
    }
    let op = |b: &mut Builder, rng: &mut Rng, l: NodeId, r: NodeId| {
        let w = rng.unit();
        let kind = match (cluster, w) {
            (true, w) if w < 0.6 => OpKind::Union,
            (true, w) if w < 0.75 => OpKind::Intersection,
            (true, _) => OpKind::Difference,
            (false, w) => [OpKind::Union, OpKind::Intersection, OpKind::Difference][(w * 3.0) as usize],
        };
        let o = if rng.unit() < smooth {
            let beta = if cluster { rng.range(0.1, 0.8) } else { rng.range(0.05, 0.6) };
            Operator::smooth(kind, Blend { beta, range: beta * rng.range(7.0 / 6.0, 3.0) })
        } else {
            Operator::sharp(kind)
        };
        b.operator(o, l, r)
    };
    let root = match shape {
        TreeShape::Left => {
            let mut t = leaves[0];
            for &l in &leaves[1..] {
                t = op(&mut b, rng, t, l);
            }
            t
        }
        TreeShape::Balanced => {
            let mut lv = leaves;
            while lv.len() > 1 {
                let mut next = Vec::new();
                for pair in lv.chunks(2) {
                    next.push(if pair.len() == 2 { op(&mut b, rng, pair[0], pair[1]) } else { pair[0] });
                }
                lv = next;
            }
            lv[0]
        }
        TreeShape::Random => {
            let mut lv = leaves;
            while lv.len() > 1 {
                let i = rng.below(lv.len() as u64 - 1) as usize;
                let m = op(&mut b, rng, lv[i], lv[i + 1]);
                lv.splice(i..i + 2, [m]);
            }
            lv[0]
        }
    };
    b.finish(root).unwrap()
}

/// Up to `k` points where |f| < `band`, by rejection in the box around the
/// bounded primitives' bounding volumes (grown by 1).
pub fn surface_points(scene: &Scene, rng: &mut Rng, k: usize, band: f64) -> Vec<[f64; 3]> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for n in scene.nodes() {
        if let crate::scene::Node::Primitive(p) = n {
            let bb = crate::scene::roi::abv(p, 0.0).aabb();
            if bb.is_bounded() {
                for a in 0..3 {
                    lo[a] = lo[a].min(bb.min[a] - 1.0);
                    hi[a] = hi[a].max(bb.max[a] + 1.0);
                }
            }
        }
    }
    let mut pts = Vec::new();
    for _ in 0..k * 40 {
        let p = [0, 1, 2].map(|a| rng.range(lo[a], hi[a]));
        if scene.eval(p).abs() < band {
            pts.push(p);
            if pts.len() >= k {
                break;
            }
        }
    }
    pts
}

fn boxd(q: Vec3, b: Vec3) -> f32 {
    let d = q.abs() - b;
    d.max(Vec3::ZERO).length() + d.x.max(d.y.max(d.z)).min(0.0)
}

/// Primitive type `ty` evaluated in f32 from its `params` rows at `p`.
pub fn eval_rows(ty: u32, rows: &[[f32; 4]], p: [f64; 3]) -> f64 {
    let p = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
    // q = (w^2 - |u|^2) v + 2 (u.v) u + 2 w (u x v), s = 1/|Q|^2.
    let (u, w) = (Vec3::new(rows[0][0], rows[0][1], rows[0][2]), rows[0][3]);
    let v = p - Vec3::new(rows[1][0], rows[1][1], rows[1][2]);
    let q = (w * w - u.dot(u)) * v + 2.0 * u.dot(v) * u + 2.0 * w * u.cross(v);
    let s = 1.0 / (u.dot(u) + w * w);
    let c = rows[2];
    let h = Vec3::new(c[0], c[1], c[2]);
    // The form the type must have been given (layout: src/scene/linear.rs).
    let form = match ty {
        1..=4 => 0.0,
        5 | 6 => 1.0,
        7 => 2.0,
        8 => 3.0,
        _ => panic!("type {ty}"),
    };
    assert_eq!(rows[1][3], form, "type {ty}: form");
    let local = match form as u32 {
        0 => boxd(q, h) - c[3],
        1 => boxd(Vec3::new(q.truncate().length() - c[1], 0.0, q.z), Vec3::new(c[0], 1e30, c[2])) - c[3],
        2 => (q.x.abs() + q.y.abs() + q.z.abs() - c[0]) / 3f32.sqrt(),
        _ => h.dot(q),
    };
    (s * local) as f64
}

/// A random profile of size about `scale` (every type; polygons of 3 to
/// 16 vertices, star-shaped around the origin so they are simple).
pub fn random_profile(rng: &mut Rng, scale: f64) -> crate::scene::Profile {
    use crate::scene::Profile;
    let u = |rng: &mut Rng, lo: f64, hi: f64| scale * rng.range(lo, hi);
    match rng.below(5) {
        0 => Profile::Circle { radius: u(rng, 0.2, 0.7) },
        1 => Profile::Rect { half: [u(rng, 0.2, 0.7), u(rng, 0.2, 0.7)] },
        2 => {
            let half = [u(rng, 0.2, 0.7), u(rng, 0.2, 0.7)];
            Profile::RoundRect { half, radius: rng.range(0.0, 1.0) * half[0].min(half[1]) }
        }
        3 => Profile::Capsule { a: [u(rng, -0.5, 0.5), u(rng, -0.5, 0.5)], b: [u(rng, -0.5, 0.5), u(rng, -0.5, 0.5)], radius: u(rng, 0.1, 0.3) },
        _ => {
            let n = 3 + rng.below(14) as usize;
            let pts: Vec<[f64; 2]> = (0..n)
                .map(|k| {
                    let a = std::f64::consts::TAU * (k as f64 + rng.range(0.0, 0.8)) / n as f64;
                    let r = u(rng, 0.2, 0.8);
                    [r * a.cos(), r * a.sin()]
                })
                .collect();
            Profile::polygon(&pts)
        }
    }
}

/// A random extruded or revolved primitive near `centre`, randomly placed.
pub fn random_profiled(rng: &mut Rng, centre: [f64; 3], scale: f64) -> Primitive {
    let profile = random_profile(rng, scale);
    let shape = if rng.unit() < 0.5 {
        Shape::Extrude { profile, half_height: scale * rng.range(0.1, 0.6) }
    } else {
        // Keep some of the profile on the near side of the axis.
        let reach = profile.bounds().1[0];
        Shape::Revolve { profile, offset: (scale * rng.range(0.0, 0.8)).max(-reach + 0.05 * scale) }
    };
    let axis = rng.direction().to_array();
    Primitive::new(shape).rotated(axis, rng.range(-3.0, 3.0)).scaled(rng.range(0.6, 1.4)).translated(centre)
}

/// A random unary node's operation (displacements gentle, so sampled
/// Lipschitz checks stay meaningful).
pub fn random_unary(rng: &mut Rng) -> crate::scene::Unary {
    use crate::scene::Unary;
    match rng.below(4) {
        0 => Unary::Offset { distance: rng.range(-0.1, 0.25) },
        1 => Unary::Shell { thickness: rng.range(0.05, 0.3) },
        2 => Unary::Infill { period: rng.range(0.3, 1.2), thickness: rng.range(0.03, 0.15) },
        _ => Unary::Displace { amplitude: rng.range(0.0, 0.08), frequency: rng.range(1.0, 6.0) },
    }
}

/// A random tree of `n` primitives of every type (basic and profiled; no
/// planes), clustered, combined at random by every operator, sharp or
/// compact smooth, with a unary node over a leaf or a combination now and
/// then.
pub fn zoo_tree(rng: &mut Rng, n: usize) -> Scene {
    let mut b = Builder::default();
    let mut c = [0.0f64; 3];
    let mut items: Vec<NodeId> = Vec::new();
    for _ in 0..n {
        c = c.map(|x| x + rng.range(-1.0, 1.0) * 0.6);
        let scale = rng.range(0.4, 1.0);
        let p = if rng.unit() < 0.5 { random_profiled(rng, c, scale) } else { random_primitive(rng, c, scale, false) };
        let mut id = b.primitive(p);
        if rng.unit() < 0.2 {
            id = b.unary(random_unary(rng), id);
        }
        items.push(id);
    }
    while items.len() > 1 {
        let i = rng.below(items.len() as u64 - 1) as usize;
        let kind = [OpKind::Union, OpKind::Union, OpKind::Intersection, OpKind::Difference][rng.below(4) as usize];
        let w = rng.unit();
        let op = if w < 0.35 {
            let beta = rng.range(0.1, 0.6);
            Operator::smooth(kind, Blend { beta, range: beta * rng.range(7.0 / 6.0, 3.0) })
        } else if w < 0.6 {
            let size = rng.range(0.05, 0.4);
            match rng.below(3) {
                0 => Operator::joined(kind, Join::Chamfer { radius: size }),
                1 => Operator::joined(kind, Join::Round { radius: size }),
                _ => Operator::joined(OpKind::Union, Join::Sum { range: size }),
            }
        } else {
            Operator::sharp(kind)
        };
        let mut m = b.operator(op, items[i], items[i + 1]);
        if rng.unit() < 0.2 {
            m = b.unary(random_unary(rng), m);
        }
        items.splice(i..i + 2, [m]);
    }
    b.finish(items[0]).unwrap()
}

/// Equal bit for bit, ∅ included.
pub fn same(a: Option<f64>, b: Option<f64>) -> bool {
    a.map(f64::to_bits) == b.map(f64::to_bits)
}

/// The sparse traversal of the active primitives `a` (post-order indices;
/// `active` the same set by scene node) at `p` equals the masked evaluation
/// bit for bit, with fast and parent ancestors, directly and through its
/// pruned view, the view built alone is the same, and the traversal stack
/// stays below the scene's evaluation stack. Returns the masked value and
/// the deepest traversal stack.
pub fn assert_sparse_is_masked(lin: &crate::scene::linear::Linear, scene: &Scene, p: [f64; 3], active: &[bool], a: &[u32]) -> (Option<f64>, u32) {
    use crate::scene::sparse::{self, Ancestors};
    let reference = scene.eval_masked(p, active);
    let mut max_stack = 0;
    for anc in [Ancestors::Fast, Ancestors::Parent] {
        let t = sparse::traverse(lin, scene, p, a, anc).unwrap();
        assert!(same(t.value, reference), "{anc:?}: {:?} vs {reference:?}", t.value);
        assert!(same(sparse::eval_view(lin, scene, p, &t.view), reference));
        assert_eq!(sparse::build_view(lin, scene, a, anc).unwrap().view, t.view);
        assert!(t.max_stack < lin.stack_depth.max(1), "stack {} of depth {}", t.max_stack, lin.stack_depth);
        max_stack = max_stack.max(t.max_stack);
    }
    (reference, max_stack)
}

/// A formula of every distance form of the scene node zoo but the newest
/// (profiles, extrusions, revolutions, unary nodes).
pub const EVERY_FORM: &str = "\
    star = polygon(0, 0.5, 0.12, 0.15, 0.48, 0.15, 0.2, -0.05, 0.3, -0.4, 0, -0.18, -0.3, -0.4, -0.2, -0.05, -0.48, 0.15, -0.12, 0.15);
    a = translate(-1.5, 0.8, 0, extrude(0.2, star));
    b = translate(-0.5, 0.8, 0, rotate(1, 0, 0, 0.6, extrude(0.15, roundrect(0.35, 0.25, 0.1))));
    c = translate(0.5, 0.8, 0, revolve(0.3, capsule2d(-0.1, -0.2, 0.15, 0.2, 0.08)));
    d = translate(1.5, 0.8, 0, scale(1.5, revolve(0.2, rect(0.1, 0.15))));
    m = translate(-0.5, -0.8, 0, offset(0.05, extrude(0.2, circle(0.3))));
    g = translate(0.5, -0.8, 0, shell(0.06, sphere(0.4)));
    h = infill(0.4, 0.05, translate(1.5, -0.8, 0, roundbox(0.4, 0.4, 0.4, 0.05)));
    k = displace(0.04, 5, translate(-1.5, -0.8, 0, torus(0.35, 0.1)));
    union(a, b, c, d, compact_union(m, g, 0.1), h, k)";

/// Two pictures of one view compared pixel by pixel: (pixels both hit,
/// of those the ones whose depths differ by more than a pixel's footprint,
/// pixels hit in one picture only). A footprint is the pixel's height at
/// its depth: both traversals stop within the screen-space hit criterion.
pub fn picture_agreement(a: &crate::render::Frame, b: &crate::render::Frame, s: &crate::render::Settings) -> (usize, usize, usize) {
    use crate::render::Status;
    let (mut both, mut far, mut differ) = (0, 0, 0);
    let per_pixel = 2.0 * (s.camera.fov_deg as f32 / 2.0).to_radians().tan() / s.height as f32;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        if p.status != q.status {
            differ += 1;
        } else if p.status == Status::Hit {
            both += 1;
            far += ((p.depth - q.depth).abs() > p.depth * per_pixel) as usize;
        }
    }
    (both, far, differ)
}

/// At each of `points`, with the active set A = {p : f_p ≤ r_p⁺}: every
/// active primitive's ABV holds the point, the sparse traversal equals the
/// masked evaluation ([`assert_sparse_is_masked`]), and every node of the
/// masked tree is exact inside its range of interest and on the same side
/// outside. Returns the number of node checks.
pub fn assert_sparse_and_ranges(scene: &Scene, points: &[[f64; 3]]) -> usize {
    use crate::scene::{linear::Linear, roi, Node};
    let lin = Linear::new(scene).unwrap();
    let r = roi::ranges(scene);
    let mut checks = 0;
    for &p in points {
        let mut active = vec![false; scene.len()];
        let mut a = Vec::new();
        for (j, &k) in lin.primitives.iter().enumerate() {
            let i = lin.order[k as usize];
            let Node::Primitive(q) = &scene.nodes()[i] else { unreachable!() };
            if q.distance(p) <= r[i].hi {
                assert!(lin.abvs[j].contains(p), "{q:?} at {p:?} outside its ABV");
                active[i] = true;
                a.push(k);
            }
        }
        assert_sparse_is_masked(&lin, scene, p, &active, &a);
        let (full, masked) = (scene.eval_nodes(p), scene.eval_masked_nodes(p, &active));
        for i in 0..scene.len() {
            let (f, s) = (full[i], masked[i].unwrap_or(f64::INFINITY));
            let ok = if f > r[i].hi { s > r[i].hi } else if f < r[i].lo { s < r[i].lo } else { s == f };
            assert!(ok, "node {i} ({:?}): full {f}, masked {s}, range {:?}", scene.nodes()[i], r[i]);
            checks += 1;
        }
    }
    checks
}

/// Formula `f` drawn through the scene field (with the bound its blobtree
/// is traced with) and compiled, sphere traced with that bound, in view `s`.
pub fn scene_and_compiled(f: &crate::Formula, s: &crate::render::Settings) -> (crate::render::Frame, crate::render::Frame) {
    use crate::render::{SphereOptions, Traversal};
    let t = Traversal::Sphere(SphereOptions::default());
    let (scene, lipschitz) = crate::choice::scene(f, &[], &t).unwrap();
    let o = SphereOptions { lipschitz, ..SphereOptions::default() };
    let own = crate::gpu::Gpu::new().unwrap();
    let a = crate::gpu::Renderer::new(&own, scene.source(&f.ir), Traversal::Sphere(o.clone())).unwrap().render(s).unwrap();
    let b = crate::gpu::Renderer::sphere(&own, &f.ir, o).unwrap().render(s).unwrap();
    (a, b)
}

/// For 200 primitives from `make`: each is 1-Lipschitz (difference
/// quotients over short random steps), and its bounding volume at a random
/// level r⁺ holds every sampled point with f ≤ r⁺. Returns how many sampled
/// points fell in such a set (for the caller's not-vacuous bound).
pub fn check_lipschitz_and_bounding_volume(rng: &mut Rng, mut make: impl FnMut(&mut Rng) -> Primitive) -> usize {
    use glam::DVec3;
    let mut inside = 0;
    for _ in 0..200 {
        let prim = make(rng);
        for _ in 0..300 {
            let a = DVec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
            let b = a + rng.direction() * rng.range(1e-4, 0.05);
            let slope = (prim.distance(a.to_array()) - prim.distance(b.to_array())).abs() / (a - b).length();
            assert!(slope <= 1.0 + 1e-6, "{prim:?}: {slope}");
        }
        let (r_plus, abv, points) = region_of_interest(rng, &prim);
        inside += points.len();
        for p in points {
            assert!(abv.contains(p), "{prim:?} r+ {r_plus}: {p:?} outside {abv:?}");
        }
    }
    inside
}

/// A random level r⁺ of `prim` (0 or up to 0.8), its bounding volume at
/// that level, and the points among 300 samples of the volume's box (grown
/// by 0.5) where f ≤ r⁺: what the volume must hold.
pub fn region_of_interest(rng: &mut Rng, prim: &Primitive) -> (f64, crate::scene::roi::Abv, Vec<[f64; 3]>) {
    let r_plus = [0.0, rng.range(0.0, 0.8)][rng.below(2) as usize];
    let abv = crate::scene::roi::abv(prim, r_plus);
    let bb = abv.aabb();
    let points = (0..300).map(|_| [0, 1, 2].map(|k| rng.range(bb.min[k] - 0.5, bb.max[k] + 0.5))).filter(|&p| prim.distance(p) <= r_plus).collect();
    (r_plus, abv, points)
}

/// Ten primitives, every other one from `special(rng, centre, scale)` and
/// the rest basic ones, and one more `special` twisted: the first six under
/// sharp unions, the rest under a smooth one.
pub fn mixed_scene(rng: &mut Rng, special: impl Fn(&mut Rng, [f64; 3], f64) -> Primitive) -> Scene {
    let mut b = Builder::default();
    let mut items = Vec::new();
    for k in 0..10 {
        let centre = [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-1.0, 1.0)];
        let p = if k % 2 == 0 { special(rng, centre, 1.0) } else { random_primitive(rng, centre, 0.6, false) };
        items.push(b.primitive(p));
    }
    let mut twisted = special(rng, [0.0, 0.0, 1.5], 0.8);
    twisted.warp = Some(crate::scene::warp::Warp { kind: crate::scene::warp::WarpKind::Twist, rate: 0.8, frame: Default::default(), clamp: None });
    items.push(b.primitive(twisted));
    let smooth = Operator::smooth(OpKind::Union, Blend::new(0.2));
    let left = b.fold(Operator::UNION, &items[..6]);
    let right = b.fold(smooth, &items[6..]);
    let root = b.operator(Operator::UNION, left, right);
    b.finish(root).unwrap()
}

//! Bisecting scenes: the device's interval enclosures of every node type
//! hold the f64 reference's values (dense sampling of random boxes), and
//! scenes bisected through the scene field match the compiled formula's
//! bisection, sphere tracing and analytic depths, thin features included.

use super::common::gpu;
use crate::field::FieldSource;
use crate::gpu::eval::{eval_boxes_scene, Box8};
use crate::scene::generate::Rng;
use crate::scene::linear::Linear;
use crate::scene::{format, Scene};

/// Scenes that hold every node type between them (with the voxel grids of
/// `examples/pebbles.scene.json`, [`node_type_scenes`]): the primitive types
/// and their shared forms, profiles (polygon, circle, rect, round rect,
/// capsule; extruded and revolved), density blobs summed by `sum_union`,
/// twists and bends, the unary types, the joins, and sharp, smooth and
/// compact operators of the three kinds.
const NODE_TYPE_SCENES: [&str; 4] = [
    include_str!("../../examples/blobs.scene.json"),
    include_str!("../../examples/profiles.scene.json"),
    include_str!("../../examples/procedural.scene.json"),
    r#"{"isotrace_scene": 1, "root": 17,
 "nodes": [
  {"type": "cone", "radius": 0.5, "half_height": 0.6, "top_radius": 0.1, "translate": [-1.0, 0.0, 0.0], "rotate": [1.0, 0.0, 0.0, 0.5]},
  {"type": "torus", "major": 0.5, "minor": 0.12, "translate": [1.0, 0.2, 0.0], "warp": {"type": "twist", "rate": 3.0, "translate": [0.2, 0.0, 0.0]}},
  {"type": "smooth_union", "left": 0, "right": 1, "beta": 0.4},
  {"type": "sphere", "radius": 0.45, "translate": [0.0, -0.9, 0.0]},
  {"type": "displace", "child": 3, "amplitude": 0.05, "frequency": 6.0},
  {"type": "chamfer_union", "left": 2, "right": 4, "radius": 0.2},
  {"type": "box", "half": [0.5, 0.5, 0.5], "translate": [0.0, 1.0, 0.0]},
  {"type": "infill", "child": 6, "period": 0.5, "thickness": 0.06},
  {"type": "sphere", "radius": 0.6, "translate": [0.0, 1.1, 0.1]},
  {"type": "round_intersection", "left": 7, "right": 8, "radius": 0.1},
  {"type": "union", "left": 5, "right": 9},
  {"type": "extrude", "profile": {"type": "rect", "half": [0.2, 0.3]}, "half_height": 0.3, "translate": [0.0, 0.0, 1.0]},
  {"type": "cylinder", "radius": 0.15, "half_height": 0.5, "translate": [0.0, 0.0, 1.0], "warp": {"type": "bend", "rate": 0.8, "translate": [0.0, 0.0, 0.9]}},
  {"type": "smooth_difference", "left": 11, "right": 12, "beta": 0.1, "r_o": 0.3},
  {"type": "sphere", "radius": 0.3, "translate": [0.1, 0.0, 1.2]},
  {"type": "smooth_intersection", "left": 13, "right": 14, "beta": 0.2},
  {"type": "offset", "child": 10, "distance": 0.01},
  {"type": "smooth_union", "left": 16, "right": 15, "beta": 0.2, "r_o": 0.5}
 ]}"#,
];

/// Every node type's scenes, named.
pub(super) fn node_type_scenes() -> Vec<(String, Scene)> {
    let mut out: Vec<(String, Scene)> = NODE_TYPE_SCENES.iter().enumerate().map(|(k, t)| (format!("scene {k}"), format::parse(t).unwrap_or_else(|e| panic!("scene {k}: {e}")))).collect();
    let pebbles = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/pebbles.scene.json");
    out.push(("pebbles".into(), format::load(&pebbles).unwrap()));
    out
}

/// A random box in the scene's box `b`, with sides from 1e-4 to half the
/// box (small boxes near surfaces are what bisection's last levels ask).
pub(super) fn random_box(rng: &mut Rng, b: &[f64; 6]) -> [f64; 6] {
    let mut out = [0.0; 6];
    let scale = 10f64.powf(rng.range(-4.0, -0.3));
    for a in 0..3 {
        let (lo, hi) = (b[2 * a], b[2 * a + 1]);
        let w = scale * (hi - lo);
        let x = rng.range(lo, hi - w);
        out[2 * a] = x;
        out[2 * a + 1] = x + w;
    }
    out
}

/// The reference's smallest and largest value over a box: its corners, its
/// centre and random points.
pub(super) fn sampled_range(scene: &Scene, rng: &mut Rng, b: &[f64; 6], n: usize) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut take = |p: [f64; 3]| {
        let v = scene.eval(p);
        lo = lo.min(v);
        hi = hi.max(v);
    };
    for k in 0..8 {
        take([b[k & 1], b[2 + ((k >> 1) & 1)], b[4 + ((k >> 2) & 1)]]);
    }
    take([0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])]);
    for _ in 0..n {
        take([rng.range(b[0], b[1]), rng.range(b[2], b[3]), rng.range(b[4], b[5])]);
    }
    (lo, hi)
}

#[test]
fn every_node_types_enclosure_holds_the_references_values() {
    let gpu = gpu();
    let mut rng = Rng::new(0x5eed_b15e);
    let mut total = 0;
    for (k, scene) in node_type_scenes() {
        let lin = Linear::new(&scene).unwrap();
        let data = lin.field_data();
        let bbox = lin.bounds.padded().unwrap_or([-3.0, 3.0, -3.0, 3.0, -3.0, 3.0]);
        let boxes: Vec<[f64; 6]> = (0..25_000).map(|_| random_box(&mut rng, &bbox)).collect();
        let b8: Vec<Box8> = boxes.iter().map(|b| [b[0] as f32, b[1] as f32, b[2] as f32, b[3] as f32, b[4] as f32, b[5] as f32, 0.0, 0.0]).collect();
        let got = eval_boxes_scene(gpu, &data, &b8).unwrap();
        let mut escapes = Vec::new();
        let mut straddle = 0;
        for (i, e) in got.iter().enumerate() {
            // The f32 box the device saw.
            let b32 = b8[i].map(f64::from);
            let f = [b32[0], b32[1], b32[2], b32[3], b32[4], b32[5]];
            let (lo, hi) = sampled_range(&scene, &mut rng, &f, 24);
            let slack = 1e-5 * (1.0 + lo.abs().max(hi.abs()));
            if !(f64::from(e[0]) <= lo + slack && f64::from(e[1]) >= hi - slack) {
                escapes.push((f, lo, hi, *e));
            }
            straddle += usize::from(e[0] < 0.0 && e[1] > 0.0);
        }
        total += boxes.len();
        assert!(escapes.is_empty(), "scene {k}: {} of {} enclosures miss sampled values, e.g. {:?}", escapes.len(), boxes.len(), &escapes[..escapes.len().min(4)]);
        // Not a vacuous pass: many boxes are proven on one side of the surface
        // (fewer with grids, whose boxes over several cells give the whole line).
        assert!(straddle * 4 < boxes.len() * 3, "scene {k}: {straddle} of {} enclosures straddle 0", boxes.len());
        assert!(data.has_enclosures());
    }
    assert!(total >= 100_000);
}

pub(super) fn bisect_ia() -> crate::render::Traversal {
    crate::render::Traversal::Bisect(crate::render::BisectOptions::new(crate::ir::Domain::Interval))
}

/// A scene's frame at `w` × `h`, framed as `render` frames it.
pub(super) fn scene_settings(lin: &Linear, w: u32, h: u32) -> crate::render::Settings {
    let b = lin.bounds.padded().unwrap_or([-3.0, 3.0, -3.0, 3.0, -3.0, 3.0]);
    crate::render::Settings::for_box(b, w, h)
}

/// The first sign change of the reference on the ray eye + d t (|d| = 1)
/// up to `far`, stepping by `step`.
fn first_root(scene: &Scene, eye: glam::DVec3, d: glam::DVec3, far: f64, step: f64) -> Option<f64> {
    let mut prev = scene.eval(eye.to_array()) <= 0.0;
    let mut t = 0.0;
    while t < far {
        t += step;
        let inside = scene.eval((eye + d * t).to_array()) <= 0.0;
        if inside != prev {
            return Some(t);
        }
        prev = inside;
    }
    None
}

/// How near `p` is to the reference's surface: |f| (a distance field's
/// value), or |f|/|∇f| where f is steeper (a formula's value says nothing
/// of distance until divided by its slope).
fn distance_estimate(scene: &Scene, p: glam::DVec3) -> f64 {
    let h = 1e-6 * (1.0 + p.length());
    let v = scene.eval(p.to_array());
    let g = glam::DVec3::new(
        scene.eval((p + glam::DVec3::X * h).to_array()) - scene.eval((p - glam::DVec3::X * h).to_array()),
        scene.eval((p + glam::DVec3::Y * h).to_array()) - scene.eval((p - glam::DVec3::Y * h).to_array()),
        scene.eval((p + glam::DVec3::Z * h).to_array()) - scene.eval((p - glam::DVec3::Z * h).to_array()),
    ) / (2.0 * h);
    v.abs() / g.length().max(1.0)
}

/// Checks a bisected scene frame against another path's frame (`other`,
/// the compiled formula's) and the f64 reference, which decides where the
/// two differ: bisection finds every root the other path finds that the
/// reference has, and a hit of its
/// own lies within eps of the reference's surface (a ray grazing a surface
/// within eps hits it: the robust side of the traversal) or at the
/// reference's first root. Returns the hits and the pixels that differ.
pub(super) fn check_bisected(scene: &Scene, s: &crate::render::Settings, ours: &crate::render::Frame, other: &crate::render::Frame, tol: f64) -> (usize, usize) {
    check_bisected_grazing(scene, s, ours, other, tol, 0.0, 2.0)
}

/// [`check_bisected`], where a hit of ours before the reference's first
/// root is also right when the other path hits within `graze` footprints
/// of it (a ray grazing a surface), or when it lies within `near` eps of
/// the surface (to first order; [`check_bisected`]: 2). Intervals of a
/// polynomial overestimate by its slope times the cell: over the last
/// cells of a ray a few eps from the surface they need not exclude 0.
pub(super) fn check_bisected_grazing(scene: &Scene, s: &crate::render::Settings, ours: &crate::render::Frame, other: &crate::render::Frame, tol: f64, graze: f64, near: f64) -> (usize, usize) {
    use crate::render::Status;
    let (w, h) = (s.width, s.height);
    let cf = s.camera.frame().unwrap();
    let eye = s.camera.eye;
    let (mut hits, mut differ) = (0, 0);
    for (i, (p, q)) in ours.pixels.iter().zip(&other.pixels).enumerate() {
        let (x, y) = ((i as u32) % w, (i as u32) / w);
        assert!(p.status != Status::Unresolved, "pixel ({x}, {y}) unresolved");
        hits += usize::from(p.status == Status::Hit);
        let (pd, qd) = (f64::from(p.depth), f64::from(q.depth));
        let foot = 2.0 * cf.tan_half_fov * pd.min(qd).max(1.0) / f64::from(h);
        let agree = p.status == q.status && (p.status != Status::Hit || (pd - qd).abs() <= tol * foot);
        if agree {
            continue;
        }
        differ += 1;
        let d = crate::render::Camera::ray(&cf, x, y, w, h);
        let far = [pd, qd].into_iter().filter(|t| t.is_finite()).fold(0.0, f64::max) + 1.0;
        let root = first_root(scene, eye, d, far, 1e-4);
        if p.status != Status::Hit {
            assert!(root.is_none(), "pixel ({x}, {y}): missed the root at {root:?} (the other path's hit: {qd})");
            continue;
        }
        let at_root = root.is_some_and(|t| (t - pd).abs() <= foot);
        let near = distance_estimate(scene, eye + d * pd) <= near * s.eps && root.is_none_or(|t| t >= pd - foot);
        let grazing = root.is_none_or(|t| t >= pd - foot) && q.status == Status::Hit && (pd - qd).abs() <= graze * foot;
        assert!(at_root || near || grazing, "pixel ({x}, {y}): hit at {pd}, the reference's first root at {root:?} (the other path's: {qd})");
    }
    (hits, differ)
}

#[test]
fn bisected_scenes_draw_what_the_compiled_formula_and_sphere_tracing_draw() {
    let gpu = gpu();
    for (k, scene) in node_type_scenes().into_iter().take(4) {
        let lin = Linear::new(&scene).unwrap();
        let data = lin.field_data();
        let s = scene_settings(&lin, 160, 120);
        let mut r = crate::gpu::Renderer::new(gpu, &data, bisect_ia()).unwrap();
        let sparse = r.render(&s).unwrap();
        r.set_dense(true);
        let dense = r.render(&s).unwrap();
        // The pruned trees draw what the whole tree draws (to rounding: a
        // pruned tree fuses sharp operators into their leaves).
        for (i, (p, q)) in sparse.pixels.iter().zip(&dense.pixels).enumerate() {
            assert!(p.status == q.status && (p.status != crate::render::Status::Hit || (p.depth - q.depth).abs() <= 1e-4 * p.depth.max(1.0)), "{k}: pixel {i}: pruned trees {p:?}, whole tree {q:?}");
        }
        // Against sphere tracing on the scenes of distance fields (scene 3's
        // gyroid infill is none: rays graze its sheets within half a pixel,
        // where sphere tracing's screen-space criterion stops).
        if k != "scene 3" {
            let sphere = crate::render::Traversal::Sphere(crate::render::SphereOptions { lipschitz: lin.lipschitz(), ..Default::default() });
            let traced = crate::gpu::Renderer::new(gpu, &data, sphere).unwrap().render(&s).unwrap();
            // Sphere tracing stops within its screen-space width: its depths
            // are a few footprints off at grazing angles, and its silhouettes
            // take in rays within half a pixel of the surface. Each
            // difference is checked against the reference.
            let (hits, differ) = check_bisected(&scene, &s, &sparse, &traced, 4.0);
            assert!(hits > 500 && differ * 4 <= hits, "{k}: {differ} pixels of {hits} hits differ from sphere tracing's");
        }
        // The polygon profiles' formula form draws sheets of its own where
        // its even-odd sign flips (scene 1): compared with the scene path only.
        if k == "scene 1" {
            continue;
        }
        let f = crate::Formula::compile("<scene>", &scene.to_formula().unwrap()).unwrap();
        // In IA, as the scene: the compact operators' formula form keeps
        // its enclosures bounded on the edge of R_o (`blend_gated`).
        let compiled = crate::gpu::Renderer::new(gpu, &f.ir, bisect_ia()).unwrap().render(&s).unwrap();
        let (hits, differ) = check_bisected(&scene, &s, &sparse, &compiled, 1.0);
        assert!(hits > 300 && differ * 20 <= hits, "{k}: {differ} pixels of {hits} hits differ from the compiled formula's");
    }
}

/// The scene of `nodes` (JSON array entries) with root `root`.
pub(super) fn scene_of(nodes: &[String], root: usize) -> Scene {
    format::parse(&format!("{{\"isotrace_scene\": 1, \"root\": {root}, \"nodes\": [{}]}}", nodes.join(", "))).unwrap()
}

/// A shell 1e-4 thick around a unit sphere (far thinner than eps) and a
/// grid of balls half a pixel across: every pixel whose ray meets one of
/// them (analytically) is a hit, at the depth of its front, within eps.
/// Bisection proves a cell empty before it skips it, so no feature of any
/// thinness is lost between samples.
#[test]
fn thin_shells_and_half_pixel_balls_are_found() {
    use crate::render::Status;
    use glam::DVec3;
    let (w, h) = (160, 120);
    let s = super::common::settings(super::common::cube(2.0), w, h);
    let cf = s.camera.frame().unwrap();
    let eye = s.camera.eye;
    let foot = |c: DVec3| 2.0 * cf.tan_half_fov * (c - eye).length() / f64::from(h);
    let balls: Vec<(DVec3, f64)> = (0..40).map(|i| DVec3::new(-1.75 + 0.5 * f64::from(i % 8), -1.9 + 0.15 * f64::from(i / 8), 0.3)).map(|c| (c, 0.25 * foot(c))).collect();
    let mut nodes = vec![r#"{"type": "sphere", "radius": 1.0}"#.to_string(), r#"{"type": "shell", "child": 0, "thickness": 0.0001}"#.to_string()];
    for (k, (c, r)) in balls.iter().enumerate() {
        nodes.push(format!(r#"{{"type": "sphere", "radius": {r}, "translate": [{}, {}, {}]}}"#, c.x, c.y, c.z));
        let left = if k == 0 { 1 } else { nodes.len() - 2 };
        nodes.push(format!(r#"{{"type": "union", "left": {left}, "right": {}}}"#, nodes.len() - 1));
    }
    let scene = scene_of(&nodes, nodes.len() - 1);
    let data = Linear::new(&scene).unwrap().field_data();
    let frame = crate::gpu::Renderer::new(gpu(), &data, bisect_ia()).unwrap().render(&s).unwrap();
    let (mut shell, mut small) = (0, 0);
    for j in 0..h {
        for i in 0..w {
            let d = crate::render::Camera::ray(&cf, i, j, w, h);
            let p = frame.pixels[(j * w + i) as usize];
            let front = super::scene_pictures::ray_ball(eye, d, DVec3::ZERO, 1.0 + 1e-4).map(|t| t.0);
            let past_rim = ((eye - d * eye.dot(d)).length() - 1.0) < -2.0 * foot(DVec3::ZERO);
            let ball = balls.iter().filter_map(|&(c, r)| super::scene_pictures::ray_ball(eye, d, c, r)).map(|t| t.0).fold(f64::INFINITY, f64::min);
            let expected = match front {
                Some(t) if t < ball && past_rim => Some(t),
                // A ray grazing the shell may go either way.
                Some(t) if t < ball => None,
                _ => ball.is_finite().then_some(ball),
            };
            let Some(t) = expected else { continue };
            assert_eq!(p.status, Status::Hit, "pixel ({i}, {j}) misses the surface at {t}");
            assert!((f64::from(p.depth) - t).abs() <= 2.0 * s.eps, "pixel ({i}, {j}): depth {} against {t}", p.depth);
            if t == ball { small += 1 } else { shell += 1 }
        }
    }
    assert!(shell > 500 && small >= 3, "{shell} shell pixels, {small} ball pixels checked");
}

/// Two density blobs whose sum's iso-surface narrows to a neck a few
/// hundredths across (a field that is no distance: sphere tracing steps by
/// a bound of its slope): every pixel whose ray crosses the neck's region
/// and meets the reference's surface (dense f64 sampling) is a hit at its
/// depth, and every other pixel of that region misses.
#[test]
fn a_thin_neck_between_density_blobs_is_found() {
    use crate::render::Status;
    use glam::DVec3;
    let (w, h) = (160, 120);
    let scene = density_neck();
    let neck = [0.0, 0.0, 0.0];
    assert!(scene.eval(neck) < 0.0 && scene.eval([0.0, 0.05, 0.0]) > 0.0, "the neck is thinner than 0.1");
    let data = Linear::new(&scene).unwrap().field_data();
    let s = super::common::settings(super::common::cube(1.0), w, h);
    let frame = crate::gpu::Renderer::new(gpu(), &data, bisect_ia()).unwrap().render(&s).unwrap();
    let cf = s.camera.frame().unwrap();
    let eye = s.camera.eye;
    let (mut hits, mut misses) = (0, 0);
    for j in 0..h {
        for i in 0..w {
            let d = crate::render::Camera::ray(&cf, i, j, w, h);
            // The rays through the neck's region: within 0.08 of the y-z plane at the blobs.
            let Some((t0, t1)) = super::scene_pictures::ray_ball(eye, d, DVec3::ZERO, 0.15) else { continue };
            let p = frame.pixels[(j * w + i) as usize];
            let mut prev = scene.eval((eye + d * (t0 - 1.0)).to_array()) <= 0.0;
            let mut root = None;
            let mut t = t0 - 1.0;
            while t < t1 + 1.0 && root.is_none() {
                t += 2e-4;
                let inside = scene.eval((eye + d * t).to_array()) <= 0.0;
                if inside != prev {
                    root = Some(t);
                }
                prev = inside;
            }
            let foot = 2.0 * cf.tan_half_fov * t0 / f64::from(h);
            match root {
                Some(t) => {
                    assert_eq!(p.status, Status::Hit, "pixel ({i}, {j}) misses the surface at {t}");
                    // At the root, or at a near miss in front of it.
                    let v = scene.eval((eye + d * f64::from(p.depth)).to_array());
                    let near = v.abs() <= 2.0 * s.eps && f64::from(p.depth) < t;
                    assert!((f64::from(p.depth) - t).abs() <= 2.0 * s.eps + foot || near, "pixel ({i}, {j}): depth {} against {t} (the reference there: {v}, eps {})", p.depth, s.eps);
                    hits += 1;
                }
                // Grazing rays may go either way.
                None if p.status == Status::Hit => {
                    let v = scene.eval((eye + d * f64::from(p.depth)).to_array());
                    assert!(v.abs() <= 2.0 * s.eps, "pixel ({i}, {j}): hit at {} where the reference is {v}", p.depth);
                }
                None => misses += 1,
            }
        }
    }
    assert!(hits > 50, "{hits} hits, {misses} misses checked");
}

/// Two density blobs summed whose iso-surface narrows to a neck a few
/// hundredths across at the origin: (1 - (a/R)^2)^3 = 0.2505 at the
/// midpoint, so the sum is just above the isovalue 0.5 there.
fn density_neck() -> Scene {
    let (radius, a) = (0.6, 0.6 * (1.0 - 0.2505f64.cbrt()).sqrt());
    let nodes = [
        format!(r#"{{"type": "density", "radius": {radius}, "iso": 0.5, "range": 0.2, "translate": [{}, 0, 0]}}"#, -a),
        format!(r#"{{"type": "density", "radius": {radius}, "iso": 0.5, "range": 0.2, "translate": [{a}, 0, 0]}}"#),
        r#"{"type": "sum_union", "left": 0, "right": 1, "range": 0.2}"#.to_string(),
    ];
    scene_of(&nodes, 2)
}

/// A scene of fewer than four primitives lists each of them once in a tile:
/// its primitive buffer is padded to 16 bytes, which the scatter pass must
/// not take for more copies of the first primitive (a comb tile would sum
/// a density twice and draw a surface in front of the neck, sphere traced
/// or bisected). The density neck sphere traced with its tiles' lists draws
/// what the whole tree draws.
#[test]
fn small_scenes_list_each_primitive_once_and_a_neck_traces_as_the_whole_tree() {
    let gpu = gpu();
    let s = super::common::settings(super::common::cube(1.0), 160, 120);
    let sphere = |lin: &Linear| crate::render::Traversal::Sphere(crate::render::SphereOptions { lipschitz: lin.lipschitz(), ..Default::default() });
    for n in 1..=3usize {
        let mut nodes: Vec<String> = (0..n).map(|k| format!(r#"{{"type": "sphere", "radius": 0.5, "translate": [{}, 0, 0]}}"#, 0.3 * k as f64)).collect();
        for k in 1..n {
            nodes.push(format!(r#"{{"type": "union", "left": {}, "right": {k}}}"#, if k == 1 { 0 } else { nodes.len() - 1 }));
        }
        let scene = scene_of(&nodes, nodes.len() - 1);
        let lin = Linear::new(&scene).unwrap();
        let frame = crate::gpu::Renderer::new(gpu, &lin.field_data(), sphere(&lin)).unwrap().render(&s).unwrap();
        assert_eq!(frame.stats.field.active_max as usize, n, "{n} primitives");
    }
    let scene = density_neck();
    let lin = Linear::new(&scene).unwrap();
    let mut r = crate::gpu::Renderer::new(gpu, &lin.field_data(), sphere(&lin)).unwrap();
    let sparse = r.render(&s).unwrap();
    assert!(sparse.stats.field.chain_share > 0.0, "the neck's tiles are comb tiles");
    r.set_dense(true);
    let dense = r.render(&s).unwrap();
    let cf = s.camera.frame().unwrap();
    for (i, (p, q)) in sparse.pixels.iter().zip(&dense.pixels).enumerate() {
        let foot = 2.0 * cf.tan_half_fov * f64::from(p.depth.min(q.depth)).max(1.0) / f64::from(s.height);
        assert!(p.status == q.status && (p.status != crate::render::Status::Hit || (f64::from(p.depth) - f64::from(q.depth)).abs() <= foot), "pixel {i}: tile lists {p:?}, whole tree {q:?}");
    }
}

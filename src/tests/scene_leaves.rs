//! Formula leaves: a scene primitive that is a formula within a box, run
//! from its tape inside the scene interpreter. The device's values and
//! interval enclosures hold the f64 reference's; scenes with leaves among
//! generated primitives draw, bisected, what the compiled formula of the
//! whole scene draws, and what sphere tracing draws where a leaf declares
//! its Lipschitz bound; bad leaves are refused by name.

use super::common::gpu;
use super::scene_enclosures::{bisect_ia, check_bisected, check_bisected_grazing, random_box, sampled_range, scene_settings};
use crate::gpu::eval::{eval_boxes_scene, eval_cells_scene, eval_points_scene, Box8};
use crate::scene::generate::{generate, Blending, Kind, Rng};
use crate::scene::linear::Linear;
use crate::scene::{format, Blend, FormulaLeaf, Node, OpKind, Operator, Primitive, Scene, Shape};
use std::sync::Arc;

/// Three of the Knoll surfaces (the tangle, the Barth sextic, the
/// teardrop), each a leaf scaled and placed beside the aggregate of
/// `level` (10 generated primitives at 0, 110 at 1), joined by `blending`'s
/// union.
fn knoll_leaves(level: u32, blending: Blending) -> Scene {
    let agg = generate(Kind::Aggregate, level, blending, 7).unwrap();
    let mut nodes = agg.nodes().to_vec();
    let leaf = |f: &str, b: [f64; 6], s: f64, t: [f64; 3]| {
        let shape = Shape::Formula(Arc::new(FormulaLeaf::new(f, b, None).unwrap()));
        Node::Primitive(Primitive::new(shape).scaled(s).translated(t))
    };
    nodes.push(leaf("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", [-3.0, 3.0, -3.0, 3.0, -3.0, 3.0], 0.22, [2.6, 0.0, 0.0]));
    nodes.push(leaf("phi = (1 + sqrt(5))/2; 4*(phi^2*x^2 - y^2)*(phi^2*y^2 - z^2)*(phi^2*z^2 - x^2) - (1 + 2*phi)*(x^2 + y^2 + z^2 - 1)^2", [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0], 0.3, [-2.6, 0.0, 0.2]));
    nodes.push(leaf("x^4 - x^3 + y^2 + z^2", [-0.25, 1.25, -0.5, 0.5, -0.5, 0.5], 1.2, [-0.6, 2.4, 0.0]));
    let k = nodes.len();
    let union = match blending {
        Blending::Smooth => Operator::smooth(OpKind::Union, Blend::new(0.2)),
        _ => Operator::UNION,
    };
    nodes.push(Node::Operator { op: union, left: k - 3, right: k - 2 });
    nodes.push(Node::Operator { op: union, left: k, right: k - 1 });
    nodes.push(Node::Operator { op: union, left: agg.root(), right: k + 1 });
    let root = nodes.len() - 1;
    Scene::new(nodes, root).unwrap()
}

/// Leaves of every operation group the interpreter has (trigonometric,
/// exponential, square roots, min and max, division, high powers), turned,
/// scaled, twisted and blended with primitives, one with a declared bound.
const MIXED: &str = r#"{"isotrace_scene": 1, "root": 10,
 "nodes": [
  {"type": "formula", "formula": "sin(3*x)*cos(3*y) + z - 0.3*exp(-x^2) + sqrt(x^2 + y^2 + 1) - 1", "bounds": [-1, 1, -1, 1, -1, 1], "rotate": [1, 1, 0, 0.7]},
  {"type": "sphere", "radius": 0.5, "translate": [0.8, 0.0, 0.0]},
  {"type": "smooth_union", "left": 0, "right": 1, "beta": 0.3},
  {"type": "formula", "formula": "max(abs(x) + abs(y) - 0.8, z^10 - 0.1) / (1 + x^2)", "bounds": [-1, 1, -1, 1, -1, 1], "scale": 0.6, "translate": [0.0, 1.5, 0.0]},
  {"type": "formula", "formula": "x^2 + y^2 + z^2 - 1", "bounds": [-1.5, 1.5, -1.5, 1.5, -1.5, 1.5], "lipschitz": 5.2, "scale": 0.5, "translate": [0.0, -1.5, 0.3]},
  {"type": "smooth_union", "left": 3, "right": 4, "beta": 0.2, "r_o": 0.4},
  {"type": "box", "half": [0.4, 0.4, 0.4], "translate": [-1.2, 0.0, 0.0]},
  {"type": "formula", "formula": "atan2(y, x) * 0.2 + x^2 + y^2 - 0.3 + tanh(z)", "bounds": [-0.8, 0.8, -0.8, 0.8, -0.6, 0.6], "translate": [-1.2, 0.0, 0.5], "warp": {"type": "twist", "rate": 1.5, "translate": [-1.2, 0.0, 0.0]}},
  {"type": "difference", "left": 6, "right": 7},
  {"type": "union", "left": 2, "right": 5},
  {"type": "union", "left": 9, "right": 8}
 ]}"#;

#[test]
fn leaves_values_and_enclosures_hold_the_references() {
    let gpu = gpu();
    let mut rng = Rng::new(0x1eaf_5eed);
    for (name, scene) in [("mixed", format::parse(MIXED).unwrap()), ("knoll", knoll_leaves(1, Blending::Smooth))] {
        let lin = Linear::new(&scene).unwrap();
        let data = lin.field_data();
        let bbox = lin.bounds.padded().unwrap();
        // Values at points, against the reference.
        let points: Vec<[f32; 3]> = (0..20_000).map(|_| [0, 1, 2].map(|a| rng.range(bbox[2 * a], bbox[2 * a + 1]) as f32)).collect();
        let values = eval_points_scene(gpu, &data, &points).unwrap();
        let mut worst = 0.0f64;
        for (p, &v) in points.iter().zip(&values) {
            let r = scene.eval(p.map(f64::from));
            let err = (f64::from(v) - r).abs() / (1.0 + r.abs());
            worst = worst.max(err);
        }
        assert!(worst < 2e-4, "{name}: a device value is {worst} (relative) from the reference");
        // Enclosures over random boxes, against dense sampling.
        let boxes: Vec<[f64; 6]> = (0..25_000).map(|_| random_box(&mut rng, &bbox)).collect();
        let b8: Vec<Box8> = boxes.iter().map(|b| [b[0] as f32, b[1] as f32, b[2] as f32, b[3] as f32, b[4] as f32, b[5] as f32, 0.0, 0.0]).collect();
        let got = eval_boxes_scene(gpu, &data, &b8).unwrap();
        let (mut escapes, mut straddle) = (Vec::new(), 0);
        for (i, e) in got.iter().enumerate() {
            let f = b8[i].map(f64::from);
            let (lo, hi) = sampled_range(&scene, &mut rng, &[f[0], f[1], f[2], f[3], f[4], f[5]], 24);
            let slack = 1e-5 * (1.0 + lo.abs().max(hi.abs()));
            if !(f64::from(e[0]) <= lo + slack && f64::from(e[1]) >= hi - slack) {
                escapes.push((f, lo, hi, *e));
            }
            straddle += usize::from(e[0] < 0.0 && e[1] > 0.0);
        }
        assert!(escapes.is_empty(), "{name}: {} of {} enclosures miss sampled values, e.g. {:?}", escapes.len(), boxes.len(), &escapes[..escapes.len().min(4)]);
        assert!(straddle * 2 < boxes.len(), "{name}: {straddle} of {} enclosures straddle 0", boxes.len());
    }
}

#[test]
fn knoll_surfaces_among_generated_primitives_draw_what_the_compiled_formula_draws() {
    let gpu = gpu();
    for blending in [Blending::Sharp, Blending::Smooth] {
        // Small enough for the compiled formula of the whole scene.
        let scene = knoll_leaves(0, blending);
        let lin = Linear::new(&scene).unwrap();
        assert!(lin.untraceable_leaf().is_some());
        let data = lin.field_data();
        let s = scene_settings(&lin, 160, 120);
        let mut r = crate::gpu::Renderer::new(gpu, &data, bisect_ia()).unwrap();
        let sparse = r.render(&s).unwrap();
        r.set_dense(true);
        let dense = r.render(&s).unwrap();
        // The pruned trees draw what the whole tree draws, but for rays
        // grazing a surface, which the whole tree's cells (no slope: it is
        // more than one leaf) end on and a leaf's tile proves monotone, and
        // the pixels the whole tree (the tree and three tapes a cell) leaves
        // unresolved for the work limit; each checked against the reference.
        let unresolved = dense.pixels.iter().filter(|p| p.status == crate::render::Status::Unresolved).count();
        let (hits, differ) = check_bisected_grazing(&scene, &s, &sparse, &dense, 0.01, 4.0, 4.0);
        assert!(differ <= unresolved + hits / 6, "{blending:?}: {differ} pixels of {hits} hits differ from the whole tree's ({unresolved} unresolved there)");
        let f = crate::Formula::compile("<scene>", &scene.to_formula().unwrap()).unwrap();
        let compiled = crate::gpu::Renderer::new(gpu, &f.ir, bisect_ia()).unwrap().render(&s).unwrap();
        // The Barth sextic's 65 double points are roots without a sign
        // change: rays passing within a cell of one hit in both paths.
        // Every pixel that differs is checked against the reference: rays
        // grazing a surface, which the two paths end at other depths.
        let (hits, differ) = check_bisected_grazing(&scene, &s, &sparse, &compiled, 1.0, 4.0, 4.0);
        assert!(hits > 500 && differ * 10 <= hits, "{blending:?}: {differ} pixels of {hits} hits differ from the compiled formula's");
        // Not vacuous: many hits are on the leaves.
        let cf = s.camera.frame().unwrap();
        let on_leaves = (0..s.width * s.height)
            .filter(|&i| {
                let p = sparse.pixels[i as usize];
                let d = crate::render::Camera::ray(&cf, i % s.width, i / s.width, s.width, s.height);
                let at = s.camera.eye + d * f64::from(p.depth);
                p.status == crate::render::Status::Hit && (at.x.abs() > 2.0 || at.y > 2.0)
            })
            .count();
        assert!(on_leaves > 300, "{blending:?}: {on_leaves} pixels on the leaves");
    }
}

#[test]
fn a_leaf_with_a_declared_bound_is_sphere_traced_as_it_is_bisected() {
    let gpu = gpu();
    let scene = format::parse(MIXED).unwrap();
    let lin = Linear::new(&scene).unwrap();
    // Three of its four leaves declare no bound.
    assert_eq!(lin.untraceable_leaf().unwrap().to_string(), "nodes[0].lipschitz: a formula leaf without a Lipschitz bound cannot be sphere traced: declare one, or render with --method bisect");
    let one = r#"{"isotrace_scene": 1, "root": 2, "nodes": [
      {"type": "formula", "formula": "sqrt(x^2 + y^2 + z^2) - 1", "bounds": [-1.5, 1.5, -1.5, 1.5, -1.5, 1.5], "lipschitz": 1, "scale": 0.8},
      {"type": "torus", "major": 0.8, "minor": 0.2, "translate": [0.9, 0.0, 0.0]},
      {"type": "smooth_union", "left": 0, "right": 1, "beta": 0.2}]}"#;
    let scene = format::parse(one).unwrap();
    let lin = Linear::new(&scene).unwrap();
    assert!(lin.untraceable_leaf().is_none());
    let data = lin.field_data();
    let s = scene_settings(&lin, 160, 120);
    let bisected = crate::gpu::Renderer::new(gpu, &data, bisect_ia()).unwrap().render(&s).unwrap();
    let sphere = crate::render::Traversal::Sphere(crate::render::SphereOptions { lipschitz: lin.lipschitz(), ..Default::default() });
    let traced = crate::gpu::Renderer::new(gpu, &data, sphere).unwrap().render(&s).unwrap();
    let (hits, differ) = check_bisected(&scene, &s, &bisected, &traced, 4.0);
    assert!(hits > 500 && differ * 4 <= hits, "{differ} pixels of {hits} hits differ from sphere tracing's");
}

#[test]
fn bad_leaves_are_refused_by_name() {
    let err = |node: &str| {
        let text = format!(r#"{{"isotrace_scene": 1, "root": 0, "nodes": [{node}]}}"#);
        format::parse(&text).unwrap_err().to_string()
    };
    assert_eq!(err(r#"{"type": "formula", "formula": "x^2 + sinn(y)", "bounds": [0, 1, 0, 1, 0, 1]}"#), "nodes[0].formula: unknown function 'sinn' at bytes 6..10 (\"sinn\")");
    assert_eq!(err(r#"{"type": "formula", "formula": "x^2 - r", "bounds": [0, 1, 0, 1, 0, 1]}"#), "nodes[0].formula: parameter 'r' has no value in a scene: write the number");
    assert_eq!(err(r#"{"type": "formula", "formula": "x"}"#), "nodes[0].bounds: missing: a formula leaf is held in a box [x0, x1, y0, y1, z0, z1]");
    assert_eq!(err(r#"{"type": "formula", "formula": "x", "bounds": [0, 1, 2, 1, 0, 1]}"#), "nodes[0].bounds[3]: must be above bounds[2] (2)");
    assert_eq!(err(r#"{"type": "formula", "formula": "x", "bounds": [0, 1, 0, 1, 0, 1], "lipschitz": 0}"#), "nodes[0].lipschitz: must be finite and > 0");
    assert_eq!(err(r#"{"type": "formula", "formula": 3, "bounds": [0, 1, 0, 1, 0, 1]}"#), "nodes[0].formula: expected formula text, found 3");
    assert_eq!(err(r#"{"type": "formula", "formula": "x", "bounds": [0, 1, 0, 1, 0, 1], "radius": 1}"#), "nodes[0].radius: unknown field for a formula; expected formula, bounds, lipschitz, translate, rotate, scale or warp");
}

#[test]
fn leaves_round_trip_and_edit_in_place() {
    let scene = format::parse(MIXED).unwrap();
    let back = format::parse(&format::to_json(&scene)).unwrap();
    assert_eq!(back, scene);
    let mut lin = Linear::new(&scene).unwrap();
    // Moving a leaf is an edit in place; another formula needs a new scene.
    let j = lin.primitives.iter().position(|&k| lin.order[k as usize] == 4).unwrap();
    let Node::Primitive(p) = &scene.nodes()[4] else { unreachable!() };
    let moved = p.clone().translated([0.1, 0.0, 0.0]);
    let patch = lin.set_primitive(j, &moved).unwrap();
    assert!(!patch.params.is_empty());
    let other = Primitive { shape: Shape::Formula(Arc::new(FormulaLeaf::new("x^2 + y^2 - 1", [-1.5, 1.5, -1.5, 1.5, -1.5, 1.5], Some(5.2)).unwrap())), ..p.clone() };
    assert_eq!(lin.set_primitive(j, &other).unwrap_err().to_string(), "nodes[4].formula: an edit in place keeps a formula leaf's formula (its tape): build a new scene to change it");
}

/// Each Knoll surface as the only leaf of a scene, framed by its box,
/// draws what the compiled formula alone draws in its box (`isotrace
/// render FORMULA --box …`): the same hits, depths within a footprint.
#[test]
fn a_knoll_surface_as_a_leaf_draws_what_its_formula_draws_alone() {
    let gpu = gpu();
    let surfaces = [
        ("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", [-3.0, 3.0, -3.0, 3.0, -3.0, 3.0]),
        // Clipped by the sphere of radius 2, as the catalogue shows it.
        ("phi = (1 + sqrt(5))/2; max(4*(phi^2*x^2 - y^2)*(phi^2*y^2 - z^2)*(phi^2*z^2 - x^2) - (1 + 2*phi)*(x^2 + y^2 + z^2 - 1)^2, x^2 + y^2 + z^2 - 4)", [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0]),
        ("x^4 - x^3 + y^2 + z^2", [-0.25, 1.25, -0.5, 0.5, -0.5, 0.5]),
    ];
    for (text, b) in surfaces {
        let leaf = Node::Primitive(Primitive::new(Shape::Formula(Arc::new(FormulaLeaf::new(text, b, None).unwrap()))));
        let scene = Scene::new(vec![leaf], 0).unwrap();
        let data = Linear::new(&scene).unwrap().field_data();
        let s = crate::render::Settings::for_box(b, 160, 120);
        let ours = crate::gpu::Renderer::new(gpu, &data, bisect_ia()).unwrap().render(&s).unwrap();
        let f = crate::Formula::compile("<leaf>", text).unwrap();
        let alone = crate::gpu::Renderer::new(gpu, &f.ir, bisect_ia()).unwrap().render(&s).unwrap();
        let (hits, differ) = check_bisected_grazing(&scene, &s, &ours, &alone, 1.0, 4.0, 4.0);
        assert!(hits > 1000 && differ * 20 <= hits, "{text}: {differ} pixels of {hits} hits differ from the compiled formula's");
    }
}

/// A tree that is one formula leaf gives bisection's cells a slope (its
/// tape's derivative program): over random cells of random rays, the
/// device's value and slope enclosures hold the f64 reference's values and
/// its differences along the ray, for leaves turned, scaled, with and
/// without a declared bound.
#[test]
fn a_single_leafs_cell_slopes_hold_the_references() {
    let gpu = gpu();
    let mut rng = Rng::new(0x5107e);
    let leaves = [
        (r#"{"type": "formula", "formula": "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", "bounds": [-3, 3, -3, 3, -3, 3], "scale": 0.22, "translate": [2.6, 0, 0], "rotate": [1, 2, 3, 0.4]}"#, 4.0),
        (r#"{"type": "formula", "formula": "sin(3*x)*cos(3*y) + z - 0.3*exp(-x^2) + sqrt(x^2 + y^2 + 1) - 1", "bounds": [-1, 1, -1, 1, -1, 1], "lipschitz": 6}"#, 1.5),
        (r#"{"type": "formula", "formula": "max(abs(x) + abs(y) - 0.8, z^10 - 0.1) / (1 + x^2)", "bounds": [-1, 1, -1, 1, -1, 1], "scale": 1.5}"#, 2.0),
    ];
    let mut checked = 0;
    for (node, reach) in leaves {
        let scene = format::parse(&format!(r#"{{"isotrace_scene": 1, "root": 0, "nodes": [{node}]}}"#)).unwrap();
        let data = Linear::new(&scene).unwrap().field_data();
        let mut cells = Vec::new();
        for _ in 0..4000 {
            let o = rng.direction() * 6.0;
            let target = glam::DVec3::new(rng.range(-reach, reach), rng.range(-reach, reach), rng.range(-reach, reach));
            let d = (target - o).normalize();
            let s0 = (target - o).length() + rng.range(-0.5, 0.5);
            let s1 = s0 + 10f64.powf(rng.range(-4.0, -0.5));
            cells.push((o, d, s0, s1));
        }
        let boxes: Vec<Box8> = cells.iter().map(|&(o, d, s0, s1)| [o.x, d.x, o.y, d.y, o.z, d.z, s0, s1].map(|v| v as f32)).collect();
        let values = eval_cells_scene(gpu, &data, &boxes, false).unwrap();
        let slopes = eval_cells_scene(gpu, &data, &boxes, true).unwrap();
        let mut decided = 0;
        for (k, b) in boxes.iter().enumerate() {
            let [o, d] = [[b[0], b[2], b[4]], [b[1], b[3], b[5]]].map(|v| glam::DVec3::from(v.map(f64::from)));
            let (s0, s1) = (f64::from(b[6]), f64::from(b[7]));
            let n = 64;
            let at = |j: usize| scene.eval((o + d * (s0 + (s1 - s0) * j as f64 / n as f64)).to_array());
            let f: Vec<f64> = (0..=n).map(at).collect();
            let (v, g) = (values[k], slopes[k]);
            let slack = |x: f64| 1e-4 * (1.0 + x.abs());
            for (j, &x) in f.iter().enumerate() {
                assert!(f64::from(v[0]) <= x + slack(x) && f64::from(v[1]) >= x - slack(x), "{node}: cell {k}: value {v:?} misses {x} at sample {j}");
            }
            // Differences are slopes at points between the samples (the
            // mean value theorem), where f is differentiable.
            for j in 0..n {
                let sl = (f[j + 1] - f[j]) / ((s1 - s0) / n as f64);
                if sl.is_finite() {
                    assert!(f64::from(g[0]) <= sl + 1e-3 * (1.0 + sl.abs()) && f64::from(g[1]) >= sl - 1e-3 * (1.0 + sl.abs()), "{node}: cell {k}: slope {g:?} misses {sl}");
                }
            }
            decided += usize::from(g[0] > 0.0 || g[1] < 0.0);
        }
        // Not vacuous: many cells are proven monotone.
        assert!(decided * 4 > cells.len(), "{node}: {decided} of {} cells monotone", cells.len());
        checked += cells.len();
    }
    assert_eq!(checked, 12_000);
}


/// Leaves of degree 4 to 10 take their cells in RAA along the cell's
/// segment (`FormulaLeaf::affine`), inside trees of several nodes too, and a
/// twisted one on intervals: over random cells of random rays the device's
/// cell enclosures hold the f64 reference's values along the segment, and
/// an RAA leaf's are narrower than the interval enclosure of the segment's
/// box (the path is taken).
#[test]
fn affine_leaves_cells_hold_the_references_and_are_narrower_than_intervals() {
    let gpu = gpu();
    let mut rng = Rng::new(0xaff1);
    let tangle = r#""formula": "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", "bounds": [-3, 3, -3, 3, -3, 3]"#;
    let scenes = [
        (format!(r#""root": 0, "nodes": [{{"type": "formula", {tangle}, "scale": 0.3, "translate": [0.2, 0, 0], "rotate": [1, 2, 3, 0.4]}}]"#), true),
        (
            format!(
                r#""root": 4, "nodes": [{{"type": "formula", {tangle}, "scale": 0.3}},
                {{"type": "box", "half": [0.9, 0.2, 0.9], "translate": [0, -0.8, 0]}},
                {{"type": "smooth_union", "left": 0, "right": 1, "beta": 0.2}},
                {{"type": "formula", "formula": "x^4 - x^3 + y^2 + z^2", "bounds": [-0.25, 1.25, -0.5, 0.5, -0.5, 0.5], "translate": [-0.4, 0.7, 0]}},
                {{"type": "union", "left": 2, "right": 3}}]"#
            ),
            true,
        ),
        (format!(r#""root": 0, "nodes": [{{"type": "formula", {tangle}, "scale": 0.3, "warp": {{"type": "twist", "rate": 0.8}}}}]"#), false),
    ];
    for (nodes, narrower) in scenes {
        let scene = format::parse(&format!(r#"{{"isotrace_scene": 1, {nodes}}}"#)).unwrap();
        let lin = Linear::new(&scene).unwrap();
        assert!(lin.features & crate::scene::linear::FEATURE_FORMULA_AFFINE != 0, "{nodes}");
        let data = lin.field_data();
        let mut cells = Vec::new();
        for _ in 0..3000 {
            let o = rng.direction() * 4.0;
            let target = glam::DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            let d = (target - o).normalize();
            let s0 = (target - o).length() + rng.range(-0.3, 0.3);
            let s1 = s0 + 10f64.powf(rng.range(-3.0, -0.7));
            cells.push([o.x, d.x, o.y, d.y, o.z, d.z, s0, s1].map(|v| v as f32));
        }
        let along = eval_cells_scene(gpu, &data, &cells, false).unwrap();
        // The same segments' boxes, enclosed on intervals.
        let boxes: Vec<Box8> = cells
            .iter()
            .map(|b| {
                let end = |s: f32| [b[0] + b[1] * s, b[2] + b[3] * s, b[4] + b[5] * s];
                let (p, q) = (end(b[6]), end(b[7]));
                [p[0].min(q[0]), p[0].max(q[0]), p[1].min(q[1]), p[1].max(q[1]), p[2].min(q[2]), p[2].max(q[2]), 0.0, 0.0]
            })
            .collect();
        let boxed = eval_boxes_scene(gpu, &data, &boxes).unwrap();
        let (mut width_along, mut width_boxed) = (0.0, 0.0);
        for (k, b) in cells.iter().enumerate() {
            let [o, d] = [[b[0], b[2], b[4]], [b[1], b[3], b[5]]].map(|v| glam::DVec3::from(v.map(f64::from)));
            let (s0, s1) = (f64::from(b[6]), f64::from(b[7]));
            let v = along[k];
            for j in 0..=32 {
                let x = scene.eval((o + d * (s0 + (s1 - s0) * j as f64 / 32.0)).to_array());
                let slack = 1e-4 * (1.0 + x.abs());
                assert!(f64::from(v[0]) <= x + slack && f64::from(v[1]) >= x - slack, "{nodes}: cell {k}: {v:?} misses {x} at sample {j}");
            }
            if v[1] < 1e3 && boxed[k][1] < 1e3 && v[0] > -1e3 && boxed[k][0] > -1e3 {
                width_along += f64::from(v[1] - v[0]);
                width_boxed += f64::from(boxed[k][1] - boxed[k][0]);
            }
        }
        if narrower {
            assert!(width_along < 0.8 * width_boxed, "{nodes}: RAA cells {width_along} wide in all, their boxes on intervals {width_boxed}");
        }
    }
}

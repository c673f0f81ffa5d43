//! The max-norm box `maxbox(bx, by, bz)` = max(|x| − bx, |y| − by, |z| − bz),
//! a primitive added through its descriptor (src/sdf/primitive/max_box.rs),
//! and the written-out box `scene lower` reads as one: the scene primitive
//! against its formula and the written-out formula, its Lipschitz bound and
//! bounding volume, the device interpreter's values and enclosures against
//! the reference, the file format and its errors, and the scene path's
//! picture against the compiled one.

use super::scene_common;
use crate::scene::generate::Rng;
use crate::scene::linear::Linear;
use crate::scene::{format, Node, Primitive, Scene, Shape};
use crate::Formula;

fn formula_value(f: &Formula, p: [f64; 3]) -> f64 {
    crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[])
}

fn random_max_box(rng: &mut Rng, centre: [f64; 3]) -> Primitive {
    let half = [0, 1, 2].map(|_| rng.range(0.1, 0.8));
    Primitive::new(Shape::MaxBox { half }).rotated(rng.direction().to_array(), rng.range(-3.0, 3.0)).scaled(rng.range(0.6, 1.4)).translated(centre)
}

/// The written-out box lowers to a `max_box` at its centre, in any order
/// of the axes, with the formula's field; near misses are not boxes.
#[test]
fn a_box_written_in_the_max_norm_lowers_to_a_max_box_with_the_same_field() {
    let src = "min(max(abs(z + 0.1) - 0.4, abs(x - 0.5) - 0.3, abs(0.2 - y) - 0.2), max(abs(x) - 1, abs(y) - 1, abs(z - 2) - 0.5))";
    let f = Formula::compile("<boxes>", src).unwrap();
    let scene = crate::scene::from_formula(&f, &[]).unwrap();
    let boxes: Vec<_> = scene.nodes().iter().filter_map(|n| if let Node::Primitive(p) = n { Some(p) } else { None }).collect();
    assert_eq!(boxes.len(), 2);
    assert_eq!(boxes[0].shape, Shape::MaxBox { half: [0.3, 0.2, 0.4] });
    assert_eq!(boxes[0].transform.translate, [0.5, 0.2, -0.1]);
    let mut rng = Rng::new(21);
    for _ in 0..2000 {
        let p = [0, 1, 2].map(|_| rng.range(-2.0, 3.0));
        let (a, b) = (scene.eval(p), formula_value(&f, p));
        assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "at {p:?}: scene {a}, formula {b}");
    }
    // The scene's own formula names the primitive, and compiles back.
    let back = scene.to_formula().unwrap();
    assert!(back.contains("maxbox(0.3, 0.2, 0.4)"), "{back}");
    let g = Formula::compile("<back>", &back).unwrap();
    for _ in 0..500 {
        let p = [0, 1, 2].map(|_| rng.range(-2.0, 3.0));
        assert!((formula_value(&g, p) - formula_value(&f, p)).abs() < 1e-12);
    }
    // An axis twice, or a half extent that is not positive: not a box.
    for bad in ["max(abs(x) - 1, abs(x) - 1, abs(z) - 1)", "max(abs(x) - 1, abs(y) + 1, abs(z) - 1)", "max(abs(x) - 1, abs(y) - 1)"] {
        let f = Formula::compile("<bad>", bad).unwrap();
        let e = crate::scene::from_formula(&f, &[]).unwrap_err().to_string();
        assert!(e.contains("'x' outside a distance form"), "{bad}: {e}");
    }
}

#[test]
fn the_max_box_is_1_lipschitz_exact_inside_and_within_its_bounding_volume() {
    let mut rng = Rng::new(22);
    let inside = scene_common::check_lipschitz_and_bounding_volume(&mut rng, |rng| {
        let centre = [0, 1, 2].map(|_| rng.range(-1.0, 1.0));
        random_max_box(rng, centre)
    });
    assert!(inside > 1_500, "{inside}");
    // Inside, the box's exact distance.
    let b = Primitive::new(Shape::MaxBox { half: [1.0, 2.0, 3.0] });
    let exact = Primitive::new(Shape::Box { half: [1.0, 2.0, 3.0] });
    for _ in 0..500 {
        let p = [rng.range(-1.0, 1.0), rng.range(-2.0, 2.0), rng.range(-3.0, 3.0)];
        assert!((b.distance(p) - exact.distance(p)).abs() < 1e-12);
    }
}

/// Max boxes among other primitives, one twisted.
fn max_box_scene(rng: &mut Rng) -> Scene {
    scene_common::mixed_scene(rng, |rng, centre, _| random_max_box(rng, centre))
}

#[test]
fn the_device_interpreter_agrees_with_the_reference_and_encloses_it() {
    let own = crate::gpu::Gpu::new().unwrap();
    let mut rng = Rng::new(23);
    for _ in 0..3 {
        let scene = max_box_scene(&mut rng);
        let lin = Linear::new(&scene).unwrap();
        let feature = crate::sdf::primitive::MAX_BOX.wgsl.unwrap().feature;
        assert_eq!(lin.features & feature, feature);
        let bb = lin.bounds;
        let points: Vec<[f32; 3]> = (0..4000).map(|_| [0, 1, 2].map(|k| rng.range(bb.min[k] - 0.3, bb.max[k] + 0.3) as f32)).collect();
        let got = crate::gpu::eval::eval_points_scene(&own, &lin.field_data(), &points).unwrap();
        let worst = points.iter().zip(&got).map(|(p, g)| (*g as f64 - scene.eval(p.map(f64::from))).abs()).fold(0.0, f64::max);
        assert!(worst < 2e-4, "scene interpreter: worst difference {worst}");
        let cells: Vec<[f64; 6]> = (0..3000).map(|_| super::scene_enclosures::random_box(&mut rng, &[bb.min[0], bb.max[0], bb.min[1], bb.max[1], bb.min[2], bb.max[2]])).collect();
        let boxes: Vec<[f32; 8]> = cells.iter().map(|c| [c[0], c[1], c[2], c[3], c[4], c[5], 0.0, 0.0].map(|v| v as f32)).collect();
        let enclosures = crate::gpu::eval::eval_boxes_scene(&own, &lin.field_data(), &boxes).unwrap();
        for (c, e) in cells.iter().zip(&enclosures) {
            let (lo, hi) = super::scene_enclosures::sampled_range(&scene, &mut rng, c, 24);
            assert!(f64::from(e[0]) <= lo + 1e-4 * (1.0 + lo.abs()) && f64::from(e[1]) >= hi - 1e-4 * (1.0 + hi.abs()), "[{lo}, {hi}] escapes {e:?} on {c:?}");
        }
    }
}

#[test]
fn max_boxes_round_trip_and_bad_ones_are_named_by_their_json_path() {
    let mut rng = Rng::new(24);
    let scene = max_box_scene(&mut rng);
    let json = format::to_json(&scene);
    assert!(json.contains("\"type\": \"max_box\", \"half\": ["), "{json}");
    assert_eq!(format::parse(&json).unwrap(), scene);
    let e = |node: &str| format::parse(&format!(r#"{{"isotrace_scene": 1, "root": 0, "nodes": [{node}]}}"#)).unwrap_err().to_string();
    assert_eq!(e(r#"{"type": "max_box"}"#), "nodes[0].half: missing");
    assert_eq!(e(r#"{"type": "max_box", "half": [1, 0, 1]}"#), "nodes[0].half[1]: must be > 0");
    assert_eq!(e(r#"{"type": "max_bx", "half": [1, 1, 1]}"#), "nodes[0].type: unknown type 'max_bx'; did you mean 'max_box'?");
}

/// The scene path draws the compiled formula's picture (depth within a
/// pixel's footprint).
#[test]
fn written_boxes_draw_the_compiled_picture_through_the_scene_path() {
    use crate::render::Settings;
    let src = "min(max(abs(x + 1) - 0.5, abs(y) - 0.4, abs(z) - 0.3), max(abs(x - 0.2) - 0.2, abs(y - 0.3) - 0.6, abs(z + 0.2) - 0.4), \
               max(abs(x - 1.2) - 0.3, abs(y + 0.2) - 0.3, abs(z - 0.3) - 0.5))";
    let f = Formula::compile("<boxes>", src).unwrap();
    let s = Settings::for_box([-1.7, 1.7, -0.9, 0.9, -0.8, 1.0], 128, 96);
    let (a, b) = scene_common::scene_and_compiled(&f, &s);
    let (both, far, differ) = scene_common::picture_agreement(&a, &b, &s);
    assert!(both > 800, "{both}");
    assert!(far * 50 < both, "{far} of {both} pixels differ by more than a footprint");
    assert!(differ * 100 < a.pixels.len(), "{differ} pixels hit in one picture only");
    assert_eq!((a.stats.unresolved, a.stats.field.overflow_tiles), (0, 0));
}

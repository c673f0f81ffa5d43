//! The capped cone, a primitive added through its descriptor alone
//! (src/sdf/primitive/cone.rs): its f64 reference against a brute-force
//! distance and against the compiled formula on the CPU and on the device, the scene interpreter against the
//! reference, its Lipschitz bound and bounding volume, the scene file's
//! fields and errors, the formula's argument checks, formula ⇄ scene
//! lowering, and the scene path's picture against the compiled one.

use super::scene_common;

use glam::DVec3;
use crate::scene::generate::Rng;
use crate::scene::linear::{self, Linear};
use crate::scene::{format, Primitive, Scene, Shape};
use crate::Formula;

fn cone(radius: f64, half_height: f64, top_radius: f64) -> Shape {
    Shape::Cone { radius, half_height, top_radius }
}

/// A cone of random proportions, placed at random (pointed now and then,
/// wider at the top now and then).
fn random_cone(rng: &mut Rng, centre: [f64; 3], scale: f64) -> Primitive {
    let top = [0.0, rng.range(0.0, 0.5), rng.range(0.5, 1.2)][rng.below(3) as usize];
    let shape = cone(scale * rng.range(0.2, 0.6), scale * rng.range(0.2, 0.7), scale * top * 0.5);
    Primitive::new(shape).rotated(rng.direction().to_array(), rng.range(-3.0, 3.0)).scaled(rng.range(0.6, 1.4)).translated(centre)
}

/// The cone's field against a brute-force distance to its surface in the
/// (ρ, z) half-plane, sampled densely, with the sign of the trapezoid.
#[test]
fn the_cone_is_the_distance_to_its_surface() {
    use crate::sdf::primitive::CONE;
    // The top radius defaults to 0.
    assert_eq!(&*CONE.with_defaults(&[1.0, 2.0]), &[1.0, 2.0, 0.0]);
    assert_eq!(&*CONE.with_defaults(&[1.0, 2.0, 0.5]), &[1.0, 2.0, 0.5]);
    let brute = |r: f64, h: f64, rt: f64, rho: f64, z: f64| {
        let pieces = [((0.0, -h), (r, -h)), ((r, -h), (rt, h)), ((rt, h), (0.0, h))];
        let mut d = f64::INFINITY;
        for ((ax, az), (bx, bz)) in pieces {
            for k in 0..=4000 {
                let t = k as f64 / 4000.0;
                d = d.min((rho - (ax + (bx - ax) * t)).hypot(z - (az + (bz - az) * t)));
            }
        }
        let inside = z.abs() <= h && rho <= r + (rt - r) * (z + h) / (2.0 * h);
        if inside { -d } else { d }
    };
    let mut rng = Rng::new(10);
    for (r, h, rt) in [(1.0, 0.5, 0.0), (0.6, 1.0, 0.3), (0.3, 0.4, 0.9), (0.5, 0.5, 0.5)] {
        for _ in 0..300 {
            let q = DVec3::new(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
            let got = (CONE.distance)(&[r, h, rt], q);
            let want = brute(r, h, rt, q.x.hypot(q.y), q.z);
            assert!((got - want).abs() < 2e-3, "cone({r}, {h}, {rt}) at {q}: {got} vs {want}");
        }
    }
}

fn formula_value(f: &Formula, p: [f64; 3]) -> f64 {
    crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[])
}

#[test]
fn the_scene_cone_is_the_formula_cone() {
    let mut rng = Rng::new(11);
    for _ in 0..60 {
        let centre = [0, 1, 2].map(|_| rng.range(-1.0, 1.0));
        let prim = random_cone(&mut rng, centre, 1.0);
        let src = crate::scene::formula::primitive_formula(&prim).expect("a cone has a form");
        assert!(src.contains("cone("), "{src}");
        let f = Formula::compile("<cone>", &src).unwrap_or_else(|e| panic!("{src}: {e}"));
        for _ in 0..200 {
            let p = [0, 1, 2].map(|_| rng.range(-3.0, 3.0));
            let (a, b) = (prim.distance(p), formula_value(&f, p));
            assert!((a - b).abs() <= 1e-12 * (1.0 + a.abs()), "{src} at {p:?}: scene {a}, formula {b}");
        }
    }
    // The top radius defaults to 0: a pointed cone, apex on the axis.
    let f = Formula::compile("<cone>", "cone(1, 0.5)").unwrap();
    assert_eq!(formula_value(&f, [0.0, 0.0, 0.5]), 0.0);
    assert_eq!(formula_value(&f, [0.0, 0.0, 1.5]), 1.0);
    assert_eq!(formula_value(&f, [0.0, 0.0, -0.5]), 0.0);
    assert_eq!(formula_value(&f, [0.0, 0.0, -1.0]), 0.5);
    assert_eq!(formula_value(&f, [3.0, 0.0, -0.5]), 2.0);
    assert!((formula_value(&f, [0.0, 0.0, 0.0]) + 0.5 * std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15, "the side is nearer than the base at the centre");
}

#[test]
fn the_cone_is_1_lipschitz_and_within_its_bounding_volume() {
    let mut rng = Rng::new(12);
    let inside = scene_common::check_lipschitz_and_bounding_volume(&mut rng, |rng| {
        let (centre, size) = ([0, 1, 2].map(|_| rng.range(-1.0, 1.0)), rng.range(0.5, 1.5));
        random_cone(rng, centre, size)
    });
    assert!(inside > 1_500, "{inside}");
}

/// Cones among the basic primitives, under sharp and smooth operators, one
/// of them twisted.
fn cone_scene(rng: &mut Rng) -> Scene {
    scene_common::mixed_scene(rng, random_cone)
}

#[test]
fn the_device_interpreter_and_the_compiled_formula_agree_with_the_reference() {
    let own = crate::gpu::Gpu::new().unwrap();
    let mut rng = Rng::new(13);
    for _ in 0..3 {
        let scene = cone_scene(&mut rng);
        let lin = Linear::new(&scene).unwrap();
        let cone_feature = crate::sdf::primitive::CONE.wgsl.unwrap().feature;
        assert_eq!(lin.features & cone_feature, cone_feature);
        assert!(lin.features & linear::FEATURE_WARP != 0);
        let bb = lin.bounds;
        let points: Vec<[f64; 3]> = (0..4000).map(|_| [0, 1, 2].map(|k| rng.range(bb.min[k] - 0.3, bb.max[k] + 0.3))).collect();
        let p32: Vec<[f32; 3]> = points.iter().map(|p| p.map(|c| c as f32)).collect();
        let got = crate::gpu::eval::eval_points_scene(&own, &lin.field_data(), &p32).unwrap();
        let worst = p32.iter().zip(&got).map(|(p, g)| (*g as f64 - scene.eval(p.map(f64::from))).abs()).fold(0.0, f64::max);
        assert!(worst < 2e-4, "scene interpreter: worst difference {worst}");
    }
    // The compiled formula: the scalar kernel at points, and the interval
    // kernel's enclosures of small boxes.
    let src = "union(translate(0.5, 0, 0, rotate(1, 1, 0, 0.7, cone(0.6, 0.5, 0.2))), translate(-0.7, 0.2, 0, cone(0.4, 0.8)))";
    let f = Formula::compile("<cone>", src).unwrap();
    let points: Vec<[f64; 3]> = (0..4000).map(|_| [rng.range(-2.0, 2.0), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5)]).collect();
    let boxes: Vec<[f32; 8]> = points.iter().map(|p| [p[0] as f32, p[0] as f32, p[1] as f32, p[1] as f32, p[2] as f32, p[2] as f32, 0.0, 0.0]).collect();
    let got = crate::gpu::eval::eval_boxes(&own, &f.ir, crate::ir::Domain::Scalar, &boxes, &[]).unwrap();
    let mut worst = 0.0f64;
    for (b, g) in boxes.iter().zip(&got) {
        worst = worst.max((g[0] as f64 - formula_value(&f, [b[0], b[2], b[4]].map(f64::from))).abs());
    }
    assert!(worst < 2e-4, "compiled formula: worst difference {worst}");
    let h = 0.02f32;
    let cells: Vec<[f32; 8]> = boxes.iter().map(|b| [b[0], b[0] + h, b[2], b[2] + h, b[4], b[4] + h, 0.0, 0.0]).collect();
    let enclosures = crate::gpu::eval::eval_boxes(&own, &f.ir, crate::ir::Domain::Interval, &cells, &[]).unwrap();
    for (c, e) in cells.iter().zip(&enclosures) {
        for corner in [[c[0], c[2], c[4]], [c[1], c[3], c[5]]] {
            let v = formula_value(&f, corner.map(f64::from));
            assert!(e[0] as f64 <= v + 1e-5 && v - 1e-5 <= e[1] as f64, "{v} outside {e:?} on {c:?}");
        }
    }
}

#[test]
fn cones_round_trip_through_the_file_format_and_the_formula() {
    let mut rng = Rng::new(14);
    let scene = cone_scene(&mut rng);
    let json = format::to_json(&scene);
    assert!(json.contains("\"type\": \"cone\", \"radius\": "), "{json}");
    assert_eq!(format::parse(&json).unwrap(), scene);
    // The top radius may be left out: 0.
    let text = r#"{"isotrace_scene": 1, "root": 0, "nodes": [{"type": "cone", "radius": 1, "half_height": 0.5, "translate": [1, 0, 0]}]}"#;
    let one = format::parse(text).unwrap();
    let crate::scene::Node::Primitive(p) = &one.nodes()[0] else { panic!("a primitive") };
    assert_eq!(p.shape, cone(1.0, 0.5, 0.0));
    assert_eq!(one.to_formula().unwrap(), "n0 = translate(1.0, 0.0, 0.0, cone(1.0, 0.5, 0.0));\nn0\n");
    // A formula lowers to the cone it names.
    let f = Formula::compile("<cone>", "translate(1, 0, 0, cone(1, 0.5))").unwrap();
    assert_eq!(crate::scene::from_formula(&f, &[]).unwrap(), one);
    let f = Formula::compile("<cone>", "cone(1, 0.5, 1.5)").unwrap();
    let lowered = crate::scene::from_formula(&f, &[]).unwrap();
    assert!(matches!(&lowered.nodes()[0], crate::scene::Node::Primitive(p) if p.shape == cone(1.0, 0.5, 1.5)));
}

#[test]
fn bad_cones_are_named_by_their_json_path_and_their_argument() {
    let e = |node: &str| format::parse(&format!(r#"{{"isotrace_scene": 1, "root": 0, "nodes": [{node}]}}"#)).unwrap_err().to_string();
    assert_eq!(e(r#"{"type": "cone", "half_height": 1}"#), "nodes[0].radius: missing");
    assert_eq!(e(r#"{"type": "cone", "radius": 1}"#), "nodes[0].half_height: missing");
    assert_eq!(e(r#"{"type": "cone", "radius": 0, "half_height": 1}"#), "nodes[0].radius: must be > 0");
    assert_eq!(e(r#"{"type": "cone", "radius": 1, "half_height": -1}"#), "nodes[0].half_height: must be > 0");
    assert_eq!(e(r#"{"type": "cone", "radius": 1, "half_height": 1, "top_radius": -0.5}"#), "nodes[0].top_radius: must be >= 0");
    assert_eq!(e(r#"{"type": "cone", "radius": 1, "half_height": 1, "top_radius": "wide"}"#), "nodes[0].top_radius: expected a number, found \"wide\"");
    assert_eq!(e(r#"{"type": "cone", "radius": 1, "half_height": 1, "height": 2}"#), "nodes[0].height: unknown field for a cone; expected radius, half_height, top_radius, translate, rotate, scale or warp");
    assert_eq!(e(r#"{"type": "cnoe", "radius": 1}"#), "nodes[0].type: unknown type 'cnoe'; did you mean 'cone'?");
    let diag = |src: &str| Formula::compile("<formula>", src).expect_err("refused").diagnostic.render("<formula>", src, false);
    assert_eq!(
        diag("cone(1, -0.5)"),
        "error: invalid argument to 'cone': the half height h must be positive, got -0.5\n  ┌─ <formula>:1:9\n  │\n1 │ cone(1, -0.5)\n  │         ^^^^ this argument\n  │\n  = usage: cone(r, h[, rt])\n\n"
    );
    assert!(diag("cone(0, 1)").starts_with("error: invalid argument to 'cone': the base radius r must be positive, got 0\n"));
    assert!(diag("cone(1, 1, -2)").starts_with("error: invalid argument to 'cone': the top radius rt must not be negative, got -2\n"));
    assert!(diag("cone(1)").starts_with("error: wrong number of arguments to 'cone': expected 2 or 3, found 1\n"));
}

/// The scene path draws the compiled formula's picture (depth within a
/// pixel's footprint).
#[test]
fn cones_draw_the_compiled_picture_through_the_scene_path() {
    use crate::render::Settings;
    let src = "union(translate(-1, 0, 0, rotate(1, 0, 0, -1.2, cone(0.6, 0.6))), \
               translate(0.2, 0, 0, rotate(1, 0.5, 0, 0.9, cone(0.3, 0.5, 0.6))), \
               compact_union(translate(1.3, 0, 0, cone(0.5, 0.4, 0.2)), translate(1.3, 0, 0.6, sphere(0.25)), 0.15))";
    let f = Formula::compile("<cones>", src).unwrap();
    let s = Settings::for_box([-1.7, 1.9, -0.9, 0.9, -0.9, 1.1], 128, 96);
    let (a, b) = scene_common::scene_and_compiled(&f, &s);
    let (both, far, differ) = scene_common::picture_agreement(&a, &b, &s);
    eprintln!("both {both}, far {far}, differ {differ} of {}", a.pixels.len());
    assert!(both > 800, "{both}");
    assert!(far * 50 < both, "{far} of {both} pixels differ by more than a footprint");
    assert!(differ * 100 < a.pixels.len(), "{differ} pixels hit in one picture only");
    assert_eq!((a.stats.unresolved, a.stats.field.overflow_tiles), (0, 0));
}

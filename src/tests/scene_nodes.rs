//! The scene node zoo (issue "Scene nodes beyond the basic primitives"):
//! extruded and revolved 2D profiles and unary nodes (offset, shell, gyroid
//! infill, noise displacement). For each: the f64 reference against
//! analytic or brute-force values, its Lipschitz bound by sampling, its
//! bounding volume against its region of interest, the sparse traversal and
//! the ranges of interest with it in the tree, and the device's
//! interpreter against the reference at random points.

use super::scene_common;

use glam::{DVec2, DVec3};
use crate::scene::generate::Rng;
use crate::scene::linear::{self, Linear};
use crate::scene::profile::{self, Profile};
use crate::scene::roi;
use crate::scene::{format, Builder, Node, Primitive, Scene, Shape, Unary};
use scene_common::{assert_sparse_and_ranges, picture_agreement, random_profile, random_profiled, scene_and_compiled, surface_points, zoo_tree, EVERY_FORM};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(1.0)
}

#[test]
fn profiles_are_the_shapes_they_stand_for() {
    let mut rng = Rng::new(1);
    let prim = |shape: Shape| Primitive::new(shape);
    let pairs = [
        (prim(Shape::Extrude { profile: Profile::Circle { radius: 0.7 }, half_height: 0.4 }), prim(Shape::Cylinder { radius: 0.7, half_height: 0.4 })),
        (prim(Shape::Revolve { profile: Profile::Circle { radius: 0.2 }, offset: 0.8 }), prim(Shape::Torus { major: 0.8, minor: 0.2 })),
        (prim(Shape::Revolve { profile: Profile::Rect { half: [0.6, 0.3] }, offset: 0.0 }), prim(Shape::Cylinder { radius: 0.6, half_height: 0.3 })),
        (prim(Shape::Extrude { profile: Profile::Rect { half: [0.6, 0.3] }, half_height: 0.2 }), prim(Shape::Box { half: [0.6, 0.3, 0.2] })),
        (
            prim(Shape::Extrude { profile: Profile::polygon(&[[-0.6, -0.3], [0.6, -0.3], [0.6, 0.3], [-0.6, 0.3]]), half_height: 0.2 }),
            prim(Shape::Box { half: [0.6, 0.3, 0.2] }),
        ),
        (
            prim(Shape::Extrude { profile: Profile::RoundRect { half: [0.6, 0.4], radius: 0.4 }, half_height: 0.5 }).rotated([1.0, 2.0, 0.5], 0.7),
            prim(Shape::Extrude { profile: Profile::Capsule { a: [-0.2, 0.0], b: [0.2, 0.0], radius: 0.4 }, half_height: 0.5 }).rotated([1.0, 2.0, 0.5], 0.7),
        ),
    ];
    for (a, b) in pairs {
        for _ in 0..3000 {
            let p = [0, 1, 2].map(|_| rng.range(-2.0, 2.0));
            assert!(close(a.distance(p), b.distance(p), 1e-12), "{a:?} vs {b:?} at {p:?}: {} {}", a.distance(p), b.distance(p));
        }
    }
}

/// Brute force: the distance to a polygon's edges, sampled densely, and the
/// even-odd rule by counting crossings of a ray towards +x.
fn brute_polygon(u: DVec2, v: &[[f64; 2]]) -> f64 {
    let n = v.len();
    let mut d = f64::INFINITY;
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (DVec2::from(v[i]), DVec2::from(v[(i + 1) % n]));
        for k in 0..=2000 {
            d = d.min((a + (b - a) * (k as f64 / 2000.0) - u).length());
        }
        if (a.y > u.y) != (b.y > u.y) && u.x < a.x + (u.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            inside = !inside;
        }
    }
    if inside { -d } else { d }
}

#[test]
fn polygons_are_signed_distances_to_their_edges() {
    let mut rng = Rng::new(2);
    let mut checked = 0;
    for _ in 0..40 {
        let p = loop {
            let p = random_profile(&mut rng, 1.0);
            if let Profile::Polygon { .. } = p {
                break p;
            }
        };
        for _ in 0..60 {
            let u = DVec2::new(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2));
            let (got, want) = (p.distance(u), brute_polygon(u, p.vertices()));
            // The brute force samples edges every 1/2000 of their length.
            assert!((got - want).abs() < 2e-3 && got.signum() == want.signum(), "{p:?} at {u}: {got} vs {want}");
            checked += 1;
        }
    }
    assert!(checked > 600, "{checked}");
}

#[test]
fn unary_nodes_follow_their_definitions() {
    let mut b = Builder::default();
    let s = b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }));
    let o = b.unary(Unary::Offset { distance: 0.25 }, s);
    let sh = b.unary(Unary::Shell { thickness: 0.2 }, o);
    let scene = b.finish(sh).unwrap();
    assert_eq!(scene.eval([0.0; 3]), 1.25 - 0.1);
    assert_eq!(scene.eval([2.0, 0.0, 0.0]), 0.75 - 0.1);
    assert!(close(scene.eval([1.25, 0.0, 0.0]), -0.1, 1e-15));
    let p = DVec3::new(0.3, -0.2, 0.7);
    let g = {
        let k = std::f64::consts::TAU / 0.5;
        let q = p * k;
        (q.x.sin() * q.y.cos() + q.y.sin() * q.z.cos() + q.z.sin() * q.x.cos()).abs() / (k * 6f64.sqrt()) - 0.05
    };
    assert_eq!(Unary::Infill { period: 0.5, thickness: 0.1 }.apply(-1.0, p.to_array()), g.max(-1.0));
    let n = crate::sdf::noise(p.to_array(), 3.0);
    assert_eq!(Unary::Displace { amplitude: 0.1, frequency: 3.0 }.apply(0.5, p.to_array()), 0.5 + 0.1 * n);
    // |n| ≤ 1 (the weights sum to 1) and its gradient is within the bound.
    let mut rng = Rng::new(3);
    let h = 1e-5;
    for _ in 0..5000 {
        let q = DVec3::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
        let f = 4.0;
        assert!(crate::sdf::noise(q.to_array(), f).abs() <= 1.0);
        let grad: DVec3 = [DVec3::X, DVec3::Y, DVec3::Z].map(|e| (crate::sdf::noise((q + e * h).to_array(), f) - crate::sdf::noise((q - e * h).to_array(), f)) / (2.0 * h)).into();
        assert!(grad.length() <= crate::sdf::NOISE_GRADIENT * f * (1.0 + 1e-6), "{}", grad.length());
    }
}

/// The largest |f(a) − f(b)| / |a − b| over random close pairs.
fn sampled_lipschitz(f: impl Fn([f64; 3]) -> f64, rng: &mut Rng, pairs: usize) -> f64 {
    let mut worst = 0.0f64;
    for _ in 0..pairs {
        let a = DVec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        let b = a + rng.direction() * rng.range(1e-4, 0.05);
        worst = worst.max((f(a.to_array()) - f(b.to_array())).abs() / (a - b).length());
    }
    worst
}

#[test]
fn lipschitz_bounds_hold_by_sampling() {
    let mut rng = Rng::new(4);
    for _ in 0..60 {
        let p = random_profiled(&mut rng, [0.0; 3], 1.0);
        let l = sampled_lipschitz(|x| p.distance(x), &mut rng, 3000);
        assert!(l <= 1.0 + 1e-6, "{p:?}: {l}");
    }
    // Zoo trees: the bound the renderer uses (which covers displacements)
    // holds for the whole field.
    for _ in 0..30 {
        let n = 1 + rng.below(12) as usize;
        let scene = zoo_tree(&mut rng, n);
        let lin = Linear::new(&scene).unwrap();
        let l = sampled_lipschitz(|x| scene.eval(x), &mut rng, 4000);
        assert!(l <= lin.lipschitz() * (1.0 + 1e-6), "{l} > {}: {}", lin.lipschitz(), format::to_json(&scene));
    }
}

#[test]
fn abvs_of_profiled_primitives_contain_their_region_of_interest() {
    let mut rng = Rng::new(5);
    let mut inside = 0;
    for _ in 0..300 {
        let centre = [0, 1, 2].map(|_| rng.range(-2.0, 2.0));
        let size = rng.range(0.3, 1.5);
        let prim = random_profiled(&mut rng, centre, size);
        let r_plus = [0.0, rng.range(0.0, 0.8)][rng.below(2) as usize];
        let abv = roi::abv(&prim, r_plus);
        let bb = abv.aabb();
        for _ in 0..400 {
            let p = [0, 1, 2].map(|k| rng.range(bb.min[k] - 0.5, bb.max[k] + 0.5));
            if prim.distance(p) <= r_plus {
                inside += 1;
                assert!(abv.contains(p), "{prim:?} r+ {r_plus}: {p:?} outside {abv:?}");
            }
        }
    }
    assert!(inside > 5_000, "{inside}");
}

/// Unary nodes in the tree: the sparse traversal still equals the masked
/// evaluation bit for bit (with fast and parent ancestors, directly and
/// through the pruned view), and with A = {p : f_p ≤ r_p⁺} every node is
/// exact inside its range of interest and on the same side outside.
#[test]
fn sparse_traversal_and_ranges_hold_with_unary_nodes() {
    let mut rng = Rng::new(6);
    let (mut checks, mut unary_nodes, mut roi_checks) = (0, 0, 0);
    for _ in 0..120 {
        let n = 1 + rng.below(24) as usize;
        let scene = zoo_tree(&mut rng, n);
        unary_nodes += scene.nodes().iter().filter(|n| matches!(n, Node::Unary { .. })).count();
        let points = surface_points(&scene, &mut rng, 40, 0.5);
        checks += 2 * points.len();
        roi_checks += assert_sparse_and_ranges(&scene, &points);
    }
    assert!(checks > 5_000 && unary_nodes > 200 && roi_checks > 50_000, "{checks} {unary_nodes} {roi_checks}");
}

/// A scene with every new node type: each profile extruded and revolved,
/// each unary node, combined by sharp and smooth operators.
pub fn every_node_scene() -> Scene {
    let mut b = Builder::default();
    let profiles = [
        Profile::Circle { radius: 0.3 },
        Profile::Rect { half: [0.35, 0.2] },
        Profile::RoundRect { half: [0.35, 0.25], radius: 0.1 },
        Profile::Capsule { a: [-0.2, -0.1], b: [0.25, 0.2], radius: 0.1 },
        Profile::polygon(&[[0.0, 0.5], [0.12, 0.15], [0.48, 0.15], [0.2, -0.05], [0.3, -0.4], [0.0, -0.18], [-0.3, -0.4], [-0.2, -0.05], [-0.48, 0.15], [-0.12, 0.15]]),
    ];
    let mut items = Vec::new();
    for (k, p) in profiles.into_iter().enumerate() {
        let x = -2.0 + k as f64;
        items.push(b.primitive(Primitive::new(Shape::Extrude { profile: p, half_height: 0.2 }).rotated([1.0, 0.3, 0.0], 0.6).translated([x, 0.8, 0.0])));
        items.push(b.primitive(Primitive::new(Shape::Revolve { profile: p, offset: 0.3 }).rotated([0.2, 1.0, 0.0], 0.9).translated([x, -0.8, 0.0])));
    }
    let sphere = b.primitive(Primitive::new(Shape::Sphere { radius: 0.5 }).translated([0.0, 0.0, 1.5]));
    let shell = b.unary(Unary::Shell { thickness: 0.1 }, sphere);
    let cube = b.primitive(Primitive::new(Shape::RoundBox { half: [0.4; 3], radius: 0.05 }).translated([1.5, 0.0, 1.5]));
    let infill = b.unary(Unary::Infill { period: 0.4, thickness: 0.05 }, cube);
    let torus = b.primitive(Primitive::new(Shape::Torus { major: 0.4, minor: 0.12 }).translated([-1.5, 0.0, 1.5]));
    let bumpy = b.unary(Unary::Displace { amplitude: 0.04, frequency: 5.0 }, torus);
    let grown = b.unary(Unary::Offset { distance: 0.05 }, items[0]);
    items[0] = grown;
    let sharp = b.fold(crate::scene::Operator::UNION, &items);
    let smooth = crate::scene::Operator::smooth(crate::scene::OpKind::Union, crate::scene::Blend::new(0.1));
    let top = b.fold(smooth, &[shell, infill, bumpy]);
    let root = b.operator(crate::scene::Operator::UNION, sharp, top);
    b.finish(root).unwrap()
}

#[test]
fn the_device_interpreter_agrees_with_the_reference_at_random_points() {
    let own = crate::gpu::Gpu::new().unwrap();
    let mut rng = Rng::new(7);
    let mut scenes = vec![every_node_scene()];
    scenes.extend((0..6).map(|_| zoo_tree(&mut rng, 20)));
    for scene in scenes {
        let lin = Linear::new(&scene).unwrap();
        let bb = lin.bounds;
        let points: Vec<[f64; 3]> = (0..4000).map(|_| [0, 1, 2].map(|k| rng.range(bb.min[k] - 0.3, bb.max[k] + 0.3))).collect();
        let p32: Vec<[f32; 3]> = points.iter().map(|p| p.map(|c| c as f32)).collect();
        let got = crate::gpu::eval::eval_points_scene(&own, &lin.field_data(), &p32).unwrap();
        let mut worst = 0.0f64;
        for (p, g) in p32.iter().zip(&got) {
            let want = scene.eval(p.map(f64::from));
            worst = worst.max((*g as f64 - want).abs());
        }
        // f32 parameters and arithmetic on fields of size about 1; the
        // polygon's sign is exact away from its edges, where |f| is large.
        assert!(worst < 2e-4, "worst difference {worst} (features {})", lin.features);
    }
}

#[test]
fn features_name_the_node_types_a_scene_uses() {
    let scene = every_node_scene();
    let lin = Linear::new(&scene).unwrap();
    let all = linear::FEATURE_PROFILE | linear::FEATURE_POLYGON | linear::FEATURE_UNARY | linear::FEATURE_INFILL | linear::FEATURE_DISPLACE | linear::FEATURE_SHAPES;
    assert_eq!(lin.features, all);
    use crate::scene::generate::{generate, Blending, Kind};
    let basic = generate(Kind::Aggregate, 1, Blending::Smooth, 1).unwrap();
    assert_eq!(Linear::new(&basic).unwrap().features, linear::FEATURE_SHAPES);
    let spheres = generate(Kind::SpherePairs, 0, Blending::Smooth, 1).unwrap();
    assert_eq!(Linear::new(&spheres).unwrap().features, 0, "spheres only: the plain-sphere kernel");
    // Displacement raises the bound the scene is traced with.
    assert!(lin.lipschitz() > linear::SMOOTH_LIPSCHITZ * (1.0 + 0.04 * 5.0 * crate::sdf::NOISE_GRADIENT) - 1e-9);
}

#[test]
fn a_renderer_built_without_a_feature_refuses_a_scene_that_needs_it() {
    let own = crate::gpu::Gpu::new().unwrap();
    let basic = crate::scene::generate::generate(crate::scene::generate::Kind::Aggregate, 0, crate::scene::generate::Blending::Sharp, 1).unwrap();
    let data = Linear::new(&basic).unwrap().field_data();
    let o = crate::render::SphereOptions::default();
    let mut r = crate::gpu::Renderer::new(&own, &data, crate::render::Traversal::Sphere(o)).unwrap();
    let zoo = Linear::new(&every_node_scene()).unwrap().field_data();
    let e = r.set_field(&zoo).err().expect("refused").to_string();
    assert!(e.contains("the scene uses node types the kernel was built without"), "{e}");
    // The other way round works: a kernel with every feature draws a basic scene.
    let mut r = crate::gpu::Renderer::new(&own, &zoo, crate::render::Traversal::Sphere(crate::render::SphereOptions::default())).unwrap();
    r.set_field(&data).unwrap();
}

#[test]
fn new_nodes_round_trip_through_the_file_format() {
    let scene = every_node_scene();
    assert_eq!(format::parse(&format::to_json(&scene)).unwrap(), scene);
    let mut rng = Rng::new(8);
    for _ in 0..20 {
        let s = zoo_tree(&mut rng, 8);
        assert_eq!(format::parse(&format::to_json(&s)).unwrap(), s);
    }
}

#[test]
fn bad_new_nodes_are_named_by_their_json_path() {
    let e = |node: &str| {
        let text = format!("{{\"isotrace_scene\": 1, \"root\": 1, \"nodes\": [{{\"type\": \"sphere\", \"radius\": 1}}, {node}]}}");
        format::parse(&text).unwrap_err().to_string()
    };
    let single = |node: &str| {
        let text = format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{node}]}}");
        format::parse(&text).unwrap_err().to_string()
    };
    assert_eq!(single(r#"{"type": "extrude", "profile": {"type": "circle", "radius": 0}, "half_height": 1}"#), "nodes[0].profile.radius: must be > 0");
    assert_eq!(single(r#"{"type": "extrude", "profile": {"type": "cirle", "radius": 1}, "half_height": 1}"#), "nodes[0].profile.type: unknown profile 'cirle'; did you mean 'circle'?");
    assert_eq!(single(r#"{"type": "extrude", "profile": {"type": "rect", "half": [1, 1], "radius": 2}, "half_height": 1}"#), "nodes[0].profile.radius: unknown field for a rect; expected half");
    assert_eq!(single(r#"{"type": "extrude", "profile": {"type": "polygon", "points": [[0, 0], [1, 0]]}, "half_height": 1}"#), "nodes[0].profile.points: a polygon has 3 to 16 vertices, found 2");
    assert_eq!(single(r#"{"type": "extrude", "profile": {"type": "polygon", "points": [[0, 0], [1, 0], [1]]}, "half_height": 1}"#), "nodes[0].profile.points[2]: expected [x, y], found an array");
    assert_eq!(single(r#"{"type": "extrude", "profile": {"type": "circle", "radius": 1}}"#), "nodes[0].half_height: missing");
    assert_eq!(single(r#"{"type": "revolve", "profile": {"type": "circle", "radius": 1}, "offset": -1}"#), "nodes[0].offset: must be >= 0");
    assert_eq!(
        single(r#"{"type": "revolve", "profile": {"type": "capsule", "a": [-3, 0], "b": [-2, 0], "radius": 0.5}, "offset": 1}"#),
        "nodes[0].offset: the profile lies on the far side of the axis (u.x <= -offset everywhere): nothing is revolved"
    );
    assert_eq!(e(r#"{"type": "shell", "child": 0, "thickness": 0}"#), "nodes[1].thickness: must be > 0");
    assert_eq!(e(r#"{"type": "shell", "child": 5, "thickness": 1}"#), "nodes[1].child: refers to nodes[5], but the scene has 2 nodes");
    assert_eq!(e(r#"{"type": "infill", "child": 0, "period": 1}"#), "nodes[1].thickness: missing");
    assert_eq!(e(r#"{"type": "displace", "child": 0, "amplitude": -1, "frequency": 2}"#), "nodes[1].amplitude: must be >= 0");
    assert_eq!(e(r#"{"type": "offset", "child": 0, "distance": 1, "left": 0}"#), "nodes[1].left: unknown field for a offset; expected child or distance");
}

/// The f32 rows a profile primitive gets hold its parameters where the
/// interpreter reads them (the layout of `linear.rs`).
#[test]
fn profile_rows_follow_the_layout() {
    let p = Primitive::new(Shape::Extrude { profile: Profile::polygon(&[[0.0, 0.0], [1.0, 0.0], [0.5, 1.0]]), half_height: 0.25 });
    let rows = linear::primitive_rows(&p);
    assert_eq!(rows.len() as u32, linear::PROFILE_ROWS + 2);
    // The identity frame: Q = (0, 0, 0, 1), c = 0.
    assert_eq!(rows[0], [0.0, 0.0, 0.0, 1.0]);
    assert_eq!(rows[1], [0.0, 0.0, 0.0, linear::FORM_EXTRUDE as f32]);
    assert_eq!(rows[2], [0.0, 0.0, 0.25, 0.0]);
    assert_eq!(rows[3], [0.0, 3.0, 0.0, 0.0]);
    assert_eq!(rows[5], [0.0, 0.0, 1.0, 0.0]);
    assert_eq!(rows[6], [0.5, 1.0, 0.0, 0.0]);
    let c = Primitive::new(Shape::Revolve { profile: Profile::Capsule { a: [0.1, 0.2], b: [0.3, 0.4], radius: 0.05 }, offset: 0.5 });
    let rows = linear::primitive_rows(&c);
    assert_eq!(rows[1][3], linear::FORM_REVOLVE as f32);
    assert_eq!(rows[2], [0.0, 0.0, 0.0, 0.05]);
    assert_eq!(rows[3], [0.5, 0.0, 0.0, 0.0]);
    assert_eq!(rows[4], [0.1, 0.2, 0.3, 0.4]);
    let _ = profile::MAX_POLYGON;
}

/// Every new form in one formula: lowered to a scene, its field equals the
/// compiled formula's (the same functions; f64 on both sides).
#[test]
fn a_formula_of_every_new_form_lowers_to_the_same_field() {
    let f = crate::Formula::compile("<zoo>", EVERY_FORM).unwrap();
    let scene = crate::scene::from_formula(&f, &[]).unwrap();
    let lin = Linear::new(&scene).unwrap();
    assert_eq!(lin.features, linear::FEATURE_PROFILE | linear::FEATURE_POLYGON | linear::FEATURE_UNARY | linear::FEATURE_INFILL | linear::FEATURE_DISPLACE | linear::FEATURE_SHAPES);
    let mut rng = Rng::new(9);
    let mut worst = 0.0f64;
    for _ in 0..20_000 {
        let p = [rng.range(-2.2, 2.2), rng.range(-1.5, 1.5), rng.range(-0.8, 0.8)];
        let want = crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]);
        worst = worst.max((scene.eval(p) - want).abs());
    }
    assert!(worst < 1e-9, "{worst}");
}

/// The same formula traced through the scene field and the compiled one:
/// the same picture, depth within a pixel's footprint.
#[test]
fn every_new_form_draws_the_compiled_picture_through_the_scene_path() {
    use crate::render::Settings;
    let f = crate::Formula::compile("<zoo>", EVERY_FORM).unwrap();
    let s = Settings::for_box([-2.3, 2.3, -1.6, 1.6, -0.9, 0.9], 128, 96);
    let (a, b) = scene_and_compiled(&f, &s);
    let (both, far, differ) = picture_agreement(&a, &b, &s);
    assert!(both > 1000, "{both}");
    assert!(far * 50 < both, "{far} of {both} pixels differ by more than a footprint");
    assert!(differ * 100 < a.pixels.len(), "{differ} pixels hit in one picture only");
    assert_eq!((a.stats.unresolved, a.stats.field.overflow_tiles), (0, 0));
    eprintln!("both {both}, far {far}, differ {differ} of {}", a.pixels.len());
}

/// The modelling examples are the scenes their formulas lower to
/// (`isotrace scene lower -f examples/scene-src/NAME.txt`), and they trace
/// to the end on every pixel.
#[test]
fn the_modelling_examples_are_their_formulas() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let own = crate::gpu::Gpu::new().unwrap();
    for name in ["heat-exchanger", "carved", "profiles", "procedural"] {
        let src = std::fs::read_to_string(format!("{dir}/examples/scene-src/{name}.txt")).unwrap();
        let f = crate::Formula::compile(name, &src).unwrap();
        let lowered = crate::scene::from_formula(&f, &[]).unwrap();
        let file = format::load(std::path::Path::new(&format!("{dir}/examples/{name}.scene.json"))).unwrap();
        assert_eq!(file, lowered, "{name}: regenerate with isotrace scene lower");
        let lin = Linear::new(&file).unwrap();
        let data = lin.field_data();
        let o = crate::render::SphereOptions { lipschitz: lin.lipschitz(), ..Default::default() };
        let s = crate::render::Settings::for_box(lin.bounds.padded().unwrap(), 96, 96);
        let frame = crate::gpu::Renderer::new(&own, &data, crate::render::Traversal::Sphere(o)).unwrap().render(&s).unwrap();
        let hits = frame.pixels.iter().filter(|p| p.status == crate::render::Status::Hit).count();
        assert!(hits > 500, "{name}: {hits} hits");
        assert_eq!((frame.stats.unresolved, frame.stats.field.overflow_tiles), (0, 0), "{name}");
    }
}

/// Two pebbles from `examples/pebble.npy` (one moved, turned and scaled)
/// blended, on a ground slab.
fn pebbles() -> Scene {
    format::load(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/pebbles.scene.json"))).unwrap()
}

#[test]
fn grid_nodes_read_their_file_once_and_round_trip() {
    let scene = pebbles();
    let grids: Vec<_> = scene.nodes().iter().filter_map(|n| match n {
        Node::Primitive(Primitive { shape: Shape::Grid(g), .. }) => Some(g.grid.clone()),
        _ => None,
    }).collect();
    assert_eq!(grids.len(), 2);
    assert!(std::sync::Arc::ptr_eq(&grids[0], &grids[1]), "one file, one grid");
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/examples");
    assert_eq!(format::parse_in(&format::to_json(&scene), std::path::Path::new(dir)).unwrap(), scene);
    assert_eq!(Linear::new(&scene).unwrap().features, linear::FEATURE_GRID | linear::FEATURE_SHAPES);
    // The field is the grid's interpolant under the primitive's transform.
    let g = crate::scene::grid::Grid::pebble();
    for p in [[0.1, 0.2, 0.3], [0.9, -0.4, 0.2], [3.0, 2.0, 1.0]] {
        let Node::Primitive(prim) = &scene.nodes()[0] else { unreachable!() };
        assert_eq!(prim.distance(p), g.eval(p));
    }
    assert!(scene.to_formula().unwrap_err().to_string().contains("is a grid, which the formula language has no form for"));
}

#[test]
fn bad_grid_nodes_name_the_field_and_the_file() {
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/examples"));
    let e = |node: &str| {
        let text = format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{node}]}}");
        format::parse_in(&text, dir).unwrap_err().to_string()
    };
    let missing = e(r#"{"type": "grid", "file": "nothere.npy", "spacing": 0.1, "origin": [0, 0, 0]}"#);
    assert!(missing.starts_with("nodes[0].file: ") && missing.contains("nothere.npy"), "{missing}");
    assert_eq!(e(r#"{"type": "grid", "file": "pebble.npy", "spacing": 0.1}"#), "nodes[0].origin: missing: a grid with a spacing needs its origin too");
    assert_eq!(e(r#"{"type": "grid", "file": "pebble.npy"}"#), format!("nodes[0].file: {}: a .npy file holds only values: the grid's spacing and origin must be given", dir.join("pebble.npy").display()));
    assert_eq!(e(r#"{"type": "grid", "file": 3}"#), "nodes[0].file: expected a file name, found 3");
    assert_eq!(e(r#"{"type": "grid", "file": "pebble.npy", "spacing": 0.1, "origin": [0, 0, 0], "radius": 1}"#), "nodes[0].radius: unknown field for a grid; expected file, spacing, origin, translate, rotate, scale or warp");
    let vdb = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/grid/sphere.vdb");
    let text = format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{{\"type\": \"grid\", \"file\": \"{vdb}\"}}]}}");
    let ok = format::parse_with(&text, std::path::Path::new(""), &format::GridPaths::Any).unwrap();
    assert!(ok.eval([0.0, 0.0, 0.0]) < 0.0);
}

#[test]
fn grid_bounding_volumes_and_bounds_hold_by_sampling() {
    let scene = pebbles();
    let lin = Linear::new(&scene).unwrap();
    let mut rng = Rng::new(10);
    let mut inside = 0;
    for (k, &node) in lin.primitives.iter().enumerate() {
        let Node::Primitive(p) = &scene.nodes()[lin.order[node as usize]] else { unreachable!() };
        let Shape::Grid(_) = p.shape else { continue };
        let r_plus = lin.roi[node as usize].hi;
        let bb = lin.abvs[k].aabb();
        for _ in 0..20_000 {
            let x = [0, 1, 2].map(|a| rng.range(bb.min[a] - 1.0, bb.max[a] + 1.0));
            if p.distance(x) <= r_plus {
                inside += 1;
                assert!(lin.abvs[k].contains(x), "{x:?} outside {:?}", lin.abvs[k]);
            }
        }
    }
    assert!(inside > 2_000, "{inside}");
    // The bound the scene is traced with holds where the field is >= 0.
    let mut worst = 0.0f64;
    for _ in 0..40_000 {
        let a = DVec3::new(rng.range(-1.5, 3.5), rng.range(-1.5, 2.0), rng.range(-0.6, 1.4));
        let b = a + rng.direction() * rng.range(1e-4, 0.03);
        let (fa, fb) = (scene.eval(a.to_array()), scene.eval(b.to_array()));
        if fa >= 0.0 && fb >= 0.0 {
            worst = worst.max((fa - fb).abs() / (a - b).length());
        }
    }
    assert!(worst <= lin.lipschitz(), "{worst} > {}", lin.lipschitz());
}

#[test]
fn the_device_interpolates_grids_as_the_reference_does() {
    let own = crate::gpu::Gpu::new().unwrap();
    let scene = pebbles();
    let lin = Linear::new(&scene).unwrap();
    let mut rng = Rng::new(11);
    let p32: Vec<[f32; 3]> = (0..20_000).map(|_| [rng.range(-1.6, 3.6) as f32, rng.range(-1.6, 2.2) as f32, rng.range(-1.4, 1.4) as f32]).collect();
    let got = crate::gpu::eval::eval_points_scene(&own, &lin.field_data(), &p32).unwrap();
    let worst = p32.iter().zip(&got).map(|(p, g)| (*g as f64 - scene.eval(p.map(f64::from))).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-4, "{worst}");
}

/// `repeat`: a centred grid of copies, the same union in the compiled
/// formula and in the scene it lowers to (one primitive per copy, so the
/// tile lists cull copy by copy).
#[test]
fn repeat_is_a_centred_grid_of_copies_on_both_paths() {
    let src = "repeat(0.5, 0.6, 1, 3, 2, 1, shell(0.04, extrude(0.1, circle(0.15))))";
    let f = crate::Formula::compile("<repeat>", src).unwrap();
    let scene = crate::scene::from_formula(&f, &[]).unwrap();
    assert_eq!(scene.primitive_count(), 6);
    let one = |p: [f64; 3]| {
        let q = DVec2::new(p[0], p[1]);
        (profile::extrude(q.length() - 0.15, p[2], 0.1)).abs() - 0.02
    };
    let mut rng = Rng::new(12);
    for _ in 0..5000 {
        let p = [rng.range(-1.5, 1.5), rng.range(-1.0, 1.0), rng.range(-0.5, 0.5)];
        let mut want = f64::INFINITY;
        for i in 0..3 {
            for j in 0..2 {
                want = want.min(one([p[0] - 0.5 * (i as f64 - 1.0), p[1] - 0.6 * (j as f64 - 0.5), p[2]]));
            }
        }
        let compiled = crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]);
        assert!((compiled - want).abs() < 1e-12 && (scene.eval(p) - want).abs() < 1e-12, "{p:?}: {compiled} {} {want}", scene.eval(p));
    }
    for (bad, message) in [
        ("repeat(1, 1, 1, 2.5, 1, 1, sphere(0.2))", "a copy count must be a whole number from 1 to 4096, got 2.5"),
        ("repeat(1, 1, 1, 100, 100, 1, sphere(0.2))", "10000 copies, above the limit of 4096"),
    ] {
        let e = crate::Formula::compile("<repeat>", bad).unwrap_err();
        assert!(format!("{e:?}").contains(message), "{bad}: {e:?}");
    }
}

/// `mirror`: a shape and its reflection, the same field compiled and as a
/// scene, where each reflected primitive is a rotated twin of its type
/// (asymmetric shapes mirrored in their own frame), also nested, tilted,
/// scaled and under unary nodes.
#[test]
fn mirror_reflects_every_shape_on_both_paths() {
    let src = "\
        star = polygon(0.1, 0.4, 0.2, 0.1, 0.5, 0.05, 0.25, -0.1, 0.35, -0.45, 0.05, -0.2, -0.2, -0.3, -0.1, 0);
        parts = union(
            translate(0.8, 0.3, 0.1, rotate(1, 2, 3, 0.7, extrude(0.1, star))),
            translate(0.6, -0.5, 0.2, rotate(0, 1, 1, 0.4, capsule(0, 0, 0, 0.3, 0.2, -0.1, 0.08))),
            translate(1.2, 0.1, -0.3, rotate(1, 0, 0, 0.9, revolve(0.2, capsule2d(0, -0.1, 0.1, 0.12, 0.04)))),
            shell(0.05, translate(0.9, 0.6, -0.2, scale(0.7, rotate(0, 0, 1, 0.3, roundbox(0.2, 0.1, 0.15, 0.03))))),
            intersect(translate(0.5, 0, 0, sphere(0.6)), plane(1, 0.3, 0.2, 0.5)));
        mirror(0, 1, 0, scale(1.3, mirror(1, 0.2, -0.1, translate(0.2, 0, 0, parts))))";
    let f = crate::Formula::compile("<mirror>", src).unwrap();
    let scene = crate::scene::from_formula(&f, &[]).unwrap();
    assert_eq!(scene.primitive_count(), 24);
    let mut rng = Rng::new(13);
    let mut worst = 0.0f64;
    for _ in 0..20_000 {
        let p = [rng.range(-2.5, 2.5), rng.range(-2.0, 2.0), rng.range(-1.5, 1.5)];
        let want = crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]);
        worst = worst.max((scene.eval(p) - want).abs());
    }
    assert!(worst < 1e-9, "{worst}");
    let e = crate::scene::from_formula(&crate::Formula::compile("<m>", "mirror(1, 0, 0, infill(0.5, 0.1, sphere(1)))").unwrap(), &[]).unwrap_err();
    assert_eq!(e.reason, "a transform over 'infill' is not a blobtree node (its pattern is fixed in the world): transform its operand instead");
}

/// `repeat` and `mirror` nodes in a scene file expand when it is read into
/// the scene their formula forms lower to.
#[test]
fn repeat_and_mirror_nodes_expand_as_their_forms_lower() {
    let text = r#"{"isotrace_scene": 1, "root": 4, "nodes": [
        {"type": "capsule", "a": [0, 0, 0], "b": [0.3, 0.2, -0.1], "radius": 0.08, "translate": [0.6, 0.1, 0]},
        {"type": "extrude", "profile": {"type": "polygon", "points": [[0, 0], [0.3, 0], [0.1, 0.2]]}, "half_height": 0.05, "translate": [0.9, -0.4, 0]},
        {"type": "union", "left": 0, "right": 1},
        {"type": "mirror", "child": 2, "normal": [1, 0.2, 0]},
        {"type": "repeat", "child": 3, "spacing": [3, 1.5, 1], "count": [2, 3, 1]}
    ]}"#;
    let scene = format::parse(text).unwrap();
    assert_eq!(scene.primitive_count(), 2 * 2 * 6);
    let src = "repeat(3, 1.5, 1, 2, 3, 1, mirror(1, 0.2, 0, union(translate(0.6, 0.1, 0, capsule(0, 0, 0, 0.3, 0.2, -0.1, 0.08)), \
               translate(0.9, -0.4, 0, extrude(0.05, polygon(0, 0, 0.3, 0, 0.1, 0.2))))))";
    let lowered = crate::scene::from_formula(&crate::Formula::compile("<copies>", src).unwrap(), &[]).unwrap();
    let mut rng = Rng::new(14);
    for _ in 0..5000 {
        let p = [rng.range(-3.5, 3.5), rng.range(-2.5, 2.5), rng.range(-0.6, 0.6)];
        assert!((scene.eval(p) - lowered.eval(p)).abs() < 1e-12, "{p:?}");
    }
    let bad = |node: &str| format::parse(&format!("{{\"isotrace_scene\": 1, \"root\": 1, \"nodes\": [{{\"type\": \"sphere\", \"radius\": 1}}, {node}]}}")).unwrap_err().to_string();
    assert_eq!(bad(r#"{"type": "repeat", "child": 0, "spacing": [1, 1, 1], "count": [2, 0.5, 1]}"#), "nodes[1].count[1]: a copy count must be a whole number from 1 to 4096, got 0.5");
    assert_eq!(bad(r#"{"type": "mirror", "child": 0, "normal": [0, 0, 0]}"#), "nodes[1].normal: must not be zero");
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/examples"));
    let grid = r#"{"isotrace_scene": 1, "root": 1, "nodes": [{"type": "grid", "file": "pebble.npy", "spacing": 0.05, "origin": [0, 0, 0]}, {"type": "mirror", "child": 0, "normal": [1, 0, 0]}]}"#;
    assert_eq!(format::parse_in(grid, dir).unwrap_err().to_string(), "nodes: a voxel grid or a twisted or bent shape cannot be mirrored");
}

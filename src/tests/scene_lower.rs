//! Formula → scene lowering (`scene::lower`): a formula built only from
//! distance forms lowers to the blobtree it describes.
//!
//! * A scene written out as a formula (`Scene::to_formula`) lowers back to
//!   the same field (f64, at random points).
//! * The catalog's distance-field models lower, and the lowered field has
//!   the sign of the formula's field everywhere (the smooth operators
//!   become compact ones, which change values away from the surface but
//!   not the zero set; the module docs give the argument, this checks it).
//! * What is not a blobtree is refused with the reason and its span.

use crate::scene::generate::{generate, Blending, Kind, Rng};
use crate::scene::{from_formula, Scene};
use crate::Formula;

fn lower(src: &str, params: &[f32]) -> Result<Scene, crate::scene::NotBlobtree> {
    let f = Formula::compile("<test>", src).unwrap_or_else(|e| panic!("{e}"));
    from_formula(&f, params)
}

fn points(n: usize, lo: [f64; 3], hi: [f64; 3], seed: u64) -> Vec<[f64; 3]> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| std::array::from_fn(|k| rng.range(lo[k], hi[k]))).collect()
}

#[test]
fn a_scene_written_as_a_formula_lowers_back_to_the_same_field() {
    let mut scenes = vec![];
    for blending in [Blending::Sharp, Blending::SmoothInside, Blending::Smooth] {
        scenes.push(generate(Kind::Aggregate, 1, blending, 7).unwrap());
        scenes.push(generate(Kind::Boxes, 0, blending, 3).unwrap());
        scenes.push(generate(Kind::SpherePairs, 0, blending, 5).unwrap());
    }
    for file in ["blobs", "aggregate-1", "boxes-1", "sphere-pairs-0"] {
        let path = format!("{}/examples/{file}.scene.json", env!("CARGO_MANIFEST_DIR"));
        scenes.push(crate::scene::format::load(std::path::Path::new(&path)).unwrap());
    }
    for (i, scene) in scenes.iter().enumerate() {
        let text = scene.to_formula().unwrap();
        let lowered = lower(&text, &[]).unwrap();
        assert_eq!(lowered.len(), scene.len(), "scene {i}");
        assert_eq!(lowered.summary(), scene.summary(), "scene {i}");
        for p in points(2000, [-3.0; 3], [3.0; 3], i as u64) {
            let (a, b) = (scene.eval(p), lowered.eval(p));
            assert!((a - b).abs() <= 1e-9 * (1.0 + a.abs()), "scene {i} at {p:?}: {a} vs {b}");
        }
    }
}

#[test]
fn transforms_compose_down_to_the_primitives() {
    // Nested translate / rotate / scale around an operator, against the
    // formula's own f64 evaluation.
    let src = "translate(0.3, -0.2, 0.1, rotate(1, 2, 3, 0.7, scale(1.5, union(rotate(0, 0, 1, 0.4, box(0.3, 0.2, 0.1)), \
               translate(0.2, 0, 0, scale(0.5, torus(0.6, 0.2)))))))";
    let f = Formula::compile("<test>", src).unwrap();
    let scene = from_formula(&f, &[]).unwrap();
    assert_eq!(scene.primitive_count(), 2);
    for p in points(3000, [-2.0; 3], [2.0; 3], 11) {
        let want = crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]);
        let got = scene.eval(p);
        assert!((want - got).abs() < 1e-6, "at {p:?}: formula {want}, scene {got}");
    }
}

#[test]
fn the_catalog_models_lower_with_the_formula_sign_everywhere() {
    for name in ["creature", "city", "jewel"] {
        let entry = crate::catalog::lookup(name).unwrap();
        let f = entry.compile().unwrap();
        let scene = from_formula(&f, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
        let b = entry.header.bbox;
        let (mut near, mut checked) = (0, 0);
        for p in points(20000, [b[0], b[2], b[4]], [b[1], b[3], b[5]], 1) {
            let want = crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]);
            let got = scene.eval(p);
            if want.abs() < 1e-9 {
                continue;
            }
            checked += 1;
            near += (want.abs() < 0.05) as usize;
            assert_eq!(want > 0.0, got > 0.0, "{name} at {p:?}: formula {want}, scene {got}");
        }
        assert!(checked > 19000 && near > 100, "{name}: {checked} points, {near} near the surface");
    }
}

#[test]
fn parameters_are_evaluated_with_their_values() {
    let src = "translate(a, 0, 0, sphere(r * 2))";
    let f = Formula::compile("<test>", src).unwrap();
    // Parameters in the formula's order: a, r.
    assert_eq!(f.ir.params.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>(), ["a", "r"]);
    let scene = from_formula(&f, &[1.0, 0.25]).unwrap();
    assert!((scene.eval([1.0, 0.0, 0.0]) + 0.5).abs() < 1e-12);
    assert!((scene.eval([2.0, 0.0, 0.0]) - 0.5).abs() < 1e-12);
}

#[test]
fn what_is_not_a_blobtree_is_refused_at_its_span() {
    let cases: &[(&str, &str, &str)] = &[
        ("x^2 + y^2 + z^2 - 1", "'x' outside a distance form: the field is not built from primitives alone", "x"),
        ("sphere(1) + 0.1", "arithmetic on a shape is not a blobtree node", "sphere(1)"),
        ("-sphere(1)", "a shape under unary minus is not a blobtree node", "-sphere(1)"),
        ("sphere(1) where z > 0", "a scene has no 'where' conditions", "z > 0"),
        ("union(sphere(1), translate(x, 0, 0, sphere(1)))", "'x' outside a distance form: the field is not built from primitives alone", "x"),
        ("sphere(1) where z > 0; box(1, 1, 1) where z < 0", "a scene draws one surface; the formula has several", "box(1, 1, 1)"),
        ("roundbox(1, 1, 1, 2)", "not a valid scene node: radius must be >= 0 and <= the smallest half extent (1)", "roundbox(1, 1, 1, 2)"),
    ];
    for (src, reason, at) in cases {
        let f = match Formula::compile("<test>", src) {
            Ok(f) => f,
            Err(e) => panic!("{src}: {e}"),
        };
        let e = from_formula(&f, &[]).unwrap_err();
        assert_eq!(e.reason, *reason, "{src}");
        assert_eq!(&src[e.span.start as usize..e.span.end as usize], *at, "{src}");
    }
    // Definitions used twice are copied: a doubling chain is refused at
    // the node limit instead of allocating a billion nodes.
    let mut src = String::from("a0 = sphere(1);\n");
    for k in 1..40 {
        src += &format!("a{k} = union(a{}, a{});\n", k - 1, k - 1);
    }
    src += "a39";
    let e = lower(&src, &[]).unwrap_err();
    assert_eq!(e.reason, "the blobtree would have more than 1000000 nodes (definitions used several times are copied)");
}

/// A union of balls as a program writes it: distances written out, in
/// every spelling of the squares and the axes in any order, under a
/// variadic `min`; a `max` of them is their intersection. Each lowers to
/// its balls, with the formula's field at random points.
#[test]
fn written_out_distances_lower_to_balls() {
    let spellings = ["(x - {a})^2 + (y - {b})^2 + (z - {c})^2", "(z - {c})^2 + ({a} - x)^2 + (y + -{b})^2", "(x + -{a})^2 + ((y - {b})^2 + (z - {c})^2)"];
    let mut rng = Rng::new(3);
    let balls: Vec<String> = (0..40)
        .map(|i| {
            let [a, b, c] = [0; 3].map(|_| (rng.range(-1.0, 1.0) * 1000.0).round() / 1000.0);
            let r = 0.05 + 0.002 * i as f64;
            format!("sqrt({}) - {r:.3}", spellings[i % 3].replace("{a}", &format!("{a}")).replace("{b}", &format!("{b}")).replace("{c}", &format!("{c}")))
        })
        .collect();
    let origin = "sqrt(x^2 + y^2 + z^2) - 0.3".to_string();
    for src in [format!("min({}, {origin})", balls.join(", ")), format!("max({}, {})", balls[0], balls[1])] {
        let f = Formula::compile("<test>", &src).unwrap();
        let scene = from_formula(&f, &[]).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.primitive_count(), if src.starts_with("min") { 41 } else { 2 });
        for p in points(3000, [-1.3; 3], [1.3; 3], 5) {
            let want = crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]);
            let got = scene.eval(p);
            assert!((want - got).abs() < 1e-9, "at {p:?}: formula {want}, scene {got}");
        }
    }
    // Not a ball: an axis missing or twice, a radius of 0, another power.
    let cases: &[(&str, &str, &str)] = &[
        ("sqrt((x - 1)^2 + (y - 2)^2) - 1", "'x' outside a distance form: the field is not built from primitives alone", "x"),
        ("sqrt((x - 1)^2 + (x - 2)^2 + z^2) - 1", "'x' outside a distance form: the field is not built from primitives alone", "x"),
        ("sqrt(x^2 + y^2 + z^2) - 0", "'x' outside a distance form: the field is not built from primitives alone", "x"),
        ("sqrt(x^2 + y^2 + z^3) - 1", "'x' outside a distance form: the field is not built from primitives alone", "x"),
        ("min(sphere(1), 0.5)", "min of a shape and a number is not a blobtree node", "0.5"),
        ("max(sphere(1), circle(0.5))", "a 2D profile is a blobtree node only inside extrude or revolve", "circle(0.5)"),
    ];
    for (src, reason, at) in cases {
        let f = Formula::compile("<test>", src).unwrap_or_else(|e| panic!("{src}: {e}"));
        let e = from_formula(&f, &[]).unwrap_err();
        assert_eq!(e.reason, *reason, "{src}");
        assert_eq!(&src[e.span.start as usize..e.span.end as usize], *at, "{src}");
    }
}

#[test]
fn auto_takes_the_scene_from_32_bounded_primitives() {
    use crate::choice::{auto_scene, FieldKind, SCENE_AUTO_MIN_BOUNDED};
    use crate::render::{BisectOptions, SphereOptions, Traversal};
    let sphere = Traversal::Sphere(SphereOptions::default());
    let kind = |name: &str, t: &Traversal| {
        let f = crate::catalog::lookup(name).unwrap().compile().unwrap();
        auto_scene(&f, &[], t).map(|(field, l)| (field.kind(), l))
    };
    // @city: 36 bounded primitives (and a ground plane), sharp unions.
    assert_eq!(kind("city", &sphere), Some((FieldKind::Scene, 1.0)));
    // @creature: 21 bounded; @jewel: 49 planes, none bounded; @tangle: no blobtree.
    for name in ["creature", "jewel", "tangle"] {
        assert_eq!(kind(name, &sphere), None, "{name}");
    }
    // Bisected in IA too; not in RAA (a scene's enclosures are intervals),
    // nor with --inline hooks (a scene runs no user WGSL).
    assert_eq!(kind("city", &Traversal::Bisect(BisectOptions::new(crate::ir::Domain::Interval))), Some((FieldKind::Scene, 1.0)));
    assert_eq!(kind("city", &Traversal::Bisect(BisectOptions::new(crate::ir::Domain::Affine))), None);
    let mut hooked = BisectOptions::new(crate::ir::Domain::Interval);
    hooked.modalities.inline = Some(crate::inline::parse_inline("hooks.wgsl", "fn hook_hit(q: vec3f) -> bool { return true; }\n").unwrap());
    assert_eq!(kind("city", &Traversal::Bisect(hooked)), None);
    // The threshold itself: 31 spheres in a row stay compiled, 32 do not.
    let row = |n: usize| (0..n).map(|i| format!("translate({}, 0, 0, sphere(0.4))", i)).reduce(|a, b| format!("union({a}, {b})")).unwrap();
    for (n, want) in [(SCENE_AUTO_MIN_BOUNDED - 1, None), (SCENE_AUTO_MIN_BOUNDED, Some(FieldKind::Scene))] {
        let f = Formula::compile("<test>", &row(n)).unwrap();
        assert_eq!(auto_scene(&f, &[], &sphere).map(|(field, _)| field.kind()), want, "{n} spheres");
    }
    // And a min of 32 distances written out.
    let balls = (0..SCENE_AUTO_MIN_BOUNDED).map(|i| format!("sqrt((x - {i})^2 + y^2 + z^2) - 0.4")).collect::<Vec<_>>();
    let f = Formula::compile("<test>", &format!("min({})", balls.join(", "))).unwrap();
    assert_eq!(auto_scene(&f, &[], &sphere).map(|(field, l)| (field.kind(), l)), Some((FieldKind::Scene, 1.0)));
}

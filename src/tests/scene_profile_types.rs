//! Every profile of the table (`crate::sdf::profile::TYPES`) end to end,
//! from its descriptor alone: extruded and revolved, a scene file node
//! reads back to itself, its formula text compiles to the same field as
//! the scene's f64 reference and lowers back to the same node, its
//! parameters convert to the scene model and back, its feature bits and
//! GPU row are the descriptor's, and a non-finite parameter is refused by
//! its field's name. A new profile is checked here without a line of its
//! own.

use super::scene_common::random_profile;
use crate::scene::codes::{FEATURE_POLYGON, FEATURE_PROFILE, FEATURE_SHAPES};
use crate::scene::generate::Rng;
use crate::scene::linear::Linear;
use crate::scene::{format, Builder, Primitive, Profile, Scene, Shape};
use crate::sdf::profile::TYPES;

/// A random profile of each type of the table, in table order.
fn one_of_each(rng: &mut Rng) -> Vec<Profile> {
    TYPES
        .iter()
        .map(|t| (0..1000).map(|_| random_profile(rng, 1.0)).find(|p| p.kind() == *t).unwrap_or_else(|| panic!("no random {t:?}")))
        .collect()
}

fn scene_of(shape: Shape) -> Scene {
    let mut b = Builder::default();
    let root = b.primitive(Primitive::new(shape).rotated([0.3, 0.5, 0.8], 0.7).translated([0.1, -0.2, 0.3]));
    b.finish(root).unwrap()
}

fn solids(profile: Profile) -> [Shape; 2] {
    [Shape::Extrude { profile, half_height: 0.4 }, Shape::Revolve { profile, offset: 0.9 }]
}

#[test]
fn each_profile_reads_writes_and_lowers_to_its_f64_reference() {
    let mut rng = Rng::new(12);
    assert_eq!(Profile::NAMES.to_vec(), TYPES.iter().map(|t| t.scene_name).collect::<Vec<_>>());
    for profile in one_of_each(&mut rng) {
        let (t, v) = profile.typed();
        assert_eq!(Profile::from_params(t, &v), profile, "{t:?}");
        assert_eq!(profile.mirror_x().mirror_x(), profile, "{t:?}");
        assert_eq!(profile.fields().len(), v.len(), "{t:?}");
        for shape in solids(profile) {
            let scene = scene_of(shape);
            let json = format::to_json(&scene);
            assert_eq!(format::parse(&json).unwrap().nodes(), scene.nodes(), "{t:?}");
            let text = scene.to_formula().unwrap();
            assert!(text.contains(&format!("{}(", t.info.name)), "{text}");
            let f = crate::Formula::compile("<test>", &text).unwrap_or_else(|e| panic!("{text}: {e}"));
            for _ in 0..300 {
                let p = [rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5)];
                let (a, b) = (scene.eval(p), crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]));
                assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{t:?} at {p:?}: scene {a}, formula {b}");
            }
            assert_eq!(format::to_json(&crate::scene::from_formula(&f, &[]).unwrap()), json, "{t:?}");
        }
    }
}

#[test]
fn each_profiles_features_and_row_are_its_descriptors() {
    let mut rng = Rng::new(13);
    for profile in one_of_each(&mut rng) {
        let (t, v) = profile.typed();
        let row = (t.row)(&v);
        let [extruded, _] = solids(profile);
        let lin = Linear::new(&scene_of(extruded)).unwrap();
        let data = lin.field_data();
        let want = FEATURE_SHAPES | if t.has_points() { FEATURE_PROFILE | FEATURE_POLYGON } else { FEATURE_PROFILE };
        assert_eq!(data.features, want, "{t:?}");
        let f = |x: f64| x as f32;
        assert!(data.params.contains(&[f(row.e[0]), f(row.e[1]), 0.4, f(row.r)]), "{t:?}: {:?}", data.params);
        assert!(data.params.contains(&[f(row.a[0]), f(row.a[1]), f(row.b[0]), f(row.b[1])]), "{t:?}");
        if !t.has_points() {
            // The shared formula box₂(u − a − (b − a)·h, e) − r is the profile.
            for _ in 0..200 {
                let u = glam::DVec2::new(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
                let (a, b) = (glam::DVec2::from(row.a), glam::DVec2::from(row.b));
                let (pa, ba) = (u - a, b - a);
                let h = if ba.dot(ba) > 0.0 { (pa.dot(ba) / ba.dot(ba)).clamp(0.0, 1.0) } else { 0.0 };
                let shared = crate::sdf::profile::box2(pa - ba * h, glam::DVec2::from(row.e)) - row.r;
                assert!((shared - profile.distance(u)).abs() < 1e-12, "{t:?} at {u}");
            }
        }
    }
}

#[test]
fn a_non_finite_parameter_is_refused_naming_its_field() {
    let mut rng = Rng::new(14);
    for profile in one_of_each(&mut rng) {
        let (t, v) = profile.typed();
        let names = t.param_names(&v);
        for k in 0..v.len() {
            let mut bad = v.to_vec();
            bad[k] = f64::NAN;
            let err = Profile::from_params(t, &bad).check().unwrap_err();
            assert_eq!(err, (format!("profile.{}", names[k]), "must be finite".to_string()), "{t:?}");
        }
    }
}

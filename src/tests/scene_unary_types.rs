//! Every unary type of the table (`crate::sdf::unary::TYPES`) end to
//! end, from its descriptor alone: a scene file node reads back to itself,
//! its formula text compiles to the same field as the scene's f64
//! reference, a bad parameter is refused naming its field, and its GPU
//! row and interpreter case are the descriptor's. A new unary type is
//! checked here without a line of its own.

use crate::scene::generate::Rng;
use crate::scene::linear::Linear;
use crate::scene::{format, Builder, Primitive, Scene, Shape, Unary};
use crate::sdf::unary::TYPES;

/// Parameters every type accepts (lengths and frequencies of a unit shape).
fn params(n: usize) -> Vec<f64> {
    [0.4, 3.0].iter().copied().take(n).collect()
}

fn scene_of(op: Unary) -> Scene {
    let mut b = Builder::default();
    let s = b.primitive(Primitive::new(Shape::Torus { major: 0.8, minor: 0.3 }));
    let root = b.unary(op, s);
    b.finish(root).unwrap()
}

#[test]
fn each_unary_type_reads_writes_and_lowers_to_its_f64_reference() {
    let mut rng = Rng::new(5);
    for t in TYPES {
        let op = Unary::from_values(t, &params(t.param_count()));
        assert_eq!(op.kind(), t);
        let scene = scene_of(op);
        let json = format::to_json(&scene);
        assert!(json.contains(&format!("\"type\": \"{}\"", t.name())), "{json}");
        assert_eq!(format::parse(&json).unwrap().nodes(), scene.nodes(), "{t:?}");
        let text = scene.to_formula().unwrap();
        assert!(text.contains(&format!("{}(", t.name())), "{text}");
        let f = crate::Formula::compile("<test>", &text).unwrap_or_else(|e| panic!("{text}: {e}"));
        for _ in 0..200 {
            let p = [rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5)];
            let (a, b) = (scene.eval(p), crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]));
            assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{t:?} at {p:?}: scene {a}, formula {b}");
        }
        let lowered = crate::scene::from_formula(&f, &[]).unwrap();
        assert_eq!(format::to_json(&lowered), json, "{t:?}");
    }
}

#[test]
fn each_unary_types_row_and_case_are_its_descriptors() {
    let shader = crate::field::scene::scene_eval_shader(u32::MAX >> 1);
    for t in TYPES {
        let v = params(t.param_count());
        let lin = Linear::new(&scene_of(Unary::from_values(t, &v))).unwrap();
        let data = lin.field_data();
        let row = (t.row)(&v).map(|x| x as f32);
        assert!(data.params.contains(&row), "{t:?}: {:?}", data.params);
        assert_eq!(data.features & t.wgsl.feature, t.wgsl.feature, "{t:?}");
        assert!(shader.contains(t.wgsl.code), "{t:?}");
        assert!(shader.contains(&format!("const NODE_{}: u32 = {}u;", t.name().to_uppercase(), t.code)), "{t:?}");
    }
}

#[test]
fn a_non_finite_parameter_is_refused_naming_its_field() {
    for t in TYPES {
        for k in 0..t.param_count() {
            let mut v = params(t.param_count());
            v[k] = f64::NAN;
            let err = Unary::from_values(t, &v).check().unwrap_err();
            assert_eq!(err, (t.fields[k].to_string(), "must be finite".to_string()), "{t:?}");
        }
    }
}

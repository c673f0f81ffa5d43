//! Every join of the table (`crate::sdf::join::TYPES`) end to end, from
//! its descriptor alone: for each of its operations a scene file node
//! reads back to itself, its formula text compiles to the same field as
//! the scene's f64 reference and lowers back to the same node, and its
//! type codes and interpreter case are the descriptor's. A new join is
//! checked here without a line of its own.

use crate::scene::generate::Rng;
use crate::scene::linear::{Linear, NODE_TYPE_MASK, NODE_TYPE_SHIFT};
use crate::scene::{format, Builder, Join, Operator, Primitive, Scene, Shape};
use crate::sdf::join::TYPES;

fn scene_of(op: Operator) -> Scene {
    let mut b = Builder::default();
    let l = b.primitive(Primitive::new(Shape::Sphere { radius: 0.8 }));
    let mut right = Primitive::new(Shape::Box { half: [0.5, 0.6, 0.4] });
    right.transform.translate = [0.7, 0.1, 0.0];
    let r = b.primitive(right);
    let root = b.operator(op, l, r);
    b.finish(root).unwrap()
}

#[test]
fn each_join_reads_writes_and_lowers_to_its_f64_reference() {
    let mut rng = Rng::new(9);
    for t in TYPES {
        for (&kind, (name, form)) in t.kinds().iter().zip(t.scene_names.iter().zip(t.forms)) {
            let op = Operator::joined(kind, Join::from_size(t, 0.25));
            assert_eq!((op.name(), Operator::parse(name, 0.25)), (*name, Some(op)));
            let scene = scene_of(op);
            let json = format::to_json(&scene);
            assert_eq!(format::parse(&json).unwrap().nodes(), scene.nodes(), "{name}");
            let text = scene.to_formula().unwrap();
            assert!(text.contains(&format!("{}(", form.name)), "{text}");
            let f = crate::Formula::compile("<test>", &text).unwrap_or_else(|e| panic!("{text}: {e}"));
            for _ in 0..300 {
                let p = [rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5)];
                let (a, b) = (scene.eval(p), crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]));
                assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{name} at {p:?}: scene {a}, formula {b}");
            }
            assert_eq!(format::to_json(&crate::scene::from_formula(&f, &[]).unwrap()), json, "{name}");
        }
    }
}

#[test]
fn each_joins_codes_and_case_are_its_descriptors() {
    let shader = crate::field::scene::scene_eval_shader(u32::MAX >> 1);
    for t in TYPES {
        assert!(shader.contains(t.wgsl), "{t:?}");
        for (k, &kind) in t.kinds().iter().enumerate() {
            let lin = Linear::new(&scene_of(Operator::joined(kind, Join::from_size(t, 0.25)))).unwrap();
            let data = lin.field_data();
            let root = data.nodes[lin.root() as usize][0];
            assert_eq!((root >> NODE_TYPE_SHIFT) & NODE_TYPE_MASK, t.code + k as u32, "{t:?} {kind:?}");
            let name = t.scene_names[k].to_uppercase();
            assert!(shader.contains(&format!("const NODE_{name}: u32 = {}u;", t.code + k as u32)), "{name}");
        }
    }
}

#[test]
fn a_bad_size_is_refused_naming_its_field() {
    for t in TYPES {
        let json = format!(
            r#"{{"isotrace_scene": 1, "root": 2, "nodes": [{{"type": "sphere", "radius": 1}}, {{"type": "sphere", "radius": 1}}, {{"type": "{}", "left": 0, "right": 1, "{}": -1}}]}}"#,
            t.scene_names[0], t.field
        );
        let err = format::parse(&json).unwrap_err().to_string();
        assert!(err.contains(t.field) && err.contains("must be > 0"), "{t:?}: {err}");
    }
}

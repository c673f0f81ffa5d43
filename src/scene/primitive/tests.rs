//! Transforms and parameter checks of primitives.
use super::*;

#[test]
fn matrix_maps_world_to_local() {
    let t = Transform { translate: [1.0, -2.0, 0.5], rotate: Some(Rotation { axis: [1.0, 2.0, 3.0], angle: 0.7 }), scale: 1.5 };
    let m = t.matrix();
    for p in [DVec3::new(0.3, 0.2, -1.0), DVec3::new(4.0, 1.0, 2.0)] {
        let q = t.to_local(p);
        for r in 0..3 {
            let v = m[r][0] * p.x + m[r][1] * p.y + m[r][2] * p.z + m[r][3];
            assert!((v - q[r]).abs() < 1e-12, "row {r}: {v} vs {}", q[r]);
        }
        assert!((t.to_world(q) - p).length() < 1e-12);
    }
}

#[test]
fn parameters_are_checked_with_field_names() {
    assert_eq!(Shape::Sphere { radius: 0.0 }.check(), Err(("radius".into(), "must be > 0".into())));
    assert_eq!(Shape::Box { half: [1.0, -1.0, 1.0] }.check(), Err(("half[1]".into(), "must be > 0".into())));
    assert_eq!(Shape::Plane { normal: [0.0; 3], offset: 1.0 }.check(), Err(("normal".into(), "must not be zero".into())));
    let p = Primitive::new(Shape::Sphere { radius: 1.0 }).scaled(0.0);
    assert_eq!(p.check(), Err(("scale".into(), "must be > 0".into())));
}

#[test]
fn every_primitive_type_has_a_shape_of_its_own() {
    for &t in &crate::sdf::primitive::TYPES {
        let v: Vec<f64> = (0..t.param_count()).map(|k| 0.25 + k as f64).collect();
        let shape = Shape::from_analytic(t, &v);
        let (back, w) = shape.analytic().expect("given by numbers");
        assert_eq!((back, &*w), (t, &v[..]), "{t:?}");
        assert_eq!(shape.kind(), ShapeKind::Analytic(t));
        assert_eq!(ShapeKind::parse(t.scene_name), Some(ShapeKind::Analytic(t)));
    }
}

use super::*;
use crate::sdf::Form;

#[test]
fn types_are_in_type_code_order_with_distinct_names_forms_and_features() {
    for w in TYPES.windows(2) {
        assert!(w[0].code < w[1].code, "{:?} before {:?}", w[0], w[1]);
    }
    for (i, a) in TYPES.iter().enumerate() {
        assert!(a.param_count() <= MAX_PARAMS, "{a:?}");
        assert!(a.fields.iter().all(|f| f.default.is_none() || f.len == 1), "{a:?}: only numbers have defaults");
        assert_eq!(a.info.form, Form::Primitive(a));
        for b in &TYPES[i + 1..] {
            assert!(a.info.name != b.info.name && a.scene_name != b.scene_name);
            if let (Some(x), Some(y)) = (a.wgsl, b.wgsl) {
                assert!(x.form != y.form && x.feature & y.feature == 0, "{a:?} and {b:?} share a form or a feature bit");
            }
        }
        if let Some(c) = a.wgsl {
            assert!(c.form < 16 && c.form > FORM_PLANE && c.feature.count_ones() == 1, "{a:?}");
        }
    }
}

#[test]
fn defaults_complete_the_trailing_parameters() {
    assert_eq!(&*CONE.with_defaults(&[1.0, 2.0]), &[1.0, 2.0, 0.0]);
    assert_eq!(&*CONE.with_defaults(&[1.0, 2.0, 0.5]), &[1.0, 2.0, 0.5]);
    let d = DENSITY.with_defaults(&[1.0, 0.0, 0.5]);
    assert_eq!(&*d, &[1.0, 0.0, 0.5, crate::sdf::density_default_range(1.0, 0.5)]);
    assert_eq!(ROUND_BOX.param_names(), ["half[0]", "half[1]", "half[2]", "radius"]);
}

/// The cone's field against a brute-force distance to its surface in the
/// (ρ, z) half-plane, sampled densely, with the sign of the trapezoid.
#[test]
fn the_cone_is_the_distance_to_its_surface() {
    let brute = |r: f64, h: f64, rt: f64, rho: f64, z: f64| {
        let pieces = [((0.0, -h), (r, -h)), ((r, -h), (rt, h)), ((rt, h), (0.0, h))];
        let mut d = f64::INFINITY;
        for ((ax, az), (bx, bz)) in pieces {
            for k in 0..=4000 {
                let t = k as f64 / 4000.0;
                d = d.min(hypot(rho - (ax + (bx - ax) * t), z - (az + (bz - az) * t)));
            }
        }
        let inside = z.abs() <= h && rho <= r + (rt - r) * (z + h) / (2.0 * h);
        if inside { -d } else { d }
    };
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for (r, h, rt) in [(1.0, 0.5, 0.0), (0.6, 1.0, 0.3), (0.3, 0.4, 0.9), (0.5, 0.5, 0.5)] {
        for _ in 0..300 {
            let q = DVec3::new(3.0 * next() - 1.5, 3.0 * next() - 1.5, 3.0 * next() - 1.5);
            let got = (CONE.distance)(&[r, h, rt], q);
            let want = brute(r, h, rt, hypot(q.x, q.y), q.z);
            assert!((got - want).abs() < 2e-3, "cone({r}, {h}, {rt}) at {q}: {got} vs {want}");
        }
    }
}

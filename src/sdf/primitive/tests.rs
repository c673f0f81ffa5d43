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
    let d = DENSITY.with_defaults(&[1.0, 0.0, 0.5]);
    assert_eq!(&*d, &[1.0, 0.0, 0.5, crate::sdf::density_default_range(1.0, 0.5)]);
    assert_eq!(ROUND_BOX.param_names(), ["half[0]", "half[1]", "half[2]", "radius"]);
}

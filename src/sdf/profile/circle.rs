//! `circle(r)`: |u| − r, exact.

use super::{plane_point, positive, Field, FieldKind, ProfileType, SegmentBox};
use crate::sdf::{Arity, Form, Info};

/// The circle.
pub static CIRCLE: ProfileType = ProfileType {
    info: Info { name: "circle", form: Form::Profile(&CIRCLE), arity: Arity::Exactly(1), signature: "circle(r)", doc: "2D profile: sqrt(x^2 + y^2) - r, r > 0 (independent of z: a prism along z); exact, L = 1" },
    scene_name: "circle",
    fields: &[Field { name: "radius", kind: FieldKind::Number }],
    check: |v| positive("radius", v[0]),
    distance: |v, u| u.length() - v[0],
    bounds: |v| ([-v[0]; 2], [v[0]; 2]),
    // A box of no extent rounded by the radius.
    row: |v| SegmentBox { r: v[0], ..SegmentBox::default() },
    expand: |b, v| {
        b.positive(v, 0, "the radius r")?;
        let u = plane_point(b)?;
        let l = b.length(&u)?;
        b.sub(l, v[0])
    },
};

//! `rect(hx, hy)`: the centred rectangle of half extents h, exact.

use super::{box2, plane_point, positive, Field, FieldKind, ProfileType, SegmentBox};
use crate::sdf::{Arity, Form, Info};
use glam::DVec2;

/// The rectangle.
pub static RECT: ProfileType = ProfileType {
    info: Info { name: "rect", form: Form::Profile(&RECT), arity: Arity::Exactly(2), signature: "rect(hx, hy)", doc: "2D profile: length(max(d, 0)) + min(max(d.x, d.y), 0), d = (|x| - hx, |y| - hy); exact, L = 1" },
    scene_name: "rect",
    fields: &[Field { name: "half", kind: FieldKind::Pair { mirrored: false } }],
    check: |v| positive("half[0]", v[0]).and(positive("half[1]", v[1])),
    distance: |v, u| box2(u, DVec2::new(v[0], v[1])),
    bounds: |v| ([-v[0], -v[1]], [v[0], v[1]]),
    row: |v| SegmentBox { e: [v[0], v[1]], ..SegmentBox::default() },
    // The 2D case of `box`'s expansion.
    expand: |b, v| {
        let u = plane_point(b)?;
        b.boxd(&u, &v[..2])
    },
};

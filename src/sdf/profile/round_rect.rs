//! `roundrect(hx, hy, r)`: the rectangle of half extents h with its
//! corners rounded by r, 0 ≤ r ≤ min(h), exact.

use super::{box2, plane_point, positive, Field, FieldKind, ProfileType, SegmentBox};
use crate::sdf::primitive::Invalid;
use crate::sdf::{Arity, Form, Info};
use glam::DVec2;

/// The rounded rectangle.
pub static ROUND_RECT: ProfileType = ProfileType {
    info: Info { name: "roundrect", form: Form::Profile(&ROUND_RECT), arity: Arity::Exactly(3), signature: "roundrect(hx, hy, r)", doc: "2D profile: rect(hx - r, hy - r) - r: same extents, corners rounded by r; exact, L = 1" },
    scene_name: "round_rect",
    fields: &[Field { name: "half", kind: FieldKind::Pair { mirrored: false } }, Field { name: "radius", kind: FieldKind::Number }],
    check,
    distance: |v, u| box2(u, DVec2::new(v[0], v[1]) - DVec2::splat(v[2])) - v[2],
    bounds: |v| ([-v[0], -v[1]], [v[0], v[1]]),
    row: |v| SegmentBox { e: [v[0] - v[2], v[1] - v[2]], r: v[2], ..SegmentBox::default() },
    expand: |b, v| {
        let u = plane_point(b)?;
        let inner = [b.sub(v[0], v[2])?, b.sub(v[1], v[2])?];
        let d = b.boxd(&u, &inner)?;
        b.sub(d, v[2])
    },
};

fn check(v: &[f64]) -> Result<(), Invalid> {
    positive("half[0]", v[0])?;
    positive("half[1]", v[1])?;
    let smallest = v[0].min(v[1]);
    if !(v[2] >= 0.0 && v[2] <= smallest) {
        return Err(("radius".into(), format!("must be >= 0 and <= the smallest half extent ({smallest})")));
    }
    Ok(())
}

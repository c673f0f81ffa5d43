//! `capsule2d(ax, ay, bx, by, r)`: the segment a–b thickened by r > 0,
//! exact (a circle around a when a = b).

use super::{plane_point, positive, segment, Field, FieldKind, ProfileType, SegmentBox};
use crate::sdf::{Arity, Form, Info};
use glam::DVec2;

/// The 2D capsule.
pub static CAPSULE: ProfileType = ProfileType {
    info: Info { name: "capsule2d", form: Form::Profile(&CAPSULE), arity: Arity::Exactly(5), signature: "capsule2d(ax, ay, bx, by, r)", doc: "2D profile: distance from (x, y) to the segment a-b, minus r; exact, L = 1" },
    scene_name: "capsule",
    fields: &[
        Field { name: "a", kind: FieldKind::Pair { mirrored: true } },
        Field { name: "b", kind: FieldKind::Pair { mirrored: true } },
        Field { name: "radius", kind: FieldKind::Number },
    ],
    check: |v| positive("radius", v[4]),
    distance: |v, u| segment(u, DVec2::new(v[0], v[1]), DVec2::new(v[2], v[3])) - v[4],
    bounds: |v| ([v[0].min(v[2]) - v[4], v[1].min(v[3]) - v[4]], [v[0].max(v[2]) + v[4], v[1].max(v[3]) + v[4]]),
    row: |v| SegmentBox { r: v[4], a: [v[0], v[1]], b: [v[2], v[3]], ..SegmentBox::default() },
    // The 2D case of `capsule`'s expansion, with its a = b guards.
    expand: |b, v| {
        let u = plane_point(b)?;
        let pa = [b.sub(u[0], v[0])?, b.sub(u[1], v[1])?];
        let ba = [b.sub(v[2], v[0])?, b.sub(v[3], v[1])?];
        let w = b.segment_offset(&pa, &ba)?;
        let l = b.length(&w)?;
        b.sub(l, v[4])
    },
};

//! Where a lowered formula's shapes sit: similarity transforms, and, under
//! `mirror`, reflections. A scene primitive keeps one rotation, so a
//! reflection is folded into it as a rotation times the reflection of the
//! primitive's own x axis, and the shape is mirrored in its local frame
//! ([`super::Shape::mirror_x`]): every shape but a voxel grid has a mirrored
//! twin of the same type.

use super::{Primitive, Rotation, Transform};
use glam::{DMat3, DQuat, DVec3};

/// A placement: a similarity transform, or one with a reflection.
#[derive(Debug, Clone)]
pub enum Placement {
    /// t + R s q.
    Plain(Transform),
    /// t + L s q with L orthogonal (det ±1).
    General {
        /// Translation.
        t: DVec3,
        /// Rotation, maybe times a reflection.
        l: DMat3,
        /// Uniform scale.
        s: f64,
    },
}

fn rotation_matrix(r: &Option<Rotation>) -> DMat3 {
    match r {
        Some(r) => DMat3::from_axis_angle(DVec3::from(r.axis).normalize(), r.angle),
        None => DMat3::IDENTITY,
    }
}

fn rotation_of(m: DMat3) -> Option<Rotation> {
    if m == DMat3::IDENTITY {
        return None;
    }
    let (axis, angle) = DQuat::from_mat3(&m).normalize().to_axis_angle();
    Some(Rotation { axis: axis.into(), angle })
}

impl Placement {
    /// No motion.
    pub fn identity() -> Placement {
        Placement::Plain(Transform::default())
    }

    /// The uniform scale (it multiplies field values).
    pub fn scale(&self) -> f64 {
        match self {
            Placement::Plain(t) => t.scale,
            Placement::General { s, .. } => *s,
        }
    }

    /// Whether it moves nothing.
    pub fn is_identity(&self) -> bool {
        matches!(self, Placement::Plain(t) if *t == Transform::default())
    }

    /// This placement after `inner`: p ↦ self(inner(p)).
    pub fn then(&self, inner: &Transform, compose: impl Fn(&Transform, &Transform) -> Transform) -> Placement {
        match self {
            Placement::Plain(t) => Placement::Plain(compose(t, inner)),
            Placement::General { t, l, s } => Placement::General {
                t: *t + *l * DVec3::from(inner.translate) * *s,
                l: *l * rotation_matrix(&inner.rotate),
                s: s * inner.scale,
            },
        }
    }

    /// This placement after the reflection across the plane through the origin
    /// with normal `n` (not zero).
    pub fn reflected(&self, n: DVec3) -> Placement {
        let n = n.normalize();
        let h = DMat3::IDENTITY - 2.0 * DMat3::from_cols(n * n.x, n * n.y, n * n.z);
        match self {
            Placement::Plain(tf) => Placement::General { t: DVec3::from(tf.translate), l: rotation_matrix(&tf.rotate) * h, s: tf.scale },
            Placement::General { t, l, s } => Placement::General { t: *t, l: *l * h, s: *s },
        }
    }

    /// Primitive `p` placed by this placement; `None` for a reflected shape that
    /// has no mirrored twin (a voxel grid, a warped primitive).
    pub fn place(&self, p: &Primitive, compose: impl Fn(&Transform, &Transform) -> Transform) -> Option<Primitive> {
        let (t, l, s) = match self {
            // A warped primitive's frame moves; its own transform is in it.
            Placement::Plain(tf) => {
                return Some(match &p.warp {
                    None => Primitive { shape: p.shape.clone(), transform: compose(tf, &p.transform), warp: None },
                    Some(w) => Primitive { warp: Some(super::warp::Warp { frame: compose(tf, &w.frame), clamp: None, ..*w }), ..p.clone() },
                });
            }
            // A reflected warp is another warp (the twist's sense flips).
            Placement::General { .. } if p.warp.is_some() => return None,
            Placement::General { t, l, s } => (*t, *l, *s),
        };
        let translate = (t + l * DVec3::from(p.transform.translate) * s).into();
        let m = l * rotation_matrix(&p.transform.rotate);
        let (shape, m) = if m.determinant() > 0.0 {
            (p.shape.clone(), m)
        } else {
            // m = (m·D)·D with D the reflection of local x: a rotation, then
            // the shape mirrored in its own frame.
            (p.shape.mirror_x()?, m * DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0)))
        };
        Some(Primitive { shape, transform: Transform { translate, rotate: rotation_of(m), scale: s * p.transform.scale }, warp: None })
    }
}

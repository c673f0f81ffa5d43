//! `density(R, h, c[, T])`: the normalized density of a segment along the
//! local z axis ([`crate::sdf::density`]): the kernel (1 − (d/R)²)³ of the
//! distance d to the segment (0, 0, ±h), at isovalue c, in length units
//! T·(1 − K/c) + max(d − R, 0). Summed with others of the same T by
//! `sum_union`. Its bound is max(1, T·1.7173/(c·R)), 1 at the default T,
//! and {f ≤ r} lies within R + max(r − T, 0) of the segment.

use super::{hypot, positive, Bound, Field, Lipschitz, PrimitiveType, Rows, WgslCase};
use crate::ir::{Func3, Op};
use crate::sdf::{density, density_default_range, density_lipschitz, Arity, Form, Info, Sink};

/// The row 1 form of a density primitive.
pub const FORM_DENSITY: u32 = 7;
/// The interpreter feature of scenes with density primitives.
pub const FEATURE_DENSITY: u32 = 256;

/// The normalized density.
pub static DENSITY: PrimitiveType = PrimitiveType {
    info: Info {
        name: "density",
        form: Form::Primitive(&DENSITY),
        arity: Arity::Between(3, 4),
        signature: "density(R, h, c[, T])",
        doc: "T (1 - K/c) + max(d - R, 0), K = max(1 - (d/R)^2, 0)^3, d the distance to the segment (0, 0, -h)-(0, 0, h); R > 0, h >= 0, 0 < c < 1, T > 0 (default c R/1.7173, needs R and c constant); L = max(1, T 1.7173/(c R)), 1 at the default T",
    },
    scene_name: "density",
    code: 12,
    // h 0, c ½ and the T that makes the primitive 1-Lipschitz by default.
    fields: &[
        Field::number("radius"),
        Field::number("half_length").or(0.0),
        Field::number("iso").or(0.5),
        Field::number("range").or_else(|v| density_default_range(v[0], v[2])),
    ],
    check: |v| {
        positive("radius", v[0])?;
        positive("range", v[3])?;
        if !(v[1] >= 0.0) {
            return Err(("half_length".into(), "must be >= 0".into()));
        }
        if !(v[2] > 0.0 && v[2] < 1.0) {
            return Err(("iso".into(), "must be between 0 and 1 (exclusive): the kernel's values".into()));
        }
        Ok(())
    },
    distance: |v, q| density(hypot(hypot(q.x, q.y), q.z - q.z.clamp(-v[1], v[1])), v[0], v[2], v[3]),
    lipschitz: Lipschitz::Of { bound: |v| density_lipschitz(v[0], v[2], v[3]), field: "range" },
    bound: |v| Bound::Capsule { a: [0.0, 0.0, -v[1]], b: [0.0, 0.0, v[1]], radius: v[0], allowance: v[3] },
    // (R, h, T, c).
    rows: |v, _| Rows { form: FORM_DENSITY, row: [v[0], v[1], v[3], v[2]] },
    wgsl: Some(WgslCase {
        form: FORM_DENSITY,
        feature: FEATURE_DENSITY,
        code: "        // r2 = (R, h, T, c) (src/sdf/blend.rs, density).
        let dd = length(vec3<f32>(q.xy, q.z - clamp(q.z, -r2.y, r2.y)));
        let t = dd / r2.x;
        let k = max(1.0 - t * t, 0.0);
        d = select(d, r2.z * (1.0 - k * k * k / r2.w) + max(dd - r2.x, 0.0), form == FORM_DENSITY);
",
        // The value is nondecreasing in the distance dd to the segment: it
        // runs between its values at the box's nearest and farthest dd.
        enclosure: Some("        let ql = scene_local_box(r0, r1, b);
        let lo = scene_lo(ql);
        let hi = scene_hi(ql);
        let dz = vec2<f32>(lo.z - clamp(lo.z, -r2.y, r2.y), hi.z - clamp(hi.z, -r2.y, r2.y));
        let dd2 = ia_sqr(vec2<f32>(lo.x, hi.x)) + ia_sqr(vec2<f32>(lo.y, hi.y)) + ia_sqr(dz);
        let dd = sqrt(max(dd2, vec2<f32>(0.0))) * vec2<f32>(1.0 - 1e-6, 1.0 + 1e-6);
        let tt = dd / r2.x;
        let kk = max(1.0 - tt * tt, vec2<f32>(0.0));
        let dv = r2.z * (1.0 - kk * kk * kk / r2.w) + max(dd - r2.x, vec2<f32>(0.0));
        e = select(e, ia_pad(dv, 1e-6 * r2.z, 1e-6) / dot(r0, r0), form == FORM_DENSITY);
"),
    }),
    expand,
};

/// The expansion in [`density`]'s order of operations, the distance to
/// the segment √(x² + y² + (z − clamp(z, −h, h))²) (for a constant h = 0
/// the plain |p|, the same number). Without T, R and c must be constants
/// for the default [`density_default_range`].
fn expand(b: &mut super::Ir<'_, '_>, v: &[crate::ir::NodeId]) -> Result<crate::ir::NodeId, super::Stopped> {
    // Checked before anything divides by R or c.
    b.positive(v, 0, "the support radius R")?;
    b.non_negative(v, 1, "the half length h")?;
    if let Some(c) = b.0.konst(v[2]) {
        if !(c > 0.0 && c < 1.0) {
            return Err(b.0.bad_argument(2, format!("the isovalue c must be between 0 and 1 (exclusive), got {c}")));
        }
    }
    let (radius, iso) = (v[0], v[2]);
    let range = match v.get(3) {
        Some(&t) => {
            b.positive(v, 3, "the range T")?;
            t
        }
        None => match (b.0.konst(radius), b.0.konst(iso)) {
            (Some(r), Some(c)) => b.c(density_default_range(r, c))?,
            // There is no argument 3: the error points at the call.
            _ => return Err(b.0.bad_argument(3, "the range T is needed when R or c is not a constant (the default c·R/1.7173 needs both)".into())),
        },
    };
    let [x, y, z] = b.xyz()?;
    let d = if b.is(v[1], 0.0) {
        b.length(&[x, y, z])?
    } else {
        let lo = b.neg(v[1])?;
        let near = b.0.push(Op::Call3(Func3::Clamp, z, lo, v[1]))?;
        let w = b.sub(z, near)?;
        b.length(&[x, y, w])?
    };
    // t = d/R; k = max(1 − t·t, 0); T·(1 − k·k·k/c) + max(d − R, 0)
    let t = b.div(d, radius)?;
    let one = b.c(1.0)?;
    let tt = b.sqr(t)?;
    let k = b.sub(one, tt)?;
    let zero = b.c(0.0)?;
    let k = b.max(k, zero)?;
    let k3 = b.0.push(Op::PowI(k, 3))?;
    let kc = b.div(k3, iso)?;
    let inside = b.sub(one, kc)?;
    let inside = b.mul(range, inside)?;
    let beyond = b.sub(d, radius)?;
    let beyond = b.max(beyond, zero)?;
    b.add(inside, beyond)
}

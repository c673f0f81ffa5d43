//! The join operators: compact edge blends other than Zanni's G (chamfer,
//! round fillet, sum), each described once, in a file of its own, by a
//! [`JoinType`]: its formula forms (names, expansion into IR operations),
//! its f64 reference, its size parameter as a scene file names it, its
//! operator range, its Lipschitz bound, its type codes and its case of the
//! scene interpreter (WGSL).
//!
//! Each equals the sharp operator outside its operator range r_o (Zanni's
//! compactness: both operands below r_o for a union, above −r_o for an
//! intersection), so ranges of interest and bounding volumes treat it like
//! G with that r_o. A difference a \ b is the intersection of a and −b.
//!
//! The formula language ([`super::lower`]) and blobtree scenes
//! (`crate::scene`: file format, validation, codes, Lipschitz bounds,
//! formula text, lowering, the interpreter's cases) read [`TYPES`] instead
//! of matching on joins. Adding one is a file here, its line in [`TYPES`],
//! and its variant of `scene::Join` (the scene model's data, with its two
//! conversions to and from its size).
//!
//! The formula forms expand to the f64 functions in their order of
//! operations, so a compiled formula and a scene agree to rounding.

use super::primitive::{Ir, Stopped};
use super::Info;
use crate::ir::NodeId;

mod chamfer;
mod round;
mod sum;

pub use chamfer::CHAMFER;
pub use round::ROUND;
pub use sum::SUM;
// The joins' functions, for the tests that check them one by one.
#[cfg(test)]
pub use {chamfer::{chamfer_intersect, chamfer_range, chamfer_union}, round::{round_intersect, round_union}, sum::sum_union};

/// Every join, in type-code order.
pub static TYPES: [&JoinType; 3] = [&CHAMFER, &ROUND, &SUM];

/// Union, intersection or difference (left minus right): the operation of
/// a binary operator, sharp, smooth or joined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum OpKind {
    /// min (sharp), G∪ or a join's union.
    Union,
    /// max (sharp), G∩ or a join's intersection.
    Intersection,
    /// max(a, −b) (sharp), G\ or a join's intersection with −b.
    Difference,
}

/// One join (module doc). Joins are compared by type code.
pub struct JoinType {
    /// The `type` of a scene file node per operation, in [`OpKind`] order
    /// (`chamfer_union`, `chamfer_intersection`, `chamfer_difference`); a
    /// join of unions only has one.
    pub scene_names: &'static [&'static str],
    /// Its formula forms, in [`OpKind`] order (`chamfer_union`,
    /// `chamfer_intersect`, `chamfer_subtract`), as many as `scene_names`.
    pub forms: &'static [Info],
    /// The type code of its union in the GPU layout (`scene::codes`); its
    /// intersection and difference have the next two.
    pub code: u32,
    /// The scene file's name of its size parameter (> 0).
    pub field: &'static str,
    /// The operator range r_o for its size: beyond it, the sharp operator.
    pub range: fn(f64) -> f64,
    /// The union of a and b for size s.
    pub union: fn(f64, f64, f64) -> f64,
    /// The intersection of a and b for size s; `None` for a join of unions
    /// only.
    pub intersect: Option<fn(f64, f64, f64) -> f64>,
    /// The bound of its value from its operands' bounds.
    pub lipschitz: fn(f64, f64) -> f64,
    /// Its case of the scene interpreter (`scene_join` in
    /// templates/fields/scene.wgsl): statements, indented by 4, that set
    /// `j` to the union of `x` and `y` for size `s` where `ty` is one of
    /// its codes (`NODE_<NAME>` for each scene name in capitals); an
    /// intersection is the negated union of the negated operands.
    pub wgsl: &'static str,
    /// The formula form's expansion of the lowered arguments (a, b, size)
    /// for operation `kind`.
    pub(in crate::sdf) expand: fn(&mut Ir<'_, '_>, OpKind, &[NodeId]) -> Result<NodeId, Stopped>,
}

impl JoinType {
    /// The operations it has: all three, or the union alone.
    pub fn kinds(&self) -> &'static [OpKind] {
        &[OpKind::Union, OpKind::Intersection, OpKind::Difference][..self.scene_names.len()]
    }

    /// Its value for operation `kind` on a and b (a difference: the
    /// intersection with −b) for size s.
    pub fn apply(&self, kind: OpKind, a: f64, b: f64, s: f64) -> f64 {
        let c = if kind == OpKind::Difference { -b } else { b };
        match (kind, self.intersect) {
            (OpKind::Union, _) | (_, None) => (self.union)(a, c, s),
            (_, Some(f)) => f(a, c, s),
        }
    }
}

impl PartialEq for JoinType {
    fn eq(&self, o: &JoinType) -> bool {
        self.code == o.code
    }
}

impl Eq for JoinType {}

impl std::hash::Hash for JoinType {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.code.hash(h)
    }
}

impl std::fmt::Debug for JoinType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.scene_names[0])
    }
}

/// (a, b), or (a, −b) for a difference: a minus b is a ∩ not-b (the
/// operator styles' expansions share it).
pub(in crate::sdf) fn operands(b: &mut Ir<'_, '_>, kind: OpKind, v: &[NodeId]) -> Result<(NodeId, NodeId), Stopped> {
    Ok((v[0], if kind == OpKind::Difference { b.neg(v[1])? } else { v[1] }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joins_have_their_own_codes_names_and_forms() {
        for (k, t) in TYPES.iter().enumerate() {
            assert_eq!(t.code, 38 + 3 * k as u32, "{t:?}");
            assert_eq!(t.forms.len(), t.scene_names.len(), "{t:?}");
            for (kind, info) in t.kinds().iter().zip(t.forms) {
                assert!(matches!(info.form, super::super::Form::Join(j, k) if j == *t && k == *kind), "{t:?}");
            }
            assert!(t.intersect.is_some() == (t.kinds().len() == 3), "{t:?}");
        }
    }

    #[test]
    fn blends_are_sharp_outside_their_ranges() {
        let r = 0.3;
        for t in TYPES {
            let ro = (t.range)(r);
            for i in 0..200 {
                for j in 0..200 {
                    let (a, b) = (-2.0 + i as f64 * 0.02, -2.0 + j as f64 * 0.02);
                    if a.max(b) >= ro {
                        assert_eq!((t.union)(a, b, r), a.min(b), "{t:?} {a} {b}");
                    }
                    if let Some(f) = t.intersect.filter(|_| a.min(b) <= -ro) {
                        assert_eq!(f(a, b, r), a.max(b), "{t:?} {a} {b}");
                    }
                }
            }
        }
    }
}

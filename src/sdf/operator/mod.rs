//! The CSG operator styles: sharp (min, max), smooth (Zanni et al. eq.
//! 8-11) and compact smooth (Zanni's G, eq. 12, 17, 18), each described
//! once, in a file of its own, by an [`OperatorStyle`]: its formula forms
//! (names, expansion into IR operations) for union, intersection and
//! difference, its f64 reference, its parameters as a scene file names them
//! with their checks, its blend and operator ranges, the factor by which it
//! can raise a Lipschitz bound, and its scene nodes (type names and codes),
//! or the style a scene keeps it as.
//!
//! The scene interpreter runs every style by one branch-free formula
//! (`scene_operator` in templates/fields/scene.wgsl) from the record
//! (β, r_o) a style gives ([`OperatorStyle::row`]): sharp CSG where β = 0
//! or an operand is beyond r_o, G elsewhere.
//!
//! The formula language ([`super::lower`]) and blobtree scenes
//! (`crate::scene`: file format, validation, codes, rows, Lipschitz bounds,
//! formula text, lowering) read [`STYLES`] instead of matching on styles.
//! Adding one is a file here and its line in [`STYLES`]; a style with scene
//! nodes of its own also needs its model in `scene::Operator` (its two
//! conversions `Operator::typed` and `Operator::styled`) and, unless the
//! interpreter's formula computes it from (β, r_o), a case of
//! `scene_operator`. The edge blends
//! other than G (chamfer, round, sum) are joins ([`super::join`]).

use super::primitive::{Field, Invalid, Ir, Params, Stopped};
use super::Info;
use crate::ir::NodeId;
use super::join::operands;

mod compact;
mod sharp;
mod smooth;

pub use super::join::OpKind;
pub use compact::{COMPACT, DEFAULT_RANGE_FACTOR};
pub use sharp::SHARP;
pub use smooth::{g, SMOOTH};
// G's f64 reference, for the tests that check it against a scene's.
#[cfg(test)]
pub use compact::compact;

/// The operations, in [`OpKind`] order: the order of every per-operation
/// list of a style or a join.
pub const KINDS: [OpKind; 3] = [OpKind::Union, OpKind::Intersection, OpKind::Difference];

/// Every style, in formula documentation order (a scene's type codes are
/// those of the styles with nodes of their own, sharp first).
pub static STYLES: [&OperatorStyle; 3] = [&SHARP, &SMOOTH, &COMPACT];

/// One operator style (module doc). Styles are compared by the name of
/// their union form.
pub struct OperatorStyle {
    /// Its formula forms, in [`OpKind`] order (`smooth_union`,
    /// `smooth_intersect`, `smooth_subtract`).
    pub forms: [Info; 3],
    /// Its parameters after the two operands, in the formula's argument
    /// order, as a scene file names them (`beta`, `r_o`), with the defaults
    /// of those a formula may leave out. A style without parameters (sharp
    /// CSG) takes any number of operands, folded left to right.
    pub params: &'static [Field],
    /// Its nodes in a scene.
    pub scene: InScene,
    /// Checks finite parameters (of a scene file); the error names the
    /// field.
    pub check: fn(&[f64]) -> Result<(), Invalid>,
    /// The f64 reference: the value of operation `kind` on a and b (a
    /// difference: a minus b) for parameters `v`.
    pub apply: fn(kind: OpKind, a: f64, b: f64, v: &[f64]) -> f64,
    /// The blend range β: how far its value may move from the sharp
    /// operator's (0 for sharp CSG).
    pub blend: fn(&[f64]) -> f64,
    /// The operator range r_o: beyond it, the sharp operator (0 for sharp
    /// CSG, whose range of interest is {0}).
    pub range: fn(&[f64]) -> f64,
    /// The factor by which it can raise its operands' Lipschitz bound.
    pub lipschitz: fn(&[f64]) -> f64,
    /// The formula form's expansion of the lowered arguments (operands,
    /// then parameters) for operation `kind`.
    pub(in crate::sdf) expand: fn(&mut Ir<'_, '_>, OpKind, &[NodeId]) -> Result<NodeId, Stopped>,
}

/// How a scene holds a style.
#[derive(Debug, Clone, Copy)]
pub enum InScene {
    /// As nodes of its own.
    Nodes {
        /// The `type` of a scene file node per operation, in [`OpKind`]
        /// order (`smooth_union`, `smooth_intersection`, `smooth_difference`).
        names: [&'static str; 3],
        /// The type code of its union in the GPU layout (`scene::codes`);
        /// its intersection and difference have the next two.
        code: u32,
    },
    /// As the nodes of another style with the same zero set, whose
    /// parameters `params` gives from this one's.
    As {
        /// The style a scene keeps it as.
        style: &'static OperatorStyle,
        /// That style's parameters.
        params: fn(&[f64]) -> Params,
    },
}

impl OperatorStyle {
    /// The number of operands of a call with `args` arguments: all of them
    /// for a style without parameters, else two.
    pub fn operand_count(&self, args: usize) -> usize {
        if self.params.is_empty() { args } else { 2 }
    }

    /// `given` (the leading parameters, as a formula may leave trailing
    /// ones out) completed with the defaults of the parameters after them.
    pub fn with_defaults(&self, given: &[f64]) -> Params {
        let mut v = given.to_vec();
        for f in &self.params[given.len().min(self.params.len())..] {
            let Some(d) = f.default else { break };
            v.push(d.value(&v));
        }
        Params::new(&v)
    }

    /// The style a scene keeps this one as (itself, when it has nodes of
    /// its own) and that style's parameters for this one's `v`.
    pub fn in_scene(&'static self, v: &[f64]) -> (&'static OperatorStyle, Params) {
        match self.scene {
            InScene::Nodes { .. } => (self, Params::new(v)),
            InScene::As { style, params } => (style, params(v)),
        }
    }

    /// Its scene file names, if it has nodes of its own.
    pub const fn scene_names(&self) -> Option<[&'static str; 3]> {
        match self.scene {
            InScene::Nodes { names, .. } => Some(names),
            InScene::As { .. } => None,
        }
    }

    /// The type code of its union (its intersection and difference have
    /// the next two), if it has nodes of its own.
    pub const fn first_code(&self) -> Option<u32> {
        match self.scene {
            InScene::Nodes { code, .. } => Some(code),
            InScene::As { .. } => None,
        }
    }

    /// Its record of the scene interpreter's operator formula for
    /// parameters `v`: (β, r_o).
    pub fn row(&self, v: &[f64]) -> [f64; 2] {
        [(self.blend)(v), (self.range)(v)]
    }
}

impl PartialEq for OperatorStyle {
    fn eq(&self, o: &OperatorStyle) -> bool {
        self.forms[0].name == o.forms[0].name
    }
}

impl Eq for OperatorStyle {}

impl std::hash::Hash for OperatorStyle {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.forms[0].name.hash(h)
    }
}

impl std::fmt::Debug for OperatorStyle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.forms[0].name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sdf::{Arity, Form};

    #[test]
    fn styles_have_their_own_forms_and_codes_before_the_joins() {
        let mut next = 32;
        for s in STYLES {
            for (info, kind) in s.forms.iter().zip(KINDS) {
                assert!(matches!(info.form, Form::Operator(t, k) if t == s && k == kind), "{s:?}");
                let args = match info.arity {
                    Arity::AtLeast(n) => n..=n + 2,
                    Arity::Exactly(n) => n..=n,
                    Arity::Between(lo, hi) => lo..=hi,
                    Arity::Pairs(..) => unreachable!("{s:?}"),
                };
                assert!(args.clone().all(|n| s.operand_count(n) + s.params.len().min(n - 2) == n), "{s:?}");
                assert_eq!(s.params.iter().filter(|f| f.default.is_none()).count() + 2, *args.start(), "{s:?}");
            }
            match s.scene {
                InScene::Nodes { code, .. } => {
                    assert_eq!(code, next, "{s:?}");
                    next += 3;
                }
                InScene::As { style, .. } => assert!(style.scene_names().is_some(), "{s:?}"),
            }
        }
        assert!(crate::sdf::join::TYPES.iter().all(|t| t.code >= next));
    }
}

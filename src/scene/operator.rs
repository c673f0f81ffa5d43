//! Binary operators: the scene model's data of an operator node. What
//! each computes is its style's descriptor (`crate::sdf::operator`: sharp
//! CSG and Zanni's compact smooth operators G, eq. 8-18 of Zanni et al.
//! 2024) or its join's (`crate::sdf::join`); this module holds the model's
//! data, each with its two conversions to and from its descriptor and
//! parameters.
//!
//! A compact operator blends only while both operands lie in its range
//! R_o, and is plain CSG outside it, so a primitive can influence the field
//! only up to a value fixed by the tree (its range of interest, `roi.rs`).

pub use crate::sdf::join::OpKind;
use crate::sdf::join::{self as joins, JoinType};
use crate::sdf::operator::{self as styles, OperatorStyle, DEFAULT_RANGE_FACTOR, KINDS};
use crate::sdf::primitive::Params;

/// The blend of a compact smooth operator (`crate::sdf::operator::COMPACT`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blend {
    /// β > 0: the blend range.
    pub beta: f64,
    /// r_o ≥ 7β/6: the operator range (beyond it the operator is sharp).
    pub range: f64,
}

impl Blend {
    /// A blend with the default range 2β.
    pub fn new(beta: f64) -> Blend {
        Blend { beta, range: DEFAULT_RANGE_FACTOR * beta }
    }
}

/// A compact edge blend other than Zanni's G: each equals the sharp
/// operator outside its operator range, so ranges of interest and bounding
/// volumes treat it like G with that r_o. What each computes is its
/// descriptor's (`crate::sdf::join`, a file a join); this is the scene
/// model's data, a variant a join with its two conversions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Join {
    /// A 45° bevel of width `radius` (r_o = r/(2 − √2); Lipschitz ×√2).
    Chamfer {
        /// r > 0.
        radius: f64,
    },
    /// A circular fillet of radius `radius` (r_o = r; Lipschitz ×√2).
    Round {
        /// r > 0.
        radius: f64,
    },
    /// min(a, b) + min(max(a, b), T) − T: the summation blend of normalized
    /// density fields with this T (r_o = T; Lipschitz: the operands' sum).
    /// Unions only.
    Sum {
        /// T > 0.
        range: f64,
    },
}

impl Join {
    /// Its descriptor and size.
    pub fn typed(&self) -> (&'static JoinType, f64) {
        match *self {
            Join::Chamfer { radius } => (&joins::CHAMFER, radius),
            Join::Round { radius } => (&joins::ROUND, radius),
            Join::Sum { range } => (&joins::SUM, range),
        }
    }

    /// The join of type `t` with size `size`.
    pub fn from_size(t: &JoinType, size: f64) -> Join {
        match t.scene_names[0] {
            "chamfer_union" => Join::Chamfer { radius: size },
            "round_union" => Join::Round { radius: size },
            "sum_union" => Join::Sum { range: size },
            other => unreachable!("join {other} has no variant"),
        }
    }

    /// Its size parameter and that parameter's field name in a scene file.
    pub fn size(&self) -> (&'static str, f64) {
        let (t, size) = self.typed();
        (t.field, size)
    }

    /// The operator range r_o beyond which the blend is the sharp operator.
    pub fn range(&self) -> f64 {
        let (t, size) = self.typed();
        (t.range)(size)
    }

    /// Checks the size; the error names the field.
    pub fn check(&self) -> Result<(), (String, String)> {
        let (name, v) = self.size();
        if !v.is_finite() {
            return Err((name.into(), "must be finite".into()));
        }
        if !(v > 0.0) {
            return Err((name.into(), "must be > 0".into()));
        }
        Ok(())
    }
}

/// An operator node's operation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Operator {
    /// Which operation.
    pub kind: OpKind,
    /// `None`: sharp CSG (unless `join` is set).
    pub blend: Option<Blend>,
    /// A chamfer, round or sum blend instead (then `blend` is `None`).
    pub join: Option<Join>,
}

impl Operator {
    /// Sharp union (min).
    pub const UNION: Operator = Operator { kind: OpKind::Union, blend: None, join: None };
    /// Sharp intersection (max).
    pub const INTERSECTION: Operator = Operator { kind: OpKind::Intersection, blend: None, join: None };
    /// Sharp difference.
    pub const DIFFERENCE: Operator = Operator { kind: OpKind::Difference, blend: None, join: None };

    /// A compact smooth operator.
    pub fn smooth(kind: OpKind, blend: Blend) -> Operator {
        Operator { kind, blend: Some(blend), join: None }
    }

    /// A sharp operator.
    pub fn sharp(kind: OpKind) -> Operator {
        Operator { kind, blend: None, join: None }
    }

    /// A chamfer, round or sum blend (the caller keeps sums to unions).
    pub fn joined(kind: OpKind, join: Join) -> Operator {
        Operator { kind, blend: None, join: Some(join) }
    }

    /// The operator of style `style` for operation `kind` with the style's
    /// parameters `v` (defaults included), as the scene keeps that style
    /// ([`OperatorStyle::in_scene`]).
    pub fn styled(kind: OpKind, style: &'static OperatorStyle, v: &[f64]) -> Operator {
        let (style, v) = style.in_scene(v);
        match style.forms[0].name {
            "union" => Operator::sharp(kind),
            "compact_union" => Operator::smooth(kind, Blend { beta: v[0], range: v[1] }),
            other => unreachable!("style {other} has no variant"),
        }
    }

    /// Its descriptor with its parameters.
    pub fn typed(&self) -> Typed {
        match (self.blend, self.join) {
            (_, Some(j)) => {
                let (t, size) = j.typed();
                Typed::Join(t, size)
            }
            (None, None) => Typed::Style(&styles::SHARP, Params::new(&[])),
            (Some(b), None) => Typed::Style(&styles::COMPACT, Params::new(&[b.beta, b.range])),
        }
    }

    /// The operator of scene file type `name`, with its first parameter (β
    /// for the smooth ones, else the join's size) when it has one and the
    /// defaults of the others.
    pub fn parse(name: &str, size: f64) -> Option<Operator> {
        if let Some((style, kind)) = Self::style_named(name) {
            let given = if style.params.is_empty() { &[][..] } else { &[size][..] };
            return Some(Operator::styled(kind, style, &style.with_defaults(given)));
        }
        let (t, k) = joins::TYPES.iter().find_map(|t| Some((*t, t.scene_names.iter().position(|n| *n == name)?)))?;
        Some(Operator::joined(KINDS[k], Join::from_size(t, size)))
    }

    /// The style with scene nodes of type `name` and that node's operation.
    pub fn style_named(name: &str) -> Option<(&'static OperatorStyle, OpKind)> {
        styles::STYLES.iter().find_map(|s| Some((*s, KINDS[s.scene_names()?.iter().position(|n| *n == name)?])))
    }

    /// The `type` of a scene file node.
    pub fn name(&self) -> &'static str {
        match self.typed() {
            Typed::Style(s, _) => s.scene_names().expect("a style of the model has nodes")[self.kind as usize],
            Typed::Join(t, _) => t.scene_names[self.kind as usize],
        }
    }

    /// Every operator type name, in type-code order: the styles' with
    /// nodes of their own ([`crate::sdf::operator::STYLES`]), then the
    /// joins' ([`crate::sdf::join::TYPES`]).
    pub fn names() -> impl Iterator<Item = &'static str> {
        let styles = styles::STYLES.iter().filter_map(|s| s.scene_names()).flatten();
        styles.chain(joins::TYPES.iter().flat_map(|t| t.scene_names.iter().copied()))
    }

    /// Its parameters as a scene file names them, in order: a style's
    /// (`beta`, `r_o`), or a join's size.
    pub fn fields(&self) -> Vec<(&'static str, f64)> {
        match self.typed() {
            Typed::Style(s, v) => s.params.iter().map(|f| f.name).zip(v.iter().copied()).collect(),
            Typed::Join(t, size) => vec![(t.field, size)],
        }
    }

    /// Checks its parameters; the error names the field.
    pub fn check(&self) -> Result<(), (String, String)> {
        match self.typed() {
            Typed::Style(s, v) => (s.check)(&v),
            Typed::Join(t, size) => Join::from_size(t, size).check(),
        }
    }

    /// Whether swapping the operands leaves the value unchanged, bit for
    /// bit (min, max and |a − b| are symmetric), so the linear form may
    /// reorder them.
    pub fn commutative(&self) -> bool {
        self.kind != OpKind::Difference
    }

    /// r_o, or 0 for a sharp operator (its range of interest is {0}).
    pub fn range(&self) -> f64 {
        match self.typed() {
            Typed::Style(s, v) => (s.range)(&v),
            Typed::Join(t, size) => (t.range)(size),
        }
    }

    /// How far the blend may move its value from the sharp operator's: a
    /// style's β, a join's whole operator range (its other operand can be
    /// anywhere in it).
    pub fn blend_range(&self) -> f64 {
        match self.typed() {
            Typed::Style(s, v) => (s.blend)(&v),
            Typed::Join(t, size) => (t.range)(size),
        }
    }

    /// The interpreter's record (β, r_o, join size, 0).
    pub fn row(&self) -> [f64; 4] {
        match self.typed() {
            Typed::Style(s, v) => {
                let [beta, range] = s.row(&v);
                [beta, range, 0.0, 0.0]
            }
            Typed::Join(t, size) => [0.0, (t.range)(size), size, 0.0],
        }
    }

    /// The value for two present operands.
    pub fn apply(&self, a: f64, b: f64) -> f64 {
        match self.typed() {
            Typed::Style(s, v) => (s.apply)(self.kind, a, b, &v),
            Typed::Join(t, size) => t.apply(self.kind, a, b, size),
        }
    }

    /// The value when an operand may be missing (∅: an inactive subtree,
    /// known to be irrelevant). Both present: [`Operator::apply`]. Else the
    /// selection rules: ∪ keeps the present operand; \ gives (x, ∅) → x and
    /// (∅, x) → ∅; ∩ gives ∅.
    pub fn select(&self, a: Option<f64>, b: Option<f64>) -> Option<f64> {
        match (a, b) {
            (Some(a), Some(b)) => Some(self.apply(a, b)),
            _ => select_kind(self.kind, a.is_some(), b.is_some()).and_then(|left| if left { a } else { b }),
        }
    }

    /// The factor by which this operator can raise the Lipschitz bound.
    /// (A style's; a join's bound is exact and carried by
    /// `super::roi::field_lipschitz` instead.)
    pub fn lipschitz_factor(&self) -> f64 {
        match self.typed() {
            Typed::Style(s, v) => (s.lipschitz)(&v),
            Typed::Join(..) => 1.0,
        }
    }

    /// The bound of this operator's value from its operands' bounds
    /// `la`, `lb`: the larger for sharp operators and G (whose own factor
    /// the renderer's 1.45 covers), a join's own rule for a join.
    pub fn combine_lipschitz(&self, la: f64, lb: f64) -> f64 {
        match self.typed() {
            Typed::Style(..) => la.max(lb),
            Typed::Join(t, _) => (t.lipschitz)(la, lb),
        }
    }
}

/// What an operator node computes: its descriptor with its parameters.
#[derive(Debug, Clone, Copy)]
pub enum Typed {
    /// An operator style ([`crate::sdf::operator`]) with its parameters.
    Style(&'static OperatorStyle, Params),
    /// A join ([`crate::sdf::join`]) with its size.
    Join(&'static JoinType, f64),
}

/// Which operand an operator with a missing operand passes on:
/// `Some(true)` the left, `Some(false)` the right, `None` nothing (∅).
/// Called only when at least one operand is missing.
pub fn select_kind(kind: OpKind, left: bool, right: bool) -> Option<bool> {
    match kind {
        OpKind::Union if left => Some(true),
        OpKind::Union if right => Some(false),
        OpKind::Difference if left => Some(true),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selection_rules() {
        let u = Operator::UNION;
        let i = Operator::INTERSECTION;
        let d = Operator::DIFFERENCE;
        assert_eq!(u.select(Some(1.0), None), Some(1.0));
        assert_eq!(u.select(None, Some(2.0)), Some(2.0));
        assert_eq!(d.select(Some(1.0), None), Some(1.0));
        assert_eq!(d.select(None, Some(2.0)), None);
        assert_eq!(i.select(Some(1.0), None), None);
        assert_eq!(u.select(None, None), None);
        assert_eq!(d.select(Some(1.0), Some(2.0)), Some(1.0));
    }
}

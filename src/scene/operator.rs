//! Binary operators: sharp CSG (min / max) and Zanni's *compact* smooth
//! versions G (eq. 8-18 of Zanni et al. 2024; `../shared/guide/blobtree-brief.md` §1.1).
//!
//! A compact operator blends only while both operands lie in its range
//! R_o, and is plain CSG outside it, so a primitive can influence the field
//! only up to a value fixed by the tree (its range of interest, `roi.rs`).
//! Everything is written NaN-free: the blend d uses h³/(6·max(β², 1e-30))
//! with h = max(β − |a − b|, 0), and the host refuses r_o < 7β/6, where G
//! would be discontinuous (so 6r_o − β > 0 in b_r).

pub use crate::sdf::join::OpKind;
use crate::sdf::join::{self as joins, JoinType};

/// The blend of a smooth operator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blend {
    /// β > 0: the blend range.
    pub beta: f64,
    /// r_o ≥ 7β/6: the operator range (beyond it the operator is sharp).
    pub range: f64,
}

/// The default operator range relative to β (the brief's choice; the
/// Lipschitz factor 6r_o/(6r_o − β) is then 12/11).
pub const DEFAULT_RANGE_FACTOR: f64 = 2.0;

impl Blend {
    /// A blend with the default range 2β.
    pub fn new(beta: f64) -> Blend {
        Blend { beta, range: DEFAULT_RANGE_FACTOR * beta }
    }

    /// Checks β and r_o; the error names the field (`beta`, `r_o`).
    ///
    /// r_o is compared with 7β/6 with a relative slack of 1e-12, so a range
    /// written as 7/6 of β in decimal is not refused for its rounding.
    pub fn check(&self) -> Result<(), (String, String)> {
        for (name, v) in [("beta", self.beta), ("r_o", self.range)] {
            if !v.is_finite() {
                return Err((name.into(), "must be finite".into()));
            }
        }
        if !(self.beta > 0.0) {
            return Err(("beta".into(), "must be > 0".into()));
        }
        let min = 7.0 * self.beta / 6.0;
        if !(self.range >= min * (1.0 - 1e-12)) {
            return Err(("r_o".into(), format!("must be >= 7/6 of beta ({}): below it the compact blend is discontinuous", crate::diag::short_number(min))));
        }
        Ok(())
    }

    /// The factor 6r_o/(6r_o − β) by which this operator can raise the
    /// Lipschitz bound of its operands (measured in the brief, §1.1).
    pub fn lipschitz_factor(&self) -> f64 {
        6.0 * self.range / (6.0 * self.range - self.beta)
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

    /// The operator of scene file type `name`, with its size (β for the
    /// smooth ones, else the join's size) when it has one.
    pub fn parse(name: &str, size: f64) -> Option<Operator> {
        const KINDS: [OpKind; 3] = [OpKind::Union, OpKind::Intersection, OpKind::Difference];
        if let Some(k) = Self::SHARP.iter().position(|n| *n == name) {
            return Some(Operator::sharp(KINDS[k]));
        }
        if let Some(k) = Self::SMOOTH.iter().position(|n| *n == name) {
            return Some(Operator::smooth(KINDS[k], Blend::new(size)));
        }
        let (t, k) = joins::TYPES.iter().find_map(|t| Some((*t, t.scene_names.iter().position(|n| *n == name)?)))?;
        Some(Operator::joined(KINDS[k], Join::from_size(t, size)))
    }

    /// The `type` of a scene file node.
    pub fn name(&self) -> &'static str {
        match (self.blend, self.join) {
            (Some(_), _) => Self::SMOOTH[self.kind as usize],
            (None, Some(j)) => j.typed().0.scene_names[self.kind as usize],
            (None, None) => Self::SHARP[self.kind as usize],
        }
    }

    /// The sharp operators' type names, in [`OpKind`] order.
    pub const SHARP: [&'static str; 3] = ["union", "intersection", "difference"];

    /// The compact smooth operators' type names, in [`OpKind`] order.
    pub const SMOOTH: [&'static str; 3] = ["smooth_union", "smooth_intersection", "smooth_difference"];

    /// Every operator type name, in type-code order: sharp, smooth, then
    /// the joins' ([`crate::sdf::join::TYPES`]).
    pub fn names() -> impl Iterator<Item = &'static str> {
        Self::SHARP.into_iter().chain(Self::SMOOTH).chain(joins::TYPES.iter().flat_map(|t| t.scene_names.iter().copied()))
    }

    /// Whether swapping the operands leaves the value unchanged, bit for
    /// bit (min, max and |a − b| are symmetric), so the linear form may
    /// reorder them.
    pub fn commutative(&self) -> bool {
        self.kind != OpKind::Difference
    }

    /// r_o, or 0 for a sharp operator (its range of interest is {0}).
    pub fn range(&self) -> f64 {
        match (self.blend, self.join) {
            (Some(b), _) => b.range,
            (None, Some(j)) => j.range(),
            (None, None) => 0.0,
        }
    }

    /// The value for two present operands.
    pub fn apply(&self, a: f64, b: f64) -> f64 {
        if let Some(j) = self.join {
            let (t, size) = j.typed();
            return t.apply(self.kind, a, b, size);
        }
        match self.blend {
            None => g(self.kind, a, b, 0.0),
            Some(bl) => compact(self.kind, a, b, bl.beta, bl.range),
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
    /// (Zanni's G; a join's bound is exact and carried by
    /// `super::roi::field_lipschitz` instead.)
    pub fn lipschitz_factor(&self) -> f64 {
        self.blend.map_or(1.0, |b| b.lipschitz_factor())
    }

    /// The bound of this operator's value from its operands' bounds
    /// `la`, `lb`: the larger for sharp operators and G (whose own factor
    /// the renderer's 1.45 covers), a join's own rule for a join.
    pub fn combine_lipschitz(&self, la: f64, lb: f64) -> f64 {
        match self.join {
            None => la.max(lb),
            Some(j) => (j.typed().0.lipschitz)(la, lb),
        }
    }
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

/// d(a, b, β) = β/6 · max(1 − |a − b|/β, 0)³ (eq. 9), NaN-free:
/// h³ / (6 · max(β², 1e-30)) with h = max(β − |a − b|, 0).
pub fn blend_d(a: f64, b: f64, beta: f64) -> f64 {
    let h = (beta - (a - b).abs()).max(0.0);
    h * h * h / (6.0 * (beta * beta).max(1e-30))
}

/// The bounded operators g (eq. 8, 10, 11); β = 0 is sharp CSG.
pub fn g(kind: OpKind, a: f64, b: f64, beta: f64) -> f64 {
    match kind {
        OpKind::Union => a.min(b) - blend_d(a, b, beta),
        OpKind::Intersection => a.max(b) + blend_d(a, b, beta),
        OpKind::Difference => a.max(-b) + blend_d(a, -b, beta),
    }
}

/// The transition b_r(x, β, r_o) = β · max(1 − 6x/(6r_o − β), 0) (eq. 18).
/// The host guarantees 6r_o − β > 0.
pub fn b_r(x: f64, beta: f64, range: f64) -> f64 {
    beta * (1.0 - 6.0 * x / (6.0 * range - beta)).max(0.0)
}

/// The compact operator G (eq. 12 and 17): g with the blend range b_r of
/// the plain blend's value while both operands are in R_o (∪: (−∞, r_o];
/// ∩ and \: [−r_o, r_o]), sharp CSG otherwise.
pub fn compact(kind: OpKind, a: f64, b: f64, beta: f64, range: f64) -> f64 {
    let inside = match kind {
        OpKind::Union => a <= range && b <= range,
        _ => a.abs() <= range && b.abs() <= range,
    };
    if !inside {
        return g(kind, a, b, 0.0);
    }
    let x = g(kind, a, b, beta);
    let x = if kind == OpKind::Union { x } else { x.abs() };
    g(kind, a, b, b_r(x, beta, range))
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

    #[test]
    fn blends_are_nan_free_and_ranges_are_checked() {
        assert_eq!(blend_d(1.0, 1.0, 0.0), 0.0);
        assert!((g(OpKind::Union, 0.0, 0.0, 0.6) + 0.1).abs() < 1e-15);
        assert_eq!(Blend { beta: 0.6, range: 0.7 }.check(), Ok(()));
        assert_eq!(Blend { beta: 1.0, range: 1.0 }.check().unwrap_err().0, "r_o");
        assert_eq!(Blend { beta: 0.0, range: 1.0 }.check().unwrap_err(), ("beta".into(), "must be > 0".into()));
        assert!((Blend::new(1.0).lipschitz_factor() - 12.0 / 11.0).abs() < 1e-15);
    }
}

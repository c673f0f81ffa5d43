//! Unary nodes: a function of one operand's value (and of the point),
//! between the primitives and the binary operators of a blobtree.
//!
//! What each type computes, and what it does to ranges of interest,
//! Lipschitz bounds, rows and the interpreter, is its descriptor's
//! ([`crate::sdf::unary`], a file a type); this is the scene model's data,
//! a variant a type with its two conversions to and from the descriptor's
//! parameters.

use crate::sdf::primitive::Params;
use crate::sdf::unary::{self as types, UnaryType};

/// A unary node's operation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Unary {
    /// f − distance.
    Offset {
        /// d: positive grows the shape, negative shrinks it.
        distance: f64,
    },
    /// |f| − thickness/2.
    Shell {
        /// t > 0: the wall's thickness.
        thickness: f64,
    },
    /// max(f, gyroid sheet).
    Infill {
        /// The gyroid's period, > 0.
        period: f64,
        /// The sheet's least thickness, > 0.
        thickness: f64,
    },
    /// f + amplitude · n(p).
    Displace {
        /// a ≥ 0.
        amplitude: f64,
        /// f > 0: the noise's base frequency.
        frequency: f64,
    },
}

impl Unary {
    /// Its type and parameters.
    pub fn typed(&self) -> (&'static UnaryType, Params) {
        let of = |t: &'static UnaryType, v: &[f64]| (t, Params::new(v));
        match *self {
            Unary::Offset { distance } => of(&types::OFFSET, &[distance]),
            Unary::Shell { thickness } => of(&types::SHELL, &[thickness]),
            Unary::Infill { period, thickness } => of(&types::INFILL, &[period, thickness]),
            Unary::Displace { amplitude, frequency } => of(&types::DISPLACE, &[amplitude, frequency]),
        }
    }

    /// The node of type `t` with parameters `v` (all of them, in its
    /// parameter order).
    pub fn from_values(t: &UnaryType, v: &[f64]) -> Unary {
        match t.name() {
            "offset" => Unary::Offset { distance: v[0] },
            "shell" => Unary::Shell { thickness: v[0] },
            "infill" => Unary::Infill { period: v[0], thickness: v[1] },
            "displace" => Unary::Displace { amplitude: v[0], frequency: v[1] },
            other => unreachable!("unary type {other} has no variant"),
        }
    }

    /// Its type.
    pub fn kind(&self) -> &'static UnaryType {
        self.typed().0
    }

    /// Its parameters, in its type's field order.
    pub fn values(&self) -> Vec<f64> {
        self.typed().1.to_vec()
    }

    /// The node's value for operand value `v` at point `p`.
    pub fn apply(&self, v: f64, p: [f64; 3]) -> f64 {
        let (t, params) = self.typed();
        (t.apply)(&params, v, p)
    }

    /// The operand's range of interest for the node's [lo, hi].
    pub fn operand_range(&self, lo: f64, hi: f64) -> (f64, f64) {
        let (t, params) = self.typed();
        (t.operand_range)(&params, lo, hi)
    }

    /// How much the node can raise its operand's Lipschitz bound, added.
    pub fn lipschitz_increase(&self) -> f64 {
        let (t, params) = self.typed();
        (t.lipschitz_increase)(&params)
    }

    /// Checks the parameters; the error names the field.
    pub fn check(&self) -> Result<(), (String, String)> {
        let (t, params) = self.typed();
        for (name, v) in t.fields.iter().zip(params.iter()) {
            if !v.is_finite() {
                return Err((name.to_string(), "must be finite".into()));
            }
        }
        (t.check)(&params)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_type_has_a_variant_that_converts_back() {
        for t in types::TYPES {
            let v: Vec<f64> = (0..t.param_count()).map(|k| 0.25 + k as f64).collect();
            let u = Unary::from_values(t, &v);
            assert_eq!((u.kind(), u.values()), (t, v), "{t:?}");
        }
    }
}

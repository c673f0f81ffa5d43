//! Unary nodes: a function of one operand's value (and of the point),
//! between the primitives and the binary operators of a blobtree.
//!
//! - **offset** d: f − d, a rounding or dilation (d > 0) or an erosion
//!   (d < 0);
//! - **shell** t: |f| − t/2, a wall of thickness t centred on the surface:
//!   it hollows a solid out (Zanni et al. 2024, Fig. 14's carved cavities);
//! - **infill** (period, thickness): max(f, g) with g a gyroid sheet at
//!   least `thickness` thick, clipped by the operand (Fig. 17's heat
//!   exchanger): g = |G(k p)| / (k√6) − thickness/2, k = 2π/period, G the
//!   gyroid sin x cos y + sin y cos z + sin z cos x, whose gradient is at
//!   most k√6 (each partial is a dot product of two unit-bounded pairs), so
//!   g is 1-Lipschitz and {g ≤ 0} holds every point within thickness/2 of
//!   the gyroid;
//! - **displace** (amplitude a, frequency f): f + a·n(p) with the fixed
//!   pseudo-noise n of [`noise`], |n| ≤ 1, |∇n| ≤
//!   [`NOISE_GRADIENT`]·f.
//!
//! **Ranges of interest** (roi.rs). A node's range [r⁻, r⁺] gives its
//! operand the range where the node's value can be in [r⁻, r⁺]: offset
//! [r⁻ + d, r⁺ + d]; shell ±(r⁺ + t/2); infill the node's own (a sharp
//! intersection with a field that is not a primitive); displace
//! [r⁻ − a, r⁺ + a]. An operand above its r⁺ puts the node above its own,
//! so a missing operand (∅, "above") stays ∅: a unary node of ∅ is ∅.
//!
//! **Lipschitz**: offset, shell and infill keep their operand's bound;
//! displace adds a·f·NOISE_GRADIENT.

use crate::sdf::{noise, NOISE_GRADIENT};
use glam::DVec3;

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

/// The unary node types, with the type codes of the linear form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum UnaryKind {
    /// `offset`
    Offset = 48,
    /// `shell`
    Shell = 49,
    /// `infill`
    Infill = 50,
    /// `displace`
    Displace = 51,
}

impl UnaryKind {
    /// Every kind, in type-code order.
    pub const ALL: [UnaryKind; 4] = [UnaryKind::Offset, UnaryKind::Shell, UnaryKind::Infill, UnaryKind::Displace];

    /// The `type` of a scene file node.
    pub fn name(self) -> &'static str {
        match self {
            UnaryKind::Offset => "offset",
            UnaryKind::Shell => "shell",
            UnaryKind::Infill => "infill",
            UnaryKind::Displace => "displace",
        }
    }

    /// The kind named `name`.
    pub fn parse(name: &str) -> Option<UnaryKind> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Its parameter fields in a scene file, in order.
    pub fn fields(self) -> &'static [&'static str] {
        match self {
            UnaryKind::Offset => &["distance"],
            UnaryKind::Shell => &["thickness"],
            UnaryKind::Infill => &["period", "thickness"],
            UnaryKind::Displace => &["amplitude", "frequency"],
        }
    }
}

impl Unary {
    /// Its kind.
    pub fn kind(&self) -> UnaryKind {
        match self {
            Unary::Offset { .. } => UnaryKind::Offset,
            Unary::Shell { .. } => UnaryKind::Shell,
            Unary::Infill { .. } => UnaryKind::Infill,
            Unary::Displace { .. } => UnaryKind::Displace,
        }
    }

    /// Builds the node of `kind` from its [`UnaryKind::fields`] values.
    pub fn from_values(kind: UnaryKind, v: &[f64]) -> Unary {
        match kind {
            UnaryKind::Offset => Unary::Offset { distance: v[0] },
            UnaryKind::Shell => Unary::Shell { thickness: v[0] },
            UnaryKind::Infill => Unary::Infill { period: v[0], thickness: v[1] },
            UnaryKind::Displace => Unary::Displace { amplitude: v[0], frequency: v[1] },
        }
    }

    /// Its parameters, in [`UnaryKind::fields`] order.
    pub fn values(&self) -> Vec<f64> {
        match *self {
            Unary::Offset { distance } => vec![distance],
            Unary::Shell { thickness } => vec![thickness],
            Unary::Infill { period, thickness } => vec![period, thickness],
            Unary::Displace { amplitude, frequency } => vec![amplitude, frequency],
        }
    }

    /// The node's value for operand value `v` at point `p`.
    pub fn apply(&self, v: f64, p: [f64; 3]) -> f64 {
        match *self {
            Unary::Offset { distance } => v - distance,
            Unary::Shell { thickness } => v.abs() - 0.5 * thickness,
            Unary::Infill { period, thickness } => v.max(gyroid_sheet(DVec3::from(p), period, thickness)),
            Unary::Displace { amplitude, frequency } => v + amplitude * noise(p, frequency),
        }
    }

    /// The operand's range of interest for the node's [lo, hi] (module doc).
    pub fn operand_range(&self, lo: f64, hi: f64) -> (f64, f64) {
        match *self {
            Unary::Offset { distance } => (lo + distance, hi + distance),
            Unary::Shell { thickness } => {
                let r = (hi + 0.5 * thickness).max(0.0);
                (-r, r)
            }
            Unary::Infill { .. } => (lo, hi),
            Unary::Displace { amplitude, .. } => (lo - amplitude, hi + amplitude),
        }
    }

    /// How much the node can raise its operand's Lipschitz bound, added.
    pub fn lipschitz_increase(&self) -> f64 {
        match *self {
            Unary::Displace { amplitude, frequency } => amplitude * frequency * NOISE_GRADIENT,
            _ => 0.0,
        }
    }

    /// Checks the parameters; the error names the field.
    pub fn check(&self) -> Result<(), (String, String)> {
        for (name, v) in self.kind().fields().iter().zip(self.values()) {
            if !v.is_finite() {
                return Err((name.to_string(), "must be finite".into()));
            }
        }
        let positive = |name: &str, v: f64| if v > 0.0 { Ok(()) } else { Err((name.to_string(), "must be > 0".to_string())) };
        match *self {
            Unary::Offset { .. } => Ok(()),
            Unary::Shell { thickness } => positive("thickness", thickness),
            Unary::Infill { period, thickness } => positive("period", period).and(positive("thickness", thickness)),
            Unary::Displace { amplitude, frequency } => {
                if !(amplitude >= 0.0) {
                    return Err(("amplitude".into(), "must be >= 0".into()));
                }
                positive("frequency", frequency)
            }
        }
    }
}

/// The gyroid sheet g of the module doc at `p`.
pub fn gyroid_sheet(p: DVec3, period: f64, thickness: f64) -> f64 {
    let k = std::f64::consts::TAU / period;
    let q = p * k;
    let g = q.x.sin() * q.y.cos() + q.y.sin() * q.z.cos() + q.z.sin() * q.x.cos();
    g.abs() / (k * 6f64.sqrt()) - 0.5 * thickness
}


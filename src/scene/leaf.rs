//! Formula leaves: a primitive whose field is any formula of the language,
//! held within a box of its local frame.
//!
//! The leaf's local field is v(q) = max(f(q)/L, box(q)): the formula f,
//! divided by its declared Lipschitz bound L (1 when none is declared),
//! intersected with the exact distance to its box. Outside the box v is at
//! least the distance to the box, so the box bounds every sublevel set the
//! sparse traversal asks about (the box grown by the level), as an exact
//! distance's own box does; inside it the zero set is f's. A leaf evaluates
//! its formula from a tape (the scene field source packs the leaves'
//! tapes into a texture of its own), so a new formula is a buffer, not a
//! shader.
//!
//! Sphere tracing needs L: a leaf without one is bisected only
//! ([`super::linear::Linear::untraceable_leaf`]).

use crate::ir::{Ir, Op};
use glam::DVec3;
use std::sync::Arc;

/// Most operations a leaf's formula may compile to: each is an instruction
/// of its tape, which the interpreter runs per evaluation.
pub const MAX_LEAF_OPS: usize = 20_000;

/// A formula leaf's shape (module doc).
#[derive(Debug, Clone)]
pub struct FormulaLeaf {
    /// The formula as the scene file gives it.
    pub source: String,
    /// Its compiled form.
    pub ir: Arc<Ir>,
    /// The box's low corner, in the leaf's local frame.
    pub lo: [f64; 3],
    /// The box's high corner.
    pub hi: [f64; 3],
    /// The declared Lipschitz bound of the formula over its box, if any.
    pub lipschitz: Option<f64>,
}

impl PartialEq for FormulaLeaf {
    fn eq(&self, o: &FormulaLeaf) -> bool {
        self.source == o.source && self.lo == o.lo && self.hi == o.hi && self.lipschitz == o.lipschitz
    }
}

/// What is wrong with a leaf: the field (`formula`, `bounds[3]`) and why.
pub type LeafError = (String, String);

impl FormulaLeaf {
    /// Compiles `source` and checks the box (`[x0, x1, y0, y1, z0, z1]`)
    /// and the bound.
    pub fn new(source: &str, bounds: [f64; 6], lipschitz: Option<f64>) -> Result<FormulaLeaf, LeafError> {
        let err = |field: &str, reason: String| Err((field.to_string(), reason));
        let program = match crate::syntax::parse(source) {
            Ok(p) => p,
            Err(e) => return err("formula", diagnostic(source, &e.to_diagnostic())),
        };
        let ir = match crate::sema::analyze_with(&program, &[]) {
            Ok(ir) => ir,
            Err(e) => return err("formula", diagnostic(source, &e.to_diagnostic())),
        };
        if ir.is_csg() {
            return err("formula", "a leaf is one surface: level-set conditions and several surfaces are for formulas rendered alone".into());
        }
        if let Some((name, _)) = ir.params.first() {
            return err("formula", format!("parameter '{name}' has no value in a scene: write the number"));
        }
        let ops = ir.live().len();
        if ops > MAX_LEAF_OPS {
            return err("formula", format!("{ops} operations, above a leaf's limit of {MAX_LEAF_OPS}"));
        }
        for k in 0..3 {
            let (a, b) = (bounds[2 * k], bounds[2 * k + 1]);
            if !(a.is_finite() && b.is_finite()) {
                return err(&format!("bounds[{}]", 2 * k + usize::from(a.is_finite())), "must be finite".into());
            }
            if !(a < b) {
                return err(&format!("bounds[{}]", 2 * k + 1), format!("must be above bounds[{}] ({a})", 2 * k));
            }
        }
        if let Some(l) = lipschitz {
            if !(l.is_finite() && l > 0.0) {
                return err("lipschitz", "must be finite and > 0".into());
            }
        }
        let lo = [bounds[0], bounds[2], bounds[4]];
        let hi = [bounds[1], bounds[3], bounds[5]];
        Ok(FormulaLeaf { source: source.to_string(), ir: Arc::new(ir), lo, hi, lipschitz })
    }

    /// The box as a scene file writes it.
    pub fn bounds(&self) -> [f64; 6] {
        [self.lo[0], self.hi[0], self.lo[1], self.hi[1], self.lo[2], self.hi[2]]
    }

    /// The box's centre.
    pub fn centre(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| 0.5 * (self.lo[k] + self.hi[k]))
    }

    /// The box's half extents.
    pub fn half(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| 0.5 * (self.hi[k] - self.lo[k]))
    }

    /// 1/L: what f is multiplied by.
    pub fn scale(&self) -> f64 {
        1.0 / self.lipschitz.unwrap_or(1.0)
    }

    /// The local field at local point `q` (module doc), the formula at time
    /// 0; where f is undefined (NaN), the leaf is absent (+∞).
    pub fn local_value(&self, q: DVec3) -> f64 {
        let f = crate::reference::eval_scalar(&self.ir, [q.x, q.y, q.z, 0.0], &[]) * self.scale();
        let f = if f.is_nan() { f64::INFINITY } else { f };
        f.max(box_distance(q - DVec3::from(self.centre()), DVec3::from(self.half())))
    }

    /// Whether the leaf's cells are enclosed in reduced affine arithmetic
    /// (its tape's RAA run along the cell's segment) rather than IA: where
    /// RAA pays for a tape ([`crate::affine_pays`]).
    pub fn affine(&self) -> bool {
        crate::affine_pays(&self.ir)
    }

    /// Whether the formula has an integer power from 8 on, which its tape
    /// (or its derivative's) runs as a square-and-multiply loop.
    pub fn has_power_loops(&self) -> bool {
        self.ir.live().iter().any(|&n| matches!(self.ir.nodes[n as usize], Op::PowI(_, k) if k >= 8))
    }

    /// The local field as formula text (`max((f) * s, translate(c, box(h)))`),
    /// `None` when f's text would pass `limit` bytes.
    pub fn formula(&self, num: &dyn Fn(f64) -> String, limit: usize) -> Option<String> {
        let f = crate::ir::display_limited(&self.ir, self.ir.root, limit);
        if f.ends_with("...") {
            return None;
        }
        let f = if self.lipschitz.is_some() { format!("({f}) * {}", num(self.scale())) } else { f };
        let [c, h] = [self.centre(), self.half()].map(|v| v.map(num).join(", "));
        Some(format!("max({f}, translate({c}, box({h})))"))
    }
}

/// A formula's diagnostic on one line: its message and where it points
/// (`unknown function 'sinn' at bytes 4..8 ("sinn")`).
fn diagnostic(source: &str, d: &crate::diag::Diagnostic) -> String {
    match d.labels.first() {
        Some((span, _)) => {
            let (a, b) = (span.start as usize, (span.end as usize).max(span.start as usize));
            match source.get(a..b.min(source.len())) {
                Some(text) if !text.is_empty() => format!("{} at bytes {a}..{b} ({text:?})", d.message),
                _ => format!("{} at byte {a}", d.message),
            }
        }
        None => d.message.clone(),
    }
}

/// The exact distance from q to the box of half extents h about the origin.
pub fn box_distance(q: DVec3, h: DVec3) -> f64 {
    let d = q.abs() - h;
    d.max(DVec3::ZERO).length() + d.max_element().min(0.0)
}

//! The unary node types (modifiers of any shape: `offset`, `shell`,
//! `infill`, `displace`), each described once, in a file of its own, by a
//! [`UnaryType`]: its formula form (name, arguments, expansion into IR
//! operations), its f64 reference, its parameters as a scene file names
//! them with their constraints, what it does to its operand's range of
//! interest, trace level and Lipschitz bound, how a transform above it
//! moves it, its parameter row in the GPU layout and its case of the scene
//! interpreter (WGSL).
//!
//! The formula language ([`super::lower`]) and blobtree scenes
//! (`crate::scene`: file format, validation, rows, ranges of interest,
//! Lipschitz bounds, formula text, lowering, the interpreter's cases) read
//! [`TYPES`] instead of matching on unary types. Adding one is a file
//! here, its line in [`TYPES`], and its variant of `scene::Unary` (the
//! scene model's data, with its two conversions to and from numbers).
//!
//! Every number a type takes is a parameter, in one order: the formula's
//! arguments before the shape, the scene file's fields and the functions
//! of the descriptor all use it.
//!
//! **Ranges of interest** (`scene::roi`). A node's range [r⁻, r⁺] gives
//! its operand the range where the node's value can be in [r⁻, r⁺]. An
//! operand above its r⁺ puts the node above its own, so a missing operand
//! (∅, "above") stays ∅: a unary node of ∅ is ∅.

use super::primitive::{Expand, Invalid, Params};
use super::Info;

mod displace;
mod infill;
mod offset;
mod shell;

pub use displace::{DISPLACE, FEATURE_DISPLACE, NOISE_WAVES};
pub use infill::{FEATURE_INFILL, INFILL};
#[cfg(test)]
pub use displace::{noise, NOISE_GRADIENT};
pub use offset::OFFSET;
pub use shell::SHELL;

/// Every unary type, in type-code order.
pub static TYPES: [&UnaryType; 4] = [&OFFSET, &SHELL, &INFILL, &DISPLACE];

/// The type named `name` (in a scene file and a formula alike).
pub fn by_name(name: &str) -> Option<&'static UnaryType> {
    TYPES.iter().copied().find(|t| t.info.name == name)
}

/// One unary type (module doc). Types are compared by type code.
pub struct UnaryType {
    /// The formula form: name (also the `type` of a scene file node),
    /// arity, signature and its one-line definition.
    pub info: Info,
    /// The type code of a node word in the GPU layout (`scene::codes`;
    /// 48 to 55 are unary).
    pub code: u32,
    /// The parameters' names in a scene file, in parameter order (numbers).
    pub fields: &'static [&'static str],
    /// Checks finite parameters; the error names the field.
    pub check: fn(&[f64]) -> Result<(), Invalid>,
    /// The node's value for operand value `v` at point `p`, written as the
    /// formula form expands (so the two agree to rounding).
    pub apply: fn(&[f64], f64, [f64; 3]) -> f64,
    /// The operand's range of interest for the node's [lo, hi].
    pub operand_range: fn(&[f64], f64, f64) -> (f64, f64),
    /// The operand's trace level for the node's level (`scene::roi::
    /// trace_levels`): where the operand's value decides the node's
    /// surface, or `None` when no one level does.
    pub operand_level: fn(&[f64], f64) -> Option<f64>,
    /// How much the node can raise its operand's Lipschitz bound, added.
    pub lipschitz_increase: fn(&[f64]) -> f64,
    /// The parameters under a transform of scale `s` (the node has no frame
    /// of its own); `None` for a pattern fixed in the world, which no
    /// transform, twist or bend may move.
    pub moved: Option<fn(&[f64], f64) -> Params>,
    /// Its parameter row in the GPU layout (the record the interpreter's
    /// case reads as `k`).
    pub row: fn(&[f64]) -> [f64; 4],
    /// Its case of the scene interpreter.
    pub wgsl: UnaryCase,
    /// The formula form's expansion of the lowered arguments `v` (the
    /// shape last).
    pub(in crate::sdf) expand: Expand,
}

/// A unary type's case of the scene interpreter (`scene_unary` in
/// templates/fields/scene.wgsl).
#[derive(Debug, Clone, Copy)]
pub struct UnaryCase {
    /// The interpreter feature bit of scenes with the type, `FEATURE_<NAME>`
    /// (NAME the type in capitals), or 0 for a type every kernel with
    /// unary nodes (`FEATURE_UNARY`) has.
    pub feature: u32,
    /// The statements, indented by 4 (by 8 under a feature): they set `r`
    /// where `ty == NODE_<NAME>`, reading the operand's value `v`, the
    /// point `p` and the row `k`.
    pub code: &'static str,
    /// Its interval enclosure for bisection (`scene_unary_ia`,
    /// templates/fields/scene_enclosure.wgsl): statements, indented as
    /// `code`, that set the range `r` where `ty == NODE_<NAME>`, reading the
    /// operand's range `v`, the box `b` (a `SceneBox`) and the row `k`.
    pub enclosure: &'static str,
}

impl UnaryType {
    /// The `type` of a scene file node and the formula's name.
    pub fn name(&self) -> &'static str {
        self.info.name
    }

    /// The number of parameters.
    pub fn param_count(&self) -> usize {
        self.fields.len()
    }
}

impl PartialEq for UnaryType {
    fn eq(&self, o: &UnaryType) -> bool {
        self.code == o.code
    }
}

impl Eq for UnaryType {}

impl std::hash::Hash for UnaryType {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.code.hash(h)
    }
}

impl std::fmt::Debug for UnaryType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.info.name)
    }
}

/// An error unless `v > 0`.
fn positive(name: &str, v: f64) -> Result<(), Invalid> {
    if v > 0.0 { Ok(()) } else { Err((name.to_string(), "must be > 0".to_string())) }
}

/// Every parameter a length, scaled with the transform.
fn scaled(v: &[f64], s: f64) -> Params {
    let mut p = Params::new(v);
    for x in p.iter_mut() {
        *x *= s;
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_unary_and_in_order() {
        for (k, t) in TYPES.iter().enumerate() {
            assert_eq!(t.code, 48 + k as u32, "{t:?}");
            assert!(matches!(t.info.form, super::super::Form::Unary(u) if u == *t), "{t:?}");
            assert_eq!(by_name(t.name()), Some(*t));
        }
    }
}

//! Which field source renders a formula: generated code (fast frames, a
//! compile that grows steeply with the formula on lavapipe) or the tape
//! (a fixed interpreter compiled once, slower per evaluation). `Auto`
//! decides by a cost model measured on this project's reference machine
//! (README, "Compiled or tape"). A later source (a formula lowered to a
//! blobtree scene) joins as one more [`FieldKind`] value.

use super::{FieldSource, TapeData, TapeError};
use crate::ir::Ir;
use crate::render::Traversal;

/// The field source asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FieldKind {
    /// The formula generated into WGSL.
    Compiled,
    /// The formula as a tape run by the fixed interpreter.
    Tape,
    /// Chosen per formula and traversal by [`choose`].
    #[default]
    Auto,
}

/// A field source ready to be bound: the tape is built once and owned.
#[derive(Debug, Clone)]
pub enum PreparedField {
    /// Generated code.
    Compiled,
    /// A tape.
    Tape(TapeData),
}

impl PreparedField {
    /// The field source over `ir`.
    pub fn source<'a>(&'a self, ir: &'a Ir) -> FieldSource<'a> {
        match self {
            PreparedField::Compiled => FieldSource::Compiled(ir),
            PreparedField::Tape(t) => FieldSource::Tape(t),
        }
    }

    /// The kind that was prepared (never `Auto`).
    pub fn kind(&self) -> FieldKind {
        match self {
            PreparedField::Compiled => FieldKind::Compiled,
            PreparedField::Tape(_) => FieldKind::Tape,
        }
    }
}

/// Operations (tape instructions of the value program) from which `Auto`
/// takes the tape, per traversal and algebra. Measured (README): the
/// compiled path's first frame (compile + frame, Mesa's shader cache off)
/// against the tape's; below these the compiled kernel reaches its first
/// frame sooner and renders every later frame faster.
pub fn crossover(traversal: &Traversal) -> usize {
    match traversal {
        Traversal::Bisect(b) if b.algebra == super::Domain::Affine => CROSSOVER_BISECT_RAA,
        Traversal::Bisect(_) => CROSSOVER_BISECT_IA,
        Traversal::Sphere(_) => CROSSOVER_SPHERE,
    }
}

/// See [`crossover`].
pub const CROSSOVER_BISECT_IA: usize = 400;
/// See [`crossover`].
pub const CROSSOVER_BISECT_RAA: usize = 150;
/// See [`crossover`].
pub const CROSSOVER_SPHERE: usize = 1000;

/// The field for `ir` traced by `traversal`. `Tape` fails when the formula
/// cannot be a tape (level-set CSG, user WGSL, too many registers); `Auto`
/// then takes the compiled field, and otherwise compares the formula's size
/// with [`crossover`].
pub fn choose(kind: FieldKind, ir: &Ir, traversal: &Traversal) -> Result<PreparedField, TapeError> {
    let hooks = matches!(traversal, Traversal::Bisect(b) if b.modalities.inline.is_some());
    match kind {
        FieldKind::Compiled => Ok(PreparedField::Compiled),
        FieldKind::Tape if hooks => Err(TapeError::Hooks),
        FieldKind::Tape => TapeData::new(ir).map(PreparedField::Tape),
        FieldKind::Auto if hooks => Ok(PreparedField::Compiled),
        FieldKind::Auto => match TapeData::new(ir) {
            Ok(t) if t.ops >= crossover(traversal) => Ok(PreparedField::Tape(t)),
            _ => Ok(PreparedField::Compiled),
        },
    }
}

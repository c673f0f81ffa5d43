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

/// Instructions of the value program from which `Auto` takes the tape, per
/// traversal and algebra. Measured on lavapipe 22.3 (README, "Compiled or
/// tape"): the tape's first frame costs about 20-70 s cold whatever the
/// formula (its interpreter kernel) and its frames run 10-100 times slower
/// than generated code, so it pays only where the compiled kernel's compile
/// is slower still: from a few thousand operations (compiled: ~35 s at
/// 2,503, over 120 s at 12,503). RAA has no measured win yet (`@creature`:
/// over 120 s compiled, over 150 s as a tape), so it uses the same line.
pub fn crossover(traversal: &Traversal) -> usize {
    match traversal {
        Traversal::Bisect(b) if b.algebra == super::Domain::Affine => CROSSOVER_BISECT_RAA,
        Traversal::Bisect(_) => CROSSOVER_BISECT_IA,
        Traversal::Sphere(_) => CROSSOVER_SPHERE,
    }
}

/// See [`crossover`].
pub const CROSSOVER_BISECT_IA: usize = 4000;
/// See [`crossover`].
pub const CROSSOVER_BISECT_RAA: usize = 4000;
/// See [`crossover`] (sphere tracing evaluates only the scalar field: its
/// compiled kernels are the cheapest to build).
pub const CROSSOVER_SPHERE: usize = 4000;

/// Whether the compiled kernel would be over [`super::kernel::MAX_SHADER_BYTES`]
/// (the renderer refuses it; the tape has no such limit).
fn too_large(ir: &Ir, traversal: &Traversal) -> bool {
    super::assemble(FieldSource::Compiled(ir), traversal).wgsl.len() > super::kernel::MAX_SHADER_BYTES
}

/// The field for `ir` traced by `traversal`. `Tape` fails when the formula
/// cannot be a tape (level-set CSG, user WGSL, too many registers); `Auto`
/// then takes the compiled field, and otherwise the tape from [`crossover`]
/// on, or when the compiled kernel would be too large to build.
pub fn choose(kind: FieldKind, ir: &Ir, traversal: &Traversal) -> Result<PreparedField, TapeError> {
    let hooks = matches!(traversal, Traversal::Bisect(b) if b.modalities.inline.is_some());
    match kind {
        FieldKind::Compiled => Ok(PreparedField::Compiled),
        FieldKind::Tape if hooks => Err(TapeError::Hooks),
        FieldKind::Tape => TapeData::new(ir).map(PreparedField::Tape),
        FieldKind::Auto if hooks => Ok(PreparedField::Compiled),
        FieldKind::Auto => match TapeData::new(ir) {
            Ok(t) if t.ops >= crossover(traversal) || too_large(ir, traversal) => Ok(PreparedField::Tape(t)),
            _ => Ok(PreparedField::Compiled),
        },
    }
}

//! Which field source renders a formula: generated code (fast frames, a
//! compile that grows steeply with the formula on lavapipe) or the tape
//! (a fixed interpreter compiled once, slower per evaluation). `Auto`
//! decides by a cost model whose lines were chosen by measurement on
//! lavapipe (docs/benchmarks.md). A later source (a formula lowered to a
//! blobtree scene) joins as one more [`FieldKind`] value.

pub(crate) use crate::field::FieldKind;
use crate::field::{FieldSource, SceneData, TapeData, TapeError};
use crate::ir::Ir;
use crate::render::Traversal;

/// A field source ready to be bound: the tape is built once and owned.
#[derive(Debug, Clone)]
pub enum PreparedField {
    /// Generated code.
    Compiled,
    /// A tape.
    Tape(TapeData),
    /// A blobtree scene's buffers.
    Scene(SceneData),
}

impl PreparedField {
    /// The field source over `ir`.
    pub fn source<'a>(&'a self, ir: &'a Ir) -> &'a dyn FieldSource {
        match self {
            PreparedField::Compiled => ir,
            PreparedField::Tape(t) => t,
            PreparedField::Scene(d) => d,
        }
    }

    /// The kind that was prepared (never `Auto`).
    pub fn kind(&self) -> FieldKind {
        match self {
            PreparedField::Compiled => FieldKind::Compiled,
            PreparedField::Tape(_) => FieldKind::Tape,
            PreparedField::Scene(_) => FieldKind::Scene,
        }
    }
}

/// Instructions of the value program ([`TapeData::size`]: an input
/// instruction counted before each use of an input) from which `Auto`
/// takes the tape, per traversal and algebra. The tape's frames are many
/// times slower than the compiled kernel's, so below the line the compiled
/// kernel's first frame comes sooner or about as soon and every later one
/// faster; above it the tape's first frame comes sooner, as the compiled
/// kernel's compile grows steeply with its size on lavapipe while the
/// interpreter is compiled once. The lines were chosen by measurement on
/// lavapipe (docs/benchmarks.md): the cold first frame of families of
/// formulas a program writes (sums of bilinear terms, products of planes,
/// sums of Gaussians and of trigonometric products), compiled and as a
/// tape, with lavapipe's LLVM passes off for a single frame
/// ([`crate::gpu::driver`]). RAA's line lies higher than IA's: its compiled
/// kernels have no interval product's zero test and build comparatively
/// sooner, while its tape's step is dearer. Transcendental functions weigh
/// more ([`HEAVY_WEIGHT`]).
pub fn crossover(traversal: &Traversal) -> usize {
    match traversal {
        Traversal::Bisect(b) if b.algebra == crate::ir::Domain::Affine => CROSSOVER_BISECT_RAA,
        Traversal::Bisect(_) => CROSSOVER_BISECT_IA,
        Traversal::Sphere(_) => CROSSOVER_SPHERE,
    }
}

/// See [`crossover`].
pub const CROSSOVER_BISECT_IA: usize = 2_400;
/// See [`crossover`].
pub const CROSSOVER_BISECT_RAA: usize = 4_000;
/// See [`crossover`] (sphere tracing evaluates only the scalar field: its
/// compiled kernels are the cheapest to build; its line was not measured
/// separately).
pub const CROSSOVER_SPHERE: usize = 4000;

/// A formula bisected as a tape at least this many times longer than it has
/// min, max, clamp, abs and sign instructions (a CSG formula: `@city` 3.4,
/// `@creature` 12) is never taken as a tape by `Auto`, only compiled (unless
/// the compiled kernel would be too large). Its tape is far slower a frame
/// than a sum's of the same length, and leaves pixels unresolved from about
/// 1,700 instructions on, while its compiled kernel builds comparatively
/// quickly: chosen by measurement on lavapipe with `@city` and copies of
/// its blocks (docs/benchmarks.md), whose tape lost in both algebras at
/// every size tried.
pub const CSG_RATIO: usize = 16;

/// The value program's min, max, clamp, abs and sign instructions.
fn minmax_ops(t: &TapeData) -> usize {
    let [start, len, _, _] = t.words[0];
    t.words[start as usize..(start + len) as usize].iter().filter(|w| crate::field::tape::is_minmax(w[0])).count()
}

/// What a division, square root or transcendental function (exp, log,
/// pow, the trigonometric and hyperbolic functions) adds to a formula's
/// size in `auto`'s weighing, beyond its own instruction, in IA (and
/// sphere tracing, not measured separately), where its sums stay chains
/// (see `heavy_weight`): the compiled kernel's build then grows much
/// faster with them than with bilinear terms of the same size, while each
/// also makes the tape's step dearer. Chosen by measurement on the
/// families of [`crossover`] (docs/benchmarks.md). A sum whose terms
/// become loops (a run compares its terms' operands in a fixed order:
/// [`crate::field::compiled::term_loops`]) weighs each loop body once, so the weight
/// matters for sums of mixed shapes.
pub const HEAVY_WEIGHT: usize = 6;
/// [`HEAVY_WEIGHT`] in RAA, whose affine transcendental functions build
/// slower still (chosen the same way).
pub const HEAVY_WEIGHT_RAA: usize = 12;

/// Whether `op` is a division, square root or transcendental function
/// ([`HEAVY_WEIGHT`]).
fn heavy(op: &crate::ir::Op) -> bool {
    use crate::ir::{Func1, Func2, Op};
    match op {
        Op::Div(..) | Op::Call2(Func2::Pow | Func2::Atan2, ..) => true,
        Op::Call1(f, _) => !matches!(f, Func1::Abs | Func1::Sign | Func1::Floor),
        _ => false,
    }
}

/// The divisions, square roots and transcendental functions of the code
/// generated for `ir` (`plan`'s loop bodies once per unrolled term),
/// weighed for `traversal` ([`HEAVY_WEIGHT`]); none where the compiled
/// field balances the formula's long sums ([`crate::field::balance`]), whose
/// build then grows about linearly with them and beats the tape's first
/// frame in both algebras.
fn heavy_weight(ir: &Ir, plan: &crate::field::compiled::term_loops::Plan, traversal: &Traversal) -> usize {
    if plan.is_empty() && crate::field::compiled::balance::balanced(ir, |_| false).is_some() {
        return 0;
    }
    let weight = match traversal {
        Traversal::Bisect(b) if b.algebra == crate::ir::Domain::Affine => HEAVY_WEIGHT_RAA,
        _ => HEAVY_WEIGHT,
    };
    weight * plan.emitted_weight(ir, |op| usize::from(heavy(op)))
}

/// Whether `Auto` takes the tape for `t`: from [`crossover`] instructions
/// on, but never for a CSG formula bisected ([`CSG_RATIO`]). (RAA needs no
/// line of its own for min and max: the op libraries' affine min and max
/// are branch-free, where branchy ones compiled in time that grew steeply
/// with their number.)
///
/// A job of `frames` frames moves the line up by √frames (at most 4×, from
/// 16 frames): the tape's later frames are an order of magnitude slower
/// than the compiled kernel's, so its head start on the first frame is
/// spent after a few (how many grows with the formula's size: chosen by
/// measurement, docs/benchmarks.md).
///
/// A formula whose long runs of same-shaped terms become loops
/// ([`crate::field::compiled::term_loops`]) is weighed by what its generated code holds (the
/// loop bodies, not every term): the 2,503-operation sum of products is
/// then 81 nodes, and its compiled first frame comes sooner than its
/// tape's; so is a polynomial of many monomials, one Horner loop
/// ([`crate::field::compiled::term_loops::horner`]).
fn tape_pays(t: &TapeData, ir: &Ir, traversal: &Traversal, frames: u64) -> bool {
    let csg = matches!(traversal, Traversal::Bisect(_)) && minmax_ops(t) * CSG_RATIO >= t.ops;
    let line = crossover(traversal) as f64 * (frames.clamp(1, 16) as f64).sqrt();
    // The code is weighed as it is generated: a sum of many monomials as a loop.
    let (gathered, plan) = crate::field::compiled::term_loops::written_plan(ir);
    let ir = gathered.as_ref().unwrap_or(ir);
    let size = if plan.is_empty() { t.size } else { plan.emitted_nodes(ir) } + heavy_weight(ir, &plan, traversal);
    !csg && size as f64 >= line
}

/// Whether the compiled kernel would be over [`crate::kernel::MAX_SHADER_BYTES`]
/// (the renderer refuses it; the tape has no such limit).
fn too_large(ir: &Ir, traversal: &Traversal) -> bool {
    crate::kernel::assemble(ir, traversal).code_bytes() > crate::kernel::MAX_SHADER_BYTES
}

/// The field for formula `f` (parameter values `params`) traced by
/// `traversal`. `Tape` fails when the formula cannot be a tape (level-set
/// CSG, user WGSL, too many registers), `Scene` when it is not a blobtree
/// or is bisected in RAA ([`scene`]); `Auto` takes the compiled field for
/// those, and otherwise the tape where it pays ([`crossover`], [`CSG_RATIO`]), or when the
/// compiled kernel would be too large to build. `Auto`'s scene is
/// [`auto_scene`], tried first by the caller (it changes the traversal's
/// Lipschitz bound).
pub fn choose(kind: FieldKind, f: &crate::Formula, params: &[f32], traversal: &Traversal) -> Result<PreparedField, FieldError> {
    choose_for(kind, f, params, traversal, 1)
}

/// [`choose`] for a job of `frames` frames (an animation, a benchmark's
/// runs): `Auto` weighs the tape's sooner first frame against its slower
/// later ones (`tape_pays`).
pub fn choose_for(kind: FieldKind, f: &crate::Formula, params: &[f32], traversal: &Traversal, frames: u64) -> Result<PreparedField, FieldError> {
    let ir = &f.ir;
    let hooks = matches!(traversal, Traversal::Bisect(b) if b.modalities.inline.is_some());
    match kind {
        FieldKind::Compiled => Ok(PreparedField::Compiled),
        FieldKind::Scene => Ok(scene(f, params, traversal)?.0),
        FieldKind::Tape if hooks => Err(TapeError::Hooks.into()),
        FieldKind::Tape => Ok(TapeData::new(ir).map(PreparedField::Tape)?),
        FieldKind::Auto if hooks => Ok(PreparedField::Compiled),
        FieldKind::Auto => match TapeData::new(ir) {
            Ok(t) if tape_pays(&t, ir, traversal, frames) || too_large(ir, traversal) => Ok(PreparedField::Tape(t)),
            _ => Ok(PreparedField::Compiled),
        },
    }
}

/// Why the field asked for cannot render the formula.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FieldError {
    /// Not as a tape.
    #[error(transparent)]
    Tape(#[from] TapeError),
    /// Not as a scene.
    #[error(transparent)]
    Scene(#[from] SceneFieldError),
}

/// Why a formula cannot be rendered as a scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneFieldError {
    /// A scene's enclosures are intervals: it is not bisected in RAA.
    #[error("a scene's nodes are enclosed in interval arithmetic only: it cannot be bisected in raa")]
    NotInterval,
    /// The formula is not built from distance forms alone.
    #[error("not a blobtree: {}", .0.reason)]
    NotBlobtree(crate::scene::NotBlobtree),
    /// The scene cannot be laid out (its evaluation stack).
    #[error("{0}")]
    Layout(crate::scene::SceneError),
}

/// Bounded primitives (a plane is not) from which `Auto` traces a formula
/// of distance forms through the scene field rather than compiled, sphere
/// traced or bisected. Chosen by measurement on lavapipe
/// (docs/benchmarks.md). Sphere traced, warm frames: with fewer
/// (`@creature`, 21 bounded; the generated level-0 scenes) the compiled
/// kernel's frames are several times faster; from 32 on (`@city`, 36; the
/// level-1 scenes) the scene's are mostly faster and at worst a little
/// slower. Bisected: from `@city` on the whole process takes less time
/// through the scene, warm (the scene kernel does not depend on the
/// formula, so Mesa's cache holds it after any scene) and cold for the big
/// CSG families, where the compiled kernel's build grows with the formula
/// and the scene's does not. An edit or a new formula compiles nothing.
pub const SCENE_AUTO_MIN_BOUNDED: usize = 32;

/// `Auto`'s scene: the formula's blobtree when it is one with at least
/// [`SCENE_AUTO_MIN_BOUNDED`] bounded primitives, with the Lipschitz bound
/// its operators need, for sphere tracing or bisection in IA without
/// `--inline` hooks (a scene's enclosures are intervals, and it runs no
/// user WGSL); `None` leaves the choice to [`choose`].
pub fn auto_scene(f: &crate::Formula, params: &[f32], traversal: &Traversal) -> Option<(PreparedField, f64)> {
    let takes = match traversal {
        Traversal::Sphere(_) => true,
        Traversal::Bisect(b) => b.algebra == crate::ir::Domain::Interval && b.modalities.inline.is_none(),
    };
    if !takes {
        return None;
    }
    let (field, lipschitz) = scene(f, params, traversal).ok()?;
    let PreparedField::Scene(data) = &field else { return None };
    let bounded = data.balls.iter().step_by(2).filter(|b| b[3].is_finite()).count();
    (bounded >= SCENE_AUTO_MIN_BOUNDED).then_some((field, lipschitz))
}

/// The formula `f` (with parameter values `params`) as a blobtree scene
/// for `traversal` (sphere tracing, or bisection in IA), and the Lipschitz
/// bound sphere tracing needs for its operators (1, or Zanni's 1.45 with compact smooth operators).
/// `Auto` takes it only from [`SCENE_AUTO_MIN_BOUNDED`] bounded primitives.
pub fn scene(f: &crate::Formula, params: &[f32], traversal: &Traversal) -> Result<(PreparedField, f64), SceneFieldError> {
    let scene = crate::scene::from_formula(f, params).map_err(SceneFieldError::NotBlobtree)?;
    if matches!(traversal, Traversal::Bisect(b) if b.algebra != crate::ir::Domain::Interval) {
        return Err(SceneFieldError::NotInterval);
    }
    let lin = crate::scene::linear::Linear::new(&scene).map_err(SceneFieldError::Layout)?;
    Ok((PreparedField::Scene(lin.field_data()), lin.lipschitz()))
}

//! Which field source renders a formula: generated code (fast frames, a
//! compile that grows steeply with the formula on lavapipe) or the tape
//! (a fixed interpreter compiled once, slower per evaluation). `Auto`
//! decides by a cost model measured on this project's reference machine
//! (README, "Compiled or tape"). A later source (a formula lowered to a
//! blobtree scene) joins as one more [`FieldKind`] value.

pub use crate::field::FieldKind;
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
    pub fn source<'a>(&'a self, ir: &'a Ir) -> FieldSource<'a> {
        match self {
            PreparedField::Compiled => FieldSource::Compiled(ir),
            PreparedField::Tape(t) => FieldSource::Tape(t),
            PreparedField::Scene(d) => FieldSource::Scene(d),
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
/// instruction counted before each use of an input, as when these were
/// measured) from which `Auto` takes the tape, per traversal and algebra. Measured on lavapipe 22.3 (README, "Compiled or
/// tape"), cold first 512² frame of sums of bilinear terms in bisection,
/// compiled / tape: 312 instructions 2.2 / 3.1 s, 612 3.8 / 3.4 s (RAA
/// 3.9 / 5.2 s), 1,212 10.0 / 4.8 s (RAA 9.3 / 6.1 s), 2,512 28.7 / 6.5 s,
/// every tape picture complete. The tape's frames stay 20-40 times slower,
/// so below the line the compiled kernel is sooner or even and faster
/// after; above it the tape is sooner and the compiled kernel's compile
/// grows steeply (3,572: 67 s). Sphere tracing is not re-measured.
///
/// Re-measured after constants became immediates and sums of products
/// multiply-adds (the tape's frames 30-40 % shorter; 512², cold, compiled /
/// tape, two runs each, sums of 70, 90, 130 and 178 terms): IA, size about
/// 710 1.24-1.39 / 1.23-1.44 s, 910 1.59-1.65 / 1.25-1.31 s, 1,310 2.1-2.2 /
/// 1.40-1.43 s; RAA (its compiled kernels build faster: no interval
/// product's zero test), 910 1.12-1.15 / 1.59-1.61 s, 1,310 1.73-1.87 /
/// 1.77-1.84 s, 1,790 2.2-2.5 / 1.9-2.3 s. So the IA line moved down to 700
/// and the RAA line up to 1,500, where the two meet.
///
/// Re-measured on Mesa 25.0 with LLVM's passes off for one frame (the
/// compiled kernels build 2-4 times sooner than when those lines were
/// drawn) over seven families of formulas a program writes (README, "The
/// lines re-measured over seven families"): sums of bilinear terms meet at about
/// 220 terms in IA (130 terms, compiled / tape: 0.66 / 1.38 s; 250: 2.36 /
/// 2.04 s) and 400 in RAA (3.35 / 3.03 s); a product of 100 planes took
/// 1.1 s compiled against 20 s as a tape (its compiled kernel has ray
/// polynomials); a sum of 100 Gaussians 2.3 against 8.9 s, of 50
/// trigonometric products 4.6 against 9.5 s. So the lines moved up, to
/// 2,400 (IA) and 4,000 (RAA), and transcendental functions weigh more
/// ([`HEAVY_WEIGHT`]).
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
/// compiled kernels are the cheapest to build).
pub const CROSSOVER_SPHERE: usize = 4000;

/// A formula bisected as a tape at least this many times longer than it has
/// min, max, clamp, abs and sign instructions (a CSG formula: `@city` 3.4,
/// `@creature` 12) is never taken as a tape by `Auto`, only compiled (unless
/// the compiled kernel would be too large). Its tape is far slower a frame
/// than a sum's of the same length, and leaves pixels unresolved from about
/// 1,700 instructions on, while its compiled kernel builds in seconds.
/// Measured on lavapipe 22.3 (README, "Compiled or tape"), `@city` and
/// copies of its blocks, cold first 512² frame, compiled / tape: 878
/// instructions IA 2.2-2.6 / 12.5-13.6 s, RAA 10.8-18.8 / 16.8-21.0 s; 1,760 IA
/// 4.5 / 40 s (125 unresolved), RAA 40 / 61 s; 3,528 IA 11 / 152 s (18,529
/// unresolved), RAA 125 / 282 s (18,939 unresolved).
pub const CSG_RATIO: usize = 16;

/// The value program's min, max, clamp, abs and sign instructions.
fn minmax_ops(t: &TapeData) -> usize {
    let [start, len, _, _] = t.words[0];
    t.words[start as usize..(start + len) as usize].iter().filter(|w| crate::field::tape::is_minmax(w[0])).count()
}

/// What a division, square root or transcendental function (exp, log,
/// pow, the trigonometric and hyperbolic functions) adds to a formula's
/// size in `auto`'s weighing, beyond its own instruction, in IA (and
/// sphere tracing, not re-measured), where its sums stay chains (see
/// [`heavy_weight`]): the compiled kernel's build then grows much faster
/// with them (cold, 512², IA, compiled: 200 Gaussians 16 s, 200
/// reciprocals 10 s, against 2.4 s for 250 bilinear terms of about the
/// same size), while each also makes the tape's step dearer. Measured by
/// the families of [`crossover`]: with 6, 100 Gaussians (1,820 weighed;
/// 2.3 s, tape 8.9 s) and 100 reciprocals (1,790; 2.6 s, tape 7.2 s) stay
/// compiled, 200 of either take the tape (3,890 and 3,680; compiled 16
/// and 10 s, tape 20 and 11 s). Those families' terms are loops now (a
/// run compares its terms' operands in a fixed order: [`crate::field::reroll`]),
/// each body weighed once, so they stay compiled (200 Gaussians 1.8 s,
/// 200 reciprocals 1.4 s); the weight is for sums of mixed shapes.
pub const HEAVY_WEIGHT: usize = 6;
/// [`HEAVY_WEIGHT`] in RAA, whose affine transcendental functions build
/// slower still: 200 reciprocals compiled 23.8 s against 13.1 s as a tape
/// (4,880 weighed: the tape), 100 Gaussians 4.4 against 10.6 s (2,420:
/// compiled).
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
/// build then grows about linearly (100 trigonometric products, IA: 23 →
/// 9.5 s compiled, sooner than the tape's 15 s; RAA 26.5 → 10.5 s, the
/// tape 19.8 s).
fn heavy_weight(ir: &Ir, plan: &crate::field::compiled::term_loops::Plan, traversal: &Traversal) -> usize {
    if plan.loops.is_empty() && crate::field::compiled::balance::balanced(ir, |_| false).is_some() {
        return 0;
    }
    let weight = match traversal {
        Traversal::Bisect(b) if b.algebra == crate::ir::Domain::Affine => HEAVY_WEIGHT_RAA,
        _ => HEAVY_WEIGHT,
    };
    weight * plan.emitted_weight(ir, |op| usize::from(heavy(op)))
}

/// Whether `Auto` takes the tape for `t`: from [`crossover`] instructions
/// on, but never for a CSG formula bisected ([`CSG_RATIO`]). (Until the op
/// libraries were made branch-free, RAA bisection took the tape the other
/// way round, from 64 min/max instructions on whatever the size: the affine
/// min and max compiled in time that grew steeply with their number,
/// `@city` 145 s at 256².)
///
/// A job of `frames` frames moves the line up by √frames (at most 4×, from
/// 16 frames): the tape's frames are 10-25 times the compiled kernel's, so
/// its head start is spent after a few. Measured (IA, 512², cold, compiled
/// / tape, frames after the first): at size ~910 1.6 / 1.3 s and 31 / 360
/// ms, so a second frame evens them (the line for 2 frames: 990); at ~1,310
/// 2.15 / 1.42 s and 28 / 545 ms, two frames even (an earlier round's 2,501
/// instructions: about seven, 3,572: about fifteen; the line for 16 frames
/// was then 2,800, and is 9,600 since the lines moved up: [`crossover`]).
///
/// A formula whose long runs of same-shaped terms become loops
/// ([`crate::field::reroll`]) is weighed by what its generated code holds (the
/// loop bodies, not every term): the 2,503-operation sum of products is
/// then 81 nodes, shown in 0.9 s cold at 512² where its tape took
/// 3.0-3.2 s (README, "Long runs of same-shaped terms").
fn tape_pays(t: &TapeData, ir: &Ir, traversal: &Traversal, frames: u64) -> bool {
    let csg = matches!(traversal, Traversal::Bisect(_)) && minmax_ops(t) * CSG_RATIO >= t.ops;
    let line = crossover(traversal) as f64 * (frames.clamp(1, 16) as f64).sqrt();
    let plan = crate::field::compiled::term_loops::plan(ir);
    let size = if plan.loops.is_empty() { t.size } else { plan.emitted_nodes(ir) } + heavy_weight(ir, &plan, traversal);
    !csg && size as f64 >= line
}

/// Whether the compiled kernel would be over [`crate::kernel::MAX_SHADER_BYTES`]
/// (the renderer refuses it; the tape has no such limit).
fn too_large(ir: &Ir, traversal: &Traversal) -> bool {
    crate::kernel::assemble(FieldSource::Compiled(ir), traversal).code_bytes() > crate::kernel::MAX_SHADER_BYTES
}

/// The field for formula `f` (parameter values `params`) traced by
/// `traversal`. `Tape` fails when the formula cannot be a tape (level-set
/// CSG, user WGSL, too many registers), `Scene` when it is not a blobtree
/// or not sphere traced ([`scene`]); `Auto` takes the compiled field for
/// those, and otherwise the tape where it pays ([`crossover`], [`CSG_RATIO`]), or when the
/// compiled kernel would be too large to build. `Auto`'s scene is
/// [`auto_scene`], tried first by the caller (it changes the traversal's
/// Lipschitz bound).
pub fn choose(kind: FieldKind, f: &crate::Formula, params: &[f32], traversal: &Traversal) -> Result<PreparedField, FieldError> {
    choose_for(kind, f, params, traversal, 1)
}

/// [`choose`] for a job of `frames` frames (an animation, a benchmark's
/// runs): `Auto` weighs the tape's sooner first frame against its slower
/// later ones ([`tape_pays`]).
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
    /// A scene has no interval enclosures.
    #[error("a scene is sphere traced: it has no interval enclosures to bisect")]
    NotSphere,
    /// The formula is not built from distance forms alone.
    #[error("not a blobtree: {}", .0.reason)]
    NotBlobtree(crate::scene::NotBlobtree),
    /// The scene cannot be laid out (its evaluation stack).
    #[error("{0}")]
    Layout(crate::scene::SceneError),
}

/// Bounded primitives (a plane is not) from which `Auto` traces a formula
/// of distance forms through the scene field rather than compiled.
/// Measured at 512² on lavapipe, GPU ms of a warm frame, compiled against
/// scene (README, "Formulas as scenes"): `@creature` (21 bounded of 22,
/// smooth) 101 against 664, the generated level-0 scenes (10 to 24) 44-180
/// against 250-430; `@city` (36 bounded of 37) 1,243 against 351, the
/// level-1 boxes (64) 205 against 116, the level-1 sphere pairs (96) 83
/// against 113. From 32 on the scene is up to 3.5× faster and at worst
/// 1.4× slower, and an edit or a new formula compiles nothing.
pub const SCENE_AUTO_MIN_BOUNDED: usize = 32;

/// `Auto`'s scene for sphere tracing: the formula's blobtree when it is one
/// with at least [`SCENE_AUTO_MIN_BOUNDED`] bounded primitives, with the
/// Lipschitz bound its operators need; `None` leaves the choice to [`choose`].
pub fn auto_scene(f: &crate::Formula, params: &[f32], traversal: &Traversal) -> Option<(PreparedField, f64)> {
    if !matches!(traversal, Traversal::Sphere(_)) {
        return None;
    }
    let (field, lipschitz) = scene(f, params, traversal).ok()?;
    let PreparedField::Scene(data) = &field else { return None };
    let bounded = data.balls.iter().step_by(2).filter(|b| b[3].is_finite()).count();
    (bounded >= SCENE_AUTO_MIN_BOUNDED).then_some((field, lipschitz))
}

/// The formula `f` (with parameter values `params`) as a blobtree scene
/// for the sphere tracing `traversal`, and the Lipschitz bound its
/// operators need (1, or Zanni's 1.45 with compact smooth operators).
/// `Auto` takes it only from [`SCENE_AUTO_MIN_BOUNDED`] bounded primitives.
pub fn scene(f: &crate::Formula, params: &[f32], traversal: &Traversal) -> Result<(PreparedField, f64), SceneFieldError> {
    let scene = crate::scene::from_formula(f, params).map_err(SceneFieldError::NotBlobtree)?;
    if !matches!(traversal, Traversal::Sphere(_)) {
        return Err(SceneFieldError::NotSphere);
    }
    let lin = crate::scene::linear::Linear::new(&scene).map_err(SceneFieldError::Layout)?;
    Ok((PreparedField::Scene(lin.field_data()), lin.lipschitz()))
}

//! The interpreter's sizes and limits: its register file, how many
//! instructions its loop runs an iteration for a tape of a given length, and
//! the work an invocation may spend under lavapipe's silent loop cap.

/// Most registers of the interpreter (a power of two: operands are masked,
/// so a register index can never leave the array). A kernel has 16, 32 or
/// 64 of them, as its tapes need ([`super::TapeData::features`]).
pub const TAPE_SLOTS: u32 = 64;
/// Programs are padded with no-ops to a multiple of this (of 8 or 16
/// for the longest tapes, [`TAPE_UNROLL_8_FROM`]): the instructions an unrolled
/// interpreter runs per loop iteration ([`super::features::UNROLL_4`]; short tapes
/// run one). lavapipe counts loop iterations against a silent cap of
/// 65,535, so an unrolled loop leaves a long tape 4 times the evaluations;
/// it doubles the compile, so short tapes run one instruction an iteration.
pub const TAPE_UNROLL: u32 = 4;
/// Tapes whose value program has this many instructions run 8 an
/// iteration ([`super::features::UNROLL_8`]), from [`TAPE_UNROLL_16_FROM`] 16,
/// their programs padded to match. A longer step lets a long tape make more
/// evaluations under lavapipe's loop cap, so fewer of its pixels give up
/// unresolved, but each doubling of the step doubles the interpreter's
/// compile. Past 4 an iteration a long tape's cell no longer fits a round
/// of the per-pixel pass, and pixels that give up have spent their budget
/// for nothing; below this line a longer step only costs compile time.
/// Rather than step longer still, a long tape gets more rounds of the
/// per-pixel pass ([`resume_rounds`]): the same work a frame, resumed, from
/// a kernel that compiles far sooner than one of 32 an iteration, with the
/// same hits. Only past [`TAPE_UNROLL_16_FROM`] (sums of inputs: a cell's
/// work no longer fits a round at 8) does it run 16. Both lines were chosen
/// by measurement on lavapipe over sums of bilinear terms and other long
/// generated formulas, counting unresolved pixels and the cold first frame
/// (docs/benchmarks.md).
pub const TAPE_UNROLL_8_FROM: usize = 3_000;
/// See [`TAPE_UNROLL_8_FROM`].
pub const TAPE_UNROLL_16_FROM: usize = 16_000;

/// Rounds of the per-pixel pass after the first that resume the pixels a
/// tape field left at its work limit (each round gives a pixel another
/// [`crate::field::limits::TAPE_WORK_LIMIT`] of interpreter work), for kernels running 1 or 4
/// instructions an iteration (longer steps get more:
/// [`resume_rounds`]). The rounds of pixels already
/// done return at once. Three resolve the superquadric (RAA) and the
/// Chmutov octic (IA), which one does not; seven resolve no more of
/// `@city` than three (its pixels stall on single cells) and cost more.
pub const TAPE_RESUME_ROUNDS: u32 = 3;

/// Rounds of the per-pixel pass after the first, for a kernel running
/// `unroll` instructions an iteration: [`TAPE_RESUME_ROUNDS`], and for the
/// longer steps as many as keep rounds × step at 128, the work a frame of
/// 32 an iteration in 4 rounds gives, which resolves the longest tapes
/// ([`TAPE_UNROLL_8_FROM`]). Rounds of pixels already done return at once.
pub fn resume_rounds(unroll: u32) -> u32 {
    if unroll >= 8 {
        128 / unroll - 1
    } else {
        TAPE_RESUME_ROUNDS
    }
}

/// Tapes whose value and derivative programs have this many instructions
/// together ask for the unrolled interpreter. A cell from the monotonicity
/// depth on runs both (the derivative program and f at its midpoint), and
/// hard pixels take over 100 cells (`@tangle` in IA: 87): below this the
/// work limit leaves them 85 such cells at one instruction an iteration.
pub const TAPE_UNROLL_FROM: usize = 64;

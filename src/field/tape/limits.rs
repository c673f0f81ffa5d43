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
/// their programs padded to match (once 32 from 10,000: below). Measured at
/// 512² in IA (sums of bilinear terms, cold whole process; unresolved
/// pixels in brackets):
///
/// | instructions | 4 an iteration | 8 | 16 | 32 |
/// |---|---|---|---|---|
/// | 3,572 | 5.2 s (0) | | 7.2 s (0) | |
/// | about 4,200 | 5.8 s (45) | 6.3 s (0) | 8.2 s (0) | |
/// | about 7,000 | 9.4 s (663) | 9.7 s (0) | 12.0 s (0) | |
/// | about 10,000 | 17.8 s (6,496) | 15.9 s (253) | 16.3 s (0) | |
/// | 17,862 | 42 s (14,543) | 33.7 s (1,674) | 28.5 s (59) | 31.1 s (0) |
/// | about 28,800 (a 63 KB formula) | | | 96.3 s (1,336) | 84.5 s (4) |
///
/// Past 4 a cell's work no longer fits a round of the per-pixel pass, and
/// pixels that give up have spent their budget for nothing; below, a longer
/// step only costs compile time (`@city`, 914 instructions, 8.4 s cold at 4,
/// 10.2 at 8, 16.5 at 16).
///
/// Those counts had a constant instruction before each use of a constant
/// and no multiply-adds. With both, the same sums have about 0.57 times as
/// many value instructions and the derivative program a larger share, so
/// the lines moved down by a quarter: the 12,503-operation formula (7,148
/// instructions) left 22 pixels unresolved at 8 an iteration and none at
/// 16, in the same time (512², cold: 11.3-11.8 against 11.4-12.8 s), and an
/// 870-term sum (3,488 instructions, `--box=-1.2,1.2`) 7 at 4 and none at 8
/// (8.7-9.3 against 8.7-8.9 s). With multiply-subtracts and immediate
/// factors as well, the 12,503-operation formula is 5,362 instructions and
/// left 9 pixels unresolved at 8 (7.8 s cold) and none at 16 (11.0 s): the
/// 16 and 32 lines moved down again, to 5,000 and 10,000; the 870-term sum
/// (2,617 instructions) resolves every pixel at 4 (7.5 s; 8.0 s at 8).
///
/// Those lines were drawn when a frame had four rounds of the per-pixel
/// pass. Each step doubles the interpreter's compile, and at 32 a kernel of
/// the min/max group took 9 s cold before its first pixel (a 60 KB sum of
/// `abs` terms at 16², 12,900 instructions: 9.2 s at 32, 3.2 s at 16, 1.9 s
/// at 8). A long tape now runs 8 an iteration and gets more rounds instead
/// ([`resume_rounds`]): the same work per frame, resumed. At 128², cold,
/// 32 an iteration and 4 rounds against 8 and 16 rounds: 60 KB sums of
/// Gaussians 14.7 against 13.3 s, of trigonometric products 40.2 against
/// 35.6 s, a min of 1,000 spheres 43.9 against 38.6 s, a random formula
/// 22.1 s (1 pixel unresolved) against 21.9 s (none); every hit the same.
/// Only past 16,000 (sums of inputs: a cell's work no longer fits a round
/// at 8) does it run 16.
pub const TAPE_UNROLL_8_FROM: usize = 3_000;
/// See [`TAPE_UNROLL_8_FROM`].
pub const TAPE_UNROLL_16_FROM: usize = 16_000;

/// Rounds of the per-pixel pass after the first that resume the pixels a
/// tape field left at its work limit (each round gives a pixel another
/// [`TAPE_WORK_LIMIT`] of interpreter work), for kernels running 1 or 4
/// instructions an iteration (longer steps get more:
/// [`resume_rounds`]). The rounds of pixels already
/// done return at once. Measured at 128²: 3 resolve the superquadric (RAA)
/// and chmutov-octic (IA), which 1 does not; 7 resolve no more of `@city`
/// than 3 (its pixels stall on single cells) and cost more.
pub const TAPE_RESUME_ROUNDS: u32 = 3;

/// Rounds of the per-pixel pass after the first, for a kernel running
/// `unroll` instructions an iteration: 3 (measured at 4: 7 resolve no
/// more of `@city` than 3), and for the longer steps as many as keep
/// rounds × step at 128, the work a frame had when the longest tapes ran
/// 32 an iteration in 4 rounds ([`TAPE_UNROLL_8_FROM`]). Rounds of pixels
/// already done return at once.
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

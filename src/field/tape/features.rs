//! Operation groups a tape kernel is compiled with: the interpreter's step
//! holds only the cases of the groups its tapes use, and its register file
//! only as many registers as they need. lavapipe compiles each inlined copy
//! of the interpreter in full, so the groups about halve the compile of a
//! polynomial kernel. Each case is an `if` that lavapipe skips when no lane
//! of the bundle takes it (a step that selected among its cases would run
//! every case for every instruction), and a bundle whose lanes disagree
//! still runs every case any of them takes. The constants, inputs, +, −, ×
//! and squares are always in.

use super::Code;

/// Division.
pub const DIV: u32 = 1;
/// min, max, clamp, abs, sign and their slopes.
pub const MINMAX: u32 = 2;
/// Square roots.
pub const SQRT: u32 = 4;
/// exp. The transcendental functions are a group each (or a pair, where
/// one's slope is the other): a transcendental case costs more to compile
/// than all the arithmetic ones together, and a tape of exponentials alone
/// need not carry logarithms, real powers and hyperbolic functions in its
/// step.
pub const EXP: u32 = 8;
/// log.
pub const LOG: u32 = 1 << 19;
/// Real powers pow(a, b).
pub const POW: u32 = 1 << 20;
/// sinh, cosh, tanh (each one's slope is another).
pub const HYPERBOLIC: u32 = 1 << 21;
/// exp, log, real powers and the hyperbolic functions (the template's
/// `// if EXPLOG` lines).
pub const EXPLOG: u32 = EXP | LOG | POW | HYPERBOLIC;
/// sin and cos (each one's slope is the other).
pub const SINCOS: u32 = 16;
/// tan.
pub const TAN: u32 = 1 << 22;
/// atan and atan2.
pub const ATAN: u32 = 1 << 23;
/// sin, cos, tan, atan, atan2.
pub const TRIG: u32 = SINCOS | TAN | ATAN;
/// floor, mix and their slopes.
pub const MISC: u32 = 32;
/// Integer powers from 8 on (square-and-multiply loops).
pub const POWERS: u32 = 64;
/// User parameters.
pub const PARAMS: u32 = 128;
/// A register file of 32 (set with [`SLOTS_64`] for 64; neither: 16).
pub const SLOTS_32: u32 = 1 << 8;
/// A register file of 64.
pub const SLOTS_64: u32 = 1 << 9;
/// An interpreter loop running 4 instructions an iteration (tapes of
/// [`super::TAPE_UNROLL_FROM`] instructions on, both programs): 4 times the evaluations
/// within lavapipe's loop cap, twice the compile. Not a requirement: a
/// kernel without it runs such a tape, with fewer evaluations.
pub const UNROLL_4: u32 = 1 << 10;
/// Count the interpreter's work per SIMD bundle with subgroup operations
/// (the renderer sets it where the device has them,
/// for bisection). lavapipe's silent loop cap counts a bundle's loop
/// iterations, and a lane's own count cannot see what its neighbours ran,
/// so without subgroups each invocation gets an eighth of the cap
/// ([`super::TAPE_WORK_LIMIT`]); with them the bundle shares one count
/// ([`super::TAPE_BUNDLE_LIMIT`]), about 7 times as many evaluations when
/// its lanes evaluate together. A kernel option, never required by a tape.
pub const BUNDLE_WORK: u32 = 1 << 11;
/// Integer powers 3 to 7 (at most two squarings, written out: no loop,
/// whose masked pass every instruction would pay).
pub const SMALL_POWERS: u32 = 1 << 12;
/// An interpreter loop running 8 instructions an iteration, for long tapes
/// ([`super::TAPE_UNROLL_8_FROM`] value instructions on, padded to a
/// multiple of 8): twice the evaluations of [`UNROLL_4`] within lavapipe's
/// loop cap, where a cell's work (an enclosure and its scalar refinement)
/// no longer fits a round of the per-pixel pass at 4, for about twice the
/// interpreter's compile. A kernel with it runs only tapes padded to 8
/// ([`super::TapeData::padding`]).
pub const UNROLL_8: u32 = 1 << 13;
/// 16 instructions an iteration, for the longest tapes
/// ([`super::TAPE_UNROLL_16_FROM`] on, padded to 16); as [`UNROLL_8`].
pub const UNROLL_16: u32 = 1 << 14;
/// Input instructions (the case that loads input k before each use): the
/// tapes whose inputs are not pinned (see [`PINNED`]).
pub const INPUTS: u32 = 1 << 16;
/// Inputs pinned in registers 0 to 6, written once per run
/// ([`super::TAPE_INPUTS`]): no input instructions.
pub const PINNED: u32 = 1 << 17;
/// Multiply-adds and -subtracts, a·b ± c (b may be an immediate): a
/// product and the sum or difference it joins in one step, a third fewer
/// steps for a sum of products. Their third operand is read on every step,
/// which kernels without them are spared.
pub const MAD: u32 = 1 << 18;
/// Every operation and the largest register file: a kernel that draws
/// every tape.
pub const ALL: u32 = DIV | MINMAX | SQRT | EXPLOG | TRIG | MISC | POWERS | PARAMS | SLOTS_32 | SLOTS_64 | UNROLL_4 | SMALL_POWERS | INPUTS | PINNED | MAD;

/// What a kernel must have to run a tape: its operations and registers.
pub const REQUIRED: u32 = ALL & !UNROLL_4 & !UNROLL_8 & !UNROLL_16;

/// Whether a kernel with `features` counts work per bundle.
pub fn bundle_work(features: u32) -> bool {
    features & BUNDLE_WORK != 0
}

/// Entries a tile's backward pass (`tape_keep`, templates/fields/tape_tiles.wgsl)
/// takes per loop iteration: 4 for the long tapes that run 8 or 16
/// instructions an iteration, whose backward passes over both programs
/// (counting, then writing) would otherwise go past the tile pass's work
/// limit by themselves and leave every tile the whole tape; 1 otherwise,
/// where each written-out entry would lengthen the tile pass's compile
/// for nothing.
pub fn keep_step(features: u32) -> u32 {
    if unroll(features) >= 8 {
        4
    } else {
        1
    }
}

/// Instructions a kernel with `features` runs per loop iteration.
pub fn unroll(features: u32) -> u32 {
    if features & UNROLL_16 != 0 {
        16
    } else if features & UNROLL_8 != 0 {
        8
    } else if features & UNROLL_4 != 0 {
        4
    } else {
        1
    }
}

/// Registers of a kernel with `features`.
pub fn slots(features: u32) -> u32 {
    if features & SLOTS_64 != 0 {
        64
    } else if features & SLOTS_32 != 0 {
        32
    } else {
        16
    }
}

/// The register bits for `registers` registers.
pub fn for_registers(registers: u32) -> u32 {
    match registers {
        0..=16 => 0,
        17..=32 => SLOTS_32,
        _ => SLOTS_32 | SLOTS_64,
    }
}

/// The operation group called `name` in the interpreter's template
/// (`// if MINMAX MISC` keeps a line for kernels with either group); 0 for
/// another name.
pub fn by_name(name: &str) -> u32 {
    match name {
        "DIV" => DIV,
        "MINMAX" => MINMAX,
        "SQRT" => SQRT,
        "EXPLOG" => EXPLOG,
        "EXP" => EXP,
        "LOG" => LOG,
        "POW" => POW,
        "HYPERBOLIC" => HYPERBOLIC,
        "TRIG" => TRIG,
        "SINCOS" => SINCOS,
        "TAN" => TAN,
        "ATAN" => ATAN,
        "MISC" => MISC,
        "POWERS" => POWERS,
        "SMALL_POWERS" => SMALL_POWERS,
        "PARAMS" => PARAMS,
        "INPUTS" => INPUTS,
        "PINNED" => PINNED,
        "MAD" => MAD,
        _ => 0,
    }
}

/// The names of the operation groups in `features`, for messages.
pub fn names(features: u32) -> Vec<&'static str> {
    [(DIV, "division"), (MINMAX, "min/max/abs/sign"), (SQRT, "sqrt"), (EXP, "exp"), (LOG, "log"), (POW, "pow"), (HYPERBOLIC, "sinh/cosh/tanh"), (SINCOS, "sin/cos"), (TAN, "tan"), (ATAN, "atan/atan2"), (MISC, "floor/mix"), (SMALL_POWERS, "powers 3 to 7"), (POWERS, "powers from 8 on"), (PARAMS, "parameters"), (INPUTS, "input instructions"), (PINNED, "inputs in registers"), (MAD, "multiply-add")]
        .into_iter()
        .filter(|(b, _)| features & b != 0)
        .map(|(_, n)| n)
        .collect()
}

/// The operation group of the instruction whose first word is `w0` (0 for
/// a code always compiled in, or none).
pub fn group_of(w0: u32) -> u32 {
    Code::ALL.get((w0 & 0xff) as usize).map_or(0, |c| c.group())
}

impl Code {
    /// The operation group of this code (0: always compiled in).
    pub fn group(self) -> u32 {
        match self {
            Code::Div => DIV,
            Code::Min | Code::Max | Code::Clamp | Code::Abs | Code::Sign | Code::Dmin | Code::Dmax | Code::Dsign => MINMAX,
            Code::Sqrt => SQRT,
            Code::Exp => EXP,
            Code::Log => LOG,
            Code::Pow => POW,
            Code::Sinh | Code::Cosh | Code::Tanh => HYPERBOLIC,
            Code::Sin | Code::Cos => SINCOS,
            Code::Tan => TAN,
            Code::Atan | Code::Atan2 => ATAN,
            Code::Floor | Code::Dfloor | Code::Mix => MISC,
            Code::PowChain => POWERS,
            Code::PowSmall => SMALL_POWERS,
            Code::Param => PARAMS,
            Code::Input => INPUTS,
            Code::Mad | Code::Msub => MAD,
            _ => 0,
        }
    }

    /// The code named `TAPE_<NAME>` in WGSL.
    pub fn wgsl_name(self) -> String {
        format!("TAPE_{}", format!("{self:?}").to_uppercase())
    }

    /// The code whose WGSL constant is `name`.
    pub fn from_wgsl_name(name: &str) -> Option<Code> {
        Code::ALL.into_iter().find(|c| c.wgsl_name() == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::TapeData;

    /// The operation groups a tape needs (where its inputs live aside).
    fn features_of(src: &str) -> u32 {
        TapeData::new(&crate::Formula::compile("<t>", src).expect("formula").ir).expect("tape").features & !(INPUTS | PINNED)
    }

    #[test]
    fn inputs_are_pinned_where_the_register_file_keeps_its_size() {
        let tape = |src: &str| TapeData::new(&crate::Formula::compile("<t>", src).expect("formula").ir).expect("tape");
        // A sum of products: 7 more registers still fit 16.
        let sum: Vec<String> = (1..=40).map(|i| format!("({i}*x - y)*(z + {i})")).collect();
        let t = tape(&sum.join(" + "));
        assert_eq!(t.features & (INPUTS | PINNED), PINNED);
        assert_eq!(slots(t.features), 16);
        // `auto` measures it as if its inputs were loaded (120 loads of x, y,
        // z), its constants too (80, one per term's product and sum), and its
        // 39 multiply-adds (a term's product and the sum it joins) and 40
        // multiply-subtracts (i·x − y) were two instructions each.
        assert_eq!(t.size, t.ops + 120 + 80 + 39 + 40);
        // No input or constant instructions: every input is an operand's
        // register, every constant an immediate of the instruction using it.
        let codes = |c: super::super::Code| t.words.iter().skip(super::super::TAPE_HEADER as usize).filter(|w| w[0] & 0xff == c as u32).count();
        assert_eq!((codes(super::super::Code::Input), codes(super::super::Code::Const)), (0, 0));
        // The Barth decic needs 11 to 16 registers: 7 more would need 32.
        let decic = crate::catalog::lookup("barth-decic").expect("catalog").compile().expect("formula");
        let t = TapeData::new(&decic.ir).expect("tape");
        assert_eq!((t.features & (INPUTS | PINNED), slots(t.features)), (INPUTS, 16));
        // Its size counts a constant instruction for each immediate operand,
        // and a multiply-add as two.
        let [start, len, _, _] = t.words[0];
        let value = &t.words[start as usize..(start + len) as usize];
        let imm = super::super::TAPE_IMM_A | super::super::TAPE_IMM_B;
        let immediates = value.iter().filter(|w| w[0] & imm != 0).count();
        let fused = value.iter().filter(|w| [super::super::Code::Mad as u32, super::super::Code::Msub as u32].contains(&(w[0] & 0xff))).count();
        assert!(immediates > 0 && fused > 0);
        assert_eq!(t.size, t.ops + immediates + fused);
    }

    #[test]
    fn a_tape_needs_the_groups_of_its_operations_and_their_slopes() {
        // The slopes' chain and product rules sum products: multiply-adds.
        assert_eq!(features_of("x^2 + y^2 + z^2 - 1"), MAD);
        assert_eq!(features_of("x^5 - 3*x*y + z"), SMALL_POWERS | MAD);
        // Its slope 9·x^8 is (x²)^4: a small power.
        assert_eq!(features_of("x^9 - 3*x*y + z"), POWERS | SMALL_POWERS | MAD);
        assert_eq!(features_of("x*x*x + y^2 - z"), MAD);
        assert_eq!(features_of("x^2 + y^2 + z^2 - a"), PARAMS | MAD);
        assert_eq!(features_of("sin(x) + z"), SINCOS | MAD);
        assert_eq!(features_of("abs(x) + y - 1"), MINMAX | MAD);
        assert_eq!(features_of("x / (1 + y^2) - z"), DIV);
        assert_eq!(features_of("x - y - z"), 0);
        // The slope of sqrt divides: the derivative program's operations count.
        assert_eq!(features_of("sqrt(x^2 + y^2) - 1 + z"), SQRT | DIV | MAD);
    }

    #[test]
    fn the_register_file_follows_the_tape() {
        assert_eq!(slots(features_of("x + y - z")), 16);
        for src in ["x^2 + y^2 + z^2 - 1", "sin(x*y) + pow(abs(z), 1.5) - atan2(y, x)*min(x, z)/(1 + y^2)"] {
            let t = TapeData::new(&crate::Formula::compile("<t>", src).expect("formula").ir).expect("tape");
            assert!(t.registers <= slots(t.features), "{src}");
        }
        for e in crate::catalog::builtin() {
            let Ok(t) = TapeData::new(&e.compile().expect("catalog formula").ir) else { continue };
            assert!(t.registers <= slots(t.features), "{}", e.name);
        }
        for (r, s) in [(1, 16), (16, 16), (17, 32), (32, 32), (33, 64), (64, 64)] {
            assert_eq!(slots(for_registers(r)), s, "{r} registers");
        }
        assert_eq!(names(ALL).len(), 17);
        // A long tape asks for the unrolled loop, which no kernel requires.
        let long: Vec<String> = (1..=40).map(|i| format!("(x - {i})*(y + {i})")).collect();
        let f = features_of(&long.join(" + "));
        assert_eq!(f & UNROLL_4, UNROLL_4);
        assert_eq!(f & REQUIRED & !(SLOTS_32 | SLOTS_64 | INPUTS | PINNED), MAD);
        assert_eq!(unroll(f), 4);
        assert_eq!(unroll(0), 1);
    }
}

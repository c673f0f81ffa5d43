//! The tape field source: a formula's IR flattened into instructions with
//! register operands, run on the device by one fixed interpreter
//! (`templates/fields/tape.wgsl`). The shader depends on the traversal, the
//! number domain and the operation groups and register file the tape needs
//! ([`features`]), never on the formula itself, so a new formula or an edit
//! is a buffer upload; lavapipe's compile time, which grows steeply with the
//! size of generated code, is paid once per kernel.
//!
//! The tape holds two programs: the value program (f) and the derivative
//! program (f and its derivative along the ray, for bisection's
//! monotonicity test). The derivative is built here, symbolically, from the
//! same rules as the generated `evald_*` functions (`derivative.rs`), so
//! the interpreter needs no second set of rules: it only ever runs `op_*`
//! operations. Registers are allocated by a linear scan over each program
//! (a value's register is reused after its last use), which keeps the
//! interpreter's register file a small fixed array.

use derivative::derivative_program;
use crate::ir::{Func1, Func2, Func3, Ir, NodeId, Op, Var};
use std::collections::HashMap;

mod limits;
pub use limits::*;
use crate::field::limits::{TAPE_BUNDLE_LIMIT, TAPE_TILE_PASS_BUNDLE_LIMIT, TAPE_TILE_PASS_WORK_LIMIT, TAPE_WORK_LIMIT};

/// Words of the header before the first program: `[value start, value len,
/// derivative start, derivative len]`, `[value out, derivative f out,
/// derivative d out, value instructions]`, `[value iterations, derivative
/// iterations, choice slots, 0]`.
pub const TAPE_HEADER: u32 = 3;

/// The interpreter's operation codes (one byte of an instruction's first
/// word). The WGSL constants are generated from this list
/// ([`wgsl_constants`]), so host and shader cannot disagree.
#[allow(missing_docs)] // the names are the operations
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Code {
    Nop = 0, Const, Input, Param, Neg, Add, Sub, Mul, Div, Sqr, PowChain,
    Sqrt, Exp, Log, Sin, Cos, Tan, Atan, Sinh, Cosh, Tanh, Abs, Sign, Floor,
    Pow, Atan2, Min, Max, Clamp, Mix, Dmin, Dmax, Dsign, Dfloor, Whole, PowSmall, Mad, Msub,
}

impl Code {
    const ALL: [Code; 38] = [
        Code::Nop, Code::Const, Code::Input, Code::Param, Code::Neg, Code::Add, Code::Sub, Code::Mul, Code::Div, Code::Sqr, Code::PowChain,
        Code::Sqrt, Code::Exp, Code::Log, Code::Sin, Code::Cos, Code::Tan, Code::Atan, Code::Sinh, Code::Cosh, Code::Tanh, Code::Abs,
        Code::Sign, Code::Floor, Code::Pow, Code::Atan2, Code::Min, Code::Max, Code::Clamp, Code::Mix, Code::Dmin, Code::Dmax,
        Code::Dsign, Code::Dfloor, Code::Whole, Code::PowSmall, Code::Mad, Code::Msub,
    ];
    fn of1(f: Func1) -> Code {
        match f {
            Func1::Sqrt => Code::Sqrt, Func1::Exp => Code::Exp, Func1::Log => Code::Log, Func1::Sin => Code::Sin,
            Func1::Cos => Code::Cos, Func1::Tan => Code::Tan, Func1::Atan => Code::Atan, Func1::Sinh => Code::Sinh,
            Func1::Cosh => Code::Cosh, Func1::Tanh => Code::Tanh, Func1::Abs => Code::Abs, Func1::Sign => Code::Sign,
            Func1::Floor => Code::Floor,
        }
    }
    fn of2(f: Func2) -> Code {
        match f {
            Func2::Pow => Code::Pow, Func2::Atan2 => Code::Atan2, Func2::Min => Code::Min, Func2::Max => Code::Max,
            Func2::PowN => unreachable!("pown is never in an IR, only in the compiled field's generated code"),
        }
    }
}

pub mod features;
mod choices;
mod remat;
mod encode;
use encode::{arity, encode, Program};
mod derivative;
pub mod source;
pub mod wgsl;
pub use choices::{is_minmax, TAPE_CHOICE_SLOTS, TAPE_NO_SLOT};
use choices::choice_slots;

/// Flag bit of an instruction's first word: the result may be empty.
pub const TAPE_RESTRICTS: u32 = 1 << 8;
/// Flag bits of an instruction's first word: its first (second) operand is
/// the constant in its last two words, not a register. A constant re-emitted
/// before each use was a whole interpreter step, over a quarter of the steps
/// of a sum of products (fidget's tapes have register-immediate opcodes
/// for the same reason).
pub const TAPE_IMM_A: u32 = 1 << 9;
#[allow(missing_docs)] // see TAPE_IMM_A
pub const TAPE_IMM_B: u32 = 1 << 10;
/// Flag bit of a constant's (or an immediate's) first word: the f32 nearest
/// to it is the enclosure's upper end (otherwise its lower end).
pub const TAPE_NEAR_HI: u32 = 1 << 11;
/// Flag bit of an instruction's first word: it reads no second operand (the
/// interpreter then loads none: a register read is a per-lane load).
pub const TAPE_UNARY: u32 = 1 << 12;

/// One tape node before register allocation: operands are node indices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Node {
    pub code: Code,
    pub args: [u32; 4],
    /// A constant's value, a parameter's or input's index, a power.
    pub imm: f64,
}

/// Index of an interpreter input (`Code::Input`): x, y, z, t, then the ray
/// direction dx, dy, dz of the derivative program.
pub(crate) const INPUT_DX: u32 = 4;
/// A tape's inputs may live in the first registers, input k in register k,
/// written once per run ([`features::PINNED`]): an instruction reads them as
/// operands, where an input instruction before each use costs a whole
/// interpreter step (its instruction fetch and register traffic), a third of the
/// steps of a sum of products. They hold 7 registers for the whole run, so a
/// tape pins them only where that keeps its register file's size
/// ([`features::INPUTS`] otherwise).
pub const TAPE_INPUTS: u32 = 7;

/// Hash-consed tape nodes in topological order.
#[derive(Default)]
pub(crate) struct Builder {
    pub nodes: Vec<Node>,
    seen: HashMap<(u8, [u32; 4], u64), u32>,
    /// Nodes of the formula's sqrt, log and pow: an empty result of one
    /// makes the whole function empty (they are strict). A log the
    /// derivative rules add is not among them, as in the generated code.
    strict: std::collections::HashSet<u32>,
    /// A scheduling hint: a derivative node's value node, placed right after
    /// it so the values its derivative needs die there (without it, a sum's
    /// every term would wait in a register for the derivative pass).
    pub partner: HashMap<u32, u32>,
    /// The choice slot of each min and max node, and of each derivative of
    /// one (`Dmin`/`Dmax` share their value's slot): where the tile pass
    /// notes which operand the node can take over a tile ([`choice_slots`]).
    slots: HashMap<u32, u32>,
}

impl Builder {
    pub fn push(&mut self, code: Code, args: [u32; 4], imm: f64) -> u32 {
        let key = (code as u8, args, imm.to_bits());
        if let Some(&n) = self.seen.get(&key) {
            return n;
        }
        self.nodes.push(Node { code, args, imm });
        let n = self.nodes.len() as u32 - 1;
        self.seen.insert(key, n);
        n
    }
    pub fn un(&mut self, code: Code, a: u32) -> u32 {
        self.push(code, [a, 0, 0, 0], 0.0)
    }
    /// A sum with a product is a multiply-add, a difference whose first
    /// operand is a product a multiply-subtract ([`Builder::fuse`]); the
    /// product node stays for other users.
    pub fn bin(&mut self, code: Code, a: u32, b: u32) -> u32 {
        let fused = match code {
            Code::Add => self
                .fuse(Code::Mad, a, b)
                .or_else(|| self.fuse(Code::Mad, b, a))
                .or_else(|| self.reassociate(a, b))
                .or_else(|| self.reassociate(b, a)),
            Code::Sub => self.fuse(Code::Msub, a, b),
            _ => None,
        };
        fused.unwrap_or_else(|| self.push(code, [a, b, 0, 0], 0.0))
    }
    /// `code` (`Mad`, `Msub`) of the product `m` and `c`, where `m` is a
    /// product with at most one constant factor, which goes second (an
    /// immediate there, the only place a multiply-add takes one), and `c`
    /// is not a constant besides it.
    fn fuse(&mut self, code: Code, m: u32, c: u32) -> Option<u32> {
        let node = self.nodes[m as usize];
        let konst = |i: u32| self.nodes[i as usize].code == Code::Const;
        let [p, q] = if konst(node.args[0]) { [node.args[1], node.args[0]] } else { [node.args[0], node.args[1]] };
        if node.code != Code::Mul || konst(p) || (konst(q) && konst(c)) {
            return None;
        }
        Some(self.push(code, [p, q, c, 0], 0.0))
    }
    /// `c + m` where `m` is a multiply-add `p·q + e` whose addend `e` is a
    /// product: `p·q + (c + e)`, two multiply-adds where the sum of `c` and
    /// a multiply-add took three instructions. The derivative program's
    /// product rule sums `a'·b + a·b'` into a running sum this way (a
    /// term of a sum of products: 7 instructions to 6). Any association
    /// of the sum's enclosures encloses it, as the written order does.
    fn reassociate(&mut self, c: u32, m: u32) -> Option<u32> {
        let node = self.nodes[m as usize];
        if node.code != Code::Mad || self.nodes[node.args[2] as usize].code != Code::Mul {
            return None;
        }
        let inner = self.fuse(Code::Mad, node.args[2], c)?;
        Some(self.push(Code::Mad, [node.args[0], node.args[1], inner, 0], 0.0))
    }
    pub fn konst(&mut self, c: f64) -> u32 {
        self.push(Code::Const, [0; 4], c)
    }
    pub fn input(&mut self, i: u32) -> u32 {
        self.push(Code::Input, [0; 4], f64::from(i))
    }
    /// a^n for n ≥ 2 exactly as the generated code writes it: a square,
    /// even powers as powers of the square, odd ones by square-and-multiply.
    pub fn powi(&mut self, a: u32, n: u32) -> u32 {
        match n {
            2 => self.un(Code::Sqr, a),
            _ if n % 2 == 0 => {
                let q = self.un(Code::Sqr, a);
                if n == 4 { self.un(Code::Sqr, q) } else { self.chain(q, n / 2) }
            }
            _ => self.chain(a, n),
        }
    }
    /// a^n (n ≥ 3) by square-and-multiply: written out for n < 8 (at most
    /// two squarings, `PowSmall`), a loop beyond (`PowChain`). A kernel
    /// with the loop pays a masked pass of it for every instruction, which
    /// counts against lavapipe's loop cap; the cubes of smooth blends need
    /// none.
    pub fn chain(&mut self, a: u32, n: u32) -> u32 {
        self.push(if n < 8 { Code::PowSmall } else { Code::PowChain }, [a, 0, 0, 0], f64::from(n))
    }
}

/// Why a formula cannot become a tape. The command line names the flag.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TapeError {
    /// `--inline` user functions are WGSL, not tape operations.
    #[error("a tape field cannot call user WGSL functions ({0})")]
    UserFunction(String),
    /// `--inline` hooks (cell rejection, hit test, shading) are compiled in.
    #[error("a tape field cannot run user WGSL hooks")]
    Hooks,
    /// Several surfaces or level-set conditions.
    #[error("a tape field draws one surface: level-set CSG (several surfaces or `where` conditions) needs the compiled field")]
    Csg,
    /// More simultaneously live values than the interpreter has registers.
    #[error("the formula needs {0} registers at once, over the tape interpreter's {TAPE_SLOTS}")]
    Registers(u32),
}

/// A formula as the tape interpreter's buffer (`templates/fields/tape.wgsl`):
/// the header, then the value and derivative programs, one `vec4<u32>` per
/// instruction: `[code | flags | out << 16, a | b << 16, c | d << 16,
/// immediate]`; a constant carries its enclosing f32 interval in the last
/// two words (the nearest f32 is one of its ends, `TAPE_NEAR_HI`), and so
/// does an arithmetic instruction with a constant operand (`TAPE_IMM_A`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TapeData {
    /// Header and instructions.
    pub words: Vec<[u32; 4]>,
    /// Operations of the value program (without padding).
    pub ops: usize,
    /// Operations of the value program with an input instruction before
    /// each use of an input, pinned or not, a constant instruction before
    /// each use of a constant, immediate or not, and a multiply-add counted
    /// as a product and a sum: the size `auto`'s crossover lines are drawn
    /// in (`crate::choice::crossover`).
    pub size: usize,
    /// Most registers either program uses.
    pub registers: u32,
    /// The operation groups and register file the interpreter needs
    /// (`features`): part of the kernel, so a kernel built for one set
    /// draws every tape whose set is within it. Widen it (up to
    /// `features::ALL`) to build a kernel for tapes still to come.
    pub features: u32,
}

impl TapeData {
    /// The tape as the texture the interpreter reads (instruction i is
    /// texel i): a texel fetch is a vector gather on lavapipe, a storage
    /// load at a per-lane address runs lane by lane.
    pub fn texels(&self) -> super::Texels<[u32; 4]> {
        super::Texels::from_rows(None, &self.words)
    }

    /// Flattens `ir` (one surface, no user functions).
    pub fn new(ir: &Ir) -> Result<TapeData, TapeError> {
        Self::padded(ir, 1)
    }

    /// [`TapeData::new`] with both programs padded to a multiple of at
    /// least `step` instructions, for an interpreter that runs `step` an
    /// iteration whatever the tape (a scene's formula leaves).
    pub fn padded(ir: &Ir, step: u32) -> Result<TapeData, TapeError> {
        if let Some((name, _)) = ir.externs.first() {
            return Err(TapeError::UserFunction(name.clone()));
        }
        if ir.is_csg() {
            return Err(TapeError::Csg);
        }
        let mut b = Builder::default();
        let values = flatten(ir, &mut b);
        let f = values[ir.root as usize];
        let df = derivative_program(ir, &values, &mut b);
        let slots = choice_slots(&mut b);
        let programs = |b: &mut Builder, pinned: bool| -> Result<(Program, Program), TapeError> {
            let value = encode(b, &[f], pinned)?;
            // A derivative program over the register file gives up the
            // monotonicity proof, never the render: its slope is the whole line.
            let deriv = match encode(b, &[df, f], pinned) {
                Err(TapeError::Registers(_)) => {
                    let whole = b.push(Code::Whole, [0; 4], 0.0);
                    encode(b, &[whole, f], pinned)?
                }
                other => other?,
            };
            Ok((value, deriv))
        };
        let file = |(v, d): &(Program, Program)| features::for_registers(v.registers.max(d.registers));
        let loaded = programs(&mut b, false)?;
        // In the unit of the crossover lines: a constant instruction per
        // use, a multiply-add as its product and its sum.
        let size = loaded.0.ops + loaded.0.immediates + loaded.0.fused;
        // Pinned inputs where they keep the register file's size (and fit).
        let (mut value, mut deriv, inputs) = match programs(&mut b, true) {
            Ok(pinned) if file(&pinned) == file(&loaded) => (pinned.0, pinned.1, features::PINNED),
            _ => (loaded.0, loaded.1, features::INPUTS),
        };
        let unroll = if value.ops >= TAPE_UNROLL_16_FROM {
            features::UNROLL_16
        } else if value.ops >= TAPE_UNROLL_8_FROM {
            features::UNROLL_8
        } else if value.ops + deriv.ops >= TAPE_UNROLL_FROM {
            features::UNROLL_4
        } else {
            0
        };
        let step = features::unroll(unroll).max(step);
        value.pad(step);
        deriv.pad(step);
        let mut words = vec![[0u32; 4]; TAPE_HEADER as usize];
        let start = TAPE_HEADER;
        let dstart = start + value.words.len() as u32;
        words[0] = [start, value.words.len() as u32, dstart, deriv.words.len() as u32];
        words[1] = [value.outputs[0], deriv.outputs[1], deriv.outputs[0], value.ops as u32];
        words[2] = [value.iterations, deriv.iterations, slots, 0];
        words.extend(value.words);
        words.extend(deriv.words);
        let registers = value.registers.max(deriv.registers);
        let ops = words.iter().skip(TAPE_HEADER as usize).fold(0, |acc, w| acc | features::group_of(w[0]));
        Ok(TapeData { words, ops: value.ops, size, registers, features: ops | inputs | unroll | features::for_registers(registers) })
    }

    /// The largest interpreter step (1, 4, 8 or 16 instructions an iteration)
    /// both programs are padded for: a kernel that runs more an iteration
    /// would read past a program's end into the next.
    pub fn padding(&self) -> u32 {
        let [_, value, _, deriv] = self.words[0];
        let lengths = value | deriv;
        [32, 16, 8, TAPE_UNROLL].into_iter().find(|&n| lengths % n == 0).unwrap_or(1)
    }

    /// Loop iterations of one value evaluation by an interpreter running
    /// `unroll` instructions an iteration.
    pub fn value_iterations(&self, unroll: u32) -> u32 {
        self.words[2][0] + self.words[0][1] / unroll
    }
}

/// The tape node of every live IR node (`u32::MAX` for dead ones).
fn flatten(ir: &Ir, b: &mut Builder) -> Vec<u32> {
    let mut v = vec![u32::MAX; ir.nodes.len()];
    for id in ir.live() {
        let m = |n: NodeId| v[n as usize];
        v[id as usize] = match ir.nodes[id as usize] {
            Op::Const(c) => b.konst(c),
            Op::Var(var) => b.input(match var {
                Var::X => 0,
                Var::Y => 1,
                Var::Z => 2,
                Var::T => 3,
            }),
            Op::Param(i) => b.push(Code::Param, [0; 4], f64::from(i)),
            Op::Neg(a) => b.un(Code::Neg, m(a)),
            Op::Add(a, c) => b.bin(Code::Add, m(a), m(c)),
            Op::Sub(a, c) => b.bin(Code::Sub, m(a), m(c)),
            Op::Mul(a, c) => b.bin(Code::Mul, m(a), m(c)),
            Op::Div(a, c) => b.bin(Code::Div, m(a), m(c)),
            Op::PowI(a, n) => b.powi(m(a), n),
            Op::Call1(f, a) => b.un(Code::of1(f), m(a)),
            Op::Call2(f, a, c) => b.bin(Code::of2(f), m(a), m(c)),
            Op::Call3(f, a, c, e) => {
                let code = if f == Func3::Clamp { Code::Clamp } else { Code::Mix };
                b.push(code, [m(a), m(c), m(e), 0], 0.0)
            }
            Op::User(..) => unreachable!("user functions are refused before flattening"),
        };
        if ir.nodes[id as usize].restricts_domain() {
            b.strict.insert(v[id as usize]);
        }
    }
    v
}

/// The operation codes and the interpreter's limits as WGSL constants, for
/// a kernel with `features`.
pub fn wgsl_constants(features: u32) -> String {
    let mut s = String::new();
    for c in Code::ALL {
        s.push_str(&format!("const {}: u32 = {}u;\n", c.wgsl_name(), c as u8));
    }
    let slots = features::slots(features);
    for (name, v) in [
        ("TAPE_SLOTS", slots),
        ("TAPE_SLOT_MASK", slots - 1),
        ("TAPE_UNROLL", features::unroll(features)),
        ("TAPE_KEEP_STEP", features::keep_step(features)),
        ("TAPE_WORK_LIMIT", TAPE_WORK_LIMIT),
        ("TAPE_BUNDLE_LIMIT", TAPE_BUNDLE_LIMIT),
        ("TAPE_TILE_PASS_WORK_LIMIT", TAPE_TILE_PASS_WORK_LIMIT),
        ("TAPE_TILE_PASS_BUNDLE_LIMIT", TAPE_TILE_PASS_BUNDLE_LIMIT),
        ("TAPE_RESTRICTS", TAPE_RESTRICTS),
        ("TAPE_IMM_A", TAPE_IMM_A),
        ("TAPE_IMM_B", TAPE_IMM_B),
        ("TAPE_NEAR_HI", TAPE_NEAR_HI),
        ("TAPE_UNARY", TAPE_UNARY),
        ("TAPE_CHOICE_SLOTS", TAPE_CHOICE_SLOTS),
        // A kernel with the power-chain case runs a pass of its loop for
        // every instruction (lavapipe enters a loop once even when no lane
        // takes its case): those passes count against the loop cap too.
        ("TAPE_POW_PASSES", u32::from(features & features::POWERS != 0)),
        ("TAPE_DONE", 0),
        ("TAPE_EMPTY", 1),
        ("TAPE_EXHAUSTED", 2),
    ] {
        s.push_str(&format!("const {name}: u32 = {v}u;\n"));
    }
    // Operand counts, from the same table the register allocator uses.
    s.push_str("fn tape_arity(code: u32) -> u32 {\n");
    for n in 0..4 {
        let codes: Vec<String> = Code::ALL.iter().filter(|&&c| arity(c) == n).map(|c| format!("code == {}", c.wgsl_name())).collect();
        s.push_str(&format!("    if ({}) {{ return {n}u; }}\n", codes.join(" || ")));
    }
    s.push_str("    return 4u;\n}\n");
    s
}

#[cfg(test)]
mod tests;

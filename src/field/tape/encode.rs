//! A flattened formula encoded as the interpreter's programs: operations
//! scheduled so that few values are alive at once, registers allocated
//! (shared subexpressions rematerialised when they would not fit) and each
//! instruction packed into one word quadruple.

use super::*;

/// One program with registers.
pub(super) struct Program {
    pub(super) words: Vec<[u32; 4]>,
    pub(super) outputs: Vec<u32>,
    pub(super) ops: usize,
    /// Constant operands taken as immediates.
    pub(super) immediates: usize,
    /// Multiply-adds and multiply-subtracts.
    pub(super) fused: usize,
    pub(super) registers: u32,
    pub(super) iterations: u32,
}

impl Program {
    /// Pads the program with no-ops to a multiple of `n` instructions.
    pub(super) fn pad(&mut self, n: u32) {
        while self.words.len() % n as usize != 0 {
            self.words.push([Code::Nop as u32, 0, 0, 0]);
        }
    }
}

/// Sethi–Ullman numbers of the nodes read as a tree: the registers a
/// subtree needs when its most demanding operand goes first. Visiting
/// operands in decreasing need keeps fewer values waiting.
fn register_need(nodes: &[Node]) -> Vec<u32> {
    let mut need = vec![1u32; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        let mut k: Vec<u32> = n.args[..arity(n.code)].iter().map(|&a| need[a as usize]).collect();
        k.sort_unstable_by(|a, b| b.cmp(a));
        need[i] = k.iter().enumerate().map(|(j, &x)| x.saturating_add(j as u32)).max().unwrap_or(1).max(1);
    }
    need
}

/// Depth-first post-order of the nodes `outputs` reach; right after a node
/// with a partner, the partner's subtree (iterative: a formula's chains can
/// be thousands deep).
fn schedule(nodes: &[Node], outputs: &[u32], partner: &HashMap<u32, u32>) -> Vec<usize> {
    let mut done = vec![false; nodes.len()];
    // On the stack: a partner there is left to its own frame.
    let mut open = vec![false; nodes.len()];
    let mut order = Vec::new();
    let need = register_need(nodes);
    // A partner the outputs do not need (a product a multiply-add took
    // over) is not computed: its register would never be freed.
    let mut reach = vec![false; nodes.len()];
    let mut todo: Vec<u32> = outputs.to_vec();
    while let Some(n) = todo.pop() {
        if !std::mem::replace(&mut reach[n as usize], true) {
            todo.extend_from_slice(&nodes[n as usize].args[..arity(nodes[n as usize].code)]);
        }
    }
    let by_need = |n: usize| {
        let mut args: Vec<u32> = nodes[n].args[..arity(nodes[n].code)].to_vec();
        args.sort_by_key(|&a| std::cmp::Reverse(need[a as usize]));
        args
    };
    for &o in outputs {
        let mut stack = vec![(o as usize, 0usize)];
        open[o as usize] = true;
        while let Some(&mut (n, ref mut next)) = stack.last_mut() {
            let args = by_need(n);
            if let Some(&a) = args.get(*next) {
                *next += 1;
                if !done[a as usize] {
                    open[a as usize] = true;
                    stack.push((a as usize, 0));
                }
                continue;
            }
            stack.pop();
            if !done[n] {
                done[n] = true;
                order.push(n);
                if let Some(&p) = partner.get(&(n as u32)) {
                    if reach[p as usize] && !done[p as usize] && !open[p as usize] {
                        open[p as usize] = true;
                        stack.push((p as usize, 0));
                    }
                }
            }
        }
    }
    order
}

/// The operands an operation may take as the constant in its instruction's
/// last two words (otherwise unused): either of a binary arithmetic
/// operation's, a multiply-add's or -subtract's second factor (its addend's
/// register then sits in the factor's place).
pub(super) fn immediate_operands(code: Code) -> &'static [usize] {
    match code {
        Code::Add | Code::Sub | Code::Mul | Code::Div | Code::Pow | Code::Atan2 => &[0, 1],
        Code::Mad | Code::Msub => &[1],
        _ => &[],
    }
}

/// Operand count of an operation.
pub(super) fn arity(code: Code) -> usize {
    match code {
        Code::Nop | Code::Const | Code::Input | Code::Param | Code::Whole => 0,
        Code::Add | Code::Sub | Code::Mul | Code::Div | Code::Pow | Code::Atan2 | Code::Min | Code::Max | Code::Dsign | Code::Dfloor => 2,
        Code::Clamp | Code::Mix | Code::Mad | Code::Msub => 3,
        Code::Dmin | Code::Dmax => 4,
        _ => 1,
    }
}

/// The nodes `outputs` need, in depth-first post-order (each operand's
/// subtree right before its user, so a long sum holds a few values at a time
/// rather than every leaf the front end created first), with registers from
/// a linear scan: an operand's register is freed at its last use, before the
/// result is given one (the interpreter reads operands before it writes).
///
/// When the shared values need more registers than the interpreter has, the
/// program is rematerialised ([`remat`]): the smallest tree size whose
/// copies make it fit, doubling from 2 up to [`REMAT_MAX_TREE`] nodes.
pub(super) fn encode(b: &Builder, outputs: &[u32], pinned: bool) -> Result<Program, TapeError> {
    let first = encode_shared(b, outputs, pinned);
    if !matches!(first, Err(TapeError::Registers(_))) {
        return first;
    }
    let mut k = 2;
    while k <= REMAT_MAX_TREE {
        // A larger k copies more: past the growth limit, so does every next one.
        let Some((b, outputs)) = remat::rematerialize(b, outputs, k, REMAT_MAX_GROWTH) else { break };
        if let Ok(p) = encode_shared(&b, &outputs, pinned) {
            return Ok(p);
        }
        k *= 2;
    }
    first
}

/// Largest expression tree [`encode`] copies at each use.
const REMAT_MAX_TREE: u64 = 256;
/// Most times as many nodes as the shared program a rematerialised one has.
const REMAT_MAX_GROWTH: usize = 8;

/// [`encode`] with every shared value in one register.
fn encode_shared(b: &Builder, outputs: &[u32], pinned: bool) -> Result<Program, TapeError> {
    let regs = Registers { free: vec![], count: if pinned { TAPE_INPUTS } else { 0 } };
    let mut e = Emitter { b, outputs, pinned, last: vec![], regs, reg: vec![0; b.nodes.len()], words: vec![], immediates: 0, fused: 0, iterations: 0 };
    // Constants, parameters and (not `pinned`) inputs are emitted again
    // right before each use (one instruction) rather than held in a
    // register from their first use to their last; `pinned` inputs are read
    // from their own registers (TAPE_INPUTS).
    let order: Vec<usize> = schedule(&b.nodes, outputs, &b.partner).into_iter().filter(|&i| !e.leaf(i)).collect();
    e.last = last_uses(&b.nodes, &order, outputs);
    e.words.reserve(order.len());
    for (k, &i) in order.iter().enumerate() {
        e.emit(k, i);
    }
    if e.regs.count > TAPE_SLOTS {
        return Err(TapeError::Registers(e.regs.count));
    }
    let ops = e.words.len();
    let outputs = outputs.iter().map(|&o| e.reg[o as usize]).collect();
    let mut program = Program { words: e.words, outputs, ops, immediates: e.immediates, fused: e.fused, registers: e.regs.count, iterations: e.iterations };
    program.pad(TAPE_UNROLL);
    Ok(program)
}

/// The position in `order` of each node's last use as an operand (the
/// outputs': never).
fn last_uses(nodes: &[Node], order: &[usize], outputs: &[u32]) -> Vec<usize> {
    let mut last = vec![0usize; nodes.len()];
    for (k, &i) in order.iter().enumerate() {
        for &a in &nodes[i].args[..arity(nodes[i].code)] {
            last[a as usize] = k;
        }
    }
    for &o in outputs {
        last[o as usize] = usize::MAX;
    }
    last
}

/// The state of [`encode_shared`]: registers by a linear scan and the
/// instructions written so far, with the program's counts.
struct Emitter<'b> {
    b: &'b Builder,
    outputs: &'b [u32],
    pinned: bool,
    /// Each node's last use ([`last_uses`]).
    last: Vec<usize>,
    regs: Registers,
    /// Each node's register.
    reg: Vec<u32>,
    words: Vec<[u32; 4]>,
    immediates: usize,
    fused: usize,
    iterations: u32,
}

impl Emitter<'_> {
    /// A constant, parameter or input that is not an output: emitted again
    /// before each use.
    fn leaf(&self, i: usize) -> bool {
        arity(self.b.nodes[i].code) == 0 && !self.outputs.contains(&(i as u32))
    }

    /// An input read from its own register.
    fn pin(&self, i: usize) -> bool {
        self.pinned && self.b.nodes[i].code == Code::Input
    }

    /// Node `i`, the `k`-th of the order: its leaf operands loaded, the
    /// registers of operands used for the last time freed, then its own
    /// register and instruction.
    fn emit(&mut self, k: usize, i: usize) {
        let n = self.b.nodes[i];
        if self.pin(i) {
            // An output that is an input (f = x) is its register.
            self.reg[i] = n.imm as u32;
            return;
        }
        let args = &n.args[..arity(n.code)];
        // One constant operand is read from the instruction.
        let imm = immediate_operands(n.code).iter().map(|&j| args[j]).find(|&a| self.b.nodes[a as usize].code == Code::Const && self.leaf(a as usize));
        self.immediates += usize::from(imm.is_some());
        self.fused += usize::from(matches!(n.code, Code::Mad | Code::Msub));
        self.load_operands(k, args, imm);
        self.reg[i] = self.regs.take();
        let w = self.instruction(i, args, imm);
        self.words.push(w);
        if n.code == Code::PowChain {
            self.iterations += 31 - (n.imm as u32).leading_zeros();
        }
    }

    /// Gives the operands of the `k`-th instruction (but the immediate
    /// `imm`) their registers, each leaf loaded by an instruction of its
    /// own, and frees those read for the last time.
    fn load_operands(&mut self, k: usize, args: &[u32], imm: Option<u32>) {
        let mut dying = vec![];
        for (j, &a) in args.iter().enumerate() {
            if args[..j].contains(&a) || imm == Some(a) {
                continue;
            }
            let a = a as usize;
            if self.pin(a) {
                self.reg[a] = self.b.nodes[a].imm as u32;
            } else if self.leaf(a) {
                self.reg[a] = self.regs.take();
                self.words.push(word(self.b, a, self.reg[a], [0; 4]));
                dying.push(self.reg[a]);
            } else if self.last[a] == k {
                dying.push(self.reg[a]);
            }
        }
        self.regs.free.extend(dying);
    }

    /// Node `i`'s instruction on operands `args`, the constant `imm` (if
    /// any) in its last two words.
    fn instruction(&self, i: usize, args: &[u32], imm: Option<u32>) -> [u32; 4] {
        let mut ra = [0u32; 4];
        let mut flags = 0;
        for (j, &a) in args.iter().enumerate() {
            if imm == Some(a) {
                flags |= if j == 0 { TAPE_IMM_A } else { TAPE_IMM_B };
            } else {
                ra[j] = self.reg[a as usize];
            }
        }
        let mut w = word(self.b, i, self.reg[i], ra);
        w[0] |= flags;
        if let Some(c) = imm {
            if args.len() == 3 {
                // A multiply-add's addend moves to the immediate's place.
                w[1] = ra[0] | ra[2] << 16;
            }
            let k = word(self.b, c as usize, 0, [0; 4]);
            w[0] |= k[0] & TAPE_NEAR_HI;
            w[2] = k[2];
            w[3] = k[3];
        }
        w
    }
}

/// The register file during allocation: freed registers are reused first.
struct Registers {
    free: Vec<u32>,
    count: u32,
}

impl Registers {
    fn take(&mut self) -> u32 {
        self.free.pop().unwrap_or_else(|| {
            self.count += 1;
            self.count - 1
        })
    }
}

/// The instruction of node `i` writing register `r` with operand registers `ra`.
fn word(b: &Builder, i: usize, r: u32, ra: [u32; 4]) -> [u32; 4] {
    let n = b.nodes[i];
    let strict = if b.strict.contains(&(i as u32)) { TAPE_RESTRICTS } else { 0 };
    let flags = strict | if arity(n.code) < 2 { TAPE_UNARY } else { 0 };
    let head = n.code as u32 | flags | r << 16;
    match n.code {
        Code::Const => {
            let (near, lo, hi) = crate::codegen::f32_enclosure(n.imm);
            let near_hi = if near.to_bits() == hi.to_bits() && lo.to_bits() != hi.to_bits() { TAPE_NEAR_HI } else { 0 };
            [head | near_hi, 0, lo.to_bits(), hi.to_bits()]
        }
        Code::Min | Code::Max | Code::Dmin | Code::Dmax | Code::Sqrt | Code::Log => {
            let slot = b.slots.get(&(i as u32)).copied().unwrap_or(TAPE_NO_SLOT);
            [head, ra[0] | ra[1] << 16, ra[2] | ra[3] << 16, slot]
        }
        _ => [head, ra[0] | ra[1] << 16, ra[2] | ra[3] << 16, n.imm as u32],
    }
}

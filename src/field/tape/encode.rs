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
    let nodes = &b.nodes;
    let leaf = |i: usize| arity(nodes[i].code) == 0 && !outputs.contains(&(i as u32));
    // Constants, parameters and (not `pinned`) inputs are emitted again
    // right before each use (one instruction) rather than held in a
    // register from their first use to their last; `pinned` inputs are read
    // from their own registers (TAPE_INPUTS).
    let order: Vec<usize> = schedule(nodes, outputs, &b.partner).into_iter().filter(|&i| !leaf(i)).collect();
    let mut last = vec![0usize; nodes.len()];
    for (k, &i) in order.iter().enumerate() {
        for &a in &nodes[i].args[..arity(nodes[i].code)] {
            last[a as usize] = k;
        }
    }
    for &o in outputs {
        last[o as usize] = usize::MAX;
    }
    let pin = |i: usize| pinned && nodes[i].code == Code::Input;
    let (mut immediates, mut fused) = (0, 0);
    let mut regs = Registers { free: vec![], count: if pinned { TAPE_INPUTS } else { 0 } };
    let mut reg = vec![0u32; nodes.len()];
    let mut words = Vec::with_capacity(order.len());
    let mut iterations = 0;
    for (k, &i) in order.iter().enumerate() {
        let n = nodes[i];
        if pin(i) {
            // An output that is an input (f = x) is its register.
            reg[i] = n.imm as u32;
            continue;
        }
        let args = &n.args[..arity(n.code)];
        // One constant operand is read from the instruction.
        let imm = immediate_operands(n.code).iter().map(|&j| args[j]).find(|&a| nodes[a as usize].code == Code::Const && leaf(a as usize));
        immediates += usize::from(imm.is_some());
        fused += usize::from(matches!(n.code, Code::Mad | Code::Msub));
        let mut dying = vec![];
        for (j, &a) in args.iter().enumerate() {
            if args[..j].contains(&a) || imm == Some(a) {
                continue;
            }
            if pin(a as usize) {
                reg[a as usize] = nodes[a as usize].imm as u32;
            } else if leaf(a as usize) {
                reg[a as usize] = regs.take();
                words.push(word(b, a as usize, reg[a as usize], [0; 4]));
                dying.push(reg[a as usize]);
            } else if last[a as usize] == k {
                dying.push(reg[a as usize]);
            }
        }
        regs.free.extend(dying);
        reg[i] = regs.take();
        let mut ra = [0u32; 4];
        let mut flags = 0;
        for (j, &a) in args.iter().enumerate() {
            if imm == Some(a) {
                flags |= if j == 0 { TAPE_IMM_A } else { TAPE_IMM_B };
            } else {
                ra[j] = reg[a as usize];
            }
        }
        let mut w = word(b, i, reg[i], ra);
        w[0] |= flags;
        if let Some(c) = imm {
            if args.len() == 3 {
                // A multiply-add's addend moves to the immediate's place.
                w[1] = ra[0] | ra[2] << 16;
            }
            let k = word(b, c as usize, 0, [0; 4]);
            w[0] |= k[0] & TAPE_NEAR_HI;
            w[2] = k[2];
            w[3] = k[3];
        }
        words.push(w);
        if n.code == Code::PowChain {
            iterations += 31 - (n.imm as u32).leading_zeros();
        }
    }
    if regs.count > TAPE_SLOTS {
        return Err(TapeError::Registers(regs.count));
    }
    let ops = words.len();
    let mut program = Program { words, outputs: outputs.iter().map(|&o| reg[o as usize]).collect(), ops, immediates, fused, registers: regs.count, iterations };
    program.pad(TAPE_UNROLL);
    Ok(program)
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
    let flags = if b.strict.contains(&(i as u32)) { TAPE_RESTRICTS } else { 0 };
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

//! Rematerialisation: a program whose shared subexpressions keep more
//! values alive at once than the interpreter has registers is rewritten
//! with its cheap shared nodes computed again at each use.
//!
//! Hash-consing shares every repeated subexpression, and a shared value
//! holds a register from its first use to its last. A sum of a few thousand
//! monomials shares its powers and their products (x², x²·y³, …) across
//! the whole sum: 140 to 760 values alive at once where the interpreter has
//! 64 registers, so such a formula could be neither a tape nor (its
//! generated code over the size limit) compiled. Computed again at each
//! use, a small subexpression lives only until its parent reads it. The
//! values are the same, operation for operation, so the enclosures are too.

use super::{arity, Builder, Node};

/// `b`'s program for `outputs` with every shared node whose expression
/// tree has at most `k` nodes copied at each of its uses (constants, inputs
/// and parameters count one; they are emitted at each use anyway), and the
/// new outputs. Nodes past `k` stay shared. A node keeps its result flag
/// (`strict`) and its choice slot; the derivative nodes' partners are kept
/// where both stay shared. `None` when the copies would make the program
/// more than `growth` times as long.
pub(super) fn rematerialize(b: &Builder, outputs: &[u32], k: u64, growth: usize) -> Option<(Builder, Vec<u32>)> {
    let nodes = &b.nodes;
    // Tree sizes (saturating: a chain of squares doubles at every step).
    let mut cost = vec![1u64; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        cost[i] = n.args[..arity(n.code)].iter().fold(1u64, |c, &a| c.saturating_add(cost[a as usize]));
    }
    let copied = |i: usize| arity(nodes[i].code) > 0 && cost[i] <= k;
    let mut reach = vec![false; nodes.len()];
    let mut todo = outputs.to_vec();
    while let Some(n) = todo.pop() {
        if !std::mem::replace(&mut reach[n as usize], true) {
            todo.extend_from_slice(&nodes[n as usize].args[..arity(nodes[n as usize].code)]);
        }
    }
    let limit = nodes.len().saturating_mul(growth);
    let mut out = Remat { b, new: Builder::default(), shared: vec![u32::MAX; nodes.len()], copied: &copied, limit };
    // Shared nodes in the original (topological) order, each once; a copied
    // operand is built again under each parent that reads it.
    for i in (0..nodes.len()).filter(|&i| reach[i] && !copied(i)) {
        let args = out.operands(i)?;
        out.shared[i] = out.emit(i, args)?;
    }
    let outputs = outputs.iter().map(|&o| out.instance(o as usize)).collect::<Option<Vec<u32>>>()?;
    for (&d, &v) in &b.partner {
        let (d, v) = (out.shared[d as usize], out.shared[v as usize]);
        if d != u32::MAX && v != u32::MAX {
            out.new.partner.insert(d, v);
        }
    }
    Some((out.new, outputs))
}

/// The program being rewritten.
struct Remat<'a, F: Fn(usize) -> bool> {
    b: &'a Builder,
    new: Builder,
    /// The new node of each shared original (`u32::MAX`: none yet).
    shared: Vec<u32>,
    copied: &'a F,
    /// Most nodes of the new program.
    limit: usize,
}

impl<F: Fn(usize) -> bool> Remat<'_, F> {
    /// Node `i` for one use: its shared node, or a new copy of its tree
    /// (at most `k` nodes deep, so the recursion is short).
    fn instance(&mut self, i: usize) -> Option<u32> {
        if !(self.copied)(i) {
            return Some(self.shared[i]);
        }
        let args = self.operands(i)?;
        self.emit(i, args)
    }

    /// The operands of node `i`, each instantiated for this use.
    fn operands(&mut self, i: usize) -> Option<[u32; 4]> {
        let n = self.b.nodes[i];
        let mut args = n.args;
        for a in args.iter_mut().take(arity(n.code)) {
            *a = self.instance(*a as usize)?;
        }
        Some(args)
    }

    /// Appends a copy of node `i` reading `args`, with its flag and slot.
    fn emit(&mut self, i: usize, args: [u32; 4]) -> Option<u32> {
        if self.new.nodes.len() >= self.limit {
            return None;
        }
        let n = self.b.nodes[i];
        self.new.nodes.push(Node { args, ..n });
        let id = self.new.nodes.len() as u32 - 1;
        if self.b.strict.contains(&(i as u32)) {
            self.new.strict.insert(id);
        }
        if let Some(&slot) = self.b.slots.get(&(i as u32)) {
            self.new.slots.insert(id, slot);
        }
        Some(id)
    }
}

//! Finding the runs: the chains of one associative operation, their terms,
//! each term's own nodes and its shape (what two terms must share to be
//! computed by one loop body).

use super::{with_operands, MIN_RUN};
use crate::ir::{Func2, Ir, NodeId, Op};

/// How an operand of a term's node is reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Ref {
    /// A node of the same term (its index in the term's body).
    Local(usize),
    /// A constant: a slot of the table.
    Slot,
    /// A node outside the term, the same for every term of the run.
    Shared(NodeId),
}

/// The chain operations: associative ones the parser writes left-deep.
fn chain_operands(op: Op) -> Option<(NodeId, NodeId)> {
    match op {
        Op::Add(a, b) | Op::Mul(a, b) | Op::Call2(Func2::Min | Func2::Max, a, b) => Some((a, b)),
        _ => None,
    }
}

fn same_kind(a: Op, b: Op) -> bool {
    with_operands(a, &[0; 4]) == with_operands(b, &[0; 4])
}

/// A commutative operand's place in a shape: the term's own nodes, then
/// constants, then shared nodes.
fn ref_rank(r: &Ref) -> (u8, usize) {
    match *r {
        Ref::Local(i) => (0, i),
        Ref::Slot => (1, 0),
        Ref::Shared(n) => (2, n as usize),
    }
}

fn is_leaf(op: Op) -> bool {
    matches!(op, Op::Const(_) | Op::Var(_) | Op::Param(_))
}

/// Who uses each live node.
pub(super) struct Uses {
    pub(super) live: Vec<NodeId>,
    pub(super) is_live: Vec<bool>,
    pub(super) users: Vec<Vec<NodeId>>,
    /// Outputs have a user outside the formula.
    pub(super) output: Vec<bool>,
}

impl Uses {
    pub(super) fn new(ir: &Ir) -> Uses {
        let n = ir.nodes.len();
        let live = ir.live();
        let mut is_live = vec![false; n];
        let mut users: Vec<Vec<NodeId>> = vec![Vec::new(); n];
        for &id in &live {
            is_live[id as usize] = true;
            for o in ir.nodes[id as usize].operands() {
                users[o as usize].push(id);
            }
        }
        let mut output = vec![false; n];
        output[ir.root as usize] = true;
        for s in &ir.surfaces {
            output[s.f as usize] = true;
            for &(g, _) in &s.conditions {
                output[g as usize] = true;
            }
        }
        Uses { live, is_live, users, output }
    }
    /// Used once, inside the formula.
    pub(super) fn single(&self, id: NodeId) -> bool {
        self.users[id as usize].len() == 1 && !self.output[id as usize]
    }
}

/// The chain node and the term that node `id` joins, if it continues a
/// chain: a node of its kind used only by it, in either operand (the front
/// end orders a commutative node's operands by when they were written, so
/// `min(a, b, c, …)` continues through its second).
fn link(ir: &Ir, u: &Uses, id: NodeId) -> Option<(NodeId, NodeId)> {
    let op = ir.nodes[id as usize];
    let (a, b) = chain_operands(op)?;
    let continues = |x: NodeId| same_kind(ir.nodes[x as usize], op) && u.single(x);
    if continues(a) {
        Some((a, b))
    } else if continues(b) {
        Some((b, a))
    } else {
        None
    }
}

/// The chains longer than [`MIN_RUN`]: each from its bottom node (whose
/// operands are terms 0 and 1) to its top, every node but the top used
/// only by the next.
pub(super) fn chains(ir: &Ir, u: &Uses) -> Vec<Vec<NodeId>> {
    let mut chains = Vec::new();
    for &top in &u.live {
        let op = ir.nodes[top as usize];
        if chain_operands(op).is_none() {
            continue;
        }
        let continued = u.single(top) && {
            let user = u.users[top as usize][0];
            same_kind(op, ir.nodes[user as usize]) && link(ir, u, user).is_some_and(|(c, _)| c == top)
        };
        if continued {
            continue;
        }
        let mut chain = vec![top];
        let mut cur = top;
        while let Some((c, _)) = link(ir, u, cur) {
            chain.push(c);
            cur = c;
        }
        chain.reverse();
        if chain.len() > MIN_RUN {
            chains.push(chain);
        }
    }
    chains
}

/// The chains' terms and the nodes each owns (those only it uses).
pub(super) struct Terms {
    /// Every chain's terms in order: terms 0 and 1 are its bottom node's
    /// operands, term i (from 2) the operand its (i − 1)-th node joins.
    pub(super) roots: Vec<NodeId>,
    /// Each chain's range of `roots`.
    pub(super) ranges: Vec<std::ops::Range<usize>>,
    /// Per term: its own nodes, operands first (its root last).
    pub(super) bodies: Vec<Vec<NodeId>>,
}

/// Each live node's structure, as a hash: a term's own node by its
/// operation and its operands' structures (a commutative node's in sorted
/// order), a constant by being one, any other node by its identity (a
/// shared input must be the same node in every term of a run).
fn signatures(ir: &Ir, u: &Uses, own: &[bool]) -> Vec<u64> {
    use std::hash::{Hash, Hasher};
    let mut sig = vec![0u64; ir.nodes.len()];
    for &id in &u.live {
        let op = ir.nodes[id as usize];
        let mut h = std::collections::hash_map::DefaultHasher::new();
        if matches!(op, Op::Const(_)) {
            "const".hash(&mut h);
        } else if own[id as usize] {
            let mut kids: Vec<u64> = op.operands().iter().map(|&o| sig[o as usize]).collect();
            if chain_operands(op).is_some() {
                kids.sort_unstable();
            }
            format!("{:?}", with_operands(op, &[0; 4])).hash(&mut h);
            kids.hash(&mut h);
        } else {
            id.hash(&mut h);
        }
        sig[id as usize] = h.finish();
    }
    sig
}

/// Appends the own nodes under `root` to `body` operands first, a
/// commutative node's in the order of their structures: the same order for
/// every term of one shape, whatever order the front end gave them (a node
/// two terms share comes earlier in the formula than the second term's
/// other nodes). An explicit stack: a term may hold a chain thousands of
/// nodes deep.
fn post_order(ir: &Ir, sig: &[u64], own: &[bool], root: NodeId, seen: &mut [bool], body: &mut Vec<NodeId>) {
    let mut stack = vec![(root, false)];
    while let Some((n, operands_done)) = stack.pop() {
        if operands_done {
            body.push(n);
            continue;
        }
        if seen[n as usize] {
            continue;
        }
        seen[n as usize] = true;
        stack.push((n, true));
        let op = ir.nodes[n as usize];
        let mut kids: Vec<NodeId> = op.operands().to_vec();
        if chain_operands(op).is_some() {
            kids.sort_by_key(|&o| sig[o as usize]);
        }
        stack.extend(kids.into_iter().rev().filter(|&o| own[o as usize] && !seen[o as usize]).map(|o| (o, false)));
    }
}

/// See [`Terms::new`]: a cheap node read by fewer than 1 in SHARED_SHARE
/// of a chain's terms is copied into each.
const SHARED_SHARE: usize = 8;
/// Most operations a cheap node's expression holds.
const CHEAP_OPS: usize = 3;

/// The operations of `id`'s expression if they are at most `budget`
/// arithmetic operations (no calls) on variables, parameters and
/// constants: what copying the node into every term costs.
fn cheap(ir: &Ir, id: NodeId, budget: usize) -> Option<usize> {
    let op = ir.nodes[id as usize];
    if is_leaf(op) {
        return Some(0);
    }
    if budget == 0 || !matches!(op, Op::Neg(_) | Op::Add(..) | Op::Sub(..) | Op::Mul(..) | Op::PowI(..)) {
        return None;
    }
    let mut used = 1;
    for o in op.operands() {
        used += cheap(ir, o, budget - used)?;
        if used > budget {
            return None;
        }
    }
    Some(used)
}

/// A term's shape: its nodes' operations and how each reaches its operands.
pub(super) type Shape = Vec<(Op, Vec<Ref>)>;

impl Terms {
    /// A term's own nodes are its root (used only by its chain node) and
    /// every node all of whose users are terms' own nodes. A node a few
    /// terms use is each one's: a program that writes its constants to
    /// three decimals writes `0.225*x` into two terms of a thousand by
    /// chance, and the front end makes it one node; counted as the
    /// terms' shared input it would make them shapes of their own and cut
    /// the run in three. The loop computes it again for each term, as
    /// written. A node [`MIN_RUN`] or more nodes use (`r` in `sin(a·r) +
    /// sin(b·r) + …`) stays a shared input, computed once, unless it is
    /// [`cheap`] and read by fewer than a [`SHARED_SHARE`]th of the longest
    /// chain's terms: a program that writes a thousand balls' centres to one
    /// decimal has 21 values of `(x - c)^2`, each read by some 50 terms, and
    /// as shared inputs they made every term's shape differ from its
    /// neighbours'.
    pub(super) fn new(ir: &Ir, u: &Uses, chains: &[Vec<NodeId>]) -> Terms {
        let n = ir.nodes.len();
        let (mut roots, mut ranges) = (Vec::new(), Vec::new());
        for chain in chains {
            let start = roots.len();
            let (a, b) = chain_operands(ir.nodes[chain[0] as usize]).expect("a chain node");
            roots.extend([a, b]);
            roots.extend(chain[1..].iter().map(|&c| link(ir, u, c).expect("a chain node").1));
            ranges.push(start..roots.len());
        }
        // A term is its own root when only chain nodes use it: a term
        // written twice (a ball a program placed twice) is one node the
        // chain reads twice, and a loop may compute it in both places.
        let mut linked = vec![false; n];
        for &c in chains.iter().flatten() {
            linked[c as usize] = true;
        }
        let mut is_root = vec![false; n];
        for &root in &roots {
            let users = &u.users[root as usize];
            is_root[root as usize] = !users.is_empty() && users.iter().all(|&x| linked[x as usize]) && !u.output[root as usize] && !is_leaf(ir.nodes[root as usize]);
        }
        // Users come later in the order.
        let longest = chains.iter().map(Vec::len).max().unwrap_or(0);
        let mut own = vec![false; n];
        for id in (0..n).rev() {
            if !u.is_live[id] || u.output[id] || is_leaf(ir.nodes[id]) {
                continue;
            }
            let users = &u.users[id];
            // A cheap node is copied into the terms that read it even where
            // other users compute it outside (a written-out term, or one
            // that is not a loop's): one such user must not make it a
            // shared input of every term.
            let cheap_and_rare = users.len() * SHARED_SHARE < longest && cheap(ir, id as NodeId, CHEAP_OPS).is_some();
            own[id] = is_root[id] || (!users.is_empty() && (cheap_and_rare || (users.len() < MIN_RUN && users.iter().all(|&x| own[x as usize]))));
        }
        let sig = signatures(ir, u, &own);
        let mut seen = vec![false; n];
        let bodies = roots
            .iter()
            .map(|&root| {
                let mut body = Vec::new();
                if is_root[root as usize] {
                    post_order(ir, &sig, &own, root, &mut seen, &mut body);
                    for &b in &body {
                        seen[b as usize] = false;
                    }
                }
                body
            })
            .collect();
        Terms { roots, ranges, bodies }
    }

    /// Term `t`'s shape; `None` for a term that cannot be a loop's (not
    /// its own root, or with a call of a user function).
    pub(super) fn shape(&self, ir: &Ir, t: usize) -> Option<Shape> {
        let body = &self.bodies[t];
        if body.last() != Some(&self.roots[t]) {
            return None;
        }
        body.iter()
            .map(|&id| {
                let op = ir.nodes[id as usize];
                if matches!(op, Op::User(..)) {
                    return None;
                }
                let mut refs: Vec<Ref> = op
                    .operands()
                    .iter()
                    .map(|&o| match ir.nodes[o as usize] {
                        Op::Const(_) => Ref::Slot,
                        _ => body.iter().position(|&b| b == o).map_or(Ref::Shared(o), Ref::Local),
                    })
                    .collect();
                // The front end orders a commutative node's operands by
                // when they were first written, so `0.3*x + 0.302` and
                // `0.5*x + 0.2` (0.2 written earlier, as another term's
                // factor) come out in opposite orders: compared in a fixed
                // order they are one shape. The loop computes every term in
                // the first term's order, which every domain's + × min max
                // enclose alike (only an affine product's rounding differs).
                if chain_operands(op).is_some() {
                    refs.sort_by_key(ref_rank);
                }
                Some((with_operands(op, &[0; 4]), refs))
            })
            .collect()
    }
}

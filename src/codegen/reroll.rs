//! Loop rerolling for the compiled field. A generated formula is usually
//! built by a program: a long chain `((… + t_k) + t_k+1) + …` (or of `*`,
//! `min`, `max`) whose terms have one shape and differ only in their
//! constants. Written out, every term is more code for lavapipe's LLVM back
//! end, whose compile time grows steeply with the shader (README, "Compiled
//! or tape"). Here such a run of terms becomes a loop over a table of their
//! constants: the shader holds one copy of the term (unrolled a few times),
//! and the constants come from a texture in the field group
//! (`@group(1) @binding(0)`). Measured on lavapipe (README, "Long runs of
//! same-shaped terms"): with a storage load at an index uniform across
//! lanes the frames were several times slower than with the texture (as if
//! lavapipe read it lane by lane), and with a WGSL constant or private
//! array indexed by the loop counter slower still.
//!
//! The loop accumulates the chain in the order it is written, so every
//! domain computes what the straight-line code computes (one operation at a
//! time, the same operands), and the enclosures are the same.
//!
//! lavapipe stops an invocation after 65,535 loop iterations in total, so a
//! rerolled evaluation first asks [`WORK_LIMIT`] for its iterations
//! (`field_admits`); past it the evaluation is the whole line and the pixel
//! is reported unresolved (`field_exhausted`), as with the tape.

use super::f32_enclosure;
use crate::ir::{Func2, Ir, NodeId, Op};

/// Shortest run of same-shaped terms made a loop: below it the loop's own
/// cost (its counter, the texel fetches) outweighs what it saves.
pub const MIN_RUN: usize = 16;
/// Loop iterations an invocation's rerolled evaluations may spend: the
/// tape's per-invocation share of lavapipe's cap (the same reasoning:
/// `codegen::tape::TAPE_WORK_LIMIT`).
pub const WORK_LIMIT: u32 = super::tape::TAPE_WORK_LIMIT;
/// Most nodes an unrolled loop body holds (terms × their nodes).
const BODY_MAX: usize = 256;

/// How an operand of a term's node is reached.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Ref {
    /// A node of the same term (its index in the term's body).
    Local(usize),
    /// A constant: a slot of the table.
    Slot,
    /// A node outside the term, the same for every term of the run.
    Shared(NodeId),
}

/// One run of terms emitted as a loop.
#[derive(Debug, Clone)]
pub struct Loop {
    /// The chain's value before the loop's first term (the accumulator's start).
    pub seed: NodeId,
    /// The chain node whose value the loop computes.
    pub end: NodeId,
    /// The chain's operation, with placeholder operands.
    pub op: Op,
    /// The first rerolled term's own nodes, in topological order: the body.
    pub body: Vec<NodeId>,
    /// Its root (the term's value).
    pub root: NodeId,
    /// Constants a term reads.
    pub slots: usize,
    /// Terms an iteration evaluates.
    pub unroll: usize,
    /// Iterations.
    pub iterations: usize,
    /// First texel of the terms' rounded constants (scalar domain).
    pub scalar_base: u32,
    /// First texel of the terms' constant enclosures (lo, hi pairs).
    pub interval_base: u32,
}

/// Where a loop's constants lie in the table for one domain: terms are
/// packed `group` to `texels` texels (several terms to a texel where
/// their constants fit: a texel fetch is most of a term's cost on lavapipe),
/// `width` floats a constant (1: the rounded value; 2: its enclosure).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// First texel.
    pub base: u32,
    /// Terms a group of texels holds.
    pub group: usize,
    /// Texels a group takes.
    pub texels: u32,
    /// Floats a constant takes.
    pub width: usize,
}

impl Layout {
    fn new(slots: usize, width: usize, unroll: usize) -> Layout {
        let floats = (slots * width).max(1);
        let group = (4 / floats).max(1);
        if group > 1 && unroll % group == 0 {
            Layout { base: 0, group, texels: 1, width }
        } else {
            Layout { base: 0, group: 1, texels: floats.div_ceil(4) as u32, width }
        }
    }
    /// The float offset, within its group's texels, of constant `slot` of
    /// the group's term `within`.
    pub fn offset(&self, slots: usize, within: usize, slot: usize) -> usize {
        (within * slots + slot) * self.width
    }
}

impl Loop {
    /// The layout the scalar domain reads (rounded constants).
    pub fn scalar(&self) -> Layout {
        Layout { base: self.scalar_base, ..Layout::new(self.slots, 1, self.unroll) }
    }
    /// The layout the interval and affine domains read (enclosures).
    pub fn interval(&self) -> Layout {
        Layout { base: self.interval_base, ..Layout::new(self.slots, 2, self.unroll) }
    }
    /// The chain's operation on `acc` and `term`.
    pub fn step(&self, acc: NodeId, term: NodeId) -> Op {
        with_operands(self.op, &[acc, term])
    }
}

/// Which nodes of a formula are emitted as loops.
#[derive(Debug, Clone, Default)]
pub struct Plan {
    /// The loops, in the order of their `end` nodes.
    pub loops: Vec<Loop>,
    /// Per node: emitted inside a loop (or replaced by one), not on its own.
    skip: Vec<bool>,
    /// Per node: computed by a loop for some term of its run.
    rerolled: Vec<bool>,
    /// The table: every loop's constants, `[f32; 4]` texels as bits.
    pub table: Vec<[u32; 4]>,
}

impl Plan {
    /// Whether node `id` is left to a loop.
    pub fn skips(&self, id: NodeId) -> bool {
        self.skip.get(id as usize).copied().unwrap_or(false)
    }
    /// The loop that computes node `id`.
    pub fn loop_at(&self, id: NodeId) -> Option<&Loop> {
        self.loops.iter().find(|l| l.end == id)
    }
    /// Loop iterations of one evaluation.
    pub fn iterations(&self) -> u32 {
        self.loops.iter().map(|l| l.iterations as u32).sum()
    }
    /// Nodes the generated code holds: the formula's less the rerolled
    /// ones, plus each loop's unrolled body (what `Auto` weighs against
    /// the tape).
    pub fn emitted_nodes(&self, ir: &Ir) -> usize {
        self.emitted_weight(ir, |_| 1)
    }

    /// The sum of `weigh` over the nodes the generated code holds (a loop's
    /// accumulating operation and body once per unrolled term).
    pub fn emitted_weight(&self, ir: &Ir, weigh: impl Fn(&Op) -> usize) -> usize {
        let kept: usize = ir.live().iter().filter(|&&n| !self.skips(n)).map(|&n| weigh(&ir.nodes[n as usize])).sum();
        let body = |l: &Loop| weigh(&l.op) + l.body.iter().map(|&n| weigh(&ir.nodes[n as usize])).sum::<usize>();
        kept + self.loops.iter().map(|l| l.unroll * body(l)).sum::<usize>()
    }
}

/// `op` with its operands replaced, in order, by `ops`.
pub(crate) fn with_operands(op: Op, ops: &[NodeId]) -> Op {
    let o = |i: usize| ops[i];
    match op {
        Op::Const(_) | Op::Var(_) | Op::Param(_) => op,
        Op::Neg(_) => Op::Neg(o(0)),
        Op::Add(..) => Op::Add(o(0), o(1)),
        Op::Sub(..) => Op::Sub(o(0), o(1)),
        Op::Mul(..) => Op::Mul(o(0), o(1)),
        Op::Div(..) => Op::Div(o(0), o(1)),
        Op::PowI(_, n) => Op::PowI(o(0), n),
        Op::Call1(f, _) => Op::Call1(f, o(0)),
        Op::Call2(f, ..) => Op::Call2(f, o(0), o(1)),
        Op::Call3(f, ..) => Op::Call3(f, o(0), o(1), o(2)),
        Op::User(u, mut args, n) => {
            args[..n as usize].copy_from_slice(&ops[..n as usize]);
            Op::User(u, args, n)
        }
    }
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
struct Uses {
    live: Vec<NodeId>,
    is_live: Vec<bool>,
    users: Vec<Vec<NodeId>>,
    /// Outputs have a user outside the formula.
    output: Vec<bool>,
}

impl Uses {
    fn new(ir: &Ir) -> Uses {
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
    fn single(&self, id: NodeId) -> bool {
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
fn chains(ir: &Ir, u: &Uses) -> Vec<Vec<NodeId>> {
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
struct Terms {
    /// Every chain's terms in order: term 0 is its bottom node's left
    /// operand, term i its i-th node's right operand.
    roots: Vec<NodeId>,
    /// Each chain's range of `roots`.
    ranges: Vec<std::ops::Range<usize>>,
    /// Per term: its own nodes, in topological order (its root last).
    bodies: Vec<Vec<NodeId>>,
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
/// other nodes).
fn post_order(ir: &Ir, sig: &[u64], own: &[bool], root: NodeId, seen: &mut [bool], body: &mut Vec<NodeId>) {
    seen[root as usize] = true;
    let op = ir.nodes[root as usize];
    let mut kids: Vec<NodeId> = op.operands().to_vec();
    if chain_operands(op).is_some() {
        kids.sort_by_key(|&o| sig[o as usize]);
    }
    for o in kids {
        if own[o as usize] && !seen[o as usize] {
            post_order(ir, sig, own, o, seen, body);
        }
    }
    body.push(root);
}

/// A term's shape: its nodes' operations and how each reaches its operands.
type Shape = Vec<(Op, Vec<Ref>)>;

impl Terms {
    /// A term's own nodes are its root (used only by its chain node) and
    /// every node all of whose users are terms' own nodes. A node a few
    /// terms use is each one's: a program that writes its constants to
    /// three decimals writes `0.225*x` into two terms of a thousand by
    /// chance, and the front end makes it one node; counted as the
    /// terms' shared input it would make them shapes of their own and cut
    /// the run in three. The loop computes it again for each term, as
    /// written. A node [`MIN_RUN`] or more nodes use (`r` in `sin(a·r) +
    /// sin(b·r) + …`) stays a shared input, computed once.
    fn new(ir: &Ir, u: &Uses, chains: &[Vec<NodeId>]) -> Terms {
        let n = ir.nodes.len();
        let (mut roots, mut ranges) = (Vec::new(), Vec::new());
        for chain in chains {
            let start = roots.len();
            let (a, b) = chain_operands(ir.nodes[chain[0] as usize]).expect("a chain node");
            roots.extend([a, b]);
            roots.extend(chain[1..].iter().map(|&c| link(ir, u, c).expect("a chain node").1));
            ranges.push(start..roots.len());
        }
        let mut is_root = vec![false; n];
        for &root in &roots {
            is_root[root as usize] = u.single(root) && !is_leaf(ir.nodes[root as usize]);
        }
        // Users come later in the order.
        let mut own = vec![false; n];
        for id in (0..n).rev() {
            if !u.is_live[id] || u.output[id] || is_leaf(ir.nodes[id]) {
                continue;
            }
            let users = &u.users[id];
            own[id] = is_root[id] || (!users.is_empty() && users.len() < MIN_RUN && users.iter().all(|&x| own[x as usize]));
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
    fn shape(&self, ir: &Ir, t: usize) -> Option<Shape> {
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

/// Finds the runs of same-shaped terms worth a loop and lays out their
/// constants.
pub fn plan(ir: &Ir) -> Plan {
    let u = Uses::new(ir);
    let chains = chains(ir, &u);
    let mut plan = Plan { skip: vec![false; ir.nodes.len()], rerolled: vec![false; ir.nodes.len()], ..Plan::default() };
    if chains.is_empty() {
        return plan;
    }
    let terms = Terms::new(ir, &u, &chains);
    // A term the written-out code takes whole from the ray (a plane, a
    // quadric: `ray_forms`) costs a few operations a cell there, exact,
    // against the loop's interval arithmetic on the cell's box: a product
    // of 100 planes took 155 ms a warm 512² frame written out and 1,190 ms
    // as a loop. Such terms stay written out.
    let rays = super::ray_forms::written_out_ray_nodes(ir);
    let from_ray = |t: usize| rays.as_ref().is_some_and(|r| r.has(terms.roots[t]));
    for (chain, range) in chains.iter().zip(&terms.ranges) {
        let shapes: Vec<Option<Shape>> = range.clone().map(|t| terms.shape(ir, t).filter(|_| !from_ray(t))).collect();
        let mut i = 0;
        while i < shapes.len() {
            let mut j = i + 1;
            while shapes[i].is_some() && j < shapes.len() && shapes[j] == shapes[i] {
                j += 1;
            }
            if let Some(shape) = shapes[i].as_ref().filter(|_| j - i >= MIN_RUN) {
                plan.add_run(ir, &terms, chain, range.start, i..j, shape);
            }
            i = j;
        }
    }
    // A rerolled term's nodes are left to the loop unless a term written
    // out uses them too (a node a few terms share is each one's).
    for id in (0..ir.nodes.len()).rev() {
        let users = &u.users[id];
        if plan.rerolled[id] && !users.is_empty() && users.iter().all(|&x| plan.skip[x as usize] || plan.loop_at(x).is_some()) {
            plan.skip[id] = true;
        }
    }
    // Constants only the rerolled terms read are not written either (the
    // loop reads them from the table; shared nodes it reads stay).
    for id in (0..ir.nodes.len()).rev() {
        let unread = !u.users[id].is_empty() && u.users[id].iter().all(|&x| plan.skip[x as usize] && plan.loop_at(x).is_none());
        if u.is_live[id] && matches!(ir.nodes[id], Op::Const(_)) && !u.output[id] && unread {
            plan.skip[id] = true;
        }
    }
    plan.loops.sort_by_key(|l| l.end);
    plan
}

impl Plan {
    /// Makes terms `run` (indices into the chain's terms, which start at
    /// `first_term`) a loop: the run's first term stays written out and
    /// seeds the accumulator, whole iterations of the rest are rerolled,
    /// and what is left over stays written out.
    fn add_run(&mut self, ir: &Ir, terms: &Terms, chain: &[NodeId], first_term: usize, run: std::ops::Range<usize>, shape: &Shape) {
        let i = run.start;
        let first = first_term + i + 1;
        let body = terms.bodies[first].clone();
        let unroll = unroll_for(run.len() - 1, body.len());
        let iterations = (run.len() - 1) / unroll;
        let count = iterations * unroll;
        let seed = if i == 0 { terms.roots[first_term] } else { chain[i - 1] };
        let end = chain[i + count - 1];
        let slots = shape.iter().flat_map(|(_, r)| r).filter(|r| **r == Ref::Slot).count();
        let op = with_operands(ir.nodes[end as usize], &[0; 4]);
        let mut l = Loop { seed, end, op, root: terms.roots[first], body, slots, unroll, iterations, scalar_base: 0, interval_base: 0 };
        let consts: Vec<Vec<f64>> = (first..first + count).map(|t| slot_values(ir, &terms.bodies[t])).collect();
        lay_out(&mut self.table, &mut l, &consts);
        for &c in &chain[i..i + count - 1] {
            self.skip[c as usize] = true;
        }
        for body in &terms.bodies[first..first + count] {
            for &b in body {
                self.rerolled[b as usize] = true;
            }
        }
        self.loops.push(l);
    }
}

/// Terms an iteration evaluates: more for long runs (fewer iterations
/// against lavapipe's loop cap), within [`BODY_MAX`] nodes, a power of two
/// (so terms pack evenly into texels).
fn unroll_for(terms: usize, body: usize) -> usize {
    let want = match terms {
        0..128 => 4,
        128..512 => 8,
        512..1024 => 16,
        1024..2048 => 32,
        _ => 64,
    };
    let u = want.min(BODY_MAX / (body + 1)).clamp(1, terms.max(1));
    1 << u.ilog2()
}

/// A term's constants in the order its body reads them.
fn slot_values(ir: &Ir, body: &[NodeId]) -> Vec<f64> {
    let mut out = Vec::new();
    for &id in body {
        for o in ir.nodes[id as usize].operands() {
            if let Op::Const(c) = ir.nodes[o as usize] {
                out.push(c);
            }
        }
    }
    out
}

/// Appends a loop's constants to the table: every term's rounded values,
/// then every term's enclosures, each packed by its [`Layout`].
fn lay_out(table: &mut Vec<[u32; 4]>, l: &mut Loop, consts: &[Vec<f64>]) {
    l.scalar_base = table.len() as u32;
    region(table, l.slots, l.scalar(), consts, |c| vec![f32_enclosure(c).0]);
    l.interval_base = table.len() as u32;
    region(table, l.slots, l.interval(), consts, |c| {
        let (_, lo, hi) = f32_enclosure(c);
        vec![lo, hi]
    });
}

fn region(table: &mut Vec<[u32; 4]>, slots: usize, lay: Layout, consts: &[Vec<f64>], floats: impl Fn(f64) -> Vec<f32>) {
    for group in consts.chunks(lay.group) {
        let mut row = vec![0.0f32; lay.texels as usize * 4];
        for (within, c) in group.iter().enumerate() {
            for (slot, &v) in c.iter().enumerate() {
                let at = lay.offset(slots, within, slot);
                for (k, f) in floats(v).into_iter().enumerate() {
                    row[at + k] = f;
                }
            }
        }
        table.extend(row.chunks(4).map(|q| [q[0].to_bits(), q[1].to_bits(), q[2].to_bits(), q[3].to_bits()]));
    }
}

/// The WGSL a kernel with loops needs once: the table's binding and
/// reader, and the work limit: per invocation ([`WORK_LIMIT`]), or with
/// `bundle` per SIMD bundle, as a tape's (`tape_field::BUNDLE_WORK`: a
/// bisection kernel on a device with subgroups, whose entry points call
/// `field_entry`). Both define `field_entry`.
pub fn support(bundle: bool) -> String {
    let admits = if bundle {
        format!(
            "const TAPE_BUNDLE_LIMIT: u32 = {}u;\n{}\
             fn field_admits(iters: u32) -> bool {{\n    let ok = bundle_admits(iters);\n    \
             if (!ok) {{ g_field_exhausted = true; }}\n    return ok;\n}}\n",
            super::tape::TAPE_BUNDLE_LIMIT,
            super::tape_field::BUNDLE_WORK
        )
    } else {
        format!(
            "fn field_entry(li: u32) {{}}\n\
             fn field_admits(iters: u32) -> bool {{\n    \
             if (g_field_work + iters > {WORK_LIMIT}u) {{ g_field_exhausted = true; return false; }}\n    \
             g_field_work = g_field_work + iters;\n    return true;\n}}\n"
        )
    };
    format!(
        "// Rerolled terms' constants (src/codegen/reroll.rs): {w} texels a row.\n\
         @group(1) @binding(0) var field_table_tex: texture_2d<u32>;\n\
         fn field_table(i: u32) -> vec4<f32> {{ return bitcast<vec4<f32>>(textureLoad(field_table_tex, vec2<u32>(i & {mask}u, i >> {shift}u), 0)); }}\n\
         // Set when an evaluation was refused for the work limit: the pixel is reported.\n\
         var<private> g_field_exhausted: bool;\n\
         // Whether an evaluation of `iters` loop iterations is within the limit (and counts it).\n{admits}",
        w = crate::scene::linear::TEXTURE_WIDTH,
        mask = crate::scene::linear::TEXTURE_WIDTH - 1,
        shift = crate::scene::linear::TEXTURE_SHIFT,
    )
}

/// The expression of the constant at float offset `at` of a group whose
/// texels are named by `q`, in the domain with prefix `p`.
pub fn slot_expr(p: &str, q: impl Fn(usize) -> String, at: usize) -> String {
    const C: [&str; 4] = ["x", "y", "z", "w"];
    match p {
        "s" => format!("s_const({}.{})", q(at / 4), C[at % 4]),
        "ia" => format!("{}.{}", q(at / 4), if at % 4 == 0 { "xy" } else { "zw" }),
        _ => format!("ra_from_ia({}.{})", q(at / 4), if at % 4 == 0 { "xy" } else { "zw" }),
    }
}

/// The table texture of a formula's loops (`None` without loops).
pub fn table_texels(ir: &Ir) -> Option<super::Texels<[u32; 4]>> {
    let plan = plan(ir);
    (!plan.loops.is_empty()).then(|| super::Texels::from_rows(None, &plan.table))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn compile(src: &str) -> Ir {
        crate::Formula::compile("<test>", src).unwrap().ir
    }

    /// No catalog surface has a run long enough: their kernels are the
    /// straight-line code they always were.
    #[test]
    fn the_catalog_is_not_rerolled() {
        for e in crate::catalog::builtin() {
            let Ok(f) = e.compile() else { continue };
            assert!(plan(&f.ir).loops.is_empty(), "{}", e.name);
        }
    }

    #[test]
    fn a_run_needs_min_run_terms_of_one_shape() {
        let terms = |n: usize| (0..n).map(|i| format!("({}*x - y)*(z + {})", i + 3, i + 200)).collect::<Vec<_>>().join(" + ");
        assert!(plan(&compile(&terms(MIN_RUN - 1))).loops.is_empty());
        let p = plan(&compile(&terms(MIN_RUN + 9)));
        // The front end orders a product's operands by node: the first term
        // is `3·x` (its constant came first), the others `x·k`. Compared in
        // a fixed order they are one shape, so the run is all 25 terms: term
        // 0 stays written out and seeds the loop, and 24 are rerolled at 4
        // an iteration.
        assert_eq!(p.loops.iter().map(|l| (l.slots, l.unroll, l.iterations)).collect::<Vec<_>>(), vec![(2, 4, 6)]);
        // A constant used twice in a term is two slots; a node all terms
        // share (x*y) is read, not copied.
        let shared = (0..40).map(|i| format!("{}*x*y*(z - {})", i + 2, i + 2)).collect::<Vec<_>>().join(" + ");
        let p = plan(&compile(&format!("x*y + {shared}")));
        assert_eq!(p.loops.len(), 1);
        assert_eq!(p.loops[0].slots, 2);
        // Min and max chains too; other shapes break a run.
        let spheres = (0..30).map(|i| format!("sqrt((x - {i})^2 + y^2 + z^2) - 1")).collect::<Vec<_>>();
        let mut u = spheres[0].clone();
        for s in &spheres[1..] {
            u = format!("min({u}, {s})");
        }
        assert_eq!(plan(&compile(&u)).loops.len(), 1);
        let mixed = (0..40).map(|i| if i % 2 == 0 { format!("{}*x", i + 2) } else { format!("{}*y*y", i + 2) }).collect::<Vec<_>>().join(" + ");
        assert!(plan(&compile(&mixed)).loops.is_empty());
        // Terms the written-out code takes whole from the ray stay written
        // out: balls as polynomials, planes.
        let balls = (0..30).map(|i| format!("(x - {i})^2 + y^2 + z^2 - 1")).collect::<Vec<_>>();
        assert!(plan(&compile(&format!("min({})", balls.join(", ")))).loops.is_empty());
        let planes = (0..30).map(|i| format!("({}*x + y - z + 1)", i + 2)).collect::<Vec<_>>();
        assert!(plan(&compile(&planes.join("*"))).loops.is_empty());
    }

    /// What a program that writes its constants to three decimals writes:
    /// operands in either order, a node two terms share by chance, a
    /// variadic min (a chain through second operands) and square roots.
    #[test]
    fn a_run_is_one_shape_whatever_the_front_ends_order_and_sharing() {
        let loops = |src: &str| plan(&compile(src)).loops.iter().map(|l| l.unroll * l.iterations).collect::<Vec<_>>();
        // 0.302 comes first as term 0's factor, so term 1's `x*0.5 + 0.302`
        // is `0.302 + x*0.5` to the front end; terms 2 and 9 share
        // `cos(0.7*y)`, which stays written out for nobody but the loop.
        let terms: Vec<String> = (0..40)
            .map(|i| {
                let (k, a, b, c) = ([0.302, 0.5][i % 2], 0.5 + 0.01 * i as f64, 0.302 + 0.011 * (i % 2) as f64, if i == 2 || i == 9 { 0.7 } else { 0.8 + 0.013 * i as f64 });
                format!("{k:.3}*sin({a:.3}*x + {b:.3})*cos({c:.3}*y)")
            })
            .collect();
        let ir = compile(&terms.join(" + "));
        assert_eq!(loops(&terms.join(" + ")), vec![36]);
        let p = plan(&ir);
        let shared = ir.live().into_iter().filter(|&n| matches!(ir.nodes[n as usize], Op::Call1(crate::ir::Func1::Cos, _))).filter(|&n| !p.skips(n)).count();
        // Only the cos of the terms written out (0, which seeds the loop,
        // and 37 to 39) is emitted on its own; the shared one is computed by
        // the loop, twice.
        assert_eq!(shared, 4);
        // min(s_0, s_1, …): the front end nests the chain in second operands.
        let balls: Vec<String> = (0..30).map(|i| format!("sqrt((x - {:.3})^2 + y^2 + z^2) - 0.2", 0.1 * i as f64)).collect();
        assert_eq!(loops(&format!("min({})", balls.join(", "))), vec![28]);
        // A node that many terms read stays one shared node (r here).
        let r = (0..30).map(|i| format!("{:.3}*sin({}*r)", 0.5 + 0.01 * i as f64, i + 1)).collect::<Vec<_>>().join(" + ");
        let ir = compile(&format!("r = sqrt(x^2 + y^2); z - ({r})"));
        let p = plan(&ir);
        assert_eq!(p.loops.len(), 1);
        assert!(p.loops[0].body.iter().all(|&b| !matches!(ir.nodes[b as usize], Op::Call1(crate::ir::Func1::Sqrt, _))));
    }

    #[test]
    fn the_table_holds_every_terms_rounded_constants_and_their_enclosures() {
        // (y + 3) is the same node in every term: shared, not a slot.
        let src = (0..20).map(|i| format!("(x - {})*(y + 3)", 0.1 * (i + 1) as f64)).collect::<Vec<_>>().join(" + ");
        let p = plan(&compile(&src));
        let l = &p.loops[0];
        assert_eq!((l.slots, l.unroll * l.iterations), (1, 16));
        let mut last = f32::NEG_INFINITY;
        // One constant a term: four terms' rounded values to a texel, two
        // terms' enclosures.
        assert_eq!((l.scalar().group, l.interval().group), (4, 2));
        for t in 0..16 {
            let n = f32::from_bits(p.table[l.scalar_base as usize + t / 4][t % 4]);
            let i = p.table[l.interval_base as usize + t / 2];
            let [lo, hi] = [i[2 * (t % 2)], i[2 * (t % 2) + 1]].map(f32::from_bits);
            // Each term's rounded constant lies in its enclosure, one ulp wide
            // where 0.1·k is not a float.
            assert!(lo <= n && n <= hi && (lo == hi || lo.next_up() == hi), "term {t}: {n} [{lo}, {hi}]");
            assert!(n > last);
            last = n;
        }
    }
}

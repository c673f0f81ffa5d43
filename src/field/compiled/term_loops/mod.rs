//! Loop rerolling for the compiled field. A generated formula is usually
//! built by a program: a long chain `((… + t_k) + t_k+1) + …` (or of `*`,
//! `min`, `max`) whose terms have one shape and differ only in their
//! constants. Written out, every term is more code for lavapipe's LLVM back
//! end, whose compile time grows steeply with the shader. Here such a run
//! of terms becomes a loop over a table of their constants: the shader
//! holds one copy of the term (unrolled a few times), and the constants
//! come from a texture in the field group (`@group(1) @binding(0)`). A
//! texture because on lavapipe a storage load at an index uniform across
//! lanes made the frames several times slower (as if lavapipe read it lane
//! by lane), and a WGSL constant or private array indexed by the loop
//! counter slower still.
//!
//! The loop accumulates the chain in the order it is written, so every
//! domain computes what the straight-line code computes (one operation at a
//! time, the same operands), and the enclosures are the same.
//!
//! lavapipe stops an invocation after 65,535 loop iterations in total, so a
//! rerolled evaluation first asks [`WORK_LIMIT`] for its iterations
//! (`field_admits`); past it the evaluation is the whole line and the pixel
//! is reported unresolved (`field_exhausted`), as with the tape.

pub(crate) mod emit;
pub mod horner;
pub mod lists;
pub(crate) mod monomials;
mod runs;

use crate::codegen::f32_enclosure;
use crate::ir::{Func1, Ir, NodeId, Op};
use runs::{chains, Ref, Shape, Terms, Uses};

/// Shortest run of same-shaped terms made a loop: below it the loop's own
/// cost (its counter, the texel fetches) outweighs what it saves.
pub const MIN_RUN: usize = 16;
/// Loop iterations an invocation's rerolled evaluations may spend: the
/// tape's per-invocation share of lavapipe's cap (the same reasoning:
/// `field::limits::TAPE_WORK_LIMIT`).
pub const WORK_LIMIT: u32 = crate::field::limits::TAPE_WORK_LIMIT;
/// Most nodes an unrolled loop body holds (terms × their nodes). A
/// smaller body runs faster on lavapipe (a long sum of sines, of
/// Gaussians, of bilinear products: several to fifteen percent from 256
/// nodes to 64), and compiles sooner; but each iteration counts against
/// the work limit, and at 32 a `min` of a thousand ball distances passed
/// it in thousands of pixels (docs/notes/2026-12-08-cell-midpoints.md).
const BODY_MAX: usize = 64;

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
    /// Constants a term reads.
    pub slots: usize,
    /// Terms an iteration evaluates.
    pub unroll: usize,
    /// Iterations.
    pub iterations: usize,
    /// First texel of the terms' rounded constants (scalar domain).
    pub scalar_base: u32,
    /// First texel of the terms' constant enclosures: pairs (lo, hi), or
    /// with `point_first` the end nearest the constant first.
    pub interval_base: u32,
    /// Whether the interval layout also gives each constant's f32 value
    /// (its first float), for f at a cell's midpoint in the cell
    /// enclosure's pass ([`crate::field::compiled::midpoint`]).
    pub point_first: bool,
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
    /// The polynomials computed as Horner loops ([`horner`]).
    pub horners: Vec<horner::Horner>,
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
    /// The Horner loop that computes node `id`.
    pub fn horner_at(&self, id: NodeId) -> Option<&horner::Horner> {
        self.horners.iter().find(|h| h.end == id)
    }
    /// Whether the formula has no loop of either kind.
    pub fn is_empty(&self) -> bool {
        self.loops.is_empty() && self.horners.is_empty()
    }
    /// Loop iterations of one evaluation.
    pub fn iterations(&self) -> u32 {
        self.loops.iter().map(|l| l.iterations as u32).chain(self.horners.iter().map(|h| h.iterations as u32)).sum()
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
        kept + self.loops.iter().map(|l| l.unroll * body(l)).sum::<usize>() + self.horners.iter().map(horner::Horner::weight).sum::<usize>()
    }
}

/// `op` with its operands replaced, in order, by `ops`.
pub(crate) fn with_operands(op: Op, ops: &[NodeId]) -> Op {
    let mut next = ops.iter().copied();
    op.with_operands(|_| next.next().expect("an operand for each of the op's"))
}

/// [`plan`] of `ir` as the compiled field writes it: the monomials of a sum
/// that mixes many of them with other terms gathered into one polynomial
/// first ([`monomials::monomial_sums`]); that IR too, where it differs from
/// `ir`.
pub fn written_plan(ir: &Ir) -> (Option<Ir>, Plan) {
    let gathered = monomials::monomial_sums(ir);
    let plan = plan(gathered.as_ref().unwrap_or(ir));
    (gathered, plan)
}

/// Finds the runs of same-shaped terms worth a loop and lays out their
/// constants.
pub fn plan(ir: &Ir) -> Plan {
    let u = Uses::new(ir);
    let mut plan = Plan { skip: vec![false; ir.nodes.len()], rerolled: vec![false; ir.nodes.len()], ..Plan::default() };
    let inside = plan.add_horners(ir, &u);
    let chains: Vec<Vec<NodeId>> = chains(ir, &u).into_iter().filter(|c| !c.iter().any(|&n| inside[n as usize])).collect();
    if chains.is_empty() {
        return plan;
    }
    let terms = Terms::new(ir, &u, &chains);
    // A term the written-out code takes whole from the ray (a plane, a
    // quadric: `ray_forms`) costs a few operations a cell there, exact,
    // against the loop's interval arithmetic on the cell's box: a product
    // of 100 planes renders several times faster written out than as a
    // loop. Such terms stay written out.
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
    // out uses them too (a node a few terms share is each one's), or a
    // loop starts from them (a term the chain reads twice may be both a
    // loop's seed and one of its terms).
    let mut seeds = vec![false; ir.nodes.len()];
    for l in &plan.loops {
        seeds[l.seed as usize] = true;
    }
    for id in (0..ir.nodes.len()).rev() {
        let users = &u.users[id];
        if plan.rerolled[id] && !seeds[id] && !users.is_empty() && users.iter().all(|&x| plan.skip[x as usize] || plan.loop_at(x).is_some()) {
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
    /// Makes every polynomial of [`horner::MIN_MONOMIALS`] monomials or more
    /// that no polynomial uses a Horner loop, outermost first, and leaves
    /// its nodes to it (but the variables, and nodes something else reads);
    /// returns which nodes lie inside one.
    fn add_horners(&mut self, ir: &Ir, u: &Uses) -> Vec<bool> {
        let mut inside = vec![false; ir.nodes.len()];
        let polys = crate::analysis::monomials::polynomials(ir, &u.live, horner::EXPANSION_BUDGET);
        let vars = horner::variables(ir, &u.live);
        for &n in u.live.iter().rev() {
            let Some(poly) = polys[n as usize].as_ref().filter(|q| q.terms.len() >= horner::MIN_MONOMIALS) else { continue };
            let top = u.output[n as usize] || u.users[n as usize].iter().any(|&x| polys[x as usize].is_none());
            if inside[n as usize] || !top {
                continue;
            }
            let mut stack = ir.nodes[n as usize].operands();
            while let Some(m) = stack.pop() {
                if !std::mem::replace(&mut inside[m as usize], true) {
                    stack.extend(ir.nodes[m as usize].operands());
                }
            }
            let used: [Option<NodeId>; 3] = [0, 1, 2].map(|i| vars[i].filter(|_| poly.monomials().any(|m| m.exps[i] > 0)));
            self.horners.push(horner::lay_out(&mut self.table, n, used, poly));
        }
        for id in (0..ir.nodes.len()).rev() {
            let kept = matches!(ir.nodes[id], Op::Var(_)) || u.output[id];
            if inside[id] && !kept && u.users[id].iter().all(|&x| self.skip[x as usize] || self.horner_at(x).is_some()) {
                self.skip[id] = true;
            }
        }
        inside
    }

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
        let point_first = !body.iter().any(|&b| costly_at_a_point(ir.nodes[b as usize]));
        let mut l = Loop { seed, end, op, body, slots, unroll, iterations, scalar_base: 0, interval_base: 0, point_first };
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

/// Whether a term operation costs about as much at a point as in the
/// loop's overhead: sin, cos and tan. The cell enclosure's point would pay
/// it on every cell, where a separate evaluation is paid only by the cells
/// that are not monotone; few, where such terms perturb a smooth surface
/// slightly, which is what a long sum of them tends to do
/// (docs/notes/2026-12-08-cell-midpoints.md).
fn costly_at_a_point(op: Op) -> bool {
    matches!(op, Op::Call1(Func1::Sin | Func1::Cos | Func1::Tan, _))
}

/// Appends a loop's constants to the table: every term's rounded values,
/// then every term's enclosures, each packed by its [`Layout`]. With
/// [`Loop::point_first`], an enclosure is its end nearest the constant
/// (the rounded value) first, then the other.
fn lay_out(table: &mut Vec<[u32; 4]>, l: &mut Loop, consts: &[Vec<f64>]) {
    l.scalar_base = table.len() as u32;
    region(table, l.slots, l.scalar(), consts, |c| vec![f32_enclosure(c).0]);
    l.interval_base = table.len() as u32;
    let point_first = l.point_first;
    region(table, l.slots, l.interval(), consts, |c| {
        let (near, lo, hi) = f32_enclosure(c);
        match point_first {
            true => vec![near, if near == lo { hi } else { lo }],
            false => vec![lo, hi],
        }
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
            crate::field::limits::TAPE_BUNDLE_LIMIT,
            crate::field::limits::BUNDLE_WORK_WGSL
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
        "// Rerolled terms' constants (src/field/compiled/term_loops): {w} texels a row.\n\
         {table}\
         fn field_table(i: u32) -> vec4<f32> {{ return bitcast<vec4<f32>>(textureLoad(field_table_tex, vec2<u32>(i & {mask}u, i >> {shift}u), 0)); }}\n\
         // Set when an evaluation was refused for the work limit: the pixel is reported.\n\
         var<private> g_field_exhausted: bool;\n\
         // Whether an evaluation of `iters` loop iterations is within the limit (and counts it).\n{admits}",
        table = crate::bindings::declarations(&[&crate::field::compiled::source::TERM_TABLE]),
        w = crate::scene::linear::TEXTURE_WIDTH,
        mask = crate::scene::linear::TEXTURE_WIDTH - 1,
        shift = crate::scene::linear::TEXTURE_SHIFT,
    )
}

/// A loop's constant in a kernel: its expression in the kernel's domain,
/// and its f32 value where the table gives it there (the scalar domain's
/// layout, or [`Loop::point_first`]).
pub struct SlotRead {
    pub expr: String,
    pub point: Option<String>,
}

/// The constant at float offset `at` of a group whose texels are named by
/// `q`, in the domain with prefix `p`, of a loop whose enclosures are
/// `point_first` ([`lay_out`]).
pub fn slot_expr(p: &str, q: impl Fn(usize) -> String, at: usize, point_first: bool) -> SlotRead {
    const C: [&str; 4] = ["x", "y", "z", "w"];
    let word = |k: usize| format!("{}.{}", q((at + k) / 4), C[(at + k) % 4]);
    let pair = format!("{}.{}", q(at / 4), if at % 4 == 0 { "xy" } else { "zw" });
    slot_read(p, &word(0), &word(1), (!point_first).then_some(pair))
}

/// [`slot_expr`] at a float offset known only at run time (`at`, a WGSL
/// `u32` expression) within the one texel `q`: a tile's list reads any
/// term of a group that shares a texel.
pub fn slot_expr_at(p: &str, q: &str, at: &str, point_first: bool) -> SlotRead {
    let (first, second) = (format!("{q}[{at}]"), format!("{q}[{at} + 1u]"));
    let pair = format!("vec2<f32>({first}, {second})");
    slot_read(p, &first, &second, (!point_first).then_some(pair))
}

/// A constant from its rounded value `first` (the scalar domain's layout)
/// or from its enclosure's two ends: `ordered`, the enclosure as a
/// `vec2<f32>`, where they are (lo, hi); else `first` is the nearer (as
/// in a Horner loop's table).
pub(super) fn slot_read(p: &str, first: &str, second: &str, ordered: Option<String>) -> SlotRead {
    let point = (p == "s" || ordered.is_none()).then(|| first.to_string());
    let pair = ordered.unwrap_or_else(|| format!("vec2<f32>(min({first}, {second}), max({first}, {second}))"));
    let expr = match p {
        "s" => format!("s_const({first})"),
        "ia" => pair,
        _ => format!("ra_from_ia({pair})"),
    };
    SlotRead { expr, point }
}

/// The table texture of a formula's loops as the compiled field generates
/// it (`None` without loops).
pub fn table_texels(ir: &Ir) -> Option<crate::field::Texels<[u32; 4]>> {
    let generated = crate::field::compiled::generated_ir(ir);
    let plan = plan(generated.as_ref().unwrap_or(ir));
    (!plan.is_empty()).then(|| crate::field::Texels::from_rows(None, &plan.table))
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

    /// A ball written twice is one node the chain reads twice: a term of
    /// the run in both places, and the loop's seed where it comes first.
    /// Such a seed was once left unwritten (the WGSL named an undefined
    /// value): a seed is always written out.
    #[test]
    fn a_seed_the_loop_also_computes_is_written_out() {
        let mut balls: Vec<String> = (0..300).map(|i| format!("sqrt((x-{:.3})^2+(y-{:.3})^2+(z-{:.3})^2)-0.1", (0.37 * i as f64).sin(), (0.53 * i as f64).cos(), (0.11 * i as f64).sin())).collect();
        // The last operand seeds the loop here; a copy of it is a term.
        balls.insert(150, balls[299].clone());
        let ir = compile(&format!("min({})", balls.join(",")));
        let p = plan(&ir);
        assert_eq!(p.loops.len(), 1);
        let u = runs::Uses::new(&ir);
        let l = &p.loops[0];
        assert!(p.rerolled[l.seed as usize] && !p.skips(l.seed), "seed {} {:?} users {:?} rerolled {} terms {}", l.seed, ir.nodes[l.seed as usize], u.users[l.seed as usize], p.rerolled[l.seed as usize], l.unroll * l.iterations);
        for domain in [super::super::Domain::Scalar, super::super::Domain::Interval] {
            crate::validate::validate(&super::super::eval_shader(&ir, domain)).expect("the seed is defined");
        }
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
            assert!(l.point_first);
            let [near, other] = [i[2 * (t % 2)], i[2 * (t % 2) + 1]].map(f32::from_bits);
            let (lo, hi) = (near.min(other), near.max(other));
            // Each term's rounded constant is its enclosure's first end, one
            // ulp wide where 0.1·k is not a float.
            assert!(near == n && (lo == hi || lo.next_up() == hi), "term {t}: {n} [{near}, {other}]");
            assert!(n > last);
            last = n;
        }
    }
}

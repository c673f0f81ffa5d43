//! Per-tile term lists of rerolled `min` and `max` loops: which loops
//! have them, where each loop's bits lie in a tile's words, and the WGSL
//! constants and hooks a bisection kernel splices in with them
//! (`templates/fields/loop_tiles.wgsl` says how the lists are made and why
//! they are exact; `term_loops::emit` writes the loops that note and read
//! them).
//!
//! Without lists, a bisected union of a thousand ball distances spends
//! nearly all its frame in the per-pixel pass evaluating every distance in
//! every cell, while near any one tile a handful can be the least.

use super::{Loop, Plan};
use crate::ir::{Func1, Func2, Ir, NodeId, Op};

/// One listed loop's place in a tile's bits.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Listed {
    /// The chain node the loop computes ([`Loop::end`]).
    pub end: NodeId,
    /// First word of its bits (a bit a term, in loop order), from the
    /// tile's first word of bits.
    pub word: u32,
    /// Words of its bits.
    pub words: u32,
}

/// The listed loops of a formula.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Lists {
    /// The listed loops, in the order of their `end` nodes.
    pub loops: Vec<Listed>,
    /// Words of bits a tile holds (all its loops').
    pub bits: u32,
    /// Terms the listed loops hold.
    pub terms: u32,
    /// Iterations the listed loops take run whole.
    pub iterations: u32,
    /// Iterations the tile pass's enclosures spend on them past the plan's
    /// (an interval or affine enclosure runs a listed loop twice, with
    /// fewer terms an iteration, to note its terms: `term_loops::emit`).
    pub notes_iterations: u32,
    /// Iterations of the per-pixel pass's whole loops over them (the
    /// fallback beside a tile's list), by domain: scalar, then interval
    /// or affine.
    pub fallback_iterations: [u32; 2],
}

impl Lists {
    /// The listed loop that computes chain node `end`.
    pub fn of(&self, end: NodeId) -> Option<&Listed> {
        self.loops.iter().find(|l| l.end == end)
    }

    /// Words a tile takes: the iterations its lists cost, its bits, and
    /// the bits of the fine and the coarse slab the tile pass encloses.
    pub fn tile_words(&self) -> u32 {
        1 + 3 * self.bits
    }

    /// Bytes of `tiles` tiles' words.
    pub fn bytes(&self, tiles: u64) -> u64 {
        tiles * u64::from(self.tile_words()) * 4
    }

    /// The constants and hooks of a kernel with these lists: they take the
    /// place of `codegen::UNSHORTENED_FIELD_HOOKS`.
    pub fn support(&self) -> String {
        format!(
            "const LOOP_BITS: u32 = {}u;\nconst LOOP_TILE_WORDS: u32 = {}u;\nconst LOOP_TERMS: u32 = {}u;\nconst LOOP_WHOLE_ITERATIONS: u32 = {}u;\nconst LOOP_FALLBACK_ITERATIONS: u32 = {}u;\n{}{}",
            self.bits,
            self.tile_words(),
            self.terms,
            self.iterations,
            self.fallback_iterations[0].min(self.fallback_iterations[1]),
            crate::bindings::declarations(&[&crate::field::compiled::source::TERM_LISTS, &crate::field::compiled::source::TERM_LIST_COUNTS]),
            include_str!("../../../../templates/fields/loop_tiles.wgsl"),
        )
    }
}

/// Fewest terms a listed loop has. The lists add a fixed cost to the
/// driver's compile whatever the loop, and save a cold frame little where
/// there are few terms; from a few hundred terms the frame is most of the
/// time and the lists win by more the more terms there are (chosen by
/// measurement on lavapipe, docs/benchmarks.md).
pub const MIN_LISTED_TERMS: usize = 128;

/// Whether a tile's list may leave out terms of loop `l`: a `min` or `max`
/// chain of at least [`MIN_LISTED_TERMS`] terms whose terms cannot make f
/// undefined (the only domain restrictions
/// in its body are square roots of values never negative by their form,
/// `nn`: a term left out must not take an emptiness with it).
fn listable(ir: &Ir, l: &Loop, nn: &[bool]) -> bool {
    let chain = matches!(l.op, Op::Call2(Func2::Min | Func2::Max, ..));
    let defined = l.body.iter().all(|&b| match ir.nodes[b as usize] {
        Op::Call1(Func1::Sqrt, a) => nn.get(a as usize).copied().unwrap_or(false),
        op => !op.restricts_domain(),
    });
    chain && defined && l.iterations * l.unroll >= MIN_LISTED_TERMS
}

/// Terms an iteration of a listed loop's whole fallback in the per-pixel
/// pass takes: at most [`SMALL_UNROLL`], at least a `group` of terms that
/// share texels (in the domain's layout). Each unrolled term is compile
/// time, and this loop runs only where a tile has no list. (Two or one a
/// loop would save some compile, but a tile past the tile pass's work
/// limit, counted per lane, then ran out of iterations and left pixels
/// unresolved where 4 left none.)
pub fn small_unroll(l: &Loop, group: usize) -> usize {
    l.unroll.min(SMALL_UNROLL.max(group))
}

/// See [`small_unroll`].
pub const SMALL_UNROLL: usize = 4;

/// Terms an iteration of a listed loop's whole loop in the tile pass, which
/// runs it twice (the loop's value over the slab, then the notes): twice
/// [`SMALL_UNROLL`], so that both passes take fewer iterations against
/// lavapipe's cap than a value pass of the plan's unroll and a notes pass
/// of [`SMALL_UNROLL`] did. (At [`SMALL_UNROLL`] the kernel compiles a
/// little sooner, but a union of over a thousand balls left tiles past the
/// tile pass's work limit, and pixels unresolved.)
pub fn record_unroll(l: &Loop, group: usize) -> usize {
    l.unroll.min((2 * SMALL_UNROLL).max(group))
}

/// The listed loops of `plan` (made for `ir`), `None` when it has none or
/// draws several surfaces (whose enclosures the lists are not made for).
pub fn lists(ir: &Ir, plan: &Plan) -> Option<Lists> {
    if ir.is_csg() {
        return None;
    }
    let nn = crate::analysis::nonneg::nonneg(ir);
    let mut out = Lists { loops: vec![], bits: 0, terms: 0, iterations: 0, notes_iterations: 0, fallback_iterations: [0; 2] };
    for l in plan.loops.iter().filter(|l| listable(ir, l, &nn)) {
        let terms = (l.iterations * l.unroll) as u32;
        let words = terms.div_ceil(32);
        out.loops.push(Listed { end: l.end, word: out.bits, words });
        out.bits += words;
        out.terms += terms;
        out.iterations += l.iterations as u32;
        // The tile pass runs the whole loop with fewer terms an iteration,
        // twice (the value, then the notes), in a loop of two passes.
        out.notes_iterations += 2 * (terms / record_unroll(l, l.interval().group) as u32) + 2 - l.iterations as u32;
        out.fallback_iterations[0] += terms / small_unroll(l, l.scalar().group) as u32;
        out.fallback_iterations[1] += terms / small_unroll(l, l.interval().group) as u32;
    }
    (!out.loops.is_empty()).then_some(out)
}

/// The lists of `ir` as the compiled field generates it.
pub fn for_formula(ir: &Ir) -> Option<Lists> {
    let balanced = crate::field::compiled::generated_ir(ir);
    let ir = balanced.as_ref().unwrap_or(ir);
    lists(ir, &super::plan(ir))
}

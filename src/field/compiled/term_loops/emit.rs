//! Emitting a rerolled loop ([`super`]): the accumulator, the
//! unrolled iterations over the table of the terms' constants, and, in a
//! bisection kernel with per-tile term lists ([`super::lists`],
//! `templates/fields/loop_tiles.wgsl`), the tile pass's notes and the
//! per-pixel loop over a tile's list.

use super::{self as reroll, lists::Listed, Loop};
use crate::field::compiled::{value_rhs, Hook};
use crate::ir::Domain;
use crate::ir::{Ir, NodeId, Op};
use std::fmt::Write;

/// What a loop does with per-tile term lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Tiles {
    /// Nothing: the loop runs whole (kernels without the lists, sphere
    /// tracing, the `eval` kernel).
    Off,
    /// The tile pass's slab enclosure: notes the terms that may be the
    /// loop's result over the slab (`loop_note`).
    Record,
    /// The per-pixel pass: runs the tile's list where there is one.
    Listed,
}

/// The state one function's loops share: fresh names and the
/// non-negative nodes.
pub(crate) struct LoopEmitter<'a> {
    pub ir: &'a Ir,
    pub domain: Domain,
    pub nn: &'a [bool],
    pub fresh: NodeId,
}

impl LoopEmitter<'_> {
    pub(super) fn fresh_id(&mut self) -> NodeId {
        self.fresh += 1;
        self.fresh - 1
    }

    /// One rerolled loop: the accumulator starts at the chain's value
    /// before the run and takes `unroll` terms an iteration, each written
    /// from the body with its constants read from the table (fresh names
    /// `v{fresh…}`). A body with square roots, logarithms or real powers
    /// (nodes whose empty result makes f empty) also gathers their
    /// emptiness, in a flag whose test it returns for the caller's. With
    /// `listed` (the loop's place in the tile lists) and [`Tiles::Listed`]
    /// the rays of a tile run its list instead; with [`Tiles::Record`]
    /// each term is noted where it may be the result.
    pub fn emit(&mut self, out: &mut String, l: &Loop, listed: Option<&Listed>, tiles: Tiles, hook: &mut impl FnMut(&mut String, Hook)) -> Option<String> {
        let acc = self.fresh_id();
        let strict = l.body.iter().any(|&b| self.ir.nodes[b as usize].restricts_domain());
        if strict {
            let _ = writeln!(out, "    var e{acc} = false;");
        }
        let _ = writeln!(out, "    var v{acc} = v{};", l.seed);
        hook(out, Hook::Begin { acc, seed: Some(l.seed) });
        let Some(at) = listed.filter(|_| tiles != Tiles::Off) else {
            self.emit_whole(out, l, acc, l.unroll, None, hook);
            return self.end(out, l, acc, strict, hook);
        };
        // The list where there is one; else the whole loop, with fewer terms
        // an iteration than without lists (each copy is compile time).
        let group = self.layout(l).group;
        let whole = match tiles {
            Tiles::Record => reroll::lists::record_unroll(l, group),
            _ => reroll::lists::small_unroll(l, group),
        };
        let note = if tiles == Tiles::Record {
            // Once the loop's bound over the slab is known, a second pass
            // over the same terms notes those that reach it. (Noting against
            // the bound so far, in one pass, kept 75 of 1,184 distances a
            // tile at 512², against 46.) Both passes run the same code: each
            // copy of a loop's terms is compile time, and the tile pass's
            // four (the list and the whole loop, each to step and to note)
            // were most of it.
            let _ = writeln!(out, "    for (var p{acc} = 0u; p{acc} < select(1u, 2u, g_loop_record && admitted); p{acc} = p{acc} + 1u) {{");
            let _ = writeln!(out, "    let n{acc} = p{acc} == 1u;");
            Some(at)
        } else {
            None
        };
        let _ = writeln!(out, "    if (g_loop_list != 0u && admitted) {{");
        self.emit_listed(out, l, at, acc, note, hook);
        out.push_str("    } else {\n");
        self.emit_whole(out, l, acc, whole, note, hook);
        out.push_str("    }\n");
        if note.is_some() {
            out.push_str("    }\n");
            // A refused enclosure noted nothing: the tile's notes are incomplete.
            out.push_str("    if (g_loop_record && !admitted) { g_loop_spoiled = true; }\n");
        }
        self.end(out, l, acc, strict, hook)
    }

    /// The loop's end: its chain node takes the accumulator.
    fn end(&mut self, out: &mut String, l: &Loop, acc: NodeId, strict: bool, hook: &mut impl FnMut(&mut String, Hook)) -> Option<String> {
        let _ = writeln!(out, "    let v{} = v{acc};", l.end);
        hook(out, Hook::End { acc, end: l.end });
        strict.then(|| format!("e{acc}"))
    }

    /// The table layout the domain reads.
    fn layout(&self, l: &Loop) -> reroll::Layout {
        match self.domain {
            Domain::Scalar => l.scalar(),
            _ => l.interval(),
        }
    }

    /// The loop over every term, `u` an iteration (the plan's unroll or a
    /// divisor of it that is a whole number of texel groups), into the
    /// accumulator; with `notes`, in the notes pass each term that may reach
    /// the accumulator's final value is noted instead (`loop_note`).
    fn emit_whole(&mut self, out: &mut String, l: &Loop, acc: NodeId, u: usize, notes: Option<&Listed>, hook: &mut impl FnMut(&mut String, Hook)) {
        let lay = self.layout(l);
        let p = self.domain.prefix();
        let iterations = l.iterations * l.unroll / u;
        let _ = writeln!(out, "    for (var i{acc} = 0u; i{acc} < select(0u, {iterations}u, admitted); i{acc} = i{acc} + 1u) {{");
        for k in 0..u {
            let (group, within) = (k / lay.group, k % lay.group);
            if within == 0 {
                let _ = writeln!(out, "    let j{acc}_{group} = {}u + (i{acc} * {}u + {group}u) * {}u;", lay.base, u / lay.group, lay.texels);
                for q in 0..lay.texels {
                    let _ = writeln!(out, "    let q{acc}_{group}_{q} = field_table(j{acc}_{group} + {q}u);");
                }
            }
            let term = self.emit_term(out, l, acc, |slot| reroll::slot_expr(p, |t| format!("q{acc}_{group}_{t}"), lay.offset(l.slots, within, slot), l.point_first), hook);
            self.note_or_step(out, l, acc, term, notes.map(|n| (n, format!("i{acc} * {u}u + {k}u"))), hook);
        }
        out.push_str("    }\n");
    }

    /// The loop over the tile's list: its words of bits, a term a set bit,
    /// each term's constants at its place in the table; with `notes`, as
    /// [`Self::emit_whole`]'s.
    fn emit_listed(&mut self, out: &mut String, l: &Loop, at: &Listed, acc: NodeId, notes: Option<&Listed>, hook: &mut impl FnMut(&mut String, Hook)) {
        let lay = self.layout(l);
        let p = self.domain.prefix();
        let _ = writeln!(out, "    let b{acc} = loop_bits() + {}u;", at.word);
        // A bound the compiler cannot see (`admitted` holds here): with a
        // constant one it unrolls a loop of a few words, and copies the body
        // into each, which lengthens the compile for nothing.
        let _ = writeln!(out, "    for (var w{acc} = 0u; w{acc} < select(0u, {}u, admitted); w{acc} = w{acc} + 1u) {{", at.words);
        let _ = writeln!(out, "    var m{acc} = loop_lists[b{acc} + w{acc}];");
        let _ = writeln!(out, "    loop {{\n    if (m{acc} == 0u) {{ break; }}");
        let _ = writeln!(out, "    let k{acc} = w{acc} * 32u + countTrailingZeros(m{acc});\n    m{acc} = m{acc} & (m{acc} - 1u);");
        let _ = writeln!(out, "    let j{acc} = {}u + k{acc} / {}u * {}u;", lay.base, lay.group, lay.texels);
        for q in 0..lay.texels {
            let _ = writeln!(out, "    let q{acc}_{q} = field_table(j{acc} + {q}u);");
        }
        if lay.group > 1 {
            // Several terms to a texel: the term's constants start at a float offset known only here.
            let _ = writeln!(out, "    let o{acc} = k{acc} % {}u * {}u;", lay.group, l.slots * lay.width);
        }
        let slot = |slot: usize| match lay.group {
            1 => reroll::slot_expr(p, |t| format!("q{acc}_{t}"), lay.offset(l.slots, 0, slot), l.point_first),
            _ => reroll::slot_expr_at(p, &format!("q{acc}_0"), &format!("o{acc} + {}u", slot * lay.width), l.point_first),
        };
        let term = self.emit_term(out, l, acc, slot, hook);
        self.note_or_step(out, l, acc, term, notes.map(|n| (n, format!("k{acc}"))), hook);
        out.push_str("    }\n    }\n");
    }

    /// A term's nodes, its constants from `slot`; returns the term's node.
    fn emit_term(&mut self, out: &mut String, l: &Loop, acc: NodeId, slot_of: impl Fn(usize) -> reroll::SlotRead, hook: &mut impl FnMut(&mut String, Hook)) -> NodeId {
        let p = self.domain.prefix();
        let mut map: Vec<(NodeId, NodeId)> = Vec::new();
        let mut slot = 0;
        for &b in &l.body {
            let op = self.ir.nodes[b as usize];
            let mut ops = Vec::new();
            for o in op.operands() {
                if let Some(&(_, f)) = map.iter().find(|(n, _)| *n == o) {
                    ops.push(f);
                } else if let Op::Const(_) = self.ir.nodes[o as usize] {
                    let f = self.fresh_id();
                    let reroll::SlotRead { expr, point } = slot_of(slot);
                    let _ = writeln!(out, "    let v{f} = {expr};");
                    hook(out, Hook::Slot { id: f, point });
                    slot += 1;
                    ops.push(f);
                } else {
                    ops.push(o);
                }
            }
            let f = self.fresh_id();
            let renamed = reroll::with_operands(op, &ops);
            let rhs = value_rhs(out, self.domain, f, renamed, self.ir, self.nn);
            let _ = writeln!(out, "    let v{f} = {rhs};");
            if op.restricts_domain() {
                let _ = writeln!(out, "    e{acc} = e{acc} || {p}_is_empty(v{f});");
            }
            hook(out, Hook::Node(f, renamed));
            map.push((b, f));
        }
        map.last().map(|&(_, f)| f).expect("a loop body is not empty")
    }

    /// After a term: the accumulator's step; with `note` (the loop's bits
    /// and the term's index in them), in the notes pass (`n{acc}`) the
    /// test that notes it instead.
    fn note_or_step(&mut self, out: &mut String, l: &Loop, acc: NodeId, term: NodeId, note: Option<(&Listed, String)>, hook: &mut impl FnMut(&mut String, Hook)) {
        let Some((at, index)) = note else {
            return self.emit_step(out, l, acc, term, hook);
        };
        let _ = writeln!(out, "    if (n{acc}) {{\n    if ({}) {{ loop_note({}u + {index}); }}\n    }} else {{", may_reach(self.domain.prefix(), l.op, term, acc), at.word * 32);
        self.emit_step(out, l, acc, term, hook);
        out.push_str("    }\n");
    }

    /// The chain's operation on the accumulator and `term`.
    fn emit_step(&mut self, out: &mut String, l: &Loop, acc: NodeId, term: NodeId, hook: &mut impl FnMut(&mut String, Hook)) {
        let next = self.fresh_id();
        let step = l.step(acc, term);
        let rhs = value_rhs(out, self.domain, next, step, self.ir, self.nn);
        let _ = writeln!(out, "    let v{next} = {rhs};");
        hook(out, Hook::Node(next, step));
        let _ = writeln!(out, "    v{acc} = v{next};");
        hook(out, Hook::Step { acc, next });
    }
}

/// Whether `term` may be the result of a min (max) loop over the region its
/// enclosure is for: its lower bound does not lie above the accumulator's
/// upper bound (for max: its upper bound below the lower). NaN keeps it.
fn may_reach(p: &str, op: Op, term: NodeId, acc: NodeId) -> String {
    match op {
        Op::Call2(crate::ir::Func2::Max, ..) => format!("!({p}_range(v{term}).y < {p}_range(v{acc}).x)"),
        _ => format!("!({p}_range(v{term}).x > {p}_range(v{acc}).y)"),
    }
}

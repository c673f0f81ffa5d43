//! A formula compiled into the kernel as a field source: its code is the
//! generated evaluators; it binds only what its loops over repeated terms
//! read (their constants' table and, bisecting, per-tile term lists).

use super::term_loops;
use crate::bindings::{Binding, Size, Slot, Statistics, TexelFormat};
use crate::field::{BindingRequest, CodeRequest, FieldSource, Refusal};
use crate::ir::Ir;

/// The rerolled terms' constants (`term_loops`), in rows of
/// `layout::TEXTURE_WIDTH` texels.
pub(crate) const TERM_TABLE: Slot = Slot::texture(0, "field table", "field_table_tex", TexelFormat::Rgba32Uint);
/// Bisection's per-tile term lists of min and max loops
/// (`templates/fields/loop_tiles.wgsl`).
pub(crate) const TERM_LISTS: Slot = Slot::storage(1, "loop lists", "loop_lists", "array<u32>", false);
/// Their counts for the statistics, zeroed before each dispatch.
pub(crate) const TERM_LIST_COUNTS: Slot = Slot::storage(4, "loop list counts", "loop_counts", "LoopListCounts", false);

/// Bytes of the term lists' counts (`LoopListCounts` in
/// `templates/fields/loop_tiles.wgsl`: four words).
pub const TERM_LIST_COUNT_BYTES: u64 = 16;

/// The largest compiled formula (live IR nodes, `isotrace check`'s
/// operations) whose bisection kernel gets the two-point root search by
/// default. A big f keeps the core busy on its own, so the second point
/// costs nearly what the first does: `@creature` (454 nodes) renders
/// faster with two points, `@city` (678) a little slower. A second copy of
/// f costs little compile.
pub const PAIR_MAX_NODES: usize = 500;

impl FieldSource for Ir {
    fn name(&self) -> &'static str {
        "compiled"
    }

    fn code(&self, r: &CodeRequest<'_>) -> String {
        // Bisection (a domain) runs the tile pass: rerolled min and max loops get per-tile lists.
        super::field_code(self, r.domain, r.inline, r.bundle, r.domain.is_some())
    }

    fn bindings(&self, r: &BindingRequest) -> Vec<Binding> {
        let mut table: Vec<Binding> = term_loops::table_texels(self).map(|t| TERM_TABLE.texels(t)).into_iter().collect();
        // The lists are bound for every kernel of the formula (one layout
        // whatever the traversal); only bisection's reads them, and a
        // kernel with `--inline` WGSL has none (the user owns its hooks).
        if let Some(lists) = term_loops::lists::for_formula(self) {
            let listed = r.bisect && !r.inline;
            // Every word of a tile's lists is written before it is read.
            table.push(TERM_LISTS.kept(if listed { Size::PerTile { bytes: lists.bytes(1) } } else { Size::Fixed { bytes: 16 } }));
            let counts = TERM_LIST_COUNTS.scratch(Size::Fixed { bytes: TERM_LIST_COUNT_BYTES });
            table.push(if listed { counts.reported(Statistics::TermLists) } else { counts });
        }
        table
    }

    fn surfaces(&self) -> usize {
        self.surfaces.len().max(1)
    }

    fn has_enclosures(&self) -> bool {
        true
    }

    fn takes_inline(&self) -> bool {
        true
    }

    /// A formula with term loops ([`super::midpoint::fused`]).
    fn cell_midpoint(&self) -> bool {
        let generated = super::generated_ir(self);
        super::midpoint::fused(generated.as_ref().unwrap_or(self))
    }

    /// A formula with rerolled loops and no per-tile term lists (sums),
    /// whose loops count against the interpreters' work limit. Each call
    /// site of f is a copy of its loops for lavapipe to compile, so one
    /// site brings a long looped sum's cold first frame noticeably sooner.
    /// A listed union keeps the inline cells: their scalar points are on
    /// the ray, where its squares come from their polynomials along it
    /// (`ray_forms`), and from one call site they are not (a union of a
    /// thousand ball distances renders markedly slower from one site).
    fn cells_resume(&self) -> bool {
        term_loops::table_texels(self).is_some() && term_loops::lists::for_formula(self).is_none()
    }

    fn resume_rounds(&self) -> u32 {
        crate::field::tape::resume_rounds(0)
    }

    fn pairs_root_search(&self) -> Option<bool> {
        Some(self.live().len() <= PAIR_MAX_NODES)
    }

    fn shares_loop_cap(&self) -> Option<&'static str> {
        term_loops::table_texels(self).is_some().then_some("a formula of rerolled terms (its loops share")
    }

    fn describe(&self) -> String {
        "the compiled formula".to_string()
    }

    fn replaces(&self, _kernel_name: &'static str, _kernel_features: u32) -> Result<(), Refusal> {
        Err(Refusal::new("compiled", "a compiled field is part of the shader: build a new renderer"))
    }
}

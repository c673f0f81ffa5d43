//! A tape as a field source: its instructions in a texture of the field
//! group, run by the interpreter in the traversal's domain; bisection's
//! tile pass shortens it per tile into lists of its own.

use super::{features, wgsl, TapeData};
use crate::bindings::{Binding, Size, Slot, Statistics, TexelFormat};
use crate::field::{BindingRequest, CodeRequest, FieldSource, Refusal};

/// The tape: header, value program, derivative program (`TapeData::texels`).
pub(crate) const TAPE_CODE: Slot = Slot::texture(0, "tape", "tape_code", TexelFormat::Rgba32Uint);
/// Bisection's per-tile shortened programs (`templates/fields/tape_tiles.wgsl`).
pub(crate) const TAPE_LISTS: Slot = Slot::storage(1, "tape lists", "tape_lists", "array<u32>", false);
/// Their counts, zeroed before the dispatch and read back for the statistics.
pub(crate) const TAPE_LIST_COUNTS: Slot = Slot::storage(4, "tape list words", "tape_counts", "TapeListCounts", false);
/// The choices the tile pass notes per tile and slab.
pub(crate) const TAPE_NOTES: Slot = Slot::storage(5, "tape notes", "tape_notes", "array<vec4<u32>>", false);

/// Bytes of the lists' counts (`TapeListCounts` in
/// `templates/fields/tape_tiles.wgsl`: eight words).
pub const TAPE_LIST_COUNT_BYTES: u64 = 32;

impl FieldSource for TapeData {
    fn name(&self) -> &'static str {
        "tape"
    }

    fn code(&self, r: &CodeRequest<'_>) -> String {
        // Bisecting on a device with subgroups, the interpreter counts its
        // work per SIMD bundle (features::BUNDLE_WORK).
        let bundle = if r.bundle && r.domain.is_some() { features::BUNDLE_WORK } else { 0 };
        wgsl::field_code(r.domain, self.features | bundle)
    }

    /// The lists are bound for every tape kernel, so one layout serves
    /// every tape; only bisection's tile pass fills them, other traversals
    /// get token buffers. A kernel built with per-tile lists (min and max)
    /// reads its blocks' entries there whatever tape it runs, so the lists
    /// are sized for the kernel's features.
    fn bindings(&self, r: &BindingRequest) -> Vec<Binding> {
        let mut table = vec![TAPE_CODE.texels(self.texels())];
        let sized = TapeData { features: self.features | (r.kernel_features & features::MINMAX), ..self.clone() };
        let lists = r.bisect && wgsl::shortens(sized.features);
        let list_size = if lists {
            let per_tile = 2 * (sized.words.len() as u64 + 4) * 4;
            Size::PerTileCapped { bytes: per_tile, at_most: wgsl::TAPE_LISTS_MAX_BYTES, plus: 16 }
        } else {
            Size::Fixed { bytes: 16 }
        };
        table.push(TAPE_LISTS.kept(list_size));
        let counts = TAPE_LIST_COUNTS.scratch(Size::Fixed { bytes: TAPE_LIST_COUNT_BYTES });
        // Reported where the tile pass may shorten this tape: it has min or max instructions.
        table.push(if lists && self.words[2][2] > 0 { counts.reported(Statistics::TapeLists) } else { counts });
        // Only a kernel with per-tile lists notes choices.
        table.push(TAPE_NOTES.kept(if lists { Size::PerTile { bytes: wgsl::NOTE_BYTES_PER_TILE } } else { Size::Fixed { bytes: 16 } }));
        table
    }

    fn has_enclosures(&self) -> bool {
        true
    }

    fn features(&self) -> u32 {
        self.features
    }

    fn cells_resume(&self) -> bool {
        true
    }

    fn resume_rounds(&self) -> u32 {
        super::resume_rounds(features::unroll(self.features))
    }

    fn block_pass(&self, kernel_features: u32) -> bool {
        wgsl::shortens(self.features | (kernel_features & features::MINMAX))
    }

    fn shares_loop_cap(&self) -> Option<&'static str> {
        Some("a tape field (its interpreter shares")
    }

    fn replaces(&self, kernel_name: &'static str, kernel_features: u32) -> Result<(), Refusal> {
        if kernel_name != self.name() {
            return Err(Refusal::new("field", "a field of another kind than the kernel was built for: build a new renderer"));
        }
        let step = features::unroll(kernel_features);
        if step > self.padding() {
            let reason = format!("the tape kernel runs {step} instructions an iteration, for long tapes, and this tape's programs are padded for {}: build a new renderer", self.padding());
            return Err(Refusal::new("tape", reason));
        }
        let missing = self.features & features::REQUIRED & !kernel_features;
        if missing != 0 {
            let mut what = features::names(missing);
            if missing & (features::SLOTS_32 | features::SLOTS_64) != 0 {
                what.push("more registers");
            }
            return Err(Refusal::new("tape", format!("the formula needs what the tape kernel was built without ({}): build a new renderer", what.join(", "))));
        }
        Ok(())
    }

    fn describe(&self) -> String {
        format!("a tape of {} instructions in the interpreter", self.ops)
    }
}

//! The viewer's present pass (`templates/view/present.wgsl`): its bind
//! group as one table, from which both the shader's declarations and the
//! page's bind group ([`PresentGroup`], sent in the program) are made, so a
//! binding number is written once.

use crate::bindings::{declarations_in, Slot};
use crate::layout::{GpuBlock, PresentBlock};
use serde::Serialize;

/// The present pass's bind group index.
pub const PRESENT_GROUP: u32 = 0;

/// The frame's pixel records in their two planes
/// (templates/shared/pixels.wgsl): heads, then tails.
pub const RECORDS: Slot = Slot::storage(0, "present records", "records", "array<vec2<u32>>", true);
/// The present block ([`PresentBlock`]).
pub const UNIFORMS: Slot = Slot::uniform(1, "present uniforms", "P", PresentBlock::WGSL_NAME);
/// A scene's selected node traced alone with the same kernel (its own
/// field buffers, no new pipeline): where its depth equals the scene's,
/// the visible surface is the selection's.
pub const SELECTION: Slot = Slot::storage(2, "selection records", "selection", "array<vec2<u32>>", true);

/// The present pass's table: each slot with the resource the page binds there.
const TABLE: [(&Slot, Source); 3] = [(&RECORDS, Source::Records), (&UNIFORMS, Source::Uniforms), (&SELECTION, Source::Selection)];

/// Which of the page's resources a binding of the present pass takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    /// The records of the frame's pass group.
    Records,
    /// The page's present block, written every frame.
    Uniforms,
    /// The records of the selection's trace (the frame's own without one).
    Selection,
}

/// One binding of the present pass.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct PresentBinding {
    /// Binding index.
    pub binding: u32,
    /// What the page binds there.
    pub source: Source,
}

/// The present pass's bind group as the page makes it.
#[derive(Debug, Clone, Serialize)]
pub struct PresentGroup {
    /// Its group index.
    pub group: u32,
    /// Its bindings.
    pub bindings: Vec<PresentBinding>,
}

/// The present pass's bind group.
pub fn group() -> PresentGroup {
    PresentGroup { group: PRESENT_GROUP, bindings: TABLE.iter().map(|(s, source)| PresentBinding { binding: s.binding, source: *source }).collect() }
}

/// The present shader with its generated uniform block, constants and
/// bindings, validated by naga like every shader isotrace hands to a
/// driver.
pub fn present_shader() -> Result<String, crate::validate::ValidateError> {
    let header = format!("{}\n{}", PresentBlock::wgsl(), crate::layout::wgsl_constants());
    let slots: Vec<&Slot> = TABLE.iter().map(|(s, _)| *s).collect();
    let bindings = declarations_in(PRESENT_GROUP, &slots);
    let wgsl = crate::codegen::template::splice(PRESENT, &[("uniforms", &header), ("bindings", &bindings)]).expect("the present template has its markers");
    crate::validate::validate(&wgsl)?;
    Ok(wgsl)
}

/// `templates/view/present.wgsl`.
const PRESENT: &str = include_str!("../../templates/view/present.wgsl");

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn the_page_binds_what_the_shader_declares() {
        let module = naga::front::wgsl::parse_str(&present_shader().expect("validates")).expect("parses");
        let declared: BTreeSet<[u32; 2]> = module.global_variables.iter().filter_map(|(_, g)| g.binding.as_ref().map(|b| [b.group, b.binding])).collect();
        let g = group();
        let listed: BTreeSet<[u32; 2]> = g.bindings.iter().map(|b| [g.group, b.binding]).collect();
        assert_eq!(declared, listed);
        let sources: BTreeSet<String> = g.bindings.iter().map(|b| format!("{:?}", b.source)).collect();
        assert_eq!(sources.len(), g.bindings.len(), "one binding a source");
    }
}

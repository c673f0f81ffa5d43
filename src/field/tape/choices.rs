//! Choice slots: where bisection's tile pass notes, per 8×8 tile, which
//! operand each min and max of a tape can take over the tile's candidate
//! slabs, and whether each domain-restricting square root or logarithm's
//! argument stays in its domain (`templates/fields/tape_tiles.wgsl` shortens
//! the tape per tile from them).

use super::{Builder, Code};

/// Whether the instruction with first word `w0` is of the min/max group (in
/// a value program: a min, max, clamp, abs or sign).
pub fn is_minmax(w0: u32) -> bool {
    super::features::group_of(w0) == super::features::MINMAX
}

/// Choice slots the tile pass keeps per tile (two bits each; 4,096 slots
/// are the tile's 1 KB of notes). A min or max past them is never
/// shortened. 512 slots left most of a union of 145 boxes (four copies of
/// `@city`'s blocks: about 900 min and max in its value program) without
/// one, and its tiles kept most of the tape.
pub const TAPE_CHOICE_SLOTS: u32 = 4096;
/// The immediate of a min or max without a slot.
pub const TAPE_NO_SLOT: u32 = u32::MAX;

/// Gives every min and max node a choice slot, in node order (the value
/// program's come first: the derivative's nodes are built after them), and
/// each `Dmin`/`Dmax` the slot of the min or max of the same operands: the
/// derivative of min(a, b) is da wherever min(a, b) is a. The formula's own
/// square roots and logarithms get one too: they restrict f's domain, so a
/// tile keeps them even in a dead operand unless their argument stays in
/// their domain over the tile (every box distance has a square root of a
/// sum of squares). Returns how many slots are in use.
pub(super) fn choice_slots(b: &mut Builder) -> u32 {
    let mut next = 0;
    for (i, n) in b.nodes.iter().enumerate() {
        let strict_root = matches!(n.code, Code::Sqrt | Code::Log) && b.strict.contains(&(i as u32));
        if (matches!(n.code, Code::Min | Code::Max) || strict_root) && next < TAPE_CHOICE_SLOTS {
            b.slots.insert(i as u32, next);
            next += 1;
        }
    }
    for (i, n) in b.nodes.iter().enumerate() {
        let value = match n.code {
            Code::Dmin => Code::Min,
            Code::Dmax => Code::Max,
            _ => continue,
        };
        let key = (value as u8, [n.args[0], n.args[1], 0, 0], 0f64.to_bits());
        if let Some(slot) = b.seen.get(&key).and_then(|v| b.slots.get(v)).copied() {
            b.slots.insert(i as u32, slot);
        }
    }
    next
}


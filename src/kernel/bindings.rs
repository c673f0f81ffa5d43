//! The traversals' bind group tables: the frame group (`@group(0)`: the
//! uniforms and bisection's environment image, alive as long as a frame)
//! and the pass group (`@group(2)`: the pixel records and a traversal's
//! per-dispatch buffers). The kernel's WGSL declarations, the device's
//! layouts (`gpu::bisect`, `gpu::sphere`) and the page's program are made
//! from these constants.

use crate::bindings::{declarations_in, Slot};

/// The frame group's index.
pub const FRAME_GROUP: u32 = 0;
/// The pass group's index.
pub const PASS_GROUP: u32 = 2;

/// The frame block and the traversal's block (`layout`), read once per
/// invocation into private copies (`load_uniforms`).
pub const UNIFORMS: Slot = Slot::storage(0, "uniforms", "Ubuf", "Uniforms", true);
/// Bisection's environment image for reflections and the background
/// (equirectangular, rgba8 packed; one dummy texel when it is procedural).
pub const ENVIRONMENT: Slot = Slot::storage(1, "environment", "env_image", "array<u32>", true);
/// Every pixel's record, written by the per-pixel pass (`render::record`).
pub const PIXEL_RECORDS: Slot = Slot::storage(0, "pixel records", "pixels", "array<vec2<u32>>", false);
/// Bisection: per 8×8 tile, the tile pass's candidate slabs.
pub const TILE_MASKS: Slot = Slot::storage(1, "tile masks", "tile_masks", "array<vec4<u32>>", false);
/// The tiles a tile pass queued and the indirect dispatch of `main` over them.
pub const TILE_LIST: Slot = Slot::storage(2, "tile list", "tile_list", "TileList", false);
/// The queued tiles' ids.
pub const TILE_IDS: Slot = Slot::storage(3, "tile ids", "tile_ids", "array<u32>", false);
/// Bisection: per pixel, its state across the rounds of a resumable `main`.
pub const RESUME_STATES: Slot = Slot::storage(4, "resume states", "resume", "array<vec4<u32>>", false);
/// Sphere tracing: per ray, its statistics word (`render::record::RayStats`).
pub const RAY_STATS: Slot = Slot::storage(1, "ray statistics", "ray_stats", "array<u32>", false);

/// The declarations every render kernel has.
pub(crate) fn shared() -> String {
    format!("{}{}", declarations_in(FRAME_GROUP, &[&UNIFORMS]), declarations_in(PASS_GROUP, &[&PIXEL_RECORDS]))
}

/// Bisection's own declarations.
pub(crate) fn bisect() -> String {
    format!("{}{}", declarations_in(FRAME_GROUP, &[&ENVIRONMENT]), declarations_in(PASS_GROUP, &[&TILE_MASKS, &TILE_LIST, &TILE_IDS, &RESUME_STATES]))
}

/// Sphere tracing's own declarations, with its tile pass's (`tiles`).
pub(crate) fn sphere(tiles: bool) -> String {
    let tile_pass: &[&Slot] = if tiles { &[&TILE_LIST, &TILE_IDS] } else { &[] };
    format!("{}{}", declarations_in(PASS_GROUP, &[&RAY_STATS]), declarations_in(PASS_GROUP, tile_pass))
}

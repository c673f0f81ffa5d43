//! A blobtree scene as a field source: nodes and parameters as data
//! textures, primitives and bounding balls as buffers, and the per-tile
//! lists and pruned node lists its two passes build every dispatch.

use super::{SceneData, SceneKernel, SCENE_PASSES, SCENE_TILE_MAX, SCENE_PRUNED_MAX, SCENE_PRUNED_TEX_WIDTH};
use crate::bindings::{Binding, Copy, Groups, Size, Slot, Stage, Statistics, TexelFormat, FIELD_GROUP};
use crate::field::{BindingRequest, CodeRequest, FieldEdit, FieldSource, FieldWrite, Refusal};
use crate::scene::linear::ScenePatch;

/// Node words (`templates/fields/scene.wgsl` says their layout).
pub(crate) const NODES: Slot = Slot::texture(0, "scene nodes", "scene_nodes", TexelFormat::Rgba32Uint);
/// Node parameters: a primitive's transform rows and form, an operator's ranges.
pub(crate) const PARAMS: Slot = Slot::texture(1, "scene params", "scene_params", TexelFormat::Rgba32Float);
/// Per primitive: its node index.
pub(crate) const PRIMS: Slot = Slot::storage(2, "scene primitives", "scene_prims", "array<u32>", true);
/// Per primitive: its augmented bounding ball (centre, radius).
pub(crate) const BALLS: Slot = Slot::storage(3, "scene balls", "scene_balls", "array<vec4<f32>>", true);
/// Per tile: how many primitives its list holds (zeroed each dispatch).
pub(crate) const TILE_COUNTS: Slot = Slot::storage(4, "scene tile counts", "scene_tile_count", "array<atomic<u32>>", false);
/// Per tile: its active primitives.
pub(crate) const TILE_PRIMS: Slot = Slot::storage(5, "scene tile primitives", "scene_tile_prims", "array<u32>", false);
/// Per tile: its slab table and pruned node lists, as the pruning pass writes them.
pub(crate) const TILE_PRUNED: Slot = Slot::storage(6, "scene tile pruned trees", "scene_tile_pruned", "array<u32>", false);
/// Per tile, for the statistics: its node lists' length and its active count.
pub(crate) const TILE_STATS: Slot = Slot::storage(7, "scene tile statistics", "scene_tile_len", "array<vec2<u32>>", false);
/// Per entry of a tile's list: the depths its primitive's ball spans.
pub(crate) const TILE_DEPTHS: Slot = Slot::storage(9, "scene tile depths", "scene_tile_depth", "array<vec2<f32>>", false);
/// `TILE_PRUNED` copied into a texture, which the trace reads a texel at a
/// time (lavapipe loads storage at a per-lane address lane by lane).
pub(crate) const PRUNED_TEXELS: Slot = Slot::texture(10, "scene tile pruned texels", "scene_pruned_tex", TexelFormat::R32Uint);

/// The formula leaves' tapes (`leaves::texels`; a token texel without leaves).
pub(crate) const TAPES: Slot = Slot::texture(11, "scene formula tapes", "scene_tapes", TexelFormat::Rgba32Uint);

/// The declarations the interpreter uses.
pub(crate) fn interpreter_declarations() -> String {
    crate::bindings::declarations(&[&NODES, &PARAMS, &PRIMS, &BALLS, &PRUNED_TEXELS])
}

/// The declarations the tile passes use.
fn tile_declarations() -> String {
    crate::bindings::declarations(&[&TILE_COUNTS, &TILE_PRIMS, &TILE_PRUNED, &TILE_STATS, &TILE_DEPTHS])
}

impl FieldSource for SceneData {
    fn name(&self) -> &'static str {
        "scene"
    }

    /// Bisecting, the interpreter runs on intervals too, in IA whatever the
    /// domain asked (a scene's nodes have no affine forms; the CLI refuses
    /// `--algebra raa` for scenes).
    fn code(&self, r: &CodeRequest<'_>) -> String {
        let kernel = match r.domain {
            Some(_) => SceneKernel::Bisect { bundle: r.bundle },
            None => SceneKernel::Sphere { sync: r.sync },
        };
        format!("{}\n{}{}", super::scene_interpreter(self.features, kernel), tile_declarations(), crate::codegen::template::SCENE_TILES)
    }

    fn bindings(&self, _: &BindingRequest) -> Vec<Binding> {
        let tile_list = Size::PerTile { bytes: SCENE_TILE_MAX as u64 * 4 };
        let pruned = Size::PerTile { bytes: SCENE_PRUNED_MAX as u64 * 4 };
        vec![
            NODES.texels(self.node_texels()),
            PARAMS.texels(self.param_texels()),
            PRIMS.data(self.prims.clone()),
            BALLS.data(bytemuck::cast_slice(&self.balls).to_vec()),
            TILE_COUNTS.scratch(Size::PerTile { bytes: 4 }),
            // Only the counts must start at zero: the rest is written before it is read.
            TILE_PRIMS.kept(tile_list),
            TILE_PRUNED.kept(pruned),
            TILE_STATS.kept(Size::PerTile { bytes: 8 }).reported(Statistics::TileLists),
            TILE_DEPTHS.kept(Size::PerTile { bytes: SCENE_TILE_MAX as u64 * 8 }),
            PRUNED_TEXELS.copied(SCENE_PRUNED_TEX_WIDTH, pruned),
            TAPES.texels(crate::layout::Texels::from_rows(None, &super::leaves::texels(self))),
        ]
    }

    /// The scatter runs an invocation per primitive, the pruning pass one
    /// per tile; the pruning pass hands its lists over as a texture.
    fn passes(&self) -> Vec<Stage> {
        let copy = Some(Copy { group: FIELD_GROUP, from: TILE_PRUNED.binding, to: PRUNED_TEXELS.binding });
        vec![
            Stage::new(SCENE_PASSES[0], Groups::Items { binding: PRIMS.binding, per_group: 64 }),
            Stage { copy, ..Stage::new(SCENE_PASSES[1], Groups::Tiles { per_group: 64 }) },
        ]
    }

    /// Interval enclosures of every node type
    /// (templates/fields/scene_enclosure.wgsl).
    fn has_enclosures(&self) -> bool {
        true
    }

    fn shares_loop_cap(&self) -> Option<&'static str> {
        Some("a scene field (its interpreter shares")
    }

    fn features(&self) -> u32 {
        self.features
    }

    fn lists_tiles(&self) -> bool {
        true
    }

    fn frame_flags(&self, dense: bool) -> u32 {
        if dense { crate::layout::FLAG_SCENE_FULL } else { 0 }
    }

    fn replaces(&self, kernel_name: &'static str, kernel_features: u32) -> Result<(), Refusal> {
        if kernel_name != self.name() {
            return Err(Refusal::new("field", "a field of another kind than the kernel was built for: build a new renderer"));
        }
        if self.features & !kernel_features != 0 {
            return Err(Refusal::new("scene", "the scene uses node types the kernel was built without (profiles, unary nodes, infill, displacement or formula leaves): build a new renderer"));
        }
        Ok(())
    }

    fn describe(&self) -> String {
        "a scene".to_string()
    }
}

/// An edit in place (`Linear::set_primitive`) writes the changed parameter
/// rows and bounding balls, nothing else.
impl FieldEdit for ScenePatch {
    fn writes(&self) -> Vec<FieldWrite> {
        let mut writes = vec![FieldWrite::Texels { binding: PARAMS.binding, first: self.param_row as u64, texels: self.params.clone() }];
        writes.extend(self.balls.iter().map(|(i, b)| FieldWrite::Bytes { binding: BALLS.binding, offset: *i as u64 * 16, bytes: bytemuck::cast_slice(&[*b]).to_vec() }));
        writes
    }
}

//! What the page needs to run a render kernel with WebGPU, as data: the
//! validated WGSL, the uniform blocks' fields and offsets (from
//! [`crate::layout`]), the three bind groups by lifetime with the size rule
//! of every buffer, and the stages of one dispatch in the order
//! [`crate::gpu::dispatch`] runs them. The page's host is a loop over this
//! description; it knows no traversal and no field source.
//!
//! The sizes and stages mirror the device host (`gpu::renderer::Renderer::stages`,
//! `TraversalHost::pass_buffers`, `gpu::field`); the browser tests compare
//! the page's pixels with `isotrace render`, so a drift shows there.

use crate::field::scene::{SCENE_TILE_MAX, SCENE_VIEW_MAX, SCENE_VIEW_TEX_WIDTH};
use crate::field::FieldSource;
use crate::kernel;
use crate::gpu::renderer::{uniform_bytes, RenderError, MAX_SHADER_BYTES};
use crate::layout::{BisectBlock, FieldLayout, FrameBlock, GpuBlock, PresentBlock, SphereBlock};
use crate::render::{Settings, Traversal};
use serde::Serialize;

/// How large a buffer is, for a frame of w × h pixels.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Size {
    /// The uniform bytes (frame block, then the traversal block).
    Uniforms,
    /// The words in `data`.
    Data,
    /// `bytes` per pixel.
    PerPixel {
        /// Bytes.
        bytes: u64,
    },
    /// `bytes` per 8×8 tile.
    PerTile {
        /// Bytes.
        bytes: u64,
    },
    /// A fixed size.
    Fixed {
        /// Bytes.
        bytes: u64,
    },
}

/// A sampled 2D texture of 32-bit texels: a scene's nodes and parameters
/// (vec4 texels, `data` given row by row), or a scratch texture filled by a
/// stage's copy (its rows: as many as its size rule's bytes need).
#[derive(Debug, Clone, Serialize)]
pub struct TextureShape {
    /// Texels per row.
    pub width: u32,
    /// Rows (0 for a scratch texture: from its size rule).
    pub height: u32,
    /// `rgba32uint`, `rgba32float` or `r32uint` (the WebGPU format name).
    pub format: &'static str,
}

/// A copy after a stage: a buffer it wrote into a scratch texture of the
/// same group, whole rows (the source buffer is made at least that large).
#[derive(Debug, Clone, Serialize)]
pub struct Copy {
    /// The bind group of both.
    pub group: u32,
    /// The buffer's binding.
    pub from: u32,
    /// The texture's binding.
    pub to: u32,
}

/// One resource of a bind group: a storage buffer (the smallest is 16
/// bytes) or, with `texture`, a sampled texture.
#[derive(Debug, Clone, Serialize)]
pub struct Binding {
    /// Binding index.
    pub binding: u32,
    /// What it holds (for the page's messages and the tests).
    pub name: &'static str,
    /// Read-only or read-write storage.
    pub read_only: bool,
    /// Its size rule.
    pub size: Size,
    /// Its contents as 32-bit words (f32 as bits), for `Size::Data`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub data: Option<Vec<u32>>,
    /// A tile pass's queue: reset to (0, 1, 1) before the dispatch and
    /// copied into the indirect arguments of the stage that reads it.
    pub indirect: bool,
    /// Zeroed before every dispatch: the device host makes these buffers
    /// anew per dispatch (a scene's tile counts are appended to).
    pub clear: bool,
    /// A sampled texture holding `data` instead of a buffer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texture: Option<TextureShape>,
}

/// How many workgroups a stage runs for a w × h frame.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Groups {
    /// One per `per_group` words of field binding `binding` (a scene's
    /// primitives), x first, then y past 65,535.
    Items {
        /// The field binding counted.
        binding: u32,
        /// Items per workgroup.
        per_group: u32,
    },
    /// One per `per_group` 8×8 tiles, in x.
    Tiles {
        /// Tiles per workgroup.
        per_group: u32,
    },
    /// One per `side` × `side` pixels (bisection's tile pass: 64; a
    /// tape's block pass: 128), `layers` deep (the block pass: 2).
    Blocks {
        /// Side in pixels.
        side: u32,
        /// Workgroups in z.
        layers: u32,
    },
    /// One per 8×8 tile in x and per `tiles_per_group` tile rows in y.
    PixelTiles {
        /// Tile rows per workgroup.
        tiles_per_group: u32,
    },
    /// The counts a tile pass left in pass binding `binding`.
    Indirect {
        /// The pass-group binding of the queue.
        binding: u32,
    },
}

/// One compute pass of a dispatch.
#[derive(Debug, Clone, Serialize)]
pub struct Stage {
    /// The WGSL entry point.
    pub entry: &'static str,
    /// Its workgroups.
    pub groups: Groups,
    /// The (group, binding) pairs the entry point uses, from naga's
    /// analysis: the page binds only these per stage, because WebGPU
    /// counts every binding of a layout against the per-stage limit (a
    /// scene's kernel binds 10 storage buffers in all, at most 8 in one stage).
    pub uses: Vec<[u32; 2]>,
    /// A copy to run after the stage (a scene's views into the texture the
    /// trace reads them from, as `gpu::field::PerDispatch::view_copy`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub copy: Option<Copy>,
}

/// The uniform blocks: the frame block at offset 0, the traversal's after it.
#[derive(Debug, Clone, Serialize)]
pub struct Blocks {
    /// `Frame` fields.
    pub frame: Vec<FieldLayout>,
    /// The traversal block's WGSL name (`Bisect`, `Sphere`).
    pub traversal_name: &'static str,
    /// Its byte offset.
    pub traversal_offset: usize,
    /// Its fields.
    pub traversal: Vec<FieldLayout>,
    /// The present pass's block (`templates/view/present.wgsl`).
    pub present: Vec<FieldLayout>,
}

/// Which values of the traversal block follow the camera or eps, so the
/// page recomputes them as `gpu::bisect::block` / `gpu::sphere::block` do.
#[derive(Debug, Clone, Serialize)]
pub struct Follow {
    /// The light follows the camera (no `--light`).
    pub light: bool,
    /// The shadow eps (bisection) or eps-min (sphere tracing) is a
    /// multiple of eps (none given): this multiple.
    pub eps_factor: Option<f64>,
}

/// A render kernel and everything the page needs to run it.
#[derive(Debug, Clone, Serialize)]
pub struct Program {
    /// `bisect` or `sphere`.
    pub method: &'static str,
    /// The validated module.
    pub wgsl: String,
    /// Uniform layouts.
    pub blocks: Blocks,
    /// The uniform bytes of the first frame, as words.
    pub uniforms: Vec<u32>,
    /// Frame, field and pass groups.
    pub groups: [Vec<Binding>; 3],
    /// The passes of one dispatch, in order.
    pub stages: Vec<Stage>,
    /// Values the page recomputes.
    pub follow: Follow,
    /// The pass-group binding of the per-ray statistics words (sphere
    /// tracing's `record::RayStats`), which the page reads for the CLI's
    /// Lipschitz warning.
    pub ray_stats: Option<u32>,
}

fn words<T: bytemuck::Pod>(v: &[T]) -> Vec<u32> {
    bytemuck::cast_slice::<T, u8>(v).chunks(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect()
}

fn data(binding: u32, name: &'static str, d: Vec<u32>) -> Binding {
    Binding { binding, name, read_only: true, size: Size::Data, data: Some(d), indirect: false, clear: false, texture: None }
}

fn texture<T: bytemuck::Pod>(binding: u32, name: &'static str, t: crate::field::Texels<T>, format: &'static str) -> Binding {
    Binding { texture: Some(TextureShape { width: t.width, height: t.height, format }), ..data(binding, name, words(&t.texels)) }
}

fn scratch(binding: u32, name: &'static str, size: Size) -> Binding {
    Binding { binding, name, read_only: false, size, data: None, indirect: false, clear: true, texture: None }
}

/// A scratch buffer its stages write before they read it: not zeroed.
fn kept(binding: u32, name: &'static str, size: Size) -> Binding {
    Binding { clear: false, ..scratch(binding, name, size) }
}

/// Sphere tracing's per-ray statistics in the pass group
/// (`gpu::sphere`'s `ray_stats_binding`).
const RAY_STATS_BINDING: u32 = 1;

/// Assembles, checks the size limit of the CLI, validates with naga and
/// describes the kernel of `field` traced by `traversal` for settings `s`.
pub fn program(field: FieldSource<'_>, traversal: &Traversal, s: &Settings) -> Result<Program, RenderError> {
    traversal.check()?;
    if matches!(traversal, Traversal::Bisect(_)) && !field.has_enclosures() {
        return Err(crate::render::SettingsError::new(crate::render::SettingsField::Features, "bisect", "this field has no interval enclosures: render it with sphere tracing").into());
    }
    let kernel = kernel::assemble(field, traversal);
    if kernel.code_bytes() > MAX_SHADER_BYTES {
        return Err(RenderError::ShaderTooLarge { bytes: kernel.code_bytes() });
    }
    let module = crate::validate::validate(&kernel.wgsl)?;
    let uniforms = uniforms(traversal, s)?;
    let mut frame = vec![Binding { binding: 0, name: "uniforms", read_only: true, size: Size::Uniforms, data: None, indirect: false, clear: false, texture: None }];
    // Every pixel's record is written: no need to clear 16 bytes a pixel.
    let mut pass = vec![Binding { clear: false, ..scratch(0, "pixel records", Size::PerPixel { bytes: 16 }) }];
    let mut stages: Vec<Stage> = Vec::new();
    let field_group = match field {
        // Rerolled terms read their constants from a table (crate::field::compiled::term_loops).
        FieldSource::Compiled(ir) => {
            let mut group: Vec<Binding> = crate::field::compiled::term_loops::table_texels(ir).map(|t| texture(0, "field table", t, "rgba32uint")).into_iter().collect();
            // Bisection's per-tile term lists of min and max loops
            // (fields/loop_tiles.wgsl): every word is written before it is read.
            if let (Some(l), Traversal::Bisect(_)) = (crate::field::compiled::term_loops::lists::for_formula(ir), traversal) {
                group.push(kept(1, "loop lists", Size::PerTile { bytes: l.bytes(1) }));
                group.push(scratch(4, "loop list counts", Size::Fixed { bytes: 16 }));
            }
            group
        }
        FieldSource::Tape(t) => {
            let mut group = vec![texture(0, "tape", t.texels(), "rgba32uint")];
            if matches!(traversal, Traversal::Bisect(_)) {
                // Bisection's per-tile lists (fields/tape_tiles.wgsl) for the
                // frame's tiles; a tile that does not fit runs the whole tape.
                let tiles = u64::from(s.width.div_ceil(8)) * u64::from(s.height.div_ceil(8));
                let bytes = crate::field::tape::wgsl::list_bytes(t, tiles).max(16);
                group.push(kept(1, "tape lists", Size::Fixed { bytes }));
                group.push(scratch(4, "tape list words", Size::Fixed { bytes: 32 }));
                // Only a kernel with per-tile lists notes choices.
                let notes = if crate::field::tape::wgsl::shortens(t.features) { Size::PerTile { bytes: crate::field::tape::wgsl::NOTE_BYTES_PER_TILE } } else { Size::Fixed { bytes: 16 } };
                group.push(kept(5, "tape notes", notes));
            }
            group
        }
        FieldSource::Scene(d) => {
            stages.push(Stage { entry: "scene_scatter", groups: Groups::Items { binding: 2, per_group: 64 }, uses: vec![], copy: None });
            let copy = Some(Copy { group: 1, from: 6, to: 10 });
            stages.push(Stage { entry: "scene_views", groups: Groups::Tiles { per_group: 64 }, uses: vec![], copy });
            let mut group = scene_buffers(d);
            group.extend([
                scratch(4, "scene tile counts", Size::PerTile { bytes: 4 }),
                // Only the counts must start at zero (gpu::field::PerDispatch):
                // the rest is written before it is read.
                kept(5, "scene tile primitives", Size::PerTile { bytes: SCENE_TILE_MAX as u64 * 4 }),
                kept(6, "scene tile views", Size::PerTile { bytes: SCENE_VIEW_MAX as u64 * 4 }),
                kept(7, "scene tile statistics", Size::PerTile { bytes: 8 }),
                kept(9, "scene tile depths", Size::PerTile { bytes: SCENE_TILE_MAX as u64 * 8 }),
                Binding {
                    read_only: true,
                    clear: false,
                    texture: Some(TextureShape { width: SCENE_VIEW_TEX_WIDTH, height: 0, format: "r32uint" }),
                    ..scratch(10, "scene tile view texels", Size::PerTile { bytes: SCENE_VIEW_MAX as u64 * 4 })
                },
            ]);
            group
        }
    };
    let (method, blocks, follow) = match traversal {
        Traversal::Bisect(b) => {
            let texels = match &b.modalities.env {
                crate::render::Environment::Image(e) => e.texels.clone(),
                _ => vec![0],
            };
            frame.push(data(1, "environment", texels));
            pass.push(scratch(1, "tile masks", Size::PerTile { bytes: 16 }));
            pass.extend(tile_list());
            // Zeroed every frame: the page runs one round of `main`, so a
            // pixel past a tape's work limit stays unresolved there.
            pass.push(scratch(4, "resume states", Size::PerPixel { bytes: 16 }));
            let tpg = crate::gpu::bisect::TILES_PER_GROUP;
            if b.optimizations.tile_culling {
                // A tape's block pass (the tile pass's entry point, two
                // layers deep: gpu::renderer dispatches it the same way).
                if matches!(field, FieldSource::Tape(t) if crate::field::tape::wgsl::shortens(t.features)) {
                    stages.push(Stage { entry: "tiles", groups: Groups::Blocks { side: 128, layers: 2 }, uses: vec![], copy: None });
                }
                stages.extend(tile_pass());
            } else {
                stages.push(Stage { entry: "main", groups: Groups::PixelTiles { tiles_per_group: tpg }, uses: vec![], copy: None });
            }
            let m = &b.modalities;
            ("bisect", blocks::<BisectBlock>(), Follow { light: m.light.is_none(), eps_factor: m.shadow_eps.is_none().then_some(4.0) })
        }
        Traversal::Sphere(o) => {
            pass.push(scratch(RAY_STATS_BINDING, "ray statistics", Size::PerPixel { bytes: 4 }));
            if kernel::sphere_tile_pass(field) {
                // The tile pass leaves the tiles without primitives out of `main`.
                pass.extend(tile_list());
                stages.extend(tile_pass());
            } else {
                stages.push(Stage { entry: "main", groups: Groups::PixelTiles { tiles_per_group: 1 }, uses: vec![], copy: None });
            }
            ("sphere", blocks::<SphereBlock>(), Follow { light: true, eps_factor: o.eps_min.is_none().then_some(1.0) })
        }
    };
    let uses = binding_uses(&module);
    for st in &mut stages {
        st.uses = uses.iter().find(|(e, _)| e == st.entry).map(|(_, u)| u.clone()).unwrap_or_default();
    }
    let ray_stats = matches!(traversal, Traversal::Sphere(_)).then_some(RAY_STATS_BINDING);
    Ok(Program { method, wgsl: kernel.wgsl, blocks, uniforms, groups: [frame, field_group, pass], stages, follow, ray_stats })
}

/// The uniform words of the first frame of `traversal` with settings `s`
/// (a scene edit changes them without a new kernel: its Lipschitz bound).
pub fn uniforms(traversal: &Traversal, s: &Settings) -> Result<Vec<u32>, RenderError> {
    Ok(words(&uniform_bytes(traversal, s)?))
}

/// A tile pass's list (the indirect dispatch counts of `main`, binding 2)
/// and queued tile ids (binding 3) in the pass group.
fn tile_list() -> [Binding; 2] {
    [Binding { indirect: true, clear: false, ..scratch(2, "tile list", Size::Fixed { bytes: 16 }) }, scratch(3, "tile ids", Size::PerTile { bytes: 4 })]
}

/// The tile pass (one invocation per 8×8 tile) and `main` by indirect
/// dispatch over the tiles it queued.
fn tile_pass() -> [Stage; 2] {
    [
        Stage { entry: "tiles", groups: Groups::Blocks { side: 64, layers: 1 }, uses: vec![], copy: None },
        Stage { entry: "main", groups: Groups::Indirect { binding: 2 }, uses: vec![], copy: None },
    ]
}

/// Every entry point's used resource bindings (naga's per-entry-point
/// global usage).
fn binding_uses(module: &naga::Module) -> Vec<(String, Vec<[u32; 2]>)> {
    let mut v = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all());
    let Ok(info) = v.validate(module) else { return vec![] };
    module
        .entry_points
        .iter()
        .enumerate()
        .map(|(i, ep)| {
            let ei = info.get_entry_point(i);
            let used = module.global_variables.iter().filter(|(h, _)| !ei[*h].is_empty()).filter_map(|(_, g)| g.binding.as_ref().map(|b| [b.group, b.binding])).collect();
            (ep.name.clone(), used)
        })
        .collect()
}

fn blocks<T: GpuBlock>() -> Blocks {
    Blocks {
        frame: FrameBlock::fields(),
        traversal_name: T::WGSL_NAME,
        traversal_offset: std::mem::size_of::<FrameBlock>(),
        traversal: T::fields(),
        present: PresentBlock::fields(),
    }
}

/// The scene buffers of the field group alone (an edit: no shader).
pub fn scene_buffers(d: &crate::field::SceneData) -> Vec<Binding> {
    vec![
        texture(0, "scene nodes", d.node_texels(), "rgba32uint"),
        texture(1, "scene params", d.param_texels(), "rgba32float"),
        data(2, "scene primitives", words(&d.prims)),
        data(3, "scene balls", words(&d.balls)),
    ]
}

/// The present shader with its generated uniform block and constants,
/// validated by naga like every shader isotrace hands to a driver.
pub fn present_shader() -> Result<String, crate::validate::ValidateError> {
    let header = format!("{}\n{}", PresentBlock::wgsl(), crate::layout::wgsl_constants());
    let wgsl = crate::codegen::template::splice(PRESENT, &[("uniforms", &header)]).expect("the present template has its marker");
    crate::validate::validate(&wgsl)?;
    Ok(wgsl)
}

/// `templates/view/present.wgsl`.
const PRESENT: &str = include_str!("../../templates/view/present.wgsl");

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

use crate::kernel::bindings::{ENVIRONMENT, PIXEL_RECORDS, RAY_STATS, RESUME_STATES, TILE_IDS, TILE_LIST, TILE_MASKS, UNIFORMS};
use crate::field::{BindingRequest, FieldSource};
use crate::kernel;
use crate::gpu::renderer::{uniform_bytes, RenderError, MAX_SHADER_BYTES};
use crate::layout::{BisectBlock, FieldLayout, FrameBlock, GpuBlock, PresentBlock, SphereBlock};
use crate::render::{Settings, Traversal};
use super::present::PresentGroup;
use serde::Serialize;

pub use crate::bindings::{Binding, Groups, Size, Stage};

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
    /// The pass-group binding of the pixel records, which the present
    /// pass draws and the page reads for the frame statistics.
    pub records: u32,
    /// The present pass's bind group (`templates/view/present.wgsl`).
    pub present: PresentGroup,
}


/// Assembles, checks the size limit of the CLI, validates with naga and
/// describes the kernel of `field` traced by `traversal` for settings `s`.
pub fn program(field: &dyn FieldSource, traversal: &Traversal, s: &Settings) -> Result<Program, RenderError> {
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
    let mut frame = vec![UNIFORMS.kept(Size::Uniforms)];
    // Every pixel's record is written: no need to clear 16 bytes a pixel.
    let mut pass = vec![PIXEL_RECORDS.kept(Size::PerPixel { bytes: 16 })];
    let mut stages: Vec<Stage> = field.passes();
    let tiles = u64::from(s.width.div_ceil(8)) * u64::from(s.height.div_ceil(8));
    let request = BindingRequest { bisect: matches!(traversal, Traversal::Bisect(_)), kernel_features: field.features(), inline: kernel.inline.is_some() };
    let field_group: Vec<Binding> = field.bindings(&request).into_iter().map(|b| Binding { size: b.size.for_page(tiles), ..b }).collect();
    let (method, blocks, follow) = match traversal {
        Traversal::Bisect(b) => {
            let texels = match &b.modalities.env {
                crate::render::Environment::Image(e) => e.texels.clone(),
                _ => vec![0],
            };
            frame.push(ENVIRONMENT.data(texels));
            pass.push(TILE_MASKS.scratch(Size::PerTile { bytes: 16 }));
            pass.extend(tile_list());
            // Zeroed every frame: the page runs one round of `main`, so a
            // pixel past a tape's work limit stays unresolved there.
            pass.push(RESUME_STATES.scratch(Size::PerPixel { bytes: 16 }));
            let tpg = crate::gpu::bisect::TILES_PER_GROUP;
            if b.optimizations.tile_culling {
                // A tape's block pass (the tile pass's entry point, two
                // layers deep: gpu::renderer dispatches it the same way).
                if field.block_pass(field.features()) {
                    stages.push(Stage::new("tiles", Groups::Blocks { side: 128, layers: 2 }));
                }
                stages.extend(tile_pass());
            } else {
                stages.push(Stage::new("main", Groups::PixelTiles { tiles_per_group: tpg }));
            }
            let m = &b.modalities;
            ("bisect", blocks::<BisectBlock>(), Follow { light: m.light.is_none(), eps_factor: m.shadow_eps.is_none().then_some(4.0) })
        }
        Traversal::Sphere(o) => {
            pass.push(RAY_STATS.scratch(Size::PerPixel { bytes: 4 }));
            if field.lists_tiles() {
                // The tile pass leaves the tiles without primitives out of `main`.
                pass.extend(tile_list());
                stages.extend(tile_pass());
            } else {
                stages.push(Stage::new("main", Groups::PixelTiles { tiles_per_group: 1 }));
            }
            ("sphere", blocks::<SphereBlock>(), Follow { light: true, eps_factor: o.eps_min.is_none().then_some(1.0) })
        }
    };
    let uses = binding_uses(&module);
    for st in &mut stages {
        st.uses = uses.iter().find(|(e, _)| e == st.entry).map(|(_, u)| u.clone()).unwrap_or_default();
    }
    // The page makes only what the kernel reads: a field's table may hold
    // bindings another traversal's kernel uses.
    let used = |b: &Binding| uses.iter().any(|(_, u)| u.contains(&[crate::bindings::FIELD_GROUP, b.binding]));
    let field_group = field_group.into_iter().filter(used).collect();
    let ray_stats = matches!(traversal, Traversal::Sphere(_)).then_some(RAY_STATS.binding);
    let present = super::present::group();
    Ok(Program { method, wgsl: kernel.wgsl, blocks, uniforms, groups: [frame, field_group, pass], stages, follow, ray_stats, records: PIXEL_RECORDS.binding, present })
}

/// The uniform words of the first frame of `traversal` with settings `s`
/// (a scene edit changes them without a new kernel: its Lipschitz bound).
pub fn uniforms(traversal: &Traversal, s: &Settings) -> Result<Vec<u32>, RenderError> {
    Ok(uniform_bytes(traversal, s)?.chunks(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect())
}

/// A tile pass's list (the indirect dispatch counts of `main`, binding 2)
/// and queued tile ids (binding 3) in the pass group.
fn tile_list() -> [Binding; 2] {
    [Binding { indirect: true, ..TILE_LIST.kept(Size::Fixed { bytes: 16 }) }, TILE_IDS.scratch(Size::PerTile { bytes: 4 })]
}

/// The tile pass (one invocation per 8×8 tile) and `main` by indirect
/// dispatch over the tiles it queued.
fn tile_pass() -> [Stage; 2] {
    [Stage::new("tiles", Groups::Blocks { side: 64, layers: 1 }), Stage::new("main", Groups::Indirect { binding: TILE_LIST.binding })]
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

/// The field group's buffers with data of their own (an edit of a data
/// field: no shader).
pub fn field_buffers(field: &dyn FieldSource) -> Vec<Binding> {
    field.bindings(&BindingRequest { kernel_features: field.features(), ..Default::default() }).into_iter().filter(|b| b.is_static()).collect()
}

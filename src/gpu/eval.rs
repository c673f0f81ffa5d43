//! Runs the `eval` kernel: the generated evaluator of one number domain over
//! a batch of boxes, one invocation per box, all in one dispatch.

use super::{Author, Gpu, GpuError};
use crate::codegen::{EVAL_BOXES, EVAL_RESULTS, EVAL_UNIFORMS};
use crate::layout::{EvalBlock, MAX_PARAMS};
use crate::ir::Domain;
use crate::ir::Ir;
use crate::validate::validate;
use wgpu::util::DeviceExt;

/// One box: `[x0, x1, y0, y1, z0, z1, t0, t1]` (a point has lo == hi).
pub type Box8 = [f32; 8];

/// Errors of `eval`: generated code rejected by naga (a bug) or the device.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// naga rejected the shader.
    #[error(transparent)]
    Validate(#[from] crate::validate::ValidateError),
    /// The device failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// The user's inline WGSL does not validate.
    #[error("{0}")]
    Inline(String),
}

/// Evaluates `ir` in `domain` on every box; returns `[lo, hi]` per box
/// (empty: lo > hi; scalar: lo == hi, at the box's low corner).
#[cfg(test)]
pub fn eval_boxes(gpu: &Gpu, ir: &Ir, domain: Domain, boxes: &[Box8], params: &[f32]) -> Result<Vec<[f32; 2]>, EvalError> {
    eval_boxes_with(gpu, ir, domain, boxes, params, None)
}

/// [`eval_boxes`] with user WGSL (`--inline`).
pub fn eval_boxes_with(
    gpu: &Gpu,
    ir: &Ir,
    domain: Domain,
    boxes: &[Box8],
    params: &[f32],
    inline: Option<&crate::inline::InlineWgsl>,
) -> Result<Vec<[f32; 2]>, EvalError> {
    if boxes.is_empty() {
        return Ok(vec![]);
    }
    let src = crate::field::compiled::eval_shader_with(ir, domain, inline);
    match inline {
        Some(user) => {
            let start = src.find(&user.text).unwrap_or(0);
            crate::validate::validate_with_inline(&src, start..start + user.text.len(), &user.path, &user.text).map_err(|e| match e {
                crate::validate::InlineError::User(m) => EvalError::Inline(m),
                crate::validate::InlineError::Bug(b) => EvalError::Validate(b),
            })?;
        }
        None => {
            validate(&src)?;
        }
    }
    let pipeline = gpu.pipeline("isotrace eval", &src, Author::of(inline.is_some()))?;
    // Rerolled terms read their constants from the field group's table.
    let table = match crate::field::compiled::term_loops::table_texels(ir) {
        Some(t) => Some(table_group(gpu, &pipeline, &t, crate::field::compiled::source::TERM_TABLE.binding)?),
        None => None,
    };
    let mut out = Vec::with_capacity(boxes.len());
    // Stay within the storage binding limit: 32 bytes in, 8 bytes out per box.
    let chunk = ((gpu.max_storage_binding / 32) as usize).clamp(1, 1 << 22);
    for part in boxes.chunks(chunk) {
        out.extend(run_chunk_with(gpu, &pipeline, part, params, table.as_ref().map(|(g, _)| g))?);
    }
    Ok(out)
}

/// A one-texture field group: a tape's code or a formula's table of
/// rerolled constants, at `binding` of the field group (the texture is kept with the group).
fn table_group(gpu: &Gpu, pipeline: &wgpu::ComputePipeline, texels: &crate::field::Texels<[u32; 4]>, binding: u32) -> Result<(wgpu::BindGroup, wgpu::Texture), EvalError> {
    let (texture, view) = gpu.texture("field table", texels, wgpu::TextureFormat::Rgba32Uint)?;
    let group = gpu.scoped("field table bind group", || {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("field table"),
            layout: &pipeline.get_bind_group_layout(1),
            entries: &[wgpu::BindGroupEntry { binding, resource: wgpu::BindingResource::TextureView(&view) }],
        })
    })?;
    Ok((group, texture))
}

/// Evaluates a tape (the fixed interpreter of the tape field source) in
/// `domain` on every box, with the results of [`eval_boxes`]: the hook the
/// conformance tests use to check the tape's enclosures on the device.
pub fn eval_boxes_tape(gpu: &Gpu, tape: &crate::field::TapeData, domain: Domain, boxes: &[Box8], params: &[f32]) -> Result<Vec<[f32; 2]>, EvalError> {
    if boxes.is_empty() {
        return Ok(vec![]);
    }
    let src = crate::field::tape::wgsl::eval_shader(domain, tape.features);
    validate(&src)?;
    let pipeline = gpu.pipeline("isotrace eval (tape)", &src, Author::Isotrace)?;
    let (group, _texture) = table_group(gpu, &pipeline, &tape.texels(), crate::field::tape::source::TAPE_CODE.binding)?;
    let mut out = Vec::with_capacity(boxes.len());
    let chunk = ((gpu.max_storage_binding / 32) as usize).clamp(1, 1 << 22);
    for part in boxes.chunks(chunk) {
        out.extend(run_chunk_with(gpu, &pipeline, part, params, Some(&group))?);
    }
    Ok(out)
}

/// Evaluates a scene's whole tree by the device's interpreter at every
/// point (the checks of the interpreter against the f64 reference).
pub fn eval_points_scene(gpu: &Gpu, scene: &crate::field::SceneData, points: &[[f32; 3]]) -> Result<Vec<f32>, EvalError> {
    if points.is_empty() {
        return Ok(vec![]);
    }
    let src = crate::field::scene::scene_eval_shader(scene.features);
    validate(&src)?;
    let pipeline = gpu.pipeline("isotrace eval (scene)", &src, Author::Isotrace)?;
    let (_textures, group) = scene_group(gpu, &pipeline, scene, false)?;
    let boxes: Vec<Box8> = points.iter().map(|p| [p[0], p[0], p[1], p[1], p[2], p[2], 0.0, 0.0]).collect();
    let mut out = Vec::with_capacity(points.len());
    let chunk = ((gpu.max_storage_binding / 32) as usize).clamp(1, 1 << 22);
    for part in boxes.chunks(chunk) {
        out.extend(run_chunk_with(gpu, &pipeline, part, &[], Some(&group))?.into_iter().map(|v| v[0]));
    }
    Ok(out)
}

/// Encloses a scene's field over every box by the device's interval
/// interpreter (bisection's `surf_ia`, whole tree): the checks of its
/// enclosures against f64 sampling of the reference.
#[cfg(test)]
pub fn eval_boxes_scene(gpu: &Gpu, scene: &crate::field::SceneData, boxes: &[Box8]) -> Result<Vec<[f32; 2]>, EvalError> {
    if boxes.is_empty() {
        return Ok(vec![]);
    }
    let src = crate::field::scene::scene_enclosure_shader(scene.features);
    validate(&src)?;
    let pipeline = gpu.pipeline("isotrace eval (scene enclosures)", &src, Author::Isotrace)?;
    // The pruned trees the enclosure may read: none, the whole tree is evaluated.
    let (_textures, group) = scene_group(gpu, &pipeline, scene, true)?;
    let mut out = Vec::with_capacity(boxes.len());
    let chunk = ((gpu.max_storage_binding / 32) as usize).clamp(1, 1 << 22);
    for part in boxes.chunks(chunk) {
        out.extend(run_chunk_with(gpu, &pipeline, part, &[], Some(&group))?);
    }
    Ok(out)
}

/// Bisection's cell enclosures over a scene's whole tree, of the ray cells
/// `boxes` encode (`field::scene::scene_cell_shader`): the values' ranges,
/// or with `slope` the slopes'.
#[cfg(test)]
pub fn eval_cells_scene(gpu: &Gpu, scene: &crate::field::SceneData, boxes: &[Box8], slope: bool) -> Result<Vec<[f32; 2]>, EvalError> {
    let src = crate::field::scene::scene_cell_shader(scene.features, slope);
    validate(&src)?;
    let pipeline = gpu.pipeline("isotrace eval (scene cells)", &src, Author::Isotrace)?;
    let (_textures, group) = scene_group(gpu, &pipeline, scene, true)?;
    run_chunk_with(gpu, &pipeline, boxes, &[], Some(&group))
}

/// The field group of an `eval` kernel over a scene: its node and
/// parameter textures, its formula leaves' tapes where the kernel runs them
/// and, for a bisection kernel (`pruned`), an empty pruned-tree texture (it
/// evaluates the whole tree); the textures are kept alive with the group.
fn scene_group(gpu: &Gpu, pipeline: &wgpu::ComputePipeline, scene: &crate::field::SceneData, pruned: bool) -> Result<(Vec<wgpu::Texture>, wgpu::BindGroup), EvalError> {
    use crate::field::scene::source::{NODES, PARAMS, PRUNED_TEXELS, TAPES};
    let mut textures = vec![
        (NODES.binding, gpu.texture("scene nodes", &scene.node_texels(), wgpu::TextureFormat::Rgba32Uint)?),
        (PARAMS.binding, gpu.texture("scene parameters", &scene.param_texels(), wgpu::TextureFormat::Rgba32Float)?),
    ];
    if let Some(t) = crate::field::scene::leaves::texture(scene) {
        textures.push((TAPES.binding, gpu.texture("scene formula tapes", &t, wgpu::TextureFormat::Rgba32Uint)?));
    }
    if pruned {
        let none = crate::field::Texels { width: 1, height: 1, texels: vec![0u32] };
        textures.push((PRUNED_TEXELS.binding, gpu.texture("scene pruned trees", &none, wgpu::TextureFormat::R32Uint)?));
    }
    let entries: Vec<wgpu::BindGroupEntry<'_>> = textures.iter().map(|(binding, (_, view))| wgpu::BindGroupEntry { binding: *binding, resource: wgpu::BindingResource::TextureView(view) }).collect();
    let group = gpu.scoped("scene bind group", || {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &pipeline.get_bind_group_layout(1),
            entries: &entries,
        })
    })?;
    Ok((textures.into_iter().map(|(_, (texture, _))| texture).collect(), group))
}

/// A cell of a ray for [`eval_ray_cells`]: the ray o + dir·s, the start
/// `s_ref` and length `len` of its part in the domain (what bisection
/// gives `field_begin_ray`), and the cell [s0, s1] inside it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg(test)]
pub struct RayCell {
    /// The ray's origin.
    pub o: [f32; 3],
    /// Its direction (any length: s is in its units).
    pub dir: [f32; 3],
    /// Where the ray's part in the domain starts.
    pub s_ref: f32,
    /// That part's length in s.
    pub len: f32,
    /// The cell [s0, s1].
    pub cell: [f32; 2],
}

/// What the device's interval bisection computes on a [`RayCell`]: the
/// value's range over the cell, the slope's along dir, and the scalar
/// field on the ray at the cell's ends.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg(test)]
pub struct CellEnclosure {
    /// f's range over the cell.
    pub value: [f32; 2],
    /// The range of f's slope d f(o + s dir) / ds over the cell.
    pub slope: [f32; 2],
    /// f on the ray at s0 and s1.
    pub ends: [f32; 2],
    /// f at the cell's midpoint from the enclosure's own pass (0 where the
    /// field does not compute it there), and from the scalar field.
    pub mid: [f32; 2],
}

/// Runs bisection's interval cell enclosure of a compiled formula (with
/// the nodes it takes from the ray, `field::compiled::ray_forms`) on every cell.
#[cfg(test)]
pub fn eval_ray_cells(gpu: &Gpu, ir: &Ir, cells: &[RayCell]) -> Result<Vec<CellEnclosure>, EvalError> {
    if cells.is_empty() {
        return Ok(vec![]);
    }
    let src = crate::field::compiled::ray_cell_eval_shader(ir);
    validate(&src)?;
    let pipeline = gpu.pipeline("isotrace eval (ray cells)", &src, Author::Isotrace)?;
    let table = match crate::field::compiled::term_loops::table_texels(ir) {
        Some(t) => Some(table_group(gpu, &pipeline, &t, crate::field::compiled::source::TERM_TABLE.binding)?),
        None => None,
    };
    let boxes: Vec<Box8> = cells
        .iter()
        .flat_map(|c| [[c.o[0], c.o[1], c.o[2], c.dir[0], c.dir[1], c.dir[2], c.s_ref, c.len], [c.cell[0], c.cell[1], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0; 8], [0.0; 8]])
        .collect();
    let chunk = ((gpu.max_storage_binding / 32) as usize).clamp(4, 1 << 22) / 4 * 4;
    let mut out = Vec::with_capacity(cells.len());
    for part in boxes.chunks(chunk) {
        let r = run_chunk_with(gpu, &pipeline, part, &[], table.as_ref().map(|(g, _)| g))?;
        out.extend(r.chunks(4).map(|q| CellEnclosure { value: q[0], slope: q[1], ends: q[2], mid: q[3] }));
    }
    Ok(out)
}

/// One dispatch over `boxes`; `field` is bound as group 1 (a tape, a scene,
/// a formula's table of rerolled constants).
fn run_chunk_with(gpu: &Gpu, pipeline: &wgpu::ComputePipeline, boxes: &[Box8], params: &[f32], field: Option<&wgpu::BindGroup>) -> Result<Vec<[f32; 2]>, EvalError> {
    let n = boxes.len() as u32;
    let groups = n.div_ceil(64);
    let gx = groups.min(65_535);
    let gy = groups.div_ceil(gx);
    if params.len() > MAX_PARAMS {
        return Err(GpuError::Limits(format!("too many parameters: {} (the limit is {MAX_PARAMS})", params.len())).into());
    }
    let mut p = [0.0f32; MAX_PARAMS];
    p[..params.len()].copy_from_slice(params);
    let u = EvalBlock { inf: f32::INFINITY, count: n, row: gx * 64, pad: 0, params: p };
    let d = &gpu.device;
    let result = gpu.scoped("eval dispatch", || {
        let ubuf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("eval uniforms"),
            contents: bytemuck::bytes_of(&u),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let bbuf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("eval boxes"),
            contents: bytemuck::cast_slice(boxes),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = n as u64 * 8;
        let obuf = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("eval results"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("eval"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: EVAL_UNIFORMS.binding, resource: ubuf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: EVAL_BOXES.binding, resource: bbuf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: EVAL_RESULTS.binding, resource: obuf.as_entire_binding() },
            ],
        });
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind, &[]);
            if let Some(g) = field {
                pass.set_bind_group(1, g, &[]);
            }
            pass.dispatch_workgroups(gx, gy, 1);
        }
        let staging = gpu.read_buffer(&mut enc, &obuf, size);
        gpu.queue.submit([enc.finish()]);
        staging
    })?;
    let bytes = gpu.map_read(&result)?;
    Ok(bytemuck::cast_slice::<u8, [f32; 2]>(&bytes).to_vec())
}

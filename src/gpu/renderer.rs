//! The render pipeline on the device: one [`Renderer`] for every traversal
//! × field source. It compiles the kernel codegen assembled, binds the
//! three groups by lifetime (frame, field, pass), runs the tile loop of
//! [`super::dispatch`] and turns the pixel records into a [`Frame`] or a
//! [`PackedFrame`] with the frame statistics. What differs between
//! traversals on the host (their uniform block, frame resources, pass
//! buffers and own statistics) sits behind `TraversalHost`.

use super::binding::Binder;
use super::dispatch::{self, Dispatch, Groups, Rect, Stage};
use super::uniforms::uniforms;
use super::{field, slot_entry, Author, Gpu, GpuError};
use crate::field::{BindingRequest, FieldSource};
use crate::kernel;
use crate::render::record::{convert, count, count_all, map_all, PackedFrame, Planes, RayStats, Record, Records};
use crate::render::{CameraBasis, Frame, Optimizations, Settings, SettingsError, SphereOptions, Stats, StatsAcc, Traversal};
use crate::bindings::Statistics;
use crate::validate::{validate, ValidateError};
use bytemuck::Zeroable;
use std::time::Instant;

/// A packed frame's output buffer handed to a render (if it has one) and
/// the records' mapped view the render leaves in it.
struct Keep {
    buffer: Option<wgpu::Buffer>,
    view: Option<wgpu::BufferView>,
}

/// Render failures.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// naga rejected the generated shader (an isotrace bug).
    #[error(transparent)]
    Validate(#[from] ValidateError),
    /// The device failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// A setting that cannot be rendered.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// The user's inline WGSL does not validate (rendered against their file).
    #[error("{0}")]
    Inline(String),
    /// The frame's host memory could not be had (over the budget, or the
    /// allocator refused).
    #[error(transparent)]
    Memory(#[from] crate::memory::MemoryError),
    /// The assembled kernel is larger than `MAX_SHADER_BYTES`.
    #[error("the generated shader is {} KB of WGSL code, over the limit of {} KB: the driver would compile it for many minutes", bytes.div_ceil(1000), MAX_SHADER_BYTES / 1000)]
    ShaderTooLarge {
        /// Its size in bytes.
        bytes: usize,
    },
}

pub(crate) use crate::kernel::MAX_SHADER_BYTES;
pub(crate) use super::uniforms::uniform_bytes;

/// Buffers of one dispatch's pass group besides the pixel records.
pub(crate) struct PassBuffers {
    /// (binding, buffer) entries.
    pub entries: Vec<(u32, wgpu::Buffer)>,
    /// The tile list of a pre-pass, if the traversal runs one.
    pub list: Option<wgpu::Buffer>,
}

/// What a traversal adds to the pipeline on the host.
pub(crate) trait TraversalHost: Sync {
    /// The traversal's uniform block for a frame.
    fn block(&self, s: &Settings, cam: &CameraBasis) -> Vec<u8>;
    /// Its bits of the frame flags.
    fn flags(&self) -> u32;
    /// Frame-group layout entries after the uniforms (binding 0), and the
    /// buffers bound there.
    fn frame_resources(&self) -> Vec<(wgpu::BindGroupLayoutEntry, &wgpu::Buffer)>;
    /// Pass-group layout entries after the pixel records (binding 0).
    fn pass_layout(&self) -> Vec<wgpu::BindGroupLayoutEntry>;
    /// The pass buffers of one dispatch over `rect`; `resumable`: the
    /// per-pixel pass runs in rounds that resume pixels (bisection of a tape
    /// or of a compiled sum's loops).
    fn pass_buffers(&self, gpu: &Gpu, rect: Rect, resumable: bool) -> PassBuffers;
    /// Workgroups of the per-pixel pass hold this many 8×8 tiles.
    fn tiles_per_group(&self) -> u32;
    /// With a pre-pass, the per-pixel pass is dispatched indirectly.
    fn pre_pass(&self) -> bool;
    /// The binding of a per-ray statistics word to read back, if any.
    fn ray_stats_binding(&self) -> Option<u32>;
    /// Fills the traversal's own statistics.
    fn finish(&self, s: &Settings, rays: &RayStats, stats: &mut Stats);
    /// The options, for callers that inspect them.
    fn options(&self) -> Traversal;
    /// The traversal's method.
    fn method(&self) -> crate::render::Method;
    /// Bisection's optimisations, if this is bisection.
    fn optimizations_mut(&mut self) -> Option<&mut Optimizations>;
    /// Sphere tracing's options, if this is sphere tracing.
    fn sphere_options_mut(&mut self) -> Option<&mut SphereOptions>;
}

/// A compiled render pipeline: one field source traced by one traversal.
/// Frames differ only in uniforms (camera, time, parameters, the
/// traversal's values), so animations and benchmarks never recompile.
pub struct Renderer<'g> {
    gpu: &'g Gpu,
    wgsl: String,
    main: wgpu::ComputePipeline,
    pre: Option<wgpu::ComputePipeline>,
    /// The field's pre-passes, in order.
    field_passes: Vec<wgpu::ComputePipeline>,
    layouts: [wgpu::BindGroupLayout; 3],
    host: Box<dyn TraversalHost + 'g>,
    field: field::FieldBinding,
    outputs: dispatch::Outputs,
    surfaces: usize,
    /// Rounds of the per-pixel pass after the first, resuming pixels a
    /// tape left at its work limit (bisection of a tape only).
    resume_rounds: u32,
}

impl<'g> Renderer<'g> {
    /// Assembles (codegen), validates (naga) and compiles the kernel of
    /// `field` traced by `traversal`.
    pub fn new(gpu: &'g Gpu, field: &dyn FieldSource, traversal: Traversal) -> Result<Renderer<'g>, RenderError> {
        traversal.check()?;
        if matches!(traversal, Traversal::Bisect(_)) && !field.has_enclosures() {
            return Err(SettingsError::new(crate::render::SettingsField::Features, "bisect", "this field has no interval enclosures: render it with sphere tracing").into());
        }
        if let Traversal::Bisect(b) = &traversal {
            if b.modalities.inline.is_some() && !field.takes_inline() {
                return Err(SettingsError::new(crate::render::SettingsField::Features, "inline", "user WGSL hooks need the compiled field").into());
            }
        }
        let kernel = kernel::assemble_for(field, &traversal, gpu.subgroups);
        if kernel.code_bytes() > MAX_SHADER_BYTES {
            return Err(RenderError::ShaderTooLarge { bytes: kernel.code_bytes() });
        }
        match &kernel.inline {
            Some((range, user)) => {
                crate::validate::validate_with_inline(&kernel.wgsl, range.clone(), &user.path, &user.text).map_err(|e| match e {
                    crate::validate::InlineError::User(m) => RenderError::Inline(m),
                    crate::validate::InlineError::Bug(b) => RenderError::Validate(b),
                })?;
            }
            None => {
                validate(&kernel.wgsl)?;
            }
        }
        let host: Box<dyn TraversalHost + 'g> = match traversal {
            Traversal::Bisect(b) => Box::new(super::bisect::Host::new(gpu, b)?),
            Traversal::Sphere(o) => Box::new(super::sphere::Host::new(o, field.lists_tiles())),
        };
        let d = &gpu.device;
        let request = BindingRequest { bisect: host.method() == crate::render::Method::Bisect, kernel_features: field.features(), inline: kernel.inline.is_some() };
        let bound = field::bind(gpu, field, &request)?;
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries });
        let mut frame_entries = vec![slot_entry(&crate::kernel::bindings::UNIFORMS)];
        frame_entries.extend(host.frame_resources().into_iter().map(|(e, _)| e));
        let mut pass_entries = vec![slot_entry(&crate::kernel::bindings::PIXEL_RECORDS)];
        pass_entries.extend(host.pass_layout());
        let layouts = gpu.scoped("bind group layouts", || [layout("frame", &frame_entries), layout("field", &bound.layout), layout("pass", &pass_entries)])?;
        let pipeline_layout = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("render"),
            bind_group_layouts: &[Some(&layouts[0]), Some(&layouts[1]), Some(&layouts[2])],
            immediate_size: 0,
        });
        // The first frame's settings do not matter to a dispatch of no workgroups.
        let warm = Settings::for_box([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0], 8, 8);
        let binder = Binder { gpu, host: host.as_ref(), field: &bound, layouts: &layouts };
        let warm_uniforms = uniforms(&binder, &warm, Rect { x: 0, y: 0, w: 8, h: 8 })?;
        let mut pipelines = gpu.pipelines_then("isotrace render", (&kernel.wgsl, Author::of(kernel.inline.is_some())), &kernel.entries, Some(&pipeline_layout), |small| {
            if !small.is_empty() {
                let failed = binder.warm_up(small, &warm_uniforms).is_err();
                gpu.warm_ups[failed as usize].fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            }
        })?;
        let field_passes = pipelines.split_off(pipelines.len() - field.passes().len());
        let mut pipelines = pipelines.into_iter();
        let main = pipelines.next().expect("a main entry point");
        let pre = pipelines.next();
        Ok(Renderer { gpu, wgsl: kernel.wgsl, main, pre, field_passes, layouts, host, field: bound, outputs: Default::default(), surfaces: field.surfaces(), resume_rounds: field.resume_rounds() })
    }

    /// Replaces a data-driven field's buffers (a scene edited, moved,
    /// grown or shrunk, another tape): new buffers and a new field bind
    /// group, no new shader or pipeline. `field` must be of the kind the
    /// kernel was built for, within its features ([`FieldSource::replaces`]).
    pub fn set_field(&mut self, field: &dyn FieldSource) -> Result<(), RenderError> {
        field.replaces(self.field.name, self.field.features).map_err(|r| SettingsError::new(crate::render::SettingsField::Features, r.value, r.reason))?;
        let request = BindingRequest { bisect: self.host.method() == crate::render::Method::Bisect, kernel_features: self.field.features, inline: false };
        let mut bound = field::bind(self.gpu, field, &request)?;
        (bound.features, bound.dense) = (self.field.features, self.field.dense);
        self.field = bound;
        Ok(())
    }

    /// The interpreter features this renderer's kernel has (a scene's node
    /// types, a tape's operation groups and register file; 0 for a compiled
    /// field): a field within them can replace its field with
    /// [`Renderer::set_field`].
    pub fn field_features(&self) -> u32 {
        self.field.features
    }

    /// How many rounds of the per-pixel pass after the first resume the
    /// pixels a field left at its work limit (bisection of a field whose
    /// cells resume, [`FieldSource::cells_resume`]; else no effect). 0
    /// leaves them unresolved: the comparison the tests and benchmarks make.
    pub fn set_resume_rounds(&mut self, rounds: u32) {
        self.resume_rounds = rounds;
    }

    /// A field that lists its tiles' work evaluates the whole field for
    /// every pixel instead (a uniform flag: no new pipeline). The dense
    /// baseline against which the sparse traversal is measured; the picture
    /// is the same.
    pub fn set_dense(&mut self, dense: bool) {
        self.field.dense = dense;
    }

    /// Uploads an edit in place of the field this renderer draws (a
    /// scene's `Linear::set_primitive` gives one): small buffer writes, no
    /// new buffer, bind group, shader or pipeline.
    pub fn edit_field(&self, edit: &(impl crate::field::FieldEdit + ?Sized)) -> Result<(), RenderError> {
        self.field.write(self.gpu, &edit.writes()).map_err(|m| SettingsError::new(crate::render::SettingsField::Features, "field edit", m).into())
    }

    /// Bisection of `formula` compiled into the shader, in the number
    /// domain `render --algebra auto` takes ([`crate::choose_algebra`]),
    /// without modalities: the short way from a formula to pictures.
    pub fn for_formula(gpu: &'g Gpu, formula: &crate::Formula) -> Result<Renderer<'g>, RenderError> {
        Self::bisect(gpu, &formula.ir, crate::choose_algebra(&formula.ir))
    }

    /// Bisection of a compiled formula in `domain`, without modalities.
    pub fn bisect(gpu: &'g Gpu, ir: &crate::ir::Ir, domain: crate::ir::Domain) -> Result<Renderer<'g>, RenderError> {
        Self::new(gpu, ir, Traversal::Bisect(crate::render::BisectOptions::new(domain)))
    }

    /// Sphere tracing of a compiled formula with options `o`.
    pub fn sphere(gpu: &'g Gpu, ir: &crate::ir::Ir, o: SphereOptions) -> Result<Renderer<'g>, RenderError> {
        Self::new(gpu, ir, Traversal::Sphere(o))
    }

    /// The validated shader source.
    pub fn wgsl(&self) -> &str {
        &self.wgsl
    }

    /// The name of the field source the kernel reads ([`FieldSource::name`]).
    pub fn field_name(&self) -> &'static str {
        self.field.name
    }

    /// What of the field shares lavapipe's loop cap with bisection's
    /// iterations ([`FieldSource::shares_loop_cap`]).
    pub fn field_shares_loop_cap(&self) -> Option<&'static str> {
        self.field.shares_loop_cap
    }

    /// The traversal and its current options.
    pub fn traversal(&self) -> Traversal {
        self.host.options()
    }

    /// Bisection's optimisation switches (uniforms: changing them never
    /// recompiles); `None` for other traversals.
    pub fn optimizations_mut(&mut self) -> Option<&mut Optimizations> {
        self.host.optimizations_mut()
    }

    /// Replaces sphere tracing's options (uniforms). The secondary rays
    /// asked for must have been compiled in.
    pub fn set_sphere_options(&mut self, o: SphereOptions) -> Result<(), RenderError> {
        o.check()?;
        let Some(cur) = self.host.sphere_options_mut() else {
            return Err(SettingsError::new(crate::render::SettingsField::Features, "sphere", "this renderer does not sphere trace").into());
        };
        let (have, want) = (cur.features(), o.features());
        if (want.shadows && !have.shadows) || (want.glass && !have.glass) {
            return Err(SettingsError::new(crate::render::SettingsField::Features, "shadows/glass", "the kernel was compiled without the secondary rays asked for").into());
        }
        if want.synchronized != have.synchronized {
            return Err(SettingsError::new(
                crate::render::SettingsField::Features,
                "synchronized",
                "the kernel was compiled for the other walk of a scene's tiles (synchronised or per ray)",
            )
            .into());
        }
        *cur = o;
        Ok(())
    }

    /// Renders one frame, tile by tile.
    pub fn render(&self, s: &Settings) -> Result<Frame, RenderError> {
        let mut f = Frame { width: 0, height: 0, pixels: Vec::new(), stats: Stats::default() };
        self.render_into(s, &mut f)?;
        Ok(f)
    }

    /// Renders one frame into `frame`, reusing its pixel memory: a viewer
    /// or an animation renders every frame into the same one. (Touching
    /// tens of MB of fresh pages a frame is a noticeable part of it.)
    pub fn render_into(&self, s: &Settings, out: &mut Frame) -> Result<(), RenderError> {
        let start = Instant::now();
        let (pixels, stats) = self.collect(s, std::mem::take(&mut out.pixels), None, "pixels", convert)?;
        *out = Frame { width: s.width, height: s.height, pixels, stats };
        out.stats.wall_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(())
    }

    /// Renders one frame into `out` and keeps the kernel's records packed
    /// (see [`PackedFrame`]), with the same statistics as [`Renderer::render_into`].
    /// Where the device maps storage in place and the frame is one
    /// dispatch, the records stay in `out`'s own output buffer, reused
    /// frame to frame.
    pub fn render_packed(&self, s: &Settings, out: &mut PackedFrame) -> Result<(), RenderError> {
        let start = Instant::now();
        let (copy, buffer) = out.records.take();
        let mut keep = Keep { buffer, view: None };
        let (copy, stats) = self.collect(s, copy, Some(&mut keep), "pixel records", |r| *r)?;
        let records = match keep {
            Keep { buffer: Some(buffer), view: Some(view) } => Records::Mapped { buffer, view },
            _ => Records::Copied(copy),
        };
        *out = PackedFrame { width: s.width, height: s.height, stats, records };
        out.stats.wall_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(())
    }

    /// Renders one frame and writes `f` of each record, row-major, into
    /// `buf` (its memory reused), gathering the statistics on the way. The
    /// frame's memory (`what`) is reserved fallibly before any dispatch.
    /// With `keep`, records left mapped in the kernel's output (see
    /// [`Renderer::run`]) are only counted, and `buf` stays empty.
    fn collect<T: Copy + Send>(&self, s: &Settings, mut buf: Vec<T>, keep: Option<&mut Keep>, what: &'static str, f: impl Fn(&Record) -> T + Copy + Sync) -> Result<(Vec<T>, Stats), RenderError> {
        let (w, h) = (s.width, s.height);
        let n = w as usize * h as usize;
        let mut acc = StatsAcc::default();
        let in_place = keep.is_some() && self.in_place(s);
        if !in_place {
            crate::memory::reserve(&mut buf, n, (w, h), what)?;
        }
        let mut stats = self.run(s, keep.filter(|_| in_place), |rect, raw| {
            if in_place {
                acc.merge(count_all(raw));
                return;
            }
            if (rect.w, rect.h) == (w, h) {
                // The usual case, one dispatch for the frame: write straight
                // into the (reused) memory, on every core, without filling it
                // first.
                buf.reserve(n);
                acc.merge(map_all(raw, &mut buf.spare_capacity_mut()[..n], f));
                // SAFETY: map_all initialised all n elements.
                unsafe { buf.set_len(n) };
                return;
            }
            if buf.is_empty() {
                buf.resize(n, f(&Record::zeroed()));
            }
            let rw = rect.w as usize;
            for row in 0..rect.h as usize {
                let chunk = raw.slice(row * rw..(row + 1) * rw);
                let start = (rect.y as usize + row) * w as usize + rect.x as usize;
                for (dst, r) in buf[start..start + rw].iter_mut().zip(chunk.iter()) {
                    *dst = f(&r);
                }
                count(chunk, &mut acc);
            }
        })?;
        acc.finish(&mut stats);
        Ok((buf, stats))
    }

    /// The rectangles a frame of settings `s` is rendered in: the largest
    /// per-pixel buffer must fit one storage binding (the records, or a
    /// scene's per-tile lists and pruned trees), the indirect dispatch its limit,
    /// and the field its own.
    fn rects(&self, s: &Settings) -> Vec<Rect> {
        let per_pixel = std::mem::size_of::<Record>() as u64;
        let indirect = self.host.pre_pass().then(|| self.host.tiles_per_group());
        let side = dispatch::max_side(self.gpu, per_pixel.max(self.field.bytes_per_pixel()), indirect, s.tile);
        let side = side.min(((self.field.max_pixels(self.gpu) as f64).sqrt() as u32 / 8 * 8).max(8));
        dispatch::split(s.width, s.height, side).collect()
    }

    /// Whether a frame's records can stay where the kernel wrote them: one
    /// dispatch, on a device that maps storage buffers in place.
    fn in_place(&self, s: &Settings) -> bool {
        self.gpu.map_in_place && self.rects(s).len() == 1
    }

    /// Runs the dispatches of one frame and hands each rectangle's records
    /// to `sink`. Returns the statistics that do not come from the records.
    /// With `keep` (a one-dispatch frame on a device that maps in place,
    /// [`Renderer::in_place`]) the records go to `keep`'s buffer (a new one
    /// if it has none of the right size) and stay mapped there, its view in
    /// `keep`.
    fn run(&self, s: &Settings, mut keep: Option<&mut Keep>, mut sink: impl FnMut(Rect, Planes)) -> Result<Stats, RenderError> {
        s.check()?;
        if let (Some(what), crate::render::Method::Bisect, true) = (self.field.shares_loop_cap, self.host.method(), s.max_iter > crate::field::limits::TAPE_MAX_ITER) {
            let reason = format!("at most {} with {what} lavapipe's 65,535 loop iterations)", crate::field::limits::TAPE_MAX_ITER);
            return Err(SettingsError::new(crate::render::SettingsField::MaxIter, s.max_iter.to_string(), reason).into());
        }
        let rays = self.host.ray_stats_binding();
        let rects = self.rects(s);
        assert!(keep.is_none() || rects.len() == 1, "records are kept in place only for a frame of one dispatch");
        let mut stats = Stats { method: self.host.method(), ..Default::default() };
        let mut ray_stats = RayStats::default();
        let mut tiles = crate::render::record::TileStats::new(s.width, s.height);
        let mut tape_lists = crate::render::TapeListStats::default();
        let mut loop_lists = crate::render::LoopListStats::default();
        let binder = Binder { gpu: self.gpu, host: self.host.as_ref(), field: &self.field, layouts: &self.layouts };
        for rect in rects {
            let records_size = rect.pixels() * std::mem::size_of::<Record>() as u64;
            let frame_buffer = keep.as_mut().map(|k| match k.buffer.take() {
                Some(b) if b.size() == records_size => b,
                _ => dispatch::output_buffers(self.gpu, records_size).0,
            });
            let b = binder.bind(rect, &uniforms(&binder, s, rect)?, |slot, size| match (&frame_buffer, slot) {
                (Some(fb), 0) => (fb.clone(), fb.clone()),
                _ => self.outputs.get(self.gpu, slot, size),
            })?;
            let job = Dispatch {
                label: "render dispatch",
                stages: self.stages(rect, &b.pass, &b.field),
                groups: [&b.groups[0], &b.groups[1], &b.groups[2]],
                outputs: b.outputs.iter().zip(b.sizes).filter_map(|(o, size)| o.as_ref().map(|(o, st)| (o.clone(), st.clone(), size))).collect(),
                clears: b.field.clears(),
            };
            let (t, view) = job.run_keeping(self.gpu, keep.is_some(), |bytes| {
                sink(rect, Planes::of_bytes(bytes[0], rect.pixels() as usize));
                let mut rest = bytes[1..].iter();
                if rays.is_some() {
                    ray_stats.add(bytemuck::cast_slice(rest.next().expect("ray words read back")));
                }
                if let (Some(words), Some(kind)) = (rest.next(), self.field.statistics()) {
                    match kind {
                        Statistics::TapeLists => tape_lists.add(bytemuck::cast_slice(words)),
                        Statistics::TermLists => loop_lists.add(bytemuck::cast_slice(words)),
                        Statistics::TileLists => tiles.add((rect.x, rect.y, rect.w), bytemuck::cast_slice(words)),
                    }
                }
            })?;
            if let Some(k) = keep.as_mut() {
                (k.buffer, k.view) = (frame_buffer, view);
            }
            stats.gpu_ms += t.total_ms;
            let nf = self.field_passes.len();
            stats.field_ms += t.stage_ms[..nf].iter().sum::<f64>();
            if self.pre.is_some() && self.host.pre_pass() {
                // With a tape's block pass before it.
                let pre = 1 + usize::from(self.field.block_pass());
                stats.tile_ms += t.stage_ms[nf..nf + pre].iter().sum::<f64>();
            }
            stats.dispatches += 1;
        }
        stats.iso_channel = self.surfaces > 1;
        self.host.finish(s, &ray_stats, &mut stats);
        match self.field.statistics() {
            Some(Statistics::TileLists) => tiles.finish(&mut stats),
            Some(Statistics::TapeLists) => stats.field.tape_lists = Some(tape_lists),
            Some(Statistics::TermLists) => stats.field.loop_lists = Some(loop_lists),
            None => {}
        }
        Ok(stats)
    }

    /// The passes of one dispatch: the field's pre-passes, the traversal's
    /// tile pass if it runs one, and the per-pixel pass (indirect after a
    /// tile pass).
    fn stages<'a>(&'a self, rect: Rect, pass: &'a PassBuffers, field: &'a field::PerDispatch) -> Vec<Stage<'a>> {
        // A pass may hand what it wrote over as a texture (a scene's node lists).
        let mut stages: Vec<Stage<'a>> = self
            .field_passes
            .iter()
            .zip(self.field.passes(rect))
            .map(|(pipeline, (g, copy))| Stage { pipeline, groups: Groups::Direct(g), copy: copy.and_then(|c| field.copy(c.from, c.to)) })
            .collect();
        // Bisecting a tape or a compiled sum's loops, pixels past the
        // field's work limit are resumed by further rounds of the per-pixel
        // pass (FieldSource::cells_resume): each is a dispatch of its
        // own, with lavapipe's loop count afresh.
        let rounds = if self.field.resumes() && self.host.method() == crate::render::Method::Bisect { 1 + self.resume_rounds } else { 1 };
        match (&self.pre, &pass.list) {
            (Some(tiles), Some(list)) if self.host.pre_pass() => {
                // A tape's block pass: the tile pass's entry point over
                // blocks of 2 × 2 tiles (8 × 8 a workgroup), as the second
                // layer of a dispatch two deep (traverse/bisect/tiles.wgsl).
                if self.field.block_pass() {
                    stages.push(Stage { pipeline: tiles, groups: Groups::Direct([rect.w.div_ceil(128), rect.h.div_ceil(128), 2]), copy: None });
                }
                stages.push(Stage { pipeline: tiles, groups: Groups::Direct([rect.w.div_ceil(64), rect.h.div_ceil(64), 1]), copy: None });
                for _ in 0..rounds {
                    stages.push(Stage { pipeline: &self.main, groups: Groups::Indirect(list), copy: None });
                }
            }
            _ => {
                let groups = [rect.w.div_ceil(8), rect.h.div_ceil(8).div_ceil(self.host.tiles_per_group()), 1];
                for _ in 0..rounds {
                    stages.push(Stage { pipeline: &self.main, groups: Groups::Direct(groups), copy: None });
                }
            }
        }
        stages
    }

}

//! Runs the sphere tracing kernel (`templates/kernels/sphere.wgsl`). A
//! [`SphereRenderer`] holds one compiled pipeline for a formula; the
//! techniques of Keinert et al. are uniforms ([`SphereOptions`]), so
//! switching one on or off for a measurement never recompiles.
//!
//! It takes the same [`Settings`] as the bisection renderer and returns the
//! same [`Frame`]; a pixel's `evals` are its sphere tracing steps (marching
//! iterations of its primary, shadow and refraction rays; the fixed-point
//! iterations and the normal are a fixed cost per hit and not counted) and
//! its `Unresolved` status means "unconverged". Images are split into tiles
//! exactly like the bisection renderer's.

use super::render::{check_settings, snorm2, unorm2, RenderError, Settings, MAX_SIZE};
use super::{pack_params, Gpu};
use crate::codegen::{emit_evaluator, libraries, template, Domain};
use crate::ir::Ir;
use crate::render::{Bound, Frame, Method, PixelOut, Stats, Status};
use crate::validate::validate;
use bytemuck::{Pod, Zeroable};
use std::time::Instant;

/// Largest `max_steps`: the primary, shadow and refraction rays each get
/// the budget, and lavapipe silently stops any invocation after 65,535 loop
/// iterations in total.
pub const MAX_STEPS_LIMIT: u32 = 16_000;
/// Default step budget per ray.
pub const DEFAULT_MAX_STEPS: u32 = 512;
/// Default over-relaxation factor (Keinert et al.: ω ≈ 1.2 was best).
pub const DEFAULT_OMEGA: f64 = 1.2;
/// Default fixed-point iterations of the discontinuity reduction (the
/// paper's final renders use 3).
pub const DEFAULT_FIXPOINT: u32 = 3;
/// Largest `fixpoint`.
pub const MAX_FIXPOINT: u32 = 64;
/// A ray "sees" a Lipschitz violation when f / L changes faster than
/// this many units per unit of distance between two of its samples.
pub const LIPSCHITZ_SLACK: f64 = 1.01;

/// What a pixel's colour shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shading {
    /// Phong shading (with shadows or glass when asked for).
    #[default]
    Shade,
    /// f(p) / err(t) at the hit point as a heat map: technique 4 makes it flat.
    Field,
}

/// Sphere tracing settings beyond [`Settings`]; every technique can be
/// switched off so its effect can be measured.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereOptions {
    /// The field is divided by this (≥ 1) to make it 1-Lipschitz.
    pub lipschitz: f64,
    /// Technique 1: over-relaxation factor in [1, 2); 1 is off.
    pub omega: f64,
    /// Technique 2: half-pixel termination and best-candidate choice; off:
    /// terminate at |f| < eps and keep the last point.
    pub screen_space: bool,
    /// Technique 3: secondary rays start 2·max(eps_min, |f(p)|) off the
    /// surface; off: eps_min.
    pub dynamic_eps: bool,
    /// Technique 3's minimum offset and the secondary rays' threshold
    /// (default: the frame's eps).
    pub eps_min: Option<f64>,
    /// Technique 4: fixed-point iterations after a hit; 0 is off.
    pub fixpoint: u32,
    /// Technique 5: a convex bound of a convex object; `None` is off.
    pub bound: Option<Bound>,
    /// Step budget per ray.
    pub max_steps: u32,
    /// Smallest forward step (world units; 0: none).
    pub min_step: f64,
    /// Cast a shadow ray towards the key light.
    pub shadows: bool,
    /// Render the object as absorbing glass (one refraction through it).
    pub glass: bool,
    /// What the colour shows.
    pub shading: Shading,
}

impl Default for SphereOptions {
    fn default() -> Self {
        SphereOptions {
            lipschitz: 1.0,
            omega: DEFAULT_OMEGA,
            screen_space: true,
            dynamic_eps: true,
            eps_min: None,
            fixpoint: DEFAULT_FIXPOINT,
            bound: None,
            max_steps: DEFAULT_MAX_STEPS,
            min_step: 0.0,
            shadows: false,
            glass: false,
            shading: Shading::Shade,
        }
    }
}

impl SphereOptions {
    /// Checks the values a user can get wrong; the message names the flag.
    pub fn check(&self) -> Result<(), String> {
        if !(self.lipschitz >= 1.0 && self.lipschitz.is_finite()) {
            return Err(format!(
                "invalid --lipschitz {}: a Lipschitz bound must be at least 1 (sphere tracing divides the field by it; \
                 a smaller value would step further than a distance field allows)",
                self.lipschitz
            ));
        }
        if !(self.omega >= 1.0 && self.omega < 2.0) {
            return Err(format!("invalid --omega {}: the over-relaxation factor must be in [1, 2) (1 switches it off)", self.omega));
        }
        if self.max_steps == 0 || self.max_steps > MAX_STEPS_LIMIT {
            return Err(format!("invalid --max-steps {}: it must be between 1 and {MAX_STEPS_LIMIT}", self.max_steps));
        }
        if self.fixpoint > MAX_FIXPOINT {
            return Err(format!("invalid --fixpoint {}: at most {MAX_FIXPOINT} iterations", self.fixpoint));
        }
        if !(self.min_step >= 0.0 && self.min_step.is_finite()) {
            return Err(format!("invalid --min-step {}: it must be a width >= 0", self.min_step));
        }
        if self.eps_min.is_some_and(|e| !(e > 0.0 && e.is_finite())) {
            return Err("invalid --eps-min: it must be a positive width".into());
        }
        Ok(())
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Uniforms {
    eye: [f32; 4],
    forward: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    box_min: [f32; 4],
    box_max: [f32; 4],
    bound_a: [f32; 4],
    bound_b: [f32; 4],
    light: [f32; 4],
    size: [u32; 2],
    tile_origin: [u32; 2],
    tile_size: [u32; 2],
    max_steps: u32,
    flags: u32,
    fixpoint: u32,
    bound_kind: u32,
    tan_half_fov: f32,
    eps: f32,
    inf: f32,
    time: f32,
    omega: f32,
    inv_lipschitz: f32,
    pixel_radius: f32,
    min_step: f32,
    eps_min: f32,
    color_mode: u32,
    params: [f32; 64],
}

const FLAG_DEBUG: u32 = 1;
const FLAG_SCREEN: u32 = 2;
const FLAG_DYNAMIC_EPS: u32 = 4;
const FLAG_SHADOWS: u32 = 8;
const FLAG_GLASS: u32 = 16;

/// The kernel's packed `Pixel`: the bisection kernel's layout plus the
/// largest rate of change of f seen along the primary ray.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct RawPixel {
    color_rg: u32,
    color_ba: u32,
    normal_xy: u32,
    normal_z: u32,
    depth: f32,
    steps: u32,
    info: u32,
    ratio: f32,
}

/// The secondary rays compiled into a kernel. They are code, not uniforms:
/// lavapipe inlines every call and pays for the unused ray loops (measured:
/// the city renders 2-3x slower with both compiled in but switched off).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Features {
    /// Shadow rays.
    pub shadows: bool,
    /// Refraction rays (glass).
    pub glass: bool,
}

impl SphereOptions {
    /// The code these options need.
    pub fn features(&self) -> Features {
        Features { shadows: self.shadows, glass: self.glass }
    }
}

/// Keeps the `//!if:NAME` … `//!else` … `//!end` sections of `text` whose
/// NAME is in `on` (and the `else` parts of the others).
fn sections(text: &str, on: &[&str]) -> String {
    let mut out = String::with_capacity(text.len());
    let mut keep: Option<bool> = None;
    for line in text.lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("//!if:") {
            keep = Some(on.contains(&name));
        } else if t == "//!else" {
            keep = keep.map(|k| !k);
        } else if t == "//!end" {
            keep = None;
        } else if keep != Some(false) {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// The complete sphere tracing shader for a formula: the scalar op
/// library and evaluator spliced into the template, with the secondary
/// rays of `features`. The traversal calls nothing but `eval_s`.
pub fn sphere_shader(ir: &Ir, features: Features) -> String {
    let lib = libraries(&[Domain::Scalar]);
    let eval = emit_evaluator(ir, Domain::Scalar);
    let mut on = Vec::new();
    if features.shadows {
        on.push("shadows");
    }
    if features.glass {
        on.push("glass");
    }
    let text = sections(template::SPHERE, &on);
    template::splice(&text, &[("library", &lib), ("evaluator", &eval)]).expect("the sphere template has its markers")
}

/// A compiled sphere tracing pipeline for one formula.
pub struct SphereRenderer<'g> {
    gpu: &'g Gpu,
    pipeline: wgpu::ComputePipeline,
    /// The secondary rays compiled in.
    pub features: Features,
    /// The shader source (validated).
    pub wgsl: String,
    buffers: super::TileBuffers,
}

impl<'g> SphereRenderer<'g> {
    /// Generates, validates (naga) and compiles the kernel with the
    /// secondary rays of `features`.
    pub fn new(gpu: &'g Gpu, ir: &Ir, features: Features) -> Result<SphereRenderer<'g>, RenderError> {
        let wgsl = sphere_shader(ir, features);
        validate(&wgsl)?;
        let pipeline = gpu.pipeline("isotrace sphere", &wgsl)?;
        Ok(SphereRenderer { gpu, pipeline, features, wgsl, buffers: super::TileBuffers::default() })
    }

    /// Renders one frame, tile by tile. `o` may ask only for the secondary
    /// rays the renderer was compiled with.
    pub fn render(&self, s: &Settings, o: &SphereOptions) -> Result<Frame, RenderError> {
        check_settings(s)?;
        o.check().map_err(RenderError::Settings)?;
        if (o.shadows && !self.features.shadows) || (o.glass && !self.features.glass) {
            return Err(RenderError::Settings("the sphere tracing kernel was compiled without the shadow or glass rays asked for".into()));
        }
        let frame = s.camera.frame().map_err(RenderError::Settings)?;
        let start = Instant::now();
        let (w, h) = (s.width, s.height);
        // A tile's pixel records must fit the device's largest storage binding.
        let fit = ((self.gpu.max_storage_binding / std::mem::size_of::<RawPixel>() as u64) as f64).sqrt() as u32 / 8 * 8;
        let tile = s.tile.clamp(8, MAX_SIZE).min(fit.max(8));
        let mut u = uniforms(s, o, &frame)?;
        let blank = PixelOut { color: [0.0; 4], normal: [0.0; 3], depth: f32::INFINITY, evals: 0, level: 0, iso: 0, status: Status::Miss };
        let mut pixels = vec![blank; (w * h) as usize];
        let (mut gpu_ms, mut dispatches, mut fallbacks) = (0.0, 0, 0u64);
        let (mut violations, mut ratio) = (0u64, 0.0f64);
        for ty in (0..h).step_by(tile as usize) {
            for tx in (0..w).step_by(tile as usize) {
                let (tw, th) = (tile.min(w - tx), tile.min(h - ty));
                u.tile_origin = [tx, ty];
                u.tile_size = [tw, th];
                let (raw, ms) = self.dispatch(&u, tw, th)?;
                gpu_ms += ms;
                dispatches += 1;
                for (k, r) in raw.iter().enumerate() {
                    let (i, j) = (tx + k as u32 % tw, ty + k as u32 / tw);
                    fallbacks += (r.info >> 8) as u64;
                    // f32 evaluation noise stays far below 1 %.
                    if r.ratio > LIPSCHITZ_SLACK as f32 {
                        violations += 1;
                    }
                    ratio = ratio.max(r.ratio as f64);
                    pixels[(j * w + i) as usize] = convert(r);
                }
            }
        }
        let stats = Stats {
            gpu_ms,
            dispatches,
            method: Method::Sphere,
            sor_fallbacks: fallbacks,
            lipschitz_violations: violations,
            lipschitz_seen: ratio * o.lipschitz,
            ..Default::default()
        };
        let mut f = Frame { width: w, height: h, pixels, stats };
        f.stats.wall_ms = start.elapsed().as_secs_f64() * 1e3;
        f.summarize();
        f.stats.evals_lower_bound = 0.0; // bisection's bound; sphere tracing has none
        Ok(f)
    }

    fn dispatch(&self, u: &Uniforms, tw: u32, th: u32) -> Result<(Vec<RawPixel>, f64), RenderError> {
        let record = std::mem::size_of::<RawPixel>() as u64;
        let mut raw = Vec::new();
        let (ms, _) = super::dispatch_tile(self.gpu, &self.pipeline, None, "sphere tracing dispatch", bytemuck::bytes_of(u), &[], &self.buffers, (tw, th, record, 1), |b| {
            raw = bytemuck::cast_slice::<u8, RawPixel>(b).to_vec()
        })?;
        Ok((raw, ms))
    }
}

/// The frame's uniforms (tile fields are filled per dispatch).
fn uniforms(s: &Settings, o: &SphereOptions, frame: &crate::render::CameraFrame) -> Result<Uniforms, RenderError> {
    let v4 = |v: glam::DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
    let f4 = |a: f64, b: f64, c: f64, d: f64| [a as f32, b as f32, c as f32, d as f32];
    let (bound_kind, bound_a, bound_b) = match o.bound {
        None => (0, [0.0; 4], [0.0; 4]),
        Some(Bound::Sphere { center: c, radius }) => (1, f4(c[0], c[1], c[2], radius), [0.0; 4]),
        Some(Bound::Box(b)) => (2, f4(b[0], b[2], b[4], 0.0), f4(b[1], b[3], b[5], 0.0)),
    };
    let flag = |on: bool, bit: u32| if on { bit } else { 0 };
    let flags = flag(s.debug_unresolved, FLAG_DEBUG)
        | flag(o.screen_space, FLAG_SCREEN)
        | flag(o.dynamic_eps, FLAG_DYNAMIC_EPS)
        | flag(o.shadows, FLAG_SHADOWS)
        | flag(o.glass, FLAG_GLASS);
    Ok(Uniforms {
        eye: v4(s.camera.eye),
        forward: v4(frame.forward),
        right: v4(frame.right),
        up: v4(frame.up),
        box_min: f4(s.bbox[0], s.bbox[2], s.bbox[4], 0.0),
        box_max: f4(s.bbox[1], s.bbox[3], s.bbox[5], s.clip_sphere.unwrap_or(0.0)),
        bound_a,
        bound_b,
        // A key light from the upper left and in front, so that shadows fall
        // visibly behind and beside the objects.
        light: v4((0.8 * frame.up - 0.2 * frame.forward - 0.7 * frame.right).normalize()),
        size: [s.width, s.height],
        tile_origin: [0, 0],
        tile_size: [0, 0],
        max_steps: o.max_steps,
        flags,
        fixpoint: o.fixpoint,
        bound_kind,
        tan_half_fov: frame.tan_half_fov as f32,
        eps: s.eps as f32,
        inf: f32::INFINITY,
        time: s.time as f32,
        omega: o.omega as f32,
        inv_lipschitz: (1.0 / o.lipschitz) as f32,
        // Half a pixel at unit distance: the screen-space error bound.
        pixel_radius: (frame.tan_half_fov / s.height as f64) as f32,
        min_step: o.min_step as f32,
        eps_min: o.eps_min.unwrap_or(s.eps) as f32,
        color_mode: match o.shading {
            Shading::Shade => 0,
            Shading::Field => 1,
        },
        params: pack_params(&s.params)?,
    })
}

fn convert(r: &RawPixel) -> PixelOut {
    let (status, [cr, cg, cb, ca], [nx, ny, nz]) = decode_common(r.info, [r.color_rg, r.color_ba], [r.normal_xy, r.normal_z]);
    // `level` marks rays that cross the domain (at least one step), so the
    // hit / miss means of the statistics count the same pixels as bisection's.
    PixelOut { color: [cr, cg, cb, ca], normal: [nx, ny, nz], depth: r.depth, evals: r.steps, level: u32::from(r.steps > 0), iso: 0, status }
}

/// The sphere tracer's packed status (low byte of `info`), colour (2 ×
/// unorm16 pairs) and normal (snorm16 pairs).
fn decode_common(info: u32, color: [u32; 2], normal: [u32; 2]) -> (Status, [f32; 4], [f32; 3]) {
    let status = match info & 0xff {
        1 => Status::Hit,
        2 => Status::Unresolved,
        _ => Status::Miss,
    };
    let ([cr, cg], [cb, ca]) = (unorm2(color[0]), unorm2(color[1]));
    let ([nx, ny], [nz, _]) = (snorm2(normal[0]), snorm2(normal[1]));
    (status, [cr, cg, cb, ca], [nx, ny, nz])
}

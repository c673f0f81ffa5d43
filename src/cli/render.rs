//! `isotrace render`: a formula's flags and `.iso` header → a
//! [`FormulaPlan`] (settings, traversal, colouring), then one frame or an
//! animation. A `.scene.json` file goes to [`super::scene_render`].

use super::args::{self, AlgebraArg, SettingsArgs, SphereArgs};
use super::report::{report, report_sphere, warn_lipschitz, warn_unresolved};
use super::{input::FormulaArgs, CliError};
use clap::Args;
use crate::gpu::{Gpu, Renderer};
use crate::layout::KernelColor;
use crate::output::{self, ColorMode};
use crate::render::{BisectOptions, Frame, Method, Settings, Shading, Traversal};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub(super) formula: FormulaArgs,
    /// Output image: .png (8-bit sRGB) or .exr (float RGBA, Z, normals, evals). With --frames, a pattern like frames/f_%04d.png: %d is the frame number, %0Nd pads it with zeros to N digits (N from 1 to 9), %% is a literal %; exactly one number field, in the file name. `-o -` writes a PNG to stdout.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub(super) output: PathBuf,
    /// Replace an existing read-only output file (it keeps its mode).
    #[arg(long)]
    pub(super) force: bool,
    #[arg(long, help = super::scene::ALLOW_SCENE_PATHS_HELP)]
    pub(super) allow_scene_paths: bool,
    /// Image size `WxH` or `N` for a square (default 512x512).
    #[arg(long, value_name = "WxH")]
    pub(super) size: Option<String>,
    #[command(flatten)]
    pub(super) settings: SettingsArgs,
    #[command(flatten)]
    pub(super) sphere: SphereArgs,
    #[command(flatten)]
    pub(super) modalities: super::modality::ModalityArgs,
    /// What the colours show: shade (alias phong), steps (alias evals: the pixel's work as a heat map, scaled to the 99th percentile; steps:MAX for a fixed scale), normal, gradient (bisection: |grad f|, Knoll's Fig. 5), depth (bisection), or field (sphere tracing: f(p) / err(t) at the hit).
    #[arg(long, value_name = "MODE", default_value = "shade")]
    pub(super) color: String,
    /// Print statistics to stderr.
    #[arg(long)]
    pub(super) stats: bool,
    /// Print statistics as one JSON object on stdout.
    #[arg(long)]
    pub(super) json: bool,
    /// Render an animation of N frames with t from --t0 to --t1.
    #[arg(long, value_name = "N")]
    pub(super) frames: Option<u32>,
    /// First time value of an animation.
    #[arg(long, value_name = "A", allow_hyphen_values = true, requires = "frames")]
    t0: Option<f64>,
    /// Last time value of an animation.
    #[arg(long, value_name = "B", allow_hyphen_values = true, requires = "frames")]
    t1: Option<f64>,
    #[command(flatten)]
    shard: super::batch::ShardArgs,
    /// With --frames: leave frames whose file exists and is a whole image of the frame size (writes are atomic; a damaged file is rendered again); a re-run renders only what is missing.
    #[arg(long, requires = "frames")]
    skip_existing: bool,
}
/// The traversal the flags and the header ask for, checked for flags that
/// belong to the other traversal.
fn traversal(a: &RenderArgs, loaded: &super::input::Loaded, color: ColorMode) -> Result<Traversal, CliError> {
    let header = loaded.header.as_ref();
    let f = &loaded.formula;
    let shadows = a.sphere.shadows || header.and_then(|h| h.modalities.shadows).unwrap_or(false);
    match args::method(a.sphere.method.as_deref(), header)? {
        Method::Bisect => {
            let kernel_color = bisect_color(a, color)?;
            if a.settings.field == Some(args::FieldArg::Scene) && a.settings.algebra == Some(AlgebraArg::Raa) {
                return Err(CliError::input("--algebra raa: a scene's nodes are enclosed in interval arithmetic only (--field scene): give --algebra ia or leave it out"));
            }
            let domain = args::resolve_algebra(a.settings.algebra.or(header.and_then(|h| h.algebra).map(args::algebra_arg)).unwrap_or(AlgebraArg::Auto), &f.ir);
            if domain == crate::ir::Domain::Scalar {
                return Err(CliError::input("--algebra scalar cannot render: the traversal needs an inclusion algebra (ia, raa or auto)"));
            }
            let mut m = super::modality::modalities(&a.modalities, shadows, kernel_color, header)?;
            m.inline = loaded.inline.clone();
            Ok(Traversal::Bisect(BisectOptions { modalities: m, ..BisectOptions::new(domain) }))
        }
        Method::Sphere => {
            if loaded.inline.is_some() {
                return Err(CliError::input("--inline applies to --method bisect only"));
            }
            refuse_bisect_flags(a, color)?;
            let mut o = args::sphere_options(&a.sphere, header)?;
            if color == ColorMode::Field {
                o.shading = Shading::Field;
            }
            Ok(Traversal::Sphere(o))
        }
    }
}
/// Refuses the flags of sphere tracing when bisecting, and gives the
/// kernel's colouring (formulas and scenes alike).
pub(super) fn bisect_color(a: &RenderArgs, color: ColorMode) -> Result<KernelColor, CliError> {
    if let Some(flag) = a.sphere.given().first() {
        return Err(CliError::input(format!("{flag} applies to --method sphere only")));
    }
    Ok(match color {
        ColorMode::Field => return Err(CliError::input("--color field applies to --method sphere only")),
        ColorMode::Gradient => KernelColor::Gradient,
        ColorMode::Depth => KernelColor::Depth,
        _ => KernelColor::Phong,
    })
}

/// Refuses the flags of bisection when sphere tracing (formulas and scenes alike).
pub(super) fn refuse_bisect_flags(a: &RenderArgs, color: ColorMode) -> Result<(), CliError> {
    let misplaced = [
        (!a.modalities.given().is_empty(), format!("{} applies to --method bisect only", a.modalities.given().first().copied().unwrap_or(""))),
        (matches!(color, ColorMode::Gradient | ColorMode::Depth), format!("--color {} applies to --method bisect only", a.color)),
        (a.settings.algebra.is_some(), "--algebra applies to --method bisect only (sphere tracing evaluates the scalar field)".into()),
        (a.settings.max_iter.is_some(), "--max-iter applies to --method bisect only; sphere tracing's budget is --max-steps".into()),
    ];
    match misplaced.into_iter().find(|(bad, _)| *bad) {
        Some((_, m)) => Err(CliError::input(m)),
        None => Ok(()),
    }
}

/// A render of a formula as the flags and the header ask for it, before
/// any device work: what `render` runs, and what `the viewer sends to the page
/// and renders for "save PNG".
pub struct FormulaPlan {
    /// The compiled formula and its header.
    pub loaded: super::input::Loaded,
    /// The frame.
    pub settings: Settings,
    /// The traversal and its options.
    pub traversal: Traversal,
    /// The colouring.
    pub color: ColorMode,
    /// The colouring as given (flag or header).
    pub color_text: String,
}

/// Loads the formula and checks every flag against it and its header.
pub fn plan(a: &RenderArgs) -> Result<FormulaPlan, CliError> {
    plan_loaded(a, a.formula.load_with_header()?)
}

/// [`plan`] of a formula already loaded (the viewer looks at its
/// parameters first).
pub fn plan_loaded(a: &RenderArgs, loaded: super::input::Loaded) -> Result<FormulaPlan, CliError> {
    let size = args::parse_size(a.size.as_deref().unwrap_or("512"))?;
    let settings = args::settings(&a.settings, size, &loaded.formula, loaded.header.as_ref())?;
    // --color defaults to "shade"; a header's colour applies unless the flag was given.
    let header_color = loaded.header.as_ref().and_then(|h| h.color.clone());
    let color_text = if a.color == "shade" { header_color.unwrap_or_else(|| a.color.clone()) } else { a.color.clone() };
    let color = output::parse_color(&color_text).map_err(|m| CliError::input(format!("invalid --color '{color_text}': {m}")))?;
    let traversal = traversal(a, &loaded, color)?;
    Ok(FormulaPlan { loaded, settings, traversal, color, color_text })
}

pub fn run(a: RenderArgs) -> Result<ExitCode, CliError> {
    if a.json && output::is_stdout(&a.output) {
        return Err(CliError::input("--json prints to stdout, where -o - writes the image: write the image to a file, or leave out --json"));
    }
    if let Some(path) = a.formula.scene_path() {
        return super::scene_render::run(&a, &path);
    }
    let FormulaPlan { loaded, settings: s, traversal, color, color_text } = plan(&a)?;
    let f = &loaded.formula;
    let header = loaded.header.as_ref();
    let (t0, t1) = time_range(&a, header, &s)?;
    let outputs = super::frames::Outputs::new(&a.output, a.frames, a.shard.resolve()?, a.skip_existing)?;
    outputs.check(a.force, a.skip_existing)?;
    let animation = match &outputs {
        super::frames::Outputs::One(_) => None,
        super::frames::Outputs::Frames { pattern, n, shard, .. } => {
            let settings = super::animate::frame_settings(f, &pattern.file_pattern(), *n, (t0, t1), &s, &traversal, &color_text);
            Some(super::animate::Animation { outputs: &outputs, n: *n, t0, t1, skip_existing: a.skip_existing, settings, shard: *shard })
        }
    };
    if let Some(an) = &animation {
        an.check_resume()?;
    }
    let todo = animation.as_ref().map_or(1, |an| an.todo());
    if let Some(an) = animation.as_ref().filter(|an| an.outputs.len() == 0) {
        eprintln!("note: shard {} has none of the {} frames", an.shard, an.n);
    }
    let mut traversal = traversal;
    // --field, else the .iso header's `field`, else auto.
    let field_given = a.settings.field.or(header.and_then(|h| h.field).map(args::field_arg));
    let field = args::prepare_field(field_given, f, &s.params, &mut traversal, a.sphere.lipschitz.is_some(), todo as u64)?;
    if matches!(&traversal, Traversal::Sphere(o) if o.synchronized) && field.kind() != crate::field::FieldKind::Scene {
        return Err(CliError::input("--scene-walk applies to scenes: a .scene.json file, or a formula of distance forms traced with --field scene"));
    }
    // No device is opened when every frame of the run is already there.
    let pixel_frames = u64::from(s.width) * u64::from(s.height) * todo as u64;
    let gpu = if todo > 0 { Some(args::open_gpu(args::shader_opt(a.settings.shader_opt, pixel_frames, true))?) } else { None };
    let renderer = match &gpu {
        Some(g) => {
            let t = traversal.clone();
            let size = || crate::kernel::assemble(field.source(&f.ir), &t).wgsl.len();
            Some(super::notice::with_compile_note(size, || Renderer::new(g, field.source(&f.ir), traversal)).map_err(super::error::render_error)?)
        }
        None => None,
    };
    let (last, heat_max) = match (&animation, &renderer, &gpu, &outputs) {
        (Some(an), r, _, _) => an.run(r.as_ref().zip(gpu.as_ref()).map(|(r, g)| (r, &g.info)), &s, color)?,
        (None, Some(r), Some(g), super::frames::Outputs::One(path)) => {
            let (frame, heat_max) = render_one(r, g, field.source(&f.ir), &s, color, path)?;
            (Some(frame), heat_max)
        }
        _ => (None, None),
    };
    if let (Some(frame), Some(renderer), Some(gpu)) = (last, &renderer, &gpu) {
        report_last(&a, &frame, &s, renderer, gpu, heat_max);
    }
    Ok(ExitCode::SUCCESS)
}

/// An animation's time range: `--t0`/`--t1`, else the header's `animate`,
/// else from the frame's time to one past it.
fn time_range(a: &RenderArgs, header: Option<&crate::catalog::Header>, s: &Settings) -> Result<(f64, f64), CliError> {
    let anim = header.and_then(|h| h.animate);
    let (t0, t1) = (a.t0.or(anim.map(|r| r[0])).unwrap_or(s.time), a.t1.or(anim.map(|r| r[1])).unwrap_or(s.time + 1.0));
    for (flag, v) in [("--t0", t0), ("--t1", t1)] {
        if !v.is_finite() {
            return Err(CliError::input(format!("invalid {flag} {v}: it must be a finite number")));
        }
    }
    Ok((t0, t1))
}

/// Renders the one frame of a run without `--frames`, recolours it and
/// writes it to `path`; the heat map's maximum for `--color steps`.
fn render_one(r: &Renderer, gpu: &Gpu, source: &dyn crate::field::FieldSource, s: &Settings, color: ColorMode, path: &Path) -> Result<(Frame, Option<u32>), CliError> {
    let what = || {
        let field = source.describe();
        let device = gpu.info.name.clone();
        format!("the {}x{} frame ({field}, on {device}; the first frame includes the driver's compile)", s.width, s.height)
    };
    let mut frame = super::notice::with_render_note(what, || r.render(s)).map_err(super::error::render_error)?;
    let heat_max = output::recolor(&mut frame, color);
    output::write_frame(path, &frame).map_err(super::error::output_error)?;
    super::notice::wrote(path, &super::notice::size(frame.width, frame.height));
    Ok((frame, heat_max))
}

/// `--stats` / `--json` of the last frame rendered, and its warnings.
fn report_last(a: &RenderArgs, frame: &Frame, s: &Settings, renderer: &Renderer, gpu: &Gpu, heat_max: Option<u32>) {
    match renderer.traversal() {
        Traversal::Bisect(b) => report(a, frame, s, b.algebra, gpu, renderer.field_name()),
        Traversal::Sphere(o) => report_sphere(a, frame, s, &o, gpu, renderer.field_name()),
    }
    warn_unresolved(frame, &renderer.traversal(), s, renderer.field_name(), renderer.field_shares_loop_cap().is_some());
    if let Traversal::Sphere(o) = renderer.traversal() {
        warn_lipschitz(frame, &o);
    }
    if let (Some(m), true) = (heat_max, a.stats) {
        eprintln!("--color steps: white = {m} {}", output::work_channel(frame));
    }
}

//! `isotrace render`: flags → [`Settings`] (and [`SphereOptions`] for
//! `--method sphere`), one frame or an animation.

use super::{input::FormulaArgs, resolve_algebra, AlgebraArg, CliError};
use clap::Args;
use glam::DVec3;
use isotrace::gpu::{Gpu, Renderer, ShaderOpt};
use isotrace::layout::KernelColor;
use isotrace::render::settings::DEFAULT_MAX_ITER;
use isotrace::render::{BisectOptions, Settings, Shading, SphereOptions, Traversal, Unresolved, View};
use isotrace::output::{self, ColorMode};
use isotrace::catalog::{self, Header};
use isotrace::render::{Bound, Method};
use std::path::PathBuf;
use std::process::ExitCode;
pub(super) use super::report::{report_sphere, warn_lipschitz, warn_unresolved};
use super::report::report;

/// Flags shared by `render` and `bench`.
#[derive(Args, Debug, Clone, Default)]
pub struct ViewArgs {
    /// Domain box: `x0,x1,y0,y1,z0,z1` or `-a,a` for a cube (default -2,2).
    #[arg(long = "box", value_name = "BOX", allow_hyphen_values = true)]
    pub bbox: Option<String>,
    /// Eye position `x,y,z` (default: azimuth 35°, elevation 25° from the target, whole box in view).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// Point looked at (default: the box centre).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub target: Option<String>,
    /// Up direction (default 0,0,1).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub up: Option<String>,
    /// Vertical field of view in degrees (default 40).
    #[arg(long, value_name = "DEG")]
    pub fov: Option<f64>,
    /// Termination width: absolute (0.001) or a power of two (2^-11); default 2^-11 × box diagonal.
    #[arg(long, value_name = "EPS", allow_hyphen_values = true)]
    pub eps: Option<String>,
    /// Time value t.
    #[arg(long = "t", value_name = "T", allow_hyphen_values = true)]
    pub time: Option<f64>,
    /// A user parameter, `name=value` (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE", allow_hyphen_values = true)]
    pub params: Vec<String>,
    /// Inclusion algebra: interval (ia), reduced affine (raa) or chosen per formula (auto).
    #[arg(long, value_enum)]
    pub algebra: Option<AlgebraArg>,
    /// Field source: compiled (the formula generated into the shader), tape (a fixed interpreter runs the formula from a buffer: no compile wall for big formulas) or auto (by formula size, algebra and method).
    #[arg(long, value_enum)]
    pub field: Option<super::FieldArg>,
    /// Iteration budget per pixel (pixels that exceed it are reported as unresolved).
    #[arg(long, value_name = "N")]
    pub max_iter: Option<u32>,
    /// Largest tile side per dispatch (renders are split so a GPU watchdog never fires).
    #[arg(long, value_name = "PIXELS", default_value_t = 1024)]
    pub tile: u32,
    /// Clip to a ball around the box centre as well as the box: `sphere:R`.
    #[arg(long, value_name = "sphere:R")]
    pub clip: Option<String>,
    /// How pixels that exhausted the budget (--max-iter, --max-steps) are
    /// drawn: `hatch` (their best guess under magenta stripes), `magenta`,
    /// or `guess` (like hits). A warning counts them in every case.
    #[arg(long, value_enum, value_name = "STYLE", default_value_t = UnresolvedArg::Hatch)]
    pub unresolved: UnresolvedArg,
    /// Short for `--unresolved magenta`.
    #[arg(long, conflicts_with = "unresolved")]
    pub debug_unresolved: bool,
    /// Whether a CPU driver (Mesa's lavapipe) runs LLVM's optimisation passes over the kernels: full (the fastest frames), none (compiles 2-3x sooner; frames of a compiled formula 1.5-2x slower, the tape's about the same; the same pictures) or auto (none for a job of at most one 1024x1024 frame's pixels, else full; bench: full). Fixed for the process by its first device; GALLIVM_PERF, when set, stands unless this flag is given. Other drivers ignore it.
    #[arg(long, value_enum, value_name = "OPT")]
    pub shader_opt: Option<ShaderOptArg>,
}

/// `--shader-opt`: see `isotrace::gpu::driver`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderOptArg {
    Auto,
    Full,
    None,
}

/// The driver optimisation to ask for: the flag's, else (without a
/// GALLIVM_PERF of the user's) auto for a job of `pixel_frames`, or full
/// where the job measures frames (`auto_none` false: bench).
pub fn shader_opt(arg: Option<ShaderOptArg>, pixel_frames: u64, auto_none: bool) -> Option<ShaderOpt> {
    let auto = || if auto_none { isotrace::gpu::driver::auto_shader_opt(pixel_frames) } else { ShaderOpt::Full };
    match arg {
        Some(ShaderOptArg::Full) => Some(ShaderOpt::Full),
        Some(ShaderOptArg::None) => Some(ShaderOpt::None),
        Some(ShaderOptArg::Auto) => Some(auto()),
        None if std::env::var_os("GALLIVM_PERF").is_some() => None,
        None => Some(auto()),
    }
}

/// `--unresolved`: see `isotrace::render::Unresolved`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum UnresolvedArg {
    #[default]
    Hatch,
    Magenta,
    Guess,
}

/// Sphere tracing flags (`--method sphere`); every technique of Keinert
/// et al. can be switched off to measure it.
#[derive(Args, Debug, Clone, Default)]
pub struct SphereArgs {
    /// Traversal: bisect (interval / affine bisection, any formula) or sphere (sphere tracing, distance bounds only). Default: the .iso header's method, else bisect.
    #[arg(long, value_name = "METHOD")]
    pub method: Option<String>,
    /// Sphere tracing: a Lipschitz bound L >= 1 of the formula; the field is divided by it (needed when the formula is not 1-Lipschitz, e.g. a displaced distance field).
    #[arg(long, value_name = "L", allow_hyphen_values = true)]
    pub lipschitz: Option<f64>,
    /// Sphere tracing: over-relaxation factor in [1, 2) (technique 1; 1 switches it off; default 1.2).
    #[arg(long, value_name = "W", allow_hyphen_values = true)]
    pub omega: Option<f64>,
    /// Sphere tracing: terminate at |f| < eps and keep the last point on an exhausted budget, instead of the screen-space criterion and best candidate (technique 2 off).
    #[arg(long)]
    pub no_screen_space: bool,
    /// Sphere tracing: offset secondary rays by a fixed eps-min instead of 2 max(eps-min, |f(p)|) (technique 3 off).
    #[arg(long)]
    pub no_dynamic_eps: bool,
    /// Sphere tracing: technique 3's minimum offset and the secondary rays' threshold (default: eps).
    #[arg(long, value_name = "E")]
    pub eps_min: Option<String>,
    /// Sphere tracing: fixed-point iterations that reduce discontinuities (technique 4; 0 switches it off; default 3).
    #[arg(long, value_name = "N")]
    pub fixpoint: Option<u32>,
    /// Sphere tracing: the object is convex and inside this convex volume, sphere:cx,cy,cz,r or box:x0,x1,y0,y1,z0,z1 (technique 5; default: the .iso header's bound).
    #[arg(long, value_name = "SPEC", allow_hyphen_values = true)]
    pub bound: Option<String>,
    /// Sphere tracing: ignore the header's bound (technique 5 off).
    #[arg(long, conflicts_with = "bound")]
    pub no_bound: bool,
    /// Sphere tracing: step budget per ray (default 512); pixels that exhaust it are reported as unconverged.
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u32>,
    /// Sphere tracing: smallest forward step in world units (default 0: none).
    #[arg(long, value_name = "S")]
    pub min_step: Option<f64>,
    /// Cast shadow rays towards the light (both methods; with bisection see also --light and --shadow-eps).
    #[arg(long)]
    pub shadows: bool,
    /// Sphere tracing: render the object as absorbing glass (a refraction ray through it).
    #[arg(long)]
    pub glass: bool,
    /// Scenes: how the primary rays of an 8x8 tile walk its depth slabs: `ray` (default), each on its own; `tile`, together, each slab's pruned view copied into workgroup memory (Zanni et al.'s Algorithm 3; slower on lavapipe).
    #[arg(long, value_name = "WALK", value_parser = ["ray", "tile"])]
    pub scene_walk: Option<String>,
}

impl SphereArgs {
    /// The sphere tracing flags that were given (for "only with --method sphere").
    fn given(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        let flags: [(&str, bool); 12] = [
            ("--lipschitz", self.lipschitz.is_some()),
            ("--omega", self.omega.is_some()),
            ("--no-screen-space", self.no_screen_space),
            ("--no-dynamic-eps", self.no_dynamic_eps),
            ("--eps-min", self.eps_min.is_some()),
            ("--fixpoint", self.fixpoint.is_some()),
            ("--bound", self.bound.is_some()),
            ("--no-bound", self.no_bound),
            ("--max-steps", self.max_steps.is_some()),
            ("--min-step", self.min_step.is_some()),
            ("--glass", self.glass),
            ("--scene-walk", self.scene_walk.is_some()),
        ];
        for (name, on) in flags {
            if on {
                v.push(name);
            }
        }
        v
    }
}

/// The traversal: `--method`, else the header's, else bisection.
pub fn method(arg: Option<&str>, header: Option<&Header>) -> Result<Method, CliError> {
    match arg {
        Some(m) => Method::parse(m).map_err(|e| input(format!("invalid --method '{m}': {e}"))),
        None => Ok(header.and_then(|h| h.method).unwrap_or(Method::Bisect)),
    }
}

/// The sphere tracing options from flags, with the header's `lipschitz`
/// and `bound` as defaults; checked before any GPU work.
pub fn sphere_options(a: &SphereArgs, header: Option<&Header>) -> Result<SphereOptions, CliError> {
    let d = SphereOptions::default();
    let bound = match (&a.bound, a.no_bound) {
        (_, true) => None,
        (Some(b), _) => Some(Bound::parse(b).map_err(|m| input(format!("invalid --bound '{b}': {m}")))?),
        (None, false) => header.and_then(|h| h.bound),
    };
    let eps_min = match &a.eps_min {
        Some(e) => Some(catalog::parse_eps(e).map_err(|m| input(format!("invalid --eps-min '{e}': {m}")))?),
        None => None,
    };
    let o = SphereOptions {
        lipschitz: a.lipschitz.or(header.and_then(|h| h.lipschitz)).unwrap_or(1.0),
        omega: a.omega.unwrap_or(d.omega),
        screen_space: !a.no_screen_space,
        dynamic_eps: !a.no_dynamic_eps,
        eps_min,
        fixpoint: a.fixpoint.unwrap_or(d.fixpoint),
        bound,
        max_steps: a.max_steps.unwrap_or(d.max_steps),
        min_step: a.min_step.unwrap_or(0.0),
        shadows: a.shadows,
        glass: a.glass,
        shading: Shading::Shade,
        synchronized: a.scene_walk.as_deref() == Some("tile"),
    };
    o.check().map_err(|e| input(super::settings_message(&e)))?;
    Ok(o)
}

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
    pub(super) view: ViewArgs,
    #[command(flatten)]
    pub(super) sphere: SphereArgs,
    #[command(flatten)]
    pub(super) modal: super::modality::ModalityArgs,
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

fn input(m: impl Into<String>) -> CliError {
    CliError::Input(m.into())
}

/// Parses `WxH` or `N`.
pub fn parse_size(s: &str) -> Result<(u32, u32), CliError> {
    let bad = || input(format!("invalid --size '{s}': expected WxH like 1024x768, or N for a square"));
    let (w, h) = match s.split_once(['x', 'X']) {
        Some((a, b)) => (a.trim().parse::<u32>().map_err(|_| bad())?, b.trim().parse::<u32>().map_err(|_| bad())?),
        None => {
            let n = s.trim().parse::<u32>().map_err(|_| bad())?;
            (n, n)
        }
    };
    let max = isotrace::render::settings::MAX_SIZE;
    if w == 0 || h == 0 || w > max || h > max {
        return Err(input(format!("invalid --size '{s}': each side must be between 1 and {max}")));
    }
    Ok((w, h))
}

/// `--box`: 2 or 6 numbers.
pub fn parse_box(s: &str) -> Result<[f64; 6], CliError> {
    catalog::parse_box(s).map_err(|m| input(format!("invalid --box '{s}': {m}")))
}

fn parse_vec3(flag: &str, s: &str) -> Result<DVec3, CliError> {
    catalog::parse_vec3(s).map(DVec3::from_array).map_err(|m| input(format!("invalid {flag} '{s}': {m}")))
}

/// `--clip sphere:R`.
pub fn parse_clip(s: &str) -> Result<f64, CliError> {
    s.strip_prefix("sphere:")
        .and_then(|r| r.trim().parse::<f64>().ok())
        .filter(|r| *r > 0.0 && r.is_finite())
        .ok_or_else(|| input(format!("invalid --clip '{s}': expected sphere:R with a radius R > 0")))
}

/// `--param name=value` pairs. A value is a number as `--eps` takes it
/// (`0.5`, `2^-1`). A name given twice is an error: the two values would
/// silently disagree (a header's value is overridden, not repeated).
pub fn parse_params(list: &[String]) -> Result<Vec<(String, f64)>, CliError> {
    let mut out: Vec<(String, f64)> = Vec::with_capacity(list.len());
    for p in list {
        let (n, v) = p.split_once('=').ok_or_else(|| input(format!("invalid --param '{p}': expected name=value")))?;
        // Plain float syntax as before (a non-finite value is the settings'
        // error); otherwise the power syntax of --eps.
        let v = match v.trim().parse::<f64>() {
            Ok(x) => x,
            Err(_) => catalog::parse_number(v).map_err(|m| match m.starts_with("expected") {
                true => input(format!("invalid --param '{p}': '{v}' is not a number")),
                false => input(format!("invalid --param '{p}': {m}")),
            })?,
        };
        let n = n.trim().to_string();
        if let Some(j) = out.iter().position(|(m, _)| *m == n) {
            return Err(input(format!("--param {n} is given twice ('{}' and '{p}'): give each parameter once", list[j])));
        }
        out.push((n, v));
    }
    Ok(out)
}

/// The view flags applied over `v` (a header's view, or a default): the
/// flags override it; parameters given by flags come after the header's,
/// so the last value given wins.
pub fn view_flags(view: &ViewArgs, mut v: View) -> Result<View, CliError> {
    if let Some(b) = &view.bbox {
        v.bbox = parse_box(b)?;
    }
    if let Some(e) = &view.eps {
        v.eps = Some(catalog::parse_eps(e).map_err(|m| input(format!("invalid --eps '{e}': {m}")))?);
    }
    v.fov = view.fov.or(v.fov);
    if let Some(t) = &view.target {
        v.target = Some(parse_vec3("--target", t)?);
    }
    if let Some(e) = &view.eye {
        v.eye = Some(parse_vec3("--eye", e)?);
    }
    if let Some(u) = &view.up {
        v.up = Some(parse_vec3("--up", u)?);
    }
    if let Some(c) = &view.clip {
        v.clip = Some(parse_clip(c)?);
    }
    v.time = view.time.or(v.time);
    v.params.extend(parse_params(&view.params)?);
    check_framing(view, &v)?;
    Ok(v)
}

/// Refuses a box too large to frame, naming the box: without --eye the
/// eye is derived from it, and its own check would name --eye, which the
/// user never gave.
fn check_framing(view: &ViewArgs, v: &View) -> Result<(), CliError> {
    let fov = v.fov.unwrap_or(isotrace::render::view::DEFAULT_FOV);
    // A bad --fov is its own error (Camera::frame checks it first).
    if v.eye.is_some() || !(fov > 0.0 && fov < 180.0) {
        return Ok(());
    }
    let eye = isotrace::render::Camera::default_for(&v.bbox, fov, 1.0).eye;
    if eye.is_finite() && eye.abs().max_element() < 1e30 {
        return Ok(());
    }
    let what = match &view.bbox {
        Some(b) => format!("invalid --box '{b}'"),
        None => "invalid box in the .iso header".to_string(),
    };
    let at = eye.to_array().map(isotrace::diag::show_number).join(",");
    Err(input(format!("{what}: too large to frame, the default eye would be at {at} (coordinates must be below 1e30); give a smaller box, or --eye")))
}

/// The budget, tile and debug flags on top of a view's settings, checked
/// before any GPU work.
pub fn finish_settings(view: &ViewArgs, mut s: Settings) -> Result<Settings, CliError> {
    s.max_iter = view.max_iter.unwrap_or(DEFAULT_MAX_ITER);
    s.tile = view.tile;
    s.unresolved = match (view.debug_unresolved, view.unresolved) {
        (true, _) | (_, UnresolvedArg::Magenta) => Unresolved::Magenta,
        (_, UnresolvedArg::Hatch) => Unresolved::Hatch,
        (_, UnresolvedArg::Guess) => Unresolved::Guess,
    };
    s.check().map_err(|e| input(super::settings_message(&e)))?;
    Ok(s)
}

/// Maps a view error: settings name their flag, parameters are formula
/// diagnostics.
pub fn view_error(e: isotrace::render::ViewError) -> CliError {
    match e {
        isotrace::render::ViewError::Settings(e) => input(super::settings_message(&e)),
        isotrace::render::ViewError::Param(e) => CliError::Formula(e),
    }
}

/// Builds the frame settings from flags, with an `.iso` header's view as
/// defaults (flags override it); validated before any GPU work.
pub fn settings(view: &ViewArgs, size: (u32, u32), f: &isotrace::Formula, header: Option<&Header>) -> Result<Settings, CliError> {
    let v = view_flags(view, header.map_or_else(View::default, Header::view))?;
    let (s, warnings) = v.settings(f, size.0, size.1).map_err(view_error)?;
    for w in warnings {
        eprint!("{}", w.render("", "", false));
    }
    finish_settings(view, s)
}

/// The traversal the flags and the header ask for, checked for flags that
/// belong to the other traversal.
fn traversal(a: &RenderArgs, loaded: &super::input::Loaded, color: ColorMode) -> Result<Traversal, CliError> {
    let header = loaded.header.as_ref();
    let f = &loaded.formula;
    let shadows = a.sphere.shadows || header.and_then(|h| h.modalities.shadows).unwrap_or(false);
    match method(a.sphere.method.as_deref(), header)? {
        Method::Bisect => {
            if let Some(flag) = a.sphere.given().first() {
                return Err(input(format!("{flag} applies to --method sphere only")));
            }
            if color == ColorMode::Field {
                return Err(input("--color field applies to --method sphere only"));
            }
            let domain = resolve_algebra(a.view.algebra.or(header.and_then(|h| h.algebra).map(algebra_arg)).unwrap_or(AlgebraArg::Auto), &f.ir);
            if domain == isotrace::ir::Domain::Scalar {
                return Err(input("--algebra scalar cannot render: the traversal needs an inclusion algebra (ia, raa or auto)"));
            }
            let kernel_color = match color {
                ColorMode::Gradient => KernelColor::Gradient,
                ColorMode::Depth => KernelColor::Depth,
                _ => KernelColor::Phong,
            };
            let mut m = super::modality::modalities(&a.modal, shadows, kernel_color, header)?;
            m.inline = loaded.inline.clone();
            Ok(Traversal::Bisect(BisectOptions { modalities: m, ..BisectOptions::new(domain) }))
        }
        Method::Sphere => {
            let misplaced = [
                (loaded.inline.is_some(), "--inline applies to --method bisect only".to_string()),
                (!a.modal.given().is_empty(), format!("{} applies to --method bisect only", a.modal.given().first().copied().unwrap_or(""))),
                (matches!(color, ColorMode::Gradient | ColorMode::Depth), format!("--color {} applies to --method bisect only", a.color)),
                (a.view.algebra.is_some(), "--algebra applies to --method bisect only (sphere tracing evaluates the scalar field)".into()),
                (a.view.max_iter.is_some(), "--max-iter applies to --method bisect only; sphere tracing's budget is --max-steps".into()),
            ];
            if let Some((_, m)) = misplaced.into_iter().find(|(bad, _)| *bad) {
                return Err(input(m));
            }
            let mut o = sphere_options(&a.sphere, header)?;
            if color == ColorMode::Field {
                o.shading = Shading::Field;
            }
            Ok(Traversal::Sphere(o))
        }
    }
}

/// The CLI value for a header's `algebra`.
pub fn algebra_arg(a: catalog::Algebra) -> AlgebraArg {
    match a {
        catalog::Algebra::Ia => AlgebraArg::Ia,
        catalog::Algebra::Raa => AlgebraArg::Raa,
        catalog::Algebra::Auto => AlgebraArg::Auto,
    }
}

/// Opens the device (asking a CPU driver for `opt`, `None`: as the
/// environment says), mapping "no adapter" to exit code 2.
pub fn open_gpu(opt: Option<ShaderOpt>) -> Result<Gpu, CliError> {
    opt.map_or_else(Gpu::new, Gpu::with_shader_opt).map_err(|e| match e {
        isotrace::gpu::GpuError::NoAdapter => CliError::NoDevice(e.to_string()),
        other => CliError::NoDevice(other.to_string()),
    })
}

/// A render of a formula as the flags and the header ask for it, before
/// any device work: what `render` runs, and what `view` sends to the page
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
    let size = parse_size(a.size.as_deref().unwrap_or("512"))?;
    let settings = settings(&a.view, size, &loaded.formula, loaded.header.as_ref())?;
    // --color defaults to "shade"; a header's colour applies unless the flag was given.
    let header_color = loaded.header.as_ref().and_then(|h| h.color.clone());
    let color_text = if a.color == "shade" { header_color.unwrap_or_else(|| a.color.clone()) } else { a.color.clone() };
    let color = output::parse_color(&color_text).map_err(|m| input(format!("invalid --color '{color_text}': {m}")))?;
    let traversal = traversal(a, &loaded, color)?;
    Ok(FormulaPlan { loaded, settings, traversal, color, color_text })
}

pub fn run(a: RenderArgs) -> Result<ExitCode, CliError> {
    if a.json && output::is_stdout(&a.output) {
        return Err(input("--json prints to stdout, where -o - writes the image: write the image to a file, or leave out --json"));
    }
    if let Some(path) = a.formula.scene_path() {
        return super::scene_render::run(&a, &path);
    }
    let FormulaPlan { loaded, settings: s, traversal, color, color_text } = plan(&a)?;
    let f = &loaded.formula;
    let header = loaded.header.as_ref();
    let anim = header.and_then(|h| h.animate);
    let (t0, t1) = (a.t0.or(anim.map(|r| r[0])).unwrap_or(s.time), a.t1.or(anim.map(|r| r[1])).unwrap_or(s.time + 1.0));
    for (flag, v) in [("--t0", t0), ("--t1", t1)] {
        if !v.is_finite() {
            return Err(input(format!("invalid {flag} {v}: it must be a finite number")));
        }
    }
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
    let field_given = a.view.field.or(header.and_then(|h| h.field).map(super::field_arg));
    let field = super::prepare_field(field_given, f, &s.params, &mut traversal, a.sphere.lipschitz.is_some(), todo as u64)?;
    if matches!(&traversal, Traversal::Sphere(o) if o.synchronized) && field.kind() != isotrace::field::FieldKind::Scene {
        return Err(input("--scene-walk applies to scenes: a .scene.json file, or a formula of distance forms traced with --field scene"));
    }
    // No device is opened when every frame of the run is already there.
    let pixel_frames = u64::from(s.width) * u64::from(s.height) * todo as u64;
    let gpu = if todo > 0 { Some(open_gpu(shader_opt(a.view.shader_opt, pixel_frames, true))?) } else { None };
    let renderer = match &gpu {
        Some(g) => {
            let t = traversal.clone();
            let size = || isotrace::kernel::assemble(field.source(&f.ir), &t).wgsl.len();
            Some(super::with_compile_note(size, || Renderer::new(g, field.source(&f.ir), traversal)).map_err(super::render_error)?)
        }
        None => None,
    };
    let (last, heat_max) = match (&animation, &renderer, &outputs) {
        (Some(an), r, _) => an.run(r.as_ref().zip(gpu.as_ref()).map(|(r, g)| (r, &g.info)), &s, color)?,
        (None, Some(r), super::frames::Outputs::One(path)) => {
            let what = || {
                let field = field.source(&f.ir).describe();
                let device = gpu.as_ref().map_or(String::new(), |g| g.info.name.clone());
                format!("the {}x{} frame ({field}, on {device}; the first frame includes the driver's compile)", s.width, s.height)
            };
            let mut frame = super::with_render_note(what, || r.render(&s)).map_err(super::render_error)?;
            let heat_max = output::recolor(&mut frame, color);
            output::write_frame(path, &frame).map_err(super::output_error)?;
            super::notice::wrote(path, &super::notice::size(frame.width, frame.height));
            (Some(frame), heat_max)
        }
        _ => (None, None),
    };
    if let (Some(frame), Some(renderer), Some(gpu)) = (last, &renderer, &gpu) {
        match renderer.traversal() {
            Traversal::Bisect(b) => report(&a, &frame, &s, b.algebra, gpu, renderer.field_name()),
            Traversal::Sphere(o) => report_sphere(&a, &frame, &s, &o, gpu, renderer.field_name()),
        }
        warn_unresolved(&frame, &renderer.traversal(), &s, renderer.field_name(), renderer.field_shares_loop_cap().is_some());
        if let Traversal::Sphere(o) = renderer.traversal() {
            warn_lipschitz(&frame, &o);
        }
        if let (Some(m), true) = (heat_max, a.stats) {
            eprintln!("--color steps: white = {m} {}", output::work_channel(&frame));
        }
    }
    Ok(ExitCode::SUCCESS)
}


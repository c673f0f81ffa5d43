//! Flags → typed settings, shared by the commands: the box, camera,
//! size, eps, parameters, budget (`--box`, `--eye`, … on [`SettingsArgs`]),
//! the traversal and sphere tracing's options ([`SphereArgs`]), the
//! algebra, the field source and the device's shader optimisation.

use super::CliError;
use clap::{Args, ValueEnum};
use glam::DVec3;
use crate::catalog::{self, Header};
use crate::gpu::{Gpu, ShaderOpt};
use crate::ir::Domain;
use crate::render::settings::DEFAULT_MAX_ITER;
use crate::render::{Bound, Method, Settings, Shading, SphereOptions, Unresolved, View};

/// The flags of a render's [`Settings`] (its box, camera, eps, time,
/// parameters, budget) and of its algebra, field and device: `render` of
/// a formula or a scene, and the viewer.
#[derive(Args, Debug, Clone, Default)]
pub struct SettingsArgs {
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
    pub field: Option<FieldArg>,
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

/// `--shader-opt`: see `crate::gpu::driver`.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderOptArg {
    Auto,
    Full,
    None,
}

/// The driver optimisation to ask for: the flag's, else (without a
/// GALLIVM_PERF of the user's) auto for a job of `pixel_frames`, or full
/// where the job measures frames (`auto_none` false: bench).
pub fn shader_opt(arg: Option<ShaderOptArg>, pixel_frames: u64, auto_none: bool) -> Option<ShaderOpt> {
    let auto = || if auto_none { crate::gpu::driver::auto_shader_opt(pixel_frames) } else { ShaderOpt::Full };
    match arg {
        Some(ShaderOptArg::Full) => Some(ShaderOpt::Full),
        Some(ShaderOptArg::None) => Some(ShaderOpt::None),
        Some(ShaderOptArg::Auto) => Some(auto()),
        None if std::env::var_os("GALLIVM_PERF").is_some() => None,
        None => Some(auto()),
    }
}

/// `--unresolved`: see `crate::render::Unresolved`.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Default)]
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
    pub fn given(&self) -> Vec<&'static str> {
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
        Some(m) => Method::parse(m).map_err(|e| CliError::input(format!("invalid --method '{m}': {e}"))),
        None => Ok(header.and_then(|h| h.method).unwrap_or(Method::Bisect)),
    }
}

/// The sphere tracing options from flags, with the header's `lipschitz`
/// and `bound` as defaults; checked before any GPU work.
pub fn sphere_options(a: &SphereArgs, header: Option<&Header>) -> Result<SphereOptions, CliError> {
    let d = SphereOptions::default();
    let bound = match (&a.bound, a.no_bound) {
        (_, true) => None,
        (Some(b), _) => Some(Bound::parse(b).map_err(|m| CliError::input(format!("invalid --bound '{b}': {m}")))?),
        (None, false) => header.and_then(|h| h.bound),
    };
    let eps_min = match &a.eps_min {
        Some(e) => Some(catalog::parse_eps(e).map_err(|m| CliError::input(format!("invalid --eps-min '{e}': {m}")))?),
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
    o.check().map_err(|e| CliError::input(super::error::settings_message(&e)))?;
    Ok(o)
}

/// Parses `WxH` or `N`.
pub fn parse_size(s: &str) -> Result<(u32, u32), CliError> {
    let bad = || CliError::input(format!("invalid --size '{s}': expected WxH like 1024x768, or N for a square"));
    let (w, h) = match s.split_once(['x', 'X']) {
        Some((a, b)) => (a.trim().parse::<u32>().map_err(|_| bad())?, b.trim().parse::<u32>().map_err(|_| bad())?),
        None => {
            let n = s.trim().parse::<u32>().map_err(|_| bad())?;
            (n, n)
        }
    };
    let max = crate::render::settings::MAX_SIZE;
    if w == 0 || h == 0 || w > max || h > max {
        return Err(CliError::input(format!("invalid --size '{s}': each side must be between 1 and {max}")));
    }
    Ok((w, h))
}

/// `--box`: 2 or 6 numbers.
pub fn parse_box(s: &str) -> Result<[f64; 6], CliError> {
    catalog::parse_box(s).map_err(|m| CliError::input(format!("invalid --box '{s}': {m}")))
}

fn parse_vec3(flag: &str, s: &str) -> Result<DVec3, CliError> {
    catalog::parse_vec3(s).map(DVec3::from_array).map_err(|m| CliError::input(format!("invalid {flag} '{s}': {m}")))
}

/// `--clip sphere:R`.
pub fn parse_clip(s: &str) -> Result<f64, CliError> {
    s.strip_prefix("sphere:")
        .and_then(|r| r.trim().parse::<f64>().ok())
        .filter(|r| *r > 0.0 && r.is_finite())
        .ok_or_else(|| CliError::input(format!("invalid --clip '{s}': expected sphere:R with a radius R > 0")))
}

/// `--param name=value` pairs. A value is a number as `--eps` takes it
/// (`0.5`, `2^-1`). A name given twice is an error: the two values would
/// silently disagree (a header's value is overridden, not repeated).
pub fn parse_params(list: &[String]) -> Result<Vec<(String, f64)>, CliError> {
    let mut out: Vec<(String, f64)> = Vec::with_capacity(list.len());
    for p in list {
        let (n, v) = p.split_once('=').ok_or_else(|| CliError::input(format!("invalid --param '{p}': expected name=value")))?;
        // Plain float syntax as before (a non-finite value is the settings'
        // error); otherwise the power syntax of --eps.
        let v = match v.trim().parse::<f64>() {
            Ok(x) => x,
            Err(_) => catalog::parse_number(v).map_err(|m| match m.starts_with("expected") {
                true => CliError::input(format!("invalid --param '{p}': '{v}' is not a number")),
                false => CliError::input(format!("invalid --param '{p}': {m}")),
            })?,
        };
        let n = n.trim().to_string();
        if let Some(j) = out.iter().position(|(m, _)| *m == n) {
            return Err(CliError::input(format!("--param {n} is given twice ('{}' and '{p}'): give each parameter once", list[j])));
        }
        out.push((n, v));
    }
    Ok(out)
}

/// The flags applied over `defaults` (a header's box, camera, eps, time
/// and parameters, or the built-in ones): the flags override them;
/// parameters given by flags come after the header's, so the last value
/// given wins.
pub fn flags_over_defaults(flags: &SettingsArgs, mut v: View) -> Result<View, CliError> {
    if let Some(b) = &flags.bbox {
        v.bbox = parse_box(b)?;
    }
    if let Some(e) = &flags.eps {
        v.eps = Some(catalog::parse_eps(e).map_err(|m| CliError::input(format!("invalid --eps '{e}': {m}")))?);
    }
    v.fov = flags.fov.or(v.fov);
    if let Some(t) = &flags.target {
        v.target = Some(parse_vec3("--target", t)?);
    }
    if let Some(e) = &flags.eye {
        v.eye = Some(parse_vec3("--eye", e)?);
    }
    if let Some(u) = &flags.up {
        v.up = Some(parse_vec3("--up", u)?);
    }
    if let Some(c) = &flags.clip {
        v.clip = Some(parse_clip(c)?);
    }
    v.time = flags.time.or(v.time);
    v.params.extend(parse_params(&flags.params)?);
    check_framing(flags, &v)?;
    Ok(v)
}

/// Refuses a box too large to frame, naming the box: without --eye the
/// eye is derived from it, and its own check would name --eye, which the
/// user never gave.
fn check_framing(flags: &SettingsArgs, v: &View) -> Result<(), CliError> {
    let fov = v.fov.unwrap_or(crate::render::view::DEFAULT_FOV);
    // A bad --fov is its own error (Camera::frame checks it first).
    if v.eye.is_some() || !(fov > 0.0 && fov < 180.0) {
        return Ok(());
    }
    let eye = crate::render::Camera::default_for(&v.bbox, fov, 1.0).eye;
    if eye.is_finite() && eye.abs().max_element() < 1e30 {
        return Ok(());
    }
    let what = match &flags.bbox {
        Some(b) => format!("invalid --box '{b}'"),
        None => "invalid box in the .iso header".to_string(),
    };
    let at = eye.to_array().map(crate::diag::show_number).join(",");
    Err(CliError::input(format!("{what}: too large to frame, the default eye would be at {at} (coordinates must be below 1e30); give a smaller box, or --eye")))
}

/// The budget, tile and unresolved-pixel flags on top of settings built
/// from the box, camera and parameters, checked before any GPU work.
pub fn apply_budget_flags(flags: &SettingsArgs, mut s: Settings) -> Result<Settings, CliError> {
    s.max_iter = flags.max_iter.unwrap_or(DEFAULT_MAX_ITER);
    s.tile = flags.tile;
    s.unresolved = match (flags.debug_unresolved, flags.unresolved) {
        (true, _) | (_, UnresolvedArg::Magenta) => Unresolved::Magenta,
        (_, UnresolvedArg::Hatch) => Unresolved::Hatch,
        (_, UnresolvedArg::Guess) => Unresolved::Guess,
    };
    s.check().map_err(|e| CliError::input(super::error::settings_message(&e)))?;
    Ok(s)
}

/// Builds a formula's frame settings from flags, with an `.iso` header's
/// values as defaults (flags override them); validated before any GPU work.
pub fn settings(flags: &SettingsArgs, size: (u32, u32), f: &crate::Formula, header: Option<&Header>) -> Result<Settings, CliError> {
    let v = flags_over_defaults(flags, header.map_or_else(View::default, Header::view))?;
    let (s, warnings) = v.settings(f, size.0, size.1).map_err(super::error::settings_error)?;
    for w in warnings {
        eprint!("{}", w.render("", "", false));
    }
    apply_budget_flags(flags, s)
}

/// Number domain of the generated evaluator.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlgebraArg {
    /// Plain f32 values (points).
    Scalar,
    /// Interval arithmetic.
    Ia,
    /// Reduced affine arithmetic (AF1).
    Raa,
    /// IA or RAA, chosen per formula.
    Auto,
}

/// The CLI value for a header's `algebra`.
pub fn algebra_arg(a: catalog::Algebra) -> AlgebraArg {
    match a {
        catalog::Algebra::Ia => AlgebraArg::Ia,
        catalog::Algebra::Raa => AlgebraArg::Raa,
        catalog::Algebra::Auto => AlgebraArg::Auto,
    }
}

/// The domain an `--algebra` value stands for with this formula.
pub fn resolve_algebra(a: AlgebraArg, ir: &crate::ir::Ir) -> Domain {
    match a {
        AlgebraArg::Scalar => Domain::Scalar,
        AlgebraArg::Ia => Domain::Interval,
        AlgebraArg::Raa => Domain::Affine,
        AlgebraArg::Auto => crate::choose_algebra(ir),
    }
}

/// The `--algebra` value that names a domain.
pub fn algebra_name(d: Domain) -> &'static str {
    match d {
        Domain::Scalar => "scalar",
        Domain::Interval => "ia",
        Domain::Affine => "raa",
    }
}

/// `--field`: the field source.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldArg {
    /// The formula generated into the shader.
    Compiled,
    /// The formula as a tape run by a fixed interpreter.
    Tape,
    /// A formula of distance forms lowered to its blobtree scene (sphere tracing, or bisection in IA).
    Scene,
    /// Chosen by formula size, algebra and method; a formula of 32 or more bounded distance forms as a scene.
    Auto,
}

/// The flag value of a field kind (a header's `field`).
pub(crate) fn field_arg(k: crate::field::FieldKind) -> FieldArg {
    match k {
        crate::field::FieldKind::Compiled => FieldArg::Compiled,
        crate::field::FieldKind::Tape => FieldArg::Tape,
        crate::field::FieldKind::Scene => FieldArg::Scene,
        crate::field::FieldKind::Auto => FieldArg::Auto,
    }
}

/// The field kind of a flag value.
pub(crate) fn field_kind(a: FieldArg) -> crate::field::FieldKind {
    match a {
        FieldArg::Compiled => crate::field::FieldKind::Compiled,
        FieldArg::Tape => crate::field::FieldKind::Tape,
        FieldArg::Scene => crate::field::FieldKind::Scene,
        FieldArg::Auto => crate::field::FieldKind::Auto,
    }
}

/// The field source of `--field` (default auto) for formula `f` with
/// parameter values `params`, traced by `t`. A scene needs the Lipschitz
/// bound of its operators: unless `--lipschitz` was given, sphere tracing
/// takes at least that.
/// `frames`: how many frames the job renders with the field (auto weighs
/// the tape's sooner first frame against its slower later ones).
pub fn prepare_field(arg: Option<FieldArg>, f: &crate::Formula, params: &[f32], t: &mut crate::render::Traversal, lipschitz_given: bool, frames: u64) -> Result<crate::choice::PreparedField, CliError> {
    use crate::choice::{self, FieldError, SceneFieldError};
    use crate::field::{FieldKind, TapeError};
    let kind = field_kind(arg.unwrap_or(FieldArg::Auto));
    if kind == FieldKind::Auto {
        if let Some((field, lipschitz)) = choice::auto_scene(f, params, t) {
            if let (crate::render::Traversal::Sphere(o), false) = (t, lipschitz_given) {
                o.lipschitz = o.lipschitz.max(lipschitz);
            }
            return Ok(field);
        }
    }
    if kind == FieldKind::Scene {
        // A scene bisects in IA (an explicit `--algebra raa` is refused
        // before: `render::traversal`).
        if let crate::render::Traversal::Bisect(b) = t {
            b.algebra = crate::ir::Domain::Interval;
        }
        let (field, lipschitz) = choice::scene(f, params, t).map_err(|e| match e {
            SceneFieldError::NotBlobtree(n) => {
                let d = crate::diag::Diagnostic::error(format!("--field scene: not a blobtree: {}", n.reason), n.span, "here")
                    .with_note("a scene is built from distance forms (sphere, box, translate, union, smooth_union, ...) with constant arguments; render it with --field compiled (or auto)");
                CliError::Rendered(d.render(&f.origin, &f.source, false))
            }
            SceneFieldError::NotInterval => CliError::Input(format!("--field scene: {e}; give --algebra ia")),
            SceneFieldError::Layout(_) => CliError::Input(format!("--field scene: in the scene the formula lowers to (`isotrace scene lower` writes it), {e}")),
        })?;
        if let (crate::render::Traversal::Sphere(o), false) = (t, lipschitz_given) {
            o.lipschitz = o.lipschitz.max(lipschitz);
        }
        return Ok(field);
    }
    choice::choose_for(kind, f, params, t, frames).map_err(|e| {
        let fix = match &e {
            FieldError::Tape(TapeError::UserFunction(_) | TapeError::Hooks) => "the functions and hooks of --inline need --field compiled (or auto)",
            _ => "render it with --field compiled (or auto)",
        };
        CliError::Input(format!("--field {}: {e}; {fix}", if kind == FieldKind::Tape { "tape" } else { "auto" }))
    })
}

/// Opens the device (asking a CPU driver for `opt`, `None`: as the
/// environment says), mapping "no adapter" to exit code 2.
pub fn open_gpu(opt: Option<ShaderOpt>) -> Result<Gpu, CliError> {
    opt.map_or_else(Gpu::new, Gpu::with_shader_opt).map_err(|e| match e {
        crate::gpu::GpuError::NoAdapter => CliError::NoDevice(e.to_string()),
        other => CliError::NoDevice(other.to_string()),
    })
}

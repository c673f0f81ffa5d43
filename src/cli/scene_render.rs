//! `isotrace render FILE.scene.json`: a blobtree scene through the scene
//! field source (its nodes in buffers, one fixed interpreter, per-tile
//! pruned trees), sphere traced or, with `--method bisect`, bisected on
//! the interval enclosures of its nodes.

use super::args::{self, apply_budget_flags, flags_over_defaults, open_gpu, sphere_options, AlgebraArg};
use super::error::settings_error;
use super::render::RenderArgs;
use super::report::{report, report_sphere, warn_lipschitz, warn_unresolved};
use super::CliError;
use crate::gpu::Renderer;
use crate::output::{self, ColorMode};
use crate::ir::Domain;
use crate::render::{BisectOptions, Method, Shading, Traversal, View};
use crate::scene::linear::Linear;
use std::path::Path;
use std::process::ExitCode;


/// Flags that have no meaning for a scene.
fn misplaced(a: &RenderArgs) -> Option<String> {
    let checks = [
        (a.frames.is_some(), "--frames applies to formulas: a scene has no time to animate".to_string()),
        (a.formula.inline.is_some(), "--inline applies to formulas rendered with --method bisect".into()),
        (a.settings.time.is_some(), "--t applies to formulas: a scene has no time".into()),
        (
            matches!(a.settings.field, Some(args::FieldArg::Compiled | args::FieldArg::Tape)),
            "--field compiled and --field tape apply to formulas: a scene file is traced by the scene field; to trace its formula, write it with `isotrace scene formula FILE.scene.json -o FILE.txt` and render `-f FILE.txt`".into(),
        ),
    ];
    checks.into_iter().find(|(bad, _)| *bad).map(|(_, m)| m)
}

/// The traversal the flags ask for: sphere tracing with the scene's
/// Lipschitz bound unless `--method bisect`, which encloses the scene's
/// nodes in interval arithmetic and needs no bound.
fn traversal(a: &RenderArgs, lin: &Linear, color: ColorMode, path: &Path) -> Result<Traversal, CliError> {
    // A scene is sphere traced unless a formula leaf has no Lipschitz bound.
    let untraceable = lin.untraceable_leaf();
    let method = a.sphere.method.as_deref().unwrap_or(if untraceable.is_some() { "bisect" } else { "sphere" });
    match args::method(Some(method), None)? {
        Method::Bisect => {
            let kernel_color = super::render::bisect_color(a, color)?;
            match a.settings.algebra {
                None | Some(AlgebraArg::Ia | AlgebraArg::Auto) => {}
                Some(AlgebraArg::Raa) => {
                    return Err(CliError::input(
                        "--algebra raa: a scene's nodes are enclosed in interval arithmetic, and formula leaves of degree 4 to 10 in RAA, node by node: give --algebra ia (every node on intervals) or leave it out",
                    ))
                }
                Some(AlgebraArg::Scalar) => return Err(CliError::input("--algebra scalar cannot render: the traversal needs an inclusion algebra (ia)")),
            }
            let m = super::modality::modalities(&a.modalities, a.sphere.shadows, kernel_color, None)?;
            Ok(Traversal::Bisect(BisectOptions { modalities: m, ..BisectOptions::new(Domain::Interval) }))
        }
        Method::Sphere => {
            if let Some(e) = untraceable {
                return Err(CliError::input(format!("{}: {e}", path.display())));
            }
            super::render::refuse_bisect_flags(a, color)?;
            let mut options = sphere_options(&a.sphere, None)?;
            if a.sphere.lipschitz.is_none() {
                options.lipschitz = lin.lipschitz();
            }
            if color == ColorMode::Field {
                options.shading = Shading::Field;
            }
            Ok(Traversal::Sphere(options))
        }
    }
}

/// The defaults a scene is framed with: its solid's box with a margin, so
/// silhouettes are not cut; `None` when a plane is not cut off. The box
/// is the ABVs' (what `bench --suite scenes` frames, so its series stay
/// comparable).
pub fn framing(lin: &Linear) -> Option<View> {
    lin.bounds.padded().map(|bbox| View { bbox, ..View::default() })
}

/// The framing `render` and the viewer start from: [`framing`] with the ABVs' box
/// shrunk by sampling the field (`roi::sampled_bounds`, a 32³ grid, scenes
/// up to about 2,000 nodes), so a scene whose bounding volumes are loose
/// (smooth blends, a bent bar) still fills the frame.
pub fn default_framing(lin: &Linear, scene: &crate::scene::Scene) -> Option<View> {
    let tight = crate::scene::roi::sampled_bounds(scene, &lin.bounds, lin.lipschitz(), 32, 64 << 20);
    tight.unwrap_or(lin.bounds).padded().map(|bbox| View { bbox, ..View::default() })
}

/// A scene render as the flags ask for it, before any device work (what
/// `render` runs and `view` shows).
pub struct ScenePlan {
    /// The scene laid out for the device.
    pub lin: Linear,
    /// The frame.
    pub settings: crate::render::Settings,
    /// The traversal and its options.
    pub traversal: Traversal,
    /// The colouring.
    pub color: ColorMode,
}

/// Checks the flags against the scene `scene` (read from `path`).
pub fn plan(a: &RenderArgs, scene: &crate::scene::Scene, path: &Path) -> Result<ScenePlan, CliError> {
    if let Some(m) = misplaced(a) {
        return Err(CliError::input(m));
    }
    let mut lin = Linear::new(scene).map_err(|e| CliError::input(format!("{}: {e}", path.display())))?;
    if a.settings.algebra == Some(AlgebraArg::Ia) {
        // Formula leaves on intervals too (their RAA run is compiled out).
        lin.features &= !crate::scene::linear::FEATURE_FORMULA_AFFINE;
    }
    crate::field::scene::leaves::check(&lin.leaves).map_err(|e| CliError::input(format!("{}: {e}", path.display())))?;
    let base = match default_framing(&lin, scene) {
        Some(v) => v,
        None if a.settings.bbox.is_some() => View::default(),
        None => return Err(CliError::input(format!("{}: the scene is unbounded (a plane is not cut off): give --box", path.display()))),
    };
    let size = args::parse_size(a.size.as_deref().unwrap_or("512"))?;
    let v = flags_over_defaults(&a.settings, base)?;
    let settings = apply_budget_flags(&a.settings, v.settings_without_params(size.0, size.1).map_err(settings_error)?)?;
    let color = output::parse_color(&a.color).map_err(|m| CliError::input(format!("invalid --color '{}': {m}", a.color)))?;
    let traversal = traversal(a, &lin, color, path)?;
    Ok(ScenePlan { lin, settings, traversal, color })
}

/// Renders the scene at `path`.
pub fn run(a: &RenderArgs, path: &Path) -> Result<ExitCode, CliError> {
    if let Some(m) = misplaced(a) {
        return Err(CliError::input(m));
    }
    let scene = super::scene::load(path, a.allow_scene_paths)?;
    let ScenePlan { lin, settings: s, traversal, color } = plan(a, &scene, path)?;
    let outputs = super::frames::Outputs::new(&a.output, None, None, false)?;
    outputs.check(a.force, false)?;
    let super::frames::Outputs::One(out) = &outputs else { unreachable!("no --frames") };
    let gpu = open_gpu(args::shader_opt(a.settings.shader_opt, u64::from(s.width) * u64::from(s.height), true))?;
    let data = lin.field_data();
    let renderer = Renderer::new(&gpu, &data, traversal.clone()).map_err(super::error::render_error)?;
    let mut frame = renderer.render(&s).map_err(super::error::render_error)?;
    let heat_max = output::recolor(&mut frame, color);
    output::write_frame(out, &frame).map_err(super::error::output_error)?;
    super::notice::wrote(out, &super::notice::size(frame.width, frame.height));
    match &traversal {
        Traversal::Bisect(b) => report(a, &frame, &s, b.algebra, &gpu, "scene"),
        Traversal::Sphere(o) => report_sphere(a, &frame, &s, o, &gpu, "scene"),
    }
    if a.stats {
        eprintln!("scene: {} nodes, {} primitives", lin.nodes.len(), lin.primitives.len());
        if let Some(m) = heat_max {
            eprintln!("--color {}: white = {m}", a.color);
        }
    }
    warn_unresolved(&frame, &renderer.traversal(), &s, renderer.field_name(), renderer.field_shares_loop_cap().is_some());
    if let Traversal::Sphere(o) = &traversal {
        warn_lipschitz(&frame, o);
    }
    if frame.stats.field.overflow_tiles > 0 {
        eprintln!(
            "note: {} tiles had more active primitives than a tile list holds ({}) and evaluated the whole tree",
            frame.stats.field.overflow_tiles,
            crate::field::scene::SCENE_TILE_MAX
        );
    }
    Ok(ExitCode::SUCCESS)
}

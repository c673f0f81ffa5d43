//! `isotrace scene`: write the paper's synthetic scenes (`gen`) and
//! validate a scene file with its figures (`check`).

use super::CliError;
use clap::{Args, Subcommand, ValueEnum};
use crate::bounded::ReadError;
use crate::diag::short_number;
use crate::scene::format::{self, FormatError, GridPaths};
use crate::scene::generate::{self, Blending, Kind, MAX_LEVEL};
use crate::scene::linear::{Linear, MAX_STACK};
use crate::scene::roi::Aabb;
use crate::scene::{roi, sparse, Scene};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args, Debug)]
pub struct SceneArgs {
    #[command(subcommand)]
    command: SceneCommand,
}

#[derive(Subcommand, Debug)]
enum SceneCommand {
    /// Write a synthetic scene of Zanni et al. 2024 (Fig. 16 aggregates, Fig. 18 instancing).
    #[command(after_help = "Primitive counts by level 0-4:\n  aggregate     10, 110, 1110, 11110, 111110  (Fig. 16)\n  boxes         16, 64, 256, 1024, 4096       (Fig. 18 a-f)\n  sphere-pairs  24, 96, 384, 1536, 6144       (Fig. 18 g-l)\n\nExamples:\n  isotrace scene gen aggregate --level 2 --smooth -o aggregate-2.scene.json\n  isotrace scene gen boxes --count 1024 -o boxes.scene.json\n  isotrace scene gen sphere-pairs --level 1 --smooth-inside --seed 7 -o pairs.scene.json")]
    Gen(GenArgs),
    /// Validate a scene file and print its counts, depth, stack depth and bounds.
    #[command(after_help = "Examples:\n  isotrace scene check examples/blobs.scene.json\n  isotrace scene check aggregate-2.scene.json --probe 1000\n  isotrace scene check boxes.scene.json --json")]
    Check(CheckArgs),
    /// Print the scene as a formula of distance forms (one definition per node), for the compiled path.
    #[command(after_help = "Only small scenes fit: a formula is at most 64 KiB (about 500 primitives).\n\nExamples:\n  isotrace scene formula examples/blobs.scene.json -o blobs.txt\n  isotrace render -f blobs.txt --method sphere --lipschitz 1.4 -o blobs.png")]
    Formula(FormulaArgs),
    /// Lower a formula built only from distance forms to the scene it describes (the inverse of `formula`).
    #[command(after_help = "Transforms are composed down to the primitives; smooth_union, smooth_intersect and smooth_subtract with blend k become the compact operators with beta = k and r_o = 2k (the same surface). Anything else (x, y, z outside a form, arithmetic on a shape, where conditions) is an error that points at it.\n\nExamples:\n  isotrace scene lower @creature -o creature.scene.json\n  isotrace scene lower 'translate(a, 0, 0, sphere(1))' --param a=0.5 -o moved.scene.json")]
    Lower(LowerArgs),
}

#[derive(Args, Debug)]
struct LowerArgs {
    #[command(flatten)]
    formula: super::input::FormulaArgs,
    /// A parameter's value, NAME=VALUE (repeatable; a header's `param:` values are the defaults).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Write the scene to FILE (.scene.json), or - for stdout.
    #[arg(short = 'o', long = "output", value_name = "FILE", allow_hyphen_values = true)]
    output: PathBuf,
}

#[derive(Args, Debug)]
struct FormulaArgs {
    /// The scene file.
    #[arg(value_name = "FILE.scene.json")]
    file: PathBuf,
    /// Write the formula to FILE instead of stdout.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: Option<PathBuf>,
    #[arg(long, help = ALLOW_SCENE_PATHS_HELP)]
    allow_scene_paths: bool,
}

/// The synthetic scene kinds.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum KindArg {
    /// Fig. 16: recursive aggregates of 10 primitives.
    Aggregate,
    /// Fig. 18: instanced groups of 16 rotated boxes.
    Boxes,
    /// Fig. 18: instanced groups of 12 lenses (intersected sphere pairs).
    SpherePairs,
}

#[derive(Args, Debug)]
#[command(group = clap::ArgGroup::new("size").required(true).args(["level", "count"]))]
struct GenArgs {
    /// Which scene.
    #[arg(value_enum)]
    kind: KindArg,
    /// Recursion or instancing level, 0 to 4.
    #[arg(long, value_name = "N")]
    level: Option<u32>,
    /// The primitive count instead of the level (one of the counts of that kind).
    #[arg(long, value_name = "N")]
    count: Option<usize>,
    /// Compact smooth unions everywhere (default: sharp min everywhere).
    #[arg(long, conflicts_with = "smooth_inside")]
    smooth: bool,
    /// Compact smooth unions inside each aggregate or instance, min between them.
    #[arg(long)]
    smooth_inside: bool,
    /// Seed of the random shapes and rotations.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write the scene to FILE (.scene.json), or - for stdout.
    #[arg(short = 'o', long = "output", value_name = "FILE", allow_hyphen_values = true)]
    output: PathBuf,
}

#[derive(Args, Debug)]
struct CheckArgs {
    /// The scene file.
    #[arg(value_name = "FILE.scene.json")]
    file: PathBuf,
    /// Also run the sparse traversal at N points inside primitives' ABVs and report node visits (fast vs parent ancestors).
    #[arg(long, value_name = "N")]
    probe: Option<usize>,
    /// Print the figures as one JSON object.
    #[arg(long)]
    json: bool,
    #[arg(long, help = ALLOW_SCENE_PATHS_HELP)]
    allow_scene_paths: bool,
}

/// Runs `isotrace scene …`.
pub fn run(a: SceneArgs) -> Result<ExitCode, CliError> {
    match a.command {
        SceneCommand::Gen(g) => generate_scene(g),
        SceneCommand::Check(c) => check(c),
        SceneCommand::Formula(f) => formula(f),
        SceneCommand::Lower(l) => lower(l),
    }
}

fn lower(a: LowerArgs) -> Result<ExitCode, CliError> {
    if a.formula.inline.is_some() {
        return Err(CliError::Input("--inline does not apply to scene lower: a scene has no user WGSL".into()));
    }
    let loaded = a.formula.load_with_header()?;
    let f = &loaded.formula;
    let mut given = loaded.header.as_ref().map_or(vec![], |h| h.params.clone());
    given.extend(super::args::parse_params(&a.params)?);
    let (values, warnings) = crate::sema::bind_params(&f.ir, &given).map_err(|d| CliError::Rendered(d.render(&f.origin, &f.source, false)))?;
    for w in warnings {
        eprint!("{}", w.render(&f.origin, &f.source, false));
    }
    let scene = crate::scene::from_formula(f, &values).map_err(|e| {
        let d = crate::diag::Diagnostic::error(format!("not a blobtree: {}", e.reason), e.span, "here");
        CliError::Rendered(d.render(&f.origin, &f.source, false))
    })?;
    let json = format::to_json(&scene);
    if write_scene(&a.output, &json)? {
        let sm = scene.summary();
        super::notice::wrote(&a.output, &format!("{} primitives, {} nodes", sm.primitives, sm.nodes));
    }
    Ok(ExitCode::SUCCESS)
}

fn formula(a: FormulaArgs) -> Result<ExitCode, CliError> {
    let scene = load(&a.file, a.allow_scene_paths)?;
    let text = scene.to_formula().map_err(|e| CliError::Input(format!("{}: {e}", a.file.display())))?;
    match a.output {
        Some(path) => crate::output::write_atomic(&path, text.as_bytes()).map_err(|e| CliError::Input(e.to_string()))?,
        None => {
            let _ = std::io::stdout().lock().write_all(text.as_bytes());
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn kind(k: KindArg) -> Kind {
    match k {
        KindArg::Aggregate => Kind::Aggregate,
        KindArg::Boxes => Kind::Boxes,
        KindArg::SpherePairs => Kind::SpherePairs,
    }
}

/// The level asked for by `--level` or `--count`.
fn level(a: &GenArgs, k: Kind) -> Result<u32, CliError> {
    let counts: Vec<String> = (0..=MAX_LEVEL).map(|l| k.primitives(l).to_string()).collect();
    match (a.level, a.count) {
        (Some(l), _) if l > MAX_LEVEL => Err(CliError::Input(format!(
            "invalid --level {l}: the highest level is {MAX_LEVEL} ({} {} primitives)",
            k.name(),
            k.primitives(MAX_LEVEL)
        ))),
        (Some(l), _) => Ok(l),
        (None, Some(c)) => k.level_for(c).ok_or_else(|| {
            let (last, rest) = counts.split_last().expect("five levels");
            CliError::Input(format!("invalid --count {c}: {} scenes have {} or {last} primitives", k.name(), rest.join(", ")))
        }),
        (None, None) => unreachable!("clap requires --level or --count"),
    }
}

fn generate_scene(a: GenArgs) -> Result<ExitCode, CliError> {
    let k = kind(a.kind);
    let level = level(&a, k)?;
    let blending = match (a.smooth, a.smooth_inside) {
        (true, _) => Blending::Smooth,
        (_, true) => Blending::SmoothInside,
        _ => Blending::Sharp,
    };
    let scene = generate::generate(k, level, blending, a.seed).map_err(|e| CliError::Internal(format!("generated an invalid scene: {e}")))?;
    let json = format::to_json(&scene);
    if !write_scene(&a.output, &json)? {
        return Ok(ExitCode::SUCCESS);
    }
    let name = match blending {
        Blending::Sharp => "sharp",
        Blending::SmoothInside => "smooth inside",
        Blending::Smooth => "smooth",
    };
    super::notice::wrote(&a.output, &format!("{} level {level}, {name}, {} primitives, {} nodes", k.name(), scene.primitive_count(), scene.len()));
    Ok(ExitCode::SUCCESS)
}

/// Loads a scene file, with messages that name the file. Its grid files
/// must be inside its directory unless `allow_paths` (`--allow-scene-paths`).
pub fn load(path: &Path, allow_paths: bool) -> Result<Scene, CliError> {
    let p = path.display();
    let paths = if allow_paths { GridPaths::Any } else { GridPaths::InsideSceneDir };
    format::load_with(path, &paths).map_err(|e| {
        CliError::Input(match e {
            FormatError::Read(ReadError::NotUtf8 { offset }) => format!("scene file '{p}' is not UTF-8 text (invalid byte at offset {offset})"),
            FormatError::Read(e) => format!("cannot read scene file '{p}': {e}"),
            FormatError::GridPath(e) => format!("{p}: {e}; {ALLOW_SCENE_PATHS}"),
            e => format!("{p}: {e}"),
        })
    })
}

/// How to read a grid file outside the scene's directory.
pub const ALLOW_SCENE_PATHS: &str = "give --allow-scene-paths to read it (only for files you trust)";

/// The help of `--allow-scene-paths`.
pub const ALLOW_SCENE_PATHS_HELP: &str =
    "Let a scene's grid files lie outside the scene file's directory (absolute, '..', or a symbolic link leading out); only for files you trust.";

/// Writes a scene to a `.scene.json` file, or to stdout for `-`; whether
/// it went to a file.
fn write_scene(output: &Path, json: &str) -> Result<bool, CliError> {
    let written = crate::output::check_extension(output, format::EXTENSION).and_then(|_| crate::output::write_atomic(output, json.as_bytes()));
    written.map_err(|e| CliError::Input(e.to_string()))?;
    Ok(!crate::output::is_stdout(output))
}

/// `[x0, x1] x [y0, y1] x [z0, z1]`.
fn bounds_text(b: &Aabb) -> String {
    if b.is_empty() {
        return "empty".into();
    }
    let side = |k: usize| format!("[{}, {}]", short3(b.min[k]), short3(b.max[k]));
    format!("{} x {} x {}", side(0), side(1), side(2))
}

fn short3(v: f64) -> String {
    if v.is_finite() { short_number((v * 1000.0).round() / 1000.0) } else if v > 0.0 { "inf".into() } else { "-inf".into() }
}

fn counts(m: &std::collections::BTreeMap<&str, usize>) -> String {
    m.iter().map(|(k, v)| format!("{k} {v}")).collect::<Vec<_>>().join(", ")
}

fn check(a: CheckArgs) -> Result<ExitCode, CliError> {
    let scene = load(&a.file, a.allow_scene_paths)?;
    let lin = Linear::new(&scene).map_err(|e| CliError::Input(format!("{}: {e}", a.file.display())))?;
    let sum = scene.summary();
    let always = lin.abvs.iter().filter(|v| matches!(v, roi::Abv::Always)).count();
    let lip = roi::path_lipschitz(&scene).into_iter().fold(1.0f64, f64::max);
    let probe = a.probe.map(|n| sparse::probe(&lin, &scene, &sparse::probe_points(&lin, n, 1)));
    let mut out = std::io::stdout().lock();
    if a.json {
        let b = &lin.bounds;
        let finite = |v: f64| if v.is_finite() { serde_json::json!(v) } else { serde_json::Value::Null };
        let mut v = serde_json::json!({
            "file": a.file.display().to_string(), "nodes": sum.nodes, "primitives": sum.primitives, "operators": sum.operators,
            "shapes": sum.shapes, "ops": sum.ops, "depth": sum.depth, "stack_depth": lin.stack_depth, "stack_limit": MAX_STACK,
            "bounds": { "min": b.min.map(finite), "max": b.max.map(finite) }, "always_active": always, "lipschitz_path_bound": lip,
            "lipschitz_field": roi::field_lipschitz(&scene), "lipschitz_traced": lin.lipschitz(), "features": feature_names(lin.features),
        });
        if let Some(p) = &probe {
            v["probe"] = serde_json::json!({
                "points": p.points, "empty": p.empty, "active_mean": p.active_mean, "active_max": p.active_max,
                "visits_fast": p.visits_fast, "visits_parent": p.visits_parent, "view_mean": p.view_mean,
                "max_stack_fast": p.max_stack_fast, "max_stack_parent": p.max_stack_parent,
            });
        }
        let _ = writeln!(out, "{v}");
        return Ok(ExitCode::SUCCESS);
    }
    let _ = writeln!(out, "scene:         {}", a.file.display());
    let _ = writeln!(out, "nodes:         {} ({} primitives, {} operators)", sum.nodes, sum.primitives, sum.operators);
    let _ = writeln!(out, "primitives:    {}", counts(&sum.shapes));
    if sum.operators > 0 {
        let _ = writeln!(out, "operators:     {}", counts(&sum.ops));
    }
    let _ = writeln!(out, "depth:         {} (nodes on the longest root-to-leaf path)", sum.depth);
    let _ = writeln!(out, "stack depth:   {} (limit {MAX_STACK})", lin.stack_depth);
    let _ = writeln!(out, "bounds:        {}", bounds_text(&lin.bounds));
    let _ = writeln!(out, "always active: {always} (planes)");
    let _ = writeln!(out, "lipschitz:     {} (largest product of 6 r_o/(6 r_o - beta) on a root-to-leaf path)", short3(lip));
    let disp = roi::field_lipschitz(&scene);
    if disp > 1.0 {
        let _ = writeln!(out, "field bound:   {} (displacements, voxel grids, warps and joins where the field is >= 0; traced with L = {})", short3(disp), short3(lin.lipschitz()));
    }
    if lin.features != 0 {
        let _ = writeln!(out, "interpreter:   {} (a kernel with this node code; scenes without it run the basic one)", feature_names(lin.features).join(", "));
    }
    if let Some(p) = probe {
        let _ = writeln!(
            out,
            "probe:         {} points ({} in no ABV): |A| mean {:.1}, max {}; node visits per traversal: fast {:.1}, parent {:.1}; view {:.1} nodes; traversal stack max {} (parent {})",
            p.points, p.empty, p.active_mean, p.active_max, p.visits_fast, p.visits_parent, p.view_mean, p.max_stack_fast, p.max_stack_parent
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The names of the interpreter features in `bits` (`scene::linear::FEATURE_*`).
fn feature_names(bits: u32) -> Vec<String> {
    use crate::scene::linear::*;
    // Primitives with a case of their own name their feature bit in the table.
    let own = crate::sdf::primitive::TYPES.iter().filter_map(|t| t.wgsl.as_ref().filter(|c| c.feature != FEATURE_DENSITY).map(|c| (c.feature, format!("{}s", t.scene_name))));
    [
        (FEATURE_PROFILE, "profiles"),
        (FEATURE_POLYGON, "polygons"),
        (FEATURE_UNARY, "unary nodes"),
        (FEATURE_INFILL, "infill"),
        (FEATURE_DISPLACE, "displacement"),
        (FEATURE_GRID, "voxel grids"),
        (FEATURE_JOIN, "chamfer, round and sum joins"),
        (FEATURE_WARP, "twists and bends"),
        (FEATURE_DENSITY, "density fields"),
        (FEATURE_SHAPES, "primitives other than spheres"),
        (FEATURE_FORMULA, "formula leaves (the tape interpreter)"),
        (FEATURE_FORMULA_POWERS, "integer powers from 8 on in formula leaves"),
        (FEATURE_FORMULA_AFFINE, "formula leaves in affine arithmetic"),
    ]
        .into_iter()
        .map(|(b, n)| (b, n.to_string()))
        .chain(own)
        .filter(|(b, _)| bits & b != 0)
        .map(|(_, n)| n)
        .collect()
}

//! `isotrace eval`: the generated evaluator on boxes (or points) read one per
//! line, run on the device (or with `--cpu` by the f64 reference).

use super::args::{parse_params, resolve_algebra, AlgebraArg};
use super::{input::FormulaArgs, CliError};
use clap::Args;
use crate::ir::Domain;
use crate::gpu::eval::{eval_boxes_with, Box8};
use crate::bounded;
use std::io::{BufRead, Write};
use std::process::ExitCode;

#[derive(Args, Debug)]
pub struct EvalArgs {
    #[command(flatten)]
    formula: FormulaArgs,
    /// Number domain: scalar (points), ia or raa.
    #[arg(long, value_enum, default_value = "ia")]
    algebra: AlgebraArg,
    /// Boxes, one per line: `x0 x1 y0 y1 z0 z1 [t0 t1]` (scalar: `x y z [t]`); `-` for stdin (default).
    #[arg(long, value_name = "FILE|-", default_value = "-")]
    boxes: String,
    /// Evaluate with the CPU f64 reference instead of the device.
    #[arg(long)]
    cpu: bool,
    /// A user parameter, `name=value` (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE", allow_hyphen_values = true)]
    params: Vec<String>,
    /// Time value for lines without a t column.
    #[arg(long = "t", value_name = "T", allow_hyphen_values = true, default_value_t = 0.0)]
    time: f64,
    /// Evaluator on the device, as `render --field`: compiled (generated code), tape (the fixed
    /// interpreter of the tape field source) or auto (the tape from render's crossover size on).
    #[arg(long, value_enum, value_name = "SOURCE")]
    field: Option<super::args::FieldArg>,
    /// Whether a CPU driver optimises the evaluator, as `render --shader-opt`; auto counts a box as a pixel (none up to 1,048,576 boxes, full past them).
    #[arg(long, value_enum, value_name = "OPT")]
    shader_opt: Option<super::args::ShaderOptArg>,
    #[arg(long, help = super::scene::ALLOW_SCENE_PATHS_HELP)]
    allow_scene_paths: bool,
}

/// Most boxes one run reads: 16 Mi boxes are 512 MiB in kernel layout, and
/// all of them are held until they are evaluated and printed.
pub const MAX_BOXES: usize = 1 << 24;
/// Longest line of box input: eight numbers in full precision take < 200 bytes.
const MAX_LINE_BYTES: u64 = 4096;

/// Reads the boxes of `--boxes` (a file, or `-` for stdin) line by line, so
/// an endless input ends at [`MAX_BOXES`] or at a line over
/// [`MAX_LINE_BYTES`] instead of filling the memory.
fn read_boxes(src: &str, scalar: bool, time: f64) -> Result<Vec<Box8>, CliError> {
    if src == "-" {
        return read_boxes_from("<stdin>", "cannot read boxes from stdin", std::io::stdin().lock(), scalar, time);
    }
    let what = format!("cannot read boxes file '{src}'");
    let file = bounded::open_regular(std::path::Path::new(src)).map_err(|e| CliError::Input(format!("{what}: {e}")))?;
    read_boxes_from(src, &what, std::io::BufReader::new(file), scalar, time)
}

fn read_boxes_from(name: &str, what: &str, mut r: impl BufRead, scalar: bool, time: f64) -> Result<Vec<Box8>, CliError> {
    let mut out = Vec::new();
    let mut line = Vec::new();
    for n in 1.. {
        match bounded::read_line(&mut r, &mut line, MAX_LINE_BYTES) {
            Ok(true) => {}
            Ok(false) => break,
            Err(bounded::ReadError::TooLarge { limit }) => {
                return Err(CliError::Input(format!("{name}:{n}: line longer than the limit of {}", bounded::bytes(limit))));
            }
            Err(e) => return Err(CliError::Input(format!("{what}: {e}"))),
        }
        let text = std::str::from_utf8(&line).map_err(|e| CliError::Input(format!("{name}:{n}: not UTF-8 text (invalid byte at offset {})", e.valid_up_to())))?;
        if let Some(b) = parse_box(name, n, text, scalar, time)? {
            if out.len() == MAX_BOXES {
                return Err(CliError::Input(format!("{name}:{n}: more than {MAX_BOXES} boxes, the limit of one eval run; split the input")));
            }
            out.push(b);
        }
    }
    Ok(out)
}

/// Parses one line of box input in kernel layout; `None` for a blank line
/// or a `#` comment.
fn parse_box(name: &str, n: usize, line: &str, scalar: bool, time: f64) -> Result<Option<Box8>, CliError> {
    let l = line.split('#').next().unwrap_or("").trim();
    if l.is_empty() {
        return Ok(None);
    }
    let vals: Result<Vec<f64>, _> = l.split_whitespace().map(|w| w.parse::<f64>()).collect();
    let want = if scalar { "3 or 4 numbers: x y z [t]" } else { "6 or 8 numbers: x0 x1 y0 y1 z0 z1 [t0 t1]" };
    let err = |m: &str| CliError::Input(format!("{name}:{n}: {m} in '{l}'"));
    let v = vals.map_err(|_| err(&format!("expected {want}; found a word that is not a number")))?;
    let b: Box8 = match (scalar, v.len()) {
        (true, 3) => [v[0], v[0], v[1], v[1], v[2], v[2], time, time].map(|x| x as f32),
        (true, 4) => [v[0], v[0], v[1], v[1], v[2], v[2], v[3], v[3]].map(|x| x as f32),
        (false, 6) => [v[0], v[1], v[2], v[3], v[4], v[5], time, time].map(|x| x as f32),
        (false, 8) => [v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]].map(|x| x as f32),
        (_, k) => return Err(err(&format!("expected {want}, found {k}"))),
    };
    if !scalar && (0..4).any(|a| !(b[2 * a] <= b[2 * a + 1])) {
        return Err(err("each range needs lo <= hi"));
    }
    Ok(Some(b))
}

pub fn run(a: EvalArgs) -> Result<ExitCode, CliError> {
    if let Some(path) = a.formula.scene_path() {
        return run_scene(&a, &path);
    }
    let loaded = a.formula.load_with_header()?;
    let f = &loaded.formula;
    let domain = match a.algebra {
        AlgebraArg::Auto => resolve_algebra(AlgebraArg::Auto, &f.ir),
        other => resolve_algebra(other, &f.ir),
    };
    let given = parse_params(&a.params)?;
    let (params, warnings) = crate::sema::bind_params(&f.ir, &given)
        .map_err(|d| CliError::Formula(crate::FormulaError { origin: f.origin.clone(), text: f.source.clone(), diagnostic: d }))?;
    for w in warnings {
        eprint!("{}", w.render("", "", false));
    }
    // The flags are checked before any input is read.
    if a.cpu && a.field.is_some() {
        return Err(CliError::Input("--field chooses the device's evaluator; --cpu evaluates the f64 reference".into()));
    }
    refuse_cpu_shader_opt(&a)?;
    if a.cpu && loaded.inline.is_some() {
        return Err(CliError::Input("--cpu cannot evaluate --inline WGSL functions (they run on the device only)".into()));
    }
    let tape = if a.cpu { None } else { device_tape(a.field, f, domain, &params)? };
    let boxes = read_boxes(&a.boxes, domain == Domain::Scalar, a.time)?;
    let results: Vec<[f64; 2]> = if a.cpu {
        let p64: Vec<f64> = params.iter().map(|&v| v as f64).collect();
        boxes.iter().map(|b| cpu_eval(&f.ir, domain, b, &p64)).collect()
    } else {
        let gpu = super::args::open_gpu(super::args::shader_opt(a.shader_opt, boxes.len() as u64, true))?;
        let run = match &tape {
            Some(t) => crate::gpu::eval::eval_boxes_tape(&gpu, t, domain, &boxes, &params),
            None => eval_boxes_with(&gpu, &f.ir, domain, &boxes, &params, loaded.inline.as_ref()),
        };
        run.map_err(|e| match e {
                crate::gpu::eval::EvalError::Inline(m) => CliError::Rendered(m),
                other => CliError::Internal(other.to_string()),
            })?
            .into_iter()
            .map(|[lo, hi]| [lo as f64, hi as f64])
            .collect()
    };
    let mut out = std::io::stdout().lock();
    for r in results {
        let _ = match (domain, r[0] > r[1]) {
            (Domain::Scalar, _) => writeln!(out, "{}", r[0]),
            (_, true) => writeln!(out, "empty"),
            _ => writeln!(out, "{} {}", r[0], r[1]),
        };
    }
    Ok(ExitCode::SUCCESS)
}

/// `--shader-opt` is the device's: with `--cpu` it is an error, not ignored.
fn refuse_cpu_shader_opt(a: &EvalArgs) -> Result<(), CliError> {
    if a.cpu && a.shader_opt.is_some() {
        return Err(CliError::Input("--shader-opt applies to the device's evaluator; --cpu evaluates the f64 reference".into()));
    }
    Ok(())
}

/// `eval FILE.scene.json --algebra scalar`: the scene's field at points, by
/// the device's interpreter over the whole tree (or `--cpu`, the f64
/// reference). A scene has no interval or affine extension, parameters,
/// time or user WGSL; those flags are refused, before any input is read.
fn run_scene(a: &EvalArgs, path: &std::path::Path) -> Result<ExitCode, CliError> {
    let refuse = |m: &str| Err(CliError::Input(format!("{m} (for {})", path.display())));
    if !matches!(a.algebra, AlgebraArg::Scalar) {
        return refuse("a scene has no interval or affine extension: evaluate it at points with --algebra scalar");
    }
    if a.field.is_some() {
        return refuse("--field chooses a formula's evaluator: a scene is evaluated by its interpreter");
    }
    if a.formula.inline.is_some() || !a.params.is_empty() {
        return refuse("--inline and --param apply to formulas");
    }
    refuse_cpu_shader_opt(a)?;
    let scene = super::scene::load(path, a.allow_scene_paths)?;
    let boxes = read_boxes(&a.boxes, true, a.time)?;
    let values: Vec<f64> = if a.cpu {
        boxes.iter().map(|b| scene.eval([b[0] as f64, b[2] as f64, b[4] as f64])).collect()
    } else {
        let lin = crate::scene::linear::Linear::new(&scene).map_err(|e| CliError::Input(format!("{}: {e}", path.display())))?;
        let points: Vec<[f32; 3]> = boxes.iter().map(|b| [b[0], b[2], b[4]]).collect();
        let gpu = super::args::open_gpu(super::args::shader_opt(a.shader_opt, points.len() as u64, true))?;
        let got = crate::gpu::eval::eval_points_scene(&gpu, &lin.field_data(), &points).map_err(|e| CliError::Internal(e.to_string()))?;
        got.into_iter().map(f64::from).collect()
    };
    let mut out = std::io::stdout().lock();
    for v in values {
        let _ = writeln!(out, "{v}");
    }
    Ok(ExitCode::SUCCESS)
}

/// The tape `--field` asks for (`None`: the generated evaluator). `auto`
/// takes the tape where `render` would for the same algebra; a scene has no
/// enclosures to evaluate on boxes.
fn device_tape(arg: Option<super::args::FieldArg>, f: &crate::Formula, domain: Domain, params: &[f32]) -> Result<Option<crate::field::TapeData>, CliError> {
    use crate::choice::{choose, FieldKind, PreparedField};
    use crate::render::{BisectOptions, SphereOptions, Traversal};
    let kind = match arg {
        None | Some(super::args::FieldArg::Compiled) => return Ok(None),
        Some(super::args::FieldArg::Scene) => return Err(CliError::Input("--field scene applies to render: a scene's enclosures are evaluated inside its render kernel, on its tiles' pruned trees".into())),
        Some(super::args::FieldArg::Tape) => FieldKind::Tape,
        Some(super::args::FieldArg::Auto) => FieldKind::Auto,
    };
    let t = match domain {
        Domain::Scalar => Traversal::Sphere(SphereOptions::default()),
        d => Traversal::Bisect(BisectOptions::new(d)),
    };
    match choose(kind, f, params, &t) {
        Ok(PreparedField::Tape(tape)) => Ok(Some(tape)),
        Ok(_) => Ok(None),
        Err(e) => Err(CliError::Input(format!("--field {}: {e}; evaluate it with --field compiled (or auto)", if kind == FieldKind::Tape { "tape" } else { "auto" }))),
    }
}

fn cpu_eval(ir: &crate::ir::Ir, domain: Domain, b: &Box8, params: &[f64]) -> [f64; 2] {
    use crate::reference as r;
    let iv = |k: usize| [b[2 * k] as f64, b[2 * k + 1] as f64];
    match domain {
        Domain::Scalar => {
            let v = r::eval_scalar(ir, [b[0] as f64, b[2] as f64, b[4] as f64, b[6] as f64], params);
            [v, v]
        }
        Domain::Interval => r::eval_interval(ir, [iv(0), iv(1), iv(2), iv(3)], params),
        Domain::Affine => {
            let forms = [0, 1, 2, 3].map(|k| r::affine_from_interval(iv(k)));
            r::affine_range(r::eval_affine(ir, forms, params))
        }
    }
}

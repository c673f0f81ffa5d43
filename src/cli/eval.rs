//! `isotrace eval`: the generated evaluator on boxes (or points) read one per
//! line, run on the device (or with `--cpu` by the f64 reference).

use super::{input::FormulaArgs, render::parse_params, resolve_algebra, AlgebraArg, CliError};
use clap::Args;
use isotrace::codegen::Domain;
use isotrace::gpu::eval::{eval_boxes_with, Box8};
use std::io::{BufRead, Write};
use std::path::PathBuf;
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
}

fn read_lines(src: &str) -> Result<(String, Vec<String>), CliError> {
    let (name, text) = if src == "-" {
        let mut s = String::new();
        for l in std::io::stdin().lock().lines() {
            let l = l.map_err(|e| CliError::Input(format!("cannot read boxes from stdin: {e}")))?;
            s.push_str(&l);
            s.push('\n');
        }
        ("<stdin>".to_string(), s)
    } else {
        let p = PathBuf::from(src);
        let s = std::fs::read_to_string(&p).map_err(|e| CliError::Input(format!("cannot read boxes file '{src}': {e}")))?;
        (src.to_string(), s)
    };
    Ok((name, text.lines().map(String::from).collect()))
}

/// Parses the box lines (blank lines and `#` comments skipped); returns the
/// boxes in kernel layout.
pub fn parse_boxes(name: &str, lines: &[String], scalar: bool, time: f64) -> Result<Vec<Box8>, CliError> {
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let l = line.split('#').next().unwrap_or("").trim();
        if l.is_empty() {
            continue;
        }
        let vals: Result<Vec<f64>, _> = l.split_whitespace().map(|w| w.parse::<f64>()).collect();
        let want = if scalar { "3 or 4 numbers: x y z [t]" } else { "6 or 8 numbers: x0 x1 y0 y1 z0 z1 [t0 t1]" };
        let err = |m: &str| CliError::Input(format!("{name}:{}: {m} in '{l}'", i + 1));
        let v = vals.map_err(|_| err(&format!("expected {want}; found a word that is not a number")))?;
        let b: Box8 = match (scalar, v.len()) {
            (true, 3) => [v[0], v[0], v[1], v[1], v[2], v[2], time, time].map(|x| x as f32),
            (true, 4) => [v[0], v[0], v[1], v[1], v[2], v[2], v[3], v[3]].map(|x| x as f32),
            (false, 6) => [v[0], v[1], v[2], v[3], v[4], v[5], time, time].map(|x| x as f32),
            (false, 8) => [v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]].map(|x| x as f32),
            (_, n) => return Err(err(&format!("expected {want}, found {n}"))),
        };
        if !scalar && (0..4).any(|a| !(b[2 * a] <= b[2 * a + 1])) {
            return Err(err("each range needs lo <= hi"));
        }
        out.push(b);
    }
    Ok(out)
}

pub fn run(a: EvalArgs) -> Result<ExitCode, CliError> {
    let loaded = a.formula.load_with_header()?;
    let f = &loaded.formula;
    let domain = match a.algebra {
        AlgebraArg::Auto => resolve_algebra(AlgebraArg::Auto, &f.ir),
        other => resolve_algebra(other, &f.ir),
    };
    let given = parse_params(&a.params)?;
    let (params, warnings) = isotrace::sema::bind_params(&f.ir, &given)
        .map_err(|d| CliError::Formula(isotrace::FormulaError { origin: f.origin.clone(), text: f.source.clone(), diagnostic: d }))?;
    for w in warnings {
        eprint!("{}", w.render("", "", false));
    }
    let (name, lines) = read_lines(&a.boxes)?;
    let boxes = parse_boxes(&name, &lines, domain == Domain::Scalar, a.time)?;
    if a.cpu && loaded.inline.is_some() {
        return Err(CliError::Input("--cpu cannot evaluate --inline WGSL functions (they run on the device only)".into()));
    }
    let results: Vec<[f64; 2]> = if a.cpu {
        let p64: Vec<f64> = params.iter().map(|&v| v as f64).collect();
        boxes.iter().map(|b| cpu_eval(&f.ir, domain, b, &p64)).collect()
    } else {
        let gpu = super::render::open_gpu()?;
        eval_boxes_with(&gpu, &f.ir, domain, &boxes, &params, loaded.inline.as_ref())
            .map_err(|e| match e {
                isotrace::gpu::eval::EvalError::Inline(m) => CliError::Rendered(m),
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

fn cpu_eval(ir: &isotrace::ir::Ir, domain: Domain, b: &Box8, params: &[f64]) -> [f64; 2] {
    use isotrace::reference as r;
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

//! `isotrace wgsl`: the generated shaders, printed or written, and the
//! checks of user WGSL (`--inline`) that `render` shares.

use super::args::{resolve_algebra, AlgebraArg};
use super::{input, notice, CliError, FormulaArgs};
use clap::{Args, ValueEnum};
use crate::ir::Domain;
use crate::{validate, Formula};
use std::io::Write;
use std::process::ExitCode;

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum KernelArg {
    /// The render kernel (stackless interval bisection).
    Render,
    /// The `eval` kernel (one invocation per box).
    Eval,
    /// The sphere tracing kernel (`render --method sphere`).
    Sphere,
}

/// The field sources `isotrace wgsl` can print.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum WgslField {
    /// The formula generated into WGSL.
    Compiled,
    /// The tape interpreter's kernel for this formula's tape.
    Tape,
}

#[derive(Args, Debug)]
pub(super) struct WgslArgs {
    #[command(flatten)]
    formula: FormulaArgs,
    /// Number domain of the inclusion function.
    #[arg(long, value_enum, default_value = "auto")]
    algebra: AlgebraArg,
    /// Which kernel to generate.
    #[arg(long, value_enum, default_value = "render")]
    kernel: KernelArg,
    /// Field source: the formula generated into the shader, or the tape
    /// interpreter's kernel (which does not depend on the formula, only on
    /// its operation groups and register file; the per-invocation work
    /// count: on a device with subgroups `render` uses the per-bundle one).
    #[arg(long, value_enum, default_value = "compiled")]
    field: WgslField,
    /// Write the shader to FILE (.wgsl) instead of stdout.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: Option<std::path::PathBuf>,
}

pub(super) fn run(a: WgslArgs) -> Result<ExitCode, CliError> {
    if let Some(o) = &a.output {
        let target = crate::output::check_extension(o, ".wgsl").and_then(|_| crate::output::check_target(o));
        target.map_err(|e| CliError::Input(e.to_string()))?;
    }
    let loaded = a.formula.load_with_header()?;
    let f = &loaded.formula;
    let inline = loaded.inline.as_ref();
    let domain = resolve_algebra(a.algebra, &f.ir);
    if a.field == WgslField::Tape {
        let src = tape_wgsl(f, domain, a.kernel, inline.is_some())?;
        validate_generated(&src, f)?;
        return write_wgsl(src, a.output);
    }
    let src = match a.kernel {
        KernelArg::Eval => crate::field::compiled::eval_shader_with(&f.ir, domain, inline),
        KernelArg::Sphere if inline.is_some() => return Err(CliError::Input("--inline applies to the render and eval kernels, not to --kernel sphere".into())),
        KernelArg::Sphere => crate::kernel::sphere_shader(&f.ir, Default::default()),
        KernelArg::Render => {
            if domain == Domain::Scalar {
                return Err(CliError::Input("--algebra scalar has no render kernel: the traversal needs an inclusion algebra (ia, raa or auto); use --kernel eval".into()));
            }
            let m = crate::render::Modalities { inline: inline.cloned(), ..Default::default() };
            let b = crate::render::BisectOptions { modalities: m, ..crate::render::BisectOptions::new(domain) };
            crate::kernel::assemble(&f.ir, &crate::render::Traversal::Bisect(b)).wgsl
        }
    };
    match inline {
        Some(user) => validate_inline(&src, user, f)?,
        None => validate_generated(&src, f)?,
    }
    write_wgsl(src, a.output)
}

/// The tape field's kernel of `kernel` for the tape of `f`.
fn tape_wgsl(f: &crate::Formula, domain: Domain, kernel: KernelArg, inline: bool) -> Result<String, CliError> {
    if inline {
        return Err(CliError::Input("--field tape: the functions and hooks of --inline need --field compiled".into()));
    }
    let tape = crate::field::TapeData::new(&f.ir).map_err(|e| CliError::Input(format!("--field tape: {e}; print it with --field compiled")))?;
    let traversal = match kernel {
        KernelArg::Eval => return Ok(crate::field::tape::wgsl::eval_shader(domain, tape.features)),
        KernelArg::Sphere => crate::render::Traversal::Sphere(Default::default()),
        KernelArg::Render if domain == Domain::Scalar => {
            return Err(CliError::Input("--algebra scalar has no render kernel: the traversal needs an inclusion algebra (ia, raa or auto); use --kernel eval".into()));
        }
        KernelArg::Render => crate::render::Traversal::Bisect(crate::render::BisectOptions::new(domain)),
    };
    Ok(crate::kernel::assemble(&tape, &traversal).wgsl)
}

/// Validates a generated shader without user WGSL: an invalid one is an
/// isotrace bug.
fn validate_generated(src: &str, f: &crate::Formula) -> Result<(), CliError> {
    validate::validate(src).map(|_| ()).map_err(|e| CliError::Internal(format!("{e}\nformula ({}): {}", f.origin, f.source.trim())))
}

/// Writes a validated shader to `output` or stdout.
fn write_wgsl(src: String, output: Option<std::path::PathBuf>) -> Result<ExitCode, CliError> {
    match output {
        Some(path) => {
            input::write_atomic(&path, src.as_bytes()).map_err(CliError::Input)?;
            notice::wrote(&path, &format!("{} lines of WGSL", src.lines().count()));
        }
        None => {
            let _ = std::io::stdout().lock().write_all(src.as_bytes());
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Validates a shader that holds the user's `--inline` WGSL: an error in the
/// user's part is a user error (exit 1), anything else a bug.
pub(super) fn validate_inline(src: &str, user: &crate::inline::InlineWgsl, f: &Formula) -> Result<(), CliError> {
    let start = src.find(&user.text).unwrap_or(0);
    validate::validate_with_inline(src, start..start + user.text.len(), &user.path, &user.text).map(|_| ()).map_err(|e| match e {
        validate::InlineError::User(m) => CliError::Rendered(m),
        validate::InlineError::Bug(b) => CliError::Internal(format!("{b}\nformula ({}): {}", f.origin, f.source.trim())),
    })
}

/// `check --inline`: the user's WGSL spliced into the render kernel (with
/// its hooks) and the eval kernel of the formula, both validated by naga, so
/// `check` reports what `render` and `eval` would.
pub(super) fn check_inline(f: &Formula, user: &crate::inline::InlineWgsl) -> Result<(), CliError> {
    let domain = crate::choose_algebra(&f.ir);
    let m = crate::render::Modalities { inline: Some(user.clone()), ..Default::default() };
    let b = crate::render::BisectOptions { modalities: m, ..crate::render::BisectOptions::new(domain) };
    let render = crate::kernel::assemble(&f.ir, &crate::render::Traversal::Bisect(b)).wgsl;
    validate_inline(&render, user, f)?;
    validate_inline(&crate::field::compiled::eval_shader_with(&f.ir, domain, Some(user)), user, f)
}

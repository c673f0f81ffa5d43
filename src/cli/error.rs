//! [`CliError`], the one error type of the commands, and the mapping of
//! the library's errors onto it in the words of the command line (the
//! flag that sets a value, what the user can do).

use crate::{validate, FormulaError};
use std::io::IsTerminal;

/// Any failure of a command, rendered once.
#[derive(Debug)]
pub enum CliError {
    /// A formula diagnostic.
    Formula(FormulaError),
    /// Bad input that is not in a formula (a flag, a file).
    Input(String),
    /// An isotrace bug (naga rejected generated code, …).
    Internal(String),
    /// No usable GPU device (exit code 2).
    NoDevice(String),
    /// Bad input with a diagnostic already rendered (exit code 1).
    Rendered(String),
}

impl CliError {
    /// Bad input that is not in a formula: a flag, a file, a header value.
    pub fn input(message: impl Into<String>) -> Self {
        CliError::Input(message.into())
    }

    /// The text for stderr. Messages quote user text (file names, header
    /// values, box lines), so control characters in them are made visible
    /// ([`crate::diag::escape_controls`]): no input reaches the terminal raw.
    pub fn render(&self) -> String {
        self.text(std::io::stderr().is_terminal())
    }

    /// The message, with terminal colours or without (for the viewer's page).
    pub fn text(&self, color: bool) -> String {
        use crate::diag::escape_controls as esc;
        match self {
            CliError::Formula(e) => e.diagnostic.render(&e.origin, &e.text, color),
            CliError::Input(m) if color => format!("\x1b[1;31merror\x1b[0m: {}\n", esc(m)),
            CliError::Input(m) => format!("error: {}\n", esc(m)),
            CliError::Internal(m) => format!("{}\n", esc(m)),
            CliError::NoDevice(m) => format!("error: {}\n", esc(m)),
            CliError::Rendered(m) => esc(m).into_owned(),
        }
    }

    /// The process's exit code: 1 bad input, 2 no device, 3 an isotrace bug.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Formula(_) | CliError::Input(_) | CliError::Rendered(_) => 1,
            CliError::Internal(_) => 3,
            CliError::NoDevice(_) => 2,
        }
    }
}

impl From<FormulaError> for CliError {
    fn from(e: FormulaError) -> Self {
        CliError::Formula(e)
    }
}
impl From<validate::ValidateError> for CliError {
    fn from(e: validate::ValidateError) -> Self {
        CliError::Internal(e.to_string())
    }
}

/// Why flags and header values cannot become settings: a value out of
/// range names its flag, a parameter is a formula diagnostic.
pub fn settings_error(e: crate::render::ViewError) -> CliError {
    match e {
        crate::render::ViewError::Settings(e) => CliError::input(settings_message(&e)),
        crate::render::ViewError::Param(e) => CliError::Formula(e),
    }
}

/// Maps a render error to the CLI's error kinds.
pub fn render_error(e: crate::gpu::RenderError) -> CliError {
    use crate::gpu::RenderError as R;
    match e {
        R::Validate(v) => CliError::Internal(v.to_string()),
        R::Gpu(g) => CliError::Internal(g.to_string()),
        R::Settings(s) => CliError::Input(settings_message(&s)),
        R::Inline(m) => CliError::Rendered(m),
        R::Memory(m) => CliError::Input(memory_message(&m.to_string(), &m)),
        e @ R::ShaderTooLarge { .. } => CliError::Input(format!(
            "{e}; render it with --field tape (or auto), which runs the formula from a buffer in a fixed interpreter, simplify the formula (a repeated subexpression written once as a definition 'name = ...;' is generated once), or split the surface into several renders"
        )),
    }
}

/// An output file's error; a refused allocation says what to do.
pub fn output_error(e: crate::output::OutputError) -> CliError {
    match &e {
        crate::output::OutputError::Memory { source, .. } => CliError::Input(memory_message(&e.to_string(), source)),
        _ => CliError::Input(e.to_string()),
    }
}

/// `message` about a refused frame allocation, with what the user can do.
fn memory_message(message: &str, m: &crate::memory::MemoryError) -> String {
    match m.budget {
        Some(_) => format!("{message}; render a smaller --size, or raise ISOTRACE_MEMORY_BUDGET"),
        None => format!("{message}; render a smaller --size"),
    }
}

/// The flag a setting is given with on the command line.
fn settings_flag(field: crate::render::SettingsField) -> &'static str {
    use crate::render::SettingsField as F;
    match field {
        F::Size => "--size",
        F::Box => "--box",
        F::Eye => "--eye",
        F::Target => "--target",
        F::Up => "--up",
        F::Fov => "--fov",
        F::Eps => "--eps",
        F::Time => "--t",
        F::Params => "--param",
        F::Clip => "--clip",
        F::MaxIter => "--max-iter",
        F::Isovalues => "--iso",
        F::Layers => "--layers",
        F::Opacity => "--opacity",
        F::Reflect => "--reflect",
        F::Reflectivity => "--reflectivity",
        F::Lipschitz => "--lipschitz",
        F::Omega => "--omega",
        F::MaxSteps => "--max-steps",
        F::Fixpoint => "--fixpoint",
        F::MinStep => "--min-step",
        F::EpsMin => "--eps-min",
        F::Features => "--method",
    }
}

/// A settings error in the words of the command line: the flag that sets
/// the value (flags and `.iso` header keys share their names).
pub fn settings_message(e: &crate::render::SettingsError) -> String {
    use crate::render::SettingsField as F;
    match (e.field, e.value.is_empty()) {
        (F::Up, true) => format!("{}: give another --up", e.reason),
        (F::Eye, true) => format!("{}: give another --eye or --target", e.reason),
        (_, true) => format!("invalid {}: {}", settings_flag(e.field), e.reason),
        (_, false) => format!("invalid {} {}: {}", settings_flag(e.field), e.value, e.reason),
    }
}

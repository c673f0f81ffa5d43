//! Where a formula comes from: the argument itself, `-f FILE`, a path ending
//! in `.iso` (with its header), `@name` from the catalog, or `-` for stdin;
//! and atomic file output.

use super::CliError;
use clap::Args;
use crate::catalog::{self, Header};
use crate::Formula;
use crate::bounded;
use crate::inline::MAX_INLINE_BYTES;
use std::path::Path;

/// Largest formula read from stdin or `-f FILE`: the front end's own limit,
/// so reading stops one byte past what it would reject anyway.
const MAX_FORMULA_BYTES: u64 = crate::syntax::parser::MAX_SOURCE_BYTES as u64;

/// The formula arguments shared by every command.
#[derive(Args, Debug, Clone)]
pub struct FormulaArgs {
    /// The formula (e.g. 'x^2 + y^2 + z^2 - 1'), @name of a catalog surface (see `isotrace list`), a path ending in .iso, or - for stdin.
    #[arg(value_name = "FORMULA", required_unless_present = "file", allow_hyphen_values = true)]
    pub formula: Option<String>,
    /// Read the formula from FILE.
    #[arg(short = 'f', long = "file", value_name = "FILE", conflicts_with = "formula")]
    pub file: Option<std::path::PathBuf>,
    /// User WGSL: functions callable from the formula (s_NAME, ia_NAME, ra_NAME versions) and hooks (hook_reject, hook_hit, hook_shade).
    #[arg(long, value_name = "FILE.wgsl")]
    pub inline: Option<std::path::PathBuf>,
}

/// A compiled formula and, for catalog entries and `.iso` files, the
/// header whose values are the defaults of the render flags.
pub struct Loaded {
    /// The formula.
    pub formula: Formula,
    /// The `.iso` header, if any.
    pub header: Option<Header>,
    /// The `--inline` file, if any.
    pub inline: Option<crate::inline::InlineWgsl>,
}

impl FormulaArgs {
    /// The `.scene.json` file given instead of a formula, if any.
    pub fn scene_path(&self) -> Option<std::path::PathBuf> {
        let is_scene = |p: &str| p.ends_with(".scene.json");
        match (&self.file, self.formula.as_deref()) {
            (Some(p), _) if is_scene(&p.to_string_lossy()) => Some(p.clone()),
            (None, Some(a)) if is_scene(a) => Some(a.into()),
            _ => None,
        }
    }

    /// Reads and compiles the formula, keeping an `.iso` header.
    pub fn load_with_header(&self) -> Result<Loaded, CliError> {
        let inline = match &self.inline {
            None => None,
            Some(p) => {
                let text = bounded::read_file_text(p, MAX_INLINE_BYTES).map_err(|e| CliError::Input(format!("cannot read --inline file '{}': {e}", p.display())))?;
                let path = p.display().to_string();
                Some(crate::inline::parse_inline(&path, &text).map_err(|d| CliError::Rendered(d.render(&path, &text, false)))?)
            }
        };
        let externs = inline.as_ref().map_or(vec![], |i| i.functions.clone());
        let entry = match (&self.file, self.formula.as_deref()) {
            (Some(p), _) if p.extension().is_some_and(|e| e == "iso") => Some(load_iso(p)?),
            (None, Some(a)) if a.starts_with('@') => Some(catalog::lookup(&a[1..]).map_err(|e| CliError::Input(e.to_string()))?),
            (None, Some(a)) if a.ends_with(".iso") => Some(load_iso(Path::new(a))?),
            _ => None,
        };
        if let Some(e) = entry {
            let formula = Formula::compile_with(&e.origin(), &e.formula, &externs)?;
            return Ok(Loaded { formula, header: Some(e.header), inline });
        }
        let (origin, text) = self.text()?;
        Ok(Loaded { formula: Formula::compile_with(&origin, &text, &externs)?, header: None, inline })
    }

    /// The formula's origin name and text (no header handling).
    pub fn text(&self) -> Result<(String, String), CliError> {
        if let Some(p) = &self.file {
            return read_file(p);
        }
        let arg = self.formula.clone().unwrap_or_default();
        if arg == "-" {
            let s = bounded::read_text(std::io::stdin().lock(), MAX_FORMULA_BYTES)
                .map_err(|e| CliError::Input(format!("cannot read the formula from stdin: {e}")))?;
            return Ok(("<stdin>".into(), s));
        }
        Ok(("<formula>".into(), arg))
    }
}

fn load_iso(p: &Path) -> Result<catalog::Entry, CliError> {
    catalog::load_file(p).map_err(|e| CliError::Input(e.to_string()))
}

fn read_file(p: &Path) -> Result<(String, String), CliError> {
    let text = bounded::read_file_text(p, MAX_FORMULA_BYTES).map_err(|e| match e {
        bounded::ReadError::NotUtf8 { offset } => {
            CliError::Input(format!("formula file '{}' is not UTF-8 text (invalid byte at offset {offset})", p.display()))
        }
        e => CliError::Input(format!("cannot read formula file '{}': {e}", p.display())),
    })?;
    Ok((p.display().to_string(), text))
}

/// Writes `bytes` to `path` through a temporary file in the same directory
/// and a rename, so a failure never leaves a partial file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    crate::output::write_atomic(path, bytes).map_err(|e| e.to_string())
}

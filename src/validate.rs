//! Every assembled shader goes through naga (parse + validate) before the
//! driver sees it. A failure here is an isotrace bug; the error carries
//! naga's own diagnostic on the generated WGSL.

use naga::valid::{Capabilities, ValidationFlags, Validator};

/// naga rejected a generated shader.
#[derive(Debug, thiserror::Error)]
#[error("internal error: the generated WGSL does not validate (this is a bug in isotrace)\n{report}")]
pub struct ValidateError {
    /// naga's rendered diagnostic with the WGSL span.
    pub report: String,
}

/// Parses and validates WGSL, returning the module on success.
pub fn validate(source: &str) -> Result<naga::Module, ValidateError> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| ValidateError {
        report: e.emit_to_string_with_path(source, "generated.wgsl"),
    })?;
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .map_err(|e| ValidateError { report: e.emit_to_string_with_path(source, "generated.wgsl") })?;
    Ok(module)
}

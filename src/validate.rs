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

/// Like [`validate`] for a shader that contains user WGSL at `region`
/// (byte range in `source`): an error whose primary span lies inside the
/// region is the user's, reported against their file with naga's message;
/// anything else is an isotrace bug.
pub fn validate_with_inline(
    source: &str,
    region: std::ops::Range<usize>,
    path: &str,
    user_text: &str,
) -> Result<naga::Module, InlineError> {
    let (message, labels, notes): (String, Vec<(std::ops::Range<usize>, String)>, Vec<String>) =
        match naga::front::wgsl::parse_str(source) {
            Err(e) => (
                e.message().to_string(),
                e.labels().filter_map(|(s, l)| s.to_range().map(|r| (r, l.to_string()))).collect(),
                vec![],
            ),
            Ok(module) => match Validator::new(ValidationFlags::all(), Capabilities::default()).validate(&module) {
                Ok(_) => return Ok(module),
                Err(e) => {
                    let mut notes = vec![];
                    let mut src: Option<&dyn std::error::Error> = std::error::Error::source(e.as_inner());
                    while let Some(s) = src {
                        notes.push(s.to_string());
                        src = s.source();
                    }
                    (
                        e.as_inner().to_string(),
                        e.spans().filter_map(|(s, l)| s.to_range().map(|r| (r, l.clone()))).collect(),
                        notes,
                    )
                }
            },
        };
    let inside = |r: &std::ops::Range<usize>| r.start >= region.start && r.end <= region.end;
    match labels.first() {
        Some((r, _)) if inside(r) => {
            let mut d = crate::diag::Diagnostic::plain(format!("in inline WGSL: {message}"));
            for (r, l) in labels.iter().filter(|(r, _)| inside(r)) {
                d = d.with_label(crate::diag::Span::new(r.start - region.start, r.end - region.start), l.clone());
            }
            for n in notes {
                d = d.with_note(n);
            }
            Err(InlineError::User(d.render(path, user_text, false)))
        }
        _ => validate(source).map_err(InlineError::Bug),
    }
}

/// A failed validation of a shader with user WGSL.
#[derive(Debug, thiserror::Error)]
pub enum InlineError {
    /// The user's WGSL is wrong (rendered against their file).
    #[error("{0}")]
    User(String),
    /// The generated part is wrong: an isotrace bug.
    #[error(transparent)]
    Bug(ValidateError),
}

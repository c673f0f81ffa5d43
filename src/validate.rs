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

/// naga's validator with the capabilities isotrace's kernels may use:
/// the defaults, and subgroup operations in compute shaders (a tape's
/// bisection counts work per SIMD bundle where the device has them; a
/// kernel that uses them only reaches such a device).
fn validator() -> Validator {
    let mut v = Validator::new(ValidationFlags::all(), Capabilities::default() | Capabilities::SUBGROUP);
    v.subgroup_stages(naga::valid::ShaderStages::COMPUTE);
    v.subgroup_operations(naga::valid::SubgroupOperationSet::BASIC | naga::valid::SubgroupOperationSet::ARITHMETIC | naga::valid::SubgroupOperationSet::BALLOT);
    v
}

/// Parses and validates WGSL, returning the module on success.
pub fn validate(source: &str) -> Result<naga::Module, ValidateError> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| ValidateError {
        report: e.emit_to_string_with_path(source, "generated.wgsl"),
    })?;
    validator()
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
            Ok(module) => match validator().validate(&module) {
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
    if let Some(d) = clash(source, &region, user_text) {
        return Err(InlineError::User(d.render(path, user_text, false)));
    }
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

/// The first module-scope name the user's WGSL (at `region`) defines that
/// the generated part of `source` defines too. naga reports such a
/// redefinition at whichever of the two comes second, often isotrace's
/// code, so it is found here by name and put on the user's declaration.
/// The generated names are read from the very shader being validated, so
/// the set cannot drift from the templates.
fn clash(source: &str, region: &std::ops::Range<usize>, user_text: &str) -> Option<crate::diag::Diagnostic> {
    use crate::inline::module_names;
    let mut generated = module_names(&source[..region.start]);
    generated.extend(module_names(&source[region.end..]));
    let (name, span) = module_names(user_text).into_iter().find(|(n, _)| generated.iter().any(|(g, _)| g == n))?;
    Some(
        crate::diag::Diagnostic::error(format!("in inline WGSL: '{name}' is already defined by the shader isotrace generates around this file"), span, "defined here too")
            .with_note("the file shares one module with isotrace's own functions, types and constants (main, traverse, field, Ray, Hit, Uniforms, the s_/ia_/ra_ op libraries, …); rename it: a prefix of your own avoids clashes"),
    )
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

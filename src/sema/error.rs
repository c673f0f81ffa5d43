//! The semantic pass's errors and how they read.

use super::{sdf, MAX_EXPONENT, MAX_NODES};
use crate::diag::{quote_user_text, show_number, Diagnostic, Span, QUOTED_CHARS};
use crate::syntax::function_names;

/// Errors of the semantic pass.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)] // fields: the names say it
pub enum SemaError {
    /// A call of a function that does not exist.
    UnknownFunction { name: String, span: Span, suggestions: Vec<String> },
    /// A built-in function used without arguments, or a name that is not a function called with some.
    NotAFunction { name: String, span: Span },
    /// A function used as a value.
    FunctionAsValue { name: String, span: Span },
    /// Wrong number of arguments.
    Arity { name: String, expected: String, found: usize, span: Span },
    /// `a = …;` twice.
    Redefinition { name: String, previous: Span, current: Span },
    /// A definition that uses a name defined after it.
    UseBeforeDefinition { name: String, used: Span, defined: Span },
    /// A definition that uses its own name (`a = a + 1;`).
    SelfReference { name: String, used: Span, defined: Span },
    /// Defining a reserved name (variable, constant, function).
    Reserved { name: String, span: Span },
    /// A constant sub-expression that is not a finite number.
    NotFinite { span: Span, value: f64 },
    /// A number literal beyond the f32 range (`1e39`).
    NumberOutOfRange { span: Span, value: f64 },
    /// An integer exponent beyond [`MAX_EXPONENT`].
    ExponentTooLarge { span: Span, exponent: f64 },
    /// More than [`MAX_NODES`] operations.
    TooLarge { nodes: usize },
    /// A distance-field argument that cannot work (`scale(0, …)`, a zero
    /// plane normal, a blend range k ≤ 0), pointing at the argument.
    BadArgument { name: String, message: String, span: Span },
}

impl SemaError {
    /// Converts to the shared diagnostic form.
    pub fn to_diagnostic(&self) -> Diagnostic {
        match self {
            SemaError::UnknownFunction { name, span, suggestions } => {
                let d = Diagnostic::error(format!("unknown function {}", quote_name(name)), *span, "not a function");
                match suggestions.as_slice() {
                    [] => product_note(d.with_note(format!("functions: {}", function_names().join(" "))), name),
                    s => d.with_note(format!("did you mean {}?", quote_list(s))),
                }
            }
            SemaError::NotAFunction { name, span } => {
                product_note(Diagnostic::error(format!("{} is not a function", quote_name(name)), *span, "called here"), name)
            }
            SemaError::FunctionAsValue { name, span } => {
                Diagnostic::error(format!("function {} used without arguments", quote_name(name)), *span, "expected '(' after this")
                    .with_note(format!("call it: `{name}(x)`"))
            }
            SemaError::Arity { name, expected, found, span } => Diagnostic::error(
                format!("wrong number of arguments to {}: expected {expected}, found {found}", quote_name(name)),
                *span,
                format!("{found} argument{}", if *found == 1 { "" } else { "s" }),
            ),
            SemaError::Redefinition { name, previous, current } => {
                Diagnostic::error(format!("redefinition of {}", quote_name(name)), *current, "defined again here")
                    .with_label(*previous, "first defined here")
            }
            SemaError::UseBeforeDefinition { name, used, defined } => {
                Diagnostic::error(format!("{} is used before its definition", quote_name(name)), *used, "used here")
                    .with_label(*defined, "defined here")
                    .with_note("move the definition above its first use")
            }
            SemaError::SelfReference { name, used, defined } => {
                Diagnostic::error(format!("{} is used in its own definition", quote_name(name)), *used, "used here")
                    .with_label(*defined, "defined here")
                    .with_note("a definition can only use names defined above it")
            }
            SemaError::Reserved { name, span } => {
                Diagnostic::error(format!("cannot define {}: the name is reserved", quote_name(name)), *span, "reserved name")
                    .with_note("x y z t w pi e and the function names cannot be redefined")
            }
            SemaError::NotFinite { span, value } => Diagnostic::error(
                format!("constant expression evaluates to {}", show_number(*value)),
                *span,
                if value.is_finite() { "beyond the 32-bit float range" } else { "not a finite number" },
            )
            .with_note("constants must be finite and within the f32 range (|c| < 3.4e38)"),
            SemaError::NumberOutOfRange { span, value } => Diagnostic::error(
                match value.is_finite() {
                    true => format!("number {} is too large for a 32-bit float", show_number(*value)),
                    false => "number too large for a 32-bit float".to_string(),
                },
                *span,
                "out of range",
            )
            .with_note("the largest 32-bit float is about 3.4e38"),
            SemaError::ExponentTooLarge { span, exponent } => Diagnostic::error(
                match *exponent < 0.0 {
                    false => format!("exponent {exponent} is too large (the limit is {MAX_EXPONENT})"),
                    true => format!("exponent {exponent} is too large (the limit is {MAX_EXPONENT} in absolute value)"),
                },
                *span,
                "exponent too large",
            ),
            SemaError::TooLarge { nodes } => Diagnostic::plain(format!(
                "formula too large: {nodes} operations (the limit is {MAX_NODES})"
            )),
            SemaError::BadArgument { name, message, span } => {
                let sig = sdf::lookup(name).map_or(name.as_str(), |i| i.signature);
                Diagnostic::error(format!("invalid argument to '{name}': {message}"), *span, "this argument")
                    .with_note(format!("usage: {sig}"))
            }
        }
    }
}

/// A name from the formula as a message quotes it (cut, escaped).
pub(super) fn quote_name(name: &str) -> String {
    quote_user_text(name, QUOTED_CHARS)
}

/// `d` with the hint to write a product, when the name is short enough to
/// be written out in it.
fn product_note(d: Diagnostic, name: &str) -> Diagnostic {
    if name.chars().count() > QUOTED_CHARS {
        return d;
    }
    d.with_note(format!("for a product write `{name}*(...)`"))
}

pub(super) fn quote_list(s: &[String]) -> String {
    let q: Vec<String> = s.iter().map(|s| format!("'{s}'")).collect();
    match q.len() {
        1 => q[0].clone(),
        _ => format!("{} or {}", q[..q.len() - 1].join(", "), q[q.len() - 1]),
    }
}


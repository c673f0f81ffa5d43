//! Reading a node object's fields with their JSON paths, and how a
//! message shows a value or a key from the file.

use super::super::SceneError;
use serde_json::{Map, Value};

/// What a JSON value is, for messages.
pub(super) fn describe(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => n.to_string(),
        Value::String(s) if s.chars().count() > 40 => "a string".into(),
        Value::String(s) => format!("\"{s}\""),
        Value::Array(_) => "an array".into(),
        Value::Object(_) => "an object".into(),
    }
}

/// A type name from the file, as a message quotes it: cut and escaped.
pub(super) fn quote(s: &str) -> String {
    crate::diag::quote_user_text(s, crate::diag::QUOTED_CHARS)
}

/// A key from the file as the path of a message names it: as written when
/// it is short and plain, else quoted, cut and escaped (a key can be
/// megabytes long, and the path is printed whole).
pub(super) fn key_path(k: &str) -> std::borrow::Cow<'_, str> {
    if k.chars().count() <= crate::diag::QUOTED_CHARS && !k.chars().any(char::is_control) {
        return k.into();
    }
    quote(k).into()
}

/// A node index: a whole number ≥ 0.
pub(super) fn index(v: &Value) -> Result<usize, String> {
    v.as_u64().and_then(|n| usize::try_from(n).ok()).ok_or_else(|| format!("expected a node index (a whole number >= 0), found {}", describe(v)))
}

/// The fields of one node object (or of an object inside it, whose field
/// names get `prefix`), read with paths.
pub(super) struct Fields<'a> {
    pub(super) i: usize,
    pub(super) obj: &'a Map<String, Value>,
    pub(super) prefix: &'static str,
}

impl Fields<'_> {
    pub(super) fn err(&self, field: &str, reason: impl Into<String>) -> SceneError {
        SceneError::at(self.i, &format!("{}{field}", self.prefix), reason)
    }

    pub(super) fn number_of(&self, field: &str, v: &Value) -> Result<f64, SceneError> {
        match v.as_f64() {
            Some(x) if x.is_finite() => Ok(x),
            Some(_) => Err(self.err(field, "must be finite")),
            None => Err(self.err(field, format!("expected a number, found {}", describe(v)))),
        }
    }

    pub(super) fn number(&self, field: &str) -> Result<f64, SceneError> {
        match self.obj.get(field) {
            Some(v) => self.number_of(field, v),
            None => Err(self.err(field, "missing")),
        }
    }

    pub(super) fn numbers<const N: usize>(&self, field: &str) -> Result<Option<[f64; N]>, SceneError> {
        let Some(v) = self.obj.get(field) else { return Ok(None) };
        let Some(a) = v.as_array() else {
            return Err(self.err(field, format!("expected {N} numbers, found {}", describe(v))));
        };
        if a.len() != N {
            return Err(self.err(field, format!("expected {N} numbers, found {}", a.len())));
        }
        let mut out = [0.0; N];
        for (k, x) in a.iter().enumerate() {
            out[k] = self.number_of(&format!("{field}[{k}]"), x)?;
        }
        Ok(Some(out))
    }

    pub(super) fn vec3(&self, field: &str) -> Result<[f64; 3], SceneError> {
        self.numbers::<3>(field)?.ok_or_else(|| self.err(field, "missing"))
    }

    pub(super) fn index(&self, field: &str) -> Result<usize, SceneError> {
        let v = self.obj.get(field).ok_or_else(|| self.err(field, "missing"))?;
        index(v).map_err(|r| self.err(field, r))
    }

    /// Refuses any key not in `allowed`.
    pub(super) fn only(&self, ty: &str, allowed: &[&str]) -> Result<(), SceneError> {
        for k in self.obj.keys() {
            if k != "type" && !allowed.contains(&k.as_str()) {
                return Err(self.err(&key_path(k), format!("unknown field for a {ty}; expected {}", list(allowed))));
            }
        }
        Ok(())
    }
}

/// `a, b or c`.
pub(super) fn list(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

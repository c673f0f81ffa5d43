//! Putting shard outputs together: the checks every merge shares. Each
//! input is read into its typed form ([`parse`]); what must agree between
//! inputs (the version and the settings) is then compared as JSON, key by
//! key, so a refusal names the exact key (with its path, `settings.size`)
//! and the two files that disagree on it.

use serde::de::{DeserializeOwned, IgnoredAny};
use serde_json::Value;

/// What one input of a merge holds under the keys that must agree, and
/// its file name (for messages).
#[derive(Debug, Clone)]
pub struct Part {
    /// Where it came from, as the user named it.
    pub file: String,
    /// The compared keys (`isotrace_version`, `settings`) as JSON.
    pub json: Value,
}

impl Part {
    /// The part of `file` whose version and settings are these.
    pub fn new(file: &str, isotrace_version: &str, settings: &impl serde::Serialize) -> Part {
        let settings = serde_json::to_value(settings).unwrap_or(Value::Null);
        Part { file: file.to_string(), json: serde_json::json!({ "isotrace_version": isotrace_version, "settings": settings }) }
    }
}

/// Why parts cannot be merged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MergeError {
    /// No parts.
    #[error("nothing to merge: no files given")]
    Empty,
    /// A file that is not the kind of part asked for.
    #[error("'{file}' is not {what}: {reason}")]
    NotAPart {
        /// The file.
        file: String,
        /// What it should be (`an isotrace bench report`, …).
        what: &'static str,
        /// Why not.
        reason: String,
    },
    /// Two parts differ in a key that must be equal.
    #[error("cannot merge '{file_b}' with '{file_a}': {key} is {value_a} in '{file_a}' but {value_b} in '{file_b}'")]
    Differs {
        /// The key's path, `settings.size`.
        key: String,
        /// The first file (the reference).
        file_a: String,
        /// Its value, as JSON.
        value_a: String,
        /// The file that differs.
        file_b: String,
        /// Its value, as JSON (`absent` when the key is missing).
        value_b: String,
    },
    /// A part whose content contradicts its own settings.
    #[error("'{file}': {reason}")]
    Inconsistent {
        /// The file.
        file: String,
        /// What contradicts what.
        reason: String,
    },
    /// Items of the batch that no part holds.
    #[error("{} of {total} {what} are in no file: {list}", .missing.len())]
    Missing {
        /// `jobs`, `frames`.
        what: &'static str,
        /// How many the batch has.
        total: usize,
        /// The missing indices, sorted.
        missing: Vec<usize>,
        /// Them, described (`3 (steiner raa), …`).
        list: String,
    },
}

/// Checks that every part has the same values as the first under each of
/// `keys` (dotted paths such as `settings.surfaces`, compared recursively,
/// in the order given so the key that explains a difference best is named
/// first), except at the paths in `ignore` (`settings.shard`): the first
/// difference is the error.
pub fn check_same(parts: &[Part], keys: &[&str], ignore: &[&str]) -> Result<(), MergeError> {
    let Some(first) = parts.first() else { return Err(MergeError::Empty) };
    parts[1..].iter().try_for_each(|p| check_pair(first, p, keys, ignore))
}

/// [`check_same`] of one part against the first: merges read their parts
/// one at a time and compare each with the first as it comes.
pub fn check_pair(first: &Part, p: &Part, keys: &[&str], ignore: &[&str]) -> Result<(), MergeError> {
    let at = |v: &'_ Value, key: &str| v.pointer(&format!("/{}", key.replace('.', "/"))).cloned();
    for key in keys {
        if let Some((path, a, b)) = difference(at(&first.json, key).as_ref(), at(&p.json, key).as_ref(), key, ignore) {
            return Err(MergeError::Differs { key: path, file_a: first.file.clone(), value_a: a, file_b: p.file.clone(), value_b: b });
        }
    }
    Ok(())
}

/// The first path under `path` where `a` and `b` differ, with both values
/// as JSON. Objects are compared key by key (in sorted order); anything else
/// (numbers, strings, arrays such as a size) as a whole.
fn difference(a: Option<&Value>, b: Option<&Value>, path: &str, ignore: &[&str]) -> Option<(String, String, String)> {
    if ignore.contains(&path) {
        return None;
    }
    let show = |v: Option<&Value>| v.map_or("absent".to_string(), |v| v.to_string());
    match (a, b) {
        (Some(Value::Object(x)), Some(Value::Object(y))) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            keys.into_iter().find_map(|k| difference(x.get(k), y.get(k), &format!("{path}.{k}"), ignore))
        }
        _ if a == b => None,
        _ => Some((path.to_string(), show(a), show(b))),
    }
}

/// Parses the text of one input of a merge (`file`, for messages) as `T`.
/// It is read straight into its typed form: a JSON tree of a large
/// manifest takes many times the file's size in memory, the typed form
/// about its size. The top level must be an object; anything else is named
/// as what it is (`found an array`) rather than as the first missing key.
pub fn parse<T: DeserializeOwned>(file: &str, text: &str, what: &'static str) -> Result<T, MergeError> {
    let not = |reason: String| MergeError::NotAPart { file: file.to_string(), what, reason };
    let kind = match text.trim_start_matches([' ', '\t', '\n', '\r']).as_bytes().first() {
        Some(b'[') => Some("an array"),
        Some(b'"') => Some("a string"),
        Some(b't' | b'f') => Some("a boolean"),
        Some(b'n') => Some("null"),
        Some(b'-' | b'0'..=b'9') => Some("a number"),
        _ => None,
    };
    // Well-formed JSON is named by its kind (a typed parse would take an
    // array for a struct's fields in order); a syntax error is the
    // parser's message, with its line and column.
    if let Some(kind) = kind {
        return Err(not(match serde_json::from_str::<IgnoredAny>(text) {
            Ok(_) => format!("expected a JSON object at the top level, found {kind}"),
            Err(e) => json_reason(&e),
        }));
    }
    serde_json::from_str(text).map_err(|e| not(json_reason(&e)))
}

/// A JSON error as a reason: the parser's message, then where (`…, at line
/// 5 column 3`), so the position does not read as part of the message.
fn json_reason(e: &serde_json::Error) -> String {
    let text = e.to_string();
    let position = format!(" at line {} column {}", e.line(), e.column());
    match text.strip_suffix(&position) {
        Some(message) if e.line() > 0 => format!("{message},{position}"),
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn part(file: &str, json: Value) -> Part {
        Part { file: file.into(), json }
    }

    #[test]
    fn the_first_differing_key_and_both_files_are_named() {
        let a = part("a.json", json!({"isotrace_version": "0.1.0", "settings": {"size": [16, 16], "shard": "0/2", "eps": 1.0}}));
        let b = part("b.json", json!({"isotrace_version": "0.1.0", "settings": {"size": [24, 24], "shard": "1/2", "eps": 1.0}}));
        let e = check_same(&[a.clone(), b], &["isotrace_version", "settings"], &["settings.shard"]).unwrap_err();
        assert_eq!(e.to_string(), "cannot merge 'b.json' with 'a.json': settings.size is [16,16] in 'a.json' but [24,24] in 'b.json'");
        let c = part("c.json", json!({"isotrace_version": "0.2.0", "settings": {"size": [16, 16], "shard": "1/2"}}));
        let e = check_same(&[a.clone(), c], &["isotrace_version", "settings"], &["settings.shard"]).unwrap_err();
        assert_eq!(e.to_string(), "cannot merge 'c.json' with 'a.json': isotrace_version is \"0.1.0\" in 'a.json' but \"0.2.0\" in 'c.json'");
        let d = part("d.json", json!({"isotrace_version": "0.1.0", "settings": {"size": [16, 16], "shard": "1/2", "eps": 1.0}}));
        assert_eq!(check_same(&[a, d], &["isotrace_version", "settings"], &["settings.shard"]), Ok(()));
    }

    #[test]
    fn a_part_must_be_an_object_and_errors_say_where() {
        #[derive(Debug, serde::Deserialize)]
        struct T {
            #[allow(dead_code)]
            a: u32,
        }
        let e = |text: &str| parse::<T>("m.json", text, "a thing").unwrap_err().to_string();
        assert_eq!(e(" []"), "'m.json' is not a thing: expected a JSON object at the top level, found an array");
        assert_eq!(e("\"x\""), "'m.json' is not a thing: expected a JSON object at the top level, found a string");
        assert_eq!(e("12"), "'m.json' is not a thing: expected a JSON object at the top level, found a number");
        assert_eq!(e("[1,"), "'m.json' is not a thing: EOF while parsing a value, at line 1 column 3");
        assert_eq!(e("{\"b\": 1}"), "'m.json' is not a thing: missing field `a`, at line 1 column 8");
        assert_eq!(e(""), "'m.json' is not a thing: EOF while parsing a value, at line 1 column 0");
        assert!(parse::<T>("m.json", "{\"a\": 1}", "a thing").is_ok());
    }

    #[test]
    fn a_missing_key_is_absent() {
        let a = part("a.json", json!({"settings": {"x": 1}}));
        let b = part("b.json", json!({"settings": {}}));
        let e = check_same(&[a, b], &["settings"], &[]).unwrap_err();
        assert_eq!(e.to_string(), "cannot merge 'b.json' with 'a.json': settings.x is 1 in 'a.json' but absent in 'b.json'");
    }
}

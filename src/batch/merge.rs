//! Putting shard outputs together: the checks every merge shares. Parts are
//! compared as JSON, key by key, so a refusal names the exact key (with its
//! path, `settings.size`) and the two files that disagree on it.

use serde_json::Value;

/// One input of a merge: its file name (for messages) and its content.
#[derive(Debug, Clone)]
pub struct Part {
    /// Where it came from, as the user named it.
    pub file: String,
    /// The parsed JSON.
    pub json: Value,
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
    let at = |v: &'_ Value, key: &str| v.pointer(&format!("/{}", key.replace('.', "/"))).cloned();
    for p in &parts[1..] {
        for key in keys {
            if let Some((path, a, b)) = difference(at(&first.json, key).as_ref(), at(&p.json, key).as_ref(), key, ignore) {
                return Err(MergeError::Differs { key: path, file_a: first.file.clone(), value_a: a, file_b: p.file.clone(), value_b: b });
            }
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

/// Deserialises a part into `T`, or says which file is not one and why.
pub fn typed<T: serde::de::DeserializeOwned>(p: &Part, what: &'static str) -> Result<T, MergeError> {
    serde_json::from_value(p.json.clone()).map_err(|e| MergeError::NotAPart { file: p.file.clone(), what, reason: e.to_string() })
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
    fn a_missing_key_is_absent() {
        let a = part("a.json", json!({"settings": {"x": 1}}));
        let b = part("b.json", json!({"settings": {}}));
        let e = check_same(&[a, b], &["settings"], &[]).unwrap_err();
        assert_eq!(e.to_string(), "cannot merge 'b.json' with 'a.json': settings.x is 1 in 'a.json' but absent in 'b.json'");
    }
}

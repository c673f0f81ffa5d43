//! The catalog of named surfaces: `.iso` files and the built-in set.
//!
//! An `.iso` file is a formula file whose leading `#@ key: value` lines are a
//! header. `#` starts a comment in the formula language, so the whole file is
//! still a valid formula and [`Entry::formula`] is the complete file text
//! (diagnostics then point at the file's own lines). The format is described
//! in `examples/README.md`. `src/tests/catalog.rs` looks up the tangle as
//! an example (`an_entry_is_found_by_name_and_compiles`).

use crate::diag::closest;
pub use crate::render::{Bound, Method};
use crate::{Formula, FormulaError};
use std::path::{Path, PathBuf};

mod header;
mod suite;
pub use header::{parse_box, parse_eps, parse_number, parse_vec3, Algebra, Header, Status};
#[cfg(test)]
pub(crate) use header::Clip;
use header::apply;
pub use suite::{suite, suite_choices};
#[cfg(test)]
pub(crate) use suite::SUITES;

/// The box of a file that gives none: `[-2, 2]³`.
pub use crate::render::view::DEFAULT_BOX;

/// Largest `.iso` file read, in bytes. Its formula is bounded by
/// [`crate::syntax::parser::MAX_SOURCE_BYTES`]; the rest leaves ample room
/// for header lines and comments, and bounds what an endless file can take.
pub const MAX_ISO_BYTES: u64 = 1 << 20;

/// Every header key, in the order the documentation lists them.
pub const KEYS: &[&str] = &[
    "name", "title", "box", "t", "eye", "target", "up", "fov", "eps", "algebra", "param", "degree", "status",
    "source", "notes", "animate", "clip", "method", "field", "lipschitz", "bound",
    // Knoll et al.'s modalities, as defaults of the render flags of the same names.
    "shadows", "light", "shadow-eps", "opacity", "layers", "iso", "reflect", "reflectivity", "env", "color",
];

/// The built-in surfaces: file name and text of every `examples/*.iso`.
const BUILTIN: &[(&str, &str)] = &[
    // The 16 surfaces of Knoll et al. (Table 1), in the table's order.
    ("sphere.iso", include_str!("../examples/sphere.iso")),
    ("steiner.iso", include_str!("../examples/steiner.iso")),
    ("mitchell.iso", include_str!("../examples/mitchell.iso")),
    ("teardrop.iso", include_str!("../examples/teardrop.iso")),
    ("4-bretzel.iso", include_str!("../examples/4-bretzel.iso")),
    ("klein-bottle.iso", include_str!("../examples/klein-bottle.iso")),
    ("tangle.iso", include_str!("../examples/tangle.iso")),
    ("decocube.iso", include_str!("../examples/decocube.iso")),
    ("barth-sextic.iso", include_str!("../examples/barth-sextic.iso")),
    ("barth-decic.iso", include_str!("../examples/barth-decic.iso")),
    ("superquadric.iso", include_str!("../examples/superquadric.iso")),
    ("icos.csg.iso", include_str!("../examples/icos.csg.iso")),
    ("sq.csg.iso", include_str!("../examples/sq.csg.iso")),
    ("sin.blob.iso", include_str!("../examples/sin.blob.iso")),
    ("cloth.iso", include_str!("../examples/cloth.iso")),
    ("water.iso", include_str!("../examples/water.iso")),
    // Further classics.
    ("torus.iso", include_str!("../examples/torus.iso")),
    ("heart.iso", include_str!("../examples/heart.iso")),
    ("gyroid.iso", include_str!("../examples/gyroid.iso")),
    ("cayley-cubic.iso", include_str!("../examples/cayley-cubic.iso")),
    ("clebsch-cubic.iso", include_str!("../examples/clebsch-cubic.iso")),
    ("kummer-quartic.iso", include_str!("../examples/kummer-quartic.iso")),
    ("chmutov-octic.iso", include_str!("../examples/chmutov-octic.iso")),
    // Distance-field scenes for sphere tracing (`method: sphere`).
    ("jewel.iso", include_str!("../examples/jewel.iso")),
    ("city.iso", include_str!("../examples/city.iso")),
    ("creature.iso", include_str!("../examples/creature.iso")),
    // Several isosurfaces of one function, seen through each other.
    ("onion.iso", include_str!("../examples/onion.iso")),
];

/// One named surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// The `name` key, else the file stem (`icos.csg` for `icos.csg.iso`).
    pub name: String,
    /// The file it was loaded from; `None` for a built-in entry.
    pub path: Option<PathBuf>,
    /// The parsed header.
    pub header: Header,
    /// The whole file text (header lines included: they are comments).
    pub formula: String,
}

/// Errors of the catalog.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CatalogError {
    /// A malformed header (or a file with no formula), with its 1-based line.
    #[error("{file}:{line}: {message}")]
    Parse {
        /// The file as displayed.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A file that cannot be read.
    #[error("{file}: {message}")]
    Read {
        /// The file as displayed.
        file: String,
        /// What went wrong.
        message: String,
    },
    /// A name that is not in the built-in catalog.
    #[error("unknown surface '{name}'; {}", unknown_tail(.suggestions, .known))]
    UnknownName {
        /// The name asked for.
        name: String,
        /// The closest built-in names (may be empty).
        suggestions: Vec<String>,
        /// Every built-in name.
        known: Vec<String>,
    },
    /// A name that is not one of [`SUITES`].
    #[error("unknown suite '{name}': expected {}", suite_choices())]
    UnknownSuite {
        /// The name asked for.
        name: String,
    },
}

fn unknown_tail(suggestions: &[String], known: &[String]) -> String {
    if suggestions.is_empty() {
        format!("the catalog has: {}", known.join(", "))
    } else {
        format!("did you mean {}?", quote_list(suggestions))
    }
}

fn quote_list(s: &[String]) -> String {
    let q: Vec<String> = s.iter().map(|s| format!("'{s}'")).collect();
    match q.len() {
        0 | 1 => q.concat(),
        n => format!("{} or {}", q[..n - 1].join(", "), q[n - 1]),
    }
}

impl Entry {
    /// Where the formula came from, for diagnostics: the file path, or
    /// `@name` for a built-in entry.
    pub fn origin(&self) -> String {
        match &self.path {
            Some(p) => p.display().to_string(),
            None => format!("@{}", self.name),
        }
    }

    /// Parses and analyses the formula (the whole file text).
    pub fn compile(&self) -> Result<Formula, FormulaError> {
        Formula::compile(&self.origin(), &self.formula)
    }

    /// The settings of a `width × height` frame of this entry's formula
    /// `f` (from [`Entry::compile`]) with the header's view.
    #[cfg(any(test, feature = "internals"))]
    pub fn settings(&self, f: &Formula, width: u32, height: u32) -> Result<crate::render::Settings, crate::render::ViewError> {
        Ok(self.header.view().settings(f, width, height)?.0)
    }

    /// The traversal the header asks for (`method`, `algebra`, and for
    /// sphere tracing `lipschitz` and `bound`), every technique and
    /// optimisation at its default, no modalities.
    #[cfg(any(test, feature = "internals"))]
    pub fn traversal(&self, f: &Formula) -> crate::render::Traversal {
        use crate::render::{BisectOptions, SphereOptions, Traversal};
        let h = &self.header;
        match h.method.unwrap_or_default() {
            Method::Sphere => Traversal::Sphere(SphereOptions { lipschitz: h.lipschitz.unwrap_or(1.0), bound: h.bound, ..Default::default() }),
            Method::Bisect => Traversal::Bisect(BisectOptions::new(h.algebra.unwrap_or(Algebra::Auto).domain(&f.ir))),
        }
    }
}

/// Every built-in surface, in catalog order.
///
/// # Panics
/// If an embedded file does not parse (the tests make sure they all do).
pub fn builtin() -> Vec<Entry> {
    BUILTIN
        .iter()
        .map(|(file, text)| parse_iso(&format!("examples/{file}"), text).unwrap_or_else(|e| panic!("built-in catalog: {e}")))
        .collect()
}

/// The built-in surface called `name`. Spaces count as hyphens, case is
/// ignored and a trailing `.iso` is dropped, so `Klein Bottle` finds
/// `klein-bottle`. An unknown name is an error that suggests close names.
pub fn lookup(name: &str) -> Result<Entry, CatalogError> {
    let wanted = name.trim();
    let wanted = wanted.strip_suffix(".iso").unwrap_or(wanted).replace(' ', "-").to_ascii_lowercase();
    let all = builtin();
    if let Some(e) = all.iter().find(|e| e.name.to_ascii_lowercase() == wanted) {
        return Ok(e.clone());
    }
    let known: Vec<String> = all.into_iter().map(|e| e.name).collect();
    let suggestions = closest(&wanted, known.iter().map(String::as_str)).into_iter().map(String::from).collect();
    Err(CatalogError::UnknownName { name: name.to_string(), suggestions, known })
}

/// Reads and parses an `.iso` file.
pub fn load_file(path: impl AsRef<Path>) -> Result<Entry, CatalogError> {
    let path = path.as_ref();
    let file = path.display().to_string();
    let text = crate::bounded::read_file_text(path, MAX_ISO_BYTES).map_err(|e| CatalogError::Read {
        file: file.clone(),
        message: match e {
            crate::bounded::ReadError::NotUtf8 { .. } => e.to_string(),
            _ => format!("cannot read: {e}"),
        },
    })?;
    let mut entry = parse_iso(&file, &text)?;
    // A relative `env:` image belongs to the file, not to the working
    // directory of whoever renders it.
    let dir = path.parent().unwrap_or(Path::new(""));
    if let Some(crate::render::EnvSpec::File(p)) = &mut entry.header.modalities.env {
        let outside = crate::bounded::leaves_dir(dir, p);
        if p.is_relative() {
            *p = dir.join(&*p);
        }
        if outside {
            entry.header.outside_paths.push(p.clone());
        }
    }
    entry.path = Some(path.to_path_buf());
    Ok(entry)
}

/// Parses the text of an `.iso` file. `path_display` names the file in
/// errors and gives the entry its name when there is no `name` key. The
/// returned entry has `path: None`; [`load_file`] fills it in.
pub fn parse_iso(path_display: &str, text: &str) -> Result<Entry, CatalogError> {
    let err = |line: usize, message: String| CatalogError::Parse { file: path_display.to_string(), line, message };
    let mut header = Header::default();
    let mut name: Option<String> = None;
    let mut seen: Vec<(&str, usize)> = Vec::new();
    let mut params_seen: Vec<(String, usize)> = Vec::new();
    let mut formula_started = false;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let trimmed = line.trim_start();
        if let Some(rest) = trimmed.strip_prefix("#@") {
            if formula_started {
                return Err(err(n, "header line after the start of the formula (header lines must come first)".into()));
            }
            let (key, value) = split_header_line(rest).map_err(|m| err(n, m))?;
            if !KEYS.contains(&key) {
                return Err(err(n, unknown_key(key)));
            }
            if key != "param" {
                if let Some(&(_, first)) = seen.iter().find(|(k, _)| *k == key) {
                    return Err(err(n, format!("duplicate key '{key}' (first given on line {first})")));
                }
                seen.push((key, n));
            }
            let bad = |why: String| err(n, format!("bad {key} value '{value}': {why}"));
            apply(&mut header, &mut name, key, value).map_err(bad)?;
            if key == "param" {
                let pname = &header.params.last().expect("apply pushed a param").0;
                if let Some((_, first)) = params_seen.iter().find(|(p, _)| p == pname) {
                    return Err(err(n, format!("duplicate param '{pname}' (first given on line {first})")));
                }
                params_seen.push((pname.clone(), n));
            }
        } else if !(trimmed.is_empty() || trimmed.starts_with('#')) {
            formula_started = true;
        }
    }
    if !formula_started {
        let end = text.lines().count() + usize::from(text.is_empty() || text.ends_with('\n'));
        return Err(err(end, "missing formula: the file has only a header".into()));
    }
    let name = name.unwrap_or_else(|| file_stem(path_display));
    Ok(Entry { name, path: None, header, formula: text.to_string() })
}

/// `" key: value"` → `("key", "value")`.
fn split_header_line(rest: &str) -> Result<(&str, &str), String> {
    let malformed = || "malformed header line: expected '#@ key: value'".to_string();
    let (key, value) = rest.split_once(':').ok_or_else(malformed)?;
    let key = key.trim();
    if key.is_empty() || !key.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'-') {
        return Err(malformed());
    }
    let value = value.trim();
    if value.is_empty() {
        return Err(format!("empty value for key '{key}'"));
    }
    Ok((key, value))
}

fn unknown_key(key: &str) -> String {
    match closest(key, KEYS.iter().copied()).first() {
        Some(s) => format!("unknown key '{key}' (did you mean '{s}'?)"),
        None => format!("unknown key '{key}' (keys: {})", KEYS.join(", ")),
    }
}

fn file_stem(path_display: &str) -> String {
    let base = path_display.rsplit(['/', '\\']).next().unwrap_or(path_display);
    base.strip_suffix(".iso").unwrap_or(base).to_string()
}

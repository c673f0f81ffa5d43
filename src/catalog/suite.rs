//! The named suites of built-in surfaces, defined here once so the `bench`
//! command, the tests, the criterion benches and the peer harness measure
//! and check the same surfaces in the same order.

use super::{CatalogError, BUILTIN};

/// The suite names [`suite`] knows, in the order messages list them.
pub const SUITES: &[&str] = &["knoll", "sdf", "all"];

/// The 16 surfaces of Knoll et al.'s Table 1, in the table's order (the
/// order their results are compared in).
const KNOLL: &[&str] = &[
    "sphere", "steiner", "mitchell", "teardrop", "4-bretzel", "klein-bottle", "tangle", "decocube", "barth-sextic",
    "barth-decic", "superquadric", "icos.csg", "sq.csg", "sin.blob", "cloth", "water",
];

/// The distance-field scenes made for sphere tracing (`method: sphere`).
/// `onion`, next to them in the catalog, is not one: it shows three
/// isosurfaces of a polynomial through each other (transparency).
const SDF: &[&str] = &["jewel", "city", "creature"];

/// The entry names of suite `name`, each a name [`super::lookup`] finds:
/// `knoll` (Table 1 of Knoll et al.), `sdf` (the distance-field scenes) or
/// `all` (every built-in entry, in catalog order). `all` is read from the
/// built-in table, so a new `.iso` file joins it without an edit here
/// (`src/tests/catalog.rs`: `suites_name_their_entries`).
pub fn suite(name: &str) -> Result<Vec<&'static str>, CatalogError> {
    match name {
        "knoll" => Ok(KNOLL.to_vec()),
        "sdf" => Ok(SDF.to_vec()),
        // An entry's name is its file stem (src/tests/catalog.rs checks that no
        // built-in file overrides it), so the names need no parsing.
        "all" => Ok(BUILTIN.iter().map(|(file, _)| file.strip_suffix(".iso").unwrap_or(file)).collect()),
        _ => Err(CatalogError::UnknownSuite { name: name.to_string() }),
    }
}

/// The suite names as a sentence ends them: `knoll, sdf or all`.
pub fn suite_choices() -> String {
    match SUITES.split_last() {
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

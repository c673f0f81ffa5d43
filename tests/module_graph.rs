//! The library's modules use each other as `docs/architecture.md` says:
//! its "may use" column is exactly the `crate::` graph of `src/` (test
//! modules, `src/tests/` and comments aside), and that graph has no cycle.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

type Graph = BTreeMap<String, BTreeSet<String>>;

/// `text` without `// …` comments and `#[cfg(test)] mod … { … }` blocks.
fn code_of(text: &str) -> String {
    let uncommented: String = text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n");
    let mut out = String::new();
    let mut rest = uncommented.as_str();
    while let Some(at) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..at]);
        let after = &rest[at + "#[cfg(test)]".len()..];
        let item = after.trim_start();
        let block = item.starts_with("mod ") && item.find('{').is_some_and(|b| item.find(';').is_none_or(|s| b < s));
        rest = if block { &item[block_end(item)..] } else { after };
    }
    out.push_str(rest);
    out
}

/// The byte after the brace that closes `item`'s first `{`, braces in
/// string and character literals aside.
fn block_end(item: &str) -> usize {
    let bytes = item.as_bytes();
    let (mut depth, mut i) = (0i32, item.find('{').unwrap_or(0));
    while i < bytes.len() {
        match bytes[i] {
            b'"' => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
            }
            // A character literal ('{', '\''), not a lifetime ('a).
            b'\'' if bytes.get(i + 2) == Some(&b'\'') => i += 2,
            b'\'' if bytes.get(i + 1) == Some(&b'\\') => i += 3,
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return i + 1;
                }
            }
            _ => {}
        }
        i += 1;
    }
    bytes.len()
}

/// Whether a file holds only unit tests (`tests.rs`, `*_tests.rs`).
fn is_test_file(path: &Path) -> bool {
    path.file_stem().and_then(|s| s.to_str()).is_some_and(|s| s == "tests" || s.ends_with("_tests"))
}

/// The library's top-level modules and the modules each uses.
fn graph_of_source(src: &Path) -> Graph {
    let modules: BTreeSet<String> = std::fs::read_dir(src)
        .expect("src/")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .map(|n| n.trim_end_matches(".rs").to_string())
        // `cli` may use every module (docs/architecture.md); `tests` holds the unit tests.
        .filter(|n| !["lib", "main", "cli", "tests"].contains(&n.as_str()))
        .collect();
    let mut graph: Graph = modules.iter().map(|m| (m.clone(), BTreeSet::new())).collect();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("a source folder").flatten() {
            let path = entry.path();
            let rel = path.strip_prefix(src).expect("inside src").to_string_lossy().replace('\\', "/");
            let top = rel.split('/').next().unwrap_or("").trim_end_matches(".rs").to_string();
            if !modules.contains(&top) {
                continue;
            }
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") || is_test_file(&path) {
                continue;
            }
            let code = code_of(&std::fs::read_to_string(&path).expect("a source file"));
            for (at, _) in code.match_indices("crate::") {
                let name: String = code[at + 7..].chars().take_while(|c| c.is_ascii_lowercase() || *c == '_').collect();
                if name != top && modules.contains(&name) {
                    graph.get_mut(&top).expect("a module").insert(name);
                }
            }
        }
    }
    graph
}

/// The "may use" column of the module table in `docs/architecture.md`.
fn graph_of_docs(text: &str) -> Graph {
    let names = |cell: &str| -> BTreeSet<String> { cell.split('`').skip(1).step_by(2).map(str::to_string).collect() };
    text.lines()
        .filter(|l| l.starts_with("| `"))
        .filter_map(|l| {
            let cells: Vec<&str> = l.trim_matches('|').split('|').map(str::trim).collect();
            let module = names(cells.first()?).into_iter().next()?;
            Some((module, names(cells.last()?)))
        })
        .collect()
}

/// A module on a cycle of `graph`, if any (depth-first search).
fn cycle(graph: &Graph) -> Option<Vec<String>> {
    fn visit(m: &str, graph: &Graph, path: &mut Vec<String>, done: &mut BTreeSet<String>) -> Option<Vec<String>> {
        if let Some(i) = path.iter().position(|p| p == m) {
            return Some(path[i..].to_vec());
        }
        if done.contains(m) {
            return None;
        }
        path.push(m.to_string());
        for n in graph.get(m).into_iter().flatten() {
            if let Some(c) = visit(n, graph, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(m.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph.keys().find_map(|m| visit(m, graph, &mut Vec::new(), &mut done))
}

#[test]
fn the_module_table_of_the_architecture_doc_is_the_code_s_import_graph() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let code = graph_of_source(&root.join("src"));
    let docs = graph_of_docs(&std::fs::read_to_string(root.join("docs/architecture.md")).expect("docs/architecture.md"));
    let show = |s: Option<&BTreeSet<String>>| s.map_or("(no row)".to_string(), |s| s.iter().cloned().collect::<Vec<_>>().join(", "));
    let wrong: Vec<String> = code
        .keys()
        .chain(docs.keys())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .filter(|m| code.get(*m) != docs.get(*m))
        .map(|m| format!("{m}: the code uses [{}], the table says [{}]", show(code.get(m)), show(docs.get(m))))
        .collect();
    assert!(wrong.is_empty(), "docs/architecture.md's module table differs from the code:\n{}", wrong.join("\n"));
    assert_eq!(cycle(&code), None, "modules that use each other");
}

#[test]
fn a_cycle_and_a_wrong_row_are_seen() {
    let graph: Graph = [("a", vec!["b"]), ("b", vec!["c"]), ("c", vec!["a"]), ("d", vec![])]
        .into_iter()
        .map(|(m, uses)| (m.to_string(), uses.into_iter().map(String::from).collect()))
        .collect();
    assert_eq!(cycle(&graph).map(|c| c.len()), Some(3));
    let docs = graph_of_docs("| `a` | job | `b` |\n| `d` | job | — |\n");
    assert_eq!(docs["a"], BTreeSet::from(["b".to_string()]));
    assert!(docs["d"].is_empty());
    assert_eq!(code_of("use crate::x;\n#[cfg(test)]\nmod tests { use crate::y; }\nfn f() {} // crate::z"), "use crate::x;\n\nfn f() {} ");
    let braces_in_literals = "#[cfg(test)]\nmod tests { fn f() { let c = '}'; let s = \"}}\"; let q = '\\''; } }\nuse crate::z;";
    assert_eq!(code_of(braces_in_literals), "\nuse crate::z;");
}

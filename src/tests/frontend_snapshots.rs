//! Snapshot tests of the generated evaluators.
//!
//! Every `tests/snapshots/in/NAME.iso` is compiled and its evaluator in each
//! domain (`crate::field::compiled::emit_evaluator`) is compared with
//! `tests/snapshots/out/NAME.{s,ia,ra}.wgsl`. Run with `ISOTRACE_BLESS=1` to
//! (re)write the expected outputs after an intended change, then review the
//! diff. Each snapshot's complete eval shader must also pass naga.

use crate::Formula;
use crate::ir::Domain;
use std::path::{Path, PathBuf};

const DOMAINS: [Domain; 3] = [Domain::Scalar, Domain::Interval, Domain::Affine];

fn dir(sub: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots").join(sub)
}

fn inputs() -> Vec<(String, PathBuf)> {
    let mut v: Vec<(String, PathBuf)> = std::fs::read_dir(dir("in"))
        .expect("tests/snapshots/in")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "iso"))
        .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), p))
        .collect();
    v.sort();
    v
}

fn bless() -> bool {
    std::env::var("ISOTRACE_BLESS").is_ok_and(|v| v == "1")
}

#[test]
fn evaluator_snapshots() {
    let inputs = inputs();
    assert!(inputs.len() >= 12, "expected the snapshot inputs, found {}", inputs.len());
    let mut failures = Vec::new();
    for (name, path) in &inputs {
        let src = std::fs::read_to_string(path).unwrap();
        let f = Formula::compile(&path.display().to_string(), &src).unwrap_or_else(|e| panic!("{e}"));
        for d in DOMAINS {
            let got = crate::field::compiled::emit_evaluator(&f.ir, d);
            let out = dir("out").join(format!("{name}.{}.wgsl", d.prefix()));
            if bless() {
                std::fs::write(&out, &got).unwrap();
                continue;
            }
            match std::fs::read_to_string(&out) {
                Ok(want) if want == got => {}
                Ok(want) => failures.push(format!("{}: differs\n--- expected\n{want}\n--- got\n{got}", out.display())),
                Err(e) => failures.push(format!("{}: {e}", out.display())),
            }
        }
    }
    assert!(failures.is_empty(), "{}\n\n{} snapshot(s) differ; rerun with ISOTRACE_BLESS=1 to accept", failures.join("\n\n"), failures.len());
}

#[test]
fn no_stale_snapshot_outputs() {
    let names: Vec<String> = inputs().into_iter().map(|(n, _)| n).collect();
    for e in std::fs::read_dir(dir("out")).expect("tests/snapshots/out") {
        let file = e.unwrap().file_name().to_string_lossy().into_owned();
        let stem = DOMAINS.iter().find_map(|d| file.strip_suffix(&format!(".{}.wgsl", d.prefix())));
        match stem {
            Some(stem) if names.iter().any(|n| n == stem) => {}
            _ => panic!("tests/snapshots/out/{file} has no input tests/snapshots/in/*.iso"),
        }
    }
}

#[test]
fn snapshot_shaders_validate() {
    for (name, path) in inputs() {
        let src = std::fs::read_to_string(&path).unwrap();
        let f = Formula::compile(&name, &src).unwrap_or_else(|e| panic!("{e}"));
        for d in DOMAINS {
            let wgsl = crate::field::compiled::eval_shader(&f.ir, d);
            if let Err(e) = crate::validate::validate(&wgsl) {
                panic!("{name} in {d:?}: {e}");
            }
        }
    }
}

//! `isotrace scene gen` and `isotrace scene check`: outputs, exact messages
//! for bad input, exit codes.

use std::path::PathBuf;
use std::process::{Command, Output};

fn isotrace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("NODEVICE_SELECT", "1").output().unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("isotrace-scene-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `stderr` is one line: `start`, then the seconds the command took, `s)`.
fn assert_success_line(stderr: &str, start: &str) {
    let rest = stderr.strip_prefix(start).unwrap_or_else(|| panic!("{stderr:?} does not start with {start:?}"));
    let seconds = rest.strip_suffix(" s)\n").unwrap_or_else(|| panic!("{stderr:?} does not end in ' s)'"));
    assert!(seconds.parse::<f64>().is_ok_and(|t| t >= 0.0), "{stderr:?}");
}

#[test]
fn gen_writes_a_scene_that_check_describes() {
    let f = tmp("pairs.scene.json");
    let p = f.to_str().unwrap();
    let o = isotrace(&["scene", "gen", "sphere-pairs", "--level", "0", "-o", p]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), "");
    assert_success_line(&stderr(&o), &format!("wrote {p} (sphere-pairs level 0, sharp, 24 primitives, 47 nodes, "));
    let o = isotrace(&["scene", "check", p]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], format!("scene:         {p}"));
    assert_eq!(lines[1], "nodes:         47 (24 primitives, 23 operators)");
    assert_eq!(lines[2], "primitives:    sphere 24");
    assert_eq!(lines[3], "operators:     intersection 12, union 11");
    assert_eq!(lines[4], "depth:         13 (nodes on the longest root-to-leaf path)");
    assert_eq!(lines[5], "stack depth:   3 (limit 32)");
    assert!(lines[6].starts_with("bounds:        [-"), "{}", lines[6]);
    assert_eq!(lines[7], "always active: 0 (planes)");
    assert_eq!(lines[8], "lipschitz:     1 (largest product of 6 r_o/(6 r_o - beta) on a root-to-leaf path)");
    // The same seed gives the same file; --count names the same scene.
    let g = tmp("pairs2.scene.json");
    let o = isotrace(&["scene", "gen", "sphere-pairs", "--count", "24", "-o", g.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&f).unwrap(), std::fs::read(&g).unwrap());
}

#[test]
fn check_json_and_probe() {
    let o = isotrace(&["scene", "check", concat!(env!("CARGO_MANIFEST_DIR"), "/examples/blobs.scene.json"), "--json", "--probe", "200"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["primitives"], 8);
    assert_eq!(v["operators"], 7);
    assert_eq!(v["always_active"], 1);
    assert_eq!(v["stack_depth"], 3);
    assert_eq!(v["shapes"]["plane"], 1);
    assert_eq!(v["probe"]["points"], 200);
    assert!(v["probe"]["visits_fast"].as_f64().unwrap() <= v["probe"]["visits_parent"].as_f64().unwrap());
    let o = isotrace(&["scene", "gen", "boxes", "--level", "1", "--smooth", "-o", "-"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let scene = isotrace::scene::format::parse(&stdout(&o)).unwrap();
    assert_eq!(scene.primitive_count(), 64);
}

fn fails(args: &[&str], message: &str) {
    let o = isotrace(args);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
    assert_eq!(stderr(&o), message, "{args:?}");
    assert!(o.stdout.is_empty());
}

#[test]
fn bad_input_is_named_and_exits_1() {
    let f = tmp("bad.scene.json");
    let p = f.to_str().unwrap();
    std::fs::write(&f, "{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{\"type\": \"sphere\", \"radius\": -1}]}").unwrap();
    fails(&["scene", "check", p], &format!("error: {p}: nodes[0].radius: must be > 0\n"));
    std::fs::write(&f, "{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [").unwrap();
    fails(&["scene", "check", p], &format!("error: {p}: EOF while parsing a list at line 1 column 43\n"));
    std::fs::write(&f, b"\xff").unwrap();
    fails(&["scene", "check", p], &format!("error: scene file '{p}' is not UTF-8 text (invalid byte at offset 0)\n"));
    let missing = tmp("missing.scene.json");
    let m = missing.to_str().unwrap();
    fails(&["scene", "check", m], &format!("error: cannot read scene file '{m}': No such file or directory (os error 2)\n"));
    fails(&["scene", "gen", "boxes", "--count", "100", "-o", p], "error: invalid --count 100: boxes scenes have 16, 64, 256, 1024 or 4096 primitives\n");
    // A flag that has no meaning for a scene file is refused, not ignored.
    let out = tmp("never.png");
    fails(
        &["render", "examples/blobs.scene.json", "--field", "compiled", "-o", out.to_str().unwrap()],
        "error: --field compiled and --field tape apply to formulas: a scene file is traced by the scene field; to trace its formula, write it with `isotrace scene formula FILE.scene.json -o FILE.txt` and render `-f FILE.txt`\n",
    );
    assert!(!out.exists());
    fails(&["scene", "gen", "aggregate", "--level", "5", "-o", p], "error: invalid --level 5: the highest level is 4 (aggregate 111110 primitives)\n");
    // Differences nested on the right beyond the stack limit.
    let mut nodes = vec!["{\"type\": \"sphere\", \"radius\": 1}".to_string()];
    for k in 0..32 {
        nodes.push("{\"type\": \"sphere\", \"radius\": 1}".into());
        nodes.push(format!("{{\"type\": \"difference\", \"left\": {}, \"right\": {}}}", 2 * k + 1, 2 * k));
    }
    std::fs::write(&f, format!("{{\"isotrace_scene\": 1, \"root\": 64, \"nodes\": [{}]}}", nodes.join(", "))).unwrap();
    let o = isotrace(&["scene", "check", p]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).starts_with(&format!("error: {p}: nodes[64]: evaluating it needs a stack of 33 values, above the limit of 32")), "{}", stderr(&o));
}

#[test]
fn usage_errors_exit_1() {
    for args in [
        &["scene", "gen", "boxes", "-o", "x.scene.json"][..],
        &["scene", "gen", "boxes", "--level", "1", "--count", "64", "-o", "x.scene.json"],
        &["scene", "gen", "spheres", "--level", "1", "-o", "x.scene.json"],
        &["scene", "gen", "boxes", "--level", "1", "--smooth", "--smooth-inside", "-o", "x.scene.json"],
    ] {
        let o = isotrace(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert!(!std::path::Path::new("x.scene.json").exists());
    }
}

#[test]
fn formula_prints_the_scene_as_distance_forms() {
    let blobs = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/blobs.scene.json");
    let o = isotrace(&["scene", "formula", blobs]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.starts_with("n0 = sphere(1.0);\nn1 = translate(1.2, 0.0, 0.0, rotate(0.0, 0.0, 1.0, 0.4, roundbox(0.6, 0.6, 0.6, 0.15)));\nn2 = compact_union(n0, n1, 0.3, 0.6);\n"), "{text}");
    assert!(text.ends_with("\nn14\n"));
    isotrace::Formula::compile("<scene>", &text).unwrap();
    let scene = isotrace::scene::format::load(std::path::Path::new(blobs)).unwrap();
    // The f64 reference evaluates the printed formula (`eval --cpu`; it reads
    // points as f32, so this one is exact in f32).
    let p = [0.875, 0.1875, -0.3125];
    let (iso, point) = (tmp("blobs-forms.iso"), tmp("blobs-point.txt"));
    std::fs::write(&iso, &text).unwrap();
    std::fs::write(&point, format!("{} {} {}\n", p[0], p[1], p[2])).unwrap();
    let o = isotrace(&["eval", "-f", iso.to_str().unwrap(), "--algebra", "scalar", "--cpu", "--boxes", point.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: f64 = stdout(&o).trim().parse().unwrap();
    assert!((v - scene.eval(p)).abs() < 1e-12);
    let big = tmp("agg2.scene.json");
    let o = isotrace(&["scene", "gen", "aggregate", "--level", "2", "-o", big.to_str().unwrap()]);
    assert!(o.status.success());
    let o = isotrace(&["scene", "formula", big.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains(": the scene's formula would be 65"), "{}", stderr(&o));
    assert!(stderr(&o).ends_with("bytes or more, above the formula language's limit of 65536 bytes\n"), "{}", stderr(&o));
}

#[test]
fn bench_suite_scenes_measures_each_series_sparse_bisect_sync_and_dense() {
    let json = tmp("scenes.json");
    let md = tmp("scenes.md");
    let o = isotrace(&["bench", "--suite", "scenes", "--max-level", "0", "--size", "32", "--repeat", "1", "--json", json.to_str().unwrap(), "--markdown", md.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let rows: Vec<&str> = out.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| scene")).collect();
    // 3 kinds × sharp/smooth × level 0 × sparse/bisect/sync/dense/compiled
    // (level 0 scenes are small enough to compile).
    assert_eq!(rows.len(), 30, "{out}");
    for (k, path) in ["sparse", "bisect", "sync", "dense", "compiled"].iter().enumerate() {
        assert!(rows[k].starts_with(&format!("| aggregate | sharp | 0 | 10 | {path} | ")), "{}", rows[k]);
    }
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 30);
    for r in rows {
        assert_eq!(r["overflow_tiles"], 0, "{r}");
        assert_eq!(r["unconverged"], 0, "{r}");
        assert!(r["gpu_ms"].as_f64().unwrap() > 0.0 && r["evals_per_ray"].as_f64().unwrap() > 0.0 && r["setup_ms"].as_f64().unwrap() > 0.0, "{r}");
    }
    // Sparse, bisect, sync and dense see the same active primitives per tile.
    for k in 1..4 {
        assert_eq!(rows[0]["active_mean"], rows[k]["active_mean"], "{}", rows[k]);
    }
    assert_eq!(rows[4]["path"], "compiled");
    assert!(std::fs::read_to_string(&md).unwrap().starts_with("Machine: llvmpipe"));

    let o = isotrace(&["bench", "--suite", "scenes", "--find-eps"]);
    assert_eq!((o.status.code(), stderr(&o).as_str()), (Some(1), "error: --find-eps does not apply to --suite scenes\n"));
    let o = isotrace(&["bench", "--suite", "scenes", "--max-level", "5"]);
    assert_eq!((o.status.code(), stderr(&o).as_str()), (Some(1), "error: invalid --max-level 5: the generated series go up to level 4\n"));
    let o = isotrace(&["bench", "sphere", "--max-level", "1"]);
    assert_eq!((o.status.code(), stderr(&o).as_str()), (Some(1), "error: --max-level applies to --suite scenes\n"));
}

#[test]
fn lower_writes_the_scene_a_formula_describes_or_points_at_what_is_not_one() {
    let out = tmp("moved.scene.json");
    let p = out.to_str().unwrap();
    let o = isotrace(&["scene", "lower", "union(translate(a, 0, 0, sphere(1)), box(0.5, 0.5, 0.5))", "--param", "a=2", "-o", p]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), "");
    assert_success_line(&stderr(&o), &format!("wrote {p} (2 primitives, 3 nodes, "));
    let scene = isotrace::scene::format::load(&out).unwrap();
    assert!((scene.eval([3.0, 0.0, 0.0])).abs() < 1e-12, "the sphere moved to x = 2");
    let o = isotrace(&["scene", "lower", "@creature", "-o", "-"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(isotrace::scene::format::parse(&stdout(&o)).unwrap().primitive_count(), 22);

    let o = isotrace(&["scene", "lower", "union(sphere(1), translate(x, 0, 0, box(1, 1, 1)))", "-o", p]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "error: not a blobtree: 'x' outside a distance form: the field is not built from primitives alone\n  ┌─ <formula>:1:28\n  │\n1 │ union(sphere(1), translate(x, 0, 0, box(1, 1, 1)))\n  │                            ^ here\n\n"
    );
}

/// Grid files are found next to the scene file; a missing one is named
/// with the scene, the node and the path tried, and no image is written.
#[test]
fn grid_scenes_render_and_missing_grids_are_named() {
    let out = tmp("pebbles.png");
    let o = isotrace(&["render", "examples/pebbles.scene.json", "--size", "48", "--force", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.exists());
    let f = tmp("nogrid.scene.json");
    let p = f.to_str().unwrap();
    std::fs::write(&f, "{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{\"type\": \"grid\", \"file\": \"nothere.npy\", \"spacing\": 0.1, \"origin\": [0, 0, 0]}]}").unwrap();
    let never = tmp("nogrid.png");
    let grid = f.parent().unwrap().join("nothere.npy");
    fails(
        &["render", p, "-o", never.to_str().unwrap()],
        &format!("error: {p}: nodes[0].file: {}: No such file or directory (os error 2)\n", grid.display()),
    );
    assert!(!never.exists());
    fails(&["scene", "formula", "examples/pebbles.scene.json"], "error: examples/pebbles.scene.json: nodes[0] is a grid, which the formula language has no form for\n");
}

/// `eval FILE.scene.json --algebra scalar`: the device's interpreter at
/// points, against the f64 reference (`--cpu`); other algebras refused.
#[test]
fn eval_evaluates_a_scene_at_points() {
    let pts = tmp("scene-points.txt");
    std::fs::write(&pts, "0 0 0\n1.5 0 0\n# a comment\n2.2 0.3 0.1\n0.3 -0.4 0.2\n").unwrap();
    let p = pts.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["eval", "examples/pebbles.scene.json", "--algebra", "scalar", "--boxes", p];
        args.extend_from_slice(extra);
        let o = isotrace(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o).lines().map(|l| l.parse::<f64>().unwrap()).collect::<Vec<f64>>()
    };
    let (device, cpu) = (run(&[]), run(&["--cpu"]));
    assert_eq!(device.len(), 4);
    for (d, c) in device.iter().zip(&cpu) {
        assert!((d - c).abs() < 1e-5, "{d} vs {c}");
    }
    assert!(cpu[0] < 0.0 && cpu[1] > 0.0);
    fails(
        &["eval", "examples/pebbles.scene.json", "--boxes", p],
        "error: a scene has no interval or affine extension: evaluate it at points with --algebra scalar (for examples/pebbles.scene.json)\n",
    );
}

/// `--scene-walk tile` renders a scene with the synchronised walk and
/// says so in the JSON statistics; a compiled formula has no tiles to walk
/// together, so the flag is refused there rather than ignored.
#[test]
fn scene_walk_applies_to_scenes_only() {
    let blobs = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/blobs.scene.json");
    let png = tmp("walk.png");
    let o = isotrace(&["render", blobs, "--size", "64", "--scene-walk", "tile", "-o", png.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(png.exists());
    assert!(stdout(&o).contains("\"scene_walk\":\"tile\""), "{}", stdout(&o));
    let out = tmp("walk-formula.png");
    let o = isotrace(&["render", "sphere(1)", "--method", "sphere", "--scene-walk", "tile", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(stderr(&o), "error: --scene-walk applies to scenes: a .scene.json file, or a formula of distance forms traced with --field scene\n");
    assert!(!out.exists());
    let o = isotrace(&["render", "sphere(1)", "--scene-walk", "tile", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(stderr(&o), "error: --scene-walk applies to --method sphere only\n");
}

#[test]
fn a_scene_file_is_bisected_with_method_bisect() {
    let png = tmp("blobs-bisect.png");
    let p = png.to_str().unwrap();
    let o = isotrace(&["render", "examples/blobs.scene.json", "--method", "bisect", "--size", "64", "--json", "-o", p]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!((v["method"].as_str(), v["algebra"].as_str(), v["field"].as_str()), (Some("bisect"), Some("ia"), Some("scene")), "{v}");
    assert_eq!(v["unresolved"], 0, "{v}");
    assert!(v["hits"].as_u64().unwrap() > 100 && v["active_mean"].as_f64().unwrap() > 0.0, "{v}");
    assert!(std::fs::metadata(&png).unwrap().len() > 0);
    fails(&["render", "examples/blobs.scene.json", "--method", "bisect", "--algebra", "raa", "-o", p], "error: --algebra raa: a scene's nodes are enclosed in interval arithmetic, and formula leaves of degree 4 to 10 in RAA, node by node: give --algebra ia (every node on intervals) or leave it out\n");
    fails(&["render", "examples/blobs.scene.json", "--method", "bisect", "--lipschitz", "2", "-o", p], "error: --lipschitz applies to --method sphere only\n");
    fails(&["render", "examples/blobs.scene.json", "--max-iter", "100", "-o", p], "error: --max-iter applies to --method bisect only; sphere tracing's budget is --max-steps\n");
    // A formula of distance forms through the scene field, bisected in IA.
    let o = isotrace(&["render", "union(sphere(1), translate(1.5, 0, 0, box(0.5, 0.5, 0.5)))", "--field", "scene", "--size", "64", "--json", "-o", p]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!((v["method"].as_str(), v["algebra"].as_str(), v["field"].as_str()), (Some("bisect"), Some("ia"), Some("scene")), "{v}");
    fails(
        &["render", "sphere(1)", "--field", "scene", "--algebra", "raa", "-o", p],
        "error: --algebra raa: a scene's nodes are enclosed in interval arithmetic only (--field scene): give --algebra ia or leave it out\n",
    );
}

#[test]
fn a_scene_with_formula_leaves_is_bisected_and_sphere_tracing_is_refused() {
    let png = tmp("leaves.png");
    let p = png.to_str().unwrap();
    // A leaf without a Lipschitz bound: bisected unless told otherwise.
    let o = isotrace(&["render", "examples/knoll-leaves.scene.json", "--size", "64", "--json", "-o", p]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!((v["method"].as_str(), v["algebra"].as_str(), v["field"].as_str()), (Some("bisect"), Some("ia"), Some("scene")), "{v}");
    fails(
        &["render", "examples/knoll-leaves.scene.json", "--method", "sphere", "-o", p],
        "error: examples/knoll-leaves.scene.json: nodes[0].lipschitz: a formula leaf without a Lipschitz bound cannot be sphere traced: declare one, or render with --method bisect\n",
    );
    let o = isotrace(&["scene", "check", "examples/knoll-leaves.scene.json"]);
    assert!(stdout(&o).contains("primitives:    formula 4, round_box 1\n"), "{}", stdout(&o));
    let bad = tmp("bad-leaf.scene.json");
    std::fs::write(&bad, r#"{"isotrace_scene": 1, "root": 0, "nodes": [{"type": "formula", "formula": "x^2 + y^2 + z^2 - 1 +", "bounds": [-1, 1, -1, 1, -1, 1]}]}"#).unwrap();
    let b = bad.to_str().unwrap();
    fails(&["render", b, "-o", p], &format!("error: {b}: nodes[0].formula: expected an expression, found end of formula at byte 21\n"));
}

/// A polynomial formula leaf's cells are enclosed in RAA unless `--algebra
/// ia` asks for intervals everywhere: the same picture with more
/// evaluations a pixel on intervals.
#[test]
fn algebra_ia_puts_affine_leaves_on_intervals() {
    let evals = |alg: &str| {
        let out = tmp(&format!("leaf-{alg}.png"));
        let o = isotrace(&["render", "examples/tangle-leaf.scene.json", "--box=-3,3", "--size", "96", "--algebra", alg, "--json", "-q", "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["unresolved"], 0, "{v}");
        (v["evals_mean"].as_f64().unwrap(), v["hits"].as_u64().unwrap())
    };
    let auto = evals("auto");
    let ia = evals("ia");
    assert!(auto.1 > 1000 && ia.1.abs_diff(auto.1) * 50 <= auto.1, "hits: {auto:?} in RAA, {ia:?} on intervals");
    assert!(ia.0 > 1.3 * auto.0, "evaluations a pixel: {} in RAA, {} on intervals", auto.0, ia.0);
}

//! `--method sphere` from the command line: outputs, statistics, the
//! heat map, bad input with exact messages, and bench with methods.

use std::path::PathBuf;
use std::process::{Command, Output};

fn isotrace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("NODEVICE_SELECT", "1").output().unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("isotrace-sphere-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn sphere_exr_has_a_steps_channel_and_json_counts_unconverged_pixels() {
    let exr = tmp("jewel.exr");
    // The jewel's header asks for sphere tracing.
    let o = isotrace(&["render", "@jewel", "--size", "32x24", "-o", exr.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["method"], "sphere");
    for key in ["unconverged", "steps_mean", "steps_p99", "steps_max", "omega", "fixpoint", "bound", "sor_fallbacks", "lipschitz_violations", "gpu_ms"] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["unconverged"], 0);
    assert_eq!(v["bound"], "sphere:0,0,-0.15,1.1");
    let (w, h, channels) = isotrace::output::read_exr_channels(&exr).unwrap();
    assert_eq!((w, h), (32, 24));
    let mut names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
    names.sort();
    assert_eq!(names, ["A", "B", "G", "N.X", "N.Y", "N.Z", "R", "Z", "steps"]);
    let steps = &channels.iter().find(|(n, _)| n == "steps").unwrap().1;
    assert!(steps.iter().any(|s| *s > 2.0));
}

#[test]
fn stats_heat_map_and_the_techniques_switched_off() {
    let shade = tmp("city.png");
    let heat = tmp("city-steps.png");
    let o = isotrace(&["render", "@city", "--size", "48x32", "-o", shade.to_str().unwrap(), "--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("method sphere") && e.contains("unconverged 0") && e.contains("steps per pixel: mean"), "{e}");
    assert!(e.contains("techniques: omega 1.2  screen-space on  dynamic eps on  fixpoint 3  bound none"), "{e}");
    let o = isotrace(&[
        "render", "@city", "--size", "48x32", "-o", heat.to_str().unwrap(), "--stats", "--color", "steps:40", "--omega", "1",
        "--no-screen-space", "--fixpoint", "0", "--no-dynamic-eps", "--shadows",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("techniques: omega 1  screen-space off  dynamic eps off  fixpoint 0  bound none"), "{e}");
    assert!(e.contains("--color steps: white = 40 steps"), "{e}");
    assert_ne!(std::fs::read(&shade).unwrap(), std::fs::read(&heat).unwrap());
    // The header's bound can be overridden and switched off.
    let o = isotrace(&["render", "@jewel", "--size", "16", "-o", shade.to_str().unwrap(), "--json", "--no-bound", "--glass"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!((v["bound"].as_str(), v["glass"].as_bool()), (Some("none"), Some(true)));
}

/// A formula that is not a distance bound still terminates; --stats says
/// how many pixels did not converge, or that f changes faster than distance.
#[test]
fn non_distance_formulas_terminate_and_are_reported() {
    let out = tmp("bad.png");
    let o = isotrace(&["render", "0.05*(x^2 + y^2 + z^2 - 1)", "--method", "sphere", "--max-steps", "8", "--size", "32", "-o", out.to_str().unwrap(), "--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    let n: u64 = e.split("unconverged ").nth(1).and_then(|r| r.split_whitespace().next()).and_then(|n| n.parse().ok()).unwrap_or(0);
    assert!(n > 20, "{e}");
    assert!(e.contains(&format!("warning: {n} pixels did not converge within --max-steps 8")), "{e}");
    let o = isotrace(&["render", "x^2 + y^2 + z^2 - 1", "--method", "sphere", "--size", "32", "-o", out.to_str().unwrap(), "--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("changed faster than the distance along the ray") && e.contains("or use --method bisect"), "{e}");
}

#[test]
fn bad_sphere_input_is_reported_before_rendering() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["render", "sphere(1)", "--method", "sphere", "--lipschitz", "0.5", "-o", "/tmp/x.png"],
            "error: invalid --lipschitz 0.5: a Lipschitz bound must be at least 1 (sphere tracing divides the field by it; a smaller value would step further than a distance field allows)\n",
        ),
        (&["render", "sphere(1)", "--method", "sphere", "--omega", "2", "-o", "/tmp/x.png"], "error: invalid --omega 2: the over-relaxation factor must be in [1, 2) (1 switches it off)\n"),
        (&["render", "sphere(1)", "--method", "sphere", "--max-steps", "0", "-o", "/tmp/x.png"], "error: invalid --max-steps 0: it must be between 1 and 16000\n"),
        (&["render", "sphere(1)", "--method", "march", "-o", "/tmp/x.png"], "error: invalid --method 'march': expected 'sphere' or 'bisect'\n"),
        (&["render", "sphere(1)", "--omega", "1.2", "-o", "/tmp/x.png"], "error: --omega applies to --method sphere only\n"),
        (&["render", "@jewel", "--method", "bisect", "--glass", "-o", "/tmp/x.png"], "error: --glass applies to --method sphere only\n"),
        (&["render", "sphere(1)", "--color", "field", "-o", "/tmp/x.png"], "error: --color field applies to --method sphere only\n"),
        (&["render", "@jewel", "--algebra", "ia", "-o", "/tmp/x.png"], "error: --algebra applies to --method bisect only (sphere tracing evaluates the scalar field)\n"),
        (&["render", "@jewel", "--max-iter", "9", "-o", "/tmp/x.png"], "error: --max-iter applies to --method bisect only; sphere tracing's budget is --max-steps\n"),
        (&["render", "@jewel", "--bound", "cone:1", "-o", "/tmp/x.png"], "error: invalid --bound 'cone:1': expected sphere:cx,cy,cz,r or box:x0,x1,y0,y1,z0,z1\n"),
    ];
    for (args, expected) in cases {
        let o = isotrace(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert_eq!(stderr(&o), *expected, "{args:?}");
    }
    // The list of colour modes grows with the bisection kernel's; only its start is fixed here.
    let o = isotrace(&["render", "sphere(1)", "--color", "pink", "-o", "/tmp/x.png"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).starts_with("error: invalid --color 'pink': expected shade"), "{}", stderr(&o));
}

#[test]
fn bench_variant_errors_name_the_flag() {
    // The command line names the flag.
    let cases = [
        (["--method", "march"], "error: invalid --method 'march': expected a comma-separated list of sphere, bisect\n"),
        (["--omega", "2"], "error: invalid --omega '2': expected a comma-separated list of factors in [1, 2)\n"),
        (["--algebra", "fast"], "error: invalid --algebra 'fast': expected a comma-separated list of ia, raa, auto\n"),
    ];
    for (flags, want) in cases {
        let mut args = vec!["bench", "jewel", "--size", "8", "--repeat", "1"];
        if flags[0] == "--omega" {
            args.extend(["--method", "sphere"]);
        }
        args.extend(flags);
        let o = isotrace(&args);
        assert_eq!((o.status.code(), stderr(&o).as_str()), (Some(1), want), "{flags:?}");
    }
}

#[test]
fn bench_compares_methods_and_over_relaxation() {
    let json = tmp("bench.json");
    let o = isotrace(&["bench", "jewel", "--method", "sphere,bisect", "--omega", "1,1.2", "--algebra", "ia", "--size", "24", "--repeat", "1", "--json", json.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("sphere-w1 (ms / steps/px)") && table.contains("sphere-w1.2 (ms / steps/px)") && table.contains("ia (ms / evals/px)"), "{table}");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let r = v["results"].as_array().unwrap();
    assert_eq!(r.len(), 3);
    assert_eq!((r[0]["algebra"].as_str(), r[0]["method"].as_str(), r[0]["omega"].as_f64()), (Some("sphere-w1"), Some("sphere"), Some(1.0)));
    assert_eq!((r[1]["method"].as_str(), r[1]["omega"].as_f64()), (Some("sphere"), Some(1.2)));
    assert_eq!((r[2]["method"].as_str(), r[2]["resolved_algebra"].as_str()), (Some("bisect"), Some("ia")));
    assert!(r[0]["unresolved"].as_u64() == Some(0) && r[0]["evals_mean"].as_f64().unwrap() > 0.0);
    assert_eq!(v["settings"]["methods"], "sphere,bisect");
}

/// A formula that is not a distance bound is not drawn blank without a
/// word: a step that leaves the domain is checked once at its midpoint,
/// the surface found there, and the violation reported without --stats;
/// the advised bound comes from samples inside the domain only.
#[test]
fn non_distance_formula_warns_without_stats() {
    let out = std::env::temp_dir().join(format!("isotrace-ndf-{}.png", std::process::id()));
    let o = isotrace(&["render", "x^2 + y^2 + z^2 - 1", "--method", "sphere", "--size", "64", "-o", out.to_str().unwrap(), "--json", "-q"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.starts_with("warning: on ") && e.contains("the formula is not a distance bound with this Lipschitz bound"), "{e}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["hits"].as_u64().unwrap() > 100, "{v}");
    // |grad f| = 2|p| <= 2 sqrt(12) in the default box: the advice stays below it.
    let seen = v["lipschitz_seen"].as_f64().unwrap();
    assert!(seen > 1.0 && seen <= 7.0, "{seen}");
}

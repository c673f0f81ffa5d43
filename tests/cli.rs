//! The command line end to end: outputs, exit codes and exact messages for
//! bad input.

use std::path::PathBuf;
use std::process::{Command, Output};

fn isotrace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("NODEVICE_SELECT", "1").output().unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("isotrace-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn render_png_and_exr_with_stats_and_json() {
    let png = tmp("s.png");
    let o = isotrace(&["render", "@sphere", "--size", "40x30", "-o", png.to_str().unwrap(), "--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("inclusion evaluations per pixel"));
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (40, 30));

    let exr = tmp("s.exr");
    let o = isotrace(&["render", "x^2 + y^2 + z^2 - 1", "--box=-1.5,1.5", "--size", "24", "-o", exr.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["width"], 24);
    assert!(v["hits"].as_u64().unwrap() > 0);
    assert!(v["gpu_ms"].as_f64().unwrap() > 0.0);
    // The tile pass is part of the GPU time.
    assert!(v["tile_ms"].as_f64().unwrap() > 0.0 && v["tile_ms"].as_f64().unwrap() < v["gpu_ms"].as_f64().unwrap());
    for key in ["wall_ms", "unresolved", "evals_mean", "evals_p99", "evals_max", "algebra", "eps", "d_max"] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    let (w, h, channels) = isotrace::output::read_exr_channels(&exr).unwrap();
    assert_eq!((w, h), (24, 24));
    let mut names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
    names.sort();
    assert_eq!(names, ["A", "B", "G", "N.X", "N.Y", "N.Z", "R", "Z", "evals"]);
    let z = &channels.iter().find(|(n, _)| n == "Z").unwrap().1;
    assert!(z.iter().any(|d| d.is_infinite()) && z.iter().any(|d| d.is_finite()));
}

#[test]
fn animation_writes_one_file_per_frame() {
    let dir = tmp("frames");
    std::fs::create_dir_all(&dir).unwrap();
    let pat = dir.join("f_%03d.png");
    let o = isotrace(&["render", "@water", "--size", "16", "--frames", "3", "--t0", "0", "--t1", "2", "-o", pat.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 0..3 {
        assert!(dir.join(format!("f_{k:03}.png")).exists());
    }
    // The frames differ: time moves the waves.
    let a = std::fs::read(dir.join("f_000.png")).unwrap();
    let b = std::fs::read(dir.join("f_002.png")).unwrap();
    assert_ne!(a, b);
}

#[test]
fn bad_render_input_is_reported_before_rendering() {
    let cases: &[(&[&str], &str)] = &[
        (&["render", "x", "-o", "/tmp/x.jpg"], "error: unknown output format '/tmp/x.jpg': the file name must end in .png or .exr\n"),
        (&["render", "x", "-o", "/nonexistent-dir/x.png"], "error: cannot write '/nonexistent-dir/x.png': No such file or directory (os error 2)\n"),
        (&["render", "x", "--size", "0", "-o", "/tmp/x.png"], "error: invalid --size '0': each side must be between 1 and 16384\n"),
        (&["render", "x", "--size", "20000x10", "-o", "/tmp/x.png"], "error: invalid --size '20000x10': each side must be between 1 and 16384\n"),
        (&["render", "x", "--size", "big", "-o", "/tmp/x.png"], "error: invalid --size 'big': expected WxH like 1024x768, or N for a square\n"),
        (&["render", "x", "--box=1,0", "-o", "/tmp/x.png"], "error: invalid --box '1,0': empty x range: 1 is not below 0\n"),
        (&["render", "x", "--eps", "-1", "-o", "/tmp/x.png"], "error: invalid --eps '-1': must be greater than 0\n"),
        (&["render", "x", "--up", "1,1,0", "--eye", "3,3,0", "--target", "0,0,0", "-o", "/tmp/x.png"], "error: the up vector is parallel to the viewing direction: give another --up\n"),
        (&["render", "x", "--clip", "ball:2", "-o", "/tmp/x.png"], "error: invalid --clip 'ball:2': expected sphere:R with a radius R > 0\n"),
        (&["render", "@tangel", "-o", "/tmp/x.png"], "error: unknown surface 'tangel'; did you mean 'tangle'?\n"),
        (&["render", "x", "--frames", "2", "-o", "/tmp/x.png"], "error: with --frames, -o needs a frame-number pattern like frames/f_%04d.png, got '/tmp/x.png'\n"),
    ];
    for (args, expected) in cases {
        let o = isotrace(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert_eq!(stderr(&o), *expected, "{args:?}");
    }
}

#[test]
fn missing_parameter_points_at_the_formula() {
    let o = isotrace(&["render", "x^2 + y^2 + z^2 - r^2", "-o", "/tmp/x.png"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "error: missing value for parameter 'r'\n  ┌─ <formula>:1:19\n  │\n1 │ x^2 + y^2 + z^2 - r^2\n  │                   ^ free name, so a parameter\n  │\n  = give it a value on the command line: --param r=1.0\n\n"
    );
}

#[test]
fn no_gpu_adapter_exits_with_2_and_names_the_fix() {
    // A backend that this build does not contain finds no adapter.
    let o = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(["render", "x", "-o", "/tmp/x.png"])
        .env("WGPU_BACKEND", "metal")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("apt-get install -y mesa-vulkan-drivers"), "{}", stderr(&o));
    assert!(!std::path::Path::new("/tmp/x.png").exists() || true);
}

#[test]
fn failed_render_leaves_no_partial_file() {
    let out = tmp("never.png");
    let _ = std::fs::remove_file(&out);
    let o = isotrace(&["render", "x^2 + q", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(!out.exists());
    // This render's temporaries only: other tests of this binary write
    // files into the same directory at the same time.
    let leftovers: Vec<_> = std::fs::read_dir(out.parent().unwrap())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with(".never.png.") && e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn eval_on_the_device_and_on_the_cpu() {
    let run = |extra: &[&str], input: &str| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_isotrace"));
        c.args(["eval", "x^2 + y^2 + z^2 - 1"]).args(extra).stdin(std::process::Stdio::piped()).stdout(std::process::Stdio::piped()).stderr(std::process::Stdio::piped());
        let mut child = c.spawn().unwrap();
        use std::io::Write;
        // The child may exit before it reads all of its input (a refused
        // line ends it): a broken pipe here is not the test's failure, its
        // exit status and output below are what is checked.
        let _ = child.stdin.take().unwrap().write_all(input.as_bytes());
        child.wait_with_output().unwrap()
    };
    let o = run(&["--algebra", "ia"], "-1 1 -1 1 -1 1\n# a comment\n\n0.5 0.6 0 0.1 0 0.1\n");
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout), "-1 2\n-0.75 -0.6200000047683716\n");
    let o = run(&["--algebra", "ia", "--cpu"], "-1 1 -1 1 -1 1\n");
    assert_eq!(String::from_utf8_lossy(&o.stdout), "-1 2\n");
    let o = run(&["--algebra", "scalar"], "1 1 1\n");
    assert_eq!(String::from_utf8_lossy(&o.stdout), "2\n");
    let o = run(&["--algebra", "ia"], "1 2 3\n");
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(stderr(&o), "error: <stdin>:1: expected 6 or 8 numbers: x0 x1 y0 y1 z0 z1 [t0 t1], found 3 in '1 2 3'\n");
    let o = run(&["--algebra", "ia"], "1 0 0 1 0 1\n");
    assert_eq!(stderr(&o), "error: <stdin>:1: each range needs lo <= hi in '1 0 0 1 0 1'\n");
    // The tape interpreter gives the generated evaluator's enclosures, in
    // every domain; a scene and --cpu take no --field.
    for alg in ["ia", "raa"] {
        let boxes = "-1 1 -1 1 -1 1\n0.5 0.6 0 0.1 0 0.1\n";
        let (c, t) = (run(&["--algebra", alg], boxes), run(&["--algebra", alg, "--field", "tape"], boxes));
        assert!(t.status.success(), "{}", stderr(&t));
        assert_eq!(String::from_utf8_lossy(&t.stdout), String::from_utf8_lossy(&c.stdout), "{alg}");
    }
    let o = run(&["--algebra", "scalar", "--field", "tape"], "1 1 1\n");
    assert_eq!(String::from_utf8_lossy(&o.stdout), "2\n");
    let o = run(&["--field", "scene"], "1 1 1\n");
    assert_eq!((o.status.code(), stderr(&o).as_str()), (Some(1), "error: --field scene applies to render: a scene's enclosures are evaluated inside its render kernel, on its tiles' pruned trees\n"));
    let o = run(&["--field", "tape", "--cpu"], "-1 1 -1 1 -1 1\n");
    assert_eq!((o.status.code(), stderr(&o).as_str()), (Some(1), "error: --field chooses the device's evaluator; --cpu evaluates the f64 reference\n"));
}

#[test]
fn sqrt_of_negative_box_is_empty() {
    let mut c = Command::new(env!("CARGO_BIN_EXE_isotrace"));
    c.args(["eval", "sqrt(x) + y", "--algebra", "raa"]).stdin(std::process::Stdio::piped()).stdout(std::process::Stdio::piped());
    let mut child = c.spawn().unwrap();
    use std::io::Write;
    child.stdin.take().unwrap().write_all(b"-3 -1 0 0 0 0\n1 4 0 0 0 0\n").unwrap();
    let o = child.wait_with_output().unwrap();
    // sqrt is padded outward by a few ulp (WGSL's sqrt is not exactly rounded).
    assert_eq!(String::from_utf8_lossy(&o.stdout), "empty\n0.9999997615814209 2.0000007152557373\n");
}

#[test]
fn list_and_bench() {
    let o = isotrace(&["list"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.lines().count() >= 16 && text.contains("barth-sextic"));
    let dir = tmp("bench");
    let json = tmp("bench.json");
    let o = isotrace(&["bench", "sphere", "steiner", "--size", "24", "--repeat", "1", "--algebra", "ia,raa", "--out", dir.to_str().unwrap(), "--json", json.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.starts_with("surface"), "{table}");
    assert_eq!(table.lines().count(), 3);
    assert!(dir.join("contact-sheet.png").exists() && dir.join("steiner_raa.png").exists());
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(v["results"].as_array().unwrap().len(), 4);
    assert!(v["device"]["name"].as_str().unwrap().len() > 0);
    assert!(v["date"].as_str().unwrap().starts_with("20"));
    // Sharding: job 1 of 4 = (sphere, raa) only.
    let o = isotrace(&["bench", "sphere", "steiner", "--size", "16", "--repeat", "1", "--algebra", "ia,raa", "--shard", "1/4"]);
    let t = String::from_utf8_lossy(&o.stdout);
    assert!(t.contains("sphere") && !t.contains("steiner"), "{t}");
}

/// `bench --field` runs every job on that field source, names it in the
/// table and per job in the JSON, and fails a job the source cannot render
/// with the reason `render --field` gives.
#[test]
fn bench_field_chooses_the_source_per_job() {
    let json = tmp("bench-field.json");
    let o = isotrace(&["bench", "tangle", "--size", "16", "--repeat", "1", "--algebra", "ia", "--field", "tape", "--json", json.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.lines().nth(1).unwrap().contains(" tape "), "{table}");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!((v["settings"]["field"].as_str(), v["results"][0]["field"].as_str()), (Some("tape"), Some("tape")));
    // auto: @city (a formula of 36 bounded distance-form primitives) is
    // sphere traced through the scene; a compiled job is not marked.
    let o = isotrace(&["bench", "city", "sphere", "--method", "sphere", "--size", "16", "--repeat", "1", "--field", "auto", "--json", json.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let fields: Vec<&str> = v["results"].as_array().unwrap().iter().map(|r| r["field"].as_str().unwrap()).collect();
    assert_eq!(fields, ["scene", "compiled"]);
    // Bisected too, in IA; with --algebra raa @city stays compiled.
    for (algebra, want) in [("ia", "scene"), ("raa", "compiled")] {
        let o = isotrace(&["bench", "city", "--method", "bisect", "--algebra", algebra, "--size", "16", "--repeat", "1", "--field", "auto", "--json", json.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        assert_eq!(v["results"][0]["field"].as_str(), Some(want), "{algebra}");
    }
    // A source that cannot render the surface fails that job, named.
    let o = isotrace(&["bench", "tangle", "--method", "sphere", "--size", "16", "--repeat", "1", "--field", "scene"]);
    assert_eq!(o.status.code(), Some(1));
    let t = String::from_utf8_lossy(&o.stdout);
    assert!(t.contains("FAILED tangle sphere: --field scene: not a blobtree: 'x' outside a distance form"), "{t}");
}

/// A `.iso` header's `field` is render's default field source; the flag
/// overrides it; --json and --stats name the source used; a bad value is
/// named with its line.
#[test]
fn header_field_is_the_default_source() {
    let iso = tmp("field-tape.iso");
    std::fs::write(&iso, "#@ name: ball\n#@ box: -2,2,-2,2,-2,2\n#@ field: tape\nx^2 + y^2 + z^2 - 1\n").unwrap();
    let out = tmp("field-tape.png");
    let field_of = |extra: &[&str]| {
        let mut args = vec!["render", iso.to_str().unwrap(), "--size", "16", "--json", "-o", out.to_str().unwrap()];
        args.extend(extra);
        let o = isotrace(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        v["field"].as_str().unwrap().to_string()
    };
    assert_eq!(field_of(&[]), "tape");
    assert_eq!(field_of(&["--field", "compiled"]), "compiled");
    let o = isotrace(&["render", iso.to_str().unwrap(), "--size", "16", "--stats", "-q", "-o", out.to_str().unwrap()]);
    assert!(stderr(&o).starts_with("size 16x16  algebra ia  field tape  eps "), "{}", stderr(&o));
    // A ball has nothing to shorten per tile: no "tape:" line (it once said
    // "0 of 0 tiles … the value program's 0 instructions"); a CSG formula has.
    assert!(!stderr(&o).contains("\ntape: "), "{}", stderr(&o));
    let o = isotrace(&["render", "max(x^2 + y^2 + z^2 - 1, -z)", "--field", "tape", "--size", "16", "--stats", "--json", "-o", out.to_str().unwrap()]);
    let e = stderr(&o);
    let line = e.lines().find(|l| l.starts_with("tape: ")).unwrap_or_else(|| panic!("{e}"));
    let words: Vec<&str> = line.split(' ').collect();
    let (shortened, tiles): (u32, u32) = (words[1].parse().unwrap(), words[3].parse().unwrap());
    assert!(tiles > 0 && shortened == tiles && line.ends_with("of the value program's 8 instructions"), "{line}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["tape_tiles"].as_u64(), Some(u64::from(tiles)), "{v}");
    std::fs::write(&iso, "#@ field: tapes\nx\n").unwrap();
    let o = isotrace(&["check", iso.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(stderr(&o), format!("error: {}:1: bad field value 'tapes': expected 'compiled', 'tape', 'scene' or 'auto'\n", iso.display()));
}

/// `check` says which runs of terms the compiled field writes as loops.
#[test]
fn check_names_the_runs_compiled_as_loops() {
    let sum = (0..40).map(|i| format!("{:.3}*sin({:.3}*x + 0.3)", 0.5 + 0.01 * f64::from(i), 1.0 + 0.02 * f64::from(i))).collect::<Vec<_>>().join(" + ");
    let o = isotrace(&["check", &sum]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    let line = text.lines().find(|l| l.starts_with("loops:")).unwrap_or_else(|| panic!("{text}"));
    assert!(line.starts_with("loops:      1 run of same-shaped terms compiled as loops (36 terms; "), "{line}");
    let o = isotrace(&["check", &sum, "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!((v["loops"]["runs"].as_u64(), v["loops"]["terms"].as_u64()), (Some(1), Some(36)), "{v}");
    let o = isotrace(&["check", "x^2 + y^2 + z^2 - 1"]);
    assert!(String::from_utf8(o.stdout).unwrap().contains("\nloops:      none\n"));
    // A polynomial of 1,330 monomials (x^a y^b z^c, every power below 11 but the constant's) is one Horner loop.
    let poly = (1..1331).map(|i| format!("0.01*x^{}*y^{}*z^{}", i % 11, i / 11 % 11, i / 121)).collect::<Vec<_>>().join(" + ");
    let o = isotrace(&["check", &format!("sin(x) + {poly}")]);
    assert!(String::from_utf8(o.stdout).unwrap().contains("\npolynomial: 1330 monomials compiled as one Horner loop\n"));
    let o = isotrace(&["check", &poly, "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["loops"]["polynomials"], serde_json::json!([1330]), "{v}");
}

#[test]
fn bench_unknown_suite_lists_the_suites() {
    let o = isotrace(&["bench", "--suite", "knol"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(stderr(&o), "error: unknown --suite 'knol': expected knoll, sdf or all\n");
}

#[test]
fn bench_failure_mid_batch_goes_on_and_exits_nonzero() {
    let bad = tmp("bad.iso");
    std::fs::write(&bad, "#@ name: needs-param\nx^2 + y^2 + z^2 - r^2\n").unwrap();
    let o = isotrace(&["bench", bad.to_str().unwrap(), "sphere", "--size", "16", "--repeat", "1", "--algebra", "ia"]);
    assert_eq!(o.status.code(), Some(1));
    let t = String::from_utf8_lossy(&o.stdout);
    assert!(t.contains("needs-param") && t.contains("FAILED") && t.contains("sphere"), "{t}");
}

#[test]
fn bench_find_eps_reports_the_coarsest_matching_eps() {
    let json = tmp("eps.json");
    let o = isotrace(&["bench", "sphere", "--size", "64", "--repeat", "1", "--algebra", "ia", "--find-eps", "--json", json.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let l = &v["results"][0]["lowest_eps"];
    let k = l["exponent"].as_i64().expect("an exponent");
    assert!((-13..=-5).contains(&k), "{l}");
    assert!(l["differing"].as_f64().unwrap() <= 0.005);
}

/// Values the library rejects name the flag that gave them (the library's
/// typed SettingsError, mapped to flags by the CLI only), and a frame with
/// unresolved pixels warns without --stats.
#[test]
fn settings_errors_name_the_flag() {
    let out = tmp("settings.png");
    let o = out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--fov", "0"], "error: invalid --fov 0: the field of view must be between 0 and 180 degrees\n"),
        (&["--fov", "nan"], "error: invalid --fov NaN: the field of view must be between 0 and 180 degrees\n"),
        (&["--t", "nan"], "error: invalid --t NaN: it must be a finite number\n"),
        (&["--t0", "inf", "--frames", "2"], "error: invalid --t0 inf: it must be a finite number\n"),
        (&["--eye", "1e39,0,0"], "error: invalid --eye 1e39,0e0,0e0: coordinates must be finite numbers below 1e30\n"),
        (&["--eps", "2^1000"], "error: invalid --eps 1.0715086071862673e301: it must be below the box diagonal (5.1962): a cell that wide holds the whole domain\n"),
        (&["--eye", "0,0,0", "--target", "0,0,0"], "error: the eye and the target are the same point: give another --eye or --target\n"),
    ];
    for (extra, want) in cases {
        let mut args = vec!["render", "@sphere", "--size", "16", "-o", o];
        args.extend_from_slice(extra);
        let r = isotrace(&args);
        assert_eq!((r.status.code(), stderr(&r).as_str()), (Some(1), *want), "{extra:?}");
    }
    let r = isotrace(&["render", "@tangle", "--size", "24", "-o", o, "--max-iter", "1"]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(stderr(&r).contains("pixels exhausted the iteration budget (--max-iter 1)"), "{}", stderr(&r));
    // A tape field names its work limit and the way out.
    let r = isotrace(&["render", "@tangle", "--field", "tape", "--size", "24", "-o", o, "--max-iter", "1"]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(
        stderr(&r).contains("or the tape interpreter's work limit (5500 loop iterations a pixel, or 40000 per SIMD bundle on a device with subgroups, which lavapipe's loop cap imposes; --field compiled has none)"),
        "{}",
        stderr(&r)
    );
}

#[test]
fn wgsl_prints_the_tape_kernel_which_does_not_depend_on_the_formula() {
    let out = |args: &[&str]| {
        let o = isotrace(args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        String::from_utf8(o.stdout).unwrap()
    };
    let a = out(&["wgsl", "x^2 + y^2 + z^2 - 1", "--field", "tape", "--algebra", "ia"]);
    assert!(a.contains("fn tape_run_ia") && a.contains("fn tiles"), "the IA bisection kernel of a tape");
    assert_eq!(a, out(&["wgsl", "x^2 + 2*y^2 + z^2 - 1.5", "--field", "tape", "--algebra", "ia"]));
    assert_ne!(a, out(&["wgsl", "x^2 + y^2 + z^2 - 1", "--algebra", "ia"]), "the compiled kernel is another");
    assert!(out(&["wgsl", "sin(x) - z", "--field", "tape", "--kernel", "eval", "--algebra", "raa"]).contains("if (code == TAPE_SIN) {"));
    let o = isotrace(&["wgsl", "x^2 + y^2 + z^2 - 1", "--field", "tape", "--algebra", "scalar"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("--algebra scalar has no render kernel"));
}

/// `auto` counts the frames a render makes: a sum of products just past the
/// IA line takes the tape for one frame and stays compiled for an
/// animation, whose later frames the tape would make 10-25 times slower.
/// (Every other term's second factor is written `z − (−b)`, so no run of
/// terms is long enough to become a loop: `field::compiled::term_loops`.)
#[test]
fn auto_takes_the_frames_of_an_animation_into_account() {
    let term = |i: i32| {
        let (a, b) = (0.5 + f64::from(i) * 0.001, f64::from(i) * 0.002 + 0.001);
        if i % 2 == 0 { format!("({a:.3}*x-y)*(z+{b:.3})") } else { format!("({a:.3}*x-y)*(z-(-{b:.3}))") }
    };
    let terms: Vec<String> = (0..250).map(term).collect();
    let formula = format!("x^2+y^2+z^2-1+1e-4*({})", terms.join("+"));
    let field = |extra: &[&str], out: &str| {
        let out = tmp(out);
        let mut args = vec!["render", formula.as_str(), "--size", "8", "--stats", "-o", out.to_str().unwrap()];
        args.extend(extra);
        let o = isotrace(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let e = stderr(&o);
        e.split("  field ").nth(1).and_then(|r| r.split(' ').next()).unwrap_or_else(|| panic!("{e}")).to_string()
    };
    assert_eq!(field(&[], "one.png"), "tape");
    assert_eq!(field(&["--frames", "3"], "anim_%04d.png"), "compiled");
}

/// The driver's optimisation (`--shader-opt`, Mesa's CPU driver): auto skips
/// LLVM's passes for a job of up to one 1024² frame's pixels and runs them
/// past it; the flag decides over auto, GALLIVM_PERF does without the flag,
/// and the picture is the same bit for bit either way.
#[test]
fn shader_opt_follows_the_job_the_flag_and_the_environment_and_keeps_the_picture() {
    let run = |extra: &[&str], env: Option<&str>, out: &str| -> (Option<String>, Vec<u8>) {
        let out = tmp(out);
        let mut c = Command::new(env!("CARGO_BIN_EXE_isotrace"));
        c.args(["render", "@sphere", "--json", "-o", out.to_str().unwrap()]).args(extra);
        c.env("NODEVICE_SELECT", "1").env_remove("GALLIVM_PERF");
        if let Some(v) = env {
            c.env("GALLIVM_PERF", v);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (v["device"]["shader_opt"].as_str().map(String::from), std::fs::read(&out).unwrap())
    };
    let (auto_small, a) = run(&["--size", "64"], None, "opt_auto.png");
    if auto_small.is_none() {
        eprintln!("skipped: the device is not one of Mesa's CPU drivers");
        return;
    }
    assert_eq!(auto_small.as_deref(), Some("none"));
    let (full, b) = run(&["--size", "64", "--shader-opt", "full"], None, "opt_full.png");
    assert_eq!(full.as_deref(), Some("full"));
    assert!(a == b, "the passes changed the picture");
    assert_eq!(run(&["--size", "1100x1000"], None, "opt_big.png").0.as_deref(), Some("full"));
    assert_eq!(run(&["--size", "1100x1000"], Some("nopt"), "opt_env.png").0.as_deref(), Some("none"));
    assert_eq!(run(&["--size", "64", "--shader-opt", "full"], Some("nopt"), "opt_flag.png").0.as_deref(), Some("full"));
    assert_eq!(run(&["--size", "1100x1000", "--shader-opt", "none"], None, "opt_none.png").0.as_deref(), Some("none"));
}

/// `eval --shader-opt`: the device's enclosures are the same with and
/// without the driver's passes; with `--cpu` the flag is refused.
#[test]
fn eval_gives_the_same_enclosures_with_either_shader_opt_and_refuses_it_with_cpu() {
    let boxes = tmp("opt_boxes.txt");
    std::fs::write(&boxes, "0 1 0 1 0 1\n-0.5 0.25 1 2 -3 -1\n0.1 0.1 0.2 0.2 0.3 0.3\n").unwrap();
    let run = |opt: &str, cpu: bool| {
        let mut args = vec!["eval", "@tangle", "--algebra", "raa", "--boxes", boxes.to_str().unwrap(), "--shader-opt", opt];
        if cpu {
            args.push("--cpu");
        }
        isotrace(&args)
    };
    let (none, full) = (run("none", false), run("full", false));
    assert!(none.status.success() && full.status.success(), "{}{}", stderr(&none), stderr(&full));
    assert_eq!(String::from_utf8_lossy(&none.stdout).lines().count(), 3);
    assert_eq!(none.stdout, full.stdout);
    let cpu = run("none", true);
    assert_eq!(cpu.status.code(), Some(1));
    assert_eq!(stderr(&cpu), "error: --shader-opt applies to the device's evaluator; --cpu evaluates the f64 reference\n");
}

/// A formula of thousands of tiny repeated terms compiles as loops
/// (`field::compiled::term_loops`); hard pixels past the traversal's budget or the
/// loops' work limit are reported with both named, and the run says it used
/// the compiled field. (Terms in t at t = 0: terms `c·x` would be collected
/// into one. The loops' work limit alone no longer leaves pixels here: the
/// per-pixel pass resumes them in its next rounds; a small `--max-iter`
/// does.)
#[test]
fn pixels_past_the_loops_work_limit_are_named_in_the_warning() {
    let terms: Vec<String> = (1..=4600).map(|i| format!("{:.9}*t", f64::from(i) * 1e-9)).collect();
    let file = tmp("loops.txt");
    std::fs::write(&file, format!("x^4-5*x^2+y^4-5*y^2+z^4-5*z^2+11.8+({})", terms.join("+"))).unwrap();
    let out = tmp("loops.png");
    // Counted per invocation (as without subgroups), some pixels stop.
    let args = ["render", "-f", file.to_str().unwrap(), "--box=-3,3", "--size", "48", "--algebra", "ia", "--max-iter", "16", "--stats", "-o", out.to_str().unwrap()];
    let o = Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("NODEVICE_SELECT", "1").env("ISOTRACE_NO_SUBGROUPS", "1").output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("field compiled"), "{e}");
    assert!(
        e.contains(
            " pixels exhausted the iteration budget (--max-iter 16) or the work limit of the formula's loops over its repeated terms \
             (5500 loop iterations a pixel, or 40000 per SIMD bundle on a device with subgroups, which lavapipe's loop cap imposes) \
             and are drawn as magenta stripes"
        ),
        "{e}"
    );
}

/// The one line on stderr a command prints when it succeeds, without its
/// seconds: `wrote P (64×48, ` of `wrote P (64×48, 0.21 s)`.
fn success_line(o: &Output) -> String {
    let err = stderr(o);
    let line = err.strip_suffix(" s)\n").unwrap_or_else(|| panic!("one success line: {err:?}"));
    let (start, seconds) = line.rsplit_once(", ").unwrap_or_else(|| panic!("seconds in {err:?}"));
    assert!(seconds.parse::<f64>().is_ok_and(|t| t >= 0.0) && !start.contains('\n'), "{err:?}");
    start.to_string()
}

#[test]
fn success_is_one_line_on_stderr_and_quiet_silences_it() {
    let png = tmp("said.png");
    let p = png.to_str().unwrap();
    let o = isotrace(&["render", "@sphere", "--size", "64x48", "-o", p]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!((o.stdout.as_slice(), success_line(&o)), (&b""[..], format!("wrote {p} (64×48")));
    for quiet in ["--quiet", "-q"] {
        let o = isotrace(&["render", "@sphere", "--size", "64x48", "-o", p, quiet]);
        assert!(o.status.success() && o.stdout.is_empty() && o.stderr.is_empty(), "{quiet}: {}", stderr(&o));
    }
    let wgsl = tmp("said.wgsl");
    let o = isotrace(&["-q", "wgsl", "@sphere", "-o", wgsl.to_str().unwrap()]);
    assert!(o.status.success() && o.stderr.is_empty(), "{}", stderr(&o));
    let o = isotrace(&["wgsl", "@sphere", "-o", wgsl.to_str().unwrap()]);
    let lines = std::fs::read_to_string(&wgsl).unwrap().lines().count();
    assert_eq!(success_line(&o), format!("wrote {} ({lines} lines of WGSL", wgsl.display()));
    // Image data on stdout: the line names it, on stderr.
    let o = isotrace(&["render", "@sphere", "--size", "16", "-o", "-"]);
    assert!(o.stdout.starts_with(b"\x89PNG"), "{}", stderr(&o));
    assert_eq!(success_line(&o), "wrote standard output (16×16");
    let dir = tmp("said-frames");
    std::fs::create_dir_all(&dir).unwrap();
    let pat = dir.join("f_%d.png");
    let o = isotrace(&["render", "@water", "--size", "16", "--frames", "2", "-o", pat.to_str().unwrap()]);
    assert_eq!(success_line(&o), "wrote 2 frames (16×16");
    // Warnings still print under --quiet.
    let o = isotrace(&["render", "x^2+y^2-z^2-0.1", "--method", "sphere", "--size", "32", "-o", p, "-q"]);
    assert!(o.status.success() && stderr(&o).starts_with("warning: "), "{}", stderr(&o));
}

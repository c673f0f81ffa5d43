//! `--inline FILE.wgsl`: declarations found, missing versions reported.

use isotrace::inline::parse_inline;

#[test]
fn finds_functions_and_hooks() {
    let text = std::fs::read_to_string("examples/inline/bumps.wgsl").unwrap();
    let lib = parse_inline("bumps.wgsl", &text).unwrap();
    assert_eq!(lib.functions, vec![("bump".to_string(), 1)]);
    assert!(lib.shade && !lib.reject && !lib.hit);
    let two = "fn s_g(a: f32, b: array<f32, 2>,) -> f32 { return a; }\nfn ia_g(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> { return a; }\n// fn ra_h(x: f32) -> f32\nfn ra_g(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> { return a; }\nfn hook_reject(r: vec2<f32>) -> bool { return true; }";
    let lib = parse_inline("g.wgsl", two).unwrap();
    assert_eq!(lib.functions, vec![("g".to_string(), 2)]);
    assert!(lib.reject);
}

#[test]
fn missing_or_mismatched_versions_point_into_the_file() {
    let e = parse_inline("f.wgsl", "fn s_f(a: f32) -> f32 { return a; }\nfn ia_f(a: vec2<f32>) -> vec2<f32> { return a; }\n").unwrap_err();
    assert_eq!(
        e.render("f.wgsl", "fn s_f(a: f32) -> f32 { return a; }\nfn ia_f(a: vec2<f32>) -> vec2<f32> { return a; }\n", false),
        "error: inline function 'f' has no ra_ version\n  ┌─ f.wgsl:1:4\n  │\n1 │ fn s_f(a: f32) -> f32 { return a; }\n  │    ^^^ declared here\n  │\n  = a function callable from the formula needs s_f (f32), ia_f (vec2<f32>) and ra_f (vec3<f32>) with the same arguments\n\n"
    );
    let src = "fn s_f(a: f32) -> f32 { return a; }\nfn ia_f(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> { return a; }\nfn ra_f(a: vec3<f32>) -> vec3<f32> { return a; }\n";
    let e = parse_inline("f.wgsl", src).unwrap_err();
    assert_eq!(e.message, "'ia_f' takes 2 arguments but 's_f' takes 1");
}

fn isotrace(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("NODEVICE_SELECT", "1").output().unwrap()
}

#[test]
fn inline_functions_render_and_evaluate_on_the_device() {
    let out = std::env::temp_dir().join(format!("isotrace-inline-{}.png", std::process::id()));
    let o = isotrace(&["render", "x^2 + y^2 + z^2 - 1 + 0.3*bump(4*z)", "--inline", "examples/inline/bumps.wgsl", "--size", "24", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_isotrace"));
    c.args(["eval", "bump(x)", "--inline", "examples/inline/bumps.wgsl", "--algebra", "ia"]).stdin(std::process::Stdio::piped()).stdout(std::process::Stdio::piped());
    let mut child = c.spawn().unwrap();
    use std::io::Write;
    child.stdin.take().unwrap().write_all(b"0 2 0 0 0 0\n").unwrap();
    let o = child.wait_with_output().unwrap();
    let v: Vec<f64> = String::from_utf8_lossy(&o.stdout).split_whitespace().map(|w| w.parse().unwrap()).collect();
    // bump over [0, 2] is [0, 1/2] (maximum at 1), padded by 1e-6.
    assert!(v[0] <= 0.0 && v[0] > -1e-5 && v[1] >= 0.5 && v[1] < 0.5 + 1e-5, "{v:?}");
}

#[test]
fn errors_in_inline_wgsl_point_into_the_users_file() {
    let bad = std::env::temp_dir().join(format!("isotrace-bad-{}.wgsl", std::process::id()));
    std::fs::write(&bad, "fn s_q(a: f32) -> f32 { return a +; }\nfn ia_q(a: vec2<f32>) -> vec2<f32> { return a; }\nfn ra_q(a: vec3<f32>) -> vec3<f32> { return a; }\n").unwrap();
    let o = isotrace(&["render", "q(x) + y", "--inline", bad.to_str().unwrap(), "-o", "/tmp/never.png"]);
    assert_eq!(o.status.code(), Some(1));
    let p = bad.display().to_string();
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!("error: in inline WGSL: expected expression, found \";\"\n  ┌─ {p}:1:35\n  │\n1 │ fn s_q(a: f32) -> f32 {{ return a +; }}\n  │                                   ^ expected expression\n\n")
    );
    // Wrong number of arguments to a user function is a formula error.
    let o = isotrace(&["check", "bump(x, y)", "--inline", "examples/inline/bumps.wgsl"]);
    assert!(String::from_utf8_lossy(&o.stderr).starts_with("error: wrong number of arguments to 'bump': expected 1, found 2"), "{}", String::from_utf8_lossy(&o.stderr));
    // The flags are refused before any box is read (here: a line that is not one).
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_isotrace"));
    c.args(["eval", "bump(x)", "--inline", "examples/inline/bumps.wgsl", "--cpu"]).env("NODEVICE_SELECT", "1");
    c.stdin(std::process::Stdio::piped()).stdout(std::process::Stdio::piped()).stderr(std::process::Stdio::piped());
    let mut child = c.spawn().unwrap();
    use std::io::Write;
    let _ = child.stdin.take().unwrap().write_all(b"not a box\n");
    let o = child.wait_with_output().unwrap();
    assert_eq!(String::from_utf8_lossy(&o.stderr), "error: --cpu cannot evaluate --inline WGSL functions (they run on the device only)\n");
}

/// Every name naga finds at module scope of a shader the inline file goes
/// into (render kernel with every modality on, eval kernel) is found by the
/// light scan that `validate_with_inline` uses to tell a redefinition by the
/// user from a bug: the two cannot drift apart.
#[test]
fn the_name_scan_finds_every_name_the_generated_shaders_define() {
    use isotrace::render::{BisectOptions, Modalities, Traversal};
    let f = isotrace::Formula::compile("t", "x^2 + y^2 + z^2 - 1").unwrap();
    let m = Modalities { shadows: true, reflect: 1, ..Default::default() };
    let b = BisectOptions { modalities: m, ..BisectOptions::new(isotrace::ir::Domain::Affine) };
    let render = isotrace::kernel::assemble(&f.ir, &Traversal::Bisect(b)).wgsl;
    let eval = isotrace::field::compiled::eval_shader(&f.ir, isotrace::ir::Domain::Interval);
    for src in [render, eval] {
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        let scanned: Vec<String> = isotrace::inline::module_names(&src).into_iter().map(|(n, _)| n).collect();
        let mut names: Vec<String> = module.functions.iter().filter_map(|(_, f)| f.name.clone()).collect();
        names.extend(module.entry_points.iter().map(|e| e.name.clone()));
        names.extend(module.types.iter().filter_map(|(_, t)| t.name.clone()));
        names.extend(module.constants.iter().filter_map(|(_, c)| c.name.clone()));
        names.extend(module.global_variables.iter().filter_map(|(_, g)| g.name.clone()));
        assert!(names.len() > 50);
        for n in &names {
            assert!(scanned.contains(n), "'{n}' is defined by the generated shader but not found by module_names");
        }
        for n in ["main", "field", "Ray", "Uniforms", "load_uniforms"] {
            assert!(scanned.iter().any(|s| s == n) || !src.contains(&format!("fn {n}")), "{n}");
        }
    }
}

#[test]
fn hooks_with_another_signature_are_refused_and_shorthands_accepted() {
    let text = "fn hook_reject(r: vec2<f32>) -> vec2<f32> { return r; }\n";
    let e = parse_inline("h.wgsl", text).unwrap_err();
    assert_eq!(e.message, "hook 'hook_reject' has the wrong signature");
    assert_eq!(e.labels[0].1, "declared as (vec2<f32>) -> vec2<f32>");
    let ok = "fn hook_hit(q : vec3f) -> bool { return true; }\nfn hook_shade(a: vec3<f32>, b: vec3f, c: vec3<f32>, d: vec3 <f32>,) -> vec3f { return a; }\n";
    assert!(parse_inline("h.wgsl", ok).is_ok());
}

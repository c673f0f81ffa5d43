//! `--inline FILE.wgsl`: declarations found, missing versions reported.


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

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

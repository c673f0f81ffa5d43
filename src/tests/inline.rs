//! `--inline FILE.wgsl`: declarations found, missing versions reported.

use crate::inline::parse_inline;

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

/// Every name naga finds at module scope of a shader the inline file goes
/// into (render kernel with every modality on, eval kernel) is found by the
/// light scan that `validate_with_inline` uses to tell a redefinition by the
/// user from a bug: the two cannot drift apart.
#[test]
fn the_name_scan_finds_every_name_the_generated_shaders_define() {
    use crate::render::{BisectOptions, Modalities, Traversal};
    let f = crate::Formula::compile("t", "x^2 + y^2 + z^2 - 1").unwrap();
    let m = Modalities { shadows: true, reflect: 1, ..Default::default() };
    let b = BisectOptions { modalities: m, ..BisectOptions::new(crate::ir::Domain::Affine) };
    let render = crate::kernel::assemble(&f.ir, &Traversal::Bisect(b)).wgsl;
    let eval = crate::field::compiled::eval_shader(&f.ir, crate::ir::Domain::Interval);
    for src in [render, eval] {
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        let scanned: Vec<String> = crate::inline::module_names(&src).into_iter().map(|(n, _)| n).collect();
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

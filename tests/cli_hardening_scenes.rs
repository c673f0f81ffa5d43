//! Scene files and messages at the command line: deep trees (folded, or
//! refused at the depth the GPU evaluates), values that throw a scene's
//! bounds out, huge strings in a file, byte-order marks, a scene file given
//! to the formula `check`. Each test asserts the exact message and exit
//! code; the renders are small (48 px) and compared with the analytic
//! sphere.

mod cli_common;
use cli_common::*;
use glam::DVec3;
use isotrace::render::Camera;
use std::path::Path;

/// A sphere of radius `r` under `chain`'s unary nodes (bottom first).
fn chain_scene(r: f64, chain: &[(&str, f64)]) -> String {
    let mut nodes = vec![format!("{{\"type\": \"sphere\", \"radius\": {r}}}")];
    for (k, (ty, v)) in chain.iter().enumerate() {
        let field = if *ty == "offset" { "distance" } else { "thickness" };
        nodes.push(format!("{{\"type\": \"{ty}\", \"{field}\": {v}, \"child\": {k}}}"));
    }
    format!("{{\"isotrace_scene\": 1, \"root\": {}, \"nodes\": [{}]}}", chain.len(), nodes.join(",\n"))
}

/// Offsets and shells in turn from the bottom: `pairs` of (offset 0.0004,
/// shell 0.0006). An offset over a shell folds into it, so the GPU keeps
/// the first offset and the shells: pairs + 1 unary nodes. Outside, every
/// value is positive, so the outer surface is the sphere of radius
/// r + pairs · (0.0004 + 0.0003).
fn alternating(pairs: usize) -> Vec<(&'static str, f64)> {
    (0..pairs).flat_map(|_| [("offset", 0.0004), ("shell", 0.0006)]).collect()
}

const VIEW: [&str; 8] = ["--size", "48", "--box=-2,2", "--eye", "4,3,2", "--target", "0,0,0", "--stats"];

/// Renders `scene` to an EXR and checks every pixel against the sphere of
/// radius `r` at the origin: rays that meet it (away from the silhouette)
/// at its depth within half a pixel along the ray plus eps, rays that pass
/// it by a pixel or more as misses; no warning. Returns the hits.
fn renders_the_sphere(scene: &Path, r: f64) -> usize {
    let exr = scene.with_extension("exr");
    let mut args = vec!["render", s(scene), "-o", s(&exr)];
    args.extend(VIEW);
    let o = isotrace(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(!err.contains("warning") && err.contains("unconverged 0"), "{err}");
    let (w, h, channels) = isotrace::output::read_exr_channels(&exr).unwrap();
    let z = &channels.iter().find(|(n, _)| n == "Z").unwrap().1;
    let cam = Camera { eye: DVec3::new(4.0, 3.0, 2.0), target: DVec3::ZERO, up: DVec3::Z, fov_deg: 40.0 };
    let frame = cam.frame().unwrap();
    let pixel = frame.tan_half_fov / h as f64;
    // The default eps: 2^-11 of the box's diagonal.
    let eps = 4.0 * 3f64.sqrt() * 2f64.powi(-11) * 1.0001;
    let (o, mut hits) = (cam.eye, 0);
    for j in 0..h {
        for i in 0..w {
            let d = Camera::ray(&frame, i, j, w, h);
            let b = o.dot(d);
            let disc = b * b - (o.length_squared() - r * r);
            let depth = z[(j * w + i) as usize] as f64;
            let miss_by = (o - d * b).length() - r;
            if disc < 0.0 {
                if miss_by > -2.0 * pixel * b {
                    assert!(depth.is_infinite(), "({i},{j}) passes the sphere but has depth {depth}");
                }
                continue;
            }
            let t = -b - disc.sqrt();
            let cos = ((o + d * t) / r).dot(d).abs();
            if cos < 0.17 {
                continue;
            }
            assert!((depth - t).abs() <= pixel * t / cos + eps, "({i},{j}): depth {depth}, the sphere's {t}");
            hits += 1;
        }
    }
    hits
}

// Deep scenes.

#[test]
fn a_chain_of_8000_offsets_is_folded_and_renders_the_sphere_of_their_sum() {
    let d = dir("deep-offsets");
    let file = d.join("offsets.scene.json");
    std::fs::write(&file, chain_scene(0.5, &[("offset", 0.0001); 8000])).unwrap();
    let o = isotrace(&["scene", "check", s(&file)]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Before: no room for a single step (0 hits); now one offset of 0.8.
    assert!(renders_the_sphere(&file, 1.3) > 400);
}

#[test]
fn a_chain_that_does_not_fold_is_refused_beyond_the_limit_and_renders_at_it() {
    let d = dir("deep-shells");
    let over = d.join("over.scene.json");
    std::fs::write(&over, chain_scene(0.5, &alternating(512))).unwrap();
    let message = format!(
        "error: {}: nodes[0]: 513 unary nodes above this primitive run at every step of a ray near it, above the limit of 512 \
         (a pixel's steps share 60000 loop iterations on the GPU); use fewer (offsets in a row already count as one)\n",
        s(&over)
    );
    assert_error(&isotrace(&["scene", "check", s(&over)]), &message);
    let png = d.join("over.png");
    assert_error(&isotrace_without_gpu(&["render", s(&over), "--size", "16", "-o", s(&png)]), &message);
    assert!(!png.exists());

    let at = d.join("at.scene.json");
    std::fs::write(&at, chain_scene(0.5, &alternating(511))).unwrap();
    assert!(renders_the_sphere(&at, 0.5 + 511.0 * 0.0007) > 200);
}

#[test]
fn a_formula_lowered_to_a_scene_meets_the_same_limit() {
    let d = dir("deep-formula");
    let f = d.join("shells.txt");
    let mut text = String::from("a0 = sphere(0.5);\n");
    for k in 1..=520 {
        text += &format!("a{k} = shell(0.001, a{});\n", k - 1);
    }
    text += "a520\n";
    std::fs::write(&f, text).unwrap();
    let o = isotrace_without_gpu(&["render", "-f", s(&f), "--field", "scene", "--method", "sphere", "--size", "16", "-o", s(&d.join("f.png"))]);
    assert_error(
        &o,
        "error: --field scene: in the scene the formula lowers to (`isotrace scene lower` writes it), nodes[0]: 520 unary nodes above this primitive \
         run at every step of a ray near it, above the limit of 512 (a pixel's steps share 60000 loop iterations on the GPU); use fewer (offsets in a row already count as one)\n",
    );
}

// Values that throw the bounds out: named at their node and field, with
// short numbers, before any flag is derived from them.

#[test]
fn a_value_that_throws_the_bounds_out_is_named_at_its_node_and_field() {
    let d = dir("extent");
    let tail = "(the GPU computes in f32, where squared distances that far out overflow)";
    let one = |node: &str| format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{node}]}}");
    let pair = |op: &str| {
        format!("{{\"isotrace_scene\": 1, \"root\": 2, \"nodes\": [{{\"type\": \"sphere\", \"radius\": 1}}, {{\"type\": \"sphere\", \"radius\": 1}}, {op}]}}")
    };
    let beyond = |what: &str| format!("{what}, beyond the limit of 1e18 {tail}");
    let cases = [
        ("translate", one(r#"{"type": "sphere", "radius": 1, "translate": [1e308, 0, 0]}"#), beyond("nodes[0].translate[0]: 1e308 puts the scene's bounds at 1e308")),
        ("radius", one(r#"{"type": "sphere", "radius": 1e300}"#), beyond("nodes[0].radius: 1e300 puts the scene's bounds at 1e300")),
        ("beta", pair(r#"{"type": "smooth_union", "left": 0, "right": 1, "beta": 1e300}"#), beyond("nodes[2].beta: 1e300 puts the scene's bounds at 2e300")),
        ("join", pair(r#"{"type": "round_union", "left": 0, "right": 1, "radius": 3e20}"#), beyond("nodes[2].radius: 3e20 puts the scene's bounds at 3e20")),
        // Within the limit, but too far for its size: the derived box was
        // `invalid --box 100000000000000000,100000000000000000`.
        (
            "far",
            one(r#"{"type": "sphere", "radius": 1, "translate": [1e17, 0, 0]}"#),
            "nodes[0].translate[0]: 1e17 puts the scene 1e17 from the origin, over 1048576 times its size (2): the GPU's f32 arithmetic cannot resolve it there; \
             move the scene near the origin"
                .to_string(),
        ),
    ];
    for (name, text, what) in cases {
        let file = d.join(format!("{name}.scene.json"));
        std::fs::write(&file, text).unwrap();
        let message = format!("error: {}: {what}\n", s(&file));
        assert_error(&isotrace(&["scene", "check", s(&file)]), &message);
        assert_error(&isotrace_without_gpu(&["render", s(&file), "--size", "16", "-o", s(&d.join("x.png"))]), &message);
    }
    // A box the user gave that is too large to frame is named as the box,
    // not as the eye derived from it.
    let o = isotrace_without_gpu(&["render", "x^2 + y^2 + z^2 - 1", "--box=-1e308,1e308", "--size", "16", "-o", s(&d.join("x.png"))]);
    assert_error(
        &o,
        "error: invalid --box '-1e308,1e308': too large to frame, the default eye would be at infinity,infinity,infinity (coordinates must be below 1e30); give a smaller box, or --eye\n",
    );
}

// Huge strings: quoted short, escaped, and found without an edit distance
// over megabytes.

#[test]
fn a_huge_type_or_key_is_quoted_short_and_escaped() {
    let d = dir("huge-strings");
    let file = d.join("type.scene.json");
    let ty = format!("a\u{1b}[2J{}", "a".repeat(50_000_000));
    std::fs::write(&file, format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{{\"type\": \"{}\"}}]}}", ty.replace('\u{1b}', "\\u001b"))).unwrap();
    let o = isotrace(&["scene", "check", s(&file)]);
    assert_error(
        &o,
        &format!(
            "error: {}: nodes[0].type: unknown type 'a\u{241b}[2J{}…' (50000005 bytes); the types are sphere, box, round_box, capsule, torus, cylinder, octahedron, \
             plane, extrude, revolve, grid, density, cone, formula, max_box, union, intersection, difference, smooth_union, smooth_intersection, smooth_difference, chamfer_union, \
             chamfer_intersection, chamfer_difference, round_union, round_intersection, round_difference, sum_union, offset, shell, infill, displace, repeat, \
             mirror, twist or bend\n",
            s(&file),
            "a".repeat(55)
        ),
    );
    let file = d.join("key.scene.json");
    let key = format!("{}\\n\\u001b[2J", "k".repeat(1000));
    std::fs::write(&file, format!("{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{{\"type\": \"sphere\", \"radius\": 1, \"{key}\": 1}}]}}")).unwrap();
    assert_error(
        &isotrace(&["scene", "check", s(&file)]),
        &format!("error: {}: nodes[0].'{}…' (1005 bytes): unknown field for a sphere; expected radius, translate, rotate, scale or warp\n", s(&file), "k".repeat(60)),
    );
    std::fs::remove_dir_all(&d).unwrap();
    // A formula's names are quoted the same way.
    let o = isotrace(&["check", &format!("x + {}(y)", "b".repeat(100))]);
    let err = stderr(&o);
    assert_eq!(err.lines().next(), Some(format!("error: unknown function '{}…' (100 bytes)", "b".repeat(60)).as_str()));
    assert!(!err.contains("for a product"), "{err}");
}

// Byte-order marks, and a scene file given to the formula `check`.

#[test]
fn a_byte_order_mark_is_skipped() {
    let d = dir("bom");
    let bom = "\u{feff}";
    let scene = d.join("bom.scene.json");
    std::fs::write(&scene, format!("{bom}{{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{{\"type\": \"sphere\", \"radius\": 1}}]}}")).unwrap();
    let o = isotrace(&["scene", "check", s(&scene)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("primitives:    sphere 1\n"));
    let formula = d.join("bom.txt");
    std::fs::write(&formula, format!("{bom}x^2 + y^2 + z^2 - 1")).unwrap();
    let iso = d.join("bom.iso");
    std::fs::write(&iso, format!("{bom}#@ name: ball\nx^2 + y^2 + z^2 - 1\n")).unwrap();
    for args in [vec!["check", "-f", s(&formula)], vec!["check", s(&iso)]] {
        let o = isotrace(&args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        assert!(String::from_utf8_lossy(&o.stdout).starts_with("formula:    (((x^2 + y^2) + z^2) - 1)\n"));
    }
    // Anywhere else it is still a character a formula cannot hold.
    std::fs::write(&formula, format!("x^2 {bom}+ y^2")).unwrap();
    assert!(stderr(&isotrace(&["check", "-f", s(&formula)])).starts_with("error: non-ASCII character '\u{feff}' (U+FEFF) in formula\n"));
}

#[test]
fn check_given_a_scene_file_points_to_scene_check() {
    let o = isotrace(&["check", "examples/blobs.scene.json"]);
    assert_error(&o, "error: 'examples/blobs.scene.json' is a scene file, not a formula: check it with `isotrace scene check examples/blobs.scene.json`\n");
    let o = isotrace(&["check", "-f", "a.scene.json"]);
    assert_error(&o, "error: 'a.scene.json' is a scene file, not a formula: check it with `isotrace scene check a.scene.json`\n");
}

// Scripts.

#[test]
fn big_formulas_script_prints_its_help_instead_of_writing_a_directory_named_help() {
    let d = dir("script-help");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/big-formulas.py");
    let o = std::process::Command::new("python3").arg(script).arg("--help").current_dir(&d).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.starts_with("usage: big-formulas.py [-h] [OUT]\n\nWrites the big formulas"), "{out}");
    assert!(out.contains("  OUT         directory to write NAME.txt into"), "{out}");
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "the script wrote into its working directory");
}

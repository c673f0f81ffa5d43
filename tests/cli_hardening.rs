//! Issue 15 ("Hardening") at the command line, the inputs: endless
//! inputs, frame patterns, control bytes in messages, inline WGSL user
//! errors, parameters and the degree, completions, man pages and `check
//! --json`. Each test asserts the exact message and exit code. Output
//! files, signals, memory and compile budgets: `cli_hardening_files.rs`.

mod cli_common;
use cli_common::*;
use std::process::Output;

// 1. Bounded input.

#[test]
fn an_endless_formula_on_stdin_is_an_error_at_the_formula_limit() {
    let o = isotrace_with_stdin(&["check", "-"], vec![b'x'; 2_000_000]);
    assert_error(&o, "error: cannot read the formula from stdin: larger than the limit of 65536 bytes (64 KiB)\n");
    // One byte over the limit is refused; the limit itself is read.
    let o = isotrace_with_stdin(&["check", "-"], vec![b'x'; 65_537]);
    assert_error(&o, "error: cannot read the formula from stdin: larger than the limit of 65536 bytes (64 KiB)\n");
    let mut at_limit = b"x".to_vec();
    at_limit.resize(65_536, b' ');
    let o = isotrace_with_stdin(&["check", "-"], at_limit);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("formula:    x\n"));
}

#[test]
fn formula_iso_and_inline_files_are_read_up_to_their_limits() {
    let d = dir("files");
    let big = d.join("big.txt");
    std::fs::write(&big, vec![b'x'; 2_000_000]).unwrap();
    let o = isotrace(&["check", "-f", s(&big)]);
    assert_error(&o, &format!("error: cannot read formula file '{}': larger than the limit of 65536 bytes (64 KiB)\n", s(&big)));
    // An endless device is not read: only regular files are.
    let o = isotrace(&["check", "-f", "/dev/zero"]);
    assert_error(&o, "error: cannot read formula file '/dev/zero': not a regular file (a character device)\n");

    let iso = d.join("big.iso");
    let mut text = b"#@ name: big\nx^2 + y^2 + z^2 - 1\n".to_vec();
    text.resize(2_000_000, b'\n');
    std::fs::write(&iso, text).unwrap();
    let o = isotrace(&["check", s(&iso)]);
    assert_error(&o, &format!("error: {}: cannot read: larger than the limit of 1048576 bytes (1 MiB)\n", s(&iso)));

    let wgsl = d.join("big.wgsl");
    std::fs::write(&wgsl, vec![b' '; 2_000_000]).unwrap();
    let o = isotrace(&["check", "x", "--inline", s(&wgsl)]);
    assert_error(&o, &format!("error: cannot read --inline file '{}': larger than the limit of 1048576 bytes (1 MiB)\n", s(&wgsl)));
}

#[test]
fn eval_boxes_are_streamed_with_a_line_and_a_count_limit() {
    let o = isotrace_with_stdin(&["eval", "x", "--cpu"], vec![b'x'; 2_000_000]);
    assert_error(&o, "error: <stdin>:1: line longer than the limit of 4096 bytes (4 KiB)\n");
    let d = dir("boxes");
    let file = d.join("boxes.txt");
    let mut text = b"0 1 0 1 0 1\n".to_vec();
    text.extend(vec![b'9'; 5000]);
    std::fs::write(&file, text).unwrap();
    let o = isotrace(&["eval", "x", "--cpu", "--boxes", s(&file)]);
    assert_error(&o, &format!("error: {}:2: line longer than the limit of 4096 bytes (4 KiB)\n", s(&file)));
    // `yes '0 1 0 1 0 1' | isotrace eval x`: one box more than the limit.
    let o = isotrace_with_stdin(&["eval", "x", "--cpu"], b"0 1 0 1 0 1\n".repeat((1 << 24) + 1));
    assert_error(&o, "error: <stdin>:16777217: more than 16777216 boxes, the limit of one eval run; split the input\n");
}

// 2 and 3. Frames and frame patterns.

#[test]
fn frames_are_capped_before_any_work() {
    let d = dir("frames-cap");
    let pat = d.join("f%d.png");
    let o = isotrace(&["render", "@sphere", "--size", "16", "--frames", "1000000000", "-o", s(&pat)]);
    assert_error(&o, "error: invalid --frames '1000000000': must be between 1 and 1000000\n");
    let o = isotrace(&["render", "@sphere", "--size", "16", "--frames", "0", "-o", s(&pat)]);
    assert_error(&o, "error: invalid --frames '0': must be between 1 and 1000000\n");
    // The cap itself passes every check; without a device it then stops with 2.
    let o = isotrace_without_gpu(&["render", "@sphere", "--size", "16", "--frames", "1000000", "-o", s(&pat)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn frame_patterns_outside_the_grammar_are_errors_that_point_at_the_problem() {
    let cases: &[(&str, &str)] = &[
        ("f%99999d.png", "'%99999d' at column 2: the width of a frame-number field is written %0Nd with one digit N from 1 to 9"),
        ("f%4d.png", "'%4d' at column 2: the width of a frame-number field is written %0Nd with one digit N from 1 to 9"),
        ("f%010d.png", "'%010d' at column 2: the width of a frame-number field is written %0Nd with one digit N from 1 to 9"),
        ("f%d_%d.png", "a second frame-number field '%d' at column 5; a pattern has exactly one (write %% for a literal %)"),
        ("f%x.png", "'%x' at column 2 is not a frame-number field: use %d or %0Nd (N from 1 to 9), or %% for a literal %"),
        ("f%d.png%", "a lone '%' at column 8 ends the pattern: write %% for a literal %"),
        ("d%d/f.png", "the frame-number field at column 2 is in a directory name; it must be in the file name"),
    ];
    for (pat, why) in cases {
        let o = isotrace(&["render", "@sphere", "--size", "16", "--frames", "2", "-o", pat]);
        assert_error(&o, &format!("error: invalid -o pattern '{pat}': {why}\n"));
    }
    let o = isotrace(&["render", "@sphere", "--size", "16", "--frames", "2", "-o", "f%%d.png"]);
    assert_error(&o, "error: with --frames, -o needs a frame-number pattern like frames/f_%04d.png, got 'f%%d.png'\n");
}

#[test]
fn a_literal_percent_and_a_padded_field_name_every_frame() {
    let d = dir("frames-ok");
    let pat = d.join("f%%%03d.png");
    let o = isotrace(&["render", "@sphere", "--size", "8", "--frames", "2", "-o", s(&pat)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut names: Vec<String> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    assert_eq!(names, ["f%000.png", "f%001.png"]);
}

// 4. Control bytes in messages.

#[test]
fn control_bytes_in_a_formula_are_shown_escaped_with_the_caret_in_place() {
    let o = isotrace(&["check", "x\x1b[31m + y"]);
    assert_error(
        &o,
        "error: control character U+001B in formula\n  ┌─ <formula>:1:2\n  │\n1 │ x\u{241b}[31m + y\n  │  ^ not allowed here\n  │\n  \
         = besides printable ASCII only spaces, tabs and line breaks may appear in a formula\n\n",
    );
    // An error before the control bytes shows the line with them escaped.
    let o = isotrace_with_stdin(&["check", "-"], "x + $ + y\x1b[31m\x7f\0");
    assert_error(&o, "error: unexpected character '$'\n  ┌─ <stdin>:1:5\n  │\n1 │ x + $ + y\u{241b}[31m\u{2421}\u{2400}\n  │     ^ no token starts with this\n\n");
}

#[test]
fn control_bytes_in_quoted_user_text_are_escaped() {
    let d = dir("control");
    let iso = d.join("e.iso");
    std::fs::write(&iso, "#@ name: a\x1b[2Jb\nx\n").unwrap();
    let o = isotrace(&["check", s(&iso)]);
    assert_error(&o, &format!("error: {}:1: bad name value 'a\u{241b}[2Jb': a name uses letters, digits, '-', '_' and '.' only\n", s(&iso)));
    let o = isotrace(&["render", "x", "--size", "\x1b]0;pwned\x07", "-o", "x.png"]);
    assert_error(&o, "error: invalid --size '\u{241b}]0;pwned\u{2407}': expected WxH like 1024x768, or N for a square\n");
    let o = isotrace_with_stdin(&["eval", "x", "--cpu"], "0 1 \x1b[31m\n");
    assert_error(&o, "error: <stdin>:1: expected 6 or 8 numbers: x0 x1 y0 y1 z0 z1 [t0 t1]; found a word that is not a number in '0 1 \u{241b}[31m'\n");
    assert!(!o.stderr.contains(&0x1b));
}

// 6. Completions, man pages, check --json.

#[test]
fn completion_scripts_know_the_commands_and_flags() {
    let o = isotrace(&["completions", "bash"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bash = String::from_utf8(o.stdout).unwrap();
    assert!(bash.contains("render") && bash.contains("--box") && bash.contains("--force"), "{bash}");
    for shell in ["zsh", "fish", "elvish", "powershell"] {
        let o = isotrace(&["completions", shell]);
        assert!(o.status.success(), "{shell}: {}", stderr(&o));
        assert!(String::from_utf8(o.stdout).unwrap().contains("--frames"), "{shell}");
    }
    let o = isotrace(&["completions", "tcsh"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).starts_with("error: invalid value 'tcsh' for '<SHELL>'"), "{}", stderr(&o));
}

#[test]
fn man_pages_for_isotrace_and_each_command() {
    let o = isotrace(&["man"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = String::from_utf8(o.stdout).unwrap();
    assert!(page.contains(".TH isotrace 1") && page.contains("completions"), "{page}");
    let file = dir("man").join("isotrace-render.1");
    let o = isotrace(&["man", "render", "-o", s(&file)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(&file).unwrap();
    assert!(page.contains(".TH isotrace-render 1") && page.contains(r"\-\-force"), "{page}");
    let o = isotrace(&["man", "paint"]);
    assert_error(&o, "error: unknown command 'paint' for man: expected one of check, wgsl, render, eval, list, bench, manifest, scene, view, completions, man, help\n");
}

#[test]
fn check_json_is_one_object_with_the_analysis() {
    let f = "x^2 + y^2 + z^2 - r^2 + 2*x*y";
    let o = isotrace(&["check", f, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(o.stdout.iter().filter(|&&b| b == b'\n').count(), 1);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["variables"], serde_json::json!(["x", "y", "z"]));
    assert_eq!(v["parameters"], serde_json::json!(["r"]));
    assert_eq!(v["degree"], 2);
    // The same analysis as the text form, field by field.
    let text = String::from_utf8(isotrace(&["check", f]).stdout).unwrap();
    let field = |key: &str| text.lines().find_map(|l| l.strip_prefix(key)).unwrap().trim().to_string();
    assert_eq!(v["formula"].as_str().unwrap(), field("formula:"));
    assert_eq!(format!("{} (auto)", v["algebra"].as_str().unwrap()), field("algebra:"));
    let ops = &v["operations"];
    assert_eq!(
        format!("{} ({} products of non-constant terms, {} integer powers)", ops["total"], ops["products"], ops["integer_powers"]),
        field("operations:")
    );
    let o = isotrace(&["check", "sin(x) - z", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["degree"], serde_json::Value::Null);
    assert_eq!(v["parameters"], serde_json::json!([]));
    assert_eq!(v["variables"], serde_json::json!(["x", "z"]));
}

// 7. Inline WGSL: user errors point into the user's file (item 9).

const CLASH_NOTE: &str = "  = the file shares one module with isotrace's own functions, types and constants (main, traverse, field, Ray, Hit, Uniforms, the s_/ia_/ra_ op libraries, …); rename it: a prefix of your own avoids clashes\n\n";

#[test]
fn inline_wgsl_that_redefines_a_generated_name_or_mistypes_a_hook_is_a_user_error() {
    let d = dir("inline-user");
    let clashes: &[(&str, &str, &str)] = &[
        ("main", "fn main() -> f32 { return 1.0; }", "   ^^^^"),
        ("traverse", "fn traverse(a: f32) -> f32 { return a; }", "   ^^^^^^^^"),
        ("tiles", "fn tiles() {}", "   ^^^^^"),
        ("field", "fn field(p: vec3<f32>) -> f32 { return 0.0; }", "   ^^^^^"),
        ("load_uniforms", "fn load_uniforms() {}", "   ^^^^^^^^^^^^^"),
        ("Ray", "struct Ray { a: f32 }", "       ^^^"),
        ("Hit", "struct Hit { a: f32 }", "       ^^^"),
        ("Uniforms", "struct Uniforms { a: f32 }", "       ^^^^^^^^"),
    ];
    for (name, line, caret) in clashes {
        let file = d.join(format!("{name}.wgsl"));
        std::fs::write(&file, format!("// mine\n{line}\n")).unwrap();
        let col = caret.find('^').unwrap() + 1;
        let expected = format!(
            "error: in inline WGSL: '{name}' is already defined by the shader isotrace generates around this file\n  ┌─ {}:2:{col}\n  │\n2 │ {line}\n  │ {caret} defined here too\n  │\n{CLASH_NOTE}",
            s(&file)
        );
        for cmd in ["check", "wgsl"] {
            let o = isotrace_without_gpu(&[cmd, "x", "--inline", s(&file)]);
            assert_error(&o, &expected);
        }
    }
    // The same in a render, before any GPU work is needed to find it.
    let main = d.join("main.wgsl");
    let o = isotrace(&["render", "x^2+y^2+z^2-1", "--inline", s(&main), "--size", "8", "-o", s(&d.join("m.png"))]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).starts_with("error: in inline WGSL: 'main' is already defined"), "{}", stderr(&o));

    let hooks: &[(&str, &str, &str)] = &[
        ("fn hook_reject(r: vec2<f32>) -> f32 { return 1.0; }", "(vec2<f32>) -> f32", "fn hook_reject(r: vec2<f32>) -> bool"),
        ("fn hook_hit(p: vec3<f32>) -> vec3<f32> { return p; }", "(vec3<f32>) -> vec3<f32>", "fn hook_hit(p: vec3<f32>) -> bool"),
        ("fn hook_hit(p: vec2<f32>, q: f32) { }", "(vec2<f32>, f32)", "fn hook_hit(p: vec3<f32>) -> bool"),
        (
            "fn hook_shade(p: vec3<f32>, dir: vec3<f32>, n: vec3<f32>, c: f32) -> vec3<f32> { return p; }",
            "(vec3<f32>, vec3<f32>, vec3<f32>, f32) -> vec3<f32>",
            "fn hook_shade(p: vec3<f32>, dir: vec3<f32>, n: vec3<f32>, c: vec3<f32>) -> vec3<f32>",
        ),
    ];
    for (i, (line, found, want)) in hooks.iter().enumerate() {
        let file = d.join(format!("hook{i}.wgsl"));
        std::fs::write(&file, format!("{line}\n")).unwrap();
        let name = &line[3..line.find('(').unwrap()];
        let carets = "^".repeat(name.len());
        let expected = format!(
            "error: hook '{name}' has the wrong signature\n  ┌─ {}:1:4\n  │\n1 │ {line}\n  │    {carets} declared as {found}\n  │\n  = the traversal calls it as {want}\n\n",
            s(&file)
        );
        let png = d.join("h.png");
        let commands: [&[&str]; 3] = [&["check"], &["eval", "--cpu"], &["render", "-o", s(&png)]];
        for cmd in commands {
            let o = isotrace_without_gpu(&[cmd, &["x", "--inline", s(&file)]].concat());
            assert_error(&o, &expected);
        }
    }
}

// 8. Messages of item 13: --param, the degree, bench's console table.

#[test]
fn params_take_the_eps_number_syntax_once_each() {
    let o = isotrace_without_gpu(&["render", "x^2+y^2+z^2-r^2", "--param", "r=1", "--param", "r=2", "-o", "p.png"]);
    assert_error(&o, "error: --param r is given twice ('r=1' and 'r=2'): give each parameter once\n");
    let o = isotrace_without_gpu(&["eval", "x - a", "--param", "a=1", "--param", " a = 2^-1", "--cpu"]);
    assert_error(&o, "error: --param a is given twice ('a=1' and ' a = 2^-1'): give each parameter once\n");
    let o = isotrace_without_gpu(&["render", "x^2+y^2+z^2-r^2", "--param", "r=2^x", "-o", "p.png"]);
    assert_error(&o, "error: invalid --param 'r=2^x': '2^x' is not a number\n");
    let o = isotrace_without_gpu(&["render", "x^2+y^2+z^2-r^2", "--param", "r=2^2000", "-o", "p.png"]);
    assert_error(&o, "error: invalid --param 'r=2^2000': must be a finite number\n");
    // 2^-1 is 0.5, as with --eps: x - a at x = 0.75 is 0.25.
    let o = isotrace_with_stdin(&["eval", "x - a", "--param", "a=2^-1", "--algebra", "scalar", "--cpu"], "0.75 0 0\n");
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout).trim().parse::<f64>().unwrap(), 0.25);
    // The same syntax in an .iso header.
    let d = dir("param-iso");
    let iso = d.join("p.iso");
    std::fs::write(&iso, "#@ name: p\n#@ param: a=2^-2\nx - a\n").unwrap();
    let o = isotrace(&["check", s(&iso)]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(&iso, "#@ name: p\n#@ param: a=2^x\nx - a\n").unwrap();
    let o = isotrace(&["check", s(&iso)]);
    assert_error(&o, &format!("error: {}:2: bad param value 'a=2^x': '2^x' is not a number\n", s(&iso)));
}

#[test]
fn the_degree_saturates_instead_of_wrapping() {
    let field = |o: &Output| String::from_utf8_lossy(&o.stdout).lines().find_map(|l| l.strip_prefix("degree:").map(|d| d.trim().to_string())).unwrap();
    assert_eq!(field(&isotrace(&["check", "((x^4096)^4096)^128"])), "2147483648");
    // 2^32 wrapped to 0 (and would have chosen the algebra by it).
    assert_eq!(field(&isotrace(&["check", "((x^4096)^4096)^256"])), "4294967295 or more (too large to count)");
    assert_eq!(field(&isotrace(&["check", "((x^4096)^4096)^4096 * y^4096"])), "4294967295 or more (too large to count)");
    let o = isotrace(&["check", "((x^4096)^4096)^256", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["degree"], 4294967295u64);
}

#[test]
fn bench_prints_the_eps_search_and_reports_setup_time_apart() {
    let d = dir("bench-eps");
    let json = d.join("b.json");
    let o = isotrace(&["bench", "sphere", "--algebra", "ia", "--size", "16", "--repeat", "1", "--find-eps", "--json", s(&json)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout).into_owned();
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let m = &v["results"][0];
    let k = m["lowest_eps"]["exponent"].as_i64().unwrap();
    let ms = m["lowest_eps"]["gpu_ms"].as_f64().unwrap();
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines[0], format!("{:<16} {:<10} {:>24} {:>18}", "surface", "degree", "ia (ms / evals/px)", "ia lowest eps"));
    assert!(lines[1].ends_with(&format!(" {:>18}", format!("2^{k} ({ms:.1} ms)"))), "{table}");
    // Shader compilation and the warm-up are measured apart from gpu_ms.
    assert!(m["setup_ms"].as_f64().unwrap() > 0.0, "{m}");
    // Without --find-eps the table is as before.
    let o = isotrace(&["bench", "sphere", "--algebra", "ia", "--size", "16", "--repeat", "1"]);
    assert!(String::from_utf8_lossy(&o.stdout).starts_with(&format!("{:<16} {:<10} {:>24}\n", "surface", "degree", "ia (ms / evals/px)")));
}


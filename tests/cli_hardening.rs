//! Issue 15 ("Hardening") at the command line: endless inputs, frame
//! patterns, control bytes in messages, output files and signals,
//! completions, man pages and `check --json`. Each test asserts the exact
//! message and exit code.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn isotrace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("NODEVICE_SELECT", "1").output().unwrap()
}

/// Runs with `input` on stdin. The input is written from a thread and a
/// broken pipe is ignored: isotrace is expected to stop reading early.
fn isotrace_with_stdin(args: &[&str], input: impl Into<Vec<u8>>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(args)
        .env("NODEVICE_SELECT", "1")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let input = input.into();
    let writer = std::thread::spawn(move || {
        let _ = stdin.write_all(&input);
    });
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    out
}

/// Without a device: any command that gets as far as opening one exits
/// with 2, so exit 1 proves a check ran before any GPU work.
fn isotrace_without_gpu(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("WGPU_BACKEND", "metal").output().unwrap()
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("isotrace-hardening-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn assert_error(o: &Output, expected: &str) {
    assert_eq!(stderr(o), expected);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(o));
}

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
    // An endless file ends too.
    let o = isotrace(&["check", "-f", "/dev/zero"]);
    assert_error(&o, "error: cannot read formula file '/dev/zero': larger than the limit of 65536 bytes (64 KiB)\n");

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

// 5. Output files and signals.

#[test]
fn a_directory_as_output_is_refused_before_rendering() {
    let d = dir("out-dir");
    let target = d.join("a.png");
    std::fs::create_dir(&target).unwrap();
    let o = isotrace_without_gpu(&["render", "@sphere", "--size", "8", "-o", s(&target)]);
    assert_error(&o, &format!("error: cannot write '{}': it is a directory\n", s(&target)));
    let pat = d.join("a%d.png");
    std::fs::create_dir(d.join("a1.png")).unwrap();
    let o = isotrace_without_gpu(&["render", "@sphere", "--size", "8", "--frames", "3", "-o", s(&pat)]);
    assert_error(&o, &format!("error: cannot write '{}': it is a directory\n", s(&d.join("a1.png"))));
}

#[test]
fn a_read_only_target_is_replaced_only_with_force_and_keeps_its_mode() {
    let d = dir("read-only");
    let target = d.join("ro.png");
    std::fs::write(&target, b"keep me").unwrap();
    let mut perm = std::fs::metadata(&target).unwrap().permissions();
    perm.set_readonly(true);
    std::fs::set_permissions(&target, perm).unwrap();
    let o = isotrace_without_gpu(&["render", "@sphere", "--size", "8", "-o", s(&target)]);
    assert_error(&o, &format!("error: '{}' exists and is read-only: give --force to replace it\n", s(&target)));
    assert_eq!(std::fs::read(&target).unwrap(), b"keep me");
    let o = isotrace(&["render", "@sphere", "--size", "8", "-o", s(&target), "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(&target).unwrap().starts_with(b"\x89PNG"));
    assert!(std::fs::metadata(&target).unwrap().permissions().readonly());
}

/// The PID of a process that has ended.
fn dead_pid() -> u32 {
    let mut c = Command::new("true").spawn().unwrap();
    let pid = c.id();
    c.wait().unwrap();
    pid
}

fn make_old(p: &Path) {
    let f = std::fs::OpenOptions::new().write(true).open(p).unwrap();
    f.set_modified(std::time::SystemTime::now() - std::time::Duration::from_secs(3600)).unwrap();
}

#[test]
fn stale_temporaries_of_the_own_target_are_removed() {
    let d = dir("stale");
    let (dead, dead2) = (dead_pid(), dead_pid());
    let stale = d.join(format!(".st.png.{dead}.tmp"));
    let fresh = d.join(format!(".st.png.{dead2}.tmp"));
    let alive = d.join(format!(".st.png.{}.tmp", std::process::id()));
    let other = d.join(format!(".other.png.{dead}.tmp"));
    let frame = d.join(format!(".f_0007.png.{dead}.tmp"));
    for p in [&stale, &fresh, &alive, &other, &frame] {
        std::fs::write(p, b"partial").unwrap();
    }
    for p in [&stale, &alive, &other, &frame] {
        make_old(p);
    }
    let o = isotrace(&["render", "@sphere", "--size", "8", "-o", s(&d.join("st.png"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o), format!("note: removed '{}', a temporary file left by a run that is gone\n", s(&stale)));
    assert!(!stale.exists());
    // Too recent, its writer alive, another target's: kept.
    assert!(fresh.exists() && alive.exists() && other.exists() && frame.exists());
    // A frame pattern cleans the names it makes.
    let o = isotrace(&["render", "@sphere", "--size", "8", "--frames", "1", "-o", s(&d.join("f_%04d.png"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!frame.exists());
    assert!(other.exists());
}

/// A write blocked half-way: the temporary file is a FIFO with a small
/// buffer that nobody reads, created where `isotrace wgsl - -o OUT` (its
/// formula held back on stdin until then) will open it. The test waits
/// until the buffer is full, so the writer is inside write_atomic, then
/// sends `sig`.
#[cfg(unix)]
fn interrupted_write_leaves_nothing(sig: i32) {
    use std::os::unix::ffi::OsStrExt;
    use std::os::unix::fs::OpenOptionsExt;
    use std::os::unix::io::AsRawFd;
    use std::os::unix::process::ExitStatusExt;
    let d = dir(&format!("signal-{sig}"));
    let out = d.join("sig.wgsl");
    let mut child = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(["wgsl", "-", "-o", s(&out)])
        .env("NODEVICE_SELECT", "1")
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let fifo = d.join(format!(".sig.wgsl.{}.tmp", child.id()));
    let c = std::ffi::CString::new(fifo.as_os_str().as_bytes()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let reader = std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK).open(&fifo).unwrap();
    let capacity = unsafe { libc::fcntl(reader.as_raw_fd(), libc::F_SETPIPE_SZ, 4096) };
    assert!(capacity > 0);
    child.stdin.take().unwrap().write_all(b"x^2 + y^2 + z^2 - 1").unwrap();
    loop {
        let mut queued: libc::c_int = 0;
        assert_eq!(unsafe { libc::ioctl(reader.as_raw_fd(), libc::FIONREAD, &mut queued) }, 0);
        if queued >= capacity {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "isotrace ended before writing");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(sig), "{status:?}");
    assert!(!fifo.exists(), "the temporary file is left behind");
    assert!(!out.exists());
}

#[cfg(unix)]
#[test]
fn sigterm_and_sigint_remove_the_temporary_file_of_a_write_in_flight() {
    interrupted_write_leaves_nothing(libc::SIGTERM);
    interrupted_write_leaves_nothing(libc::SIGINT);
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
    assert_error(&o, "error: unknown command 'paint' for man: expected one of check, wgsl, render, eval, list, bench, manifest, scene, completions, man, help\n");
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

// 9. The trust model of .iso headers (item 12).

#[test]
fn a_header_reads_files_only_inside_its_directory_unless_allowed() {
    let d = dir("header-paths");
    let env = d.join("env.png");
    let o = isotrace(&["render", "@sphere", "--size", "8", "-o", s(&env)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let sub = d.join("sub");
    std::fs::create_dir(&sub).unwrap();
    std::fs::copy(&env, sub.join("inside.png")).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(&env, sub.join("link.png")).unwrap();
    let iso = |name: &str, value: &str| {
        let p = sub.join(format!("{name}.iso"));
        std::fs::write(&p, format!("#@ name: {name}\n#@ reflect: 1\n#@ env: {value}\nx^2 + y^2 + z^2 - 1\n")).unwrap();
        p
    };
    let out = d.join("o.png");
    let refused = |file: &Path, shown: &str| {
        let o = isotrace_without_gpu(&["render", s(file), "--size", "8", "-o", s(&out)]);
        assert_error(
            &o,
            &format!("error: the .iso header's env: image '{shown}' is outside the directory of the .iso file; give --allow-header-paths to read it (only for files you trust)\n"),
        );
    };
    refused(&iso("abs", s(&env)), s(&env));
    refused(&iso("up", "../env.png"), &format!("{}/../env.png", s(&sub)));
    #[cfg(unix)]
    refused(&iso("link", "link.png"), &format!("{}/link.png", s(&sub)));
    // Inside the directory, relative to the file: read.
    let o = isotrace(&["render", s(&iso("in", "inside.png")), "--size", "8", "-o", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    // With the flag, or with the user's own --env, the file is read.
    let o = isotrace(&["render", s(&iso("abs", s(&env))), "--size", "8", "-o", s(&out), "--allow-header-paths"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = isotrace(&["render", s(&iso("up", "../env.png")), "--size", "8", "-o", s(&out), "--env", s(&env)]);
    assert!(o.status.success(), "{}", stderr(&o));
    // check and wgsl read no header file.
    let o = isotrace(&["check", s(&iso("abs", "/etc/passwd"))]);
    assert!(o.status.success(), "{}", stderr(&o));
}

// 10. Host memory of big frames (item 4): an error, never an abort.

#[test]
fn a_frame_too_big_for_host_memory_is_an_error() {
    let d = dir("memory");
    let out = d.join("big.png");
    let with_budget = |budget: &str, size: &str, out: &Path| {
        Command::new(env!("CARGO_BIN_EXE_isotrace"))
            .args(["render", "@sphere", "--size", size, "-o", s(out)])
            .env("NODEVICE_SELECT", "1")
            .env("ISOTRACE_MEMORY_BUDGET", budget)
            .output()
            .unwrap()
    };
    let o = with_budget("1G", "16384", &out);
    assert_error(
        &o,
        "error: a 16384x16384 frame needs 12.9 GB of host memory for its pixels, over the memory budget of 1.0 GB; render a smaller --size, or raise ISOTRACE_MEMORY_BUDGET\n",
    );
    assert!(!out.exists());
    let o = with_budget("20k", "32", &out);
    assert_error(&o, "error: a 32x32 frame needs 49.2 kB of host memory for its pixels, over the memory budget of 20.0 kB; render a smaller --size, or raise ISOTRACE_MEMORY_BUDGET\n");
    let exr = d.join("ok.exr");
    let o = with_budget("49152", "32", &exr);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = with_budget("8 GiB", "32", &exr);
    assert_error(&o, "error: invalid ISOTRACE_MEMORY_BUDGET '8 GiB': expected a number of bytes, optionally with a suffix k, M, G or T (e.g. 8G)\n");
}

/// Without a budget the allocator itself refuses: an address-space limit
/// of 6 GB (enough for the device, not for 12.9 GB of pixels) makes the
/// refusal real and cheap; before, this aborted.
#[cfg(unix)]
#[test]
fn a_refused_allocation_is_an_error_without_a_budget() {
    let out = dir("memory-rlimit").join("big.png");
    let cmd = format!("ulimit -v 6000000 && exec '{}' render @sphere --size 16384 -o '{}'", env!("CARGO_BIN_EXE_isotrace"), s(&out));
    let o = Command::new("sh").args(["-c", &cmd]).env("NODEVICE_SELECT", "1").env_remove("ISOTRACE_MEMORY_BUDGET").output().unwrap();
    assert_error(&o, "error: a 16384x16384 frame needs 12.9 GB of host memory for its pixels; render a smaller --size\n");
}

/// The encoders allocate fallibly too (a budget below their need, set in
/// this test process only).
#[test]
fn encoding_a_frame_checks_its_memory() {
    use isotrace::render::{Frame, PixelOut, Stats, Status};
    let px = PixelOut { color: [0.0; 4], normal: [0.0; 3], depth: 1.0, evals: 0, level: 0, iso: 0, status: Status::Miss };
    let frame = Frame { width: 16, height: 16, pixels: vec![px; 256], stats: Stats::default() };
    let d = dir("memory-encode");
    isotrace::memory::set_budget(Some(700));
    let png = isotrace::output::write_frame(&d.join("a.png"), &frame).unwrap_err();
    let exr = isotrace::output::write_frame(&d.join("a.exr"), &frame).unwrap_err();
    isotrace::memory::set_budget(None);
    assert_eq!(png.to_string(), format!("cannot write '{}': a 16x16 frame needs 768 bytes of host memory for its PNG bytes, over the memory budget of 700 bytes", s(&d.join("a.png"))));
    assert_eq!(exr.to_string(), format!("cannot write '{}': a 16x16 frame needs 9.2 kB of host memory for its EXR channels, over the memory budget of 700 bytes", s(&d.join("a.exr"))));
    assert!(isotrace::output::write_frame(&d.join("a.png"), &frame).is_ok());
}

// 11. Shader compilation budget and bench job timeouts (item 5).

#[test]
fn a_huge_generated_shader_is_refused_and_a_slow_compile_is_announced() {
    let d = dir("shader-budget");
    // 3000 pseudo-random monomials: 54 KB of formula, 1.4 MB of WGSL.
    let mut r: u64 = 12345;
    let terms: Vec<String> = (0..3000)
        .map(|_| {
            r = (r * 1103515245 + 12345) % (1 << 31);
            format!("{}.{}*x^{}*y^{}*z^{}", (r >> 9) % 9 + 1, (r >> 13) % 10, r % 7, (r >> 3) % 7, (r >> 6) % 7)
        })
        .collect();
    let file = d.join("big.txt");
    std::fs::write(&file, terms.join(" + ")).unwrap();
    let o = isotrace(&["render", "-f", s(&file), "--field", "compiled", "--size", "8", "-o", s(&d.join("b.png"))]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.starts_with("error: the generated shader is ") && e.ends_with(
        " KB of WGSL, over the limit of 500 KB: the driver would compile it for many minutes; render it with --field tape (or auto), which runs the formula from a buffer in a fixed interpreter, simplify the formula (a repeated subexpression written once as a definition 'name = ...;' is generated once), or split the surface into several renders\n"
    ), "{e}");
    // The note after a (test-sized) delay, with the shader's size.
    let o = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(["render", "@sphere", "--size", "8", "-o", s(&d.join("s.png"))])
        .env("NODEVICE_SELECT", "1")
        .env("ISOTRACE_COMPILE_NOTE_MS", "0")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let kb: usize = stderr(&o).strip_prefix("note: compiling the shader (").and_then(|r| r.strip_suffix(" KB of WGSL) …\n")).unwrap().parse().unwrap();
    assert!((20..200).contains(&kb), "{kb}");
}

#[test]
fn bench_jobs_time_out_one_by_one_and_the_batch_goes_on() {
    let o = isotrace(&["bench", "sphere", "steiner", "--algebra", "ia", "--size", "16", "--repeat", "1", "--job-timeout", "0.05"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(table.ends_with(
        "FAILED sphere ia: timed out after 0.05 s; the job was stopped and the batch went on\nFAILED steiner ia: timed out after 0.05 s; the job was stopped and the batch went on\n"
    ), "{table}");
    // With time enough, the jobs run in child processes and report as usual.
    let d = dir("bench-timeout");
    let json = d.join("b.json");
    let o = isotrace(&["bench", "sphere", "--algebra", "ia,raa", "--size", "16", "--repeat", "1", "--job-timeout", "120", "--out", s(&d), "--json", s(&json)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(v["results"].as_array().unwrap().len(), 2);
    assert!(v["results"][1]["gpu_ms"].as_f64().unwrap() > 0.0, "{v}");
    assert!(d.join("sphere_raa.png").exists() && d.join("contact-sheet.png").exists());
    let o = isotrace(&["bench", "sphere", "--job-timeout", "0"]);
    assert_error(&o, "error: invalid --job-timeout 0: it must be a number of seconds above 0 and at most 86400\n");
}

//! Hardening at the command line, the files and budgets: output files and
//! signals, files that are not regular files (devices, FIFOs, directories)
//! as outputs and inputs, `-o -`, the trust model of `.iso` headers, host
//! memory of big frames, unresolved pixels, the shader compilation budget
//! and bench job timeouts. Each test asserts the exact message and exit
//! code. The inputs: `cli_hardening.rs`; scene grid paths: `scene_paths.rs`.

mod cli_common;
use cli_common::*;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

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
    let o = isotrace(&["render", "@sphere", "--size", "8", "-q", "-o", s(&d.join("st.png"))]);
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

// Files that are not files: writers refuse them, readers do not wait on them.

#[cfg(unix)]
fn mkfifo(p: &Path) {
    let c = std::ffi::CString::new(s(p)).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
}

#[cfg(unix)]
fn is_fifo(p: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::symlink_metadata(p).unwrap().file_type().is_fifo()
}

/// Runs isotrace without a device and fails the test instead of hanging
/// when it does not end: a blocking open of a FIFO would never return.
fn isotrace_ending(args: &[&str]) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(args)
        .env("WGPU_BACKEND", "metal")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while child.try_wait().unwrap().is_none() {
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("isotrace {args:?} did not end: it waits on a file");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[cfg(unix)]
#[test]
fn writers_refuse_fifos_and_devices_and_leave_them_as_they_are() {
    use std::os::unix::fs::FileTypeExt;
    let d = dir("not-files-out");
    let fifo = |name: &str| {
        let p = d.join(name);
        mkfifo(&p);
        p
    };
    let refused = |args: &[&str], target: &Path, kind: &str| {
        assert_error(&isotrace_ending(args), &format!("error: cannot write '{}': it is {kind}\n", s(target)));
    };
    // Refused before rendering: without a device, exit 1 and not 2.
    let png = fifo("a.png");
    refused(&["render", "@sphere", "--size", "8", "-o", s(&png)], &png, "a FIFO");
    let f1 = fifo("f1.png");
    refused(&["render", "@sphere", "--size", "8", "--frames", "3", "-o", s(&d.join("f%d.png"))], &f1, "a FIFO");
    let wgsl = fifo("k.wgsl");
    refused(&["wgsl", "@sphere", "-o", s(&wgsl)], &wgsl, "a FIFO");
    let scene = fifo("g.scene.json");
    refused(&["scene", "gen", "aggregate", "--level", "0", "-o", s(&scene)], &scene, "a FIFO");
    let json = fifo("b.json");
    refused(&["bench", "sphere", "--json", s(&json)], &json, "a FIFO");
    for p in [&png, &f1, &wgsl, &scene, &json] {
        assert!(is_fifo(p), "{} was replaced", s(p));
    }
    assert!(!d.join("f0.png").exists(), "no frame rendered");
    // The null device: refused and left a device.
    let null = Path::new("/dev/null");
    let blobs = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/blobs.scene.json");
    refused(&["scene", "formula", blobs, "-o", "/dev/null"], null, "a character device");
    refused(&["view", "@sphere", "--export", "/dev/null"], null, "a character device");
    assert!(std::fs::symlink_metadata(null).unwrap().file_type().is_char_device());
}

#[cfg(unix)]
#[test]
fn a_symbolic_link_as_output_is_replaced_and_its_target_kept() {
    let d = dir("link-out");
    let target = d.join("target.png");
    std::fs::write(&target, b"keep me").unwrap();
    // Read-only, which would need --force if the link were followed.
    let mut perm = std::fs::metadata(&target).unwrap().permissions();
    perm.set_readonly(true);
    std::fs::set_permissions(&target, perm).unwrap();
    let link = d.join("link.png");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let o = isotrace(&["render", "@sphere", "--size", "8", "-o", s(&link)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_file());
    assert!(std::fs::read(&link).unwrap().starts_with(b"\x89PNG"));
    assert_eq!(std::fs::read(&target).unwrap(), b"keep me");
    assert!(std::fs::metadata(&target).unwrap().permissions().readonly());
    assert!(!std::fs::metadata(&link).unwrap().permissions().readonly(), "the new file does not take the target's mode");
    // A link to a device is replaced too: the device is not written.
    let to_null = d.join("null.wgsl");
    std::os::unix::fs::symlink("/dev/null", &to_null).unwrap();
    let o = isotrace(&["wgsl", "@sphere", "-o", s(&to_null)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&to_null).unwrap().contains("fn main"));
}

#[cfg(unix)]
#[test]
fn readers_refuse_fifos_and_devices_at_once() {
    let d = dir("not-files-in");
    let fifo = |name: &str| {
        let p = d.join(name);
        mkfifo(&p);
        p
    };
    let out = d.join("o.png");
    let formula = fifo("f.txt");
    assert_error(&isotrace_ending(&["check", "-f", s(&formula)]), &format!("error: cannot read formula file '{}': not a regular file (a FIFO)\n", s(&formula)));
    let env = fifo("env.png");
    let o = isotrace_ending(&["render", "@sphere", "--size", "8", "--reflect", "1", &format!("--env={}", s(&env)), "-o", s(&out)]);
    assert_error(&o, &format!("error: cannot read --env image '{}': not a regular file (a FIFO)\n", s(&env)));
    // A header's env: image inside its directory is read only if it is a file.
    let iso = d.join("h.iso");
    std::fs::write(&iso, "#@ reflect: 1\n#@ env: env.png\nx^2 + y^2 + z^2 - 1\n").unwrap();
    let o = isotrace_ending(&["render", s(&iso), "--size", "8", "-o", s(&out)]);
    assert_error(&o, &format!("error: cannot read --env image '{}': not a regular file (a FIFO)\n", s(&env)));
    let scene = fifo("s.scene.json");
    assert_error(&isotrace_ending(&["scene", "check", s(&scene)]), &format!("error: cannot read scene file '{}': not a regular file (a FIFO)\n", s(&scene)));
    // A grid file that is a FIFO named *.npy, inside the scene's directory.
    fifo("g.npy");
    let grid_scene = d.join("grid.scene.json");
    std::fs::write(&grid_scene, r#"{"isotrace_scene": 1, "root": 0, "nodes": [{"type": "grid", "file": "g.npy", "spacing": 0.1, "origin": [0, 0, 0]}]}"#).unwrap();
    let o = isotrace_ending(&["scene", "check", s(&grid_scene)]);
    assert_error(&o, &format!("error: {}: nodes[0].file: {}: not a regular file (a FIFO)\n", s(&grid_scene), s(&d.join("g.npy"))));
    let boxes = fifo("boxes.txt");
    let o = isotrace_ending(&["eval", "x", "--cpu", "--boxes", s(&boxes)]);
    assert_error(&o, &format!("error: cannot read boxes file '{}': not a regular file (a FIFO)\n", s(&boxes)));
    let manifest = fifo("m.manifest.json");
    assert_error(&isotrace_ending(&["manifest", "merge", s(&manifest)]), &format!("error: cannot read '{}': not a regular file (a FIFO)\n", s(&manifest)));
    // A directory and a device.
    let iso_dir = d.join("dir.iso");
    std::fs::create_dir(&iso_dir).unwrap();
    assert_error(&isotrace_ending(&["check", s(&iso_dir)]), &format!("error: {}: cannot read: not a regular file (a directory)\n", s(&iso_dir)));
    assert_error(&isotrace_ending(&["check", "x", "--inline", "/dev/zero"]), "error: cannot read --inline file '/dev/zero': not a regular file (a character device)\n");
    // stdin stays a source.
    let o = isotrace_with_stdin(&["check", "-"], "x^2 + y^2 + z^2 - 1");
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn dash_writes_to_stdout_and_writers_check_their_extension() {
    let o = isotrace(&["render", "@sphere", "--size", "8", "-o", "-"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = image::load_from_memory(&o.stdout).unwrap();
    assert_eq!((png.width(), png.height()), (8, 8));
    let o = isotrace(&["wgsl", "@sphere", "-o", "-"]);
    assert!(o.status.success() && String::from_utf8_lossy(&o.stdout).contains("fn main"), "{}", stderr(&o));
    let o = isotrace_without_gpu(&["render", "@sphere", "--size", "8", "--json", "-o", "-"]);
    assert_error(&o, "error: --json prints to stdout, where -o - writes the image: write the image to a file, or leave out --json\n");
    let d = dir("extensions");
    for (args, name, expected) in [
        (&["scene", "gen", "aggregate", "--level", "0", "-o"][..], "agg.json", ".scene.json"),
        (&["scene", "lower", "sphere(1)", "-o"][..], "s.json", ".scene.json"),
        (&["wgsl", "@sphere", "-o"][..], "k.txt", ".wgsl"),
    ] {
        let p = d.join(name);
        let mut a = args.to_vec();
        a.push(s(&p));
        assert_error(&isotrace(&a), &format!("error: unknown output format '{}': the file name must end in {expected}\n", s(&p)));
        assert!(!p.exists());
    }
    let ok = d.join("agg.scene.json");
    let o = isotrace(&["scene", "gen", "aggregate", "--level", "0", "-o", s(&ok)]);
    assert!(o.status.success() && ok.is_file(), "{}", stderr(&o));
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
// 11. Shader compilation budget and bench job timeouts (item 5).

#[test]
fn a_huge_generated_shader_is_refused_and_a_slow_compile_is_announced() {
    let d = dir("shader-budget");
    // 2500 sines of pseudo-random monomials with powers below 21: no two
    // neighbours of one shape (no loop), not a polynomial (no Horner
    // loop), 60 KB of formula and over 1 MB of WGSL.
    let mut r: u64 = 12345;
    let terms: Vec<String> = (0..2500)
        .map(|_| {
            r = (r * 1103515245 + 12345) % (1 << 31);
            format!("{}.{}*sin(x^{}*y^{}*z^{})", (r >> 9) % 9 + 1, (r >> 13) % 10, r % 21, (r >> 5) % 21, (r >> 10) % 21)
        })
        .collect();
    let file = d.join("big.txt");
    std::fs::write(&file, terms.join(" + ")).unwrap();
    let o = isotrace(&["render", "-f", s(&file), "--field", "compiled", "--size", "8", "-o", s(&d.join("b.png"))]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.starts_with("error: the generated shader is ") && e.ends_with(
        " KB of WGSL code, over the limit of 500 KB: the driver would compile it for many minutes; render it with --field tape (or auto), which runs the formula from a buffer in a fixed interpreter, simplify the formula (a repeated subexpression written once as a definition 'name = ...;' is generated once), or split the surface into several renders\n"
    ), "{e}");
    // The note after a (test-sized) delay, with the shader's size.
    let o = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(["render", "@sphere", "--size", "8", "-q", "-o", s(&d.join("s.png"))])
        .env("NODEVICE_SELECT", "1")
        .env("ISOTRACE_COMPILE_NOTE_MS", "0")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let kb: usize = stderr(&o).strip_prefix("note: compiling the shader (").and_then(|r| r.strip_suffix(" KB of WGSL) …\n")).unwrap().parse().unwrap();
    assert!((20..200).contains(&kb), "{kb}");
    // A frame still rendering after a (test-sized) delay is named: a big
    // tape's frame takes minutes on a CPU device.
    let o = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(["render", "x^2 + y^2 + z^2 - 1", "--field", "tape", "--size", "8", "-q", "-o", s(&d.join("t.png"))])
        .env("NODEVICE_SELECT", "1")
        .env("ISOTRACE_RENDER_NOTE_MS", "0")
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(e.starts_with("note: still rendering the 8x8 frame (a tape of 6 instructions in the interpreter, on ") && e.ends_with("; the first frame includes the driver's compile) …\n"), "{e}");
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

// 12. Unresolved pixels never look like hits, and are always reported (item 6).

/// The one warning line of a render, its pixel count taken out.
fn unresolved_warning(o: &std::process::Output) -> (u64, String) {
    assert_eq!(o.status.code(), Some(0), "{}", stderr(o));
    let e = stderr(o);
    let line = e.lines().find(|l| l.contains("pixels")).unwrap_or_else(|| panic!("no warning in {e:?}"));
    let rest = line.strip_prefix("warning: ").unwrap();
    let (n, text) = rest.split_once(' ').unwrap();
    (n.parse().unwrap(), text.to_string())
}

#[test]
fn unresolved_pixels_are_hatched_by_default_and_always_reported() {
    let d = dir("unresolved");
    let png = d.join("t.png");
    let run = |extra: &[&str]| {
        let mut a = vec!["render", "@tangle", "--size", "48", "--max-iter", "3", "-o", s(&png)];
        a.extend_from_slice(extra);
        unresolved_warning(&isotrace(&a))
    };
    let budget = "pixels exhausted the iteration budget (--max-iter 3) and are drawn";
    let (n, text) = run(&[]);
    assert!(n > 0);
    assert_eq!(text, format!("{budget} as magenta stripes over the nearest cell that may hold the surface (--unresolved magenta|guess to change)"));
    let magenta = |p: &image::Rgba<u8>| p.0 == [255, 0, 255, 255];
    let hatched = image::open(&png).unwrap().to_rgba8();
    assert_eq!(run(&["--unresolved", "magenta"]), (n, format!("{budget} magenta")));
    let solid = image::open(&png).unwrap().to_rgba8();
    assert_eq!(run(&["--debug-unresolved"]), (n, format!("{budget} magenta")));
    assert_eq!(run(&["--unresolved", "guess"]), (n, format!("{budget} like hits at the nearest cell that may hold the surface (--unresolved guess)")));
    let guess = image::open(&png).unwrap().to_rgba8();
    let count = |img: &image::RgbaImage| img.pixels().filter(|p| magenta(p)).count();
    assert_eq!(count(&solid) as u64, n);
    assert_eq!(count(&guess), 0);
    assert!(count(&hatched) > 0 && (count(&hatched) as u64) < n);

    let o = isotrace(&["render", "@tangle", "--debug-unresolved", "--unresolved", "guess", "-o", s(&png)]);
    assert_eq!(o.status.code(), Some(1), "a usage error");
    assert!(stderr(&o).starts_with("error: the argument '--debug-unresolved' cannot be used with '--unresolved <STYLE>'"), "{}", stderr(&o));

    let o = isotrace(&["render", "@torus", "--method", "sphere", "--max-steps", "4", "--size", "48", "-o", s(&png)]);
    let (n, text) = unresolved_warning(&o);
    assert!(n > 0);
    assert_eq!(text, "pixels did not converge within --max-steps 4 and are drawn as magenta stripes over their best candidate (--unresolved magenta|guess to change)");
}

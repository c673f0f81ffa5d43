//! Encoding a frame checks it against the host memory budget.

use std::path::Path;

/// The budget is process-wide (`memory::set_budget`): the check runs alone in
/// a child process of this test binary, so no other test sees the budget.
#[test]
fn encoding_a_frame_checks_its_memory() {
    if std::env::var_os("ISOTRACE_TEST_ALONE").is_none() {
        let name = concat!(module_path!(), "::encoding_a_frame_checks_its_memory").split_once("::").unwrap().1;
        let o = std::process::Command::new(std::env::current_exe().unwrap()).args(["--exact", name, "--test-threads=1"]).env("ISOTRACE_TEST_ALONE", "1").output().unwrap();
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(o.status.success() && out.contains("1 passed"), "{out}{}", String::from_utf8_lossy(&o.stderr));
        return;
    }
    use crate::render::{Frame, PixelOut, Stats, Status};
    let px = PixelOut { color: [0.0; 4], normal: [0.0; 3], depth: 1.0, evals: 0, level: 0, iso: 0, status: Status::Miss };
    let frame = Frame { width: 16, height: 16, pixels: vec![px; 256], stats: Stats::default() };
    let d = dir("memory-encode");
    crate::memory::set_budget(Some(700));
    let png = crate::output::write_frame(&d.join("a.png"), &frame).unwrap_err();
    let exr = crate::output::write_frame(&d.join("a.exr"), &frame).unwrap_err();
    crate::memory::set_budget(None);
    assert_eq!(png.to_string(), format!("cannot write '{}': a 16x16 frame needs 768 bytes of host memory for its PNG bytes, over the memory budget of 700 bytes", s(&d.join("a.png"))));
    assert_eq!(exr.to_string(), format!("cannot write '{}': a 16x16 frame needs 9.2 kB of host memory for its EXR channels, over the memory budget of 700 bytes", s(&d.join("a.exr"))));
    assert!(crate::output::write_frame(&d.join("a.png"), &frame).is_ok());
}

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("isotrace-hardening-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

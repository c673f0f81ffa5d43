//! Helpers of the command-line hardening tests: run the binary (with
//! stdin, or without a device), scratch directories, exact-error checks.
#![allow(dead_code)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

pub fn isotrace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("NODEVICE_SELECT", "1").output().unwrap()
}

/// Runs with `input` on stdin. The input is written from a thread and a
/// broken pipe is ignored: isotrace is expected to stop reading early.
pub fn isotrace_with_stdin(args: &[&str], input: impl Into<Vec<u8>>) -> Output {
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
pub fn isotrace_without_gpu(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_isotrace")).args(args).env("WGPU_BACKEND", "metal").output().unwrap()
}

pub fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("isotrace-hardening-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

pub fn assert_error(o: &Output, expected: &str) {
    assert_eq!(stderr(o), expected);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(o));
}


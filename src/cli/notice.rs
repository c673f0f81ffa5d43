//! What a command tells the user on stderr besides warnings and errors,
//! so that standard output stays the command's data: the one line it
//! prints when it succeeds, `wrote tangle.png (768×768, 0.25 s)`, which
//! `--quiet` silences; the notes of a long compile or frame; progress bars.

use std::io::IsTerminal;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

static QUIET: AtomicBool = AtomicBool::new(false);
static START: OnceLock<Instant> = OnceLock::new();

/// Starts the clock the success line reports and sets `--quiet`.
pub fn begin(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
    let _ = START.set(Instant::now());
}

/// Seconds since [`begin`].
fn elapsed() -> f64 {
    START.get().map_or(0.0, |t| t.elapsed().as_secs_f64())
}

/// How the line names an output: its path, or standard output for `-`.
fn shown(path: &Path) -> String {
    if crate::output::is_stdout(path) { "standard output".into() } else { crate::diag::user_text(&path.display().to_string(), 200) }
}

/// `wrote PATH (DETAIL, T s)` unless `--quiet`.
pub fn wrote(path: &Path, detail: &str) {
    done(&format!("wrote {}", shown(path)), detail);
}

/// `WHAT (DETAIL, T s)` unless `--quiet`; `detail` may be empty.
pub fn done(what: &str, detail: &str) {
    if QUIET.load(Ordering::Relaxed) {
        return;
    }
    let sep = if detail.is_empty() { "" } else { ", " };
    eprintln!("{what} ({detail}{sep}{:.2} s)", elapsed());
}

/// An image's detail for [`wrote`]: `768×768`.
pub fn size(width: u32, height: u32) -> String {
    format!("{width}×{height}")
}

/// After how long a pipeline build is reported on stderr.
const COMPILE_NOTE_AFTER: std::time::Duration = std::time::Duration::from_secs(2);
/// After how long a frame still rendering is reported on stderr.
const RENDER_NOTE_AFTER: std::time::Duration = std::time::Duration::from_secs(5);

/// Runs `build` (naga, then the driver's shader compiler). When it takes
/// longer than [`COMPILE_NOTE_AFTER`] (or `ISOTRACE_COMPILE_NOTE_MS`, a
/// test hook), a note on stderr says what is happening, with the shader's
/// size from `wgsl_bytes`, so that a long compile does not look like a
/// hang.
pub fn with_compile_note<T>(wgsl_bytes: impl FnOnce() -> usize + Send, build: impl FnOnce() -> T) -> T {
    with_note("ISOTRACE_COMPILE_NOTE_MS", COMPILE_NOTE_AFTER, || format!("compiling the shader ({} KB of WGSL)", wgsl_bytes().div_ceil(1000)), build)
}

/// Runs `render` (one frame). When it takes longer than
/// [`RENDER_NOTE_AFTER`] (or `ISOTRACE_RENDER_NOTE_MS`, a test hook), a note
/// on stderr says what is rendering: a CPU device compiles the kernel at
/// its first dispatch, and a big formula's tape takes seconds to minutes a
/// frame there.
pub fn with_render_note<T>(what: impl FnOnce() -> String + Send, render: impl FnOnce() -> T) -> T {
    with_note("ISOTRACE_RENDER_NOTE_MS", RENDER_NOTE_AFTER, || format!("still rendering {}", what()), render)
}

/// Runs `work`; if it is not done after `after` (or the milliseconds in
/// the environment variable `hook`), prints `note: {note()} …` on stderr.
/// A delay of zero prints the note before `work` starts: a timer of zero
/// would race a quick `work` and make the hook's tests depend on speed.
fn with_note<T>(hook: &str, after: std::time::Duration, note: impl FnOnce() -> String + Send, work: impl FnOnce() -> T) -> T {
    let after = std::env::var(hook).ok().and_then(|v| v.parse().ok()).map_or(after, std::time::Duration::from_millis);
    if after.is_zero() {
        eprintln!("note: {} …", note());
        return work();
    }
    let (finished, wait) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|scope| {
        scope.spawn(move || {
            if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(after) {
                eprintln!("note: {} …", note());
            }
        });
        let out = work();
        drop(finished);
        out
    })
}

/// A progress bar on a terminal; `None` (plain lines elsewhere) otherwise.
pub fn progress(len: u64, what: &str) -> Option<indicatif::ProgressBar> {
    if len <= 1 || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) = indicatif::ProgressStyle::with_template(&format!("{{bar:40}} {{pos}}/{{len}} {what} {{elapsed}}")) {
        bar.set_style(style);
    }
    Some(bar)
}

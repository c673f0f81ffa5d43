//! The one line a command prints when it succeeds, on stderr so that
//! standard output stays the command's data: `wrote tangle.png (768×768,
//! 0.25 s)`. `--quiet` silences it (warnings and errors still print).

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
    if isotrace::output::is_stdout(path) { "standard output".into() } else { isotrace::diag::user_text(&path.display().to_string(), 200) }
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

//! The temporary files of atomic writes: a registry of the ones in flight,
//! so that the command line can remove them when the process is told to
//! stop (SIGINT, SIGTERM), and the removal of stale ones that a killed run
//! (SIGKILL, a power cut) left behind.
//!
//! A temporary file is named `.NAME.PID.tmp` next to its target `NAME`.
//! The PID says whether its writer can still be at work: a later run
//! removes such a file only when that process is gone and the file has not
//! been touched for [`STALE_AFTER`], and only for the names it is about to
//! write itself.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

/// Temporary files that exist now or are about to be created.
static IN_FLIGHT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn in_flight() -> MutexGuard<'static, Vec<PathBuf>> {
    // A panic elsewhere while holding the lock leaves the list intact.
    IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner())
}

/// Keeps a temporary path in the registry while it lives.
pub(super) struct Guard(PathBuf);

impl Guard {
    /// Registers `path`. Call it before creating the file, so that no
    /// moment exists when the file is there and unregistered.
    pub(super) fn new(path: &Path) -> Guard {
        in_flight().push(path.to_path_buf());
        Guard(path.to_path_buf())
    }
}

impl Drop for Guard {
    fn drop(&mut self) {
        let mut list = in_flight();
        if let Some(i) = list.iter().position(|p| *p == self.0) {
            list.swap_remove(i);
        }
    }
}

/// Removes every temporary file in flight and returns how many there
/// were. For a process about to end on a signal: the registry stays locked
/// afterwards, so a writer that goes on blocks before it can create another
/// temporary file (and every atomic write in this process blocks from now on).
pub fn remove_temporaries() -> usize {
    let list = in_flight();
    for p in list.iter() {
        let _ = std::fs::remove_file(p);
    }
    let n = list.len();
    std::mem::forget(list);
    n
}

/// How long a temporary file of a dead process must have been left
/// untouched before it is removed. The PID is only meaningful on this
/// machine: in a directory shared with other machines, a file whose PID is
/// unknown here may be another machine's write in progress, and such a
/// write touches its file continually.
pub const STALE_AFTER: Duration = Duration::from_secs(60);

/// Removes the stale temporary files `.NAME.PID.tmp` in `dir` whose `NAME`
/// satisfies `is_target` (the caller's own output names), whose process is
/// no longer alive, and which are older than [`STALE_AFTER`]. Returns the
/// removed paths. Errors (an unreadable directory, a file that cannot be
/// removed) leave things as they are: this is housekeeping.
pub fn remove_stale_temporaries(dir: &Path, is_target: impl Fn(&str) -> bool) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else { return vec![] };
    let own = std::process::id();
    let mut removed = vec![];
    for e in entries.flatten() {
        let name = e.file_name();
        let Some((target, pid)) = name.to_str().and_then(parse_tmp_name) else { continue };
        if pid == own || !is_target(target) || process_alive(pid) {
            continue;
        }
        let Ok(meta) = e.metadata() else { continue };
        let old = meta.modified().ok().and_then(|t| t.elapsed().ok()).is_some_and(|age| age >= STALE_AFTER);
        if old && meta.is_file() && std::fs::remove_file(e.path()).is_ok() {
            removed.push(e.path());
        }
    }
    removed
}

/// `.NAME.PID.tmp` → `(NAME, PID)`.
fn parse_tmp_name(file: &str) -> Option<(&str, u32)> {
    let (target, pid) = file.strip_prefix('.')?.strip_suffix(".tmp")?.rsplit_once('.')?;
    if target.is_empty() || pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    // PIDs are positive and fit in pid_t; 0 and negative values mean
    // process groups to kill(2).
    let pid: u32 = pid.parse().ok()?;
    (pid > 0 && pid <= i32::MAX as u32).then_some((target, pid))
}

/// Whether a process with this PID exists on this machine (whoever owns it).
#[cfg(unix)]
fn process_alive(pid: u32) -> bool {
    // Signal 0 checks that the process exists without sending anything;
    // EPERM means it exists but belongs to someone else.
    // SAFETY: kill with signal 0 has no effect besides the check, and pid
    // is a positive pid_t (see parse_tmp_name).
    let r = unsafe { libc::kill(pid as libc::pid_t, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
}

/// Without a way to ask, every writer counts as alive: nothing is removed.
#[cfg(not(unix))]
fn process_alive(_pid: u32) -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_parse_back_to_target_and_pid() {
        assert_eq!(parse_tmp_name(".f_0001.png.4242.tmp"), Some(("f_0001.png", 4242)));
        assert_eq!(parse_tmp_name(".a.b.c.7.tmp"), Some(("a.b.c", 7)));
        for bad in ["f.png.12.tmp", "..12.tmp", ".f.png.tmp", ".f.png.0.tmp", ".f.png.-3.tmp", ".f.png.99999999999.tmp", ".f.png.1x.tmp"] {
            assert_eq!(parse_tmp_name(bad), None, "{bad}");
        }
    }

    #[test]
    fn this_process_is_alive() {
        assert!(process_alive(std::process::id()));
    }
}

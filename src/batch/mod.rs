//! Batch work past one machine: isotrace as a task of the schedulers people
//! already run (Slurm job arrays, Kubernetes Indexed Jobs, GNU parallel),
//! not a scheduler of its own.
//!
//! - [`shard`]: which part of a batch a task does (`i/n`, or read from the
//!   scheduler's environment);
//! - [`manifest`]: the record an animation shard writes next to its frames,
//!   and the summary of many of them (complete and missing frames);
//! - [`merge`]: putting shard outputs together, refusing parts that come
//!   from different settings or isotrace versions;
//! - [`frame_check`]: whether a frame file on disk is whole.
//!
//! Everything here but [`frame_check`] is pure: reading files, the
//! environment and the clock is the caller's job, so every rule is
//! unit-tested.

pub mod frame_check;
pub mod manifest;
pub mod merge;
pub mod shard;

pub use shard::{GivenCount, Shard, ShardError};

/// 64-bit FNV-1a of `bytes`, as 16 hex digits: identifies a formula's text
/// or a set of options in a manifest. Not cryptographic: it tells shards of
/// different runs apart, it does not protect against forgery.
pub fn fnv1a64(bytes: &[u8]) -> String {
    let mut h = Fnv::default();
    h.feed(bytes);
    h.hex()
}

/// An FNV-1a hasher that is also a `fmt::Write`, so a value's `Debug` text
/// is hashed without being built in memory (an environment image's texels
/// are millions of numbers).
#[derive(Debug, Clone)]
pub struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    /// Adds bytes.
    pub fn feed(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0 ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// The hash so far, as 16 hex digits.
    pub fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

impl std::fmt::Write for Fnv {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.feed(s.as_bytes());
        Ok(())
    }
}

/// Text read from a file (a device or surface name, a formula's origin, a
/// frame's file name) as one line of a terminal or a report: every control
/// character is made visible ([`crate::diag::user_text`]), and
/// line breaks and tabs too, so the text can neither send escape sequences
/// to a terminal nor pass for lines of the output.
pub fn one_line(s: &str) -> String {
    crate::diag::user_text(s, usize::MAX)
}

/// Sorted numbers as ranges, `0-3, 7, 9-10`: a list of missing frames stays
/// readable when a whole shard (every n-th frame) or a run is missing.
pub fn ranges(sorted: &[usize]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < sorted.len() {
        let mut j = i;
        while j + 1 < sorted.len() && sorted[j + 1] == sorted[j] + 1 {
            j += 1;
        }
        out.push(if j == i { sorted[i].to_string() } else { format!("{}-{}", sorted[i], sorted[j]) });
        i = j + 1;
    }
    out.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv_matches_the_reference_values() {
        // From the FNV reference (draft-eastlake-fnv): "" and "a".
        assert_eq!(fnv1a64(b""), "cbf29ce484222325");
        assert_eq!(fnv1a64(b"a"), "af63dc4c8601ec8c");
        let mut h = Fnv::default();
        std::fmt::Write::write_fmt(&mut h, format_args!("{}{}", "a", "")).unwrap();
        assert_eq!(h.hex(), fnv1a64(b"a"));
    }

    #[test]
    fn text_from_files_stays_on_one_visible_line() {
        assert_eq!(one_line("llvmpipe\x1b[2J"), "llvmpipe\u{241b}[2J");
        assert_eq!(one_line("a\r\nb\tc\u{9b}"), "a\u{240d}\u{240a}b\u{2409}c\u{fffd}");
        assert_eq!(one_line("plain"), "plain");
    }

    #[test]
    fn ranges_join_runs() {
        assert_eq!(ranges(&[]), "");
        assert_eq!(ranges(&[0, 1, 2, 3, 7, 9, 10]), "0-3, 7, 9-10");
        assert_eq!(ranges(&[5]), "5");
    }
}

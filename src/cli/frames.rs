//! The output files of `render`: one file, or with `--frames N` one per
//! frame from a pattern, named lazily (a million frames need no million
//! names in memory), all checked before any rendering.
//!
//! The pattern grammar (the whole `-o` value):
//!
//! ```text
//! pattern := part* field part*
//! part    := "%%"                  a literal '%'
//!          | any character but '%'
//! field   := "%d"                  the frame number 0 … N-1 as it is
//!          | "%0" [1-9] "d"        zero-padded to that many digits
//! ```
//!
//! There is exactly one field, and it is in the file name, not in a
//! directory name (so every frame goes into one directory, checked once).
//! Anything else after a '%' is an error that names its column.

use super::CliError;
use crate::batch::{manifest, Shard};
use crate::diag::escape_controls;
use crate::output;
use std::path::{Path, PathBuf};

/// Most frames one `render` writes (what a manifest may list): it bounds
/// the run's length and the file names checked before it, not its memory.
pub const MAX_FRAMES: u32 = manifest::MAX_FRAMES;

/// A parsed frame pattern: `prefix`, the frame number padded to `width`
/// digits (0: no padding), `suffix`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FramePattern {
    prefix: String,
    width: usize,
    suffix: String,
}

/// Why a pattern is not one, with the 1-based column of the problem.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PatternError {
    /// No `%d` or `%0Nd`.
    #[error("no frame-number field")]
    NoField,
    /// A second field.
    #[error("a second frame-number field '{text}' at column {column}; a pattern has exactly one (write %% for a literal %)")]
    SecondField { column: usize, text: String },
    /// `%` followed by digits that are not `0` and one digit 1-9.
    #[error("'{text}' at column {column}: the width of a frame-number field is written %0Nd with one digit N from 1 to 9")]
    BadWidth { column: usize, text: String },
    /// `%` followed by something else.
    #[error("'{text}' at column {column} is not a frame-number field: use %d or %0Nd (N from 1 to 9), or %% for a literal %")]
    Unknown { column: usize, text: String },
    /// A `%` that ends the pattern.
    #[error("a lone '%' at column {column} ends the pattern: write %% for a literal %")]
    Trailing { column: usize },
    /// The field is in a directory name.
    #[error("the frame-number field at column {column} is in a directory name; it must be in the file name")]
    InDirectory { column: usize },
}

impl FramePattern {
    /// Parses a pattern (see the module documentation for the grammar).
    pub fn parse(p: &str) -> Result<FramePattern, PatternError> {
        let chars: Vec<char> = p.chars().collect();
        let (mut prefix, mut suffix) = (String::new(), String::new());
        let mut field: Option<(usize, usize)> = None; // (column, width)
        let mut i = 0;
        while i < chars.len() {
            let column = i + 1;
            let out = if field.is_some() { &mut suffix } else { &mut prefix };
            if chars[i] != '%' {
                out.push(chars[i]);
                i += 1;
                continue;
            }
            // The conversion: '%', then digits, then the character after them.
            let digits = chars[i + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
            let end = i + 1 + digits;
            let text: String = chars[i..(end + 1).min(chars.len())].iter().collect();
            let width = match (chars.get(i + 1), chars.get(end)) {
                (None, _) => return Err(PatternError::Trailing { column }),
                (Some('%'), _) => {
                    out.push('%');
                    i += 2;
                    continue;
                }
                (Some('d'), _) => 0,
                (Some(_), Some('d')) if digits == 2 && chars[i + 1] == '0' && chars[i + 2] != '0' => chars[i + 2] as usize - '0' as usize,
                (Some(c), Some('d')) if c.is_ascii_digit() => return Err(PatternError::BadWidth { column, text }),
                _ => return Err(PatternError::Unknown { column, text }),
            };
            if field.is_some() {
                return Err(PatternError::SecondField { column, text });
            }
            field = Some((column, width));
            i = end + 1;
        }
        let Some((column, width)) = field else { return Err(PatternError::NoField) };
        if suffix.contains(std::path::is_separator) {
            return Err(PatternError::InDirectory { column });
        }
        Ok(FramePattern { prefix, width, suffix })
    }

    /// The path of frame `k`.
    pub fn name(&self, k: u32) -> PathBuf {
        PathBuf::from(format!("{}{k:0w$}{}", self.prefix, self.suffix, w = self.width))
    }

    /// The directory every frame is in (`.` for a bare file name).
    pub fn dir(&self) -> PathBuf {
        match self.prefix.rfind(std::path::is_separator) {
            Some(i) => PathBuf::from(&self.prefix[..=i]),
            None => PathBuf::from("."),
        }
    }

    /// The part of the prefix in the file name (after the last separator).
    fn file_prefix(&self) -> &str {
        self.prefix.rsplit(std::path::is_separator).next().unwrap_or("")
    }

    /// What names this animation's manifests: the file name around the
    /// number, without the extension (`f_` for `frames/f_%04d.png`,
    /// `f__left` for `f_%d_left.exr`).
    pub fn stem(&self) -> String {
        let suffix = self.suffix.rsplit_once('.').map_or(self.suffix.as_str(), |(s, _)| s);
        format!("{}{suffix}", self.file_prefix())
    }

    /// The pattern's file name in canonical form (`f_%04d.png`, a literal
    /// `%` written `%%`): what the manifest records.
    pub fn file_pattern(&self) -> String {
        let field = if self.width == 0 { "%d".to_string() } else { format!("%0{}d", self.width) };
        format!("{}{field}{}", self.file_prefix().replace('%', "%%"), self.suffix.replace('%', "%%"))
    }

    /// Whether `file` (a file name without directory) is a name this
    /// pattern gives some frame.
    pub fn matches(&self, file: &str) -> bool {
        let stem = self.prefix.rsplit(std::path::is_separator).next().unwrap_or("");
        let Some(digits) = file.strip_prefix(stem).and_then(|r| r.strip_suffix(self.suffix.as_str())) else { return false };
        let Ok(k) = digits.parse::<u32>() else { return false };
        digits.bytes().all(|b| b.is_ascii_digit()) && format!("{k:0w$}", w = self.width) == digits
    }
}

/// The files one `render` writes.
pub enum Outputs {
    /// One image.
    One(PathBuf),
    /// The frames of `shard` among `n` frames named by a pattern, and
    /// whether the run keeps a manifest next to them.
    Frames { pattern: FramePattern, n: u32, shard: Shard, manifest: bool },
}

impl Outputs {
    /// `-o`, `--frames` and `--shard` as given. A batch run (`--shard` or
    /// `--skip-existing`) keeps a manifest; a plain `--frames` run writes
    /// only its frames, as it always has.
    pub fn new(output: &Path, frames: Option<u32>, shard: Option<Shard>, batch: bool) -> Result<Outputs, CliError> {
        let Some(n) = frames else {
            if shard.is_some() {
                return Err(CliError::Input("--shard applies to --frames only: a single image is not split".into()));
            }
            return Ok(Outputs::One(output.to_path_buf()));
        };
        if !(1..=MAX_FRAMES).contains(&n) {
            return Err(CliError::Input(format!("invalid --frames '{n}': must be between 1 and {MAX_FRAMES}")));
        }
        let Some(pat) = output.to_str() else {
            return Err(CliError::Input(format!("invalid -o pattern '{}': not UTF-8 text", output.display())));
        };
        let manifest = batch || shard.is_some();
        let shard = shard.unwrap_or(Shard::ALL);
        match FramePattern::parse(pat) {
            Ok(pattern) => Ok(Outputs::Frames { pattern, n, shard, manifest }),
            Err(PatternError::NoField) => Err(CliError::Input(format!(
                "with --frames, -o needs a frame-number pattern like frames/f_%04d.png, got '{pat}'"
            ))),
            Err(e) => Err(CliError::Input(format!("invalid -o pattern '{pat}': {e}"))),
        }
    }

    /// How many files this run is responsible for (its shard's frames).
    pub fn len(&self) -> usize {
        self.iter().count()
    }

    /// The frame numbers and paths of this run, in order, made one at a
    /// time (a single image is frame 0).
    pub fn iter(&self) -> Box<dyn Iterator<Item = (u32, PathBuf)> + '_> {
        match self {
            Outputs::One(p) => Box::new(std::iter::once((0, p.clone()))),
            Outputs::Frames { pattern, n, shard, .. } => Box::new(shard.items(*n as usize).map(move |k| (k as u32, pattern.name(k as u32)))),
        }
    }

    /// The manifest of a batch run's shard, next to its frames
    /// ([`manifest::file_name`]); `None` for a single image or a plain
    /// `--frames` run.
    pub fn manifest_path(&self) -> Option<PathBuf> {
        match self {
            Outputs::Frames { pattern, shard, manifest: true, .. } => Some(pattern.dir().join(manifest::file_name(&pattern.stem(), *shard))),
            _ => None,
        }
    }

    /// Checks every file of this run before any rendering: a known format,
    /// a writable directory, no directory in the way, no read-only file to
    /// replace unless `force` (a file `skip_existing` will leave alone may
    /// be read-only). Then removes the stale temporary files of these names
    /// that a killed run left ([`output::remove_stale_temporaries`]).
    pub fn check(&self, force: bool, skip_existing: bool) -> Result<(), CliError> {
        let input = |e: output::OutputError| CliError::Input(e.to_string());
        let first = match self {
            Outputs::One(p) => p.clone(),
            Outputs::Frames { pattern, .. } => pattern.name(0),
        };
        // Every frame has the first one's directory and extension.
        output::format_of(&first).map_err(input)?;
        output::check_writable(&first).map_err(input)?;
        let manifest = self.manifest_path();
        for p in self.iter().map(|(_, p)| p).chain(manifest.clone()) {
            output::check_target(&p).map_err(input)?;
            let left_alone = skip_existing && Some(&p) != manifest.as_ref() && p.is_file();
            if !force && !left_alone {
                output::check_not_read_only(&p).map_err(|e| CliError::Input(format!("{e}: give --force to replace it")))?;
            }
        }
        let dir = match first.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let own = first.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let manifest_name = manifest.as_ref().and_then(|m| m.file_name()).map(|n| n.to_string_lossy().into_owned());
        for p in output::remove_stale_temporaries(dir, |name| match self {
            Outputs::One(_) => name == own,
            Outputs::Frames { pattern, .. } => pattern.matches(name) || Some(name) == manifest_name.as_deref(),
        }) {
            eprintln!("note: removed '{}', a temporary file left by a run that is gone", escape_controls(&p.display().to_string()));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(p: &str, ks: &[u32]) -> Vec<String> {
        let f = FramePattern::parse(p).unwrap();
        ks.iter().map(|&k| f.name(k).display().to_string()).collect()
    }

    #[test]
    fn fields_and_literal_percents() {
        assert_eq!(names("out/f_%04d.png", &[0, 12, 123456]), ["out/f_0000.png", "out/f_0012.png", "out/f_123456.png"]);
        assert_eq!(names("f%d.png", &[0, 999999]), ["f0.png", "f999999.png"]);
        assert_eq!(names("f%%%d.png", &[3]), ["f%3.png"]);
        assert_eq!(names("100%%/f%09d%%.exr", &[7]), ["100%/f000000007%.exr"]);
    }

    #[test]
    fn every_other_conversion_is_an_error_at_its_column() {
        use PatternError::*;
        let cases = [
            ("f.png", NoField),
            ("f%%d.png", NoField),
            ("f%99999d.png", BadWidth { column: 2, text: "%99999d".into() }),
            ("f%4d.png", BadWidth { column: 2, text: "%4d".into() }),
            ("f%00d.png", BadWidth { column: 2, text: "%00d".into() }),
            ("f%010d.png", BadWidth { column: 2, text: "%010d".into() }),
            ("f%d_%d.png", SecondField { column: 5, text: "%d".into() }),
            ("f%x.png", Unknown { column: 2, text: "%x".into() }),
            ("f%.png", Unknown { column: 2, text: "%.".into() }),
            ("f%03.png", Unknown { column: 2, text: "%03.".into() }),
            ("f%04", Unknown { column: 2, text: "%04".into() }),
            ("f%d.png%", Trailing { column: 8 }),
            ("dir%d/f.png", InDirectory { column: 4 }),
        ];
        for (p, e) in cases {
            assert_eq!(FramePattern::parse(p), Err(e), "{p}");
        }
    }

    #[test]
    fn matches_exactly_the_names_it_makes() {
        let f = FramePattern::parse("out/f_%04d.png").unwrap();
        assert!(f.matches("f_0000.png") && f.matches("f_0042.png") && f.matches("f_123456.png"));
        for other in ["f_42.png", "f_00042.png", "g_0000.png", "f_0000.exr", "f_+042.png", "f_.png"] {
            assert!(!f.matches(other), "{other}");
        }
        let f = FramePattern::parse("f%d.png").unwrap();
        assert!(f.matches("f0.png") && f.matches("f10.png") && !f.matches("f010.png"));
    }

    #[test]
    fn directory_stem_and_canonical_file_pattern() {
        let cases = [
            ("frames/f_%04d.png", "frames", "f_", "f_%04d.png"),
            ("f%d_left.exr", ".", "f_left", "f%d_left.exr"),
            ("a/b/%03d.png", "a/b", "", "%03d.png"),
            ("100%%/x%%%d.png", "100%", "x%", "x%%%d.png"),
        ];
        for (p, dir, stem, file) in cases {
            let f = FramePattern::parse(p).unwrap();
            assert_eq!((f.dir(), f.stem(), f.file_pattern()), (PathBuf::from(dir), stem.to_string(), file.to_string()), "{p}");
        }
    }
}

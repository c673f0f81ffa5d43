//! The manifest an animation shard writes next to its frames, and the
//! summary of a set of them.
//!
//! A manifest says which run made which frame: the settings (so frames of
//! different runs are never mixed up), the shard, the device, and per frame
//! its time value, file, status and timings. A summary puts the manifests of
//! all shards together and lists what is complete and what is missing.

use super::merge::{self, check_pair, MergeError, Part};
use super::Shard;
use crate::gpu::DeviceInfo;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a manifest file is (in `NotAPart` messages).
pub const WHAT: &str = "an isotrace frame manifest";

/// Most frames of one animation (`render --frames`). Frames are rendered
/// one after the other, so this bounds a run's length and its manifest,
/// not its memory.
pub const MAX_FRAMES: u32 = 1_000_000;

/// Largest manifest file read. A manifest has one line of about 125 bytes
/// per frame (`f_%04d.png`: 1.25 MB for 10,000 frames; `frame_%06d.png`:
/// 13.2 MB for 100,000), so one shard of [`MAX_FRAMES`] frames writes some
/// 135 MB; the limit leaves room for file names 130 characters longer.
pub const MAX_FILE_BYTES: u64 = 256 << 20;

/// The keys every manifest of one animation shares, in the order that
/// explains a difference best.
const SHARED: [&str; 5] = ["isotrace_version", "settings.formula", "settings.pattern", "settings.frames", "settings"];

/// Parses a manifest's text (`file` names it in messages): a JSON object of
/// the manifest's schema, with a shard `i/n` (0 ≤ i < n) and 1 to
/// [`MAX_FRAMES`] frames.
pub fn parse(file: &str, text: &str) -> Result<Manifest, MergeError> {
    let m: Manifest = merge::parse(file, text, WHAT)?;
    if !(1..=MAX_FRAMES).contains(&m.settings.frames) {
        let reason = format!("settings.frames is {}: an animation has 1 to {MAX_FRAMES} frames", m.settings.frames);
        return Err(MergeError::NotAPart { file: file.to_string(), what: WHAT, reason });
    }
    Ok(m)
}

/// The file name of shard `shard`'s manifest for frames whose names start
/// with `stem` (the pattern's file name without the number and extension:
/// `f_` for `f_%04d.png`): `f_.shard-2-of-4.manifest.json`. With an empty
/// stem (`%04d.png`) it is `frames.shard-2-of-4.manifest.json`.
pub fn file_name(stem: &str, shard: Shard) -> String {
    let stem = if stem.is_empty() { "frames" } else { stem };
    format!("{stem}.shard-{}-of-{}.manifest.json", shard.index, shard.count)
}

/// One shard's record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// The isotrace that wrote it.
    pub isotrace_version: String,
    /// What the frames are (equal in every shard of one animation).
    pub settings: FrameSettings,
    /// Which shard.
    pub shard: Shard,
    /// The device that rendered (`null` when nothing was rendered).
    pub device: Option<DeviceInfo>,
    /// When the run started (UTC, ISO 8601).
    pub started: String,
    /// When it ended; `null` while it runs (or if it was killed).
    pub finished: Option<String>,
    /// This shard's frames, in order.
    pub frames: Vec<FrameEntry>,
}

impl Manifest {
    /// A copy without the frames (cheap for a long animation).
    pub fn clone_without_frames(&self) -> Manifest {
        Manifest {
            isotrace_version: self.isotrace_version.clone(),
            settings: self.settings.clone(),
            shard: self.shard,
            device: self.device.clone(),
            started: self.started.clone(),
            finished: self.finished.clone(),
            frames: vec![],
        }
    }
}

/// The settings of an animation: everything that changes its pictures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameSettings {
    /// Where the formula came from and its text.
    pub formula: FormulaId,
    /// The frame pattern's file name (`f_%04d.png`).
    pub pattern: String,
    /// Frames in the whole animation (all shards).
    pub frames: u32,
    /// t of the first frame.
    pub t0: f64,
    /// t of the last frame.
    pub t1: f64,
    /// Image width and height.
    pub size: [u32; 2],
    /// `bisect` or `sphere`.
    pub method: String,
    /// Bisection's algebra (`ia`, `raa`); `null` for sphere tracing.
    pub algebra: Option<String>,
    /// Absolute termination width.
    pub eps: f64,
    /// The camera.
    pub camera: CameraId,
    /// The domain box.
    #[serde(rename = "box")]
    pub bbox: [f64; 6],
    /// Parameter values, in the formula's order.
    pub params: Vec<f32>,
    /// The clip ball's radius.
    pub clip: Option<f64>,
    /// The colouring (`shade`, `steps`, …).
    pub color: String,
    /// Bisection's iteration budget.
    pub max_iter: u32,
    /// FNV-1a of every other traversal option (modalities, sphere tracing
    /// techniques, inline WGSL): two runs that differ in any are different.
    pub options_fnv1a64: String,
}

/// A formula: its origin (`@water`, a file, `<formula>`) and the FNV-1a of
/// its text.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FormulaId {
    /// Where it came from.
    pub origin: String,
    /// [`super::fnv1a64`] of the text.
    pub text_fnv1a64: String,
}

/// The camera as numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CameraId {
    /// Eye position.
    pub eye: [f64; 3],
    /// Point looked at.
    pub target: [f64; 3],
    /// Up direction.
    pub up: [f64; 3],
    /// Vertical field of view, degrees.
    pub fov_deg: f64,
}

impl From<&crate::render::Camera> for CameraId {
    fn from(c: &crate::render::Camera) -> CameraId {
        CameraId { eye: c.eye.to_array(), target: c.target.to_array(), up: c.up.to_array(), fov_deg: c.fov_deg }
    }
}

/// One frame of a shard.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameEntry {
    /// Frame number in the whole animation.
    pub index: u32,
    /// Its time value t.
    pub t: f64,
    /// Its file name, in the manifest's directory.
    pub file: String,
    /// What this run did with it.
    pub status: FrameStatus,
    /// GPU time of the frame, ms (`null` unless rendered).
    pub gpu_ms: Option<f64>,
    /// Wall time of rendering and writing it, ms (`null` unless rendered).
    pub wall_ms: Option<f64>,
}

/// What a run did with a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FrameStatus {
    /// Rendered and written by this run.
    Rendered,
    /// Its file existed (`--skip-existing`): a complete frame, left alone.
    Skipped,
    /// Not reached (yet): the run is going on, failed or was killed.
    Pending,
}

/// What a set of manifests says about an animation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// The isotrace version of every manifest.
    pub isotrace_version: String,
    /// The settings every manifest shares.
    pub settings: FrameSettings,
    /// The shards whose manifest was given.
    pub shards: Vec<Shard>,
    /// When every manifest has the same shard count: the shards that own
    /// frames and have no manifest.
    pub shards_without_manifest: Vec<Shard>,
    /// Complete frames: a manifest says rendered or skipped and the file
    /// is there and whole. One entry per frame, in order (rendered wins
    /// over skipped).
    pub complete: Vec<FrameEntry>,
    /// Frames a manifest says are done whose file is not counted, and why.
    pub not_counted: Vec<NotCounted>,
    /// Frame numbers that are not complete, in order.
    pub missing: Vec<usize>,
}

impl Summary {
    /// Complete frames this set of runs rendered.
    pub fn rendered(&self) -> usize {
        self.complete.iter().filter(|f| f.status == FrameStatus::Rendered).count()
    }
}

/// A frame a manifest says is done whose file does not count.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct NotCounted {
    /// The manifest.
    pub manifest: String,
    /// The frame number.
    pub index: u32,
    /// The file the manifest names.
    pub file: String,
    /// Why it does not count (`an absolute path, …`, `empty`).
    pub reason: String,
}

/// What is on disk for a frame a manifest says is done.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FrameFile {
    /// A whole frame.
    Present,
    /// Nothing (deleted after its run): the frame is missing.
    Absent,
    /// Something that is not a whole frame of this animation, and why.
    Unusable(String),
}

/// Why a manifest's frame `file` cannot be one of its frames, if so.
/// `render` records a frame by its file name in the manifest's directory;
/// anything else (`/etc/passwd`, `../x.png`, `sub/x.png`) would let a merge
/// count a file elsewhere as a frame.
pub fn foreign_file(file: &str) -> Option<&'static str> {
    if file.starts_with(['/', '\\']) || file.get(1..3) == Some(":\\") {
        Some("an absolute path, not a file in the manifest's directory")
    } else if file.split(['/', '\\']).any(|c| c == "..") || file == "." || file.is_empty() {
        Some("not a file name: it climbs out of the manifest's directory")
    } else if file.contains(['/', '\\']) {
        Some("a path into another directory, not a file in the manifest's directory")
    } else {
        None
    }
}

/// Puts the manifests of an animation together, one at a time: each must
/// share the isotrace version and every setting with the first (the first
/// difference is the error). Only the complete frames are kept, so a merge
/// holds one manifest at a time.
#[derive(Debug, Default)]
pub struct Summarizer {
    /// The first manifest's compared keys and its record without frames.
    first: Option<(Part, Manifest)>,
    done: BTreeMap<u32, FrameEntry>,
    shards: Vec<Shard>,
    not_counted: Vec<NotCounted>,
}

impl Summarizer {
    /// Adds manifest `m` of `file`. `on_disk(name)` says what is on disk
    /// for a frame file name of it (a name [`foreign_file`] accepts), so a
    /// frame deleted or damaged after its run counts as missing.
    pub fn add(&mut self, file: &str, m: Manifest, mut on_disk: impl FnMut(&str) -> FrameFile) -> Result<(), MergeError> {
        let part = Part::new(file, &m.isotrace_version, &m.settings);
        match &self.first {
            None => self.first = Some((part, m.clone_without_frames())),
            Some((first, _)) => check_pair(first, &part, &SHARED, &[])?,
        }
        let n = m.settings.frames as usize;
        for f in m.frames {
            if f.index as usize >= n || !m.shard.contains(f.index as usize) {
                let reason = format!("frame {} is not one of shard {}'s {n} frames", f.index, m.shard);
                return Err(MergeError::Inconsistent { file: file.to_string(), reason });
            }
            let done = matches!(f.status, FrameStatus::Rendered | FrameStatus::Skipped);
            let better = self.done.get(&f.index).is_none_or(|old| old.status == FrameStatus::Skipped && f.status == FrameStatus::Rendered);
            if !(done && better) {
                continue;
            }
            let state = match foreign_file(&f.file) {
                Some(reason) => FrameFile::Unusable(reason.to_string()),
                None => on_disk(&f.file),
            };
            match state {
                FrameFile::Present => {
                    self.done.insert(f.index, f);
                }
                FrameFile::Absent => {}
                FrameFile::Unusable(reason) => self.not_counted.push(NotCounted { manifest: file.to_string(), index: f.index, file: f.file, reason }),
            }
        }
        self.shards.push(m.shard);
        Ok(())
    }

    /// The summary of the manifests added.
    pub fn finish(self) -> Result<Summary, MergeError> {
        let Some((_, first)) = self.first else { return Err(MergeError::Empty) };
        let n = first.settings.frames as usize;
        let mut shards = self.shards;
        shards.sort();
        shards.dedup();
        let count = first.shard.count;
        // Only shards that own a frame (index below the frame count) can
        // be missing: a count past the frames lists no empty shard.
        let shards_without_manifest = if shards.iter().all(|s| s.count == count) {
            (0..count.min(n)).map(|i| Shard { index: i, count }).filter(|s| shards.binary_search(s).is_err()).collect()
        } else {
            vec![]
        };
        let missing = (0..n).filter(|k| !self.done.contains_key(&(*k as u32))).collect();
        Ok(Summary {
            isotrace_version: first.isotrace_version,
            settings: first.settings,
            shards,
            shards_without_manifest,
            complete: self.done.into_values().collect(),
            not_counted: self.not_counted,
            missing,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifest_names_follow_the_pattern_and_the_shard() {
        assert_eq!(file_name("f_", Shard { index: 2, count: 4 }), "f_.shard-2-of-4.manifest.json");
        assert_eq!(file_name("", Shard::ALL), "frames.shard-0-of-1.manifest.json");
    }

    #[test]
    fn only_file_names_in_the_manifests_directory_are_frames() {
        assert_eq!(foreign_file("f_0001.png"), None);
        assert_eq!(foreign_file("..f.png"), None);
        assert_eq!(foreign_file("/etc/passwd"), Some("an absolute path, not a file in the manifest's directory"));
        assert_eq!(foreign_file("C:\\x.png"), Some("an absolute path, not a file in the manifest's directory"));
        assert_eq!(foreign_file("../x"), Some("not a file name: it climbs out of the manifest's directory"));
        assert_eq!(foreign_file(".."), Some("not a file name: it climbs out of the manifest's directory"));
        assert_eq!(foreign_file("a/../../x"), Some("not a file name: it climbs out of the manifest's directory"));
        assert_eq!(foreign_file("sub/x.png"), Some("a path into another directory, not a file in the manifest's directory"));
    }
}

//! The manifest an animation shard writes next to its frames, and the
//! summary of a set of them.
//!
//! A manifest says which run made which frame: the settings (so frames of
//! different runs are never mixed up), the shard, the device, and per frame
//! its time value, file, status and timings. A summary puts the manifests of
//! all shards together and lists what is complete and what is missing.

use super::merge::{check_same, typed, MergeError, Part};
use super::Shard;
use crate::gpu::DeviceInfo;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a manifest file is (in `NotAPart` messages).
pub const WHAT: &str = "an isotrace frame manifest";

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
    /// When every manifest has the same shard count: the shards without one.
    pub shards_without_manifest: Vec<Shard>,
    /// Complete frames: a manifest says rendered or skipped and the file
    /// is there. One entry per frame, in order (rendered wins over skipped).
    pub complete: Vec<FrameEntry>,
    /// Frame numbers that are not complete, in order.
    pub missing: Vec<usize>,
}

impl Summary {
    /// Complete frames this set of runs rendered.
    pub fn rendered(&self) -> usize {
        self.complete.iter().filter(|f| f.status == FrameStatus::Rendered).count()
    }
}

/// Puts manifests together. They must share the isotrace version and every
/// setting (the first difference is the error). `exists(part, file)` says
/// whether `file` of manifest `part` (an index into `parts`) is on disk, so
/// a frame deleted after its run counts as missing.
pub fn summarize(parts: &[Part], exists: impl Fn(usize, &str) -> bool) -> Result<Summary, MergeError> {
    check_same(parts, &["isotrace_version", "settings.formula", "settings.pattern", "settings.frames", "settings"], &[])?;
    let manifests: Vec<Manifest> = parts.iter().map(|p| typed(p, WHAT)).collect::<Result<_, _>>()?;
    let first = &manifests[0];
    let n = first.settings.frames as usize;
    let mut done: BTreeMap<u32, FrameEntry> = BTreeMap::new();
    for (k, (m, p)) in manifests.iter().zip(parts).enumerate() {
        for f in &m.frames {
            if f.index as usize >= n || !m.shard.contains(f.index as usize) {
                let reason = format!("frame {} is not one of shard {}'s {n} frames", f.index, m.shard);
                return Err(MergeError::Inconsistent { file: p.file.clone(), reason });
            }
            let complete = matches!(f.status, FrameStatus::Rendered | FrameStatus::Skipped) && exists(k, &f.file);
            let better = done.get(&f.index).is_none_or(|old| old.status == FrameStatus::Skipped && f.status == FrameStatus::Rendered);
            if complete && better {
                done.insert(f.index, f.clone());
            }
        }
    }
    let mut shards: Vec<Shard> = manifests.iter().map(|m| m.shard).collect();
    shards.sort();
    shards.dedup();
    let count = first.shard.count;
    let shards_without_manifest = if shards.iter().all(|s| s.count == count) {
        (0..count).map(|i| Shard { index: i, count }).filter(|s| !shards.contains(s)).collect()
    } else {
        vec![]
    };
    let missing = (0..n).filter(|k| !done.contains_key(&(*k as u32))).collect();
    Ok(Summary {
        isotrace_version: first.isotrace_version.clone(),
        settings: first.settings.clone(),
        shards,
        shards_without_manifest,
        complete: done.into_values().collect(),
        missing,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifest_names_follow_the_pattern_and_the_shard() {
        assert_eq!(file_name("f_", Shard { index: 2, count: 4 }), "f_.shard-2-of-4.manifest.json");
        assert_eq!(file_name("", Shard::ALL), "frames.shard-0-of-1.manifest.json");
    }
}

//! `render --frames`: the frames of this run's shard, one after the other,
//! each written atomically, and the shard's manifest next to them.
//!
//! With `--skip-existing` a frame whose file is there and whole is left
//! alone: writes are atomic (a temporary file and a rename), so a file this
//! run's command wrote is complete, and a re-queued task only renders what
//! is missing. A file damaged since (cut short, empty, another size) is
//! rendered again ([`crate::batch::frame_check`]).
//!
//! A batch run (`--shard` or `--skip-existing`) keeps a manifest; a plain
//! `--frames` run writes only its frames, as before batch work existed. The
//! manifest is written when the run starts (every frame pending), at most
//! every [`MANIFEST_EVERY`] while it runs, and when it ends, so a task that
//! is killed leaves a record of what it finished.

use super::frames::Outputs;
use super::CliError;
use crate::batch::manifest::{self, CameraId, FormulaId, FrameEntry, FrameSettings, FrameStatus, Manifest};
use crate::batch::merge::{self, check_same, MergeError, Part};
use crate::batch::{fnv1a64, frame_check, one_line, Fnv, Shard};
use crate::gpu::{DeviceInfo, Renderer};
use crate::output::{self, ColorMode};
use crate::render::{Frame, Settings, Traversal};
use crate::Formula;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How often a running animation rewrites its manifest.
pub const MANIFEST_EVERY: Duration = Duration::from_secs(5);

/// An animation's frames: where they go and their time values.
pub struct Animation<'a> {
    /// This run's frames and their manifest.
    pub outputs: &'a Outputs,
    /// Frames in the whole animation.
    pub n: u32,
    /// t of frame 0 and frame n-1.
    pub t0: f64,
    /// See `t0`.
    pub t1: f64,
    /// Leave frames whose file exists.
    pub skip_existing: bool,
    /// What goes into the manifest's `settings`.
    pub settings: FrameSettings,
    /// This run's shard.
    pub shard: Shard,
}

impl Animation<'_> {
    /// t of frame `k`.
    pub fn time(&self, k: u32) -> f64 {
        if self.n > 1 { self.t0 + (self.t1 - self.t0) * k as f64 / (self.n - 1) as f64 } else { self.t0 }
    }

    /// The frames still to render: all of this shard's, or with
    /// `--skip-existing` those whose file is not there or not whole.
    pub fn todo(&self) -> usize {
        self.outputs.iter().filter(|(_, p)| !self.kept(p, false)).count()
    }

    /// Whether frame file `p` is left alone: with `--skip-existing`, when it
    /// is a whole image of this animation's size. A damaged one is rendered
    /// again, and with `say_why` a note says what is wrong with it.
    fn kept(&self, p: &Path, say_why: bool) -> bool {
        if !self.skip_existing || !p.exists() {
            return false;
        }
        let [width, height] = self.settings.size;
        let whole = output::format_of(p).map_err(|e| e.to_string()).and_then(|format| frame_check::check(p, format, width, height));
        if let (Err(reason), true) = (&whole, say_why) {
            eprintln!("note: '{}' is rendered again: {}", one_line(&p.display().to_string()), one_line(reason));
        }
        whole.is_ok()
    }

    /// With `--skip-existing`, the frames already there must be this run's:
    /// when the shard's manifest from an earlier run records other settings
    /// or another isotrace version, keeping its frames would mix two
    /// animations, so that is an error (checked before any GPU work).
    pub fn check_resume(&self) -> Result<(), CliError> {
        let Some(path) = self.outputs.manifest_path().filter(|p| self.skip_existing && p.is_file()) else { return Ok(()) };
        let file = path.display().to_string();
        let read = super::batch::read_part(&path, manifest::MAX_FILE_BYTES, manifest::WHAT).ok();
        let Some(recorded) = read.and_then(|text| merge::parse::<Recorded>(&file, &text, manifest::WHAT).ok()) else {
            return Ok(()); // Unreadable: it is replaced, as before manifests existed.
        };
        let json = serde_json::json!({ "isotrace_version": recorded.isotrace_version, "settings": recorded.settings });
        let parts = [Part { file: file.clone(), json }, Part::new("this run", env!("CARGO_PKG_VERSION"), &self.settings)];
        match check_same(&parts, &["isotrace_version", "settings"], &[]) {
            Err(MergeError::Differs { key, value_a, value_b, .. }) => Err(CliError::Input(format!(
                "--skip-existing: '{file}' records another run ({key} is {value_a} there but {value_b} now): its frames would be kept and mixed \
                 with this run's; remove them (and the manifest), or render to another -o pattern"
            ))),
            _ => Ok(()),
        }
    }

    /// Renders the frames (`renderer` is `None` when [`Animation::todo`]
    /// is 0: no device is opened for nothing) and writes the manifest.
    /// Returns the last rendered frame, for the statistics.
    pub fn run(&self, renderer: Option<(&Renderer, &DeviceInfo)>, s: &Settings, color: ColorMode) -> Result<(Option<Frame>, Option<u32>), CliError> {
        let path = self.outputs.manifest_path();
        let mut m = Manifest {
            isotrace_version: env!("CARGO_PKG_VERSION").into(),
            settings: self.settings.clone(),
            shard: self.shard,
            device: renderer.map(|(_, d)| d.clone()),
            started: crate::bench::utc_now(),
            finished: None,
            frames: self.outputs.iter().map(|(k, p)| entry(k, self.time(k), &p)).collect(),
        };
        write_manifest(&path, &m)?;
        let bar = super::notice::progress(m.frames.len() as u64, "frames");
        let (mut last, mut heat_max, mut written, mut write_took) = (None, None, Instant::now(), Duration::ZERO);
        for (i, (k, p)) in self.outputs.iter().enumerate() {
            if self.kept(&p, true) {
                m.frames[i].status = FrameStatus::Skipped;
            } else if let Some((r, _)) = renderer {
                let start = Instant::now();
                let mut sk = s.clone();
                sk.time = self.time(k);
                let done = r.render(&sk).map_err(super::error::render_error).and_then(|mut frame| {
                    heat_max = output::recolor(&mut frame, color);
                    output::write_frame(&p, &frame).map_err(super::error::output_error)?;
                    Ok(frame)
                });
                let frame = match done {
                    Ok(frame) => frame,
                    Err(e) => {
                        // The record of what was finished, then the error.
                        let _ = write_manifest(&path, &m);
                        return Err(e);
                    }
                };
                let f = &mut m.frames[i];
                (f.status, f.gpu_ms, f.wall_ms) = (FrameStatus::Rendered, Some(frame.stats.gpu_ms), Some(start.elapsed().as_secs_f64() * 1e3));
                last = Some(frame);
            }
            if let Some(b) = &bar {
                b.inc(1);
            }
            // At most every MANIFEST_EVERY, and at most a tenth of the time
            // (a shard of a million frames has a 100 MB manifest).
            if written.elapsed() >= MANIFEST_EVERY.max(10 * write_took) {
                let start = Instant::now();
                write_manifest(&path, &m)?;
                (written, write_took) = (Instant::now(), start.elapsed());
            }
        }
        if let Some(b) = bar {
            b.finish_and_clear();
        }
        m.finished = Some(crate::bench::utc_now());
        write_manifest(&path, &m)?;
        let rendered = m.frames.iter().filter(|f| matches!(f.status, FrameStatus::Rendered)).count();
        let skipped = m.frames.len() - rendered;
        let kept = if skipped > 0 { format!("{skipped} already there, ") } else { String::new() };
        let manifest = path.as_ref().map_or(String::new(), |p| format!(" and the manifest {}", p.display()));
        let what = format!("wrote {rendered} frames{manifest}");
        super::notice::done(&crate::diag::user_text(&what, 400), &format!("{kept}{}", super::notice::size(s.width, s.height)));
        Ok((last, heat_max))
    }
}

/// What an earlier run's manifest records, compared key by key with this
/// run's (its frames are skipped over, not kept).
#[derive(serde::Deserialize)]
struct Recorded {
    #[serde(default)]
    isotrace_version: serde_json::Value,
    #[serde(default)]
    settings: serde_json::Value,
}

/// The manifest's settings: everything that changes the pictures, so the
/// manifests of different runs are never merged. Traversal options beyond
/// method and algebra (modalities, sphere tracing techniques, inline WGSL)
/// are one hash of their `Debug` text.
pub fn frame_settings(f: &Formula, pattern: &str, n: u32, (t0, t1): (f64, f64), s: &Settings, t: &Traversal, color: &str) -> FrameSettings {
    let mut options = Fnv::default();
    let _ = write!(options, "{t:?}|unresolved={:?}", s.unresolved);
    FrameSettings {
        formula: FormulaId { origin: f.origin.clone(), text_fnv1a64: fnv1a64(f.source.as_bytes()) },
        pattern: pattern.to_string(),
        frames: n,
        t0,
        t1,
        size: [s.width, s.height],
        method: t.method().name().to_string(),
        algebra: match t {
            Traversal::Bisect(b) => Some(super::args::algebra_name(b.algebra).to_string()),
            Traversal::Sphere(_) => None,
        },
        eps: s.eps,
        camera: CameraId::from(&s.camera),
        bbox: s.bbox,
        params: s.params.clone(),
        clip: s.clip_sphere,
        color: color.to_string(),
        max_iter: s.max_iter,
        options_fnv1a64: options.hex(),
    }
}

/// Frame `k` before the run reaches it.
fn entry(k: u32, t: f64, p: &Path) -> FrameEntry {
    let file = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    FrameEntry { index: k, t, file, status: FrameStatus::Pending, gpu_ms: None, wall_ms: None }
}

/// Writes the manifest atomically: indented, with one line per frame (a
/// long animation's manifest stays readable and a third of the size).
fn write_manifest(path: &Option<PathBuf>, m: &Manifest) -> Result<(), CliError> {
    let Some(path) = path else { return Ok(()) };
    let head = serde_json::to_string_pretty(&m.clone_without_frames()).unwrap_or_default();
    let lines: Vec<String> = m.frames.iter().map(|f| format!("    {}", serde_json::to_string(f).unwrap_or_default())).collect();
    let frames = if lines.is_empty() { "[]".to_string() } else { format!("[\n{}\n  ]", lines.join(",\n")) };
    let text = match head.rsplit_once("\"frames\": []") {
        Some((a, b)) => format!("{a}\"frames\": {frames}{b}\n"),
        None => head,
    };
    output::write_atomic(path, text.as_bytes()).map_err(|e| CliError::Input(e.to_string()))
}

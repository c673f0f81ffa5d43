//! The JSON report of `isotrace bench`, and merging the reports of shards
//! into the report one run of the whole batch would have written (up to
//! timings, dates and devices).

use super::{JobResult, Outcome};
use crate::batch::merge::{self, check_pair, MergeError, Part};
use crate::batch::{ranges, Shard};
use crate::gpu::DeviceInfo;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a bench report file is (in `NotAPart` messages).
pub const WHAT: &str = "an isotrace bench report";

/// Largest report file read. A report has about 730 bytes per job (`bench
/// --suite all` with three algebras and two ω, 135 jobs: 99 KB), so the
/// limit holds some 90,000 jobs: days of timing, at a second or more a job.
pub const MAX_FILE_BYTES: u64 = 64 << 20;

/// Most jobs of one batch (surfaces × variants). A merge keeps one row per
/// job, so this bounds its memory whatever the lists in a report say.
pub const MAX_JOBS: usize = 1_000_000;

/// The keys every part of one batch shares, in the order that explains a
/// difference best; `settings.shard` is the one setting that differs.
const SHARED: [&str; 4] = ["isotrace_version", "settings.surfaces", "settings.algebras", "settings"];

/// Parses a report's text (`file` names it in messages): a JSON object of
/// the report's schema whose job count is its surfaces × variants, at most
/// [`MAX_JOBS`].
pub fn parse(file: &str, text: &str) -> Result<Report, MergeError> {
    let r: Report = merge::parse(file, text, WHAT)?;
    let s = &r.settings;
    let (surfaces, algebras) = (s.surfaces.len(), s.algebras.len());
    let reason = match surfaces.checked_mul(algebras) {
        _ if s.jobs > MAX_JOBS => format!("settings.jobs is {}: a batch has at most {MAX_JOBS} jobs", s.jobs),
        Some(n) if n == s.jobs => return Ok(r),
        Some(n) => format!("settings.jobs is {} but its {surfaces} surfaces and {algebras} variants make {n} jobs", s.jobs),
        None => format!("its {surfaces} surfaces and {algebras} variants make more than {MAX_JOBS} jobs"),
    };
    Err(MergeError::NotAPart { file: file.to_string(), what: WHAT, reason })
}

/// A bench run's JSON report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// The isotrace that measured.
    pub isotrace_version: String,
    /// When the report was written (UTC, ISO 8601); for a merged report,
    /// the latest of its parts.
    pub date: String,
    /// The device (for a merged report from several devices: its first
    /// part's; every part's is in `merged_from`).
    pub device: DeviceInfo,
    /// CPU threads of the machine.
    pub cpu_threads: usize,
    /// What was measured: equal in every shard of one batch.
    pub settings: ReportSettings,
    /// One row per job, in job order.
    pub results: Vec<JobResult>,
    /// A merged report's parts, in the order given; absent otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub merged_from: Vec<PartInfo>,
}

/// The settings of a bench run. Everything but `shard` must be equal for
/// reports to merge.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReportSettings {
    /// `--field` as given (`compiled` in reports written before it existed).
    #[serde(default = "compiled_field")]
    pub field: String,
    /// The surfaces of the whole batch, in order (before sharding).
    pub surfaces: Vec<String>,
    /// Jobs in the whole batch.
    pub jobs: usize,
    /// Image width and height.
    pub size: [u32; 2],
    /// eps relative to each box's diagonal.
    pub eps_relative: f64,
    /// Timed runs per job.
    pub repeat: u32,
    /// The variant labels (columns).
    pub algebras: Vec<String>,
    /// `--method` as given.
    pub methods: String,
    /// `--omega` as given.
    pub omegas: String,
    /// Sphere tracing's step budget, if given.
    pub max_steps: Option<u32>,
    /// Whether the eps search ran.
    pub find_eps: bool,
    /// This run's shard, `i/n`; `null` for the whole batch.
    pub shard: Option<String>,
}

/// Where a merged report's rows came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartInfo {
    /// The part's file.
    pub file: String,
    /// Its shard.
    pub shard: Option<String>,
    /// Its date.
    pub date: String,
    /// Its device.
    pub device: DeviceInfo,
    /// Its machine's CPU threads.
    pub cpu_threads: usize,
    /// Rows it held.
    pub jobs: usize,
}

/// A merged report, and whether its parts ran on different devices (their
/// timings then compare only within one device).
#[derive(Debug, Clone, PartialEq)]
pub struct Merged {
    /// The report.
    pub report: Report,
    /// Parts from more than one device.
    pub mixed_devices: bool,
}

/// Merges shard reports, one at a time. They must share the isotrace
/// version and every setting but the shard (the first difference is the
/// error, naming the key and both files). A job in several parts (a shard
/// run twice) is kept once: a success over a failure, else the first given.
/// Every job of the batch must be somewhere; the result is in job order.
#[derive(Debug, Default)]
pub struct Merger {
    /// The first report's compared keys and the report without its rows.
    first: Option<(Part, Report)>,
    rows: BTreeMap<usize, JobResult>,
    merged_from: Vec<PartInfo>,
}

impl Merger {
    /// Adds report `r` of `file` ([`parse`] checked its job count).
    pub fn add(&mut self, file: &str, mut r: Report) -> Result<(), MergeError> {
        let part = Part::new(file, &r.isotrace_version, &r.settings);
        if let Some((first, _)) = &self.first {
            check_pair(first, &part, &SHARED, &["settings.shard"])?;
        }
        let results = std::mem::take(&mut r.results);
        // Equal in every part but the shard, now.
        let (surfaces, algebras, jobs) = (&r.settings.surfaces, &r.settings.algebras, r.settings.jobs);
        let shard = r.settings.shard.as_deref().map(Shard::parse).transpose().map_err(|e| inconsistent(file, format!("settings.shard {e}")))?;
        for row in &results {
            // Job k is surface k / algebras and variant k % algebras (surface-major).
            if row.index >= jobs {
                return Err(inconsistent(file, format!("job {} is beyond the batch's {jobs} jobs", row.index)));
            }
            let (surface, algebra) = (&surfaces[row.index / algebras.len()], &algebras[row.index % algebras.len()]);
            if (surface, algebra) != (&row.surface, &row.algebra) {
                let reason = format!("job {} is {} {}, but its settings make it {surface} {algebra}", row.index, row.surface, row.algebra);
                return Err(inconsistent(file, reason));
            }
            if let Some(s) = shard.filter(|s| !s.contains(row.index)) {
                return Err(inconsistent(file, format!("job {} is not in shard {s}", row.index)));
            }
        }
        self.merged_from.push(PartInfo {
            file: file.to_string(),
            shard: r.settings.shard.clone(),
            date: r.date.clone(),
            device: r.device.clone(),
            cpu_threads: r.cpu_threads,
            jobs: results.len(),
        });
        let failed = |r: &JobResult| matches!(r.outcome, Outcome::Failed { .. });
        for row in results {
            if self.rows.get(&row.index).is_none_or(|old| failed(old) && !failed(&row)) {
                self.rows.insert(row.index, row);
            }
        }
        if self.first.is_none() {
            self.first = Some((part, r));
        }
        Ok(())
    }

    /// The merged report.
    pub fn finish(self) -> Result<Merged, MergeError> {
        let Some((_, first)) = self.first else { return Err(MergeError::Empty) };
        let s = &first.settings;
        let missing: Vec<usize> = (0..s.jobs).filter(|k| !self.rows.contains_key(k)).collect();
        if !missing.is_empty() {
            // Named one by one up to 20, then as ranges of indices.
            let job = |k: usize| format!("{k} ({} {})", s.surfaces[k / s.algebras.len()], s.algebras[k % s.algebras.len()]);
            let mut list = missing.iter().take(20).map(|&k| job(k)).collect::<Vec<_>>().join(", ");
            if missing.len() > 20 {
                list.push_str(&format!(", … (all missing jobs: {})", ranges(&missing)));
            }
            return Err(MergeError::Missing { what: "jobs", total: s.jobs, missing, list });
        }
        let mixed_devices = self.merged_from.iter().any(|p| p.device != first.device);
        let report = Report {
            date: self.merged_from.iter().map(|p| p.date.clone()).max().unwrap_or_default(),
            settings: ReportSettings { shard: None, ..first.settings },
            results: self.rows.into_values().collect(),
            merged_from: self.merged_from,
            ..first
        };
        Ok(Merged { mixed_devices, report })
    }
}

fn inconsistent(file: &str, reason: String) -> MergeError {
    MergeError::Inconsistent { file: file.to_string(), reason }
}

fn compiled_field() -> String {
    "compiled".into()
}

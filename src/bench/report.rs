//! The JSON report of `isotrace bench`, and merging the reports of shards
//! into the report one run of the whole batch would have written (up to
//! timings, dates and devices).

use super::{jobs, JobResult, Outcome};
use crate::batch::merge::{check_same, typed, MergeError, Part};
use crate::batch::{ranges, Shard};
use crate::gpu::DeviceInfo;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a bench report file is (in `NotAPart` messages).
pub const WHAT: &str = "an isotrace bench report";

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

/// Merges shard reports. They must share the isotrace version and every
/// setting but the shard (the first difference is the error, naming the
/// key and both files). A job in several parts (a shard run twice) is kept
/// once: a success over a failure, else the first given. Every job of the
/// batch must be somewhere; the result is in job order.
pub fn merge(parts: &[Part]) -> Result<Merged, MergeError> {
    check_same(parts, &["isotrace_version", "settings.surfaces", "settings.algebras", "settings"], &["settings.shard"])?;
    let reports: Vec<Report> = parts.iter().map(|p| typed(p, WHAT)).collect::<Result<_, _>>()?;
    let first = &reports[0];
    let expected = jobs(&first.settings.surfaces, &first.settings.algebras);
    let mut rows: BTreeMap<usize, JobResult> = BTreeMap::new();
    for (r, p) in reports.iter().zip(parts) {
        let shard = r.settings.shard.as_deref().map(Shard::parse).transpose().map_err(|e| inconsistent(p, format!("settings.shard {e}")))?;
        for row in &r.results {
            let Some(job) = expected.get(row.index) else {
                return Err(inconsistent(p, format!("job {} is beyond the batch's {} jobs", row.index, expected.len())));
            };
            if (job.surface.as_str(), job.algebra.as_str()) != (row.surface.as_str(), row.algebra.as_str()) {
                let reason = format!("job {} is {} {}, but its settings make it {} {}", row.index, row.surface, row.algebra, job.surface, job.algebra);
                return Err(inconsistent(p, reason));
            }
            if let Some(s) = shard.filter(|s| !s.contains(row.index)) {
                return Err(inconsistent(p, format!("job {} is not in shard {s}", row.index)));
            }
            let failed = |r: &JobResult| matches!(r.outcome, Outcome::Failed { .. });
            if rows.get(&row.index).is_none_or(|old| failed(old) && !failed(row)) {
                rows.insert(row.index, row.clone());
            }
        }
    }
    let missing: Vec<usize> = (0..expected.len()).filter(|k| !rows.contains_key(k)).collect();
    if !missing.is_empty() {
        // Named one by one up to 20, then as ranges of indices.
        let mut list = missing.iter().take(20).map(|&k| format!("{k} ({} {})", expected[k].surface, expected[k].algebra)).collect::<Vec<_>>().join(", ");
        if missing.len() > 20 {
            list.push_str(&format!(", … (all missing jobs: {})", ranges(&missing)));
        }
        return Err(MergeError::Missing { what: "jobs", total: expected.len(), missing, list });
    }
    let merged_from = reports
        .iter()
        .zip(parts)
        .map(|(r, p)| PartInfo {
            file: p.file.clone(),
            shard: r.settings.shard.clone(),
            date: r.date.clone(),
            device: r.device.clone(),
            cpu_threads: r.cpu_threads,
            jobs: r.results.len(),
        })
        .collect();
    let report = Report {
        isotrace_version: first.isotrace_version.clone(),
        date: reports.iter().map(|r| r.date.clone()).max().unwrap_or_default(),
        device: first.device.clone(),
        cpu_threads: first.cpu_threads,
        settings: ReportSettings { shard: None, ..first.settings.clone() },
        results: rows.into_values().collect(),
        merged_from,
    };
    Ok(Merged { mixed_devices: reports.iter().any(|r| r.device != first.device), report })
}

fn inconsistent(p: &Part, reason: String) -> MergeError {
    MergeError::Inconsistent { file: p.file.clone(), reason }
}

fn compiled_field() -> String {
    "compiled".into()
}

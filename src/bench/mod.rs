//! The benchmark suite's bookkeeping: jobs, variants (method × algebra or
//! over-relaxation factor) and shards, the per-job
//! measurements, the "lowest correct eps" image comparison, the contact
//! sheet, the table / Markdown / JSON reports and merging the reports of
//! shards ([`report`]). The CLI (`isotrace bench`) renders; everything here
//! is pure and tested.

pub mod report;

use crate::batch::Shard;
use crate::render::{Frame, Stats, Status};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// One unit of work: a surface rendered with one variant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Job {
    /// Position in the full job list (before sharding).
    pub index: usize,
    /// Surface name.
    pub surface: String,
    /// The variant's label ([`Variant::label`]): the algebra name (`ia`,
    /// `raa`, `auto`) for bisection, `sphere…` for sphere tracing.
    pub algebra: String,
}

/// How one job renders: bisection with an algebra, or sphere tracing with
/// an over-relaxation factor.
#[derive(Debug, Clone, PartialEq)]
pub enum Variant {
    /// `--method bisect` with this algebra name (`ia`, `raa`, `auto`).
    Bisect(String),
    /// `--method sphere` with this ω (1 = no over-relaxation).
    Sphere(f64),
}

impl Variant {
    /// The job label (a table column, a file name part): the algebra for
    /// bisection; `sphere`, or `sphere-w1.2` when several ω are compared.
    pub fn label(&self, several_omegas: bool) -> String {
        match self {
            Variant::Bisect(a) => a.clone(),
            Variant::Sphere(w) if several_omegas => format!("sphere-w{w}"),
            Variant::Sphere(_) => "sphere".into(),
        }
    }
}

/// Which list of [`variants`] holds a bad entry (the command line maps it to
/// its flag).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VariantList {
    /// Traversals.
    Method,
    /// Algebras of bisection.
    Algebra,
    /// Over-relaxation factors of sphere tracing.
    Omega,
}

/// A bad entry of a variant list.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid {list:?} '{value}': expected {expected}")]
pub struct VariantError {
    /// The list.
    pub list: VariantList,
    /// The entry.
    pub value: String,
    /// What the list takes.
    pub expected: &'static str,
}

/// The variants of the method, algebra and ω lists: for each method in
/// order, every algebra (bisect) or every ω (sphere); the algebra only
/// matters for bisection. Unknown names are errors.
pub fn variants(methods: &str, algebras: &str, omegas: &str) -> Result<Vec<Variant>, VariantError> {
    let list = |s: &str| s.split(',').map(str::trim).map(str::to_string).collect::<Vec<_>>();
    let bad = |list, value: String, expected| Err(VariantError { list, value, expected });
    let mut v = Vec::new();
    for m in list(methods) {
        match m.as_str() {
            "bisect" => {
                for a in list(algebras) {
                    if !matches!(a.as_str(), "ia" | "raa" | "auto") {
                        return bad(VariantList::Algebra, a, "a comma-separated list of ia, raa, auto");
                    }
                    v.push(Variant::Bisect(a));
                }
            }
            "sphere" => {
                for w in list(omegas) {
                    match w.parse::<f64>() {
                        Ok(x) if (1.0..2.0).contains(&x) => v.push(Variant::Sphere(x)),
                        _ => return bad(VariantList::Omega, w, "a comma-separated list of factors in [1, 2)"),
                    }
                }
            }
            _ => return bad(VariantList::Method, m, "a comma-separated list of sphere, bisect"),
        }
    }
    Ok(v)
}

/// All jobs: every surface with every algebra, surface-major.
pub fn jobs(surfaces: &[String], algebras: &[String]) -> Vec<Job> {
    let mut v = Vec::new();
    for s in surfaces {
        for a in algebras {
            v.push(Job { index: v.len(), surface: s.clone(), algebra: a.clone() });
        }
    }
    v
}

/// The jobs of a shard: every n-th job starting at i (the rule every
/// shard of isotrace follows, [`Shard::contains`]), so shards are balanced
/// and together cover every job exactly once.
pub fn shard(all: &[Job], shard: Shard) -> Vec<Job> {
    all.iter().filter(|j| shard.contains(j.index)).cloned().collect()
}

/// What one job measured.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Measure {
    /// Median GPU time over the timed runs, ms.
    pub gpu_ms: f64,
    /// Median GPU time of the tile pass alone (part of `gpu_ms`), ms.
    pub tile_ms: f64,
    /// 1000 / gpu_ms.
    pub fps: f64,
    /// Median wall time of a frame (dispatch + read-back), ms.
    pub wall_ms: f64,
    /// Inclusion evaluations per pixel.
    pub evals_mean: f64,
    /// 99th percentile.
    pub evals_p99: u32,
    /// Maximum.
    pub evals_max: u32,
    /// The work lower bound per pixel (see [`crate::render::BisectStats::evals_lower_bound`]).
    pub lower_bound: f64,
    /// evals_mean / lower_bound.
    pub ratio: f64,
    /// Pixels that ran out of iterations.
    pub unresolved: u64,
    /// Fraction of pixels that hit.
    pub hit_fraction: f64,
    /// Bisection depth for the box diagonal.
    pub d_max: u32,
    /// Absolute eps used.
    pub eps: f64,
    /// The algebra actually used (auto resolves to ia or raa).
    pub resolved_algebra: String,
    /// With `--find-eps`: the coarsest matching eps (relative to the box
    /// diagonal, as a power of two exponent) and the GPU ms there.
    pub lowest_eps: Option<LowestEps>,
    /// `bisect` or `sphere`. With sphere tracing the `evals` figures are
    /// marching steps per pixel and there is no lower bound (0).
    pub method: String,
    /// Sphere tracing: the over-relaxation factor.
    pub omega: Option<f64>,
    /// Mean evaluations (steps) of the pixels that hit.
    pub evals_hit_mean: f64,
    /// Sphere tracing: failed over-relaxed steps that fell back, per pixel.
    pub sor_fallbacks_per_pixel: f64,
    /// Wall time from the start of building the pipeline to the end of the
    /// warm-up frame, ms: naga validation, the driver's shader compilation
    /// (seconds on a cold Mesa shader cache) and one frame. Not part of
    /// `gpu_ms` or `wall_ms`, which are measured after the warm-up. 0 in
    /// reports written before it existed.
    #[serde(default)]
    pub setup_ms: f64,
    /// The field source the job ran on (`compiled`, `tape`, `scene`;
    /// `--field auto` decides per surface). `compiled` in reports written
    /// before it existed.
    #[serde(default = "compiled")]
    pub field: String,
}

fn compiled() -> String {
    "compiled".into()
}

/// Result of the "lowest correct eps" search.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct LowestEps {
    /// k in eps = 2^k × diagonal.
    pub exponent: i32,
    /// GPU ms at that eps (median).
    pub gpu_ms: f64,
    /// Fraction of pixels that differed from the reference there.
    pub differing: f64,
}

impl Measure {
    /// Summarises timed runs of one job.
    pub fn from_runs(runs: &[Stats], eps: f64, resolved_algebra: &str) -> Measure {
        let med = |f: &dyn Fn(&Stats) -> f64| {
            let mut v: Vec<f64> = runs.iter().map(f).collect();
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied().unwrap_or(0.0)
        };
        let s = runs.last().cloned().unwrap_or_default();
        let gpu_ms = med(&|s| s.gpu_ms);
        Measure {
            gpu_ms,
            tile_ms: med(&|s| s.tile_ms),
            fps: if gpu_ms > 0.0 { 1000.0 / gpu_ms } else { 0.0 },
            wall_ms: med(&|s| s.wall_ms),
            evals_mean: s.evals_mean,
            evals_p99: s.evals_p99,
            evals_max: s.evals_max,
            lower_bound: s.bisect.evals_lower_bound,
            ratio: if s.bisect.evals_lower_bound > 0.0 { s.evals_mean / s.bisect.evals_lower_bound } else { 0.0 },
            unresolved: s.unresolved,
            hit_fraction: s.hits as f64 / s.pixels.max(1) as f64,
            d_max: s.bisect.d_max,
            eps,
            resolved_algebra: resolved_algebra.to_string(),
            lowest_eps: None,
            method: s.method.name().to_string(),
            omega: None,
            evals_hit_mean: s.evals_hit_mean,
            sor_fallbacks_per_pixel: s.sphere.sor_fallbacks as f64 / s.pixels.max(1) as f64,
            setup_ms: 0.0,
            field: compiled(),
        }
    }
}

/// One row of the report.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct JobResult {
    /// The job's position in the whole batch ([`Job::index`]): merged
    /// reports are put in this order.
    pub index: usize,
    /// Surface name.
    pub surface: String,
    /// Degree as the catalog states it.
    pub degree: String,
    /// Algebra asked for.
    pub algebra: String,
    /// The measurement, or why the job failed.
    #[serde(flatten)]
    pub outcome: Outcome,
}

/// A job's outcome.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Outcome {
    /// It ran.
    Ok(Measure),
    /// It failed; the batch went on.
    Failed {
        /// The error message.
        error: String,
    },
}

/// Tolerance of the image comparison used by `--find-eps`: a pixel differs
/// when a colour channel differs by more than [`PIXEL_TOLERANCE`] (8-bit
/// sRGB) or its hit status differs; two images match when at most
/// [`MATCH_FRACTION`] of the pixels differ.
pub const PIXEL_TOLERANCE: u8 = 16;
/// See [`PIXEL_TOLERANCE`].
pub const MATCH_FRACTION: f64 = 0.005;

/// Fraction of differing pixels between two frames of the same size.
pub fn differing_fraction(a: &Frame, b: &Frame) -> f64 {
    let rgb_a = crate::output::frame_rgb8(a);
    let rgb_b = crate::output::frame_rgb8(b);
    let n = a.pixels.len().max(1);
    let diff = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .enumerate()
        .filter(|(k, (p, q))| {
            (p.status == Status::Hit) != (q.status == Status::Hit)
                || (0..3).any(|c| rgb_a[3 * k + c].abs_diff(rgb_b[3 * k + c]) > PIXEL_TOLERANCE)
        })
        .count();
    diff as f64 / n as f64
}

/// A grid of labelled thumbnails (RGB8), `cols` per row, each `cell` pixels
/// square (images are resampled by nearest neighbour), with the label
/// drawn in an 8×8 bitmap font under each cell.
pub fn contact_sheet(images: &[(String, u32, u32, Vec<u8>)], cell: u32, cols: u32) -> (u32, u32, Vec<u8>) {
    let cols = cols.max(1).min(images.len().max(1) as u32);
    let rows = (images.len() as u32).div_ceil(cols).max(1);
    let label_h = 20;
    let (w, h) = (cols * cell, rows * (cell + label_h));
    let mut out = vec![24u8; (w * h * 3) as usize];
    for (k, (label, iw, ih, rgb)) in images.iter().enumerate() {
        let (cx, cy) = ((k as u32 % cols) * cell, (k as u32 / cols) * (cell + label_h));
        let scale = (*iw).max(*ih) as f64 / cell as f64;
        for y in 0..cell {
            for x in 0..cell {
                let (sx, sy) = ((x as f64 * scale) as u32, (y as f64 * scale) as u32);
                if sx < *iw && sy < *ih {
                    let s = ((sy * iw + sx) * 3) as usize;
                    let d = (((cy + y) * w + cx + x) * 3) as usize;
                    out[d..d + 3].copy_from_slice(&rgb[s..s + 3]);
                }
            }
        }
        draw_text(&mut out, w, cx + 4, cy + cell + 6, label, cell - 8);
    }
    (w, h, out)
}

fn draw_text(img: &mut [u8], w: u32, x0: u32, y0: u32, text: &str, max_w: u32) {
    for (i, ch) in text.chars().enumerate() {
        let x = x0 + 8 * i as u32;
        if x + 8 > x0 + max_w {
            break;
        }
        let glyph = font8x8::legacy::BASIC_LEGACY.get(ch as usize).copied().unwrap_or([0; 8]);
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8 {
                if bits >> col & 1 == 1 {
                    let d = (((y0 + row as u32) * w + x + col) * 3) as usize;
                    if d + 3 <= img.len() {
                        img[d..d + 3].copy_from_slice(&[235, 235, 235]);
                    }
                }
            }
        }
    }
}

fn cell(r: &JobResult) -> String {
    match &r.outcome {
        Outcome::Ok(m) if m.field != "compiled" => format!("{} {:.1} ms / {:.2} ev", shown(&m.field), m.gpu_ms, m.evals_mean),
        Outcome::Ok(m) => format!("{:.1} ms / {:.2} ev", m.gpu_ms, m.evals_mean),
        Outcome::Failed { .. } => "FAILED".to_string(),
    }
}

/// Rows of (surface, degree, one cell per algebra), surface order kept. A
/// row or a column is found by name in a map, not by a search: a merged
/// report may hold many thousand surfaces, or columns. A result whose
/// algebra is no column is left out.
fn grid<'a>(results: &'a [JobResult], algebras: &[String]) -> Vec<(String, String, Vec<Option<&'a JobResult>>)> {
    let columns: HashMap<&str, usize> = algebras.iter().enumerate().rev().map(|(k, a)| (a.as_str(), k)).collect();
    let mut row_of: HashMap<&str, usize> = HashMap::new();
    let mut rows: Vec<(String, String, Vec<Option<&JobResult>>)> = Vec::new();
    for r in results {
        let Some(&col) = columns.get(r.algebra.as_str()) else { continue };
        let row = *row_of.entry(r.surface.as_str()).or_insert_with(|| {
            rows.push((r.surface.clone(), r.degree.clone(), vec![None; algebras.len()]));
            rows.len() - 1
        });
        rows[row].2[col] = Some(r);
    }
    rows
}

/// What a column's work figure counts: sphere tracing columns count steps.
fn unit(label: &str) -> &'static str {
    if label.starts_with("sphere") { "steps/px" } else { "evals/px" }
}

/// The plain-text table (Knoll et al.'s Table 1 shape: surface, degree, one
/// column per algebra with GPU ms and evaluations per pixel; sphere tracing
/// columns give steps per pixel).
pub fn table_text(results: &[JobResult], algebras: &[String]) -> String {
    table(results, algebras, false)
}

/// [`table_text`] with, after each algebra's column, the result of
/// `--find-eps`: the coarsest matching eps and the GPU ms there (`none`
/// when no eps of the search matched the reference, `-` for a sphere
/// tracing or failed job).
pub fn table_text_with_eps(results: &[JobResult], algebras: &[String]) -> String {
    table(results, algebras, true)
}

fn lowest_eps_cell(r: &JobResult) -> String {
    match &r.outcome {
        Outcome::Ok(m) if m.method == "sphere" => "-".into(),
        Outcome::Ok(m) => m.lowest_eps.as_ref().map_or("none".into(), |l| format!("2^{} ({:.1} ms)", l.exponent, l.gpu_ms)),
        Outcome::Failed { .. } => "-".into(),
    }
}

/// Text of a report (which `bench --merge` reads from files) as one table
/// cell: on one line, control characters visible.
fn shown(s: &str) -> String {
    crate::batch::one_line(s)
}

/// [`shown`] for a Markdown table, with `|` escaped so a cell stays one.
fn md(s: &str) -> String {
    shown(s).replace('|', "\\|")
}

fn table(results: &[JobResult], algebras: &[String], eps: bool) -> String {
    let mut s = format!("{:<16} {:<10}", "surface", "degree");
    for a in algebras.iter().map(|a| shown(a)) {
        s.push_str(&format!(" {:>24}", format!("{a} (ms / {})", unit(&a))));
        if eps {
            s.push_str(&format!(" {:>18}", format!("{a} lowest eps")));
        }
    }
    s.push('\n');
    for (surface, degree, cells) in grid(results, algebras) {
        let (surface, deg): (String, String) = (shown(&surface), shown(&degree).chars().take(10).collect());
        s.push_str(&format!("{surface:<16} {deg:<10}"));
        for c in cells {
            s.push_str(&format!(" {:>24}", c.map(cell).unwrap_or_else(|| "-".into())));
            if eps {
                s.push_str(&format!(" {:>18}", c.map(lowest_eps_cell).unwrap_or_else(|| "-".into())));
            }
        }
        s.push('\n');
    }
    for r in results {
        if let Outcome::Failed { error } = &r.outcome {
            s.push_str(&format!("FAILED {} {}: {}\n", shown(&r.surface), shown(&r.algebra), shown(error.lines().next().unwrap_or(""))));
        }
    }
    s
}

/// The Markdown report: the summary table and a detail table per job.
pub fn markdown(results: &[JobResult], algebras: &[String], machine: &str) -> String {
    let mut s = format!("Machine: {}\n\n| surface | degree |", shown(machine));
    for a in algebras.iter().map(|a| md(a)) {
        s.push_str(&format!(" {a} ms | {a} fps | {a} {} |", unit(&a)));
    }
    s.push_str("\n|---|---|");
    s.push_str(&"---:|---:|---:|".repeat(algebras.len()));
    s.push('\n');
    for (surface, degree, cells) in grid(results, algebras) {
        s.push_str(&format!("| {} | {} |", md(&surface), md(&degree)));
        for c in cells {
            match c.map(|r| &r.outcome) {
                Some(Outcome::Ok(m)) => s.push_str(&format!(" {:.1} | {:.1} | {:.2} |", m.gpu_ms, m.fps, m.evals_mean)),
                Some(Outcome::Failed { .. }) => s.push_str(" FAILED | | |"),
                None => s.push_str(" - | - | - |"),
            }
        }
        s.push('\n');
    }
    s.push_str("\n| surface | algebra | used | GPU ms | wall ms | evals/px mean | p99 | max | lower bound | ratio | hits | unresolved | d_max | lowest eps (ms) |\n");
    s.push_str("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    for r in results {
        match &r.outcome {
            Outcome::Ok(m) => s.push_str(&format!(
                "| {} | {} | {} | {:.1} | {:.1} | {:.2} | {} | {} | {:.2} | {:.2} | {:.1} % | {} | {} | {} |\n",
                md(&r.surface), md(&r.algebra), md(&if m.field == "compiled" { m.resolved_algebra.clone() } else { format!("{}, {}", m.resolved_algebra, m.field) }), m.gpu_ms, m.wall_ms, m.evals_mean, m.evals_p99, m.evals_max,
                m.lower_bound, m.ratio, 100.0 * m.hit_fraction, m.unresolved, m.d_max,
                m.lowest_eps.as_ref().map_or("-".to_string(), |l| format!("2^{} ({:.1} ms)", l.exponent, l.gpu_ms))
            )),
            Outcome::Failed { error } => s.push_str(&format!("| {} | {} | FAILED: {} |||||||||||\n", md(&r.surface), md(&r.algebra), md(error.lines().next().unwrap_or("")))),
        }
    }
    s
}

/// Today's date and time in UTC, ISO 8601 (from the system clock).
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Civil-from-days (proleptic Gregorian), H. Hinnant's algorithm.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", rem / 3600, rem % 3600 / 60, rem % 60)
}

//! `isotrace bench`: renders surfaces × methods × algebras (bisection) or
//! over-relaxation factors (sphere tracing) with a warm-up and timed
//! repeats, and reports a Knoll-style table, JSON and Markdown, images and a
//! contact sheet. A failing job is reported and the batch goes on.

use super::args::{algebra_arg, algebra_name, open_gpu, resolve_algebra, sphere_options, AlgebraArg, SphereArgs};
use super::CliError;
use clap::Args;
use crate::batch::merge::MergeError;
use crate::batch::one_line;
use crate::bench::report::{self, Merger, Report, ReportSettings};
use crate::bench::{self, JobResult, LowestEps, Measure, Outcome, Variant};
use crate::catalog::{self, Entry};
use crate::gpu::{Gpu, Renderer};
use crate::render::record::PackedFrame;
use crate::render::{BisectOptions, Settings, Traversal};
use crate::output;
use crate::render::Frame;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Surfaces: catalog names or .iso files (default: the Knoll suite).
    #[arg(value_name = "NAME|FILE")]
    surfaces: Vec<String>,
    /// A predefined suite: knoll (Table 1 of Knoll et al.), sdf (the distance-field scenes), all (the whole catalog), or scenes (Zanni et al.'s generated blobtree series through the scene field, sparse and dense; takes --size, --repeat, --max-steps, --max-level, --json, --markdown).
    #[arg(long, value_name = "SUITE")]
    suite: Option<String>,
    /// With --suite scenes: the highest level of each generated series (0-4; default 3: up to 11,110 aggregate primitives, 1,024 boxes, 1,536 sphere pairs).
    #[arg(long, value_name = "L")]
    max_level: Option<u32>,
    /// Image size `WxH` or `N`.
    #[arg(long, default_value = "1024")]
    size: String,
    /// Termination width relative to each surface's box diagonal (2^-11 = the render default).
    #[arg(long, default_value = "2^-11")]
    eps: String,
    /// Comma-separated algebras for --method bisect: ia, raa, auto.
    #[arg(long, default_value = "ia,raa,auto")]
    algebra: String,
    /// Comma-separated traversals: bisect, sphere (jobs = surfaces x methods x algebras or omegas).
    #[arg(long, default_value = "bisect")]
    method: String,
    /// Comma-separated over-relaxation factors for --method sphere, e.g. 1,1.2 (1 is off).
    #[arg(long, default_value = "1.2")]
    omega: String,
    /// Step budget per ray for --method sphere (default 512).
    #[arg(long, value_name = "N")]
    max_steps: Option<u32>,
    /// Field source of every job, as `render --field`: compiled (the default), tape, scene (formulas of distance forms, sphere tracing) or auto (chosen per surface and method). The table names any source but compiled in its cells; the JSON and Markdown reports name it per job.
    #[arg(long, value_enum, value_name = "SOURCE")]
    field: Option<super::args::FieldArg>,
    /// Timed runs per job (after one warm-up run); the median is reported. Building the pipeline and the warm-up run, where a cold Mesa shader cache compiles the shader, are not in the reported ms; their wall time is the JSON's setup_ms.
    #[arg(long, default_value_t = 5)]
    repeat: u32,
    /// Directory for the images and the contact sheet.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Write the results as JSON.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Write the results as Markdown.
    #[arg(long, value_name = "FILE")]
    markdown: Option<PathBuf>,
    /// Also find the coarsest eps whose image matches a fine-eps reference (Knoll's last column; bisection jobs only).
    #[arg(long)]
    find_eps: bool,
    /// Fail a job that takes longer than SECONDS (pipeline build and shader compilation included) and go on with the batch. Each job then runs in a child process of isotrace, killed at the deadline.
    #[arg(long, value_name = "SECONDS")]
    job_timeout: Option<f64>,
    /// Run only the job with this index (of the whole batch) and print its outcome as JSON: the child process of --job-timeout.
    #[arg(long, hide = true, value_name = "INDEX")]
    run_job: Option<usize>,
    /// Whether a CPU driver optimises the kernels, as `render --shader-opt`; by default full, since the table reports frames (none: the frames of generated fields run 1.5-2x slower, after a 2-3x sooner compile).
    #[arg(long, value_enum, value_name = "OPT")]
    shader_opt: Option<super::args::ShaderOptArg>,
    #[command(flatten)]
    shard: super::batch::ShardArgs,
    /// Merge the JSON reports of shards (written with --json) into one report instead of running jobs: the table on stdout, and --json / --markdown as a single run would write them. A quoted wildcard in a file name is expanded.
    #[arg(long, value_name = "REPORT", num_args = 1.., conflicts_with_all = ["surfaces", "suite", "shard", "out", "find_eps", "size", "eps", "algebra", "method", "omega", "max_steps", "repeat", "job_timeout", "shader_opt"])]
    merge: Vec<PathBuf>,
}

/// `--suite scenes`: flags of catalog jobs are refused, not ignored.
fn scenes(a: &BenchArgs) -> Result<ExitCode, CliError> {
    let misplaced = [
        (!a.surfaces.is_empty(), "surface names"),
        (a.find_eps, "--find-eps"),
        (a.out.is_some(), "--out"),
        (a.job_timeout.is_some(), "--job-timeout"),
        (a.shard.shard.is_some(), "--shard"),
    ];
    if let Some((_, flag)) = misplaced.iter().find(|(given, _)| *given) {
        return Err(CliError::input(format!("{flag} does not apply to --suite scenes")));
    }
    if a.repeat == 0 {
        return Err(CliError::input("--repeat must be at least 1"));
    }
    let size = super::args::parse_size(&a.size)?;
    let opt = super::args::shader_opt(a.shader_opt, 0, false);
    super::bench_scenes::run(size, a.repeat, a.max_steps, a.max_level.unwrap_or(3), a.json.as_deref(), a.markdown.as_deref(), opt)
}

/// The jobs' variants with their labels (a bad list entry names its flag).
fn labelled_variants(a: &BenchArgs) -> Result<Vec<(String, Variant)>, CliError> {
    let variants = bench::variants(&a.method, &a.algebra, &a.omega).map_err(|e| {
        let flag = match e.list {
            bench::VariantList::Method => "--method",
            bench::VariantList::Algebra => "--algebra",
            bench::VariantList::Omega => "--omega",
        };
        CliError::input(format!("invalid {flag} '{}': expected {}", e.value, e.expected))
    })?;
    let several = variants.iter().filter(|v| matches!(v, Variant::Sphere(_))).count() > 1;
    Ok(variants.iter().map(|v| (v.label(several), v.clone())).collect())
}


fn entries(a: &BenchArgs) -> Result<Vec<Entry>, CliError> {
    // With neither names nor a suite, the Knoll suite.
    let suite = a.suite.as_deref().or(a.surfaces.is_empty().then_some("knoll"));
    let mut names: Vec<String> = match suite {
        None => vec![],
        Some(s) => {
            let names = catalog::suite(s).map_err(|_| CliError::input(format!("unknown --suite '{s}': expected {}", catalog::suite_choices())))?;
            names.into_iter().map(String::from).collect()
        }
    };
    names.extend(a.surfaces.iter().cloned());
    names
        .iter()
        .map(|n| {
            let r = if n.ends_with(".iso") { catalog::load_file(n) } else { catalog::lookup(n.trim_start_matches('@')) };
            r.map_err(|e| CliError::input(e.to_string()))
        })
        .collect()
}

fn algebra(a: &str) -> AlgebraArg {
    match a {
        "ia" => AlgebraArg::Ia,
        "raa" => AlgebraArg::Raa,
        _ => AlgebraArg::Auto,
    }
}

pub fn run(a: BenchArgs) -> Result<ExitCode, CliError> {
    if !a.merge.is_empty() {
        return merge(&a);
    }
    if a.suite.as_deref() == Some("scenes") {
        return scenes(&a);
    }
    if a.max_level.is_some() {
        return Err(CliError::input("--max-level applies to --suite scenes"));
    }
    let surfaces = entries(&a)?;
    let labelled = labelled_variants(&a)?;
    if let Some(n) = a.max_steps {
        crate::render::SphereOptions { max_steps: n, ..Default::default() }.check().map_err(|e| CliError::input(super::error::settings_message(&e)))?;
    }
    let size = super::args::parse_size(&a.size)?;
    let rel_eps = catalog::parse_eps(&a.eps).map_err(|m| CliError::input(format!("invalid --eps '{}': {m}", a.eps)))?;
    if a.repeat == 0 {
        return Err(CliError::input("--repeat must be at least 1"));
    }
    let names: Vec<String> = surfaces.iter().map(|e| e.name.clone()).collect();
    let alg_names: Vec<String> = labelled.iter().map(|(n, _)| n.clone()).collect();
    if names.len().checked_mul(alg_names.len()).is_none_or(|n| n > report::MAX_JOBS) {
        return Err(CliError::input(format!(
            "{} surfaces and {} variants make more than {} jobs, the most one batch (and its report) holds; split the surfaces into several runs",
            names.len(),
            alg_names.len(),
            report::MAX_JOBS
        )));
    }
    let all_jobs = bench::jobs(&names, &alg_names);
    let timeout = job_timeout(a.job_timeout)?;
    let job_of = |job: &bench::Job| {
        let entry = &surfaces[names.iter().position(|n| *n == job.surface).unwrap_or(0)];
        let variant = labelled.iter().find(|(n, _)| *n == job.algebra).map(|(_, v)| v.clone()).unwrap_or(Variant::Bisect("auto".into()));
        (entry, variant)
    };
    if let Some(index) = a.run_job {
        let job = all_jobs.iter().find(|j| j.index == index).ok_or_else(|| CliError::input(format!("no job {index} in this batch")))?;
        let (entry, variant) = job_of(job);
        return run_child_job(&a, job, entry, &variant, size, rel_eps);
    }
    let shard = a.shard.resolve()?;
    let jobs = shard.map_or_else(|| all_jobs.clone(), |s| bench::shard(&all_jobs, s));
    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir).map_err(|e| CliError::input(format!("cannot create --out directory '{}': {e}", dir.display())))?;
        output::check_writable(&dir.join("probe.png")).map_err(|e| CliError::input(format!("--out directory is not writable: {e}")))?;
    }
    for p in [&a.json, &a.markdown].into_iter().flatten() {
        output::check_writable(p).map_err(|e| CliError::input(e.to_string()))?;
    }
    let gpu = open_gpu(super::args::shader_opt(a.shader_opt, 0, false))?;
    let (results, thumbs) = run_jobs(&a, &gpu, &jobs, job_of, timeout, size, rel_eps)?;
    if let Some(dir) = &a.out {
        if !thumbs.is_empty() {
            let (w, h, rgb) = bench::contact_sheet(&thumbs, 256, 4);
            output::write_png(&dir.join("contact-sheet.png"), w, h, &rgb).map_err(|e| CliError::input(e.to_string()))?;
        }
    }
    let settings = ReportSettings {
        surfaces: names,
        jobs: all_jobs.len(),
        size: [size.0, size.1],
        eps_relative: rel_eps,
        repeat: a.repeat,
        algebras: alg_names,
        field: a.field.map_or("compiled", |f| super::args::field_kind(f).name()).into(),
        methods: a.method.clone(),
        omegas: a.omega.clone(),
        max_steps: a.max_steps,
        find_eps: a.find_eps,
        shard: shard.map(|s| s.to_string()),
    };
    let report = report(settings, results, &gpu);
    write_reports(&a, &report, &machine(&report.device, report.cpu_threads))
}

/// `--job-timeout SECONDS` as a duration (positive, finite, at most a day).
fn job_timeout(s: Option<f64>) -> Result<Option<Duration>, CliError> {
    match s {
        None => Ok(None),
        Some(t) if t.is_finite() && t > 0.0 && t <= 86_400.0 => Ok(Some(Duration::from_secs_f64(t))),
        Some(t) => Err(CliError::input(format!("invalid --job-timeout {t}: it must be a number of seconds above 0 and at most 86400"))),
    }
}

/// A surface's first image, kept for the contact sheet: name, width,
/// height, RGB bytes.
type Thumb = (String, u32, u32, Vec<u8>);

/// Runs this shard's jobs (each in a child process under `timeout`, if
/// given), reporting progress, writing each image to `--out` and keeping
/// each surface's first image for the contact sheet.
fn run_jobs<'e>(a: &BenchArgs, gpu: &Gpu, jobs: &[bench::Job], job_of: impl Fn(&bench::Job) -> (&'e Entry, Variant), timeout: Option<Duration>, size: (u32, u32), rel_eps: f64) -> Result<(Vec<JobResult>, Vec<Thumb>), CliError> {
    let bar = super::notice::progress(jobs.len() as u64, "jobs");
    let mut results = Vec::new();
    let mut thumbs: Vec<Thumb> = Vec::new();
    for (k, job) in jobs.iter().enumerate() {
        let (entry, variant) = job_of(job);
        let (outcome, frame) = match timeout {
            Some(t) => (run_job_isolated(job.index, t), None),
            None => match run_job(gpu, entry, &variant, size, rel_eps, a) {
                Ok((m, f)) => (Outcome::Ok(m), Some(f)),
                Err(e) => (Outcome::Failed { error: e }, None),
            },
        };
        let line = match &outcome {
            Outcome::Ok(m) if m.method == "sphere" => format!("{:.1} ms, {:.2} steps/px ({:.2} per hit), {} unconverged", m.gpu_ms, m.evals_mean, m.evals_hit_mean, m.unresolved),
            Outcome::Ok(m) => format!("{:.1} ms, {:.2} evals/px ({:.2}x bound)", m.gpu_ms, m.evals_mean, m.ratio),
            Outcome::Failed { error } => format!("FAILED: {}", error.lines().next().unwrap_or("")),
        };
        match &bar {
            Some(b) => {
                b.set_message(format!("{} {}", one_line(&job.surface), job.algebra));
                b.inc(1);
            }
            None => eprintln!("[{}/{}] {} {}: {}", k + 1, jobs.len(), one_line(&job.surface), job.algebra, one_line(&line)),
        }
        if let Some(dir) = &a.out {
            keep_image(dir, job, frame.as_ref(), matches!(outcome, Outcome::Ok(_)), &mut thumbs)?;
        }
        let degree = entry.header.degree.clone().unwrap_or_else(|| entry.compile().ok().and_then(|f| f.ir.degree()).map_or("-".into(), |d| d.to_string()));
        results.push(JobResult { index: job.index, surface: job.surface.clone(), degree, algebra: job.algebra.clone(), outcome });
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    Ok((results, thumbs))
}

/// Writes a job's image into `--out` (`frame`, rendered in this process)
/// and keeps a surface's first image for the contact sheet.
fn keep_image(dir: &std::path::Path, job: &bench::Job, frame: Option<&Frame>, ok: bool, thumbs: &mut Vec<Thumb>) -> Result<(), CliError> {
    if let Some(f) = frame {
        let rgb = output::frame_rgb8(f);
        let path = dir.join(format!("{}_{}.png", job.surface, job.algebra));
        output::write_png(&path, f.width, f.height, &rgb).map_err(|e| CliError::input(e.to_string()))?;
        if !thumbs.iter().any(|t| t.0 == job.surface) {
            thumbs.push((job.surface.clone(), f.width, f.height, rgb));
        }
    }
    // A child process wrote its image; read it back for the contact sheet.
    if let (None, true) = (frame, ok) {
        let img = output::read_image(&dir.join(format!("{}_{}.png", job.surface, job.algebra))).map(|i| i.to_rgb8());
        if let (Ok(img), false) = (img, thumbs.iter().any(|t| t.0 == job.surface)) {
            thumbs.push((job.surface.clone(), img.width(), img.height(), img.into_raw()));
        }
    }
    Ok(())
}

/// The child side of `--job-timeout`: runs one job on its own device,
/// writes its image into `--out`, and prints the outcome as JSON.
fn run_child_job(a: &BenchArgs, job: &bench::Job, entry: &Entry, variant: &Variant, size: (u32, u32), rel_eps: f64) -> Result<ExitCode, CliError> {
    let gpu = open_gpu(super::args::shader_opt(a.shader_opt, 0, false))?;
    let outcome = match run_job(&gpu, entry, variant, size, rel_eps, a) {
        Ok((m, f)) => {
            if let Some(dir) = &a.out {
                let path = dir.join(format!("{}_{}.png", job.surface, job.algebra));
                output::write_png(&path, f.width, f.height, &output::frame_rgb8(&f)).map_err(|e| CliError::input(e.to_string()))?;
            }
            Outcome::Ok(m)
        }
        Err(e) => Outcome::Failed { error: e },
    };
    let _ = writeln!(std::io::stdout().lock(), "{}", serde_json::to_string(&outcome).unwrap_or_default());
    Ok(ExitCode::SUCCESS)
}

/// Runs job `index` in a child process of isotrace (the same command line
/// with `--run-job INDEX`) and kills it at the deadline. A process, not a
/// thread: a thread cannot be stopped, so an abandoned job would go on
/// compiling on the cores (and holding the shared device) while the next
/// jobs are timed; a killed process frees both at once.
fn run_job_isolated(index: usize, timeout: Duration) -> Outcome {
    let failed = |error: String| Outcome::Failed { error };
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => return failed(format!("cannot start the job's process: {e}")),
    };
    let child = std::process::Command::new(exe)
        .args(std::env::args_os().skip(1))
        .args(["--run-job", &index.to_string()])
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => return failed(format!("cannot start the job's process: {e}")),
    };
    let deadline = Instant::now() + timeout;
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(10)),
            Ok(None) | Err(_) => {
                let _ = child.kill();
                let _ = child.wait();
                return failed(format!("timed out after {} s; the job was stopped and the batch went on", timeout.as_secs_f64()));
            }
        }
    };
    let mut text = String::new();
    let _ = child.stdout.take().map(|mut o| std::io::Read::read_to_string(&mut o, &mut text));
    serde_json::from_str(text.trim()).unwrap_or_else(|_| failed(format!("the job's process ended without a result ({status})")))
}

/// A run's report: its results and settings, the isotrace version, the date
/// and the machine.
fn report(settings: ReportSettings, results: Vec<JobResult>, gpu: &Gpu) -> Report {
    Report {
        isotrace_version: env!("CARGO_PKG_VERSION").into(),
        date: bench::utc_now(),
        device: gpu.info.clone(),
        cpu_threads: std::thread::available_parallelism().map_or(0, |n| n.get()),
        settings,
        results,
        merged_from: vec![],
    }
}

/// "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, llvmpipe Mesa 25.0.7 (LLVM
/// 15.0.6)), shader opt full, 2 CPU threads": the Markdown report's machine
/// line. A merged report's devices come from its files: shown on one line,
/// controls visible.
pub(super) fn machine(d: &crate::gpu::DeviceInfo, threads: usize) -> String {
    format!("{}, {threads} CPU threads", crate::batch::one_line(&d.describe()))
}

/// The table on stdout and the --markdown and --json files of a report (a
/// run's or a merged one); exit code 1 when a job failed.
fn write_reports(a: &BenchArgs, report: &Report, machine: &str) -> Result<ExitCode, CliError> {
    let (results, columns) = (&report.results, &report.settings.algebras);
    let table = if report.settings.find_eps { bench::table_text_with_eps(results, columns) } else { bench::table_text(results, columns) };
    let _ = std::io::stdout().lock().write_all(table.as_bytes());
    if let Some(p) = &a.markdown {
        output::write_atomic(p, bench::markdown(results, columns, machine).as_bytes()).map_err(|e| CliError::input(e.to_string()))?;
    }
    if let Some(p) = &a.json {
        let text = serde_json::to_string_pretty(report).unwrap_or_default();
        output::write_atomic(p, text.as_bytes()).map_err(|e| CliError::input(e.to_string()))?;
    }
    let failed = results.iter().any(|r| matches!(r.outcome, Outcome::Failed { .. }));
    Ok(if failed { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

/// `bench --merge`: one report from the reports of shards (see
/// [`bench::report::merge`] for what must agree and how duplicates go).
fn merge(a: &BenchArgs) -> Result<ExitCode, CliError> {
    for p in [&a.json, &a.markdown].into_iter().flatten() {
        output::check_writable(p).map_err(|e| CliError::input(e.to_string()))?;
    }
    let files = super::batch::part_files(&a.merge)?;
    let mut merger = Merger::default();
    for f in &files {
        let file = f.display().to_string();
        let text = super::batch::read_part(f, report::MAX_FILE_BYTES, report::WHAT)?;
        let r = report::parse(&file, &text).map_err(|e| CliError::input(e.to_string()))?;
        drop(text);
        merger.add(&file, r).map_err(|e| CliError::input(e.to_string()))?;
    }
    let merged = merger.finish().map_err(|e| match e {
        MergeError::Missing { .. } => CliError::input(format!("{e}; run their shards again")),
        e => CliError::input(e.to_string()),
    })?;
    let r = &merged.report;
    let mut machines: Vec<String> = Vec::new();
    for m in r.merged_from.iter().map(|p| machine(&p.device, p.cpu_threads)) {
        if !machines.contains(&m) {
            machines.push(m);
        }
    }
    if merged.mixed_devices {
        eprintln!("warning: the reports come from different devices ({}): timings compare only within one device", machines.join("; "));
    }
    eprintln!("merged {} reports: {} jobs", files.len(), r.results.len());
    write_reports(a, r, &machines.join("; "))
}

/// The timed runs of one renderer and settings, and the last frame. Timed
/// as a viewer renders: the kernel's records kept packed (decoding 1024²
/// pixels into `Frame` pixels would add ~3.5 ms a frame).
fn timed_packed(r: &Renderer, s: &Settings, repeat: u32) -> Result<(Vec<crate::render::Stats>, Frame, Instant), String> {
    let mut frame = PackedFrame::default();
    let (runs, warm) = timed(repeat, &mut || {
        r.render_packed(s, &mut frame).map_err(|e| e.to_string())?;
        Ok(frame.stats.clone())
    })?;
    Ok((runs, frame.decode(), warm))
}

/// Warm-up (shader compile, caches), then `repeat` timed renders; `render`
/// keeps its frame and returns the frame's statistics. Also returns when
/// the warm-up ended, so the caller can report the setup time apart.
fn timed(repeat: u32, render: &mut dyn FnMut() -> Result<crate::render::Stats, String>) -> Result<(Vec<crate::render::Stats>, Instant), String> {
    render()?;
    let warm = Instant::now();
    let runs = (0..repeat).map(|_| render()).collect::<Result<Vec<_>, _>>()?;
    if runs.is_empty() {
        return Err("no run".into());
    }
    Ok((runs, warm))
}

/// A job's error as its report line says it (without the `error: ` of stderr).
fn job_error(e: &CliError) -> String {
    e.text(false).trim_end().trim_start_matches("error: ").to_string()
}

/// Renders one job: warm-up, `repeat` timed runs, optional eps search
/// (bisection only).
fn run_job(gpu: &Gpu, entry: &Entry, variant: &Variant, size: (u32, u32), rel_eps: f64, a: &BenchArgs) -> Result<(Measure, Frame), String> {
    let f = entry.compile().map_err(|e| e.to_string())?;
    // --field, else the header's `field`, else the generated code.
    let field_arg = a.field.or(entry.header.field.map(super::args::field_arg)).unwrap_or(super::args::FieldArg::Compiled);
    let b = entry.header.bbox;
    let diag = crate::render::box_diagonal(&b);
    let mut defaults = entry.header.view();
    defaults.eps = Some(rel_eps * diag);
    let s = defaults.settings(&f, size.0, size.1).map_err(|e| e.to_string())?.0;
    let alg = match variant {
        Variant::Bisect(name) => algebra(name),
        Variant::Sphere(omega) => {
            // The header's Lipschitz bound and convex bound, every technique on.
            let args = SphereArgs { omega: Some(*omega), max_steps: a.max_steps, ..Default::default() };
            let o = sphere_options(&args, Some(&entry.header)).map_err(|e| match e {
                CliError::Input(m) => m,
                other => format!("{other:?}"),
            })?;
            // A scene's operators may need a larger Lipschitz bound than the
            // header's (never a smaller one): prepare_field raises it.
            let mut t = Traversal::Sphere(o);
            let field = super::args::prepare_field(Some(field_arg), &f, &s.params, &mut t, false, u64::from(a.repeat) + 1).map_err(|e| job_error(&e))?;
            let start = Instant::now();
            let r = Renderer::new(gpu, field.source(&f.ir), t).map_err(|e| e.to_string())?;
            let (runs, frame, warm) = timed_packed(&r, &s, a.repeat)?;
            let mut m = Measure::from_runs(&runs, s.eps, "-");
            m.omega = Some(*omega);
            m.setup_ms = warm.duration_since(start).as_secs_f64() * 1e3;
            m.field = field.kind().name().into();
            return Ok((m, frame));
        }
    };
    let alg = if alg == AlgebraArg::Auto { entry.header.algebra.map(algebra_arg).unwrap_or(AlgebraArg::Auto) } else { alg };
    let domain = resolve_algebra(alg, &f.ir);
    let mut t = Traversal::Bisect(BisectOptions::new(domain));
    let field = super::args::prepare_field(Some(field_arg), &f, &s.params, &mut t, false, u64::from(a.repeat) + 1).map_err(|e| job_error(&e))?;
    let start = Instant::now();
    let r = Renderer::new(gpu, field.source(&f.ir), t).map_err(|e| e.to_string())?;
    let (runs, frame, warm) = timed_packed(&r, &s, a.repeat)?;
    let mut m = Measure::from_runs(&runs, s.eps, algebra_name(domain));
    m.setup_ms = warm.duration_since(start).as_secs_f64() * 1e3;
    m.field = field.kind().name().into();
    if a.find_eps {
        let mut fine = s.clone();
        fine.eps = diag * 2f64.powi(-14);
        let reference = r.render(&fine).map_err(|e| e.to_string())?;
        // Coarse to fine: the first match is the coarsest correct eps.
        for k in (-13..=-5).rev() {
            let mut sk = s.clone();
            sk.eps = diag * 2f64.powi(k);
            let fr = r.render(&sk).map_err(|e| e.to_string())?;
            let diff = bench::differing_fraction(&fr, &reference);
            if diff <= bench::MATCH_FRACTION {
                let (runs, _, _) = timed_packed(&r, &sk, a.repeat)?;
                let ms = Measure::from_runs(&runs, sk.eps, "").gpu_ms;
                m.lowest_eps = Some(LowestEps { exponent: k, gpu_ms: ms, differing: diff });
                break;
            }
        }
    }
    Ok((m, frame))
}

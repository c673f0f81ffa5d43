//! The command line of batch work: `--shard i/n|auto` and `--shard-count`
//! (shared by `render --frames` and `bench`), reading the parts of a merge
//! (with wildcards expanded for schedulers that run no shell), and
//! `isotrace manifest merge`.

use super::CliError;
use clap::{Args, Subcommand};
use isotrace::batch::manifest::{self, Summary};
use isotrace::batch::merge::{MergeError, Part};
use isotrace::batch::{ranges, GivenCount, Shard, ShardError};
use isotrace::bounded;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Largest part file read: a manifest of a million frames is ~150 MB.
const MAX_PART_BYTES: u64 = 512 << 20;

fn input(m: impl Into<String>) -> CliError {
    CliError::Input(m.into())
}

/// `--shard` and `--shard-count`.
#[derive(Args, Debug, Clone, Default)]
pub struct ShardArgs {
    /// Do only shard i of n: the items k with k % n == i (frames of --frames, or bench jobs). `auto` reads i and n from a Slurm job array (SLURM_ARRAY_TASK_ID with SLURM_ARRAY_TASK_COUNT, or SLURM_ARRAY_TASK_MIN and _MAX) or a Kubernetes Indexed Job (JOB_COMPLETION_INDEX with --shard-count or ISOTRACE_SHARD_COUNT).
    #[arg(long, value_name = "i/n|auto")]
    pub shard: Option<String>,
    /// With --shard auto: the number of shards where the scheduler publishes only the index (Kubernetes: the Job's completions). Default: $ISOTRACE_SHARD_COUNT.
    #[arg(long, value_name = "N", requires = "shard")]
    pub shard_count: Option<usize>,
}

impl ShardArgs {
    /// The shard asked for, checked before any GPU work; `--shard auto`
    /// says on stderr which variables it came from (for the task's log).
    pub fn resolve(&self) -> Result<Option<Shard>, CliError> {
        match self.shard.as_deref() {
            None => Ok(None),
            Some("auto") => {
                let given = self.shard_count.map(|n| GivenCount { count: n, source: format!("--shard-count {n}") });
                let r = Shard::from_env(|k| std::env::var(k).ok(), given).map_err(|e| input(auto_message(&e)))?;
                eprintln!("note: --shard auto: shard {} from {}", r.shard, r.source);
                Ok(Some(r.shard))
            }
            Some(s) => {
                if self.shard_count.is_some() {
                    return Err(input("--shard-count applies to --shard auto only (--shard i/n gives the count)"));
                }
                Shard::parse(s).map(Some).map_err(|e| input(format!("invalid --shard {e}, or auto")))
            }
        }
    }
}

/// A `--shard auto` failure in the words of the command line.
fn auto_message(e: &ShardError) -> String {
    match e {
        ShardError::NoScheduler => format!("--shard auto: {e}; outside a scheduler give --shard i/n"),
        ShardError::NoCount { .. } => format!("--shard auto: {e} (or give --shard-count N)"),
        _ => format!("--shard auto: {e}"),
    }
}

/// The files an argument names: itself, or when it does not exist and its
/// file name holds `*` or `?`, the matching files of its directory in name
/// order. Kubernetes and Slurm's `--wrap` may run without a shell, so
/// `'frames/*.manifest.json'` works quoted too.
pub fn expand(arg: &Path) -> Result<Vec<PathBuf>, CliError> {
    let name = arg.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    if arg.exists() || !name.contains(['*', '?']) {
        return Ok(vec![arg.to_path_buf()]);
    }
    let dir = match arg.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let entries = std::fs::read_dir(&dir).map_err(|e| input(format!("cannot read '{}': {e}", dir.display())))?;
    let pattern: Vec<char> = name.chars().collect();
    let mut found: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .filter(|e| wildcard(&pattern, &e.file_name().to_string_lossy().chars().collect::<Vec<_>>()))
        .map(|e| if arg.parent().is_some_and(|p| p.as_os_str().is_empty()) { PathBuf::from(e.file_name()) } else { e.path() })
        .collect();
    if found.is_empty() {
        return Err(input(format!("no file matches '{}'", arg.display())));
    }
    found.sort();
    Ok(found)
}

/// `*` (any run) and `?` (one character) matching of a whole name.
fn wildcard(p: &[char], s: &[char]) -> bool {
    match p.first() {
        None => s.is_empty(),
        Some('*') => (0..=s.len()).any(|k| wildcard(&p[1..], &s[k..])),
        Some('?') => !s.is_empty() && wildcard(&p[1..], &s[1..]),
        Some(c) => s.first() == Some(c) && wildcard(&p[1..], &s[1..]),
    }
}

/// Reads the parts of a merge (arguments expanded as [`expand`] does). A
/// file named twice is read once.
pub fn read_parts(args: &[PathBuf], what: &'static str) -> Result<(Vec<PathBuf>, Vec<Part>), CliError> {
    let mut files: Vec<PathBuf> = Vec::new();
    for a in args {
        for f in expand(a)? {
            if !files.contains(&f) {
                files.push(f);
            }
        }
    }
    let parts = files
        .iter()
        .map(|f| {
            let file = f.display().to_string();
            let text = bounded::read_file_text(f, MAX_PART_BYTES).map_err(|e| input(format!("cannot read '{file}': {e}")))?;
            let json = serde_json::from_str(&text).map_err(|e| input(MergeError::NotAPart { file: file.clone(), what, reason: e.to_string() }.to_string()))?;
            Ok(Part { file, json })
        })
        .collect::<Result<Vec<_>, CliError>>()?;
    Ok((files, parts))
}

/// `isotrace manifest …`.
#[derive(Args, Debug)]
pub struct ManifestArgs {
    #[command(subcommand)]
    command: ManifestCommand,
}

#[derive(Subcommand, Debug)]
enum ManifestCommand {
    /// Put the manifests of an animation's shards together: which frames are complete and which are missing (exit code 1 when any is).
    #[command(after_help = "Examples:\n  isotrace manifest merge frames/f_.shard-*-of-16.manifest.json\n  isotrace manifest merge 'frames/*.manifest.json' --json frames/summary.json")]
    Merge(MergeArgs),
}

#[derive(Args, Debug)]
struct MergeArgs {
    /// The manifests (`render --frames` writes NAME.shard-i-of-n.manifest.json next to the frames); a quoted wildcard in the file name is expanded.
    #[arg(required = true, value_name = "MANIFEST")]
    manifests: Vec<PathBuf>,
    /// Also write the summary as JSON: settings, shards, the complete frames' entries and the missing frame numbers.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
}

/// Runs `isotrace manifest …`.
pub fn run(a: ManifestArgs) -> Result<ExitCode, CliError> {
    let ManifestCommand::Merge(m) = a.command;
    if let Some(p) = &m.json {
        isotrace::output::check_writable(p).map_err(|e| input(e.to_string()))?;
    }
    let (files, parts) = read_parts(&m.manifests, manifest::WHAT)?;
    let dirs: Vec<PathBuf> = files.iter().map(|f| f.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf)).collect();
    let summary = manifest::summarize(&parts, |k, file| dirs[k].join(file).is_file()).map_err(|e| input(e.to_string()))?;
    print!("{}", summary_text(&summary));
    if let Some(p) = &m.json {
        let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
        isotrace::output::write_atomic(p, text.as_bytes()).map_err(|e| input(e.to_string()))?;
    }
    if summary.missing.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    let mut hint = String::new();
    if !summary.shards_without_manifest.is_empty() {
        let list: Vec<String> = summary.shards_without_manifest.iter().map(Shard::to_string).collect();
        hint = format!("; no manifest for shard {}", list.join(", "));
    }
    Err(input(format!(
        "{} of {} frames are missing: {}{hint}; render them with the same command and --skip-existing",
        summary.missing.len(),
        summary.settings.frames,
        missing_list(&summary)
    )))
}

/// The missing frames with their file names, or as ranges of numbers when
/// there are more than 20.
fn missing_list(s: &Summary) -> String {
    let pattern = super::frames::FramePattern::parse(&s.settings.pattern).ok();
    match pattern {
        Some(p) if s.missing.len() <= 20 => {
            s.missing.iter().map(|&k| format!("{k} ({})", p.name(k as u32).display())).collect::<Vec<_>>().join(", ")
        }
        _ => ranges(&s.missing),
    }
}

/// The summary for stdout.
fn summary_text(s: &Summary) -> String {
    let st = &s.settings;
    let shards: Vec<String> = s.shards.iter().map(Shard::to_string).collect();
    format!(
        "animation: {} ({}), {} frames, t {} to {}, {}x{}\nmanifests: {} (shards {})\ncomplete: {} of {} frames ({} rendered, {} skipped as already there)\nmissing: {}\n",
        st.pattern,
        st.formula.origin,
        st.frames,
        st.t0,
        st.t1,
        st.size[0],
        st.size[1],
        s.shards.len(),
        shards.join(", "),
        s.complete.len(),
        st.frames,
        s.rendered(),
        s.complete.len() - s.rendered(),
        if s.missing.is_empty() { "none".to_string() } else { ranges(&s.missing) },
    )
}

#[cfg(test)]
mod tests {
    use super::wildcard;

    #[test]
    fn wildcards_match_whole_names() {
        let m = |p: &str, s: &str| wildcard(&p.chars().collect::<Vec<_>>(), &s.chars().collect::<Vec<_>>());
        assert!(m("*.manifest.json", "f_.shard-0-of-4.manifest.json"));
        assert!(m("part?.json", "part3.json") && !m("part?.json", "part10.json"));
        assert!(!m("*.json", "a.json.tmp") && m("*", ""));
    }
}

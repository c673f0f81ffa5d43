//! The command line of batch work: `--shard i/n|auto` and `--shard-count`
//! (shared by `render --frames` and `bench`), reading the parts of a merge
//! (with wildcards expanded for schedulers that run no shell), and
//! `isotrace manifest merge`.

use super::CliError;
use clap::{Args, Subcommand};
use crate::batch::manifest::{self, FrameFile, Summarizer, Summary};
use crate::batch::{frame_check, one_line, ranges, GivenCount, Shard, ShardError};
use crate::bounded;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Lines of frames that do not count, and of shards without a manifest,
/// shown before the rest is summed up (the `--json` summary has them all).
const LISTED: usize = 10;


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
                let r = Shard::from_env(|k| std::env::var(k).ok(), given).map_err(|e| CliError::input(auto_message(&e)))?;
                eprintln!("note: --shard auto: shard {} from {}", r.shard, r.source);
                Ok(Some(r.shard))
            }
            Some(s) => {
                if self.shard_count.is_some() {
                    return Err(CliError::input("--shard-count applies to --shard auto only (--shard i/n gives the count)"));
                }
                Shard::parse(s).map(Some).map_err(|e| CliError::input(format!("invalid --shard {e}, or auto")))
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
    let entries = std::fs::read_dir(&dir).map_err(|e| CliError::input(format!("cannot read '{}': {e}", dir.display())))?;
    let pattern: Vec<char> = name.chars().collect();
    let mut found: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .filter(|e| wildcard(&pattern, &e.file_name().to_string_lossy().chars().collect::<Vec<_>>()))
        .map(|e| if arg.parent().is_some_and(|p| p.as_os_str().is_empty()) { PathBuf::from(e.file_name()) } else { e.path() })
        .collect();
    if found.is_empty() {
        return Err(CliError::input(format!("no file matches '{}'", arg.display())));
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

/// The files of a merge's arguments (expanded as [`expand`] does), each
/// once, in the order given.
pub fn part_files(args: &[PathBuf]) -> Result<Vec<PathBuf>, CliError> {
    let mut files: Vec<PathBuf> = Vec::new();
    for a in args {
        for f in expand(a)? {
            if !files.contains(&f) {
                files.push(f);
            }
        }
    }
    Ok(files)
}

/// The text of one part of a merge, `what` (`an isotrace bench report`) of
/// at most `limit` bytes: a larger file is refused by its size before it
/// is read, and the read stops past the limit whatever the size said.
pub fn read_part(path: &Path, limit: u64, what: &str) -> Result<String, CliError> {
    // The limit is the kind of file's: say which kind it was.
    let refuse = |e: bounded::ReadError| match e {
        bounded::ReadError::TooLarge { .. } => CliError::input(format!("cannot read '{}': {e} for {what}", path.display())),
        e => CliError::input(format!("cannot read '{}': {e}", path.display())),
    };
    bounded::read_file_text(path, limit).map_err(refuse)
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
        crate::output::check_writable(p).map_err(|e| CliError::input(e.to_string()))?;
    }
    let summary = summarize(&part_files(&m.manifests)?)?;
    print!("{}", summary_text(&summary));
    warn_not_counted(&summary);
    if let Some(p) = &m.json {
        let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
        crate::output::write_atomic(p, text.as_bytes()).map_err(|e| CliError::input(e.to_string()))?;
    }
    if summary.missing.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    let mut hint = String::new();
    if let Some(list) = listed(&summary.shards_without_manifest) {
        hint = format!("; no manifest for shard {list}");
    }
    Err(CliError::input(format!(
        "{} of {} frames are missing: {}{hint}; render them with the same command and --skip-existing",
        summary.missing.len(),
        summary.settings.frames,
        missing_list(&summary)
    )))
}

/// Reads the manifests one at a time (each is dropped once its complete
/// frames are taken) and checks their frames on disk.
fn summarize(files: &[PathBuf]) -> Result<Summary, CliError> {
    let merge_error = |e: crate::batch::merge::MergeError| CliError::input(e.to_string());
    let mut summarizer = Summarizer::default();
    for f in files {
        let file = f.display().to_string();
        let m = manifest::parse(&file, &read_part(f, manifest::MAX_FILE_BYTES, manifest::WHAT)?).map_err(merge_error)?;
        let dir = f.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        let frames = FramesDir { dir, resolved: dir.canonicalize().ok(), width: m.settings.size[0], height: m.settings.size[1] };
        summarizer.add(&file, m, |name| frames.on_disk(name)).map_err(merge_error)?;
    }
    summarizer.finish().map_err(merge_error)
}

/// The directory of a manifest, where its frames are, and their size.
struct FramesDir<'a> {
    dir: &'a Path,
    /// `dir` with its symbolic links resolved, once.
    resolved: Option<PathBuf>,
    width: u32,
    height: u32,
}

impl FramesDir<'_> {
    /// What is on disk for frame file `name` (a file name, no directory
    /// part): a frame counts when it is a whole image of the animation's
    /// size in the directory itself (a symbolic link that leads out of it
    /// does not count).
    fn on_disk(&self, name: &str) -> FrameFile {
        let path = self.dir.join(name);
        let Ok(meta) = std::fs::symlink_metadata(&path) else { return FrameFile::Absent };
        if meta.file_type().is_symlink() {
            match (&self.resolved, path.canonicalize()) {
                (_, Err(_)) => return FrameFile::Absent,
                (Some(d), Ok(p)) if p.starts_with(d) => {}
                _ => return FrameFile::Unusable("a symbolic link to a file outside the manifest's directory".into()),
            }
        }
        let Ok(format) = crate::output::format_of(&path) else { return FrameFile::Unusable("not a .png or .exr file".into()) };
        match frame_check::check(&path, format, self.width, self.height) {
            Ok(()) => FrameFile::Present,
            Err(reason) => FrameFile::Unusable(reason),
        }
    }
}

/// One warning per frame a manifest calls done whose file does not count,
/// up to [`LISTED`], then their number.
fn warn_not_counted(s: &Summary) {
    for f in s.not_counted.iter().take(LISTED) {
        eprintln!(
            "warning: '{}': frame {}'s file '{}' does not count: {}",
            one_line(&f.manifest),
            f.index,
            one_line(&f.file),
            one_line(&f.reason)
        );
    }
    if s.not_counted.len() > LISTED {
        eprintln!("warning: … and {} more frames whose files do not count (--json lists them all)", s.not_counted.len() - LISTED);
    }
}

/// Shards as `1/16, 3/16`, up to [`LISTED`], then their number (a count
/// in a manifest may make a million shards); `None` for none.
fn listed(shards: &[Shard]) -> Option<String> {
    let mut text = shards.iter().take(LISTED).map(Shard::to_string).collect::<Vec<_>>().join(", ");
    if shards.len() > LISTED {
        text.push_str(&format!(", … ({} shards in all)", shards.len()));
    }
    (!shards.is_empty()).then_some(text)
}

/// The missing frames with their file names, or as ranges of numbers when
/// there are more than 20.
fn missing_list(s: &Summary) -> String {
    let pattern = super::frames::FramePattern::parse(&s.settings.pattern).ok();
    match pattern {
        Some(p) if s.missing.len() <= 20 => {
            s.missing.iter().map(|&k| format!("{k} ({})", one_line(&p.name(k as u32).display().to_string()))).collect::<Vec<_>>().join(", ")
        }
        _ => ranges(&s.missing),
    }
}

/// The summary for stdout (the pattern and the formula's origin come from
/// a file: shown on one line, controls visible).
fn summary_text(s: &Summary) -> String {
    let st = &s.settings;
    format!(
        "animation: {} ({}), {} frames, t {} to {}, {}x{}\nmanifests: {} (shards {})\ncomplete: {} of {} frames ({} rendered, {} skipped as already there)\nmissing: {}\n",
        one_line(&st.pattern),
        one_line(&st.formula.origin),
        st.frames,
        st.t0,
        st.t1,
        st.size[0],
        st.size[1],
        s.shards.len(),
        s.shards.iter().map(Shard::to_string).collect::<Vec<_>>().join(", "),
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

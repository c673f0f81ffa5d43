//! The documentation cannot drift: every shell example that runs `isotrace` in README.md and in
//! docs/**/*.md (dated notes under docs/notes/ aside) is run with the built binary, and every
//! relative link of those files points to a file (and heading) that exists.
//!
//! Rules for examples (the docs' authors rely on them):
//! - Examples live in fenced blocks tagged `sh`, `bash`, `shell` or `console`. In a `console` block
//!   only lines starting with `$ ` are commands (the rest is output); elsewhere a leading `$ ` is
//!   dropped. A line ending in `\` continues on the next line. Blank and `#` lines are skipped.
//! - A command is an example when one of its stages (split at unquoted `|`, `||`, `&&`, `;`, `&`)
//!   starts with `isotrace`, after optional `VAR=value` assignments and `time`. Other lines (`cargo`,
//!   `sbatch`, `python3`, …) are not run.
//! - The examples of one file run in order, in one fresh directory holding a copy of `examples/`, with
//!   `isotrace` on `PATH`, through `bash -o pipefail -c`: later examples may use earlier outputs.
//!   Each must exit with 0, and every file it names as an output (`-o`/`--output`, `--export`,
//!   `--markdown`, `--out`, `--json FILE` of `bench` and `manifest merge`, a frame pattern with
//!   `--frames`, a `>` redirection) must exist and not be empty afterwards.
//! - `isotrace view` without `--export` serves until stopped: it runs with `--port 0` (a given
//!   `--port` and `--open` are dropped), must print its URL and answer a GET of it with 200, and is then
//!   stopped.
//! - A block after a line `<!-- doc-test: parse-only: REASON -->` (an hour-long benchmark, a cluster,
//!   files from elsewhere) is not run: each `isotrace` command of it must parse, checked by running it
//!   with `--help` appended.

#[path = "doc_examples/shell.rs"]
mod shell;

use shell::{isotrace_args, outputs, redirected, stages, words};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest a single example may run before it counts as hung.
const EXAMPLE_TIMEOUT: Duration = Duration::from_secs(300);
/// Longest a served `view` may take to print its URL.
const SERVE_TIMEOUT: Duration = Duration::from_secs(60);

/// Blocks of files this test may not annotate yet (their owners do): each entry is a file and the
/// start of a command run parse-only, as if its block carried `<!-- doc-test: parse-only -->`. An
/// entry that matches no command fails the test, so the list cannot go stale.
const PARSE_ONLY_UNTIL_ANNOTATED: &[(&str, &str)] = &[
    // Needs the manifests of a 16-shard run.
    ("docs/batch.md", "isotrace manifest merge frames/f_.shard-*-of-16.manifest.json"),
    ("docs/batch.md", "isotrace manifest merge 'frames/*.manifest.json' --json frames/summary.json"),
    // One shard of sixteen on each machine, then the merge of all sixteen.
    ("docs/batch.md", "isotrace bench --suite knoll --shard 3/16"),
    ("docs/batch.md", "isotrace bench --merge 'bench/part-*.json'"),
    // Inside a Kubernetes pod, and after GNU parallel.
    ("docs/batch.md", "isotrace manifest merge '/out/*.manifest.json'"),
    ("docs/batch.md", "isotrace manifest merge 'par/*.manifest.json'"),
];

#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    Run,
    ParseOnly,
}

#[derive(Debug, Clone, PartialEq)]
struct Example {
    line: usize,
    command: String,
    mode: Mode,
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// README.md and docs/**/*.md, relative to the root, sorted; with or without docs/notes/.
fn doc_files(with_notes: bool) -> Vec<String> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "md") {
                out.push(p);
            }
        }
    }
    let mut found = Vec::new();
    walk(&root().join("docs"), &mut found);
    let mut files: Vec<String> = found
        .iter()
        .map(|p| p.strip_prefix(root()).unwrap().to_string_lossy().into_owned())
        .filter(|p| with_notes || !p.starts_with("docs/notes/"))
        .collect();
    files.push("README.md".into());
    files.sort();
    files
}

// ---- extraction -------------------------------------------------------------------------------

/// The shell examples of one Markdown text, by the rules above.
fn extract(text: &str) -> Vec<Example> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let Some(lang) = lines[i].trim_start().strip_prefix("```").map(str::trim) else {
            i += 1;
            continue;
        };
        let before = lines[..i].iter().rev().find(|l| !l.trim().is_empty());
        let mode = match before.is_some_and(|l| l.trim().starts_with("<!-- doc-test: parse-only")) {
            true => Mode::ParseOnly,
            false => Mode::Run,
        };
        let body_start = i + 1;
        i = body_start;
        while i < lines.len() && !lines[i].trim_start().starts_with("```") {
            i += 1;
        }
        if matches!(lang, "sh" | "bash" | "shell" | "console") {
            for (line, command) in commands(&lines[body_start..i], body_start + 1, lang == "console") {
                if is_example(&command) {
                    out.push(Example { line, command, mode });
                }
            }
        }
        i += 1;
    }
    out
}

/// The command lines of a shell block whose first line is line `first` of the file: prompts
/// dropped (in a console block, lines without one are output), continuations joined.
fn commands(body: &[&str], first: usize, console: bool) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut pending: Option<(usize, String)> = None;
    for (k, line) in body.iter().enumerate() {
        let text = match &pending {
            Some(_) => Some(*line),
            None if console => line.strip_prefix("$ "),
            None => Some(line.strip_prefix("$ ").unwrap_or(line)),
        };
        let Some(text) = text else { continue };
        let (start, mut joined) = pending.take().unwrap_or((first + k, String::new()));
        match text.strip_suffix('\\') {
            Some(head) => {
                joined.push_str(head);
                pending = Some((start, joined));
            }
            None => {
                joined.push_str(text);
                out.push((start, joined.trim().to_string()));
            }
        }
    }
    out
}

fn is_example(command: &str) -> bool {
    stages(&words(command)).iter().any(|s| isotrace_args(s).is_some())
}

// ---- running -----------------------------------------------------------------------------------

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let dest = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_dir(&p, &dest);
        } else {
            std::fs::copy(&p, &dest).unwrap();
        }
    }
}

/// A fresh directory for one Markdown file's examples, with `examples/` and `bin/isotrace`.
fn workdir(file: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("doc-examples").join(file.replace('/', "_"));
    let _ = std::fs::remove_dir_all(&dir);
    copy_dir(&root().join("examples"), &dir.join("examples"));
    std::fs::create_dir_all(dir.join(".bin")).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_isotrace"), dir.join(".bin/isotrace")).unwrap();
    dir
}

fn search_path(dir: &Path) -> String {
    format!("{}:{}", dir.join(".bin").display(), std::env::var("PATH").unwrap_or_default())
}

/// Waits for a child up to a deadline; kills it past the deadline.
fn wait_for(child: &mut std::process::Child, timeout: Duration) -> Option<std::process::ExitStatus> {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return Some(status);
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Runs one example of `Mode::Run` in `dir`; an error says what went wrong.
fn run(dir: &Path, ex: &Example) -> Result<(), String> {
    let ws = words(&ex.command);
    let parts = stages(&ws);
    if let [stage] = &parts[..] {
        if let Some(args) = isotrace_args(stage) {
            if args.first().is_some_and(|a| a == "view") && !args.iter().any(|a| a.starts_with("--export")) {
                return serve(dir, &args);
            }
        }
    }
    let log = dir.with_extension("stderr");
    let mut child = Command::new("bash")
        .args(["-o", "pipefail", "-c", &ex.command])
        .current_dir(dir)
        .env("PATH", search_path(dir))
        .env("NODEVICE_SELECT", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let status = wait_for(&mut child, EXAMPLE_TIMEOUT).ok_or_else(|| format!("still running after {EXAMPLE_TIMEOUT:?}"))?;
    let stderr = std::fs::read_to_string(&log).unwrap_or_default();
    if !status.success() {
        let code = status.code().map_or("a signal".to_string(), |c| c.to_string());
        return Err(format!("exit code {code}; stderr:\n{}", stderr.lines().take(12).collect::<Vec<_>>().join("\n")));
    }
    let mut expected: Vec<String> = parts.iter().filter_map(|s| isotrace_args(s)).flat_map(|a| outputs(&a)).collect();
    expected.extend(redirected(&ws));
    for f in expected {
        let p = dir.join(&f);
        let ok = if p.is_dir() { true } else { std::fs::metadata(&p).is_ok_and(|m| m.len() > 0) };
        if !ok {
            return Err(format!("exit 0, but '{f}' was not written"));
        }
    }
    Ok(())
}

/// Runs a serving `isotrace view`: its URL must appear and answer `GET /` with 200.
fn serve(dir: &Path, args: &[String]) -> Result<(), String> {
    let mut kept = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--open" => {}
            "--port" => {
                it.next();
            }
            _ if a.starts_with("--port=") => {}
            _ => kept.push(a.clone()),
        }
    }
    kept.extend(["--port".to_string(), "0".to_string()]);
    let mut child = Command::new(env!("CARGO_BIN_EXE_isotrace"))
        .args(&kept)
        .current_dir(dir)
        .env("NODEVICE_SELECT", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if let Some(url) = line.strip_prefix("isotrace view: http://") {
                let _ = tx.send(url.to_string());
                return;
            }
        }
    });
    let result = match rx.recv_timeout(SERVE_TIMEOUT) {
        Ok(addr) => get_root(&addr),
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => Err(format!("no 'isotrace view: http://…' line within {SERVE_TIMEOUT:?}")),
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => Err("it ended without printing 'isotrace view: http://…'".to_string()),
    };
    let _ = child.kill();
    let _ = child.wait();
    let mut stderr = String::new();
    let _ = child.stderr.take().unwrap().read_to_string(&mut stderr);
    result.map_err(|e| format!("{e}; stderr:\n{stderr}"))
}

/// `GET` of the printed URL (`HOST:PORT/?token=…`), as a browser opens it.
fn get_root(url: &str) -> Result<(), String> {
    let (addr, path) = url.split_once('/').map_or((url, String::from("/")), |(a, p)| (a, format!("/{p}")));
    let mut s = std::net::TcpStream::connect(addr).map_err(|e| format!("cannot connect to {addr}: {e}"))?;
    s.set_read_timeout(Some(SERVE_TIMEOUT)).unwrap();
    write!(s, "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n").unwrap();
    let mut status = String::new();
    BufReader::new(s).read_line(&mut status).map_err(|e| format!("no answer from {addr}: {e}"))?;
    if status.starts_with("HTTP/1.1 200") { Ok(()) } else { Err(format!("GET / answered '{}'", status.trim())) }
}

/// Checks a parse-only example: each isotrace stage, with `--help` appended, exits with 0.
fn parse(ex: &Example) -> Result<(), String> {
    for args in stages(&words(&ex.command)).iter().filter_map(|s| isotrace_args(s)) {
        let o = Command::new(env!("CARGO_BIN_EXE_isotrace")).args(&args).arg("--help").output().unwrap();
        if !o.status.success() {
            return Err(format!("does not parse: {}", String::from_utf8_lossy(&o.stderr).trim()));
        }
    }
    Ok(())
}

/// The examples of `file`, with the exemptions of [`PARSE_ONLY_UNTIL_ANNOTATED`] applied.
fn examples_of(file: &str, used: &mut [bool]) -> Vec<Example> {
    let text = std::fs::read_to_string(root().join(file)).unwrap();
    let mut examples = extract(&text);
    for ex in &mut examples {
        for (k, (f, start)) in PARSE_ONLY_UNTIL_ANNOTATED.iter().enumerate() {
            if *f == file && ex.command.starts_with(start) {
                ex.mode = Mode::ParseOnly;
                used[k] = true;
            }
        }
    }
    examples
}

#[test]
fn every_isotrace_example_in_the_docs_runs() {
    let start = Instant::now();
    let mut used = vec![false; PARSE_ONLY_UNTIL_ANNOTATED.len()];
    let (mut failures, mut ran, mut parsed) = (Vec::new(), 0, 0);
    for file in doc_files(false) {
        let examples = examples_of(&file, &mut used);
        if examples.is_empty() {
            continue;
        }
        let dir = workdir(&file);
        let before = failures.len();
        for ex in &examples {
            let result = match ex.mode {
                Mode::Run => run(&dir, ex),
                Mode::ParseOnly => parse(ex),
            };
            match ex.mode {
                Mode::Run => ran += 1,
                Mode::ParseOnly => parsed += 1,
            }
            if let Err(e) = result {
                failures.push(format!("{file}:{}: {}\n  {e}", ex.line, ex.command));
            }
        }
        if failures.len() == before {
            let _ = std::fs::remove_dir_all(&dir);
        }
    }
    for (k, (file, start)) in PARSE_ONLY_UNTIL_ANNOTATED.iter().enumerate() {
        if !used[k] {
            failures.push(format!("{file}: no command starts with '{start}': remove it from PARSE_ONLY_UNTIL_ANNOTATED"));
        }
    }
    eprintln!("doc examples: {ran} run, {parsed} parsed only, in {:.0?}", start.elapsed());
    assert!(failures.is_empty(), "{} of {} doc examples failed:\n\n{}", failures.len(), ran + parsed, failures.join("\n\n"));
}

#[test]
fn examples_are_extracted_by_the_documented_rules() {
    let md = "text\n```sh\nisotrace render @sphere \\\n  --size 64 -o s.png   # a comment\n# isotrace not this\ncargo build\n\
              NODEVICE_SELECT=1 isotrace list | head -3\necho 1 2 | isotrace eval x\n```\n\n```console\n$ isotrace check x\n\
              isotrace output line\n```\n\n<!-- doc-test: parse-only: slow -->\n```sh\n$ isotrace bench --suite knoll\n```\n\
              ```\nisotrace in a plain block\n```\n";
    let ex = |line, command: &str, mode| Example { line, command: command.to_string(), mode };
    assert_eq!(
        extract(md),
        vec![
            ex(3, "isotrace render @sphere   --size 64 -o s.png   # a comment", Mode::Run),
            ex(7, "NODEVICE_SELECT=1 isotrace list | head -3", Mode::Run),
            ex(8, "echo 1 2 | isotrace eval x", Mode::Run),
            ex(12, "isotrace check x", Mode::Run),
            ex(18, "isotrace bench --suite knoll", Mode::ParseOnly),
        ]
    );
    let args = isotrace_args(&stages(&words("isotrace render @water --frames 4 -o 'f %02d.png' --shard 1/2 > log.txt"))[0]).unwrap();
    assert_eq!(outputs(&args), ["f 01.png", "f 03.png"]);
    assert_eq!(redirected(&words("isotrace completions bash > isotrace.bash 2>/dev/null")), ["isotrace.bash"]);
    let bench = isotrace_args(&words("isotrace bench sphere --json b.json --out imgs")).unwrap();
    assert_eq!(outputs(&bench), ["imgs", "b.json"]);
    assert_eq!(outputs(&isotrace_args(&words("isotrace render @sphere --json -o s.exr")).unwrap()), ["s.exr"]);
}

// ---- links ---------------------------------------------------------------------------------------

/// GitHub's anchors of a Markdown text's headings: lower case, punctuation dropped, spaces as
/// hyphens, and `-1`, `-2`, … after repeats.
fn anchors(text: &str) -> Vec<String> {
    let mut seen = std::collections::HashMap::new();
    let mut out = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        let hashes = line.chars().take_while(|&c| c == '#').count();
        if fenced || !(1..=6).contains(&hashes) || !line[hashes..].starts_with(' ') {
            continue;
        }
        let slug: String = line[hashes..]
            .trim()
            .to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
            .map(|c| if c == ' ' { '-' } else { c })
            .collect();
        let n: &mut usize = seen.entry(slug.clone()).or_default();
        out.push(if *n == 0 { slug } else { format!("{slug}-{n}") });
        *n += 1;
    }
    out
}

/// The targets of a Markdown text's inline links and images, outside code (line, target).
fn links(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut fenced = false;
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Code spans hold no links.
        let prose: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            let tail = &rest[at + 2..];
            let end = tail.find(')').unwrap_or(tail.len());
            out.push((n + 1, tail[..end].trim().to_string()));
            rest = &tail[end..];
        }
    }
    out
}

#[test]
fn every_relative_link_in_the_docs_points_to_a_file_and_heading_that_exist() {
    let mut broken = Vec::new();
    for file in doc_files(true) {
        let path = root().join(&file);
        let text = std::fs::read_to_string(&path).unwrap();
        for (line, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (rel, anchor) = target.split_once('#').unwrap_or((&target, ""));
            let dest = if rel.is_empty() { path.clone() } else { path.parent().unwrap().join(rel) };
            if !dest.exists() {
                broken.push(format!("{file}:{line}: '{target}': no such file"));
            } else if !anchor.is_empty() && dest.extension().is_some_and(|x| x == "md") {
                let dest_text = std::fs::read_to_string(&dest).unwrap();
                if !anchors(&dest_text).iter().any(|a| a == anchor) {
                    broken.push(format!("{file}:{line}: '{target}': no heading with that anchor"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

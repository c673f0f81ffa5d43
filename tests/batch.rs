//! Batch work on the command line (issue 17): shards of `render --frames`
//! and `bench` (`--shard i/n|auto`), resuming with `--skip-existing`, the
//! per-shard manifests and `isotrace manifest merge`, and `bench --merge`.
//! Small sizes throughout; scripts/simulate-array.sh runs the example batch
//! scripts as a simulated Slurm array.

use proptest::prelude::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Every variable `--shard auto` reads: the tests may themselves run inside
/// a Slurm job or a Kubernetes pod, so each run starts without them.
const SCHEDULER_VARS: [&str; 7] = [
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_MAX",
    "SLURM_ARRAY_TASK_STEP",
    "JOB_COMPLETION_INDEX",
    "ISOTRACE_SHARD_COUNT",
];

fn command(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_isotrace"));
    c.args(args).current_dir(dir).env("NODEVICE_SELECT", "1");
    for v in SCHEDULER_VARS {
        c.env_remove(v);
    }
    c.envs(env.iter().copied());
    c
}

/// Runs isotrace in `dir` with the scheduler variables `env` only.
fn run_in(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    command(dir, args, env).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "exit {:?}: {}", o.status.code(), stderr(&o));
    o
}

/// A fresh directory for one test (or one proptest case).
fn fresh(name: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::env::temp_dir().join(format!("isotrace-batch-{}-{name}-{}", std::process::id(), N.fetch_add(1, Ordering::Relaxed)));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("frames")).unwrap();
    d
}

fn json(p: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).unwrap()
}

/// `render @water --size 8 --frames N -o frames/f_%03d.png` plus `extra`.
fn render_frames(dir: &Path, n: u32, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let n = n.to_string();
    let mut args = vec!["render", "@water", "--size", "8", "--frames", &n, "--t0", "0", "--t1", "1", "-o", "frames/f_%03d.png"];
    args.extend_from_slice(extra);
    run_in(dir, &args, env)
}

/// The frame numbers a manifest lists, with their statuses.
fn statuses(manifest: &Value) -> Vec<(u64, String)> {
    manifest["frames"].as_array().unwrap().iter().map(|f| (f["index"].as_u64().unwrap(), f["status"].as_str().unwrap().to_string())).collect()
}


proptest! {
    #![proptest_config(ProptestConfig { cases: 4, ..ProptestConfig::default() })]
    /// On the command line: the manifests of n shards of an animation list
    /// every frame of the unsharded run's manifest exactly once, every frame
    /// file is there, and `manifest merge` finds nothing missing.
    #[test]
    fn render_shards_cover_the_animation_exactly_once(frames in 1u32..8, n in 1usize..5) {
        let dir = fresh("cover");
        ok(render_frames(&dir, frames, &["--shard", "0/1"], &[]));
        let whole = json(&dir.join("frames/f_.shard-0-of-1.manifest.json"));
        let unsharded: Vec<u64> = statuses(&whole).into_iter().map(|(k, _)| k).collect();
        prop_assert_eq!(&unsharded, &(0..frames as u64).collect::<Vec<_>>());
        std::fs::remove_dir_all(dir.join("frames")).unwrap();
        std::fs::create_dir(dir.join("frames")).unwrap();
        let mut union = Vec::new();
        for i in 0..n {
            ok(render_frames(&dir, frames, &["--shard", &format!("{i}/{n}")], &[]));
            let m = json(&dir.join(format!("frames/f_.shard-{i}-of-{n}.manifest.json")));
            prop_assert_eq!(&m["shard"], &serde_json::json!({"index": i, "count": n}));
            for (k, status) in statuses(&m) {
                prop_assert_eq!(status, "rendered");
                let file = dir.join(format!("frames/f_{k:03}.png"));
                prop_assert!(file.is_file(), "{} is missing", file.display());
                union.push(k);
            }
        }
        union.sort();
        prop_assert_eq!(union, unsharded);
        let o = ok(run_in(&dir, &["manifest", "merge", "frames/*.manifest.json"], &[]));
        let text = String::from_utf8_lossy(&o.stdout);
        prop_assert!(text.contains(&format!("complete: {frames} of {frames} frames")) && text.ends_with("missing: none\n"), "{}", text);
    }
}

/// A run whose frames were lost (deleted, or never finished: a killed write
/// leaves only its temporary file) renders exactly those again with
/// --skip-existing and leaves the others untouched.
#[test]
fn resuming_renders_only_the_missing_frames() {
    let dir = fresh("resume");
    ok(render_frames(&dir, 6, &[], &[]));
    // A plain --frames run writes its frames and nothing else.
    assert_eq!(std::fs::read_dir(dir.join("frames")).unwrap().count(), 6);
    let f = |k: u32| dir.join(format!("frames/f_{k:03}.png"));
    let before: Vec<_> = (0..6).map(|k| std::fs::metadata(f(k)).unwrap().modified().unwrap()).collect();
    std::fs::remove_file(f(1)).unwrap();
    std::fs::remove_file(f(4)).unwrap();
    // What SIGKILL during frame 4's write leaves: a partial temporary file.
    std::fs::write(dir.join("frames/.f_004.png.999999.tmp"), b"partial").unwrap();
    std::thread::sleep(std::time::Duration::from_millis(20));
    ok(render_frames(&dir, 6, &["--skip-existing"], &[]));
    let m = json(&dir.join("frames/f_.shard-0-of-1.manifest.json"));
    let want: Vec<(u64, String)> = (0..6).map(|k| (k, if k == 1 || k == 4 { "rendered" } else { "skipped" }.to_string())).collect();
    assert_eq!(statuses(&m), want);
    for k in 0..6u32 {
        let e = &m["frames"][k as usize];
        assert_eq!(e["file"], format!("f_{k:03}.png"));
        assert_eq!(e["t"].as_f64().unwrap(), k as f64 / 5.0);
        assert_eq!(e["gpu_ms"].is_number(), k == 1 || k == 4, "{e}");
        if k != 1 && k != 4 {
            assert_eq!(std::fs::metadata(f(k)).unwrap().modified().unwrap(), before[k as usize], "frame {k} was rewritten");
        }
    }
    assert!(m["finished"].is_string() && m["device"]["name"].is_string());
    ok(run_in(&dir, &["manifest", "merge", "frames/f_.shard-0-of-1.manifest.json"], &[]));
    // Resuming with other settings would keep frames of another animation.
    let o = run_in(&dir, &["render", "@water", "--size", "10", "--frames", "6", "--t0", "0", "--t1", "1", "-o", "frames/f_%03d.png", "--skip-existing"], &[]);
    assert_eq!(
        (o.status.code(), stderr(&o).as_str()),
        (
            Some(1),
            "error: --skip-existing: 'frames/f_.shard-0-of-1.manifest.json' records another run (settings.size is [8,8] there but [10,10] now): \
             its frames would be kept and mixed with this run's; remove them (and the manifest), or render to another -o pattern\n"
        )
    );
}

/// A real kill: SIGKILL in the middle of an animation, then a re-run with
/// --skip-existing renders exactly the frames that were not there.
#[test]
fn a_killed_run_is_completed_by_a_rerun() {
    let dir = fresh("kill");
    let args = ["render", "@water", "--size", "96", "--frames", "60", "-o", "frames/f_%03d.png", "--skip-existing"];
    let mut child = command(&dir, &args, &[]).spawn().unwrap();
    let count = || std::fs::read_dir(dir.join("frames")).unwrap().filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().ends_with(".png")).count();
    let start = std::time::Instant::now();
    while count() < 3 && start.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let there = (0..60).filter(|k| dir.join(format!("frames/f_{k:03}.png")).is_file()).count() as u64;
    let o = run_in(&dir, &["manifest", "merge", "frames/f_.shard-0-of-1.manifest.json"], &[]);
    assert_eq!(o.status.code(), Some(if there == 60 { 0 } else { 1 }), "{}", stderr(&o));
    ok(run_in(&dir, &args, &[]));
    let m = json(&dir.join("frames/f_.shard-0-of-1.manifest.json"));
    let rendered = statuses(&m).iter().filter(|(_, s)| s == "rendered").count() as u64;
    assert_eq!((rendered, 60 - rendered), (60 - there, there));
    ok(run_in(&dir, &["manifest", "merge", "frames/f_.shard-0-of-1.manifest.json"], &[]));
}

/// `manifest merge` lists missing frames (with the shards that left no
/// manifest) and refuses manifests of different settings.
#[test]
fn manifest_merge_reports_missing_frames_and_refuses_mixed_settings() {
    let dir = fresh("manifests");
    for i in [0, 2] {
        ok(render_frames(&dir, 7, &["--shard", &format!("{i}/3")], &[]));
    }
    let o = run_in(&dir, &["manifest", "merge", "frames/*.manifest.json"], &[]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stderr(&o),
        "error: 2 of 7 frames are missing: 1 (f_001.png), 4 (f_004.png); no manifest for shard 1/3; \
         render them with the same command and --skip-existing\n"
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("manifests: 2 (shards 0/3, 2/3)\ncomplete: 5 of 7 frames (5 rendered, 0 skipped as already there)\nmissing: 1, 4\n"), "{out}");
    // Shard 1 rendered at another size: refused, naming the key and both files.
    let o = run_in(&dir, &["render", "@water", "--size", "12", "--frames", "7", "--t0", "0", "--t1", "1", "-o", "frames/f_%03d.png", "--shard", "1/3"], &[]);
    ok(o);
    let o = run_in(&dir, &["manifest", "merge", "frames/f_.shard-0-of-3.manifest.json", "frames/f_.shard-1-of-3.manifest.json"], &[]);
    assert_eq!(
        (o.status.code(), stderr(&o).as_str()),
        (Some(1), "error: cannot merge 'frames/f_.shard-1-of-3.manifest.json' with 'frames/f_.shard-0-of-3.manifest.json': settings.size is [8,8] in 'frames/f_.shard-0-of-3.manifest.json' but [12,12] in 'frames/f_.shard-1-of-3.manifest.json'\n")
    );
}

/// `--shard auto` reads Slurm's and Kubernetes' variables; without them, or
/// when they disagree, it fails before any GPU work, naming the variables.
#[test]
fn shard_auto_reads_the_scheduler_and_names_what_is_missing() {
    let dir = fresh("auto");
    let slurm = [("SLURM_ARRAY_TASK_ID", "5"), ("SLURM_ARRAY_TASK_MIN", "4"), ("SLURM_ARRAY_TASK_MAX", "6"), ("SLURM_ARRAY_TASK_COUNT", "3")];
    let o = ok(render_frames(&dir, 5, &["--shard", "auto", "-q"], &slurm));
    assert_eq!(stderr(&o), "note: --shard auto: shard 1/3 from SLURM_ARRAY_TASK_ID=5, SLURM_ARRAY_TASK_MIN=4 and SLURM_ARRAY_TASK_MAX=6\n");
    assert_eq!(statuses(&json(&dir.join("frames/f_.shard-1-of-3.manifest.json"))), [(1, "rendered".into()), (4, "rendered".into())]);
    let o = ok(render_frames(&dir, 5, &["--shard", "auto", "--shard-count", "2"], &[("JOB_COMPLETION_INDEX", "1")]));
    assert!(stderr(&o).starts_with("note: --shard auto: shard 1/2 from JOB_COMPLETION_INDEX=1 and --shard-count 2\n"), "{}", stderr(&o));
    // Failures happen before any GPU work: the same messages without a device.
    let no_gpu = |extra: &[&str], env: &[(&str, &str)]| {
        let mut args = vec!["render", "@water", "--size", "8", "--frames", "5", "-o", "frames/f_%03d.png"];
        args.extend_from_slice(extra);
        let o = command(&dir, &args, env).env("WGPU_BACKEND", "metal").output().unwrap();
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        stderr(&o)
    };
    assert_eq!(
        no_gpu(&["--shard", "auto"], &[]),
        "error: --shard auto: no array task in the environment: neither SLURM_ARRAY_TASK_ID (a Slurm job array) nor JOB_COMPLETION_INDEX \
         (a Kubernetes Indexed Job) is set; outside a scheduler give --shard i/n\n"
    );
    assert_eq!(
        no_gpu(&["--shard", "auto"], &[("JOB_COMPLETION_INDEX", "3")]),
        "error: --shard auto: the task index 3 is set but the shard count is not: set SLURM_ARRAY_TASK_COUNT (or SLURM_ARRAY_TASK_MIN and \
         SLURM_ARRAY_TASK_MAX) for Slurm, or ISOTRACE_SHARD_COUNT to the Job's completions for Kubernetes (or give --shard-count N)\n"
    );
    assert_eq!(
        no_gpu(&["--shard", "auto"], &[("SLURM_ARRAY_TASK_ID", "7"), ("SLURM_ARRAY_TASK_COUNT", "4")]),
        "error: --shard auto: inconsistent array variables: SLURM_ARRAY_TASK_ID=7 is not below the shard count 4 (SLURM_ARRAY_TASK_COUNT=4)\n"
    );
    assert_eq!(
        no_gpu(&["--shard", "auto"], &[("SLURM_ARRAY_TASK_ID", "1"), ("SLURM_ARRAY_TASK_COUNT", "4"), ("ISOTRACE_SHARD_COUNT", "8")]),
        "error: --shard auto: inconsistent array variables: ISOTRACE_SHARD_COUNT=8 but SLURM_ARRAY_TASK_ID=1 and SLURM_ARRAY_TASK_COUNT=4 make 4 shards\n"
    );
    assert_eq!(no_gpu(&["--shard", "4/4"], &[]), "error: invalid --shard '4/4': expected i/n with 0 <= i < n, e.g. 0/4, or auto\n");
    assert_eq!(no_gpu(&["--shard", "1/4", "--shard-count", "4"], &[]), "error: --shard-count applies to --shard auto only (--shard i/n gives the count)\n");
    let o = command(&dir, &["render", "@water", "-o", "one.png", "--shard", "0/2"], &[]).env("WGPU_BACKEND", "metal").output().unwrap();
    assert_eq!((o.status.code(), stderr(&o).as_str()), (Some(1), "error: --shard applies to --frames only: a single image is not split\n"));
    let o = ok(run_in(&dir, &["bench", "sphere", "--size", "8", "--repeat", "1", "--algebra", "ia,raa", "--shard", "auto", "--json", "b.json"], &[("JOB_COMPLETION_INDEX", "1"), ("ISOTRACE_SHARD_COUNT", "2")]));
    assert!(stderr(&o).starts_with("note: --shard auto: shard 1/2 from JOB_COMPLETION_INDEX=1 and ISOTRACE_SHARD_COUNT=2\n"), "{}", stderr(&o));
    let b = json(&dir.join("b.json"));
    assert_eq!((b["settings"]["shard"].as_str(), b["results"].as_array().unwrap().len(), &b["results"][0]["algebra"]), (Some("1/2"), 1, &Value::from("raa")));
}

/// The bench of the merge tests: 2 surfaces x 2 algebras = 4 jobs.
fn bench(dir: &Path, size: &str, extra: &[&str]) {
    let mut args = vec!["bench", "sphere", "steiner", "--algebra", "ia,raa", "--size", size, "--repeat", "1"];
    args.extend_from_slice(extra);
    ok(run_in(dir, &args, &[]));
}

/// A report without what changes from run to run: timings, dates, the
/// shard and the merge's own record.
fn without_timings(mut v: Value) -> Value {
    let o = v.as_object_mut().unwrap();
    for k in ["date", "merged_from"] {
        o.remove(k);
    }
    o["settings"].as_object_mut().unwrap().remove("shard");
    for r in o["results"].as_array_mut().unwrap() {
        for k in ["gpu_ms", "tile_ms", "fps", "wall_ms", "setup_ms"] {
            r.as_object_mut().unwrap().remove(k);
        }
    }
    v
}

/// `bench --merge` of three shards (given out of order, one of them twice
/// under another name) equals one unsharded run's report up to timings.
#[test]
fn merged_shard_reports_equal_a_single_run_up_to_timings() {
    let dir = fresh("bench-merge");
    bench(&dir, "16", &["--json", "single.json"]);
    for i in 0..3 {
        bench(&dir, "16", &["--shard", &format!("{i}/3"), "--json", &format!("part{i}.json")]);
    }
    std::fs::copy(dir.join("part1.json"), dir.join("again.json")).unwrap();
    let o = ok(run_in(&dir, &["bench", "--merge", "part2.json", "again.json", "part1.json", "part0.json", "--json", "all.json", "--markdown", "all.md"], &[]));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.starts_with("surface") && table.lines().count() == 3, "{table}");
    let all = json(&dir.join("all.json"));
    assert_eq!(all["merged_from"].as_array().unwrap().len(), 4);
    assert_eq!(all["settings"]["shard"], Value::Null);
    assert_eq!(without_timings(all), without_timings(json(&dir.join("single.json"))));
    let md = std::fs::read_to_string(dir.join("all.md")).unwrap();
    assert!(md.contains("| sphere | ia | ia |") && md.contains("| steiner | raa | raa |"), "{md}");
}

/// Reports of other settings, another isotrace version or with jobs
/// missing are refused with a message that names the key and the files.
#[test]
fn bench_merge_refuses_mixed_settings_versions_and_gaps() {
    let dir = fresh("bench-refuse");
    bench(&dir, "16", &["--shard", "0/2", "--json", "a.json"]);
    bench(&dir, "12", &["--shard", "1/2", "--json", "b.json"]);
    let refuse = |files: &[&str]| {
        let mut args = vec!["bench", "--merge"];
        args.extend_from_slice(files);
        let o = run_in(&dir, &args, &[]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        stderr(&o)
    };
    assert_eq!(refuse(&["a.json", "b.json"]), "error: cannot merge 'b.json' with 'a.json': settings.size is [16,16] in 'a.json' but [12,12] in 'b.json'\n");
    let mut v = json(&dir.join("a.json"));
    v["isotrace_version"] = "0.0.9".into();
    v["settings"]["shard"] = "1/2".into();
    v["results"] = serde_json::json!([]);
    std::fs::write(dir.join("old.json"), v.to_string()).unwrap();
    let version = env!("CARGO_PKG_VERSION");
    assert_eq!(refuse(&["a.json", "old.json"]), format!("error: cannot merge 'old.json' with 'a.json': isotrace_version is \"{version}\" in 'a.json' but \"0.0.9\" in 'old.json'\n"));
    assert_eq!(refuse(&["a.json"]), "error: 2 of 4 jobs are in no file: 1 (sphere raa), 3 (steiner raa); run their shards again\n");
    std::fs::write(dir.join("junk.json"), "{\"results\": 3}").unwrap();
    assert!(refuse(&["junk.json"]).starts_with("error: 'junk.json' is not an isotrace bench report: "));
}

/// The Kubernetes example runs: its Job is Indexed with as many
/// completions as ISOTRACE_SHARD_COUNT, and its container's args (with
/// Kubernetes' $(VAR) expansion of its env, at a tiny size) render two
/// shards that `manifest merge` finds complete.
#[test]
fn the_kubernetes_example_renders_its_shards() {
    let yaml = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/batch/k8s-job.yaml")).unwrap();
    let value = |key: &str| yaml.lines().map(str::trim).find_map(|l| l.strip_prefix(key)).map(|v| v.trim().trim_matches('"').to_string());
    assert_eq!(value("completionMode:").as_deref(), Some("Indexed"));
    let mut env: Vec<(String, String)> = Vec::new();
    let lines: Vec<&str> = yaml.lines().map(str::trim).collect();
    for w in lines.windows(2) {
        if let (Some(n), Some(v)) = (w[0].strip_prefix("- name: "), w[1].strip_prefix("value: ")) {
            env.push((n.to_string(), v.trim_matches('"').to_string()));
        }
    }
    let get = |k: &str| env.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone()).unwrap();
    assert_eq!(value("completions:"), Some(get("ISOTRACE_SHARD_COUNT")));
    let args: Vec<String> = serde_json::from_str(&value("args:").unwrap()).unwrap();
    let dir = fresh("k8s");
    let tiny = [("OUT", dir.join("frames").display().to_string()), ("SIZE", "8".into()), ("FRAMES", "3".into())];
    let args: Vec<String> = args
        .iter()
        .map(|a| tiny.iter().fold(a.clone(), |a, (k, v)| a.replace(&format!("$({k})"), v)))
        .collect();
    assert!(args.iter().all(|a| !a.contains("$(")), "{args:?}");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    for index in ["0", "1"] {
        ok(run_in(&dir, &args, &[("JOB_COMPLETION_INDEX", index), ("ISOTRACE_SHARD_COUNT", "2")]));
    }
    let o = ok(run_in(&dir, &["manifest", "merge", "frames/*.manifest.json"], &[]));
    assert!(String::from_utf8_lossy(&o.stdout).contains("complete: 3 of 3 frames"));
}

/// The first manifest of a fresh 4-frame run, as JSON, for the tests that
/// damage it.
fn manifest_of_a_run(dir: &Path) -> Value {
    ok(render_frames(dir, 4, &["--shard", "0/1"], &[]));
    json(&dir.join("frames/f_.shard-0-of-1.manifest.json"))
}

/// `manifest merge` of one file: its exit code and stderr.
fn merge_one(dir: &Path, file: &str) -> (Option<i32>, String) {
    let o = run_in(dir, &["manifest", "merge", file], &[]);
    (o.status.code(), stderr(&o))
}

/// A shard count of 0 (was a division by zero, exit 101), an index past
/// the count, too many frames and a top level that is not an object are
/// refused with the file and the JSON path.
#[test]
fn manifests_with_impossible_shards_or_shapes_are_refused_by_path() {
    let dir = fresh("shapes");
    let m = manifest_of_a_run(&dir);
    let write = |name: &str, v: &Value| std::fs::write(dir.join(name), serde_json::to_string_pretty(v).unwrap()).unwrap();
    let mut zero = m.clone();
    zero["shard"] = serde_json::json!({"index": 0, "count": 0});
    write("zero.json", &zero);
    let line = serde_json::to_string_pretty(&zero).unwrap().lines().position(|l| l.starts_with("  \"started\"")).unwrap();
    assert_eq!(
        merge_one(&dir, "zero.json"),
        (Some(1), format!("error: 'zero.json' is not an isotrace frame manifest: shard.count is 0: a shard count must be at least 1, at line {line} column 3\n"))
    );
    let mut past = m.clone();
    past["shard"] = serde_json::json!({"index": 3, "count": 2});
    write("past.json", &past);
    assert!(merge_one(&dir, "past.json").1.starts_with("error: 'past.json' is not an isotrace frame manifest: shard.index is 3 but shard.count is 2: the index must be below the count, at line "));
    let mut many = m.clone();
    many["settings"]["frames"] = 4_000_000_000u32.into();
    write("many.json", &many);
    assert_eq!(merge_one(&dir, "many.json"), (Some(1), "error: 'many.json' is not an isotrace frame manifest: settings.frames is 4000000000: an animation has 1 to 1000000 frames\n".into()));
    std::fs::write(dir.join("list.json"), "[]").unwrap();
    assert_eq!(merge_one(&dir, "list.json"), (Some(1), "error: 'list.json' is not an isotrace frame manifest: expected a JSON object at the top level, found an array\n".into()));
}

/// Runs `isotrace` under an address-space limit of `kib` KiB (`ulimit -v`):
/// an allocation the limit refuses would abort (exit 134).
#[cfg(unix)]
fn run_limited(dir: &Path, kib: u64, args: &[&str]) -> Output {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    let cmd = format!("ulimit -v {kib} && exec '{}' {}", env!("CARGO_BIN_EXE_isotrace"), quoted.join(" "));
    Command::new("sh").args(["-c", &cmd]).current_dir(dir).env("NODEVICE_SELECT", "1").output().unwrap()
}

/// Reports and manifests over their size limit are refused by their size,
/// before they are read; one under it is parsed into its typed form, not a
/// JSON tree (a 23 MB manifest took 216 MB that way and aborted under a
/// 300 MB address space; now about 50 MB).
#[cfg(unix)]
#[test]
fn large_manifests_and_reports_are_bounded() {
    let dir = fresh("large");
    let sparse = |name: &str, len: u64| std::fs::File::create(dir.join(name)).unwrap().set_len(len).unwrap();
    sparse("big.manifest.json", (256 << 20) + 1);
    sparse("big-report.json", (64 << 20) + 1);
    let o = run_limited(&dir, 300_000, &["manifest", "merge", "big.manifest.json"]);
    assert_eq!(
        (o.status.code(), stderr(&o).as_str()),
        (Some(1), "error: cannot read 'big.manifest.json': larger than the limit of 268435456 bytes (256 MiB) for an isotrace frame manifest\n")
    );
    let o = run_limited(&dir, 300_000, &["bench", "--merge", "big-report.json"]);
    assert_eq!(
        (o.status.code(), stderr(&o).as_str()),
        (Some(1), "error: cannot read 'big-report.json': larger than the limit of 67108864 bytes (64 MiB) for an isotrace bench report\n")
    );
    // 200,000 pending frames of a real manifest's head: 23 MB.
    let mut m = manifest_of_a_run(&dir);
    let n = 200_000;
    m["settings"]["frames"] = n.into();
    m["frames"] = Value::Array(vec![]);
    let head = serde_json::to_string(&m).unwrap();
    let frames: Vec<String> = (0..n).map(|k| format!("{{\"index\":{k},\"t\":{},\"file\":\"f_{k:06}.png\",\"status\":\"pending\",\"gpu_ms\":null,\"wall_ms\":null}}", k as f64 / 7.0)).collect();
    let text = head.replace("\"frames\":[]", &format!("\"frames\":[\n{}\n]", frames.join(",\n")));
    std::fs::write(dir.join("long.json"), text).unwrap();
    let o = run_limited(&dir, 300_000, &["manifest", "merge", "long.json"]);
    assert_eq!(
        (o.status.code(), stderr(&o).as_str()),
        (Some(1), "error: 200000 of 200000 frames are missing: 0-199999; render them with the same command and --skip-existing\n")
    );
}

/// --skip-existing renders a frame cut to 50 bytes and an empty one again
/// (before, both were kept with exit 0 and the merge said complete), and
/// `manifest merge` does not count a frame damaged after its run.
#[test]
fn damaged_frames_are_rendered_again_and_never_count() {
    let dir = fresh("damaged");
    ok(render_frames(&dir, 6, &[], &[]));
    let f = |k: u32| dir.join(format!("frames/f_{k:03}.png"));
    let whole = std::fs::read(f(1)).unwrap();
    std::fs::write(f(1), &whole[..50]).unwrap();
    std::fs::write(f(4), b"").unwrap();
    let o = ok(render_frames(&dir, 6, &["--skip-existing", "-q"], &[]));
    assert_eq!(
        stderr(&o),
        "note: 'frames/f_001.png' is rendered again: a PNG file cut short: it ends at byte 50, inside its IDAT chunk at byte 33\n\
         note: 'frames/f_004.png' is rendered again: an empty file\n"
    );
    let m = json(&dir.join("frames/f_.shard-0-of-1.manifest.json"));
    let want: Vec<(u64, String)> = (0..6).map(|k| (k, if k == 1 || k == 4 { "rendered" } else { "skipped" }.to_string())).collect();
    assert_eq!(statuses(&m), want);
    assert_eq!(std::fs::read(f(1)).unwrap(), whole);
    ok(run_in(&dir, &["manifest", "merge", "frames/f_.shard-0-of-1.manifest.json"], &[]));
    std::fs::write(f(2), &whole[..whole.len() - 1]).unwrap();
    let at = whole.len() - 12;
    assert_eq!(
        merge_one(&dir, "frames/f_.shard-0-of-1.manifest.json"),
        (
            Some(1),
            format!(
                "warning: 'frames/f_.shard-0-of-1.manifest.json': frame 2's file 'f_002.png' does not count: a PNG file cut short: it ends at byte {}, inside its IEND chunk at byte {at}\n\
                 error: 1 of 6 frames are missing: 2 (f_002.png); render them with the same command and --skip-existing\n",
                whole.len() - 1
            )
        )
    );
}

/// A manifest naming a file outside its directory (an absolute path, a
/// path that climbs out, a symbolic link that leads out) never counts it
/// as a frame, even when that file is a whole frame of the right size.
#[test]
fn frames_outside_the_manifests_directory_never_count() {
    let dir = fresh("outside");
    let mut m = manifest_of_a_run(&dir);
    std::fs::copy(dir.join("frames/f_003.png"), dir.join("x")).unwrap();
    m["frames"][0]["file"] = "/etc/passwd".into();
    m["frames"][1]["file"] = "../x".into();
    std::fs::write(dir.join("frames/evil.json"), m.to_string()).unwrap();
    #[cfg(unix)]
    {
        std::fs::remove_file(dir.join("frames/f_002.png")).unwrap();
        std::os::unix::fs::symlink(dir.join("x"), dir.join("frames/f_002.png")).unwrap();
    }
    let (code, text) = merge_one(&dir, "frames/evil.json");
    let mut want = "warning: 'frames/evil.json': frame 0's file '/etc/passwd' does not count: an absolute path, not a file in the manifest's directory\n\
                    warning: 'frames/evil.json': frame 1's file '../x' does not count: not a file name: it climbs out of the manifest's directory\n"
        .to_string();
    let mut missing = "0 (f_000.png), 1 (f_001.png)";
    if cfg!(unix) {
        want.push_str("warning: 'frames/evil.json': frame 2's file 'f_002.png' does not count: a symbolic link to a file outside the manifest's directory\n");
        missing = "0 (f_000.png), 1 (f_001.png), 2 (f_002.png)";
    }
    want.push_str(&format!("error: {} of 4 frames are missing: {missing}; render them with the same command and --skip-existing\n", missing.matches('(').count()));
    assert_eq!((code, text), (Some(1), want));
}

/// Text from a report reaches neither the terminal nor the Markdown raw: a
/// device name with ESC[2J (clear the screen) and a surface name with a
/// line break are shown with visible stand-ins.
#[test]
fn report_text_is_shown_escaped() {
    let dir = fresh("escape");
    ok(run_in(&dir, &["bench", "sphere", "--algebra", "ia", "--size", "8", "--repeat", "1", "--json", "a.json"], &[]));
    let mut a = json(&dir.join("a.json"));
    a["settings"]["surfaces"][0] = "sphere\nok".into();
    a["results"][0]["surface"] = "sphere\nok".into();
    std::fs::write(dir.join("a.json"), a.to_string()).unwrap();
    a["device"]["name"] = "gpu\u{1b}[2J".into();
    std::fs::write(dir.join("b.json"), a.to_string()).unwrap();
    let o = ok(run_in(&dir, &["bench", "--merge", "a.json", "b.json", "--markdown", "m.md"], &[]));
    let (out, err) = (String::from_utf8_lossy(&o.stdout).into_owned(), stderr(&o));
    let md = std::fs::read_to_string(dir.join("m.md")).unwrap();
    for text in [&out, &err, &md] {
        assert!(!text.contains('\u{1b}') && !text.contains("sphere\nok"), "{text}");
    }
    assert!(err.starts_with("warning: the reports come from different devices (") && err.contains("; gpu\u{241b}[2J (Vulkan, "), "{err}");
    assert!(out.lines().nth(1).unwrap().starts_with("sphere\u{240a}ok "), "{out}");
    assert!(md.contains("; gpu\u{241b}[2J (Vulkan, ") && md.contains("\n| sphere\u{240a}ok | 2 |"), "{md}");
}

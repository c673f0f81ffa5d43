//! `isotrace bench --suite scenes`: the generated series of Zanni et al.
//! (Fig. 16's recursive aggregates, Fig. 18's instanced boxes and sphere
//! pairs; sharp and smooth) through the scene field: sparse (every 8×8 tile
//! evaluates its pruned views, each ray walking the tile's depth slabs on
//! its own), sync (the same with the tile's rays walking them together,
//! Algorithm 3: a kernel of its own), bisect (the sparse pruned trees
//! bisected on interval enclosures, one a tile), dense (the sparse kernel with every
//! tile evaluating the whole tree, a uniform flag), and, where
//! its formula is small enough to compile in about a minute, through the
//! compiled field (the scene's formula generated into the shader). Dense
//! rows are skipped where the last level's dense frame, scaled by the
//! primitive count, would pass [`DENSE_BUDGET_MS`]. The table is what the
//! README's scene figures are made of; `scripts/plot-scenes.py` draws ms
//! against primitive count from the JSON.

use super::CliError;
use crate::gpu::{Gpu, Renderer};
use crate::render::{SphereOptions, Stats, Traversal};
use crate::scene::generate::{generate, Blending, Kind, MAX_LEVEL};
use crate::scene::linear::Linear;
use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

/// One measured row.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SceneRow {
    /// `aggregate`, `boxes`, `sphere-pairs`.
    pub kind: String,
    /// `sharp` or `smooth`.
    pub blending: String,
    /// Level of the series.
    pub level: u32,
    /// Primitives.
    pub primitives: usize,
    /// `sparse`, `bisect`, `sync`, `dense` or `compiled`.
    pub path: String,
    /// Building the renderer (for `compiled`: generating and compiling the
    /// scene's shader, cold or from Mesa's cache), ms.
    pub setup_ms: f64,
    /// Median GPU ms of the timed runs.
    pub gpu_ms: f64,
    /// Marching steps per pixel (each evaluates the field once); for
    /// `bisect`, interval evaluations per pixel.
    pub steps_per_ray: f64,
    /// Field evaluations per ray: the steps plus the six of the normal on a hit.
    pub evals_per_ray: f64,
    /// Mean and most active primitives per 8×8 tile.
    pub active_mean: f64,
    /// The most in one tile.
    pub active_max: u32,
    /// Mean nodes in a depth slab's pruned view (what a step evaluates).
    pub slab_view_mean: f64,
    /// The share of the tiles with primitives that are union or comb
    /// tiles (each ray evaluates its own primitives).
    pub chain_share: f64,
    /// Tiles whose active primitives overflowed the tile list.
    pub overflow_tiles: u64,
    /// Pixels that did not converge.
    pub unconverged: u64,
}

/// A dense frame expected to take longer than this is not run (its row is
/// left out, and the console says so).
pub const DENSE_BUDGET_MS: f64 = 120_000.0;
/// Tape instructions (the size measure of `--field auto`'s crossover) up to
/// which a scene's formula is also traced compiled: the compiled kernel of
/// a 2,503-operation formula took 35 s to build on lavapipe, of a
/// 12,503-operation one over 120 s (README, "Compiled or tape"). In the
/// generated series this takes level 0.
pub const COMPILED_MAX_OPS: usize = 3000;

/// The series measured: every kind up to `max_level`, sharp and smooth.
fn series(max_level: u32) -> Vec<(Kind, Blending, u32)> {
    let mut v = vec![];
    for kind in [Kind::Aggregate, Kind::Boxes, Kind::SpherePairs] {
        for blending in [Blending::Sharp, Blending::Smooth] {
            v.extend((0..=max_level).map(|l| (kind, blending, l)));
        }
    }
    v
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// One path's timed frames.
fn time_frames(r: &Renderer, s: &crate::render::Settings, repeat: u32) -> Result<Vec<Stats>, CliError> {
    r.render(s).map_err(super::error::render_error)?; // warm-up
    (0..repeat).map(|_| r.render(s).map(|f| f.stats).map_err(super::error::render_error)).collect()
}

/// A row from a path's timed frames.
fn row(scene: (Kind, Blending, u32, usize), path: &str, setup_ms: f64, runs: &[Stats]) -> SceneRow {
    let (kind, blending, level, primitives) = scene;
    let st = runs.last().expect("repeat >= 1").clone();
    let hit_share = st.hits as f64 / st.pixels.max(1) as f64;
    SceneRow {
        kind: kind.name().into(),
        blending: if blending == Blending::Sharp { "sharp" } else { "smooth" }.into(),
        level,
        primitives,
        path: path.into(),
        setup_ms,
        gpu_ms: median(runs.iter().map(|s| s.gpu_ms).collect()),
        steps_per_ray: st.evals_mean,
        evals_per_ray: st.evals_mean + 6.0 * hit_share,
        active_mean: st.field.active_mean,
        active_max: st.field.active_max,
        slab_view_mean: st.field.slab_view_mean,
        chain_share: st.field.chain_share,
        overflow_tiles: st.field.overflow_tiles,
        unconverged: st.unresolved,
    }
}

/// The scene's formula compiled into the shader, when its tape has at most
/// [`COMPILED_MAX_OPS`] instructions (it builds in about a minute).
fn compiled_formula(scene: &crate::scene::Scene) -> Option<crate::Formula> {
    let text = scene.to_formula().ok()?;
    let f = crate::Formula::compile("<scene>", &text).ok()?;
    (crate::field::tape::TapeData::new(&f.ir).ok()?.size <= COMPILED_MAX_OPS).then_some(f)
}

/// Measures one scene: sparse, dense unless `dense_estimate` (ms) passes
/// the budget, and compiled where it compiles in time.
fn measure(gpu: &Gpu, job: (Kind, Blending, u32), size: (u32, u32), repeat: u32, max_steps: Option<u32>, dense_estimate: Option<f64>) -> Result<Vec<SceneRow>, CliError> {
    let (kind, blending, level) = job;
    let fail = |m: String| CliError::Input(format!("{} level {level}: {m}", kind.name()));
    let scene = generate(kind, level, blending, 1).map_err(|e| fail(e.to_string()))?;
    let lin = Linear::new(&scene).map_err(|e| fail(e.to_string()))?;
    let framing = super::scene_render::framing(&lin).ok_or_else(|| fail("unbounded".into()))?;
    let s = framing.settings_without_params(size.0, size.1).map_err(|e| fail(e.to_string()))?;
    let mut o = SphereOptions { lipschitz: lin.lipschitz(), ..Default::default() };
    if let Some(n) = max_steps {
        o.max_steps = n;
    }
    let data = lin.field_data();
    let id = (kind, blending, level, lin.primitives.len());
    let t0 = std::time::Instant::now();
    let mut r = Renderer::new(gpu, &data, Traversal::Sphere(o.clone())).map_err(super::error::render_error)?;
    let setup = t0.elapsed().as_secs_f64() * 1e3;
    let mut rows = vec![row(id, "sparse", setup, &time_frames(&r, &s, repeat)?)];
    // The same scene bisected on its interval enclosures (no Lipschitz
    // bound): a kernel of its own.
    let t0 = std::time::Instant::now();
    let bisect = Traversal::Bisect(crate::render::BisectOptions::new(crate::ir::Domain::Interval));
    let rb = Renderer::new(gpu, &data, bisect).map_err(super::error::render_error)?;
    rows.push(row(id, "bisect", t0.elapsed().as_secs_f64() * 1e3, &time_frames(&rb, &s, repeat)?));
    // The same sparse path with the tile's rays walking its slabs together
    // (Algorithm 3): a kernel of its own.
    let t0 = std::time::Instant::now();
    let sync = SphereOptions { synchronized: true, ..o.clone() };
    let rs = Renderer::new(gpu, &data, Traversal::Sphere(sync)).map_err(super::error::render_error)?;
    rows.push(row(id, "sync", t0.elapsed().as_secs_f64() * 1e3, &time_frames(&rs, &s, repeat)?));
    match dense_estimate {
        Some(ms) if ms > DENSE_BUDGET_MS => eprintln!("  dense skipped: about {:.0} s a frame expected (the last level's, scaled by the primitives)", ms / 1e3),
        _ => {
            r.set_dense(true);
            rows.push(row(id, "dense", setup, &time_frames(&r, &s, repeat)?));
        }
    }
    if let Some(f) = compiled_formula(&scene) {
        let t0 = std::time::Instant::now();
        let c = Renderer::new(gpu, &f.ir, Traversal::Sphere(o)).map_err(super::error::render_error)?;
        rows.push(row(id, "compiled", t0.elapsed().as_secs_f64() * 1e3, &time_frames(&c, &s, repeat)?));
    }
    Ok(rows)
}

/// The console / Markdown table.
pub fn table(rows: &[SceneRow]) -> String {
    let mut t = String::from(
        "| scene | blend | level | primitives | path | setup ms | GPU ms | steps/ray | evals/ray | active/tile (mean, max) | view nodes/slab | overflow tiles | unconverged |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} | {} | {:.0} | {:.1} | {:.2} | {:.2} | {:.1}, {} | {:.1} | {} | {} |",
            r.kind, r.blending, r.level, r.primitives, r.path, r.setup_ms, r.gpu_ms, r.steps_per_ray, r.evals_per_ray, r.active_mean, r.active_max, r.slab_view_mean, r.overflow_tiles, r.unconverged
        );
    }
    t
}

/// Runs the series. `size`, `repeat`, `max_steps` and the outputs come from
/// the bench flags; `max_level` from `--max-level`; the driver's
/// optimisation from `--shader-opt`.
pub fn run(size: (u32, u32), repeat: u32, max_steps: Option<u32>, max_level: u32, json: Option<&Path>, markdown: Option<&Path>, opt: Option<crate::gpu::ShaderOpt>) -> Result<ExitCode, CliError> {
    if max_level > MAX_LEVEL {
        return Err(CliError::Input(format!("invalid --max-level {max_level}: the generated series go up to level {MAX_LEVEL}")));
    }
    let gpu = super::args::open_gpu(opt)?;
    let machine = super::bench::machine(&gpu.info, std::thread::available_parallelism().map_or(1, |n| n.get()));
    let mut rows: Vec<SceneRow> = vec![];
    let jobs = series(max_level);
    for (k, &(kind, blending, level)) in jobs.iter().enumerate() {
        // The last dense row of this series, scaled by the primitive count.
        let last_dense = rows.iter().rev().find(|r| r.kind == kind.name() && (r.blending == "sharp") == (blending == Blending::Sharp) && r.path == "dense");
        let prims = kind.primitives(level);
        let estimate = last_dense.map(|r| r.gpu_ms * prims as f64 / r.primitives.max(1) as f64);
        let new = measure(&gpu, (kind, blending, level), size, repeat, max_steps, estimate)?;
        for r in &new {
            eprintln!(
                "[{}/{}] {} {} level {} ({} primitives) {}: {:.1} ms (setup {:.0} ms), {:.2} evals/ray, {:.1} active/tile",
                k + 1, jobs.len(), r.kind, r.blending, r.level, r.primitives, r.path, r.gpu_ms, r.setup_ms, r.evals_per_ray, r.active_mean
            );
        }
        rows.extend(new);
    }
    let t = table(&rows);
    println!("{machine}, {}x{}, median of {repeat}\n\n{t}", size.0, size.1);
    if let Some(p) = json {
        let doc = serde_json::json!({ "machine": machine, "size": [size.0, size.1], "repeat": repeat, "rows": rows });
        crate::output::write_atomic(p, serde_json::to_string_pretty(&doc).expect("serialisable").as_bytes()).map_err(|e| CliError::Input(e.to_string()))?;
    }
    if let Some(p) = markdown {
        let text = format!("Machine: {machine}; {}x{}, median of {repeat} runs.\n\n{t}", size.0, size.1);
        crate::output::write_atomic(p, text.as_bytes()).map_err(|e| CliError::Input(e.to_string()))?;
    }
    Ok(ExitCode::SUCCESS)
}

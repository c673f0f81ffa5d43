//! What both modes share: fidget's render set-up and its time guards, the
//! alternating timing loop, and the mask/depth comparison of two pictures.

use crate::view::View;
use fidget::context::{Context, Node};
use fidget::jit::JitShape;
use fidget::raster::voxel::{self, RenderConfig};
use fidget::render::{CancelToken, VoxelSize};
use isotrace::gpu::Renderer;
use isotrace::render::PackedFrame;
use isotrace::render::{Frame, Settings, Status};
use nalgebra::Matrix4;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

/// fidget's render configuration for `view`: its voxel grid (side `size`,
/// `size` voxels deep) mapped onto model space through the view's matrix.
pub fn render_config(view: &View, size: u32) -> Result<RenderConfig, String> {
    let vsize = VoxelSize::new(size, size, view.depth);
    let screen_to_world: Matrix4<f32> = vsize.screen_to_world();
    let world_to_screen = screen_to_world.try_inverse().ok_or("singular screen matrix")?;
    Ok(RenderConfig { image_size: vsize, world_to_model: view.matrix().cast::<f32>() * world_to_screen })
}

/// One fidget render; `None` when `cancel` fired first.
pub fn render(shape: &JitShape, cfg: &RenderConfig, cancel: CancelToken) -> Option<voxel::Image> {
    let bound = shape.clone().try_into().expect("no free variables");
    voxel::render(bound, cfg, &voxel::EvalConfig { cancel, ..Default::default() })
}

/// A fidget render cancelled after `guard`: a warm-up that would take
/// longer gives `Err`, so one slow shape cannot stall the whole table.
pub fn render_guarded(shape: &JitShape, cfg: &RenderConfig, guard: Duration) -> Result<voxel::Image, String> {
    let token = CancelToken::new();
    let (done, wait) = mpsc::channel::<()>();
    let timer_token = token.clone();
    let timer = std::thread::spawn(move || {
        if wait.recv_timeout(guard) == Err(RecvTimeoutError::Timeout) {
            timer_token.cancel();
        }
    });
    let img = render(shape, cfg, token);
    drop(done);
    timer.join().expect("the timer thread does not panic");
    img.ok_or_else(|| format!("skipped: fidget render > {} s", guard.as_secs_f64()))
}

/// Builds a fidget expression with `build` and JIT-compiles it, on a
/// thread with a large stack, waiting at most `guard`. Returns the shape,
/// the expression's node count and the seconds taken. There is no way to
/// stop fidget's compilation from outside, so on a timeout the thread is
/// left running (detached) and the caller is told so in the error.
pub fn build_guarded<F>(build: F, guard: Duration) -> Result<(JitShape, usize, f64), String>
where
    F: FnOnce(&mut Context) -> Result<Node, String> + Send + 'static,
{
    let (tx, rx) = mpsc::channel();
    let t0 = Instant::now();
    std::thread::Builder::new()
        .name("fidget-build".into())
        .stack_size(256 << 20)
        .spawn(move || {
            let mut ctx = Context::new();
            let r = build(&mut ctx).and_then(|root| {
                let nodes = ctx.len();
                JitShape::new(&ctx, root).map(|s| (s, nodes)).map_err(|e| e.to_string())
            });
            let _ = tx.send(r);
        })
        .map_err(|e| format!("cannot start the build thread: {e}"))?;
    match rx.recv_timeout(guard) {
        Ok(r) => r.map(|(s, n)| (s, n, t0.elapsed().as_secs_f64())),
        Err(RecvTimeoutError::Timeout) => Err(format!(
            "skipped: fidget build > {} s (the build thread is still running and shares the CPU with later rows)",
            guard.as_secs_f64()
        )),
        Err(RecvTimeoutError::Disconnected) => Err("the fidget build thread panicked".into()),
    }
}

/// Medians of the alternating runs.
pub struct Timing {
    /// isotrace, wall ms of `render_packed`.
    pub iso_ms: f64,
    /// isotrace, kernel ms from timestamp queries.
    pub iso_gpu_ms: f64,
    /// fidget, wall ms of `voxel::render`.
    pub fid_ms: f64,
}

/// Times isotrace (`Renderer::render_packed` into one reused frame, as a
/// viewer would keep it) and fidget alternating, `repeat` times each, after
/// one warm-up of the packed path (the caller has warmed fidget up).
pub fn alternate(r: &Renderer, s: &Settings, repeat: usize, shape: &JitShape, cfg: &RenderConfig) -> Result<Timing, String> {
    let (mut ti, mut tg, mut tf) = (Vec::new(), Vec::new(), Vec::new());
    let mut fr = PackedFrame::default();
    r.render_packed(s, &mut fr).map_err(|e| e.to_string())?;
    for _ in 0..repeat {
        let t0 = Instant::now();
        r.render_packed(s, &mut fr).map_err(|e| e.to_string())?;
        ti.push(t0.elapsed().as_secs_f64() * 1e3);
        tg.push(fr.stats.gpu_ms);
        let t0 = Instant::now();
        let img = render(shape, cfg, CancelToken::new()).expect("not cancelled");
        tf.push(t0.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(img);
    }
    Ok(Timing { iso_ms: median(&mut ti), iso_gpu_ms: median(&mut tg), fid_ms: median(&mut tf) })
}

/// isotrace's median wall ms alone, for a row whose fidget render was cut
/// off by the guard.
pub fn isotrace_ms(r: &Renderer, s: &Settings, repeat: usize) -> Result<f64, String> {
    let mut fr = PackedFrame::default();
    r.render_packed(s, &mut fr).map_err(|e| e.to_string())?;
    let mut t = Vec::new();
    for _ in 0..repeat {
        let t0 = Instant::now();
        r.render_packed(s, &mut fr).map_err(|e| e.to_string())?;
        t.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    Ok(median(&mut t))
}

/// The median (the mean of the middle two for an even count).
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

/// The share of pixels on which the two renders agree (both miss, or both
/// hit within 1% of the box diagonal in depth) and the median |depth
/// difference| (in box diagonals) over the pixels both hit.
pub fn compare(view: &View, iso: &Frame, fid: &voxel::Image, diag: f64) -> (f64, f64) {
    let (w, h) = (iso.width, iso.height);
    let mut agree = 0usize;
    let mut diffs = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let p = &iso.pixels[(j * w + i) as usize];
            let fd = fid[(j * w + i) as usize].depth;
            match (matches!(p.status, Status::Hit), fd > 0) {
                (false, false) => agree += 1,
                (true, true) => {
                    let d = (view.ray_distance(i, j, fd as f64 - 1.0) - p.depth as f64).abs() / diag;
                    if d <= 0.01 {
                        agree += 1;
                    }
                    diffs.push(d);
                }
                _ => {}
            }
        }
    }
    let err = if diffs.is_empty() { f64::NAN } else { median(&mut diffs) };
    (agree as f64 / (w * h) as f64, err)
}

/// The CPU's model name from /proc/cpuinfo (both renderers run on it:
/// lavapipe is a CPU driver).
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| t.lines().find(|l| l.starts_with("model name")).and_then(|l| l.split_once(':')).map(|(_, v)| v.trim().to_string()))
        .unwrap_or_else(|| "unknown CPU".into())
}

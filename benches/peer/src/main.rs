//! Peer benchmark (issue 8, target 2): isotrace against fidget on the Knoll suite.
//!
//! Each surface is rendered at SIZE² by isotrace (wgpu on the Vulkan device,
//! default optimisations, `auto` algebra, eps = 2^-11 × box diagonal, the
//! rest of the view from the surface's `.iso` header) and by
//! fidget's 3D voxel renderer (JIT evaluator, rayon on all cores), runs
//! alternating (isotrace, fidget, isotrace, fidget, …) after a warm-up, and the
//! per-surface medians, their ratio fidget / isotrace and the geometric mean of
//! the ratios are printed.
//!
//! ```sh
//! cargo run --release --manifest-path benches/peer/Cargo.toml -- --size 1024 --repeat 5 [--images DIR] [NAME…]
//! ```
//!
//! The same view: fidget's voxel renderer maps voxel (u, v, k) through a 4×4
//! homogeneous matrix (with the perspective divide) to model space, so the
//! matrix below sends voxel column (i, j) exactly onto isotrace's primary ray
//! through the centre of pixel (i, j) of its pinhole camera, and the k
//! axis onto depth between the nearest and farthest point of the domain,
//! uniformly in 1/depth (the usual perspective z-buffer spacing). fidget then
//! sees the same frustum and the same domain (f intersected with the box, and
//! with the ball for clipped surfaces).

use fidget::context::{BadNode, Context, Node};
use fidget::jit::JitShape;
use fidget::raster::voxel::{self, GeometryPixel, RenderConfig};
use fidget::render::{ThreadPool, VoxelSize};
use isotrace::catalog;
use isotrace::gpu::Gpu;
use isotrace::gpu::Renderer;
use isotrace::ir::{Func1, Func2, Func3, Ir, Op, Var};
use isotrace::render::{Camera, CameraFrame, Frame, Status};
use nalgebra::{Matrix4, Vector3};
use std::path::PathBuf;
use std::time::Instant;

const USAGE: &str = "usage: isotrace-peer-bench [--size N] [--repeat N] [--images DIR] [--sign auto|keep|flip] [NAME...]

  --size N        image side (1024)
  --repeat N      timed runs per renderer, median reported (5); one warm-up run each first
  --images DIR    write, per surface, NAME.isotrace.png (shaded), NAME.isotrace-depth.png,
                  NAME.fidget-depth.png (same grey scale: near bright, far dark, miss black),
                  NAME.fidget-normals.png and NAME.diff.png (green: both hit, red: only isotrace,
                  blue: only fidget; brightness: |depth difference|)
  --sign S        which side of f fidget treats as solid (fidget: negative = inside).
                  auto (default): render both f and -f in the warm-up and keep the one whose
                  hit/miss mask agrees best with isotrace's; keep: f; flip: -f
  NAME...         catalog names (default: the 16 Knoll surfaces)";

struct Args {
    size: u32,
    repeat: usize,
    images: Option<PathBuf>,
    sign: SignMode,
    names: Vec<String>,
}

#[derive(Clone, Copy, PartialEq)]
enum SignMode {
    Auto,
    Keep,
    Flip,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args { size: 1024, repeat: 5, images: None, sign: SignMode::Auto, names: vec![] };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = |name: &str| it.next().ok_or_else(|| format!("{name} needs a value"));
        match arg.as_str() {
            "--size" => a.size = value("--size")?.parse().map_err(|e| format!("--size: {e}"))?,
            "--repeat" => a.repeat = value("--repeat")?.parse().map_err(|e| format!("--repeat: {e}"))?,
            "--images" => a.images = Some(PathBuf::from(value("--images")?)),
            "--sign" => {
                a.sign = match value("--sign")?.as_str() {
                    "auto" => SignMode::Auto,
                    "keep" => SignMode::Keep,
                    "flip" => SignMode::Flip,
                    s => return Err(format!("--sign: expected auto, keep or flip, got '{s}'")),
                }
            }
            "-h" | "--help" => {
                println!("{USAGE}");
                std::process::exit(0);
            }
            s if s.starts_with('-') => return Err(format!("unknown flag '{s}'")),
            s => a.names.push(s.trim_start_matches('@').to_string()),
        }
    }
    if a.size == 0 || a.size > 4096 || a.repeat == 0 {
        return Err("--size must be in 1..=4096 and --repeat at least 1".into());
    }
    if a.names.is_empty() {
        a.names = catalog::suite("knoll").map_err(|e| e.to_string())?.into_iter().map(String::from).collect();
    }
    Ok(a)
}

// ---------------------------------------------------------------------------
// isotrace IR → fidget expression graph

/// Translates the formula DAG into a fidget [`Context`] node, substituting
/// the time `t` and the parameter values. Everything in isotrace's language is
/// expressible; the operations fidget has no opcode for are rewritten:
/// sinh/cosh/tanh through exp, sign through compare(a, 0), pow(a, b) (a ≥ 0)
/// as exp(b·ln a), clamp through min/max, mix as a + (b − a)·t, and integer
/// powers by square-and-multiply (fidget's `square` keeps even powers tight).
fn to_fidget(ctx: &mut Context, ir: &Ir, t: f64, params: &[f32]) -> Result<Node, String> {
    let mut map: Vec<Option<Node>> = vec![None; ir.nodes.len()];
    let e = |e: BadNode| e.to_string();
    for id in ir.live() {
        let g = |n: u32| map[n as usize].expect("operands precede their users");
        let node = match ir.nodes[id as usize] {
            Op::Const(c) => ctx.constant(c as f32),
            Op::Var(Var::X) => ctx.x(),
            Op::Var(Var::Y) => ctx.y(),
            Op::Var(Var::Z) => ctx.z(),
            Op::Var(Var::T) => ctx.constant(t as f32),
            Op::Param(i) => ctx.constant(*params.get(i as usize).ok_or("parameter without a value")?),
            Op::Neg(a) => ctx.neg(g(a)).map_err(e)?,
            Op::Add(a, b) => ctx.add(g(a), g(b)).map_err(e)?,
            Op::Sub(a, b) => ctx.sub(g(a), g(b)).map_err(e)?,
            Op::Mul(a, b) => ctx.mul(g(a), g(b)).map_err(e)?,
            Op::Div(a, b) => ctx.div(g(a), g(b)).map_err(e)?,
            Op::PowI(a, n) => powi(ctx, g(a), n).map_err(e)?,
            Op::Call1(f, a) => {
                let a = g(a);
                match f {
                    Func1::Sqrt => ctx.sqrt(a),
                    Func1::Exp => ctx.exp(a),
                    Func1::Log => ctx.ln(a),
                    Func1::Sin => ctx.sin(a),
                    Func1::Cos => ctx.cos(a),
                    Func1::Tan => ctx.tan(a),
                    Func1::Atan => ctx.atan(a),
                    Func1::Abs => ctx.abs(a),
                    Func1::Floor => ctx.floor(a),
                    Func1::Sign => ctx.compare(a, 0.0),
                    Func1::Sinh | Func1::Cosh => {
                        let p = ctx.exp(a).map_err(e)?;
                        let na = ctx.neg(a).map_err(e)?;
                        let m = ctx.exp(na).map_err(e)?;
                        let s = if f == Func1::Sinh { ctx.sub(p, m) } else { ctx.add(p, m) }.map_err(e)?;
                        ctx.mul(s, 0.5)
                    }
                    Func1::Tanh => {
                        // 1 − 2 / (e^{2a} + 1): no overflow to inf/inf
                        let a2 = ctx.mul(a, 2.0).map_err(e)?;
                        let ex = ctx.exp(a2).map_err(e)?;
                        let d = ctx.add(ex, 1.0).map_err(e)?;
                        let q = ctx.div(2.0, d).map_err(e)?;
                        let one = ctx.constant(1.0);
                        ctx.sub(one, q)
                    }
                    #[allow(unreachable_patterns)] // functions added to isotrace later
                    other => return Err(format!("no fidget translation for {}", other.name())),
                }
                .map_err(e)?
            }
            Op::Call2(f, a, b) => {
                let (a, b) = (g(a), g(b));
                match f {
                    Func2::Min => ctx.min(a, b),
                    Func2::Max => ctx.max(a, b),
                    Func2::Atan2 => ctx.atan2(a, b),
                    Func2::Pow => {
                        let l = ctx.ln(a).map_err(e)?;
                        let p = ctx.mul(b, l).map_err(e)?;
                        ctx.exp(p)
                    }
                    #[allow(unreachable_patterns)]
                    other => return Err(format!("no fidget translation for {}", other.name())),
                }
                .map_err(e)?
            }
            Op::Call3(f, a, b, c) => {
                let (a, b, c) = (g(a), g(b), g(c));
                match f {
                    Func3::Clamp => {
                        let lo = ctx.max(a, b).map_err(e)?;
                        ctx.min(lo, c).map_err(e)?
                    }
                    Func3::Mix => {
                        let d = ctx.sub(b, a).map_err(e)?;
                        let s = ctx.mul(d, c).map_err(e)?;
                        ctx.add(a, s).map_err(e)?
                    }
                    #[allow(unreachable_patterns)]
                    other => return Err(format!("no fidget translation for {}", other.name())),
                }
            }
            #[allow(unreachable_patterns)] // operations added to isotrace later
            other => return Err(format!("no fidget translation for {other:?}")),
        };
        map[id as usize] = Some(node);
    }
    map[ir.root as usize].ok_or_else(|| "the root is not live".to_string())
}

fn powi(ctx: &mut Context, a: Node, n: u32) -> Result<Node, BadNode> {
    match n {
        0 => Ok(ctx.constant(1.0)),
        1 => Ok(a),
        _ if n % 2 == 0 => {
            let h = powi(ctx, a, n / 2)?;
            ctx.square(h)
        }
        _ => {
            let h = powi(ctx, a, n - 1)?;
            ctx.mul(h, a)
        }
    }
}

/// The domain isotrace traces: the box, and the ball of radius R around the
/// box centre when the entry clips. Negative inside (fidget's convention).
fn domain(ctx: &mut Context, b: &[f64; 6], clip: Option<f64>) -> Result<Node, BadNode> {
    let axes = [ctx.x(), ctx.y(), ctx.z()];
    let mut d: Option<Node> = None;
    let mut r2: Option<Node> = None;
    for (k, &v) in axes.iter().enumerate() {
        let (lo, hi) = (b[2 * k], b[2 * k + 1]);
        let c = ctx.sub(v, (0.5 * (lo + hi)) as f32)?;
        let abs = ctx.abs(c)?;
        let s = ctx.sub(abs, (0.5 * (hi - lo)) as f32)?;
        d = Some(match d {
            None => s,
            Some(p) => ctx.max(p, s)?,
        });
        let sq = ctx.square(c)?;
        r2 = Some(match r2 {
            None => sq,
            Some(p) => ctx.add(p, sq)?,
        });
    }
    let mut d = d.unwrap();
    if let Some(r) = clip {
        let ball = ctx.sub(r2.unwrap(), (r * r) as f32)?;
        d = ctx.max(d, ball)?;
    }
    Ok(d)
}

// ---------------------------------------------------------------------------
// The camera: isotrace's pinhole model as a fidget voxel transform

/// Voxel (u, v, k) → model space, homogeneous: the column (u = i, v = j) is
/// isotrace's ray through the centre of pixel (i, j); k ∈ [0, D] runs from the
/// far depth (k = 0) to the near depth (k = D) uniformly in 1/depth (fidget
/// puts +k towards the viewer).
struct View {
    frame: CameraFrame,
    eye: Vector3<f64>,
    /// 1 / depth = alpha·k + beta.
    alpha: f64,
    beta: f64,
    width: u32,
    height: u32,
    /// Voxels along k.
    depth: u32,
}

impl View {
    fn new(cam: &Camera, bbox: &[f64; 6], clip: Option<f64>, w: u32, h: u32, d: u32) -> View {
        let frame = cam.frame().expect("a camera that Settings::check accepted");
        let eye = Vector3::new(cam.eye.x, cam.eye.y, cam.eye.z);
        let fwd = Vector3::new(frame.forward.x, frame.forward.y, frame.forward.z);
        // depth (distance along `forward`) range of the domain
        let (mut near, mut far) = (f64::INFINITY, f64::NEG_INFINITY);
        for c in 0..8 {
            let p = Vector3::new(bbox[c & 1], bbox[2 + ((c >> 1) & 1)], bbox[4 + ((c >> 2) & 1)]);
            let s = (p - eye).dot(&fwd);
            near = near.min(s);
            far = far.max(s);
        }
        if let Some(r) = clip {
            let centre = Vector3::new(bbox[0] + bbox[1], bbox[2] + bbox[3], bbox[4] + bbox[5]) * 0.5;
            let s = (centre - eye).dot(&fwd);
            near = near.max(s - r);
            far = far.min(s + r);
        }
        // a small margin, so the extreme points of the domain are inside the voxel range
        let (near, far) = (near * (1.0 - 1e-3), far * (1.0 + 1e-3));
        assert!(near > 0.0, "the eye is inside the domain's depth range");
        let beta = 1.0 / far;
        let alpha = (1.0 / near - 1.0 / far) / d as f64;
        View { frame, eye, alpha, beta, width: w, height: h, depth: d }
    }

    /// sx(u) = a_x·u + b_x, sy(v) = a_y·v + b_y (pixel centres, as isotrace).
    fn screen(&self) -> (f64, f64, f64, f64) {
        let (w, h) = (self.width as f64, self.height as f64);
        let th = self.frame.tan_half_fov;
        let (ax, bx) = (2.0 / w * th * w / h, (1.0 / w - 1.0) * th * w / h);
        let (ay, by) = (-2.0 / h * th, (1.0 - 1.0 / h) * th);
        (ax, bx, ay, by)
    }

    /// The voxel → model matrix.
    fn matrix(&self) -> Matrix4<f64> {
        let v = |d: glam::DVec3| Vector3::new(d.x, d.y, d.z);
        let (f, r, u) = (v(self.frame.forward), v(self.frame.right), v(self.frame.up));
        let (ax, bx, ay, by) = self.screen();
        // x_h = eye·q + f + sx·r + sy·u, w_h = q, q = alpha·k + beta
        let cu = r * ax;
        let cv = u * ay;
        let ck = self.eye * self.alpha;
        let c1 = self.eye * self.beta + f + r * bx + u * by;
        #[rustfmt::skip]
        let m = Matrix4::new(
            cu.x, cv.x, ck.x, c1.x,
            cu.y, cv.y, ck.y, c1.y,
            cu.z, cv.z, ck.z, c1.z,
            0.0,  0.0,  self.alpha, self.beta,
        );
        m
    }

    /// Distance along the unit ray of pixel (i, j) of a voxel depth value
    /// (fidget: the first filled voxel is k = depth − 1).
    fn ray_distance(&self, i: u32, j: u32, k: f64) -> f64 {
        let (ax, bx, ay, by) = self.screen();
        let (sx, sy) = (ax * i as f64 + bx, ay * j as f64 + by);
        let dir = self.frame.forward + sx * self.frame.right + sy * self.frame.up;
        dir.length() / (self.alpha * k + self.beta)
    }
}

// ---------------------------------------------------------------------------

struct Row {
    name: String,
    iso_ms: f64,
    iso_gpu_ms: f64,
    fid_ms: f64,
    flipped: bool,
    agree: f64,
    depth_err: f64,
    algebra: &'static str,
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

/// The share of pixels on which the two renders agree (both miss, or both
/// hit within 1% of the box diagonal in depth) and the median |depth
/// difference| (in box diagonals) over the pixels both hit.
fn compare(view: &View, iso: &Frame, fid: &voxel::Image, diag: f64) -> (f64, f64) {
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

fn write_images(dir: &std::path::Path, name: &str, view: &View, iso: &Frame, fid: &voxel::Image) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let (w, h) = (iso.width, iso.height);
    let fid_t = |i: u32, j: u32| {
        let d = fid[(j * w + i) as usize].depth;
        (d > 0).then(|| view.ray_distance(i, j, d as f64 - 1.0))
    };
    let iso_t = |i: u32, j: u32| {
        let p = &iso.pixels[(j * w + i) as usize];
        matches!(p.status, Status::Hit).then_some(p.depth as f64)
    };
    // one grey scale for both: the depth range of the domain along the centre ray
    let (t_near, t_far) = (view.ray_distance(w / 2, h / 2, view.depth as f64), view.ray_distance(w / 2, h / 2, 0.0));
    let grey = |t: Option<f64>| -> u8 {
        match t {
            None => 0,
            Some(t) => (255.0 - 215.0 * ((t - t_near) / (t_far - t_near)).clamp(0.0, 1.0)).round() as u8,
        }
    };
    let save = |img: image::RgbImage, suffix: &str| {
        let p = dir.join(format!("{name}.{suffix}.png"));
        img.save(&p).map_err(|e| format!("{}: {e}", p.display()))
    };
    save(image::RgbImage::from_fn(w, h, |i, j| image::Rgb([grey(iso_t(i, j)); 3])), "isotrace-depth")?;
    save(image::RgbImage::from_fn(w, h, |i, j| image::Rgb([grey(fid_t(i, j)); 3])), "fidget-depth")?;
    save(
        image::RgbImage::from_fn(w, h, |i, j| image::Rgb(GeometryPixel::to_color(&fid[(j * w + i) as usize]))),
        "fidget-normals",
    )?;
    save(
        image::RgbImage::from_fn(w, h, |i, j| {
            let c = iso.pixels[(j * w + i) as usize].color;
            let s = |v: f32| (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8;
            image::Rgb([s(c[0]), s(c[1]), s(c[2])])
        }),
        "isotrace",
    )?;
    let scale = 1.0 / (t_far - t_near);
    save(
        image::RgbImage::from_fn(w, h, |i, j| match (iso_t(i, j), fid_t(i, j)) {
            (None, None) => image::Rgb([0, 0, 0]),
            (Some(_), None) => image::Rgb([255, 0, 0]),
            (None, Some(_)) => image::Rgb([0, 80, 255]),
            (Some(a), Some(b)) => {
                // brightness: 64 + |Δt| in units of 1/100 of the depth range
                let g = (64.0 + 19100.0 * ((a - b).abs() * scale).min(0.01)).round() as u8;
                image::Rgb([0, g, 0])
            }
        }),
        "diff",
    )
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {e}\n\n{USAGE}");
            std::process::exit(1);
        }
    };
    let size = args.size;
    let gpu = match Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("error: no usable GPU device: {e}");
            std::process::exit(2);
        }
    };
    let threads = ThreadPool::Global.thread_count();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("# isotrace vs fidget {} (JIT), {size}x{size}, median of {} alternating runs after a warm-up", "0.5.1", args.repeat);
    println!("# machine: {cores} cores; isotrace on {} (default optimisations, auto algebra, eps 2^-11 x box diagonal); fidget on {threads} rayon threads", format!("{} ({})", gpu.info.name, gpu.info.driver));
    println!("# times: wall ms of one frame (isotrace: Renderer::render incl. upload, read-back and unpacking; fidget: voxel::render), compile/JIT excluded;");
    println!("#   (gpu ms): isotrace's kernel time from timestamp queries, fid/gpu the ratio against it");
    println!("# view: isotrace's perspective camera (the .iso header's, else the default) for both (fidget via a projective voxel->model matrix); domain: box (and clip ball) for both");
    println!("# depth: fidget is voxel-quantised ({size} levels, uniform in 1/depth over the domain's depth range); isotrace finds roots to eps = 2^-11 x box diagonal");
    println!("# agree: pixels where both miss or both hit within 0.01 box diagonal in depth; |dz|: median depth difference over pixels both hit, in box diagonals");
    println!("# sign: the side fidget fills (f: f < 0, -f: f > 0); auto picks the one that agrees best with isotrace in the warm-up");
    println!();
    println!(
        "{:<14} {:>4} {:>11} {:>9} {:>9} {:>8} {:>8} {:>4} {:>7} {:>8}",
        "surface", "alg", "isotrace ms", "(gpu ms)", "fidget ms", "fid/iso", "fid/gpu", "sign", "agree", "|dz|"
    );
    let mut rows: Vec<Row> = Vec::new();
    let mut skipped: Vec<(String, String)> = Vec::new();
    for name in &args.names {
        match bench_one(&gpu, name, &args) {
            Ok(r) => {
                println!(
                    "{:<14} {:>4} {:>11.1} {:>9.1} {:>9.1} {:>8.2} {:>8.2} {:>4} {:>6.2}% {:>8.1e}",
                    r.name,
                    r.algebra,
                    r.iso_ms,
                    r.iso_gpu_ms,
                    r.fid_ms,
                    r.fid_ms / r.iso_ms,
                    r.fid_ms / r.iso_gpu_ms,
                    if r.flipped { "-f" } else { "f" },
                    100.0 * r.agree,
                    r.depth_err
                );
                rows.push(r);
            }
            Err(e) => {
                println!("{name:<14} skipped: {e}");
                skipped.push((name.clone(), e));
            }
        }
    }
    if !rows.is_empty() {
        let geo = |f: &dyn Fn(&Row) -> f64| (rows.iter().map(|r| f(r).ln()).sum::<f64>() / rows.len() as f64).exp();
        let g = geo(&|r| r.fid_ms / r.iso_ms);
        let gg = geo(&|r| r.fid_ms / r.iso_gpu_ms);
        println!(
            "{:<14} {:>4} {:>11.1} {:>9.1} {:>9.1} {:>8.2} {:>8.2}",
            "geomean",
            "",
            geo(&|r| r.iso_ms),
            geo(&|r| r.iso_gpu_ms),
            geo(&|r| r.fid_ms),
            g,
            gg
        );
        println!();
        let verdict = |g: f64| if g >= 1.0 { format!("isotrace {g:.2}x faster") } else { format!("fidget {:.2}x faster", 1.0 / g) };
        println!("# geometric mean of fidget/isotrace over {} surfaces: {g:.2} by wall time ({}),", rows.len(), verdict(g));
        println!("#   {gg:.2} against isotrace's kernel time alone ({})", verdict(gg));
    }
    if !skipped.is_empty() {
        println!("# skipped: {}", skipped.iter().map(|(n, e)| format!("{n} ({e})")).collect::<Vec<_>>().join(", "));
    }
}

fn bench_one(gpu: &Gpu, name: &str, args: &Args) -> Result<Row, String> {
    let size = args.size;
    let e = catalog::lookup(name).map_err(|e| e.to_string())?;
    let f = e.compile().map_err(|e| e.to_string())?;
    let b = e.header.bbox;
    let diag = isotrace::render::box_diagonal(&b);
    // The header's view (box, camera, t, parameters, clip ball), but one
    // relative eps for every surface, as `isotrace bench` measures.
    let mut s = e.settings(&f, size, size).map_err(|e| e.to_string())?;
    s.eps = diag * 2f64.powi(-11);
    let (time, clip, params, camera) = (s.time, s.clip_sphere, s.params.clone(), s.camera);
    let domain_alg = isotrace::choose_algebra(&f.ir);
    let r = Renderer::bisect(gpu, &f.ir, domain_alg).map_err(|e| e.to_string())?;
    let algebra = match domain_alg {
        isotrace::codegen::Domain::Interval => "ia",
        isotrace::codegen::Domain::Affine => "raa",
        isotrace::codegen::Domain::Scalar => "scalar",
    };

    // fidget: max(±f, domain)
    let mut ctx = Context::new();
    let fnode = to_fidget(&mut ctx, &f.ir, time, &params)?;
    let dom = domain(&mut ctx, &b, clip).map_err(|e| e.to_string())?;
    let shape_for = |ctx: &mut Context, flip: bool| -> Result<JitShape, String> {
        let g = if flip { ctx.neg(fnode).map_err(|e| e.to_string())? } else { fnode };
        let root = ctx.max(g, dom).map_err(|e| e.to_string())?;
        JitShape::new(ctx, root).map_err(|e| e.to_string())
    };
    let view = View::new(&camera, &b, clip, size, size, size);
    let vsize = VoxelSize::new(size, size, size);
    let screen_to_world: Matrix4<f32> = vsize.screen_to_world();
    let world_to_screen = screen_to_world.try_inverse().ok_or("singular screen matrix")?;
    let cfg = RenderConfig { image_size: vsize, world_to_model: view.matrix().cast::<f32>() * world_to_screen };
    let run_fidget = |shape: &JitShape| -> voxel::Image {
        let bound = shape.clone().try_into().expect("no free variables");
        voxel::render(bound, &cfg, &voxel::EvalConfig::default()).expect("not cancelled")
    };

    // warm-up (and the sign choice)
    let iso_frame = r.render(&s).map_err(|e| e.to_string())?;
    let candidates: Vec<bool> = match args.sign {
        SignMode::Auto => vec![false, true],
        SignMode::Keep => vec![false],
        SignMode::Flip => vec![true],
    };
    let mut best: Option<(f64, bool, JitShape, voxel::Image, f64)> = None;
    for flip in candidates {
        let shape = shape_for(&mut ctx, flip)?;
        let img = run_fidget(&shape);
        let (agree, err) = compare(&view, &iso_frame, &img, diag);
        if best.as_ref().is_none_or(|b| agree > b.0) {
            best = Some((agree, flip, shape, img, err));
        }
    }
    let (agree, flipped, shape, fid_img, depth_err) = best.unwrap();

    let (mut ti, mut tg, mut tf) = (Vec::new(), Vec::new(), Vec::new());
    // isotrace renders into one frame, reused and kept packed as a viewer
    // would (its 16-byte records: colour, normal, depth, status, evaluations).
    let mut fr = isotrace::render::record::PackedFrame::default();
    r.render_packed(&s, &mut fr).map_err(|e| e.to_string())?;
    for _ in 0..args.repeat {
        let t0 = Instant::now();
        r.render_packed(&s, &mut fr).map_err(|e| e.to_string())?;
        ti.push(t0.elapsed().as_secs_f64() * 1e3);
        tg.push(fr.stats.gpu_ms);
        let t0 = Instant::now();
        let img = run_fidget(&shape);
        tf.push(t0.elapsed().as_secs_f64() * 1e3);
        std::hint::black_box(img);
    }
    if let Some(dir) = &args.images {
        write_images(dir, name, &view, &iso_frame, &fid_img)?;
    }
    Ok(Row {
        name: name.to_string(),
        iso_ms: median(&mut ti),
        iso_gpu_ms: median(&mut tg),
        fid_ms: median(&mut tf),
        flipped,
        agree,
        depth_err,
        algebra,
    })
}

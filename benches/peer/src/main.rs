//! Peer benchmark: isotrace against fidget 0.5.1 (JIT, all cores).
//!
//! Two modes, each run per view (`--view perspective|ortho|both`):
//!
//! - the Knoll suite (issue 8, target 2; issue 14; [`knoll`]): each surface
//!   rendered at SIZE² by isotrace (wgpu on the Vulkan device, default
//!   optimisations, `auto` algebra, eps = 2^-11 × box diagonal, the rest of
//!   the view from the surface's `.iso` header) and by fidget's 3D voxel
//!   renderer;
//! - `--scenes` (issue 13; [`scenes`]): Zanni et al.'s generated scene
//!   series, sharp and smooth, through isotrace's scene field (sphere
//!   tracing) and as one fidget expression.
//!
//! Runs alternate (isotrace, fidget, isotrace, fidget, …) after a warm-up;
//! the per-row medians, their ratio fidget / isotrace and the geometric
//! mean of the ratios per view are printed.
//!
//! ```sh
//! cargo run --release --manifest-path benches/peer/Cargo.toml -- --size 1024 --repeat 5 [--view both] [--images DIR] [NAME…]
//! cargo run --release --manifest-path benches/peer/Cargo.toml -- --scenes --max-level 2 --size 512 --repeat 3 [aggregate|boxes|sphere-pairs]
//! ```
//!
//! The same view: fidget's voxel renderer maps voxel (u, v, k) through a 4×4
//! homogeneous matrix (with the perspective divide) to model space, so
//! [`view::View`] sends voxel column (i, j) exactly onto isotrace's primary
//! ray through the centre of pixel (i, j) of its pinhole camera, and the k
//! axis onto depth between the nearest and farthest point of the domain,
//! uniformly in 1/depth (the usual perspective z-buffer spacing). fidget then
//! sees the same frustum and the same domain (f intersected with the box, and
//! with the ball for clipped surfaces).

mod images;
mod knoll;
mod measure;
mod report;
mod scenes;
mod view;

use fidget::render::ThreadPool;
use isotrace::catalog;
use isotrace::gpu::Gpu;
use isotrace::scene::generate::MAX_LEVEL;
use report::Table;
use std::path::PathBuf;
use view::{ViewKind, ORTHO_FOV_DEG};

const USAGE: &str = "usage: isotrace-peer-bench [--size N] [--repeat N] [--view V] [--images DIR] [--guard S]
                            [--sign auto|keep|flip] [NAME...]
       isotrace-peer-bench --scenes [--max-level L] [--size N] [--repeat N] [--view V] [--images DIR] [--guard S]

  --size N        image side (1024)
  --repeat N      timed runs per renderer, median reported (5); one warm-up run each first
  --view V        perspective (default: the .iso header's camera, or isotrace's default camera),
                  ortho (near-orthographic: the same viewing direction, vertical fov 2.5 degrees,
                  the eye moved back until the domain's box, or clip ball, just fills the frame),
                  or both (one table per view)
  --images DIR    write, per surface (or scene) and view, NAME.VIEW.isotrace.png (shaded),
                  NAME.VIEW.isotrace-depth.png, NAME.VIEW.fidget-depth.png (same grey scale: near
                  bright, far dark, miss black), NAME.VIEW.fidget-normals.png and NAME.VIEW.diff.png
                  (green: both hit, red: only isotrace, blue: only fidget; brightness: |depth difference|)
  --guard S       seconds fidget may take to build and JIT its expression, and for its warm-up
                  render (120); a row that takes longer is skipped and says so
  --sign S        Knoll surfaces: which side of f fidget treats as solid (fidget: negative = inside).
                  auto (default): render both f and -f in the warm-up and keep the one whose
                  hit/miss mask agrees best with isotrace's; keep: f; flip: -f
  NAME...         catalog names (default: the 16 Knoll surfaces); with --scenes,
                  series kinds: aggregate, boxes, sphere-pairs (default: all)
  --scenes        instead of catalog surfaces, the generated scene series of `isotrace bench
                  --suite scenes` (aggregate, boxes, sphere-pairs; sharp and smooth; levels 0..L)
  --max-level L   the highest level of the series (2; at most 4)
  --method M      with --scenes: how isotrace renders the scenes: sphere (sphere tracing, the
                  default, as `isotrace render` does) or bisect (interval bisection on the
                  scene's enclosures, `render --method bisect`)";

/// The command line.
pub struct Args {
    size: u32,
    repeat: usize,
    images: Option<PathBuf>,
    sign: SignMode,
    names: Vec<String>,
    views: Vec<ViewKind>,
    /// `--scenes`, with the highest level.
    scenes: Option<u32>,
    /// Seconds.
    guard: f64,
    /// `--method bisect` with `--scenes`: interval bisection instead of sphere tracing.
    bisect: bool,
}

/// `--sign`.
#[derive(Clone, Copy, PartialEq)]
pub enum SignMode {
    Auto,
    Keep,
    Flip,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args { size: 1024, repeat: 5, images: None, sign: SignMode::Auto, names: vec![], views: vec![ViewKind::Perspective], scenes: None, guard: 120.0, bisect: false };
    let (mut scenes, mut max_level, mut sign_given, mut method_given) = (false, None, false, false);
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = |name: &str| it.next().ok_or_else(|| format!("{name} needs a value"));
        match arg.as_str() {
            "--size" => a.size = value("--size")?.parse().map_err(|e| format!("--size: {e}"))?,
            "--repeat" => a.repeat = value("--repeat")?.parse().map_err(|e| format!("--repeat: {e}"))?,
            "--images" => a.images = Some(PathBuf::from(value("--images")?)),
            "--guard" => a.guard = value("--guard")?.parse().map_err(|e| format!("--guard: {e}"))?,
            "--scenes" => scenes = true,
            "--method" => {
                method_given = true;
                a.bisect = match value("--method")?.as_str() {
                    "sphere" => false,
                    "bisect" => true,
                    s => return Err(format!("--method: expected sphere or bisect, got '{s}'")),
                }
            }
            "--max-level" => max_level = Some(value("--max-level")?.parse::<u32>().map_err(|e| format!("--max-level: {e}"))?),
            "--view" => {
                a.views = match value("--view")?.as_str() {
                    "perspective" => vec![ViewKind::Perspective],
                    "ortho" => vec![ViewKind::Ortho],
                    "both" => vec![ViewKind::Perspective, ViewKind::Ortho],
                    s => return Err(format!("--view: expected perspective, ortho or both, got '{s}'")),
                }
            }
            "--sign" => {
                sign_given = true;
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
    if !(a.guard > 0.0 && a.guard.is_finite()) {
        return Err("--guard must be a positive number of seconds".into());
    }
    if scenes {
        if sign_given {
            return Err("--sign applies to the Knoll run, not to --scenes".into());
        }
        // With --scenes, names choose series kinds.
        if let Some(bad) = a.names.iter().find(|n| !["aggregate", "boxes", "sphere-pairs"].contains(&n.as_str())) {
            return Err(format!("--scenes {bad}: the series are aggregate, boxes and sphere-pairs"));
        }
        let l = max_level.unwrap_or(2);
        if l > MAX_LEVEL {
            return Err(format!("--max-level {l}: the generated series go up to level {MAX_LEVEL}"));
        }
        a.scenes = Some(l);
    } else if max_level.is_some() {
        return Err("--max-level applies to --scenes".into());
    } else if method_given {
        return Err("--method applies to --scenes (the Knoll surfaces are bisected)".into());
    }
    if a.names.is_empty() && !scenes {
        a.names = catalog::suite("knoll").map_err(|e| e.to_string())?.into_iter().map(String::from).collect();
    }
    Ok(a)
}

/// What the tables mean, printed once above them.
fn print_header(gpu: &Gpu, args: &Args) {
    let threads = ThreadPool::Global.thread_count();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let size = args.size;
    println!("# isotrace vs fidget 0.5.1 (JIT), {size}x{size}, median of {} alternating runs after a warm-up", args.repeat);
    println!("# CPU: {} ({cores} cores); isotrace on {} ({}); fidget on {threads} rayon threads", measure::cpu_model(), gpu.info.name, gpu.info.driver);
    if args.scenes.is_some() {
        if args.bisect {
            println!("# isotrace: the scene field (SceneData as the FieldSource), interval bisection (render --method bisect), IA, eps 2^-11 x box diagonal, compact G for smooth operators");
        } else {
            println!("# isotrace: the scene field (SceneData as the FieldSource), sphere tracing with default options, Lipschitz 1 (sharp) or 1.45 (smooth), compact G for smooth operators");
        }
        println!("# fidget: the scene as one expression (min / max / max(a,-b); smooth: polynomial g = min(a,b) - h^3/(6 beta^2)), intersected with the box");
        println!("# nodes: fidget expression nodes; build s: building the expression and JitShape::new (not timed in the ms columns)");
    } else {
        println!("# isotrace: Renderer::bisect, default optimisations, auto algebra, eps 2^-11 x box diagonal; fidget: max(+-f, box, clip ball)");
        println!("# sign: the side fidget fills (f: f < 0, -f: f > 0); auto picks the one that agrees best with isotrace in the warm-up");
    }
    println!("# times: wall ms of one frame (isotrace: Renderer::render_packed incl. uniforms, dispatch and read-back; fidget: voxel::render), compile/JIT excluded;");
    println!("#   (gpu ms): isotrace's kernel time from timestamp queries, fid/gpu the ratio against it");
    println!("# views: fidget gets isotrace's camera through a projective voxel->model matrix (column (i, j) = isotrace's ray through pixel (i, j));");
    println!("#   ortho = the same direction, vertical fov {ORTHO_FOV_DEG} degrees, eye moved back until the box (or clip ball) just fills the frame");
    println!("# depth: fidget is voxel-quantised ({size} levels, uniform in 1/depth over the domain's depth range)");
    println!("# agree: pixels where both miss or both hit within 0.01 box diagonal in depth; |dz|: median depth difference over pixels both hit, in box diagonals");
    println!();
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {e}\n\n{USAGE}");
            std::process::exit(1);
        }
    };
    let gpu = match Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("error: no usable GPU device: {e}");
            std::process::exit(2);
        }
    };
    print_header(&gpu, &args);
    for &kind in &args.views {
        if let Some(max_level) = args.scenes {
            scenes::run(&gpu, &args, kind, max_level);
            continue;
        }
        let title = match kind {
            ViewKind::Perspective => "Knoll surfaces, view: perspective (the .iso header's camera, else the default: azimuth 35, elevation 25, fov 40)".to_string(),
            ViewKind::Ortho => format!("Knoll surfaces, view: ortho (the header's direction, fov {ORTHO_FOV_DEG}, box or clip ball just fills the frame)"),
        };
        let mut table = Table::start(&title, knoll::COLUMNS);
        for name in &args.names {
            match knoll::bench(&gpu, name, &args, kind) {
                Ok(r) => table.add(r),
                Err(e) => table.skip(&format!("{name:<19}"), &format!("skipped: {}", e.trim_start_matches("skipped: "))),
            }
        }
        table.finish(None);
    }
}

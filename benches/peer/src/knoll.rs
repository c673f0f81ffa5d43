//! The Knoll-surface run (issue 8, target 2; issue 14): each catalog
//! surface rendered by isotrace's bisection renderer and by fidget's voxel
//! renderer from the same camera, over the same domain.

use crate::measure::{self, Timing};
use crate::report::Row;
use crate::view::{self, View, ViewKind};
use crate::{Args, SignMode};
use fidget::context::{BadNode, Context, Node};
use fidget::jit::JitShape;
use fidget::raster::voxel;
use isotrace::catalog;
use isotrace::gpu::{Gpu, Renderer};
use isotrace::ir::{Func1, Func2, Func3, Ir, Op, Var};
use std::time::Duration;

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
            Op::Call1(f, a) => call1(ctx, f, g(a))?,
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

/// A one-argument function, rewritten where fidget has no opcode for it.
fn call1(ctx: &mut Context, f: Func1, a: Node) -> Result<Node, String> {
    let e = |e: BadNode| e.to_string();
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
    .map_err(e)
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


/// fidget's solid for a surface: max(±f, domain), negative inside.
fn solid(ctx: &mut Context, ir: &Ir, time: f64, params: &[f32], bbox: &[f64; 6], clip: Option<f64>, flip: bool) -> Result<Node, String> {
    let f = to_fidget(ctx, ir, time, params)?;
    let dom = view::domain(ctx, bbox, clip).map_err(|e| e.to_string())?;
    let g = if flip { ctx.neg(f).map_err(|e| e.to_string())? } else { f };
    ctx.max(g, dom).map_err(|e| e.to_string())
}

/// The signs `--sign` lets the warm-up try (false: f, true: −f).
fn candidates(sign: SignMode) -> Vec<bool> {
    match sign {
        SignMode::Auto => vec![false, true],
        SignMode::Keep => vec![false],
        SignMode::Flip => vec![true],
    }
}

/// Renders the catalog surface `name` with both renderers from the view
/// `kind` (the header's camera, or its framed near-orthographic variant),
/// after a warm-up that also picks fidget's side of the surface, then times
/// them alternating.
pub fn bench(gpu: &Gpu, name: &str, args: &Args, kind: ViewKind) -> Result<Row, String> {
    let size = args.size;
    let e = catalog::lookup(name).map_err(|e| e.to_string())?;
    let f = e.compile().map_err(|e| e.to_string())?;
    let b = e.header.bbox;
    let diag = isotrace::render::box_diagonal(&b);
    // The header's view (box, camera, t, parameters, clip ball), but one
    // relative eps for every surface, as `isotrace bench` measures.
    let mut s = e.settings(&f, size, size).map_err(|e| e.to_string())?;
    s.eps = diag * 2f64.powi(-11);
    s.camera = kind.camera(&s.camera, &b, s.clip_sphere, 1.0);
    let (time, clip, params) = (s.time, s.clip_sphere, s.params.clone());
    let domain_alg = isotrace::choose_algebra(&f.ir);
    let r = Renderer::bisect(gpu, &f.ir, domain_alg).map_err(|e| e.to_string())?;
    let algebra = match domain_alg {
        isotrace::ir::Domain::Interval => "ia",
        isotrace::ir::Domain::Affine => "raa",
        isotrace::ir::Domain::Scalar => "scalar",
    };
    let view = View::new(&s.camera, &b, clip, size, size, size);
    let cfg = measure::render_config(&view, size)?;
    let guard = Duration::from_secs_f64(args.guard);

    // warm-up (and the sign choice)
    let iso_frame = r.render(&s).map_err(|e| e.to_string())?;
    let mut best: Option<(f64, bool, JitShape, voxel::Image, f64)> = None;
    for flip in candidates(args.sign) {
        let (ir, params) = (f.ir.clone(), params.clone());
        let (shape, _, _) = measure::build_guarded(move |ctx| solid(ctx, &ir, time, &params, &b, clip, flip), guard)?;
        let img = measure::render_guarded(&shape, &cfg, guard)?;
        let (agree, err) = measure::compare(&view, &iso_frame, &img, diag);
        if best.as_ref().is_none_or(|b| agree > b.0) {
            best = Some((agree, flip, shape, img, err));
        }
    }
    let (agree, flipped, shape, fid_img, depth_err) = best.expect("at least one sign");
    let timing: Timing = measure::alternate(&r, &s, args.repeat, &shape, &cfg)?;
    if let Some(dir) = &args.images {
        crate::images::write(dir, &format!("{name}.{}", kind.name()), &view, &iso_frame, &fid_img)?;
    }
    Ok(Row {
        left: format!("{name:<14} {algebra:>4}"),
        timing,
        right: format!("{:>4} {:>6.2}% {:>8.1e}", if flipped { "-f" } else { "f" }, 100.0 * agree, depth_err),
        primitives: None,
    })
}

/// The left and right column headers of a Knoll table.
pub const COLUMNS: (&str, &str) = ("surface         alg", "sign   agree     |dz|");

//! What `render` tells the user after a frame: `--stats` and `--json`
//! reports, and the warnings for unresolved pixels and a sphere traced
//! field's Lipschitz bound.

use super::render::RenderArgs;
use crate::gpu::Gpu;
use crate::render::{Bound, Frame, Settings, SphereOptions, Traversal, Unresolved};
use std::io::Write;

/// Pixels whose traversal ran out of budget hold a best guess, not a hit:
/// always say so (with or without `--stats`), and how they are drawn. A
/// tape or scene field also stops at its interpreter's work limit, and a
/// compiled field at its loops': say which way out there is.
pub(super) fn warn_unresolved(frame: &Frame, t: &Traversal, s: &Settings, field: &str, loops: bool) {
    let n = frame.stats.unresolved;
    if n == 0 {
        return;
    }
    let (what, guess) = match t {
        Traversal::Bisect(_) if field == crate::field::FieldKind::Tape.name() => (
            format!(
                "exhausted the iteration budget (--max-iter {}) or the tape interpreter's work limit ({} loop iterations a pixel, \
                 or {} per SIMD bundle on a device with subgroups, which lavapipe's loop cap imposes; --field compiled has none)",
                s.max_iter,
                crate::field::limits::TAPE_WORK_LIMIT,
                crate::field::limits::TAPE_BUNDLE_LIMIT
            ),
            "the nearest cell that may hold the surface",
        ),
        Traversal::Bisect(_) if field == crate::field::FieldKind::Scene.name() => (
            format!(
                "exhausted the iteration budget (--max-iter {}) or the scene interpreter's work limit ({} node evaluations a pixel, \
                 or {} per SIMD bundle on a device with subgroups, which lavapipe's loop cap imposes; each enclosure runs the tile's pruned tree)",
                s.max_iter,
                crate::field::limits::TAPE_WORK_LIMIT,
                crate::field::limits::TAPE_BUNDLE_LIMIT
            ),
            "the nearest cell that may hold the surface",
        ),
        Traversal::Bisect(_) if loops => (
            format!(
                "exhausted the iteration budget (--max-iter {}) or the work limit of the formula's loops over its repeated terms \
                 ({} loop iterations a pixel, or {} per SIMD bundle on a device with subgroups, which lavapipe's loop cap imposes)",
                s.max_iter,
                crate::field::compiled::term_loops::WORK_LIMIT,
                crate::field::limits::TAPE_BUNDLE_LIMIT
            ),
            "the nearest cell that may hold the surface",
        ),
        Traversal::Bisect(_) => (
            format!("exhausted the iteration budget (--max-iter {})", s.max_iter),
            "the nearest cell that may hold the surface",
        ),
        // A scene's step runs its tile's whole view: a long one spends the
        // loop budget long before --max-steps.
        Traversal::Sphere(o) if field == crate::field::FieldKind::Scene.name() => (
            format!(
                "did not converge within --max-steps {} or the loop budget of {} iterations a pixel (each step evaluates the nodes of the tile's view of the scene)",
                o.max_steps,
                crate::layout::LOOP_LIMIT
            ),
            "their best candidate",
        ),
        Traversal::Sphere(o) => (format!("did not converge within --max-steps {}", o.max_steps), "their best candidate"),
    };
    let drawn = match s.unresolved {
        Unresolved::Hatch => format!("drawn as magenta stripes over {guess} (--unresolved magenta|guess to change)"),
        Unresolved::Magenta => "drawn magenta".to_string(),
        Unresolved::Guess => format!("drawn like hits at {guess} (--unresolved guess)"),
    };
    eprintln!("warning: {n} pixels {what} and are {drawn}");
}

/// Evidence that a sphere traced formula is not a distance bound with the
/// Lipschitz bound given: always say so (surfaces may be missed).
pub(super) fn warn_lipschitz(frame: &Frame, o: &crate::render::SphereOptions) {
    let st = &frame.stats;
    if st.sphere.lipschitz_violations > 0 {
        let seen = format!("{:.3}", st.sphere.lipschitz_seen);
        eprintln!("{}", lipschitz_warning(&st.sphere.lipschitz_violations, &o.lipschitz, &seen));
    }
}

/// The text of [`warn_lipschitz`]: `violations` rays, the bound
/// `lipschitz`, the largest rate `seen` (3 decimals). The viewer passes
/// placeholders and its page fills them from its own frames, so the page
/// and the CLI say the same.
pub(super) fn lipschitz_warning(violations: &dyn std::fmt::Display, lipschitz: &dyn std::fmt::Display, seen: &dyn std::fmt::Display) -> String {
    format!(
        "warning: on {violations} pixels f / {lipschitz} changed faster than the distance along the ray (up to {seen} per unit): the formula is not a distance bound \
         with this Lipschitz bound, and sphere tracing can miss surfaces; give --lipschitz {seen} or more, or use --method bisect"
    )
}

pub(super) fn report(a: &RenderArgs, frame: &Frame, s: &Settings, domain: crate::ir::Domain, gpu: &Gpu, field: &str) {
    let st = &frame.stats;
    let algebra = super::args::algebra_name(domain);
    if a.stats {
        eprintln!(
            "size {}x{}  algebra {algebra}  field {field}  eps {:.3e}  d_max {}\n\
             gpu {:.1} ms (tile pass {:.1})  wall {:.1} ms  dispatches {}\n\
             hits {} ({:.1} %)  unresolved {}\n\
             inclusion evaluations per pixel: mean {:.2}  p99 {}  max {}  (hits {:.2}, misses {:.2}; lower bound {:.2})\n\
             device {}",
            frame.width, frame.height, s.eps, st.bisect.d_max, st.gpu_ms, st.tile_ms, st.wall_ms, st.dispatches, st.hits,
            100.0 * st.hits as f64 / st.pixels.max(1) as f64, st.unresolved, st.evals_mean, st.evals_p99, st.evals_max,
            st.evals_hit_mean, st.evals_miss_mean, st.bisect.evals_lower_bound, gpu.info.describe()
        );
        if let Some(t) = &st.field.tape_lists {
            eprintln!(
                "tape: {} of {} tiles with candidate slabs run a shortened tape, keeping {:.1} % of the value program's {} instructions",
                t.shortened,
                t.tiles,
                100.0 * t.kept_share(),
                t.whole.checked_div(t.shortened).unwrap_or(0)
            );
            let whole = t.whole.checked_div(t.shortened).unwrap_or(0);
            eprintln!("tape: the block pass shortened it for {} of {} blocks of 2x2 tiles, keeping {:.1} %", t.blocks_shortened, t.blocks, 100.0 * t.block_kept_share(whole));
        }
        tile_lists_text(st, None);
        if let Some(l) = &st.field.loop_lists {
            eprintln!(
                "loops: {} of {} tiles with candidate slabs run their own terms of the min/max loops, {:.1} of {} on average",
                l.listed,
                l.tiles,
                l.kept_per_tile(),
                l.terms()
            );
        }
    }
    if a.json {
        let mut v = serde_json::json!({
            "width": frame.width, "height": frame.height, "method": "bisect", "algebra": algebra, "field": field, "eps": s.eps, "d_max": st.bisect.d_max,
            "gpu_ms": st.gpu_ms, "tile_ms": st.tile_ms, "wall_ms": st.wall_ms, "dispatches": st.dispatches,
            "pixels": st.pixels, "hits": st.hits, "unresolved": st.unresolved,
            "evals_mean": st.evals_mean, "evals_p99": st.evals_p99, "evals_max": st.evals_max,
            "evals_hit_mean": st.evals_hit_mean, "evals_miss_mean": st.evals_miss_mean, "evals_lower_bound": st.bisect.evals_lower_bound,
            "device": gpu.info,
        });
        if let Some(t) = &st.field.tape_lists {
            v["tape_tiles"] = t.tiles.into();
            v["tape_shortened_tiles"] = t.shortened.into();
            v["tape_kept_share"] = t.kept_share().into();
            v["tape_blocks"] = t.blocks.into();
            v["tape_shortened_blocks"] = t.blocks_shortened.into();
            v["tape_block_kept_share"] = t.block_kept_share(t.whole.checked_div(t.shortened).unwrap_or(0)).into();
        }
        if st.field.tiles > 0 {
            tile_lists_json(st, &mut v);
        }
        if let Some(l) = &st.field.loop_lists {
            v["loop_tiles"] = l.tiles.into();
            v["loop_listed_tiles"] = l.listed.into();
            v["loop_terms_per_tile"] = l.kept_per_tile().into();
            v["loop_terms"] = l.terms().into();
        }
        let _ = writeln!(std::io::stdout().lock(), "{v}");
    }
}

/// Statistics of a sphere traced frame: steps instead of inclusion
/// evaluations, unconverged pixels, and which techniques were on.
pub(super) fn report_sphere(a: &RenderArgs, frame: &Frame, s: &Settings, o: &SphereOptions, gpu: &Gpu, field: &str) {
    let st = &frame.stats;
    let bound = match o.bound {
        None => "none".to_string(),
        Some(Bound::Sphere { center: c, radius }) => format!("sphere:{},{},{},{radius}", c[0], c[1], c[2]),
        Some(Bound::Box(b)) => format!("box:{},{},{},{},{},{}", b[0], b[1], b[2], b[3], b[4], b[5]),
    };
    let on = |b: bool| if b { "on" } else { "off" };
    if a.stats {
        eprintln!(
            "size {}x{}  method sphere  field {field}  lipschitz {}  eps {:.3e}  max steps {}\n\
             techniques: omega {}  screen-space {}  dynamic eps {}  fixpoint {}  bound {bound}\n\
             gpu {:.1} ms  wall {:.1} ms  dispatches {}\n\
             hits {} ({:.1} %)  unconverged {}\n\
             steps per pixel: mean {:.2}  p99 {}  max {}  (hits {:.2}, misses {:.2}); over-relaxation fallbacks {}\n\
             largest rate of change of f seen along a ray: {:.3}\n\
             device {}",
            frame.width, frame.height, o.lipschitz, s.eps, o.max_steps, o.omega, on(o.screen_space), on(o.dynamic_eps), o.fixpoint,
            st.gpu_ms, st.wall_ms, st.dispatches, st.hits, 100.0 * st.hits as f64 / st.pixels.max(1) as f64, st.unresolved,
            st.evals_mean, st.evals_p99, st.evals_max, st.evals_hit_mean, st.evals_miss_mean, st.sphere.sor_fallbacks, st.sphere.lipschitz_seen,
            gpu.info.describe()
        );
        tile_lists_text(st, Some(if o.synchronized { "tile (synchronised)" } else { "ray" }));
    }
    if a.json {
        let mut v = serde_json::json!({
            "width": frame.width, "height": frame.height, "method": "sphere", "field": field, "eps": s.eps,
            "lipschitz": o.lipschitz, "omega": o.omega, "screen_space": o.screen_space, "dynamic_eps": o.dynamic_eps,
            "fixpoint": o.fixpoint, "bound": bound, "max_steps": o.max_steps, "min_step": o.min_step,
            "shadows": o.shadows, "glass": o.glass,
            "gpu_ms": st.gpu_ms, "wall_ms": st.wall_ms, "dispatches": st.dispatches,
            "pixels": st.pixels, "hits": st.hits, "unconverged": st.unresolved, "unresolved": st.unresolved,
            "steps_mean": st.evals_mean, "steps_p99": st.evals_p99, "steps_max": st.evals_max,
            "steps_hit_mean": st.evals_hit_mean, "steps_miss_mean": st.evals_miss_mean, "sor_fallbacks": st.sphere.sor_fallbacks,
            "lipschitz_violations": st.sphere.lipschitz_violations, "lipschitz_seen": st.sphere.lipschitz_seen,
            "device": gpu.info,
        });
        if st.field.tiles > 0 {
            tile_lists_json(st, &mut v);
            v["scene_walk"] = (if o.synchronized { "tile" } else { "ray" }).into();
        }
        let _ = writeln!(std::io::stdout().lock(), "{v}");
    }
}

/// `--stats` of a field that lists each tile's primitives (a scene): its
/// pre-passes, the active primitives per tile and the pruned trees; with
/// `walk`, sphere tracing's depth slabs and how its rays walk them.
fn tile_lists_text(st: &crate::render::Stats, walk: Option<&str>) {
    let f = &st.field;
    if f.tiles == 0 {
        return;
    }
    eprintln!(
        "scene: field pre-passes {:.1} ms; active primitives per 8x8 tile: mean {:.2}  max {}; tiles over the list limit (whole tree): {}",
        st.field_ms, f.active_mean, f.active_max, f.overflow_tiles
    );
    match walk {
        Some(walk) => eprintln!(
            "scene: depth slabs per tile: mean {:.2}; nodes in a slab's view: mean {:.2}; union or comb tiles (each ray its own primitives): {:.1} %; walk: {walk}",
            f.slabs_mean,
            f.slab_view_mean,
            100.0 * f.chain_share
        ),
        None => eprintln!("scene: nodes in a tile's pruned tree: mean {:.2}; union or comb tiles: {:.1} %", f.slab_view_mean, 100.0 * f.chain_share),
    }
}

/// The JSON of [`tile_lists_text`].
fn tile_lists_json(st: &crate::render::Stats, v: &mut serde_json::Value) {
    v["field_ms"] = st.field_ms.into();
    v["active_mean"] = st.field.active_mean.into();
    v["active_max"] = st.field.active_max.into();
    v["overflow_tiles"] = st.field.overflow_tiles.into();
    v["slabs_mean"] = st.field.slabs_mean.into();
    v["slab_view_mean"] = st.field.slab_view_mean.into();
    v["chain_share"] = st.field.chain_share.into();
}

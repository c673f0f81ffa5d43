//! Per-tile term lists of a compiled formula's rerolled `min` and `max`
//! loops (`crate::field::compiled::term_loops::lists`, `templates/fields/loop_tiles.wgsl`):
//! the tile pass notes which terms can be the loop's result over each
//! tile's candidate slabs, and the per-pixel pass runs only those. The
//! picture must be the one the whole loops draw, and the f64 reference's.

use super::common;

use common::gpu;
use crate::field::compiled::term_loops::{self, lists};
use crate::ir::Domain;
use crate::gpu::Renderer;
use crate::render::{BisectOptions, Frame, Settings, Status, Traversal};
use crate::Formula;

/// `n` ball distances at pseudo-random centres in [-1, 1]³ (radii 0.06 to
/// 0.18), seeded.
fn balls(n: usize, seed: u64) -> Vec<String> {
    let mut state = seed;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 11) as f64) / ((1u64 << 53) as f64)
    };
    (0..n)
        .map(|_| {
            let (a, b, c, r) = (2.0 * next() - 1.0, 2.0 * next() - 1.0, 2.0 * next() - 1.0, 0.06 + 0.12 * next());
            format!("sqrt((x - {a:.3})^2 + (y - {b:.3})^2 + (z - {c:.3})^2) - {r:.3}")
        })
        .collect()
}

/// Bisection of `f` in `domain` with the per-tile lists on or off.
fn bisect(f: &Formula, domain: Domain, s: &Settings, lists: bool) -> Frame {
    let mut r = Renderer::new(gpu(), &f.ir, Traversal::Bisect(BisectOptions::new(domain))).unwrap();
    r.optimizations_mut().expect("bisection").tape_shortening = lists;
    r.render(s).unwrap()
}

/// Renders `src` with and without lists in IA and RAA: the same pixels hit,
/// at depths within 2 eps and normals within 0.05 (the tiles' enclosures
/// are tighter, so cells and root searches may differ), and the tiles that
/// run lists (at least `listed` of those with candidate slabs: a tile whose
/// list would cost more than twice the whole loops' iterations runs them)
/// keep at most `share` of the loops' terms on average.
fn lists_draw_the_whole_loops_picture(src: &str, size: u32, listed: f64, share: f64) {
    let f = Formula::compile("<loops>", src).unwrap();
    let l = lists::for_formula(&f.ir).expect("a listed loop");
    let s = common::settings(common::cube(1.3), size, size);
    for domain in [Domain::Interval, Domain::Affine] {
        let on = bisect(&f, domain, &s, true);
        let off = bisect(&f, domain, &s, false);
        assert!(on.stats.hits > 300 && on.stats.unresolved == 0 && off.stats.unresolved == 0, "{:?} {:?}", on.stats, off.stats);
        let st = on.stats.field.loop_lists.expect("list statistics");
        assert!(st.listed > 0 && st.listed as f64 >= listed * st.tiles as f64, "{domain:?}: {st:?}");
        assert_eq!(st.terms(), u64::from(l.terms));
        assert!(st.kept_per_tile() <= share * f64::from(l.terms), "{domain:?}: {st:?}");
        assert_eq!(off.stats.field.loop_lists.expect("counted").listed, 0);
        let mut differ = Vec::new();
        for (k, (p, q)) in on.pixels.iter().zip(&off.pixels).enumerate() {
            let normal = (0..3).map(|i| (p.normal[i] - q.normal[i]).abs()).fold(0.0f32, f32::max);
            if p.status != q.status || (p.status == Status::Hit && ((p.depth - q.depth).abs() > 2.0 * s.eps as f32 || normal > 0.05)) {
                differ.push((k, p.depth, q.depth, normal));
            }
        }
        assert!(differ.is_empty(), "{domain:?}: {} pixels differ: {:?}", differ.len(), &differ[..differ.len().min(5)]);
    }
}

/// A union of 200 balls, written as one variadic `min`.
#[test]
fn a_union_of_distances_draws_the_same_with_lists() {
    lists_draw_the_whole_loops_picture(&format!("min({})", balls(200, 7).join(", ")), 96, 0.8, 0.3);
}

/// An intersection: a `max` of 140 slabs' distances along tilted normals,
/// written through abs (no square roots), inside a larger formula whose
/// other operations see the loop's value. Many faces can be the largest
/// over a tile's slabs, so at 192² a fifth of the tiles run lists.
#[test]
fn an_intersection_inside_a_formula_draws_the_same_with_lists() {
    let planes: Vec<String> = (0..140)
        .map(|i| {
            let a = 0.045 * i as f64;
            format!("abs({:.3}*x + {:.3}*y + {:.3}*z) - 0.9", a.cos() * 0.8, a.sin() * 0.8, 0.6 * (0.9 * i as f64).sin())
        })
        .collect();
    let chain = planes[1..].iter().fold(planes[0].clone(), |a, b| format!("max({a}, {b})"));
    lists_draw_the_whole_loops_picture(&format!("{chain} + 0.03*sin(7*x)"), 192, 0.1, 0.5);
}

/// A union drawn with lists has the f64 reference's first root at every
/// hit pixel, and no pixel the reference hits is missed.
#[test]
fn a_listed_union_has_the_reference_roots() {
    let f = Formula::compile("<balls>", &format!("min({})", balls(150, 3).join(", "))).unwrap();
    let s = common::settings(common::cube(1.3), 40, 40);
    let a = bisect(&f, Domain::Interval, &s, true);
    assert!(a.stats.field.loop_lists.is_some_and(|l| l.listed > 0), "{:?}", a.stats);
    let mut wrong = Vec::new();
    for (k, p) in a.pixels.iter().enumerate() {
        let (i, j) = (k as u32 % s.width, k as u32 / s.width);
        match (p.status, common::reference_root(&f, &s, i, j, 2000)) {
            (Status::Hit, Some((t, w))) if (f64::from(p.depth) - t).abs() <= w + 4.0 * s.eps => {}
            (Status::Miss, None) => {}
            (st, r) => wrong.push(format!("({i},{j}) {st:?} {} vs {r:?}", p.depth)),
        }
    }
    assert!(wrong.is_empty(), "{wrong:?}");
}

/// A union a program writes in no order, balls, boxes and cylinders by
/// turns (420 operands): the front end groups its operands by shape
/// (`sema::chains`), so it is three listed loops, not 420 written-out
/// terms. Its first roots are the f64 reference's, and small tiles, which
/// keep few terms, draw what the whole loops draw. (Large tiles keep most
/// terms, and run the whole loops: a list would cost more iterations.)
#[test]
fn a_union_of_three_shapes_in_no_order_is_three_listed_loops() {
    let b = balls(140, 5);
    let shapes: Vec<String> = (0..140)
        .flat_map(|i| {
            let (a, c, h) = (-0.9 + 0.013 * i as f64, (0.7 * i as f64).sin() * 0.9, 0.04 + 0.0005 * i as f64);
            [
                b[i].clone(),
                format!("max(abs(x - {a:.3}) - {h:.3}, abs(y - {c:.3}) - 0.05, abs(z + {c:.3}) - 0.06)"),
                format!("max(sqrt((x - {c:.3})^2 + (z - {a:.3})^2) - {h:.3}, abs(y - {a:.3}) - 0.1)"),
            ]
        })
        .collect();
    let f = Formula::compile("<shapes>", &format!("min({})", shapes.join(", "))).unwrap();
    let l = lists::for_formula(&f.ir).expect("listed loops");
    assert_eq!((l.loops.len(), l.terms), (3, 408), "{l:?}");
    let s = common::settings(common::cube(1.3), 32, 32);
    let a = bisect(&f, Domain::Interval, &s, true);
    assert!(a.stats.hits > 150 && a.stats.unresolved == 0, "{:?}", a.stats);
    let mut wrong = Vec::new();
    for (k, p) in a.pixels.iter().enumerate() {
        let (i, j) = (k as u32 % s.width, k as u32 / s.width);
        // A ray that grazes a box's edge is inside it for less than the
        // coarse reference's step: where that one disagrees, a finer one.
        let agrees = |r: Option<(f64, f64)>| match (p.status, r) {
            (Status::Hit, Some((t, w))) => (f64::from(p.depth) - t).abs() <= w + 4.0 * s.eps,
            (st, r) => st == Status::Miss && r.is_none(),
        };
        if !agrees(common::reference_root(&f, &s, i, j, 1000)) && !agrees(common::reference_root(&f, &s, i, j, 100_000)) {
            wrong.push(format!("({i},{j}) {:?} {}", p.status, p.depth));
        }
    }
    assert!(wrong.is_empty(), "{wrong:?}");
    let s = common::settings(common::cube(1.3), 160, 160);
    let (on, off) = (bisect(&f, Domain::Interval, &s, true), bisect(&f, Domain::Interval, &s, false));
    let st = on.stats.field.loop_lists.expect("counted");
    assert!(2 * st.listed > st.tiles && st.kept_per_tile() < 0.25 * 408.0 && on.stats.unresolved == 0, "{st:?} {:?}", on.stats);
    let differ = on.pixels.iter().zip(&off.pixels).filter(|(p, q)| p.status != q.status || (p.status == Status::Hit && (p.depth - q.depth).abs() > 2.0 * s.eps as f32)).count();
    assert_eq!(differ, 0, "{st:?}");
}

/// Loops whose terms may make f undefined (a square root of `x − a`), sums,
/// several surfaces and short loops get no lists: leaving a term out could
/// lose an emptiness, a sum's terms all count, the lists are made for one
/// f, and below `MIN_LISTED_TERMS` they cost more compile than they save.
#[test]
fn only_min_and_max_loops_of_defined_terms_are_listed() {
    let listed = |src: &str| {
        let f = Formula::compile("<t>", src).unwrap();
        assert_eq!(term_loops::plan(&f.ir).loops.len(), 1, "{src}");
        lists::for_formula(&f.ir).map(|l| (l.loops.len(), l.terms))
    };
    let roots: Vec<String> = (0..140).map(|i| format!("sqrt(x - {:.3}) - 0.{}", -0.5 + 0.001 * i as f64, i % 9 + 1)).collect();
    assert_eq!(listed(&format!("min({})", roots.join(", "))), None);
    let sum: Vec<String> = (0..140).map(|i| format!("sin({:.2}*x)*y", 1.0 + 0.1 * i as f64)).collect();
    assert_eq!(listed(&sum.join(" + ")), None);
    assert_eq!(listed(&format!("min({}) where z > 0", balls(140, 1).join(", "))), None);
    assert_eq!(listed(&format!("min({})", balls(100, 1).join(", "))), None);
    assert!(lists::MIN_LISTED_TERMS > 96);
    // The first ball seeds the loop and 136 run in it (17 iterations of 8);
    // the last 3 are left over, written out.
    assert_eq!(listed(&format!("min({})", balls(140, 1).join(", "))), Some((1, 136)));
}

/// The kernel with lists spends its list in the per-pixel pass only: the
/// whole loop, fewer terms an iteration, stays beside it for rays outside
/// the tile's candidate slabs, and the tile pass notes the terms in a
/// second, short pass.
#[test]
fn the_kernel_runs_lists_per_pixel_and_notes_them_in_the_tile_pass() {
    let f = Formula::compile("<balls>", &format!("min({})", balls(150, 5).join(", "))).unwrap();
    let r = Renderer::new(gpu(), &f.ir, Traversal::Bisect(BisectOptions::new(Domain::Interval))).unwrap();
    let w = r.wgsl();
    assert!(w.contains("if (g_loop_list != 0u && admitted) {"), "the listed loop");
    assert!(w.contains("loop_note("), "the tile pass's notes");
    assert!(w.contains("let PAD = vec2<f32>(vec2<f32>(-2.0, 2.0) * gradient_step_size());"), "padded slabs");
    let sphere = Renderer::new(gpu(), &f.ir, Traversal::Sphere(Default::default())).unwrap();
    assert!(!sphere.wgsl().contains("g_loop_list"), "sphere tracing has no tile lists");
    let s = common::settings(common::cube(1.3), 32, 32);
    assert!(sphere.render(&s).unwrap().stats.hits > 50);
}

/// The browser page binds the lists as `render` does: the field group of
/// a bisection kernel with a listed loop has the lists' words per tile and
/// their counts; sphere tracing's has neither. (The browser suite cannot
/// draw such a formula in CI time: SwiftShader takes over 90 s to create
/// the pipeline of a `min` loop of 100 terms, with lists or without.)
#[test]
fn the_page_binds_the_lists_for_bisection_only() {
    let f = Formula::compile("<balls>", &format!("min({})", balls(150, 5).join(", "))).unwrap();
    let l = lists::for_formula(&f.ir).expect("listed");
    let s = common::settings(common::cube(1.3), 64, 64);
    let bisect = crate::view::program(&f.ir, &Traversal::Bisect(BisectOptions::new(Domain::Interval)), &s).unwrap();
    let group = &bisect.groups[1];
    let named = |n: &str| group.iter().find(|b| b.name == n).map(|b| (b.binding, serde_json::to_value(&b.size).unwrap()));
    assert_eq!(named("loop lists"), Some((1, serde_json::json!({"kind": "per_tile", "bytes": l.bytes(1)}))));
    assert_eq!(named("loop list counts"), Some((4, serde_json::json!({"kind": "fixed", "bytes": 16}))));
    assert!(bisect.wgsl.contains("var<storage, read_write> loop_lists"));
    let sphere = crate::view::program(&f.ir, &Traversal::Sphere(Default::default()), &s).unwrap();
    assert!(sphere.groups[1].iter().all(|b| !b.name.starts_with("loop list")));
}

/// Counted per lane (a device without subgroups), a tile pass over a union
/// of 700 balls runs past the work limit in tiles with several candidate
/// coarse slabs: those tiles' notes are incomplete, so they run the whole
/// loop (and their fine slabs do not run a coarse slab's short list). No
/// pixel that lists off hit is missed, every pixel both hit agrees, and
/// every hit has the f64 reference's root.
#[test]
fn tiles_past_the_work_limit_run_the_whole_loop() {
    // Without spaces, within the front end's 64 KiB.
    let f = Formula::compile("<balls>", &format!("min({})", balls(700, 9).join(",")).replace(' ', "")).unwrap();
    let s = common::settings(common::cube(1.3), 40, 40);
    let mut per_lane = crate::gpu::Gpu::new().unwrap();
    per_lane.subgroups = false;
    let t = || Traversal::Bisect(BisectOptions::new(Domain::Interval));
    let mut on = Renderer::new(&per_lane, &f.ir, t()).unwrap();
    let a = on.render(&s).unwrap();
    let st = a.stats.field.loop_lists.expect("counted");
    assert!(st.listed > 0 && st.listed < st.tiles, "some tiles listed, some not: {st:?}");
    on.optimizations_mut().expect("bisection").tape_shortening = false;
    let b = on.render(&s).unwrap();
    let mut wrong = Vec::new();
    for (k, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        let (i, j) = (k as u32 % s.width, k as u32 / s.width);
        if p.status == Status::Hit && q.status == Status::Hit && (p.depth - q.depth).abs() > 2.0 * s.eps as f32 {
            wrong.push(format!("({i},{j}) {} vs {}", p.depth, q.depth));
        }
        if p.status == Status::Miss && q.status == Status::Hit {
            wrong.push(format!("({i},{j}) missed, {} without lists", q.depth));
        }
        if p.status == Status::Hit {
            match common::reference_root(&f, &s, i, j, 2000) {
                Some((t, w)) if (f64::from(p.depth) - t).abs() <= w + 4.0 * s.eps => {}
                r => wrong.push(format!("({i},{j}) {} vs the reference {r:?}", p.depth)),
            }
        }
    }
    assert!(wrong.is_empty() && a.stats.hits > 100, "{:?} {st:?}: {wrong:?}", a.stats);
}

//! Rerolled terms (`crate::field::compiled::term_loops`): a long sum of same-shaped terms is
//! compiled as a loop over a table of its constants. It must give what the
//! same sum written out gives: the same enclosures on the device (and they
//! hold f64 samples), the same picture, and pixels past the loops' work
//! limit reported, never drawn from a cut-off sum.
//!
//! The written-out reference is the same sum with every other term's
//! second factor written `z − (−b)`: the shapes alternate, so no run is
//! long enough to reroll, and each operation gives what `z + b` gives
//! (subtracting a negated f32, or its negated enclosure, is adding it in
//! every domain), so the values are the same. (Swapped factors would no
//! longer do: a run compares a product's operands in a fixed order.)

use super::common;

use common::gpu;
use crate::field::compiled::term_loops;
use crate::ir::Domain;
use crate::gpu::eval::{eval_boxes, Box8};
use crate::gpu::Renderer;
use crate::render::{BisectOptions, Status, Traversal};
use crate::Formula;

/// The sum of `n` terms (a x³ − 0.5)(z + b) on the unit sphere; `alternate`
/// writes every other term's second factor as `z − (−b)`. Each term is of degree
/// 4: a node of degree ≤ 2 in x, y, z with two or more terms is taken from
/// the ray when written out but not inside a loop (`field::compiled::ray_forms`),
/// and a sum of bilinear terms would be one such node, whose code would
/// stand in for the loop's in both versions.
fn sum(n: usize, alternate: bool) -> Formula {
    let terms: Vec<String> = (0..n)
        .map(|i| {
            let (a, b) = (0.5 + i as f64 * 0.013, i as f64 * 0.021 - 0.3);
            if alternate && i % 2 == 1 { format!("({a:.3}*x^3-0.5)*(z-({:.3}))", -b) } else { format!("({a:.3}*x^3-0.5)*(z+{b:.3})") }
        })
        .collect();
    Formula::compile("<test>", &format!("x^2 + y^2 + z^2 - 1 + 0.004*({})", terms.join(" + "))).unwrap()
}

#[test]
fn only_the_uniform_sum_is_rerolled() {
    let (rolled, written) = (sum(300, false), sum(300, true));
    let plan = term_loops::plan(&rolled.ir);
    assert_eq!(plan.loops.len(), 1);
    let l = &plan.loops[0];
    assert_eq!((l.slots, l.unroll * l.iterations), (3, 296), "{l:?}");
    assert!(plan.emitted_nodes(&rolled.ir) < 100, "{}", plan.emitted_nodes(&rolled.ir));
    assert!(term_loops::plan(&written.ir).loops.is_empty());
}

/// Boxes around the sphere, some thin, some points.
pub(super) fn boxes(n: usize) -> Vec<Box8> {
    common::points(1.3, n, 7)
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let w = [0.0, 1e-3, 0.05, 0.4][i % 4] as f32;
            let c = p.map(|v| v as f32);
            [c[0] - w, c[0] + w, c[1] - w * 0.5, c[1] + w, c[2] - w, c[2] + w * 0.25, 0.0, 0.0]
        })
        .collect()
}

/// Every enclosure in `r` holds f's f64 values at `samples` points along
/// its box's diagonal (within f32 rounding: the conformance suite checks
/// the op libraries' own rounding).
pub(super) fn assert_encloses(f: &Formula, r: &[[f32; 2]], bx: &[Box8], samples: usize, what: &str) {
    for (k, (e, b8)) in r.iter().zip(bx).enumerate() {
        for s in 0..samples {
            let w = s as f64 / (samples - 1) as f64;
            let p = [0, 2, 4].map(|i| f64::from(b8[i]) + w * f64::from(b8[i + 1] - b8[i]));
            let v = crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]);
            let tol = 1e-5 * (1.0 + v.abs());
            assert!(f64::from(e[0]) - tol <= v && v <= f64::from(e[1]) + tol, "{what} box {k}: {v} outside {e:?}");
        }
    }
}

/// Bit for bit at 28 terms (a written-out chain of 32 or more is generated
/// as a balanced tree, `crate::field::compiled::balance`, which rounds differently); at
/// 300 both hold f64 samples of the sum.
#[test]
fn a_rerolled_sum_has_the_enclosures_of_the_written_out_sum() {
    let bx = boxes(2000);
    for n in [28, 300] {
        let (rolled, written) = (sum(n, false), sum(n, true));
        for domain in [Domain::Scalar, Domain::Interval, Domain::Affine] {
            let a = eval_boxes(gpu(), &rolled.ir, domain, &bx, &[]).unwrap();
            let b = eval_boxes(gpu(), &written.ir, domain, &bx, &[]).unwrap();
            if n < 32 {
                let differ = a.iter().zip(&b).filter(|(p, q)| p != q).count();
                assert_eq!(differ, 0, "{domain:?}: {differ} of {} boxes differ", bx.len());
            }
            if domain == Domain::Scalar {
                continue;
            }
            // And they hold f64 samples of the sum.
            assert_encloses(&rolled, &a, &bx, 5, &format!("{n} terms {domain:?}"));
            assert_encloses(&written, &b, &bx, 5, &format!("{n} terms, written out, {domain:?}"));
        }
    }
}

/// (28 terms: a written-out chain of 32 or more is generated as a balanced
/// tree, `crate::field::compiled::balance`, whose rounding differs.) The rerolled sum's
/// cells run their scalar work from one call site (`cells_resumable.wgsl`,
/// `crate::kernel::cells_resume`), the written-out sum's inline: the
/// same pixels hit, at depths within 2 eps (the root searches differ).
#[test]
fn a_rerolled_sum_draws_the_written_out_sums_picture() {
    let s = common::settings(common::cube(1.6), 96, 96);
    let (rolled, written) = (sum(28, false), sum(28, true));
    assert_eq!(term_loops::plan(&rolled.ir).loops.len(), 1);
    for domain in [Domain::Interval, Domain::Affine] {
        let t = Traversal::Bisect(BisectOptions::new(domain));
        let a = Renderer::new(gpu(), &rolled.ir, t.clone()).unwrap().render(&s).unwrap();
        let b = Renderer::new(gpu(), &written.ir, t).unwrap().render(&s).unwrap();
        assert!(a.stats.hits > 500 && a.stats.unresolved == 0, "{:?}", a.stats);
        let differ = a.pixels.iter().zip(&b.pixels).filter(|(p, q)| p.status != q.status || (p.depth - q.depth).abs() > 2.0 * s.eps as f32).count();
        assert_eq!(differ, 0, "{domain:?}: {differ} pixels differ");
    }
}

/// A sum long enough that hard pixels' evaluations pass the work limit
/// (4,600 terms `c·t` on the tangle cube at t = 0, 143 iterations an
/// evaluation; terms `c·x` would be like terms, collected into one by the
/// semantic pass, which leaves t alone):
/// in one round of the per-pixel pass, those pixels are reported
/// unresolved; the rounds after it resume them at their cells
/// (`cells_resumable.wgsl`); every pixel drawn as a hit has the f64
/// reference's first root.
#[test]
fn pixels_past_the_loops_work_limit_are_reported_not_cut_short() {
    let s = common::settings(common::cube(3.0), 48, 48);
    let terms: Vec<String> = (1..=4600).map(|i| format!("{:.9}*t", i as f64 * 1e-9)).collect();
    let long = Formula::compile("<test>", &format!("x^4-5*x^2+y^4-5*y^2+z^4-5*z^2+11.8+({})", terms.join("+"))).unwrap();
    let plan = term_loops::plan(&long.ir);
    assert_eq!((plan.loops[0].unroll, plan.iterations()), (32, 143));
    let t = || Traversal::Bisect(BisectOptions::new(Domain::Interval));
    // Counted per invocation (a device without subgroups): in one round
    // some pixels stop; the next rounds resume them.
    let mut per_lane = crate::gpu::Gpu::new().unwrap();
    per_lane.subgroups = false;
    let mut r = Renderer::new(&per_lane, &long.ir, t()).unwrap();
    r.set_resume_rounds(0);
    let one = r.render(&s).unwrap();
    assert!(one.stats.unresolved > 0 && one.stats.hits > 200, "{:?}", one.stats);
    r.set_resume_rounds(3);
    let lane = r.render(&s).unwrap();
    // (The stopped pixels may all be misses: a cell's midpoint costs the
    // loops no evaluation of their own, `field::compiled::midpoint`.)
    assert!(lane.stats.unresolved == 0 && lane.stats.hits >= one.stats.hits, "{:?} {:?}", lane.stats, one.stats);
    let mut frames = vec![("one round, per lane", one), ("per lane", lane)];
    // Counted per SIMD bundle, as lavapipe's cap counts: the same pixels resolve.
    if gpu().subgroups {
        let r = Renderer::new(gpu(), &long.ir, t()).unwrap();
        assert!(r.wgsl().contains("subgroupMax"));
        let bundle = r.render(&s).unwrap();
        assert_eq!(bundle.stats.unresolved, 0, "{:?}", bundle.stats);
        frames.push(("per bundle", bundle));
    }
    for (name, a) in frames {
        let mut wrong = Vec::new();
        for (k, p) in a.pixels.iter().enumerate().filter(|(_, p)| p.status == Status::Hit) {
            let (i, j) = (k as u32 % s.width, k as u32 / s.width);
            match common::reference_root(&long, &s, i, j, 300) {
                Some((t, w)) if (f64::from(p.depth) - t).abs() <= w + 4.0 * s.eps => {}
                r => wrong.push(format!("({i},{j}) {} vs {r:?}", p.depth)),
            }
        }
        assert!(wrong.is_empty(), "{name}: {wrong:?}");
    }
}

/// The traversal's budget leaves room for the loops' work: `--max-iter` is
/// at most 16,000 with such a formula, said in the error.
#[test]
fn a_formula_of_loops_caps_the_traversals_budget() {
    let f = sum(40, false);
    let mut s = common::settings(common::cube(1.6), 16, 16);
    s.max_iter = 20_000;
    let t = Traversal::Bisect(BisectOptions::new(Domain::Interval));
    let e = Renderer::new(gpu(), &f.ir, t).unwrap().render(&s).err().expect("refused").to_string();
    assert!(e.contains("at most 16000 with a formula of rerolled terms (its loops share lavapipe's 65,535 loop iterations)"), "{e}");
}

/// A union (`min` chain) of 30 same-shaped balls is a loop too: its
/// picture is the tape's (an independent path) at every pixel both resolve.
#[test]
fn a_rerolled_union_draws_what_the_tape_draws() {
    let balls = distances();
    let mut src = balls[0].clone();
    for b in &balls[1..] {
        src = format!("min({src}, {b})");
    }
    draws_what_the_tape_draws(&src);
}

/// 30 balls as distances: a ball's polynomial x² + … − r² would be taken
/// whole from the ray, which keeps such terms written out
/// (`crate::field::compiled::term_loops`).
fn distances() -> Vec<String> {
    (0..30).map(|i| format!("sqrt((x - {:.3})^2 + (y - {:.3})^2 + z^2) - 0.2", -1.2 + 0.08 * i as f64, 0.5 * (0.7 * i as f64).sin())).collect()
}

/// The picture of `src` compiled (one loop, the plan says) against the
/// tape's, an independent path, in IA and RAA: the same pixel by pixel
/// where both resolve, depth within 2 eps.
fn draws_what_the_tape_draws(src: &str) {
    let f = Formula::compile("<terms>", src).unwrap();
    assert_eq!(term_loops::plan(&f.ir).loops.len(), 1);
    let s = common::settings(common::cube(1.5), 96, 96);
    for domain in [Domain::Interval, Domain::Affine] {
        let t = Traversal::Bisect(BisectOptions::new(domain));
        let a = Renderer::new(gpu(), &f.ir, t.clone()).unwrap().render(&s).unwrap();
        let tape = crate::field::TapeData::new(&f.ir).unwrap();
        let b = Renderer::new(gpu(), &tape, t).unwrap().render(&s).unwrap();
        assert!(a.stats.hits > 300 && a.stats.unresolved == 0 && b.stats.unresolved == 0, "{:?} {:?}", a.stats, b.stats);
        let differ = a.pixels.iter().zip(&b.pixels).filter(|(p, q)| p.status != q.status || (p.status == Status::Hit && (p.depth - q.depth).abs() > 2.0 * s.eps as f32)).count();
        assert_eq!(differ, 0, "{domain:?}");
    }
}

/// `min(s_0, s_1, …)` of 30 balls as distances: the front end nests the
/// chain in second operands, and every term has a square root.
#[test]
fn a_rerolled_min_of_distances_draws_what_the_tape_draws() {
    draws_what_the_tape_draws(&format!("min({})", distances().join(", ")));
}

/// A sum of square roots is empty where one root's argument is negative
/// (x < −0.02 here): the loop gathers its roots' emptiness, which an affine
/// sum would lose (an empty form plus another is no longer empty), so the
/// part of the sphere with x ≥ −0.02 is all that is drawn, in RAA as in IA.
#[test]
fn a_rerolled_sum_of_roots_is_empty_where_a_root_is() {
    // The roots' ends −0.6 to −0.02 in a shuffled order, so that the ones
    // written out (the first, which seeds the loop, and the last, left
    // over) are −0.6 and −0.14, defined from x = −0.14 on.
    let roots: Vec<String> = (0..30).map(|i| format!("{:.4}*sqrt(x - {:.3})", 0.002 + 0.0001 * i as f64, -0.6 + 0.02 * ((i * 7) % 30) as f64)).collect();
    let src = format!("x^2 + y^2 + z^2 - 1 + {}", roots.join(" + "));
    draws_what_the_tape_draws(&src);
    // Boxes with −0.13 ≤ x ≤ −0.1, where only roots of the loop are
    // undefined: empty.
    let f = Formula::compile("<roots>", &src).unwrap();
    let bx: Vec<Box8> = (0..64).map(|i| [-0.13, -0.1 - 0.0004 * i as f32, -0.2, 0.3, -0.9, 0.9, 0.0, 0.0]).collect();
    for domain in [Domain::Interval, Domain::Affine] {
        let r = eval_boxes(gpu(), &f.ir, domain, &bx, &[]).unwrap();
        assert!(r.iter().all(|e| e[0] > e[1]), "{domain:?}: {:?}", &r[..4]);
    }
}

/// Random term shapes (a small generator over + − × / sin cos exp abs min
/// max sqrt and squares), each summed 17 to 40 times with random constants: the
/// sum is rerolled, its kernel validates, and its enclosures on the device
/// hold f64 samples in IA and RAA.
#[test]
fn random_term_shapes_rerolled_enclose() {
    let (rerolled, roots, _) = random_term_shapes(0x2545_f491_4f6c_dd1d, 1000);
    assert!(rerolled >= 15, "{rerolled} of 24 shapes rerolled");
    assert!(roots >= 2, "{roots} rerolled shapes with a square root");
}

/// The same with the constants inside each term from eight values (none
/// 0 or ±1, which the front end folds away; each term's factor stays one
/// of 4,001, so that terms differ), so that terms share nodes by chance
/// (`0.3*x` in several terms is one node) and a commutative
/// node's operands come in either order: the loops copy the shared nodes
/// into each term and compute every term in the first one's order.
#[test]
fn random_term_shapes_with_coinciding_constants_rerolled_enclose() {
    let (rerolled, _, shared) = random_term_shapes(0x9e37_79b9_7f4a_7c15, 0);
    assert!(rerolled >= 12, "{rerolled} of 24 shapes rerolled");
    assert!(shared >= 5, "{shared} rerolled sums with nodes their terms share");
}

/// 24 random shapes, summed with constants of `scale` steps per unit in
/// [−2, 2] (0: the factor so, the others from eight values): (sums rerolled, of them with a square
/// root, of them whose terms share a node).
fn random_term_shapes(seed: u64, scale: u64) -> (usize, usize, usize) {
    let mut seed = seed;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    fn shape(r: &mut dyn FnMut() -> u64, depth: u32) -> String {
        if depth > 2 || r() % 10 < 3 {
            return ["x", "y", "z", "C"][(r() % 4) as usize].to_string();
        }
        let (a, b) = (shape(r, depth + 1), shape(r, depth + 1));
        match r() % 10 {
            0 => format!("({a} + {b})"),
            1 => format!("({a} - {b})"),
            2 => format!("({a} * {b})"),
            3 => format!("({a} / (1.5 + {b}^2))"),
            4 => format!("sin({a})"),
            5 => format!("exp(-({a})^2)"),
            6 => format!("abs({a})"),
            7 => format!("min({a}, {b})"),
            8 => format!("sqrt(0.2 + ({a})^2)"),
            _ => format!("max({a}, {b})"),
        }
    }
    let (mut rerolled, mut roots, mut shared) = (0, 0, 0);
    for case in 0..24 {
        let t = format!("(C*{})", shape(&mut next, 0));
        let n = 17 + (next() % 24) as usize;
        let terms: Vec<String> = (0..n)
            .map(|_| {
                let mut s = t.clone();
                let mut first = true;
                while s.contains('C') {
                    let c = match scale {
                        0 if !first => [0.3, 0.7, 1.3, -0.6, 1.7, -1.4, 0.2, -0.9][(next() % 8) as usize],
                        0 => (next() % 4001) as f64 / 1000.0 - 2.0,
                        _ => (next() % (4 * scale + 1)) as f64 / scale as f64 - 2.0,
                    };
                    first = false;
                    s = s.replacen('C', &format!("{c:.3}"), 1);
                }
                s
            })
            .collect();
        let f = Formula::compile("<random>", &format!("x^2 + y^2 + z^2 - 1 + 0.01*({})", terms.join(" + "))).unwrap();
        let plan = term_loops::plan(&f.ir);
        if plan.loops.is_empty() {
            continue;
        }
        rerolled += 1;
        roots += usize::from(t.contains("sqrt"));
        // A node the loop computes for several terms: the loop's body is
        // larger than the IR's nodes it leaves to the loop, per term.
        let left = f.ir.live().into_iter().filter(|&n| plan.skips(n) && plan.loop_at(n).is_none()).count();
        let looped: usize = plan.loops.iter().map(|l| l.body.len() * l.unroll * l.iterations).sum();
        shared += usize::from(looped > left);
        let bx = boxes(200);
        for domain in [Domain::Interval, Domain::Affine] {
            let r = eval_boxes(gpu(), &f.ir, domain, &bx, &[]).unwrap_or_else(|e| panic!("case {case} {t}: {e}"));
            assert_encloses(&f, &r, &bx, 3, &format!("case {case} {t} {domain:?}"));
        }
    }
    (rerolled, roots, shared)
}


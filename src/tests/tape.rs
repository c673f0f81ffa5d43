//! The tape field source: its kernels do not depend on the formula (a new
//! formula is a buffer, never a pipeline), and its renders agree with the
//! compiled field's (bisection in IA and RAA over the Knoll suite, sphere
//! tracing over the sdf suite) and with the f64 CPU reference.

use super::common;

use common::gpu;
use crate::field::tape::features;
use crate::kernel::assemble;
use crate::ir::Domain;
use crate::field::TapeData;
use crate::gpu::Renderer;
use crate::render::{BisectOptions, Frame, Settings, SphereOptions, Status, Traversal};
use crate::Formula;
use std::sync::atomic::Ordering;

fn tape(src: &str) -> (Formula, TapeData) {
    let f = Formula::compile("<test>", src).unwrap();
    let t = TapeData::new(&f.ir).unwrap();
    (f, t)
}

#[test]
fn tape_kernels_depend_on_the_operation_groups_not_the_formula() {
    let (_, a) = tape("x^2 + y^2 + z^2 - 1");
    let (_, a2) = tape("x^2 + 2*y^2 + z^2 - 1.5");
    let (_, b) = tape("sin(x*y) + pow(abs(z), 1.5) - atan2(y, x)*min(x, z)/(1 + y^2)");
    assert_eq!(a.features, a2.features);
    assert_ne!(a.features, b.features);
    let (mut wide_a, mut wide_b) = (a.clone(), b.clone());
    wide_a.features = features::ALL;
    wide_b.features = features::ALL;
    for t in [
        Traversal::Bisect(BisectOptions::new(Domain::Interval)),
        Traversal::Bisect(BisectOptions::new(Domain::Affine)),
        Traversal::Sphere(SphereOptions::default()),
    ] {
        let ka = assemble(&a, &t).wgsl;
        assert_eq!(ka, assemble(&a2, &t).wgsl);
        let kb = assemble(&b, &t).wgsl;
        assert!(ka.len() < kb.len(), "{t:?}: the polynomial kernel has fewer cases");
        assert!(!ka.contains("if (code == TAPE_SIN) {") && kb.contains("if (code == TAPE_SIN) {"));
        let wide = assemble(&wide_a, &t).wgsl;
        assert_eq!(wide, assemble(&wide_b, &t).wgsl);
        for k in [&ka, &kb, &wide] {
            crate::validate::validate(k).unwrap_or_else(|e| panic!("{t:?}: {e}"));
        }
    }
}

/// A kernel built for a polynomial refuses a tape with sines (naming what
/// is missing) and draws any polynomial; one built wider draws both.
#[test]
fn a_tape_beyond_the_kernel_is_refused_by_name() {
    let s = common::settings(common::cube(2.0), 16, 16);
    let (_, sphere) = tape("x^2 + y^2 + z^2 - 1");
    let (_, wavy) = tape("x^2 + y^2 + z^2 - 1 + 0.1*sin(5*x)/(1 + y^2)");
    let t = Traversal::Bisect(BisectOptions::new(Domain::Interval));
    let mut r = Renderer::new(gpu(), &sphere, t.clone()).unwrap();
    let e = r.set_field(&wavy).err().expect("refused").to_string();
    assert!(e.contains("the formula needs what the tape kernel was built without (division, sin/cos): build a new renderer"), "{e}");
    // The ball's inputs are pinned in registers; the Barth decic's are loaded
    // by input instructions (7 more registers would need 32): a kernel
    // without that case refuses it.
    let decic = crate::catalog::lookup("barth-decic").unwrap().compile().unwrap();
    let decic = TapeData::new(&decic.ir).unwrap();
    assert_eq!((sphere.features & features::PINNED, decic.features & features::INPUTS), (features::PINNED, features::INPUTS));
    let e = r.set_field(&decic).err().expect("refused").to_string();
    assert!(e.contains("input instructions") && e.ends_with("build a new renderer"), "{e}");
    // A long polynomial asks for the unrolled loop: a kernel without it runs
    // it, one instruction an iteration, so fewer evaluations fit in the work
    // limit (pixels past it are reported); the unrolled kernel resolves all.
    let terms: Vec<String> = (1..=30).map(|i| format!("0.01*(x - {i}*0.01)*(y + {i}*0.02)")).collect();
    let (_, long) = tape(&format!("x^2 + y^2 + z^2 - 1 + {}", terms.join(" + ")));
    assert_ne!(long.features & features::UNROLL_4, 0);
    r.set_field(&long).unwrap();
    let rolled = r.render(&s).unwrap().stats;
    let unrolled = Renderer::new(gpu(), &long, t.clone()).unwrap().render(&s).unwrap().stats;
    assert_eq!(unrolled.unresolved, 0, "{unrolled:?}");
    assert!(unrolled.hits > 0 && rolled.hits + rolled.unresolved >= unrolled.hits, "{rolled:?} {unrolled:?}");
    let mut wide = sphere.clone();
    wide.features |= wavy.features;
    let mut r = Renderer::new(gpu(), &wide, t).unwrap();
    r.set_field(&wavy).unwrap();
    assert!(r.render(&s).unwrap().stats.hits > 0);
}

#[test]
fn new_formulas_change_buffers_not_pipelines() {
    let s = common::settings(common::cube(2.0), 32, 32);
    let (_, sphere) = tape("x^2 + y^2 + z^2 - 1");
    let (_, torus) = tape("(x^2 + y^2 + z^2 + 0.75)^2 - 4*(x^2 + y^2)");
    // A device of its own: the other tests create pipelines concurrently.
    let own = crate::gpu::Gpu::new().unwrap();
    let mut r = Renderer::new(&own, &sphere, Traversal::Bisect(BisectOptions::new(Domain::Interval))).unwrap();
    let before = r.render(&s).unwrap();
    let created = own.pipelines_created.load(Ordering::Relaxed);
    r.set_field(&torus).unwrap();
    let after = r.render(&s).unwrap();
    assert_eq!(own.pipelines_created.load(Ordering::Relaxed), created, "a new formula built a pipeline");
    let changed = before.pixels.iter().zip(&after.pixels).filter(|(a, b)| a.status != b.status).count();
    assert!(changed > 20, "{changed}");
    assert_eq!(after.stats.unresolved, 0);
}

/// A tape far past the interpreter's work limit (also when the kernel
/// counts its work per SIMD bundle): nothing is culled or drawn that was not
/// proven; its pixels are reported unresolved. The longest tapes run 16
/// instructions an iteration, where a cell's work (its enclosure and scalar
/// refinement) fits a round of the per-pixel pass again, with 7 rounds
/// after the first: the same tape's pixels resolve, and none misses a sign
/// change of the f64 reference. A tape padded for 4 is refused by such a
/// kernel (it would read past its programs).
#[test]
fn a_tape_past_the_work_limit_reports_its_pixels_and_16_an_iteration_resolves_them() {
    let (f, data) = tape(&sum_of_inputs(16_100));
    assert!(data.ops >= crate::field::tape::TAPE_UNROLL_16_FROM, "{} instructions", data.ops);
    assert_eq!((features::unroll(data.features), data.padding()), (16, 16));
    assert_eq!([1, 4, 8, 16].map(crate::field::tape::resume_rounds), [3, 3, 15, 7]);
    let s = common::settings(common::cube(2.0), 16, 16);
    let ia = || Traversal::Bisect(BisectOptions::new(Domain::Interval));
    let mut four = data.clone();
    four.features = four.features & !(features::UNROLL_8 | features::UNROLL_16) | features::UNROLL_4;
    assert_eq!(features::unroll(four.features), 4);
    let frame = Renderer::new(gpu(), &four, ia()).unwrap().render(&s).unwrap();
    assert!(frame.stats.unresolved > 0, "{:?}", frame.stats);
    let missed = misses_of_the_reference(&f, &s, &frame, 500, false);
    assert!(missed.is_empty(), "{} pixels: {:?}", missed.len(), &missed[..missed.len().min(8)]);
    let mut r = Renderer::new(gpu(), &data, ia()).unwrap();
    let frame = r.render(&s).unwrap();
    assert_eq!(frame.stats.unresolved, 0, "{:?}", frame.stats);
    assert!(frame.stats.hits >= 12, "{:?}", frame.stats);
    let missed = misses_of_the_reference(&f, &s, &frame, 500, false);
    assert!(missed.is_empty(), "{} pixels: {:?}", missed.len(), &missed[..missed.len().min(8)]);
    // A cylinder's programs are 4 and 12 instructions long.
    let (_, cylinder) = tape("x^2 + y^2 - 1");
    assert_eq!(cylinder.padding(), 4);
    let e = r.set_field(&cylinder).err().expect("refused").to_string();
    assert!(e.contains("the tape kernel runs 16 instructions an iteration, for long tapes, and this tape's programs are padded for 4: build a new renderer"), "{e}");
}

/// A long tape runs 8 instructions an iteration, padded to match, and the
/// kernel draws it: no pixel left unresolved, no sign change of the f64
/// reference missed.
#[test]
fn a_long_tape_runs_8_an_iteration() {
    let (f, data) = tape(&sum_of_terms(1050));
    let range = crate::field::tape::TAPE_UNROLL_8_FROM..crate::field::tape::TAPE_UNROLL_16_FROM;
    assert!(range.contains(&data.ops), "{} instructions", data.ops);
    assert_eq!(features::unroll(data.features), 8);
    assert_eq!(data.padding() % 8, 0);
    let s = common::settings(common::cube(1.2), 16, 16);
    let frame = Renderer::new(gpu(), &data, Traversal::Bisect(BisectOptions::new(Domain::Interval))).unwrap().render(&s).unwrap();
    assert_eq!(frame.stats.unresolved, 0, "{:?}", frame.stats);
    assert!(frame.stats.hits > 30, "{:?}", frame.stats);
    let missed = misses_of_the_reference(&f, &s, &frame, 2000, false);
    assert!(missed.is_empty(), "{} pixels: {:?}", missed.len(), &missed[..missed.len().min(8)]);
}

/// A sphere plus a small multiple of t + t + …, `n` inputs (at t = 0): an
/// instruction per two bytes of formula, for tapes past 16,000 instructions
/// within the front end's 64 KiB (a sum of products no longer gets there:
/// its constants are immediates, its products multiply-adds; and x + y + z
/// + x + … would be collected into three terms by the semantic pass, which
/// leaves t alone).
fn sum_of_inputs(n: usize) -> String {
    let terms: Vec<&str> = ["t"].iter().cycle().take(n).copied().collect();
    format!("x^2+y^2+z^2-1+1e-5*({})", terms.join("+"))
}

/// A unit sphere plus 1e-4 times a sum of `n` bilinear terms: a tape of
/// about 3n instructions (its inputs pinned in registers, its constants
/// immediates, each term's i·x − y one multiply-subtract and its product
/// and sum one multiply-add) whose surface is known.
fn sum_of_terms(n: u32) -> String {
    let terms: Vec<String> = (0..n).map(|i| format!("({:.3}*x-y)*(z+{:.3})", 0.5 + f64::from(i) * 0.001, f64::from(i) * 0.002)).collect();
    format!("x^2+y^2+z^2-1+1e-4*({})", terms.join("+"))
}

/// [`sum_of_terms`] with every other term's second factor written
/// `z − (−b)` (swapped factors no longer do: a run compares a product's
/// operands in a fixed order): no run of same-shaped terms, so its compiled kernel writes every term out (a
/// uniform sum's becomes a loop, `crate::field::compiled::term_loops`, and `auto` keeps it
/// compiled).
fn mixed_sum_of_terms(n: u32) -> String {
    let term = |i: u32| {
        let (a, b) = (0.5 + f64::from(i) * 0.001, f64::from(i) * 0.002);
        if i % 2 == 0 { format!("({a:.3}*x-y)*(z+{b:.3})") } else { format!("({a:.3}*x-y)*(z-(-{b:.3}))") }
    };
    format!("x^2+y^2+z^2-1+1e-4*({})", (0..n).map(term).collect::<Vec<_>>().join("+"))
}

/// Pixels where the f64 reference finds a root along the ray and the frame
/// has neither a hit there nor an unresolved pixel. With `in_front_ok` a
/// hit in front of the reference's first root counts as found: it may be a
/// thin feature the reference's samples stepped over, as on icos.csg's
/// spikes.
pub(super) fn misses_of_the_reference(f: &Formula, s: &Settings, frame: &Frame, samples: usize, in_front_ok: bool) -> Vec<String> {
    let mut missed = vec![];
    for j in 0..s.height {
        for i in 0..s.width {
            let p = frame.pixels[(j * s.width + i) as usize];
            if p.status == Status::Unresolved {
                continue;
            }
            if let Some((t, step)) = common::reference_root(f, s, i, j, samples) {
                let d = f64::from(p.depth);
                if !(p.status == Status::Hit && d <= t + s.eps + step && (in_front_ok || d >= t - s.eps - step)) {
                    missed.push(format!("({i},{j}) ref {t:.5} got {:?} {:.5}", p.status, p.depth));
                }
            }
        }
    }
    missed
}

/// Settings of a catalog entry at a small size.
pub(super) fn entry_settings(e: &crate::catalog::Entry, f: &Formula, n: u32) -> Settings {
    e.settings(f, n, n).unwrap()
}

/// Pixels that differ: a different status, or hits more than `tol` apart.
/// Pixels the tape's interpreter gave up on (its work limit) are reported
/// as unresolved, never drawn wrong: they are not compared.
pub(super) fn differences(a: &Frame, b: &Frame, tol: f64) -> Vec<String> {
    let mut bad = vec![];
    for (k, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        if q.status == Status::Unresolved && p.status != Status::Unresolved {
            continue;
        }
        let same = match (p.status, q.status) {
            (Status::Hit, Status::Hit) => (f64::from(p.depth) - f64::from(q.depth)).abs() <= tol,
            (x, y) => x == y,
        };
        if !same {
            bad.push(format!("px {k}: {:?} {} vs {:?} {}", p.status, p.depth, q.status, q.depth));
        }
    }
    bad
}

#[test]
fn bisection_agrees_with_the_compiled_field_on_the_knoll_suite() {
    for domain in [Domain::Interval, Domain::Affine] {
        let t = Traversal::Bisect(BisectOptions::new(domain));
        let mut tape_renderer: Option<Renderer> = None;
        // Pixels past the interpreter's work limit are reported, not
        // compared (the superquadric's x^200 in RAA, for one, runs out).
        let mut hits = 0;
        for name in crate::catalog::suite("knoll").unwrap() {
            let e = crate::catalog::lookup(name).unwrap();
            let f = e.compile().unwrap();
            let s = entry_settings(&e, &f, 40);
            let data = TapeData::new(&f.ir).unwrap();
            let r = match &mut tape_renderer {
                Some(r) => {
                    r.set_field(&data).unwrap();
                    r
                }
                none => {
                    // One kernel for the whole suite: built for every operation.
                    let wide = TapeData { features: features::ALL, ..data.clone() };
                    none.insert(Renderer::new(gpu(), &wide, t.clone()).unwrap())
                }
            };
            let taped = r.render(&s).unwrap();
            let compiled = Renderer::new(gpu(), &f.ir, t.clone()).unwrap().render(&s).unwrap();
            let bad = differences(&compiled, &taped, 2.0 * s.eps);
            assert!(bad.len() <= 2, "{name} {domain:?}: {} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
            hits += taped.stats.hits;
        }
        assert!(hits > 1000, "{domain:?}: {hits} hits over the suite");
    }
}

#[test]
fn sphere_tracing_agrees_with_the_compiled_field_on_the_sdf_suite() {
    for name in crate::catalog::suite("sdf").unwrap() {
        let e = crate::catalog::lookup(name).unwrap();
        let f = e.compile().unwrap();
        let s = entry_settings(&e, &f, 40);
        let t = e.traversal(&f);
        let data = TapeData::new(&f.ir).unwrap();
        let taped = Renderer::new(gpu(), &data, t.clone()).unwrap().render(&s).unwrap();
        let compiled = Renderer::new(gpu(), &f.ir, t).unwrap().render(&s).unwrap();
        // Where the interpreter ran out of work the pixel is reported
        // (unresolved), never drawn wrong: compare the others.
        let mut bad = vec![];
        for (k, (p, q)) in compiled.pixels.iter().zip(&taped.pixels).enumerate() {
            if q.status == Status::Unresolved {
                continue;
            }
            let same = match (p.status, q.status) {
                (Status::Hit, Status::Hit) => (f64::from(p.depth) - f64::from(q.depth)).abs() <= 4.0 * s.eps,
                (x, y) => x == y,
            };
            if !same {
                bad.push(format!("px {k}: {:?} {} vs {:?} {}", p.status, p.depth, q.status, q.depth));
            }
        }
        // The sdf scenes have 400-900 instructions: sphere tracing them
        // runs into the interpreter's work limit on most pixels (README,
        // "Compiled or tape"), so what is checked is that no pixel it
        // resolved differs.
        assert!(bad.len() <= 2, "{name}: {} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
    }
}

/// A tape whose pixels need several times the interpreter's work limit
/// (counted per invocation, as on a device without subgroups): the later
/// rounds of the per-pixel pass resume them at the cell where they stopped,
/// so every pixel resolves and no sign change of the f64 reference is
/// missed.
#[test]
fn pixels_past_the_work_limit_resume_and_miss_no_root() {
    let (f, data) = tape(&sum_of_terms(280));
    let s = common::settings(common::cube(1.2), 32, 32);
    let mut per_lane = crate::gpu::Gpu::new().unwrap();
    per_lane.subgroups = false;
    let mut r = Renderer::new(&per_lane, &data, Traversal::Bisect(BisectOptions::new(Domain::Interval))).unwrap();
    r.set_resume_rounds(0);
    let one_round = r.render(&s).unwrap().stats;
    r.set_resume_rounds(crate::field::tape::TAPE_RESUME_ROUNDS);
    let frame = r.render(&s).unwrap();
    assert!(one_round.unresolved >= 4, "one round resolved it all: {one_round:?}");
    assert_eq!(frame.stats.unresolved, 0);
    let missed = misses_of_the_reference(&f, &s, &frame, 4000, false);
    assert!(missed.is_empty(), "{} pixels: {:?}", missed.len(), &missed[..missed.len().min(8)]);
    assert!(frame.stats.hits > 100, "{:?}", frame.stats);
}

/// Where the device has subgroups, a tape's bisection counts its work per
/// SIMD bundle (what lavapipe's loop cap counts): one round resolves pixels
/// that the per-invocation count leaves unresolved, and the picture is the
/// compiled field's.
#[test]
fn counting_work_per_bundle_resolves_more_and_draws_the_same_picture() {
    if !gpu().subgroups {
        eprintln!("skipped: the device has no subgroup operations");
        return;
    }
    let src = sum_of_terms(280);
    let (f, data) = tape(&src);
    let s = common::settings(common::cube(1.2), 32, 32);
    let ia = || Traversal::Bisect(BisectOptions::new(Domain::Interval));
    let mut per_lane = crate::gpu::Gpu::new().unwrap();
    per_lane.subgroups = false;
    let mut a = Renderer::new(&per_lane, &data, ia()).unwrap();
    a.set_resume_rounds(0);
    let mut b = Renderer::new(gpu(), &data, ia()).unwrap();
    assert!(b.wgsl().contains("subgroupMax"));
    b.set_resume_rounds(0);
    let (lane, bundle) = (a.render(&s).unwrap().stats, b.render(&s).unwrap());
    assert!(bundle.stats.unresolved * 4 < lane.unresolved, "per lane {} vs per bundle {}", lane.unresolved, bundle.stats.unresolved);
    let compiled = Renderer::new(gpu(), &f.ir, ia()).unwrap().render(&s).unwrap();
    let bad = differences(&compiled, &bundle, 2.0 * s.eps);
    assert!(bad.is_empty(), "{} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
    assert!(misses_of_the_reference(&f, &s, &bundle, 2000, false).is_empty());
}

#[test]
fn tape_renders_find_every_sign_change_of_the_reference() {
    let cases: &[(&str, [f64; 6])] = &[
        ("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", common::cube(3.0)),
        ("x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z", common::cube(1.0)),
        ("max(x^8 + y^8 + z^8 - 1, -min(min(y^2 + z^2 - 0.25, x^2 + z^2 - 0.25), x^2 + y^2 - 0.25))", common::cube(1.5)),
    ];
    for (src, bbox) in cases {
        let (f, data) = tape(src);
        let s = common::settings(*bbox, 32, 32);
        for domain in [Domain::Interval, Domain::Affine] {
            let frame = Renderer::new(gpu(), &data, Traversal::Bisect(BisectOptions::new(domain))).unwrap().render(&s).unwrap();
            assert!(4 * frame.stats.unresolved <= u64::from(s.width * s.height), "{src} {domain:?}: {} unresolved", frame.stats.unresolved);
            // A reported (unresolved) pixel is not a wrong one.
            let missed = misses_of_the_reference(&f, &s, &frame, 4000, true);
            assert!(missed.is_empty(), "{src} {domain:?}: {} pixels miss a sign change: {:?}", missed.len(), &missed[..missed.len().min(8)]);
        }
    }
}

/// A unit sphere plus 1e-6 times a sum of `n` (at most 512) monomials
/// x^a·y^b·z^c (a, b, c below 8), each a different one, in a pseudo-random
/// order: their powers and products are shared across the whole sum, more
/// values alive at once than the interpreter's 64 registers from about 350
/// terms on, and no two of them are like terms (which the semantic pass
/// would collect into one).
fn sum_of_monomials(n: u32) -> String {
    let mut r: u64 = 12345;
    let mut used = [false; 512];
    let mut terms = Vec::new();
    while terms.len() < n.min(512) as usize {
        r = (r * 1103515245 + 12345) % (1 << 31);
        let k = ((r >> 4) % 512) as usize;
        if std::mem::replace(&mut used[k], true) {
            continue;
        }
        terms.push(format!("{}.{}*x^{}*y^{}*z^{}", (r >> 13) % 9 + 1, (r >> 17) % 10, k % 8, k / 8 % 8, k / 64));
    }
    format!("x^2+y^2+z^2-1+1e-6*({})", terms.join("+"))
}

/// A long sum of like monomials (3,000 terms, 48 KB, 343 distinct
/// monomials) is collected by the semantic pass into one term per monomial,
/// written in nested Horner form, and its picture finds every root of the
/// f64 reference, in both algebras, compiled and as a tape.
#[test]
fn like_monomials_are_collected_and_drawn() {
    let mut r: u64 = 12345;
    let terms: Vec<String> = (0..3000)
        .map(|_| {
            r = (r * 1103515245 + 12345) % (1 << 31);
            format!("{}.{}*x^{}*y^{}*z^{}", (r >> 9) % 9 + 1, (r >> 13) % 10, r % 7, (r >> 3) % 7, (r >> 6) % 7)
        })
        .collect();
    let src = format!("x^2+y^2+z^2-1+1e-6*({})", terms.join("+"));
    assert!(src.len() > 45_000);
    let (f, data) = tape(&src);
    // 343 monomials of at most x^6·y^6·z^6 and the sphere: each monomial is
    // a product with its coefficient and a sum, on shared powers.
    assert!(f.ir.nodes.len() < 4 * 343 + 40, "{} nodes", f.ir.nodes.len());
    // In nested Horner form (from 64 monomials on) few values are alive at once.
    assert!(data.registers <= 16, "{} registers", data.registers);
    let s = common::settings(common::cube(1.5), 24, 24);
    for domain in [Domain::Interval, Domain::Affine] {
        let taped = bisect_tape(&data, domain, &s, true);
        assert!(taped.stats.hits > 40 && taped.stats.unresolved == 0, "{domain:?}: {:?}", taped.stats);
        assert!(misses_of_the_reference(&f, &s, &taped, 1000, false).is_empty(), "{domain:?}");
    }
    let compiled = common::render(&src, Domain::Interval, &s);
    assert!(misses_of_the_reference(&f, &s, &compiled, 1000, false).is_empty());
}

/// Shared values past the register file are computed again at each use
/// (`tape::remat`): such a formula is a tape, within 64 registers, and its
/// picture finds every root of the f64 reference, in both algebras. (Its
/// compiled kernel takes half a minute to build here; `auto` takes the
/// tape.)
#[test]
fn a_formula_of_more_shared_values_than_registers_is_rematerialised() {
    let (f, data) = tape(&sum_of_monomials(400));
    assert!(data.registers <= 64, "{}", data.registers);
    let s = common::settings(common::cube(1.5), 24, 24);
    for domain in [Domain::Interval, Domain::Affine] {
        let taped = bisect_tape(&data, domain, &s, true);
        assert!(taped.stats.hits > 40 && taped.stats.unresolved == 0, "{domain:?}: {:?}", taped.stats);
        let missed = misses_of_the_reference(&f, &s, &taped, 1000, false);
        assert!(missed.is_empty(), "{domain:?}: {missed:?}");
    }
    let t = Traversal::Bisect(BisectOptions::new(Domain::Interval));
    let auto = crate::choice::choose(crate::field::FieldKind::Auto, &f, &[], &t).unwrap();
    assert_eq!(auto.kind(), crate::field::FieldKind::Tape);
}

#[test]
fn a_formula_that_cannot_be_a_tape_is_a_typed_error() {
    let f = Formula::compile("<t>", "x^2 + y^2 + z^2 - 1 where z > 0").unwrap();
    assert_eq!(TapeData::new(&f.ir), Err(crate::field::TapeError::Csg));
    let t = Traversal::Bisect(BisectOptions::new(Domain::Interval));
    // `Auto` falls back to the compiled field; asking for the tape fails.
    let auto = crate::choice::choose(crate::field::FieldKind::Auto, &f, &[], &t).unwrap();
    assert_eq!(auto.kind(), crate::field::FieldKind::Compiled);
    assert!(crate::choice::choose(crate::field::FieldKind::Tape, &f, &[], &t).is_err());
}

/// Bisection of `data` in `domain` with the per-tile shortening on or off.
pub(super) fn bisect_tape(data: &TapeData, domain: Domain, s: &Settings, shorten: bool) -> Frame {
    let mut r = Renderer::new(gpu(), data, Traversal::Bisect(BisectOptions::new(domain))).unwrap();
    r.optimizations_mut().expect("bisection").tape_shortening = shorten;
    r.render(s).unwrap()
}

#[test]
fn the_power_loops_pass_counts_against_the_loop_cap() {
    // lavapipe runs one masked pass of the power-chain case's loop for every
    // instruction of a kernel that has the case; uncounted, those passes
    // took bundles past the driver's silent cap, which cut the traversal
    // short: hits became misses with no pixel reported (@creature at 256²
    // lost 561). Every pixel now hits, or is reported. (x^9 keeps the loop:
    // powers below 8 are written out, PowSmall.)
    let (f, data) = tape(&format!("{}+1e-4*x^9", sum_of_terms(180)));
    assert!(data.features & features::POWERS != 0);
    let s = common::settings(common::cube(1.2), 32, 32);
    let taped = bisect_tape(&data, Domain::Interval, &s, true);
    let compiled = Renderer::new(gpu(), &f.ir, Traversal::Bisect(BisectOptions::new(Domain::Interval))).unwrap().render(&s).unwrap();
    let bad = differences(&compiled, &taped, 2.0 * s.eps);
    assert!(bad.is_empty(), "{} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
    assert!(misses_of_the_reference(&f, &s, &taped, 2000, false).is_empty());
}

#[test]
fn auto_keeps_csg_formulas_compiled_in_both_algebras() {
    use crate::choice;
    use crate::field::FieldKind;
    let kind = |name: &str, domain: Domain| {
        let f = crate::catalog::lookup(name).unwrap().compile().unwrap();
        choice::choose(FieldKind::Auto, &f, &[], &Traversal::Bisect(BisectOptions::new(domain))).unwrap().kind()
    };
    // The city's 257 min/max compiled for minutes in RAA (145 s cold at
    // 256²) while the affine min and max were branchy code, and auto took
    // the tape for them; branch-free, the compiled kernel's first 512² frame
    // is as soon as the tape's and its frames 30 times faster.
    for domain in [Domain::Affine, Domain::Interval] {
        for name in ["city", "creature", "icos.csg"] {
            assert_eq!(kind(name, domain), FieldKind::Compiled, "{name} {domain:?}");
        }
    }
    // Past the crossover too: the city with two more copies of its blocks
    // (3,528 instructions) compiles in 11 s in IA, where its tape took 152 s
    // and left 18,529 pixels unresolved at 512²; a longer sum takes the tape.
    let city = std::fs::read_to_string("examples/city.iso").unwrap();
    let blocks = "union(row0, row1, row2, row3, row4, row5)";
    let copies = format!("translate(0.05, 0.4, 0.02, {blocks}), translate(-0.3, 0.1, 0.01, {blocks}), translate(0.2, -0.25, 0.03, {blocks})");
    let big = city.replace("union(ground, row0, row1, row2, row3, row4, row5)", &format!("union(ground, row0, row1, row2, row3, row4, row5, {copies})"));
    assert_ne!(big, city);
    let auto = |text: &str, domain: Domain| {
        let f = Formula::compile("<big>", text).unwrap();
        let t = crate::field::TapeData::new(&f.ir).unwrap();
        (t.size, choice::choose(FieldKind::Auto, &f, &[], &Traversal::Bisect(BisectOptions::new(domain))).unwrap().kind())
    };
    for domain in [Domain::Affine, Domain::Interval] {
        let (size, k) = auto(&big, domain);
        let line = choice::crossover(&Traversal::Bisect(BisectOptions::new(domain)));
        assert!(size > line * 4 / 5, "{size}");
        assert_eq!(k, FieldKind::Compiled, "{domain:?}");
        let (size, k) = auto(&mixed_sum_of_terms(450), domain);
        assert!(size > line, "{size}");
        assert_eq!(k, FieldKind::Tape, "{domain:?}");
        // The same sum with one shape is a loop in 81 nodes: compiled.
        assert_eq!(auto(&sum_of_terms(400), domain).1, FieldKind::Compiled, "{domain:?}");
    }
}

/// `auto` weighs the number of frames: a sum past the IA line (size about
/// 2,500) takes the tape for one frame, whose head start a second frame
/// spends, and stays compiled for an animation of 4 frames (the line ×2);
/// a sum four times as long takes the tape however many frames. Below the
/// line a product of 100 planes stays compiled (1.1 s cold at 512²,
/// against 20 s as a tape), and so do sums of 50 to 200 trigonometric
/// products.
#[test]
fn auto_weighs_the_frames_of_the_job() {
    use crate::choice;
    use crate::field::FieldKind;
    let ia = Traversal::Bisect(BisectOptions::new(Domain::Interval));
    let kind = |terms: u32, frames: u64| {
        let f = Formula::compile("<sum>", &mixed_sum_of_terms(terms)).unwrap();
        let t = crate::field::TapeData::new(&f.ir).unwrap();
        (t.size, choice::choose_for(FieldKind::Auto, &f, &[], &ia, frames).unwrap().kind())
    };
    let (size, one) = kind(250, 1);
    assert!(size > choice::crossover(&ia) && size < 2 * choice::crossover(&ia), "{size}");
    assert_eq!(one, FieldKind::Tape);
    assert_eq!(kind(250, 4).1, FieldKind::Compiled);
    assert_eq!(kind(250, 1000).1, FieldKind::Compiled);
    let (size, k) = kind(1000, 1000);
    assert!(size > 4 * choice::crossover(&ia), "{size}");
    assert_eq!(k, FieldKind::Tape);
    let auto = |src: String| choice::choose(FieldKind::Auto, &Formula::compile("<f>", &src).unwrap(), &[], &ia).unwrap().kind();
    let planes: Vec<String> = (0..100).map(|i| format!("({:.3}*x + {:.3}*y - {:.3}*z + {:.3})", 0.3 + 0.007 * f64::from(i), 0.9 - 0.005 * f64::from(i), 0.1 + 0.003 * f64::from(i), -0.5 + 0.01 * f64::from(i))).collect();
    assert_eq!(auto(planes.join("*")), FieldKind::Compiled);
    let trig = |n: u32| (0..n).map(|i| format!("{:.3}*sin({:.3}*x + {:.3})*cos({:.3}*y - {:.3})*sin({:.3}*z)", 0.5 + 0.01 * f64::from(i), 1.0 + 0.013 * f64::from(i), 0.002 * f64::from(i), 0.7 + 0.011 * f64::from(i), 0.003 * f64::from(i), 1.1 + 0.007 * f64::from(i))).collect::<Vec<_>>().join(" + ") + " - 0.3";
    // Their terms are one shape, so the compiled field runs them as a loop
    // (`crate::field::compiled::term_loops`), weighed by its body: cold at 512², 100 terms
    // 2.1 s against the tape's 15 s, 200 terms 4.3 s against 38 s.
    assert_eq!(auto(trig(50)), FieldKind::Compiled);
    assert_eq!(auto(trig(100)), FieldKind::Compiled);
    assert_eq!(auto(trig(200)), FieldKind::Compiled);
}

/// A tape's hit finds its gradient in the cells' own loop (forward
/// differences from the root finder's last point, cells_resumable.wgsl), where
/// the compiled field takes central differences after the traversal: the
/// normals agree on every pixel both hit at the same depth, away from
/// creases (where the compiled field's own normal jumps between neighbours
/// the two stencils straddle different faces), also where the tile's
/// shortened tape runs (the gradient's points leave the tile's rays, and
/// run the tile's list where they stay inside its frustum and the ray's run
/// of candidate slabs).
#[test]
fn a_tapes_normals_agree_with_the_compiled_fields() {
    let e = crate::catalog::lookup("icos.csg").unwrap();
    let icos = e.compile().unwrap();
    let cases = [
        ("sphere", Formula::compile("<sphere>", "x^2 + y^2 + z^2 - 1").unwrap(), common::settings(common::cube(1.5), 64, 64)),
        ("torus", Formula::compile("<torus>", "(x^2 + y^2 + z^2 + 0.6^2 - 0.25^2)^2 - 4*0.6^2*(x^2 + y^2)").unwrap(), common::settings(common::cube(1.0), 96, 96)),
        ("icos.csg", icos.clone(), entry_settings(&e, &icos, 128)),
    ];
    let dot = |a: &[f32; 3], b: &[f32; 3]| -> f32 { a.iter().zip(b).map(|(x, y)| x * y).sum() };
    for (name, f, s) in &cases {
        for domain in [Domain::Interval, Domain::Affine] {
            let t = Traversal::Bisect(BisectOptions::new(domain));
            let data = TapeData::new(&f.ir).unwrap();
            let taped = Renderer::new(gpu(), &data, t.clone()).unwrap().render(s).unwrap();
            let compiled = Renderer::new(gpu(), &f.ir, t).unwrap().render(s).unwrap();
            let w = s.width as usize;
            let crease = |k: usize| {
                let q = &compiled.pixels[k];
                [k.wrapping_sub(1), k + 1, k.wrapping_sub(w), k + w]
                    .iter()
                    .filter_map(|&j| compiled.pixels.get(j))
                    .any(|n| n.status != Status::Hit || dot(&n.normal, &q.normal) < 0.95)
            };
            let mut compared = 0;
            for (k, (p, q)) in taped.pixels.iter().zip(&compiled.pixels).enumerate() {
                if p.status != Status::Hit || q.status != Status::Hit || (p.depth - q.depth).abs() > 2.0 * s.eps as f32 || crease(k) {
                    continue;
                }
                let cos = dot(&p.normal, &q.normal);
                assert!(cos > 0.999, "{name} {domain:?} px {k}: normals {:?} and {:?}", p.normal, q.normal);
                compared += 1;
            }
            assert!(compared > 200, "{name} {domain:?}: {compared} pixels compared");
        }
    }
}

/// A pixel that runs out of budget keeps its nearest candidate cell as a
/// guess, drawn like a hit with `--unresolved guess`: the tape's cell work
/// finds the guess's gradient too, so its normal is f's gradient there (for
/// the unit sphere, the guess point's direction), not a zero gradient's
/// fallback.
#[test]
fn an_unresolved_guess_on_a_tape_is_shaded_with_its_gradient() {
    let f = Formula::compile("<sphere>", "x^2 + y^2 + z^2 - 1").unwrap();
    let mut s = common::settings(common::cube(1.5), 48, 48);
    s.max_iter = 2;
    let data = TapeData::new(&f.ir).unwrap();
    let frame = Renderer::new(gpu(), &data, Traversal::Bisect(BisectOptions::new(Domain::Interval))).unwrap().render(&s).unwrap();
    let cam = s.camera.frame().unwrap();
    let (mut guesses, mut agree) = (0, 0);
    for (k, p) in frame.pixels.iter().enumerate() {
        let (i, j) = (k as u32 % s.width, k as u32 / s.width);
        if p.status != Status::Unresolved || !p.depth.is_finite() {
            continue;
        }
        guesses += 1;
        let at = s.camera.eye + crate::render::Camera::ray(&cam, i, j, s.width, s.height).normalize() * f64::from(p.depth);
        let want = at.normalize();
        let cos = f64::from(p.normal[0]) * want.x + f64::from(p.normal[1]) * want.y + f64::from(p.normal[2]) * want.z;
        agree += usize::from(cos > 0.999);
    }
    assert!(guesses > 100, "{guesses} unresolved pixels");
    assert!(agree * 10 >= guesses * 9, "{agree} of {guesses} guesses have f's gradient as their normal");
}

/// A long sum is generated as a balanced tree in the compiled field
/// (`crate::field::compiled::balance`), where the tape keeps the order written: the two
/// draw the same picture, and it misses no sign change of the f64
/// reference. (Its compile: README, "Long sums as balanced trees".)
#[test]
fn a_long_sum_balanced_in_the_compiled_field_draws_what_the_tape_draws() {
    let terms: Vec<String> = (0..60)
        .map(|i| {
            let k = f64::from(i);
            format!("{}0.02*sqrt((x - {:.3})^2 + (y + {:.3})^2 + 0.1)", if i % 4 == 3 { "- " } else { "+ " }, (k * 0.37).sin(), (k * 0.71).cos())
        })
        .collect();
    let (f, data) = tape(&format!("x^2 + y^2 + z^2 - 2 {}", terms.join(" ")));
    let t = Traversal::Bisect(BisectOptions::new(Domain::Interval));
    let wgsl = assemble(&f.ir, &t).wgsl;
    // 61 terms in a chain would nest 60 sums deep; balanced, the comment's
    // formula opens with a handful of parentheses.
    let f_line = wgsl.lines().find(|l| l.starts_with("// f = ")).expect("the formula's comment");
    assert!(f_line.trim_start_matches("// f = ").chars().take_while(|&c| c == '(').count() < 10, "{f_line}");
    let s = common::settings(common::cube(1.6), 32, 32);
    let compiled = Renderer::new(gpu(), &f.ir, t.clone()).unwrap().render(&s).unwrap();
    let taped = Renderer::new(gpu(), &data, t).unwrap().render(&s).unwrap();
    assert!(compiled.stats.hits > 80 && compiled.stats.unresolved == 0, "{:?}", compiled.stats);
    let bad = differences(&compiled, &taped, 2.0 * s.eps);
    assert!(bad.is_empty(), "{} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
    assert!(misses_of_the_reference(&f, &s, &compiled, 2000, false).is_empty());
}

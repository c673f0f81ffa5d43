//! Long sums of unlike monomials (`crate::field::compiled::term_loops::monomials`): every
//! monomial of degree 3 or more is written `c · pown(x, a) · pown(y, b) ·
//! pown(z, e)` and the compiled field runs them as one loop over a table of
//! coefficients and exponents. Its enclosures must hold f64 samples in every
//! domain, and its picture must be the tape's, which runs the formula as the
//! semantic pass wrote it.

use super::common;
use super::reroll::{assert_encloses, boxes};

use common::gpu;
use crate::field::compiled::{generated_ir, term_loops};
use crate::gpu::eval::eval_boxes;
use crate::gpu::Renderer;
use crate::ir::Domain;
use crate::render::{BisectOptions, Status, Traversal};
use crate::Formula;

/// A sphere plus `n` distinct monomials with small seeded coefficients,
/// written term by term; the first few take the extreme powers (0 to 31,
/// even and odd). `like` adds a second x³y, so that the semantic pass
/// collects the sum and writes it as a Horner form.
fn monomials(n: usize, like: bool) -> String {
    let mut seen = std::collections::HashSet::new();
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move |m: u64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % m
    };
    let mut terms = vec![];
    let fixed = [[31, 0, 0], [0, 30, 1], [1, 1, 16], [15, 2, 0], [3, 0, 0]];
    while terms.len() < n {
        let e = match fixed.get(terms.len()) {
            Some(&e) => e,
            None => [next(9) as u32, next(9) as u32, next(9) as u32],
        };
        if e.iter().sum::<u32>() < 3 || !seen.insert(e) {
            continue;
        }
        let c = (next(2001) as f64 - 1000.0) * 1e-5 / 1.5f64.powi(e.iter().sum::<u32>() as i32 / 2);
        let mut t = format!("{c:.8}");
        for (v, k) in ["x", "y", "z"].iter().zip(e) {
            match k {
                0 => {}
                1 => t += &format!("*{v}"),
                _ => t += &format!("*{v}^{k}"),
            }
        }
        terms.push(t);
    }
    let like = if like { " + 0.002*x^3*y" } else { "" };
    format!("x^2 + y^2 + z^2 - 1 + {}{like}", terms.join(" + "))
}

#[test]
fn a_long_sum_of_unlike_monomials_is_one_loop() {
    for like in [false, true] {
        let f = Formula::compile("<t>", &monomials(200, like)).unwrap();
        assert!(term_loops::plan(&f.ir).loops.is_empty(), "no run as written");
        let g = generated_ir(&f.ir).expect("rewritten");
        let plan = term_loops::plan(&g);
        assert_eq!(plan.loops.len(), 1, "like terms: {like}");
        assert!(plan.loops[0].unroll * plan.loops[0].iterations >= 190, "{:?}", plan.loops[0]);
        assert!(plan.emitted_nodes(&g) < 250, "{}", plan.emitted_nodes(&g));
    }
    // Too few monomials, and a product of sums (expanded it would hold more
    // terms than it has operations), stay as written.
    for src in [monomials(40, false), "(x^2 + y^2 + z^2 - 1)^3 * (x^4 + y^4 + z^4 - x*y*z) - 0.5".to_string()] {
        let f = Formula::compile("<t>", &src).unwrap();
        assert!(term_loops::monomials::monomial_sums(&f.ir).is_none(), "{src}");
    }
}

#[test]
fn a_monomial_loop_encloses_f64_samples() {
    let bx = boxes(2000);
    for like in [false, true] {
        let f = Formula::compile("<t>", &monomials(200, like)).unwrap();
        for domain in [Domain::Scalar, Domain::Interval, Domain::Affine] {
            let r = eval_boxes(gpu(), &f.ir, domain, &bx, &[]).unwrap();
            if domain != Domain::Scalar {
                assert_encloses(&f, &r, &bx, 5, &format!("{domain:?}, like terms {like}"));
                continue;
            }
            // The scalar field at the boxes' first corners, against f64.
            for (k, (e, b)) in r.iter().zip(&bx).enumerate() {
                let v = crate::reference::eval_scalar(&f.ir, [f64::from(b[0]), f64::from(b[2]), f64::from(b[4]), 0.0], &[]);
                assert!((f64::from(e[0]) - v).abs() <= 1e-4 * (1.0 + v.abs()), "box {k}: {} against {v}", e[0]);
            }
        }
    }
}

/// The loop's picture against the tape's (the formula as written, an
/// independent path), in IA and RAA: the same pixels hit, at depths within
/// 2 eps.
#[test]
fn a_monomial_loop_draws_what_the_tape_draws() {
    let f = Formula::compile("<t>", &monomials(200, false)).unwrap();
    let s = common::settings(common::cube(1.3), 96, 96);
    for domain in [Domain::Interval, Domain::Affine] {
        let t = Traversal::Bisect(BisectOptions::new(domain));
        let a = Renderer::new(gpu(), &f.ir, t.clone()).unwrap().render(&s).unwrap();
        let tape = crate::field::TapeData::new(&f.ir).unwrap();
        let b = Renderer::new(gpu(), &tape, t).unwrap().render(&s).unwrap();
        assert!(a.stats.hits > 1000 && a.stats.unresolved == 0 && b.stats.unresolved == 0, "{:?} {:?}", a.stats, b.stats);
        let differ = a.pixels.iter().zip(&b.pixels).filter(|(p, q)| p.status != q.status || (p.status == Status::Hit && (p.depth - q.depth).abs() > 2.0 * s.eps as f32)).count();
        assert!(differ <= 4, "{domain:?}: {differ} pixels differ");
    }
}

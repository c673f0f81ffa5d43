//! Polynomials of many monomials (`crate::field::compiled::term_loops::horner`): the
//! compiled field runs their Horner form as one loop over a table of
//! coefficients and powers, whether the semantic pass wrote the form
//! (like terms collected) or the sum came term by term, alone or among
//! other terms. Its enclosures must hold f64 samples in every domain, and
//! its picture must be the tape's, which runs the formula as written.

use super::common;
use super::reroll::{assert_encloses, boxes};

use common::gpu;
use crate::field::compiled::{generated_ir, term_loops};
use crate::gpu::eval::{eval_boxes, eval_ray_cells, RayCell};
use crate::gpu::Renderer;
use crate::ir::Domain;
use crate::render::{BisectOptions, Status, Traversal};
use crate::Formula;

/// A sphere plus `n` distinct monomials with small seeded coefficients,
/// written term by term; the first few take the extreme powers (0 to 31,
/// even and odd). `like` adds a second x³¹, so that the semantic pass
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
            None => [next(12) as u32, next(12) as u32, next(12) as u32],
        };
        if e.iter().sum::<u32>() < 3 || !seen.insert(e) {
            continue;
        }
        let c = (next(2000) as f64 - 999.5) * 1e-5 / 1.6f64.powi(e.iter().sum::<u32>() as i32);
        let mut t = format!("{c:.4e}");
        for (v, k) in ["x", "y", "z"].iter().zip(e) {
            match k {
                0 => {}
                1 => t += &format!("*{v}"),
                _ => t += &format!("*{v}^{k}"),
            }
        }
        terms.push(t);
    }
    let like = if like { " + 0.002*x^31" } else { "" };
    format!("x^2 + y^2 + z^2 - 1 + {}{like}", terms.join(" + "))
}

#[test]
fn a_polynomial_of_many_monomials_is_one_horner_loop() {
    let mixed = format!("sin(x) + {}", monomials(1100, false));
    for src in [monomials(1100, false), monomials(1100, true), mixed] {
        let f = Formula::compile("<t>", &src).unwrap();
        let g = generated_ir(&f.ir);
        let ir = g.as_ref().unwrap_or(&f.ir);
        let plan = term_loops::plan(ir);
        assert_eq!((plan.loops.len(), plan.horners.len()), (0, 1), "{src}");
        // The sphere's four monomials and the 1,100 (the like terms' two are one).
        assert_eq!(plan.horners[0].monomials, 1104, "{src}");
        assert!(plan.emitted_nodes(ir) < 300, "{}", plan.emitted_nodes(ir));
    }
    // Too few monomials, and a product of sums (expanded it would hold more
    // terms than it has operations), stay as written.
    for src in [monomials(1000, false), "(x^2 + y^2 + z^2 - 1)^3 * (x^4 + y^4 + z^4 - x*y*z) - 0.5".to_string()] {
        let f = Formula::compile("<t>", &src).unwrap();
        assert!(term_loops::plan(&f.ir).is_empty(), "{src}");
        assert!(term_loops::monomials::monomial_sums(&f.ir).is_none(), "{src}");
    }
}

#[test]
fn a_horner_loop_encloses_f64_samples() {
    let bx = boxes(2000);
    // The collected form after 40 other terms: a chain long enough to be
    // balanced, which must leave the loop's polynomial whole.
    let sines: Vec<String> = (0..40).map(|i| format!("0.01*sin({:.2}*x + {:.2})", 1.0 + 0.05 * f64::from(i), 0.1 * f64::from(i))).collect();
    let mixed = format!("{} + {}", sines.join(" + "), monomials(1100, true));
    for src in [monomials(1100, false), monomials(1100, true), mixed] {
        let f = Formula::compile("<t>", &src).unwrap();
        let g = generated_ir(&f.ir);
        assert_eq!(term_loops::plan(g.as_ref().unwrap_or(&f.ir)).horners.len(), 1);
        let bytes = src.len();
        for domain in [Domain::Scalar, Domain::Interval, Domain::Affine] {
            let r = eval_boxes(gpu(), &f.ir, domain, &bx, &[]).unwrap();
            if domain != Domain::Scalar {
                assert_encloses(&f, &r, &bx, 5, &format!("{domain:?}, formula of {bytes} bytes"));
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

/// The loop's picture against the f64 reference's first root along each
/// ray, in IA and RAA (the tape, at this size, passes its work limit): every
/// hit at the reference's root, every root the reference finds hit.
#[test]
fn a_horner_loop_draws_the_reference_roots() {
    let f = Formula::compile("<t>", &monomials(1100, false)).unwrap();
    let s = common::settings(common::cube(1.3), 40, 40);
    let roots: Vec<Option<(f64, f64)>> = (0..s.width * s.height).map(|k| common::reference_root(&f, &s, k % s.width, k / s.width, 300)).collect();
    assert!(roots.iter().filter(|r| r.is_some()).count() > 200);
    for domain in [Domain::Interval, Domain::Affine] {
        let a = Renderer::new(gpu(), &f.ir, Traversal::Bisect(BisectOptions::new(domain))).unwrap().render(&s).unwrap();
        assert_eq!(a.stats.unresolved, 0, "{:?}", a.stats);
        let mut wrong = Vec::new();
        for (k, (p, r)) in a.pixels.iter().zip(&roots).enumerate() {
            match (p.status == Status::Hit, r) {
                (true, Some((t, w))) if (f64::from(p.depth) - t).abs() <= w + 4.0 * s.eps => {}
                (false, None) => {}
                _ => wrong.push(format!("{k}: {:?} {} vs {r:?}", p.status, p.depth)),
            }
        }
        assert!(wrong.is_empty(), "{domain:?}: {wrong:?}");
    }
}

/// `--algebra auto` takes RAA for a Horner polynomial (its steps multiply
/// by x, y, z, exact affine forms along the ray), whatever its degree, but
/// not in a formula with min or max, nor for a polynomial written out.
#[test]
fn auto_takes_raa_for_a_horner_polynomial() {
    let poly = monomials(1100, false);
    assert_eq!(crate::choose_algebra(&Formula::compile("<t>", &poly).unwrap().ir), Domain::Affine);
    // Among other terms, as the compiled field gathers it.
    assert_eq!(crate::choose_algebra(&Formula::compile("<t>", &format!("sin(x) + {poly}")).unwrap().ir), Domain::Affine);
    assert_eq!(crate::choose_algebra(&Formula::compile("<t>", &format!("min({poly}, x - 0.5)")).unwrap().ir), Domain::Interval);
    assert_eq!(crate::choose_algebra(&Formula::compile("<t>", &monomials(1000, false)).unwrap().ir), Domain::Interval);
}

/// The cell enclosure of a formula with term loops (a Horner loop, a run of
/// terms) computes f at the cell's midpoint in its own pass
/// (`field::compiled::midpoint`), so a non-monotone cell's mean-value form
/// costs no scalar evaluation: the number is f's there, and the scalar
/// field's at that point. A formula written out, or one with a run of
/// terms that call sin, cos or tan, leaves the midpoint to the scalar
/// field.
#[test]
fn cells_with_term_loops_give_f_at_their_midpoints() {
    let cells: Vec<RayCell> = (0..64u8)
        .map(|k| {
            let a = f32::from(k) * 0.37;
            let o = [3.0 * a.cos(), 3.0 * a.sin(), 0.4 * (a * 1.7).sin()];
            let dir = [-o[0] / 3.0, -o[1] / 3.0, 0.1 * (a * 2.3).cos()];
            let s0 = 1.0 + 0.05 * f32::from(k % 29);
            RayCell { o, dir, s_ref: 0.5, len: 5.0, cell: [s0, s0 + 0.01 + 0.002 * f32::from(k % 7)] }
        })
        .collect();
    // Runs of 40 same-shaped terms, whose constants are not all floats.
    let run = |term: &dyn Fn(f64) -> String| format!("x^2 + y^2 + z^2 - 1 + {}", (0..40).map(|i| term(f64::from(i))).collect::<Vec<_>>().join(" + "));
    let gauss = run(&|i| format!("0.01*exp(-{:.2}*((x - {:.3})^2 + y^2))", 3.0 + 0.1 * i, 0.013 * i));
    let sines = run(&|i| format!("0.01*sin({:.2}*x + {:.2})*cos(y - {:.3})", 1.0 + 0.05 * i, 0.1 * i, 0.013 * i));
    let cases = [(monomials(1100, false), true, true), (gauss, true, true), (sines, true, false), ("x^2 + y^2 + z^2 - 1".to_string(), false, false)];
    for (src, looped, fused) in cases {
        let f = Formula::compile("<t>", &src).unwrap();
        let g = generated_ir(&f.ir);
        assert_eq!(term_loops::plan(g.as_ref().unwrap_or(&f.ir)).is_empty(), !looped, "{src}");
        let got = eval_ray_cells(gpu(), &f.ir, &cells).unwrap();
        for (c, e) in cells.iter().zip(&got) {
            let s = 0.5 * (f64::from(c.cell[0]) + f64::from(c.cell[1]));
            let p = [0, 1, 2].map(|k| f64::from(c.o[k]) + f64::from(c.dir[k]) * s);
            let v = crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[]);
            assert!((f64::from(e.mid[1]) - v).abs() <= 1e-5 * (1.0 + v.abs()), "field_ray: {} against {v} on {c:?}", e.mid[1]);
            match fused {
                true => assert_eq!(e.mid[0], e.mid[1], "the enclosure's midpoint on {c:?}"),
                false => assert_eq!(e.mid[0], 0.0, "{src}"),
            }
        }
    }
}

//! RAA kernels that read ranges without the NaN test: a compiled formula
//! whose affine forms cannot overflow for inputs within a radius
//! (`analysis::magnitude`) drops the test, and its `ra_safe` makes the
//! enclosure of any input past the radius the whole line.

use super::common;

use common::*;
use crate::ir::Domain;
use crate::render::Status;
use crate::Formula;

fn frame(src: &str, s: &crate::render::Settings) -> crate::render::Frame {
    let f = Formula::compile("<test>", src).unwrap();
    crate::gpu::Renderer::bisect(gpu(), &f.ir, Domain::Affine).unwrap().render(s).unwrap()
}

fn bounded(src: &str) -> bool {
    let f = Formula::compile("<test>", src).unwrap();
    crate::field::compiled::safe_radius(&f.ir, Domain::Affine).is_some()
}

/// The same formula plus min(0, 1/(x² + 1)), which is 0 (the quotient's
/// range is positive, so its affine min is the exact 0 form), but a
/// division: that kernel keeps the NaN test. Both draw the same picture,
/// pixel for pixel (the work differs: the quotient's slope widens the
/// sum's, so fewer cells are proven monotone).
#[test]
fn kernels_without_the_nan_test_draw_what_the_tested_kernels_draw() {
    let (city, creature) = (catalog_formula("city"), catalog_formula("creature"));
    let formulas = [
        (city.as_str(), [-2.6, 2.6, -2.6, 2.6, -0.1, 2.0]),
        (creature.as_str(), crate::catalog::lookup("creature").unwrap().header.bbox),
        ("min(sqrt(x^2 + y^2) - 0.8, abs(z) - 0.3) + 0.1*sin(3*x) + max(abs(y) - 0.9, 0)", cube(1.5)),
        ("sin(x)*cos(y) + sin(y)*cos(z) + sin(z)*cos(x) + 0.2*abs(x*y*z)", cube(3.0)),
    ];
    for (src, bbox) in formulas {
        let guarded = format!("{src}\n + min(0, 1/(x*x + 1))");
        assert!(bounded(src) && !bounded(&guarded), "{src}");
        let s = settings(bbox, 64, 64);
        let (a, b) = (frame(src, &s), frame(&guarded, &s));
        assert!(a.stats.hits > 300, "{src}: {:?}", a.stats);
        for (k, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
            assert_eq!(p.status, q.status, "{src}: pixel {k}");
            assert!(p.status != Status::Hit || (p.depth - q.depth).abs() as f64 <= 2.0 * s.eps, "{src}: pixel {k}: {} vs {}", p.depth, q.depth);
        }
    }
}

/// A parameter past the radius (2^24 here; a^4 would overflow f32 from
/// a = 4.3e9) makes every enclosure the whole line: nothing is culled,
/// pixels run out of budget and are reported, and every hit is a sign
/// change of f (f is the same surface for every a: min(0, a^4) is 0).
/// Under the radius the frame is the plain one.
#[test]
fn inputs_past_the_radius_are_the_whole_line() {
    let src = "min(x^4 + y^4 + z^4 - 1, abs(x) - 2) + min(0, a^4)";
    let f = Formula::compile("<test>", src).unwrap();
    assert_eq!(crate::field::compiled::safe_radius(&f.ir, Domain::Affine), Some(16777216.0));
    let renderer = crate::gpu::Renderer::bisect(gpu(), &f.ir, Domain::Affine).unwrap();
    let bits = 16777216f32.to_bits();
    assert!(renderer.wgsl().contains(&format!("bitcast<u32>(abs(iso_param(0u))) <= {bits}u")), "the parameter is checked against 2^24");
    let mut s = settings(cube(1.5), 48, 48);
    let draw = |s: &crate::render::Settings| renderer.render(s).unwrap();
    s.params = vec![0.5];
    let within = draw(&s);
    s.params = vec![1e8];
    let past = draw(&s);
    assert_eq!(within.stats.unresolved, 0);
    assert!(past.stats.unresolved > 100 && past.stats.evals_mean > 50.0 * within.stats.evals_mean, "{:?}", past.stats);
    for (k, (p, q)) in within.pixels.iter().zip(&past.pixels).enumerate() {
        if q.status == Status::Hit {
            assert!(p.status == Status::Hit || sign_change_near(&f, &s, k as u32, q.depth as f64), "pixel {k}: {:?} vs a hit at {}", p.status, q.depth);
        }
    }
}

/// The radius is one within which the forms stay finite: the device's RAA
/// enclosure (the eval kernel, which keeps the NaN test and would give the
/// whole line after an overflow) over boxes reaching it is finite.
#[test]
fn enclosures_reaching_the_radius_are_finite() {
    let (city, creature) = (catalog_formula("city"), catalog_formula("creature"));
    let formulas = [
        city.as_str(),
        creature.as_str(),
        "min(x^4 + y^4 + z^4 - 1, abs(x) - 2) + sin(t)",
        "sqrt(x^2 + y^2 + z^2) * abs(x*y) - max(z^4, 1) / 3",
        "exp(-abs(x)) + 0.5*sin(y*z) - 0.25",
    ];
    for src in formulas {
        let f = Formula::compile("<test>", src).unwrap();
        let b = crate::field::compiled::safe_radius(&f.ir, Domain::Affine).unwrap() as f32;
        let boxes = [[b / 2.0, b, b / 2.0, b, b / 2.0, b, 0.0, 0.0], [-b, b, -b, b, -b, b, -b, b], [-b, -b, b, b, -b, -b, b, b]];
        let r = crate::gpu::eval::eval_boxes(gpu(), &f.ir, Domain::Affine, &boxes, &[]).unwrap();
        for (bx, [lo, hi]) in boxes.iter().zip(r) {
            assert!(lo.is_finite() && hi.is_finite() && lo <= hi, "{src} over {bx:?} (radius {b}): [{lo}, {hi}]");
        }
    }
}

//! Bisection's two root searches (templates/traverse/bisect/root_search_one_point.wgsl,
//! one point of f a step, and root_search_two_points.wgsl, two): the same hits at the
//! same depth on every Knoll surface, roots where f changes sign, and the
//! automatic choice by the formula's size.

use super::common;

use common::*;
use crate::field::compiled::source::PAIR_MAX_NODES;
use crate::kernel::assemble;
use crate::ir::Domain;
use crate::gpu::Renderer;
use crate::render::{BisectOptions, Frame, RootSearch, Settings, Status, Traversal};
use crate::Formula;

fn bisect(f: &Formula, domain: Domain, search: RootSearch, s: &Settings) -> Frame {
    let b = BisectOptions { root_search: search, ..BisectOptions::new(domain) };
    Renderer::new(gpu(), &f.ir, Traversal::Bisect(b)).unwrap().render(s).unwrap()
}

/// Pixels where the two searches disagree: a different status, or depths
/// more than 2 eps apart (each ends within eps/2 of its bracket's root,
/// and both find the same bracket), or a two-point hit without a sign
/// change of f (f64) within 2 eps where the one-point hit has one.
fn disagreements(f: &Formula, s: &Settings, one: &Frame, two: &Frame) -> Vec<String> {
    let mut bad = vec![];
    for (k, (a, b)) in one.pixels.iter().zip(&two.pixels).enumerate() {
        let same = match (a.status, b.status) {
            (Status::Hit, Status::Hit) => {
                let close = (a.depth as f64 - b.depth as f64).abs() <= 2.0 * s.eps;
                close && (sign_change_near(f, s, k as u32, b.depth as f64) || !sign_change_near(f, s, k as u32, a.depth as f64))
            }
            (x, y) => x == y,
        };
        if !same {
            bad.push(format!("px {k}: {:?} {} vs {:?} {}", a.status, a.depth, b.status, b.depth));
        }
    }
    bad
}

#[test]
fn both_root_searches_give_the_same_picture_on_the_knoll_surfaces() {
    for e in crate::catalog::builtin().into_iter().take(16) {
        let f = e.compile().unwrap();
        let mut s = settings(e.header.bbox, 48, 48);
        s.time = e.header.t.unwrap_or(0.0);
        s.clip_sphere = e.header.clip.map(|crate::catalog::Clip::Sphere(r)| r);
        s.params = crate::sema::bind_params(&f.ir, &e.header.params).unwrap().0;
        let domain = crate::choose_algebra(&f.ir);
        let one = bisect(&f, domain, RootSearch::OnePoint, &s);
        let two = bisect(&f, domain, RootSearch::TwoPoints, &s);
        assert!(one.stats.hits > 0, "{}: no hits", e.name);
        let bad = disagreements(&f, &s, &one, &two);
        assert!(bad.is_empty(), "{}: {} pixels differ: {:?}", e.name, bad.len(), &bad[..bad.len().min(6)]);
    }
}

/// Leaves: cells at the depth limit whose enclosure holds 0 without f
/// changing sign across them (a double root, where the surface only
/// touches the ray, and a shell thinner than a cell), where both searches
/// look further along the ray and then refine a sign change.
#[test]
fn both_root_searches_agree_on_leaves() {
    let cases = [
        // A sphere of double roots: f ≥ 0 everywhere, 0 on the sphere.
        ("(x^2 + y^2 + z^2 - 1)^2", 1.5),
        // A shell 2e-4 thick: its two sign changes share one eps cell.
        ("(x^2 + y^2 + z^2 - 1)^2 - 1e-8", 1.5),
        // The 4-bretzel's tube, thin next to the cells of a 40² frame.
        ("((x^2 + y^2)^3 - 4*x^2*y^2)^2 + z^2 - 0.0005", 1.2),
    ];
    for (src, a) in cases {
        let f = Formula::compile("<test>", src).unwrap();
        let s = settings(cube(a), 40, 40);
        for domain in [Domain::Interval, Domain::Affine] {
            let one = bisect(&f, domain, RootSearch::OnePoint, &s);
            let two = bisect(&f, domain, RootSearch::TwoPoints, &s);
            assert!(one.stats.hits > 0, "{src} ({domain:?}): no hits");
            let bad = disagreements(&f, &s, &one, &two);
            assert!(bad.is_empty(), "{src} ({domain:?}): {} pixels differ: {:?}", bad.len(), &bad[..bad.len().min(6)]);
        }
    }
}

/// The analytic sphere: two-point hits at the distance |eye| − 1 from the
/// eye along the ray's closest approach, to eps.
#[test]
fn two_point_hits_on_the_sphere_are_at_its_analytic_depth() {
    let f = Formula::compile("<test>", "x^2 + y^2 + z^2 - 1").unwrap();
    let s = settings(cube(1.5), 32, 32);
    let frame = bisect(&f, Domain::Interval, RootSearch::TwoPoints, &s);
    let cf = s.camera.frame().unwrap();
    let mut hits = 0;
    for (k, p) in frame.pixels.iter().enumerate() {
        let d = crate::render::Camera::ray(&cf, k as u32 % s.width, k as u32 / s.width, s.width, s.height).normalize();
        let o = s.camera.eye;
        let b = o.dot(d);
        let disc = b * b - (o.dot(o) - 1.0);
        if p.status != Status::Hit {
            assert!(disc <= 1e-3, "pixel {k} missed a ray that crosses the sphere (disc {disc})");
            continue;
        }
        hits += 1;
        let t = -b - disc.sqrt();
        assert!((p.depth as f64 - t).abs() <= s.eps, "pixel {k}: depth {} against {t}", p.depth);
    }
    assert!(hits > 80, "{hits} hits");
}

/// `Auto` takes two points up to PAIR_MAX_NODES live nodes and one point
/// above: the kernels are those of the explicit choices.
#[test]
fn auto_takes_two_points_for_small_formulas_only() {
    let kernel = |f: &Formula, r: RootSearch| {
        let b = BisectOptions { root_search: r, ..BisectOptions::new(Domain::Interval) };
        assemble(&f.ir, &Traversal::Bisect(b)).wgsl
    };
    let small = Formula::compile("<test>", "x^4 + y^4 + z^4 - 1").unwrap();
    assert_eq!(kernel(&small, RootSearch::Auto), kernel(&small, RootSearch::TwoPoints));
    assert_ne!(kernel(&small, RootSearch::Auto), kernel(&small, RootSearch::OnePoint));
    let terms: Vec<String> = (0..PAIR_MAX_NODES / 4 + 1).map(|i| format!("sin(x + {i}) * y")).collect();
    let big = Formula::compile("<test>", &format!("{} - z", terms.join(" + "))).unwrap();
    assert!(big.ir.live().len() > PAIR_MAX_NODES, "{} nodes", big.ir.live().len());
    assert_eq!(kernel(&big, RootSearch::Auto), kernel(&big, RootSearch::OnePoint));
}

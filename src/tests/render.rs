//! Renderer tests: depth against analytic intersections, silhouettes, tiles,
//! the unresolved counter, and no missed sign changes against a brute-force
//! f64 reference.

use super::common;

use common::*;
use crate::ir::Domain;
use crate::render::{Camera, Status, Unresolved};

/// Analytic ray–sphere (unit sphere at the origin) distance.
fn sphere_hit(o: glam::DVec3, d: glam::DVec3, r: f64) -> Option<f64> {
    let b = o.dot(d);
    let c = o.dot(o) - r * r;
    let disc = b * b - c;
    (disc >= 0.0).then(|| -b - disc.sqrt())
}

/// Also from an eye 100 units away with a 2° field of view (the peer
/// harness's near-orthographic view): in IA the sphere is one polynomial
/// along each ray (`field::compiled::ray_forms`), worked out from the ray's entry
/// into the box, not from the far eye, whose |o|² is 10⁴.
#[test]
fn sphere_depth_within_eps_and_silhouette_within_a_pixel() {
    for (domain, far) in [(Domain::Interval, false), (Domain::Affine, false), (Domain::Interval, true)] {
        let mut s = settings(cube(1.5), 96, 64);
        if far {
            s.camera.eye = s.camera.eye.normalize() * 100.0;
            s.camera.fov_deg = 2.0;
        }
        let frame = render("x^2 + y^2 + z^2 - 1", domain, &s);
        // Depth as a user gets it: the EXR Z channel.
        let z = exr_channel(&frame, "Z");
        let cf = s.camera.frame().unwrap();
        let mut worst = 0.0f64;
        for j in 0..s.height {
            for i in 0..s.width {
                let mut p = frame.pixels[(j * s.width + i) as usize];
                p.depth = z[(j * s.width + i) as usize];
                let d = Camera::ray(&cf, i, j, s.width, s.height);
                let exact = sphere_hit(s.camera.eye, d, 1.0);
                match (p.status, exact) {
                    (Status::Hit, Some(t)) => {
                        if (p.depth as f64 - t).abs() > s.eps { eprintln!("{domain:?} ({i},{j}) depth {} exact {t}", p.depth); }
                        worst = worst.max((p.depth as f64 - t).abs());
                        // The normal (packed octahedrally by the kernel) is
                        // the sphere's, facing the eye.
                        let n = glam::DVec3::from_array(p.normal.map(f64::from));
                        let exact_n = (s.camera.eye + d * t).normalize();
                        assert!((n - exact_n).length() < 2e-3, "{domain:?} ({i},{j}): normal {n} exact {exact_n}");
                        assert!(p.color[3] == 1.0 && p.color[..3].iter().all(|c| (0.0..=1.0).contains(c)), "{:?}", p.color);
                    }
                    (Status::Miss, None) => assert!(p.normal == [0.0; 3] && p.color[3] == 0.0 && p.depth.is_infinite()),
                    (Status::Unresolved, _) => panic!("{domain:?}: unresolved pixel ({i},{j})"),
                    (got, exact) => {
                        // Disagreement only at the silhouette: a neighbour ray must
                        // graze the sphere within about one pixel.
                        let pix = 2.0 * cf.tan_half_fov / s.height as f64 * s.camera.eye.length();
                        let miss_dist = {
                            let b = s.camera.eye.dot(d);
                            (s.camera.eye.length_squared() - b * b).sqrt()
                        };
                        assert!((miss_dist - 1.0).abs() < 1.5 * pix, "{domain:?}: pixel ({i},{j}) is {got:?} but the exact answer is {exact:?} (ray passes {miss_dist} from the centre)");
                    }
                }
            }
        }
        assert!(worst <= s.eps, "{domain:?}: depth error {worst} exceeds eps {}", s.eps);
    }
}

#[test]
fn plane_depth_within_eps() {
    let s = settings([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0], 48, 48);
    let frame = render("z - 0.3 + 0*x", Domain::Interval, &s);
    let z = exr_channel(&frame, "Z");
    let cf = s.camera.frame().unwrap();
    let (mut hits, mut expected) = (0, 0);
    for j in 0..s.height {
        for i in 0..s.width {
            let mut p = frame.pixels[(j * s.width + i) as usize];
            p.depth = z[(j * s.width + i) as usize];
            let d = Camera::ray(&cf, i, j, s.width, s.height);
            let t = (0.3 - s.camera.eye.z) / d.z;
            let q = s.camera.eye + d * t;
            let inside = q.x.abs() < 0.999 && q.y.abs() < 0.999;
            expected += usize::from(inside);
            if p.status == Status::Hit {
                hits += 1;
                assert!((p.depth as f64 - t).abs() <= s.eps, "pixel ({i},{j}): depth {} vs {t}", p.depth);
            } else if inside {
                eprintln!("{:?}", p);
                panic!("pixel ({i},{j}) misses the plane inside the box");
            }
        }
    }
    assert!(hits >= expected && expected > 200, "{hits} hits, {expected} expected");
}

#[test]
fn tiled_and_untiled_renders_are_identical() {
    let mut s = settings(cube(2.0), 80, 56);
    let src = "4*(2.618034*x^2 - y^2)*(2.618034*y^2 - z^2)*(2.618034*z^2 - x^2) - 4.236068*(x^2 + y^2 + z^2 - 1)^2";
    let whole = render(src, Domain::Affine, &s);
    s.tile = 24;
    let tiled = render(src, Domain::Affine, &s);
    assert_eq!(tiled.stats.dispatches, 4 * 3);
    assert_eq!(whole.stats.dispatches, 1);
    assert!(whole.pixels == tiled.pixels, "tiled render differs");
}

#[test]
fn packed_frames_hold_the_same_pixels_and_statistics() {
    use crate::gpu::Renderer;
use crate::render::record::PackedFrame;
    let f = crate::Formula::compile("<test>", "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8").unwrap();
    let r = Renderer::bisect(gpu(), &f.ir, Domain::Affine).unwrap();
    for tile in [1024, 24] {
        let mut s = settings(cube(3.0), 72, 48);
        s.tile = tile;
        let frame = r.render(&s).unwrap();
        let mut packed = PackedFrame::default();
        r.render_packed(&s, &mut packed).unwrap();
        let decoded = packed.decode();
        assert!(decoded.pixels == frame.pixels, "tile {tile}: packed pixels differ");
        assert_eq!(packed.pixel(72 * 20 + 30), frame.pixels[72 * 20 + 30]);
        let (a, b) = (&packed.stats, &frame.stats);
        assert_eq!((a.hits, a.unresolved, a.evals_p99, a.evals_max, a.dispatches), (b.hits, b.unresolved, b.evals_p99, b.evals_max, b.dispatches));
        assert_eq!((a.evals_mean, a.bisect.evals_lower_bound, a.evals_hit_mean, a.evals_miss_mean), (b.evals_mean, b.bisect.evals_lower_bound, b.evals_hit_mean, b.evals_miss_mean));
        assert!(b.hits > 0 && b.hits < 72 * 48);
    }
}

#[test]
fn unresolved_pixels_are_counted_and_flagged() {
    let mut s = settings(cube(3.0), 40, 40);
    s.max_iter = 1; // a hit needs at least 2 iterations (a cell, then a monotone one)
    let frame = render("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", Domain::Interval, &s);
    assert!(frame.stats.unresolved > 0);
    assert_eq!(frame.stats.hits, 0);
    // Unresolved pixels are not background, and by default they do not look
    // like hits either: the shaded best guess (`Guess`) under diagonal
    // magenta stripes 3 pixels wide; `Magenta` paints them all.
    let magenta = [1.0, 0.0, 1.0, 1.0];
    let with = |u: Unresolved| {
        let mut s = s.clone();
        s.unresolved = u;
        render("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", Domain::Interval, &s)
    };
    let (hatch, guess, solid) = (with(Unresolved::Hatch), with(Unresolved::Guess), with(Unresolved::Magenta));
    let mut striped = 0;
    for (i, ((h, g), m)) in hatch.pixels.iter().zip(&guess.pixels).zip(&solid.pixels).enumerate() {
        assert_eq!((h.status, h.depth), (g.status, g.depth), "pixel {i}: the style changes colour only");
        if h.status != Status::Unresolved {
            assert_eq!((h.color, m.color), (g.color, g.color), "pixel {i}");
            continue;
        }
        assert_eq!(m.color, magenta, "pixel {i}");
        assert_ne!(g.color, magenta, "pixel {i}: the guess is shaded");
        let (x, y) = (i as u32 % 40, i as u32 / 40);
        if (x + y) / 3 % 2 == 0 {
            assert_eq!(h.color, magenta, "pixel {i} is on a stripe");
            striped += 1;
        } else {
            assert_eq!(h.color, g.color, "pixel {i} is between stripes");
        }
    }
    assert!(striped > 0 && striped < frame.stats.unresolved as usize);
}

/// The standard against which robustness is judged: every pixel whose ray
/// has a sign change of f (found by dense f64 sampling) must be a hit, no
/// farther than the reference root plus eps.
fn assert_no_missed_roots(src: &str, bbox: [f64; 6], domain: Domain, size: u32) {
    let f = crate::Formula::compile("<test>", src).unwrap();
    let s = settings(bbox, size, size);
    let frame = render(src, domain, &s);
    let mut missed = vec![];
    for j in 0..size {
        for i in 0..size {
            let p = frame.pixels[(j * size + i) as usize];
            if let Some((t, step)) = reference_root(&f, &s, i, j, 4000) {
                let ok = p.status == Status::Hit && (p.depth as f64) <= t + s.eps + step;
                if !ok {
                    missed.push(format!("({i},{j}) ref {t:.5} got {:?} {:.5}", p.status, p.depth));
                }
            }
        }
    }
    assert!(missed.is_empty(), "{src} {domain:?}: {} pixels miss a sign change: {:?}", missed.len(), &missed[..missed.len().min(8)]);
}

#[test]
fn no_missed_sign_changes_on_knoll_surfaces() {
    let cases: &[(&str, [f64; 6])] = &[
        ("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", cube(3.0)),
        ("4*(x^4 + (y^2 + z^2)^2) + 17*x^2*(y^2 + z^2) - 20*(x^2 + y^2 + z^2) + 17", cube(2.5)),
        ("x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z", cube(1.0)),
        ("4*(1.618033988749895^2*x^2 - y^2)*(1.618033988749895^2*y^2 - z^2)*(1.618033988749895^2*z^2 - x^2) - (1 + 2*1.618033988749895)*(x^2 + y^2 + z^2 - 1)^2", cube(2.0)),
        ("z - sin(3*sqrt(x^2 + y^2 + 0.000001))/(3*sqrt(x^2 + y^2 + 0.000001))", [-4.0, 4.0, -4.0, 4.0, -0.5, 1.2]),
        ("max(x^8 + y^8 + z^8 - 1, -min(min(y^2 + z^2 - 0.25, x^2 + z^2 - 0.25), x^2 + y^2 - 0.25))", cube(1.5)),
    ];
    for (src, bbox) in cases {
        for domain in [Domain::Interval, Domain::Affine] {
            assert_no_missed_roots(src, *bbox, domain, 48);
        }
    }
}

/// A node of degree ≤ 2 in x, y, z with two or more terms is taken from its
/// polynomial along the ray (`field::compiled::ray_forms`): its exact range over
/// a cell (the ends and the vertex), its exact slope and its value at a
/// point, where intervals over the cell's box overestimate a sum of several
/// variables' terms. icos.csg's ten planes |n·p| and its ball; quadrics
/// with cross terms; the decocube's three. No sign change the f64 reference
/// finds is missed, and icos.csg needs fewer evaluations than over the box
/// (here 3.07 over the box, 2.30 with its planes from the segment's ends,
/// 2.20 with its ball from the ray too).
#[test]
fn nodes_of_degree_two_are_taken_from_the_ray() {
    let icos = &catalog_formula("icos.csg");
    let f = crate::Formula::compile("<test>", icos).unwrap();
    let wgsl = crate::kernel::render_shader(&f.ir, Domain::Interval);
    assert_eq!(wgsl.matches("ia_ray_lin(g_q").count(), 10, "the ten planes' enclosures");
    assert_eq!(wgsl.matches("ia_ray(g_q").count(), 1, "the ball's");
    assert_eq!(wgsl.matches("s_ray_lin(g_q").count() + wgsl.matches("s_ray(g_q").count(), 11, "and their values at points");
    assert_no_missed_roots(icos, cube(1.4), Domain::Interval, 64);
    let frame = render(icos, Domain::Interval, &settings(cube(1.4), 64, 64));
    assert!(frame.stats.hits > 400, "{:?}", frame.stats);
    assert!(frame.stats.evals_mean < 2.25, "{} evaluations a pixel", frame.stats.evals_mean);
    let quadrics: &[(&str, [f64; 6])] = &[
        ("x*y + y*z + z*x + 0.3*x - 0.2", cube(1.0)),
        ("(x - 0.2)^2/0.8 + 2*(y + 0.1)^2 + (1.5*z)^2 - 0.3*x*z - 0.7", cube(1.2)),
    ];
    for (src, bbox) in quadrics {
        let f = crate::Formula::compile("<test>", src).unwrap();
        assert!(crate::kernel::render_shader(&f.ir, Domain::Interval).contains("ia_ray(g_q"), "{src}");
        assert_no_missed_roots(src, *bbox, Domain::Interval, 48);
    }
}

/// A polynomial node of degree 3 to 6 whose terms depend on each other is
/// taken from its polynomial along the ray by its Bernstein coefficients
/// over each cell (`field::compiled::ray_polys`): the decocube's three quartic
/// factors, the 4-bretzel's sextic (x² + y²)³ − 4x²y² inside its square,
/// the tangle whole, a quintic with a product of two sums. No sign change
/// the f64 reference finds is missed, and every hit is at the RAA kernel's
/// depth (no ray polynomials there) within two eps.
#[test]
fn polynomials_of_degree_three_to_six_are_taken_from_the_ray() {
    let bretzel = catalog_formula("4-bretzel");
    let cases: &[(&str, [f64; 6], &str, usize)] = &[
        ("((x^2 + y^2 - 0.64)^2 + (z^2 - 1)^2)*((y^2 + z^2 - 0.64)^2 + (x^2 - 1)^2)*((z^2 + x^2 - 0.64)^2 + (y^2 - 1)^2) - 0.04", cube(1.5), "ia_ray_poly(ray_poly4_bern(g_pa", 3),
        (&bretzel, [-1.2, 1.2, -1.2, 1.2, -0.1, 0.1], "ia_ray_poly(ray_poly6_bern(g_pa", 1),
        ("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8", cube(3.0), "ia_ray_poly(ray_poly4_bern(g_pa", 1),
        ("(x + 0.5*y)*(x^2 + z^2 - 1)^2 - y^3*z + 0.1*sin(x)", cube(1.5), "ia_ray_poly(ray_poly5_bern(g_pa", 1),
    ];
    for (src, bbox, call, n) in cases {
        let f = crate::Formula::compile("<test>", src).unwrap();
        let wgsl = crate::kernel::render_shader(&f.ir, Domain::Interval);
        assert_eq!(wgsl.matches(call).count(), *n, "{src}: {call}");
        assert_no_missed_roots(src, *bbox, Domain::Interval, 48);
        let s = settings(*bbox, 48, 48);
        let (ia, raa) = (render(src, Domain::Interval, &s), render(src, Domain::Affine, &s));
        assert!(ia.stats.hits > 60, "{src}: {:?}", ia.stats);
        let apart: Vec<_> = ia.pixels.iter().zip(&raa.pixels).enumerate().filter(|(_, (a, b))| a.status != b.status || (a.status == Status::Hit && (a.depth - b.depth).abs() > 2.0 * s.eps as f32)).map(|(i, (a, b))| (i, a.status, a.depth, b.status, b.depth)).collect();
        assert!(apart.is_empty(), "{src}: {} pixels differ from RAA: {:?}", apart.len(), &apart[..apart.len().min(6)]);
    }
}

/// Every catalog surface whose IA kernel takes polynomial nodes from the ray
/// (12 of them) draws the RAA kernel's picture: the same hits and misses
/// and depths within two eps, except where the IA kernel's hit or the
/// nearer of two depths has no sign change of f near it (a tangent zero
/// set or a node, Knoll's rule: Steiner's axes, the Barth surfaces' nodes,
/// the heart's cusp).
#[test]
fn catalog_polynomials_from_the_ray_draw_the_raa_picture() {
    let mut checked = 0;
    for e in crate::catalog::builtin() {
        let f = e.compile().unwrap();
        if !crate::field::compiled::takes_ray_polynomials(&f.ir) {
            continue;
        }
        let mut s = settings(e.header.bbox, 96, 96);
        s.time = e.header.t.unwrap_or(0.0);
        s.clip_sphere = e.header.clip.map(|crate::catalog::Clip::Sphere(r)| r);
        s.params = crate::sema::bind_params(&f.ir, &e.header.params).unwrap().0;
        let draw = |d| crate::gpu::Renderer::bisect(gpu(), &f.ir, d).unwrap().render(&s).unwrap();
        let (ia, raa) = (draw(Domain::Interval), draw(Domain::Affine));
        let tangent = |k: usize, depth: f32| !sign_change_near(&f, &s, k as u32, depth as f64);
        let bad: Vec<String> = ia
            .pixels
            .iter()
            .zip(&raa.pixels)
            .enumerate()
            .filter(|&(k, (a, b))| match (a.status, b.status) {
                (Status::Hit, Status::Hit) => (a.depth - b.depth).abs() > 2.0 * s.eps as f32 && !tangent(k, a.depth.min(b.depth)),
                (Status::Hit, _) => !tangent(k, a.depth),
                (_, Status::Hit) => !tangent(k, b.depth),
                (x, y) => x != y,
            })
            .map(|(k, (a, b))| format!("px {k}: {:?} {} vs {:?} {}", a.status, a.depth, b.status, b.depth))
            .collect();
        assert!(bad.is_empty(), "{}: {} pixels differ from RAA: {:?}", e.name, bad.len(), &bad[..bad.len().min(6)]);
        assert!(ia.stats.hits > 200, "{}: {:?}", e.name, ia.stats);
        checked += 1;
    }
    assert!(checked >= 12, "{checked} catalog surfaces with ray polynomials");
}

/// In RAA the slopes of a formula that is not a polynomial of moderate
/// degree are intervals (`derivative::slope_domain`): x^200's slope beyond
/// f32 keeps its sign there, where an affine slope is the whole line and
/// no cell near the surface is proven monotone (56 evaluations a pixel at
/// 256² with affine slopes, 4.9 with interval ones). The picture is the
/// interval kernel's, hit for hit.
#[test]
fn a_high_power_keeps_its_slope_in_raa() {
    let src = "x^200 + y^200 + z^200 - 1";
    let s = settings(cube(1.5), 48, 48);
    let (raa, ia) = (render(src, Domain::Affine, &s), render(src, Domain::Interval, &s));
    assert!(raa.stats.hits > 400, "{}", raa.stats.hits);
    assert!(raa.stats.evals_mean < 12.0, "{} evaluations a pixel", raa.stats.evals_mean);
    for (k, (a, b)) in raa.pixels.iter().zip(&ia.pixels).enumerate() {
        assert_eq!(a.status, b.status, "pixel {k}");
        assert!(a.status != Status::Hit || (a.depth - b.depth).abs() as f64 <= 2.0 * s.eps, "pixel {k}: {} vs {}", a.depth, b.depth);
    }
    assert_no_missed_roots(src, cube(1.5), Domain::Affine, 48);
}

/// The tile pass encloses f only inside the domain (box and clip ball): rays
/// are clipped to it, so a surface that goes on past it (here a plane beside
/// the box, then one past the ball) keeps no tile for the per-pixel pass.
/// Almost every tile then makes its 8 coarse slab enclosures and nothing
/// more (8/64 = 0.125 a pixel; 0.137 at 64², a few tiles at the box's edge
/// enclosing fine slabs too). Before, the tiles beside the domain went on to
/// their fine slabs and were queued (0.21 at 64²), as were most tiles of a
/// height field's frame (cloth: 14,042 of 16,384 at 1024², 6,789 now).
#[test]
fn the_tile_pass_encloses_only_inside_the_domain() {
    let mut s = settings(cube(1.0), 64, 64);
    let f = render("x - 1.5", Domain::Interval, &s);
    assert_eq!(f.stats.hits, 0);
    assert!(f.stats.evals_mean <= 9.0 / 64.0, "{} evaluations a pixel", f.stats.evals_mean);
    // The same inside the box but past the clip ball (0.21 before).
    s.clip_sphere = Some(0.5);
    let f = render("x - 0.8", Domain::Interval, &s);
    assert_eq!(f.stats.hits, 0);
    assert!(f.stats.evals_mean <= 9.0 / 64.0, "clipped: {} evaluations a pixel", f.stats.evals_mean);
}

/// Every optimisation only skips work that is proven unnecessary: with and
/// without each, every Knoll surface gives the same hits at the same depth
/// (within eps, plus the step of refinement that differs: the monotone path
/// solves to eps, the bisection path refines the first eps cell).
#[test]
fn optimisations_do_not_change_the_picture() {
    use crate::gpu::Renderer;
use crate::render::Optimizations;
    let variants = [
        Optimizations { tile_culling: false, monotone: false, ..Default::default() },
        Optimizations { tile_culling: true, monotone: false, ..Default::default() },
        Optimizations { tile_culling: false, monotone: true, ..Default::default() },
    ];
    for e in crate::catalog::builtin().into_iter().take(16) {
        let f = e.compile().unwrap();
        let mut s = settings(e.header.bbox, 40, 40);
        s.time = e.header.t.unwrap_or(0.0);
        s.clip_sphere = e.header.clip.map(|crate::catalog::Clip::Sphere(r)| r);
        s.params = crate::sema::bind_params(&f.ir, &e.header.params).unwrap().0;
        let mut r = Renderer::bisect(gpu(), &f.ir, crate::choose_algebra(&f.ir)).unwrap();
        let all = r.render(&s).unwrap();
        for o in variants {
            *r.optimizations_mut().unwrap() = o;
            let other = r.render(&s).unwrap();
            let mut bad = vec![];
            for (k, (a, b)) in all.pixels.iter().zip(&other.pixels).enumerate() {
                let same = match (a.status, b.status) {
                    (Status::Hit, Status::Hit) => {
                        let (da, db) = (a.depth as f64, b.depth as f64);
                        // Without the monotonicity proof, an eps cell whose
                        // enclosure contains 0 before the surface is a hit
                        // (Knoll's rule); with it such a cell is rejected
                        // unless f changes sign. So `other` may only be
                        // earlier, at a point where f does not change sign.
                        (da - db).abs() <= 2.0 * s.eps || (db < da && !sign_change_near(&f, &s, k as u32, db))
                    }
                    // The same where the ray misses with the proof: a
                    // tangent zero set (Steiner's axes) is a hit without it.
                    (Status::Miss, Status::Hit) => !sign_change_near(&f, &s, k as u32, b.depth as f64),
                    (x, y) => x == y,
                };
                if !same {
                    bad.push(format!("px {k}: {:?} {} vs {:?} {}", a.status, a.depth, b.status, b.depth));
                }
            }
            assert!(bad.len() <= 1, "{} with {o:?}: {} pixels differ: {:?}", e.name, bad.len(), &bad[..bad.len().min(6)]);
        }
    }
}

/// A monotone cell's root (the ITP method, `itp_point` in the bisection
/// kernel) ends within eps of f's sign change also where f is steep: x^200
/// goes from -1 to 1e35 across the superquadric's faces, where regula
/// falsi's secant lands next to one end, step after step.
#[test]
fn steep_roots_are_found_within_eps() {
    let src = "x^200 + y^200 + z^200 - 1";
    let f = crate::Formula::compile("<test>", src).unwrap();
    for domain in [Domain::Interval, Domain::Affine] {
        let s = settings(cube(1.5), 64, 64);
        let frame = render(src, domain, &s);
        let mut hits = 0;
        for (k, p) in frame.pixels.iter().enumerate() {
            assert!(p.status != Status::Unresolved, "{domain:?}: pixel {k} unresolved");
            if p.status == Status::Hit {
                hits += 1;
                assert!(sign_change_near(&f, &s, k as u32, p.depth as f64), "{domain:?}: pixel {k}: no sign change within 2 eps of {}", p.depth);
            }
        }
        assert!(hits > 500, "{domain:?}: {hits} hits");
    }
}

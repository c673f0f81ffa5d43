//! Sphere tracing on the device: depth against bisection on the SDF scenes,
//! against the analytic sphere, each technique switched off, tiles, the
//! convex bound, and formulas that are not distance bounds.

use super::common;

use common::gpu;
use glam::DVec3;
use crate::catalog;
use crate::ir::Domain;
use crate::gpu::Renderer;
use crate::render::Settings;
use crate::render::SphereOptions;
use crate::render::{Camera, Frame, Status};
use crate::Formula;

/// Settings from a catalog scene's header (box, camera), CLI defaults otherwise.
fn scene(name: &str, w: u32, h: u32) -> (Formula, Settings, catalog::Header) {
    let e = catalog::lookup(name).unwrap();
    let hd = e.header.clone();
    let b = hd.bbox;
    let mut s = Settings::for_box(b, w, h);
    s.camera = Camera::default_for(&b, hd.fov.unwrap_or(40.0), w as f64 / h as f64);
    if let Some(t) = hd.target {
        s.camera.target = DVec3::from_array(t);
    }
    if let Some(eye) = hd.eye {
        s.camera.eye = DVec3::from_array(eye);
    }
    (e.compile().unwrap(), s, hd)
}

fn sphere(f: &Formula, s: &Settings, o: &SphereOptions) -> Frame {
    Renderer::sphere(gpu(), &f.ir, o.clone()).unwrap().render(s).unwrap()
}

fn bisect(f: &Formula, s: &Settings) -> Frame {
    Renderer::bisect(gpu(), &f.ir, Domain::Interval).unwrap().render(s).unwrap()
}

fn options(h: &catalog::Header) -> SphereOptions {
    SphereOptions { bound: h.bound, ..Default::default() }
}

/// How two depth images of the same view agree.
struct Agreement {
    compared: usize,
    grazing: usize,
    worst: f64,
    bad: Vec<String>,
}

/// First t in [t0, t1] where the ray comes within `thr(t)` of the surface
/// (f < thr), by f64 stepping (no GPU technique): an independent reference
/// for where a screen-space or threshold criterion may stop. f is
/// 1-Lipschitz and thr grows by at most `slope` per unit, so no point with
/// f < thr lies within (v - thr) / (1 + slope) of a point where f = v.
fn first_approach(f: &Formula, o: DVec3, d: DVec3, t0: f64, t1: f64, thr: &dyn Fn(f64) -> f64, slope: f64) -> Option<f64> {
    let mut t = t0;
    for _ in 0..200_000 {
        if t > t1 {
            return None;
        }
        let p = o + d * t;
        let v = crate::reference::eval_scalar(&f.ir, [p.x, p.y, p.z, 0.0], &[]);
        let gap = v - thr(t);
        if gap < 0.0 {
            return Some(t);
        }
        t += (gap / (1.0 + slope)).max(1e-6 * t.max(1.0));
    }
    None
}

/// Compares a sphere traced frame with a bisection frame of the same view.
/// A pixel is *grazing* when its ray passes within the termination
/// threshold `thr(t)` of a surface (f < thr) before the bisection depth
/// minus the tolerance, or misses while passing that close, or when the
/// surface is seen at more than ~80° (|cos| < 0.17): near silhouette edges
/// the criterion legitimately stops at the edge that bisection passes.
/// Every other pixel must have the same status, and depths within
/// `tol(t, cos)`.
fn agreement(f: &Formula, sp: &Frame, bi: &Frame, s: &Settings, thr: (&dyn Fn(f64) -> f64, f64), tol: &dyn Fn(f64, f64) -> f64) -> Agreement {
    let cf = s.camera.frame().unwrap();
    let mut a = Agreement { compared: 0, grazing: 0, worst: 0.0, bad: vec![] };
    for j in 0..s.height {
        for i in 0..s.width {
            let k = (j * s.width + i) as usize;
            let (b, p) = (bi.pixels[k], sp.pixels[k]);
            let d = Camera::ray(&cf, i, j, s.width, s.height);
            let cos = (DVec3::from_array(b.normal.map(f64::from)).dot(d)).abs();
            let near = common::clip(s.camera.eye, d, &s.bbox).and_then(|(t0, t1)| first_approach(f, s.camera.eye, d, t0, t1, thr.0, thr.1));
            let grazing = match (b.status, near) {
                (Status::Hit, Some(t)) => cos < 0.17 || t < b.depth as f64 - tol(b.depth as f64, cos),
                (Status::Hit, None) => cos < 0.17,
                (_, near) => near.is_some(),
            };
            if grazing {
                a.grazing += 1;
                continue;
            }
            a.compared += 1;
            match (p.status, b.status) {
                (Status::Miss, Status::Miss) => {}
                (Status::Hit, Status::Hit) => {
                    let t = b.depth as f64;
                    let err = (p.depth as f64 - t).abs();
                    let allowed = tol(t, cos);
                    a.worst = a.worst.max(err / allowed);
                    if err > allowed {
                        a.bad.push(format!("({i},{j}) sphere {} bisect {} cos {cos:.2}", p.depth, b.depth));
                    }
                }
                (ps, bs) => a.bad.push(format!("({i},{j}) sphere {ps:?} bisect {bs:?}")),
            }
        }
    }
    a
}

/// The README's statement: on the SDF scenes sphere tracing and bisection
/// find the same surface. With the default techniques the depths differ by
/// at most one pixel's footprint along the ray, 2 r_px t / cos θ
/// (r_px = tan(fov/2) / height: the criterion stops within half a pixel of
/// *some* surface, which near a crease is not the one hit), plus 2 eps;
/// with technique 2 off (absolute threshold eps) by at most
/// 2 eps / cos θ + eps. Grazing pixels (see [`agreement`]) are excluded and
/// must stay below 10 %.
#[test]
fn depth_agrees_with_bisection_on_the_sdf_scenes() {
    for name in catalog::suite("sdf").unwrap() {
        let (f, s, hd) = scene(name, 80, 60);
        let bi = bisect(&f, &s);
        let r_px = s.camera.frame().unwrap().tan_half_fov / s.height as f64;
        let eps = s.eps;
        type Rule = Box<dyn Fn(f64) -> f64>;
        type Tol = Box<dyn Fn(f64, f64) -> f64>;
        let modes: [(&str, SphereOptions, Rule, Tol); 2] = [
            ("default", options(&hd), Box::new(move |t| r_px * t), Box::new(move |t, cos| 2.0 * r_px * t / cos.max(0.17) + 2.0 * eps)),
            (
                "absolute",
                SphereOptions { screen_space: false, ..options(&hd) },
                Box::new(move |_| eps),
                Box::new(move |_, cos| 2.0 * eps / cos.max(0.17) + eps),
            ),
        ];
        for (mode, o, thr, tol) in modes {
            let sp = sphere(&f, &s, &o);
            let slope = if o.screen_space { r_px } else { 0.0 };
            let a = agreement(&f, &sp, &bi, &s, (thr.as_ref(), slope), tol.as_ref());
            eprintln!("{name} {mode}: {} compared, {} grazing, worst {:.2} of the tolerance, {} bad; steps {:.1}/px", a.compared, a.grazing, a.worst, a.bad.len(), sp.stats.evals_mean);
            assert!(a.bad.is_empty(), "{name} {mode}: {} of {} pixels disagree: {:?}", a.bad.len(), a.compared, &a.bad[..a.bad.len().min(6)]);
            assert!(a.grazing * 10 < a.compared, "{name} {mode}: too many grazing pixels ({} of {})", a.grazing, a.compared);
            assert_eq!(sp.stats.unresolved, 0, "{name} {mode}");
        }
    }
}

/// Depth of the unit sphere against the analytic intersection: within the
/// half-pixel criterion along the ray (plus eps), silhouettes excepted.
#[test]
fn sphere_depth_matches_the_analytic_intersection() {
    let f = Formula::compile("<test>", "sphere(1)").unwrap();
    let mut s = common::settings(common::cube(1.5), 64, 48);
    s.tile = 1024;
    let fr = sphere(&f, &s, &SphereOptions::default());
    let cf = s.camera.frame().unwrap();
    let r_px = cf.tan_half_fov / s.height as f64;
    let o = s.camera.eye;
    let (mut hits, mut worst) = (0, 0.0f64);
    for j in 0..s.height {
        for i in 0..s.width {
            let p = fr.pixels[(j * s.width + i) as usize];
            let d = Camera::ray(&cf, i, j, s.width, s.height);
            let b = o.dot(d);
            let disc = b * b - (o.length_squared() - 1.0);
            if disc < 0.0 {
                continue;
            }
            let t = -b - disc.sqrt();
            let cos = ((o + d * t).normalize().dot(d)).abs();
            if cos < 0.17 {
                continue; // grazing: the silhouette
            }
            assert_eq!(p.status, Status::Hit, "({i},{j})");
            hits += 1;
            let allowed = r_px * t / cos + s.eps;
            worst = worst.max((p.depth as f64 - t).abs() / allowed);
        }
    }
    assert!(hits > 150 && worst <= 1.0, "{hits} hits, worst {worst} of the tolerance");
}

#[test]
fn tiled_and_untiled_renders_are_identical() {
    let (f, mut s, hd) = scene("creature", 72, 40);
    let o = SphereOptions { shadows: true, ..options(&hd) };
    let whole = sphere(&f, &s, &o);
    s.tile = 16;
    let tiled = sphere(&f, &s, &o);
    assert_eq!(tiled.stats.dispatches, 5 * 3);
    assert!(whole.pixels == tiled.pixels, "tiled render differs");
}

/// Technique 1: over-relaxation takes fewer steps for the same picture.
#[test]
fn over_relaxation_saves_steps_and_keeps_the_picture() {
    for name in ["city", "creature"] {
        let (f, s, hd) = scene(name, 96, 64);
        let plain = sphere(&f, &s, &SphereOptions { omega: 1.0, ..options(&hd) });
        let relaxed = sphere(&f, &s, &options(&hd));
        assert_eq!(plain.stats.sphere.sor_fallbacks, 0);
        assert!(relaxed.stats.sphere.sor_fallbacks > 0);
        assert!(relaxed.stats.evals_mean < 0.97 * plain.stats.evals_mean, "{name}: {} vs {} steps", relaxed.stats.evals_mean, plain.stats.evals_mean);
        let differ = plain.pixels.iter().zip(&relaxed.pixels).filter(|(a, b)| a.status != b.status).count();
        assert!(differ * 200 < plain.pixels.len(), "{name}: {differ} pixels change status");
    }
}

/// f(p) / (r_px t) at each hit, by the f64 reference evaluator.
fn relative_field(f: &Formula, fr: &Frame, s: &Settings, only: Status) -> Vec<f64> {
    let cf = s.camera.frame().unwrap();
    let r_px = cf.tan_half_fov / s.height as f64;
    let mut v = Vec::new();
    for j in 0..s.height {
        for i in 0..s.width {
            let p = fr.pixels[(j * s.width + i) as usize];
            if p.status == only {
                let q = s.camera.eye + Camera::ray(&cf, i, j, s.width, s.height) * p.depth as f64;
                v.push(crate::reference::eval_scalar(&f.ir, [q.x, q.y, q.z, 0.0], &[]) / (r_px * p.depth as f64));
            }
        }
    }
    v
}

/// Technique 2: when the budget runs out, the best candidate (smallest
/// unbounding sphere in screen space) stays near a surface, while the last
/// point of a ray that grazed an edge has flown on into the air behind it
/// (Keinert Fig. 8). Compared on the pixels that exhaust a budget of 12
/// steps either way: how many end 8 or more half-pixels from any surface.
#[test]
fn screen_space_candidate_beats_the_last_point_on_an_exhausted_budget() {
    let (f, s, hd) = scene("city", 96, 64);
    let with = SphereOptions { max_steps: 12, ..options(&hd) };
    let without = SphereOptions { screen_space: false, ..with.clone() };
    let a = sphere(&f, &s, &with);
    let b = sphere(&f, &s, &without);
    let both: Vec<bool> = a.pixels.iter().zip(&b.pixels).map(|(p, q)| p.status == Status::Unresolved && q.status == Status::Unresolved).collect();
    let far = |fr: &Frame| {
        let mut only = fr.clone();
        for (p, keep) in only.pixels.iter_mut().zip(&both) {
            if !keep {
                p.status = Status::Miss;
            }
        }
        relative_field(&f, &only, &s, Status::Unresolved).iter().filter(|r| r.abs() >= 8.0).count()
    };
    let n = both.iter().filter(|b| **b).count();
    let (fa, fb) = (far(&a), far(&b));
    assert!(n > 50, "{n} pixels unconverged in both");
    assert!(fa * 4 < fb, "of {n} unconverged pixels, {fa} end far from a surface with the candidate, {fb} with the last point");
}

/// Technique 4: without it f(p) at the hits is scattered over [0, err(t)]
/// (where each ray happened to stop); the fixed-point iteration moves the
/// hits onto the level set f = err(t), so f / err is near 1 almost
/// everywhere (Keinert Fig. 9). At grazing angles it converges slowly
/// (rate 1 - cos θ), hence "almost".
#[test]
fn fixed_point_iteration_flattens_the_field_at_the_hits() {
    let (f, s, hd) = scene("creature", 96, 64);
    let level = |fp: u32| {
        let fr = sphere(&f, &s, &SphereOptions { fixpoint: fp, ..options(&hd) });
        let v = relative_field(&f, &fr, &s, Status::Hit);
        v.iter().filter(|r| (0.75..=1.25).contains(*r)).count() as f64 / v.len() as f64
    };
    let (off, on) = (level(0), level(3));
    assert!(off < 0.5 && on > 0.9, "hits with f/err in [0.75, 1.25]: {off:.2} without, {on:.2} with 3 iterations");
}

/// Techniques 3 and 5 on the glass jewel: with the dynamic offset the
/// refraction ray starts inside; a fixed small offset leaves it outside
/// (the hit point is up to half a pixel off the surface), so it stops at
/// once and the glass loses its colour. The convex bound changes the
/// picture except at a few facet edges, and saves steps.
#[test]
fn dynamic_epsilon_and_convex_bound_on_the_glass_jewel() {
    let (f, s, hd) = scene("jewel", 96, 64);
    let glass = SphereOptions { glass: true, ..options(&hd) };
    let bounded = sphere(&f, &s, &glass);
    let unbounded = sphere(&f, &s, &SphereOptions { bound: None, ..glass.clone() });
    let fixed = sphere(&f, &s, &SphereOptions { dynamic_eps: false, ..glass.clone() });
    let hit = |fr: &Frame| fr.pixels.iter().filter(|p| p.status == Status::Hit).count();
    let differ = |a: &Frame, b: &Frame, tol: f32| {
        a.pixels.iter().zip(&b.pixels).filter(|(p, q)| p.status == Status::Hit && (0..3).any(|c| (p.color[c] - q.color[c]).abs() > tol)).count()
    };
    assert!(hit(&bounded) > 800, "{} hits", hit(&bounded));
    // The exit point is found from the other side of the surface (within
    // eps_min); only where it lies on a facet edge does the exit normal, and
    // so the refracted colour, change: a few per cent of the pixels.
    assert!(differ(&bounded, &unbounded, 0.02) * 30 < hit(&bounded), "the bound changed {} of {} pixels", differ(&bounded, &unbounded, 0.02), hit(&bounded));
    assert!(bounded.stats.evals_hit_mean < 0.85 * unbounded.stats.evals_hit_mean, "{} vs {} steps per hit", bounded.stats.evals_hit_mean, unbounded.stats.evals_hit_mean);
    assert!(differ(&bounded, &fixed, 0.05) * 4 > hit(&bounded), "a fixed offset changed only {} of {} pixels", differ(&bounded, &fixed, 0.05), hit(&bounded));
}

/// A field scaled by 2 is 2-Lipschitz: `--lipschitz 2` gives exactly the
/// picture of the distance itself; without it the violation is reported.
#[test]
fn lipschitz_bound_divides_the_field() {
    let s = common::settings(common::cube(1.5), 48, 48);
    let exact = sphere(&Formula::compile("<t>", "sphere(1)").unwrap(), &s, &SphereOptions::default());
    let twice = Formula::compile("<t>", "2*sphere(1)").unwrap();
    let fixed = sphere(&twice, &s, &SphereOptions { lipschitz: 2.0, ..Default::default() });
    assert!(exact.pixels == fixed.pixels);
    assert_eq!(exact.stats.sphere.lipschitz_violations, 0);
    let wrong = sphere(&twice, &s, &SphereOptions::default());
    assert!(wrong.stats.sphere.lipschitz_violations > 100, "{:?}", wrong.stats);
    // A lower estimate of the true bound 2, from the samples the rays took.
    assert!(wrong.stats.sphere.lipschitz_seen > 1.5 && wrong.stats.sphere.lipschitz_seen < 2.01, "{}", wrong.stats.sphere.lipschitz_seen);
    let err = SphereOptions { lipschitz: 0.5, ..Default::default() }.check().unwrap_err();
    assert_eq!((err.field, err.value.as_str()), (crate::render::SettingsField::Lipschitz, "0.5"));
    assert!(err.reason.starts_with("a Lipschitz bound must be at least 1"), "{err}");
}

/// Bad input: formulas that are not distance bounds still terminate. A
/// field far below the distance runs out of steps (reported unconverged);
/// one far above it is caught changing faster than the distance.
#[test]
fn non_distance_formulas_terminate_and_are_reported() {
    let s = common::settings(common::cube(2.0), 48, 48);
    let slow = Formula::compile("<t>", "0.05*(x^2 + y^2 + z^2 - 1)").unwrap();
    let fr = sphere(&slow, &s, &SphereOptions { max_steps: 16, ..Default::default() });
    assert!(fr.stats.unresolved > 100, "{:?}", fr.stats);
    assert!(fr.stats.evals_max <= 16);
    let fast = Formula::compile("<t>", "sin(8*x)*sin(8*y)*sin(8*z) + 0.2").unwrap();
    let fr = sphere(&fast, &s, &SphereOptions::default());
    assert!(fr.stats.sphere.lipschitz_violations > 100 && fr.stats.sphere.lipschitz_seen > 2.0, "{:?}", fr.stats);
    assert!(fr.stats.evals_max <= SphereOptions::default().max_steps + 24);
}


/// Zanni et al.'s minimum step: steps never shrink below it, so a step can
/// land past the surface; the sign change is then bisected, so hits stay
/// on the surface (within eps / cos θ + eps of the analytic root, as without
/// it) while grazing rays need fewer steps.
#[test]
fn minimum_step_keeps_hits_exact() {
    let f = Formula::compile("<test>", "sphere(1)").unwrap();
    let s = common::settings(common::cube(1.5), 48, 48);
    let plain = sphere(&f, &s, &SphereOptions { screen_space: false, fixpoint: 0, ..Default::default() });
    let coarse = sphere(&f, &s, &SphereOptions { screen_space: false, fixpoint: 0, min_step: 0.05, ..Default::default() });
    assert_eq!(plain.stats.hits, coarse.stats.hits);
    assert!(coarse.stats.evals_max < plain.stats.evals_max, "{} vs {}", coarse.stats.evals_max, plain.stats.evals_max);
    let cf = s.camera.frame().unwrap();
    let o = s.camera.eye;
    for j in 0..s.height {
        for i in 0..s.width {
            let p = coarse.pixels[(j * s.width + i) as usize];
            let d = Camera::ray(&cf, i, j, s.width, s.height);
            let b = o.dot(d);
            let disc = b * b - (o.length_squared() - 1.0);
            if p.status != Status::Hit || disc < 0.0 {
                continue;
            }
            let t = -b - disc.sqrt();
            let cos = ((o + d * t).normalize().dot(d)).abs().max(0.17);
            assert!((p.depth as f64 - t).abs() <= s.eps / cos + s.eps, "({i},{j}): {} vs {t}", p.depth);
        }
    }
}

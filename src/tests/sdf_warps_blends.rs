//! The warps (`twist`, `bend`), the chamfer, round and sum blends and the
//! normalized `density` primitive, compiled, against the f64 definitions of
//! `crate::sdf` (the functions a blobtree scene evaluates) composed here
//! with primitives written out in this file; then the facts those
//! definitions promise (sharp outside the operator range, a fillet, the
//! density's surface radius), the argument checks, and one evaluation on
//! the device.

use super::common;

use crate::ir::Domain;
use crate::sdf;
use common::points;
use crate::Formula;

fn f(src: &str) -> Formula {
    Formula::compile("<test>", src).unwrap_or_else(|e| panic!("{src}: {e}"))
}

fn at(formula: &Formula, p: [f64; 3]) -> f64 {
    crate::reference::eval_scalar(&formula.ir, [p[0], p[1], p[2], 0.0], &[])
}

/// Within 1e-12, relative to the value (absolute below 1).
fn close(got: f64, want: f64) -> bool {
    (got - want).abs() <= 1e-12 * want.abs().max(1.0)
}


fn sphere(p: [f64; 3], r: f64) -> f64 {
    (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - r
}

/// The exact box distance, half extents `b`.
fn boxd(p: [f64; 3], b: [f64; 3]) -> f64 {
    let q = [p[0].abs() - b[0], p[1].abs() - b[1], p[2].abs() - b[2]];
    let o = [q[0].max(0.0), q[1].max(0.0), q[2].max(0.0)];
    (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt() + q[0].max(q[1].max(q[2])).min(0.0)
}

fn moved(p: [f64; 3], d: [f64; 3]) -> [f64; 3] {
    [p[0] - d[0], p[1] - d[1], p[2] - d[2]]
}

/// `src` compiled equals `want` at 200 random points of [-s, s]³.
#[track_caller]
fn same(src: &str, s: f64, want: impl Fn([f64; 3]) -> f64) {
    let g = f(src);
    for p in points(s, 200, src.len() as u64) {
        let (got, w) = (at(&g, p), want(p));
        assert!(close(got, w), "{src} at {p:?}: {got}, expected {w}");
    }
}

#[test]
fn warps_are_the_shape_at_the_warped_point() {
    for k in [0.8, -1.7, 3.0] {
        same(&format!("twist({k}, box(0.5, 0.3, 1))"), 1.5, |p| boxd(sdf::twist_point(k, p), [0.5, 0.3, 1.0]));
        same(&format!("bend({k}, box(1, 0.2, 0.3))"), 1.5, |p| boxd(sdf::bend_point(k, p), [1.0, 0.2, 0.3]));
    }
    // k may be any expression of constants, the shape any expression.
    let k = std::f64::consts::PI / 4.0;
    same("twist(pi/4, translate(0.5, 0, 0, sphere(0.3)))", 1.5, |p| sphere(moved(sdf::twist_point(k, p), [0.5, 0.0, 0.0]), 0.3));
    same("bend(2*0.5, x + y*z)", 1.5, |p| {
        let q = sdf::bend_point(1.0, p);
        q[0] + q[1] * q[2]
    });
    // Warps compose: the inner warp's point, warped again.
    same("twist(0.5, bend(0.7, box(1, 0.2, 0.3)))", 1.5, |p| boxd(sdf::bend_point(0.7, sdf::twist_point(0.5, p)), [1.0, 0.2, 0.3]));
}

/// k = 0 folds away: as many nodes as the shape alone, the same values.
#[test]
fn a_zero_warp_costs_nothing() {
    let shape = f("box(0.5, 0.3, 1)");
    for warp in ["twist", "bend"] {
        let g = f(&format!("{warp}(0, box(0.5, 0.3, 1))"));
        assert_eq!(g.ir.nodes.len(), shape.ir.nodes.len(), "{warp}: {:?}", g.ir.nodes);
        for p in points(1.5, 50, 1) {
            assert_eq!(at(&g, p), at(&shape, p), "{warp} at {p:?}");
        }
    }
}

/// Every blend of two shapes, against its f64 definition.
#[test]
fn blends_follow_their_definitions() {
    let a = |p: [f64; 3]| sphere(p, 1.0);
    let b = |p: [f64; 3]| boxd(moved(p, [1.2, 0.0, 0.0]), [0.5, 0.5, 0.5]);
    let cases: [(&str, fn(f64, f64, f64) -> f64); 9] = [
        ("chamfer_union", sdf::chamfer_union),
        ("chamfer_intersect", sdf::chamfer_intersect),
        ("chamfer_subtract", |a, b, r| sdf::chamfer_intersect(a, -b, r)),
        ("round_union", sdf::round_union),
        ("round_intersect", sdf::round_intersect),
        ("round_subtract", |a, b, r| sdf::round_intersect(a, -b, r)),
        ("sum_union", sdf::sum_union),
        // a and b swapped: the operand order does not matter to the value.
        ("chamfer_union", |a, b, r| sdf::chamfer_union(b, a, r)),
        ("round_union", |a, b, r| sdf::round_union(b, a, r)),
    ];
    for (name, def) in cases {
        for r in [0.3, 0.05, 1.5] {
            same(&format!("{name}(sphere(1), translate(1.2, 0, 0, box(0.5, 0.5, 0.5)), {r})"), 2.5, |p| def(a(p), b(p), r));
        }
    }
    // Blends of blends nest like the functions.
    same("round_union(chamfer_intersect(x, y, 0.2), z, 0.4)", 1.0, |p| sdf::round_union(sdf::chamfer_intersect(p[0], p[1], 0.2), p[2], 0.4));
}

/// Outside the operator range each blend is the sharp operator (compiled
/// operands, compiled blends); inside it, somewhere, it is not.
#[test]
fn blends_are_sharp_outside_their_ranges() {
    let (a, b) = ("sphere(1)", "translate(0.6, 0.2, 0, box(0.8, 0.9, 0.7))");
    let (fa, fb) = (f(a), f(b));
    let r = 0.2;
    let blend = |name: &str| f(&format!("{name}({a}, {b}, {r})"));
    let (cu, ci, cs) = (blend("chamfer_union"), blend("chamfer_intersect"), blend("chamfer_subtract"));
    let (ru, ri, rs, su) = (blend("round_union"), blend("round_intersect"), blend("round_subtract"), blend("sum_union"));
    let (co, ro) = (sdf::chamfer_range(r), r);
    // Per row: points outside the range, points inside where it blends.
    let mut counts = [[0usize; 2]; 7];
    for p in points(2.0, 4000, 7) {
        let (u, v) = (at(&fa, p), at(&fb, p));
        let rows: [(&Formula, f64, bool); 7] = [
            (&cu, u.min(v), u.max(v) >= co),
            (&ci, u.max(v), u.min(v) <= -co),
            (&cs, u.max(-v), u.min(-v) <= -co),
            (&ru, u.min(v), u.max(v) >= ro),
            (&ri, u.max(v), u.min(v) <= -ro),
            (&rs, u.max(-v), u.min(-v) <= -ro),
            (&su, u.min(v), u.max(v) >= ro),
        ];
        for (k, (g, sharp, outside)) in rows.into_iter().enumerate() {
            let got = at(g, p);
            if outside {
                assert!((got - sharp).abs() <= 1e-12 * (1.0 + sharp.abs()), "row {k} at {p:?}: {got} vs the sharp {sharp}");
                counts[k][0] += 1;
            } else if (got - sharp).abs() > 1e-6 {
                counts[k][1] += 1;
            }
        }
    }
    for (k, [outside, blended]) in counts.into_iter().enumerate() {
        assert!(outside > 50 && blended > 10, "row {k}: {outside} points outside the range, {blended} blended inside");
    }
}

/// Two unit spheres touching at the origin: the round union fills the
/// neck around the contact point (inside the surface where the union is
/// outside, within about r of it); the chamfer does too.
#[test]
fn a_round_union_of_touching_spheres_has_a_fillet() {
    let spheres = "translate(-1, 0, 0, sphere(1)), translate(1, 0, 0, sphere(1))";
    let (sharp, round, chamfer) = (f(&format!("union({spheres})")), f(&format!("round_union({spheres}, 0.3)")), f(&format!("chamfer_union({spheres}, 0.3)")));
    for k in 0..24 {
        let angle = k as f64 * std::f64::consts::TAU / 24.0;
        for (x, rho) in [(0.0, 0.05), (0.0, 0.2), (0.0, 0.3), (0.02, 0.25), (-0.02, 0.25)] {
            let p = [x, rho * angle.cos(), rho * angle.sin()];
            let m = at(&sharp, p);
            let (g, c) = (at(&round, p), at(&chamfer, p));
            assert!(m > 0.0, "at {p:?}: {m}: not in the gap");
            assert!(g < 0.0 && c < 0.0, "at {p:?}: the gap {m} is not filled (round {g}, chamfer {c})");
        }
    }
    // Where both spheres are r or more away the fillet does not reach.
    for p in [[-2.5, 0.0, 0.0], [1.0, 1.5, 0.0], [3.0, 0.5, 0.5], [0.0, 2.0, 0.0]] {
        assert_eq!(at(&round, p), at(&sharp, p), "{p:?}");
    }
}

/// d, the distance to the segment (0, 0, −h)–(0, 0, h), as the form
/// defines it.
fn skeleton(p: [f64; 3], h: f64) -> f64 {
    let w = p[2] - p[2].max(-h).min(h);
    (p[0] * p[0] + p[1] * p[1] + w * w).sqrt()
}

#[test]
fn density_follows_its_definition() {
    for (r, h, c) in [(1.0, 0.0, 0.5), (1.2, 0.5, 0.4), (0.7, 1.0, 0.9)] {
        let t = sdf::density_default_range(r, c);
        same(&format!("density({r}, {h}, {c})"), 2.5, |p| sdf::density(skeleton(p, h), r, c, t));
        same(&format!("density({r}, {h}, {c}, 0.25)"), 2.5, |p| sdf::density(skeleton(p, h), r, c, 0.25));
    }
    // Densities with the same T summed: the density blend, T(1 − ΣK/c).
    same("sum_union(density(1, 0, 0.5, 0.3), translate(0.8, 0, 0, density(1, 0.3, 0.5, 0.3)), 0.3)", 2.5, |p| {
        let (a, b) = (sdf::density(skeleton(p, 0.0), 1.0, 0.5, 0.3), sdf::density(skeleton(moved(p, [0.8, 0.0, 0.0]), 0.3), 1.0, 0.5, 0.3));
        sdf::sum_union(a, b, 0.3)
    });
    // A point skeleton folds to |p|: no clamp is built.
    assert!(!f("density(1, 0, 0.5)").ir.nodes.iter().any(|op| matches!(op, crate::ir::Op::Call3(..))));
    // T is required only when the default cannot be computed.
    f("density(t, 0, 0.5, 0.3)");
}

/// density(1, 0, 0.5) is ≤ 0 exactly within R·√(1 − c^(1/3)) of the
/// skeleton, > 0 beyond, and 1-Lipschitz at the default T.
#[test]
fn density_has_its_surface_at_the_kernels_isovalue() {
    let g = f("density(1, 0, 0.5)");
    let surface = (1.0 - 0.5f64.powf(1.0 / 3.0)).sqrt();
    let (mut inside, mut outside) = (0, 0);
    for p in points(1.5, 4000, 3) {
        let (rho, v) = (sphere(p, 0.0), at(&g, p));
        if rho < surface * (1.0 - 1e-9) {
            assert!(v <= 0.0, "{p:?} (|p| = {rho}): {v}");
            inside += 1;
        } else if rho > surface * (1.0 + 1e-9) {
            assert!(v > 0.0, "{p:?} (|p| = {rho}): {v}");
            outside += 1;
        }
    }
    assert!(inside > 50 && outside > 1000, "{inside} inside, {outside} outside");
    let mut worst: f64 = 0.0;
    for k in 0..4000 {
        let x = k as f64 * 2.0 / 4000.0;
        let d = (at(&g, [x + 1e-6, 0.0, 0.0]) - at(&g, [x, 0.0, 0.0])).abs() / 1e-6;
        worst = worst.max(d);
    }
    assert!(worst <= 1.0 + 1e-5 && worst > 0.99, "{worst}");
}

fn diag(src: &str) -> String {
    Formula::compile("<formula>", src).expect_err("expected an error").diagnostic.render("<formula>", src, false)
}

#[test]
fn bad_arguments_point_at_the_argument() {
    assert_eq!(
        diag("chamfer_union(x, y, 0)"),
        "error: invalid argument to 'chamfer_union': the chamfer width r must be positive, got 0\n  ┌─ <formula>:1:21\n  │\n1 │ chamfer_union(x, y, 0)\n  │                     ^ this argument\n  │\n  = usage: chamfer_union(a, b, r)\n\n"
    );
    assert_eq!(
        diag("density(1, 0, 1.5)"),
        "error: invalid argument to 'density': the isovalue c must be between 0 and 1 (exclusive), got 1.5\n  ┌─ <formula>:1:15\n  │\n1 │ density(1, 0, 1.5)\n  │               ^^^ this argument\n  │\n  = usage: density(R, h, c[, T])\n\n"
    );
    // No T and no default: the error is at the call.
    assert_eq!(
        diag("density(t, 0, 0.5)"),
        "error: invalid argument to 'density': the range T is needed when R or c is not a constant (the default c·R/1.7173 needs both)\n  ┌─ <formula>:1:1\n  │\n1 │ density(t, 0, 0.5)\n  │ ^^^^^^^^^^^^^^^^^^ this argument\n  │\n  = usage: density(R, h, c[, T])\n\n"
    );
    let first = |src: &str| diag(src).lines().next().unwrap().to_string();
    let cases = [
        ("chamfer_intersect(x, y, -1)", "'chamfer_intersect': the chamfer width r must be positive, got -1"),
        ("chamfer_subtract(x, y, 0)", "'chamfer_subtract': the chamfer width r must be positive, got 0"),
        ("round_union(x, y, 0)", "'round_union': the fillet radius r must be positive, got 0"),
        ("round_intersect(x, y, -0.5)", "'round_intersect': the fillet radius r must be positive, got -0.5"),
        ("round_subtract(x, y, 0)", "'round_subtract': the fillet radius r must be positive, got 0"),
        ("sum_union(x, y, 0)", "'sum_union': the range T must be positive, got 0"),
        ("density(0, 0, 0.5)", "'density': the support radius R must be positive, got 0"),
        ("density(1, -1, 0.5)", "'density': the half length h must not be negative, got -1"),
        ("density(1, 0, 0)", "'density': the isovalue c must be between 0 and 1 (exclusive), got 0"),
        ("density(1, 0, 1)", "'density': the isovalue c must be between 0 and 1 (exclusive), got 1"),
        ("density(1, 0, 0.5, 0)", "'density': the range T must be positive, got 0"),
    ];
    for (src, message) in cases {
        assert_eq!(first(src), format!("error: invalid argument to {message}"), "{src}");
    }
    assert_eq!(first("twist(1)"), "error: wrong number of arguments to 'twist': expected 2, found 1");
    assert_eq!(first("density(1, 0)"), "error: wrong number of arguments to 'density': expected 3 or 4, found 2");
    // The column of a bad argument: the 3rd argument of round_union.
    assert!(diag("round_union(sphere(1), x, 0)").contains("<formula>:1:27\n"));
    // Non-constant arguments are not checked; a zero or negative k is a warp.
    for src in ["chamfer_union(x, y, t)", "round_subtract(x, y, t)", "sum_union(x, y, t)", "twist(-2, x)", "bend(t, x)", "density(1, t, 0.5)"] {
        f(src);
    }
}

/// A formula with a twist and a chamfer on the device (the generated
/// scalar and interval evaluators of the normal compiled path) agrees with
/// the CPU's f64 within f32 rounding, and its intervals enclose it.
#[test]
fn twist_and_chamfer_on_the_device_match_the_cpu() {
    let gpu = crate::gpu::Gpu::new().unwrap_or_else(|e| panic!("this test needs a GPU or lavapipe: {e}"));
    let g = f("chamfer_union(twist(0.8, box(0.5, 0.3, 1)), translate(0.6, 0, 0.4, sphere(0.4)), 0.2)");
    let pts = points(1.5, 500, 11);
    // f32 coordinates, and the CPU evaluated at those very coordinates.
    let p32: Vec<[f32; 3]> = pts.iter().map(|p| [p[0] as f32, p[1] as f32, p[2] as f32]).collect();
    let cpu: Vec<f64> = p32.iter().map(|p| at(&g, [p[0] as f64, p[1] as f64, p[2] as f64])).collect();
    let boxes: Vec<[f32; 8]> = p32.iter().map(|p| [p[0], p[0], p[1], p[1], p[2], p[2], 0.0, 0.0]).collect();
    let scalar = crate::gpu::eval::eval_boxes(&gpu, &g.ir, Domain::Scalar, &boxes, &[]).unwrap();
    for ((p, want), got) in p32.iter().zip(&cpu).zip(&scalar) {
        assert!((got[0] as f64 - want).abs() <= 2e-6 * (1.0 + want.abs()), "at {p:?}: device {}, cpu {want}", got[0]);
    }
    let h = 0.01f32;
    let small: Vec<[f32; 8]> = p32.iter().map(|p| [p[0] - h, p[0] + h, p[1] - h, p[1] + h, p[2] - h, p[2] + h, 0.0, 0.0]).collect();
    let ranges = crate::gpu::eval::eval_boxes(&gpu, &g.ir, Domain::Interval, &small, &[]).unwrap();
    for ((p, want), r) in p32.iter().zip(&cpu).zip(&ranges) {
        let slack = 1e-5 * (1.0 + want.abs());
        assert!(r[0] as f64 <= want + slack && *want <= r[1] as f64 + slack, "at {p:?}: {want} not in {r:?}");
        assert!(r[1] - r[0] < 0.2, "at {p:?}: {r:?} is too wide for a box of side {}", 2.0 * h);
    }
}

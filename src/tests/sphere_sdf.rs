//! The distance-field language on the CPU: every primitive against its
//! analytic distance, transforms and operators against their definitions,
//! the Lipschitz bound of the example scenes by sampling, the diagnostics of
//! bad arguments, and naga validation of every kernel for an SDF formula.

use crate::ir::Domain;
use crate::validate::validate;
use crate::Formula;

use super::sdf_common::{at, check, f};

#[test]
fn primitives_are_exact_distances() {
    let r2 = 2f64.sqrt();
    check("sphere(1)", &[([2.0, 0.0, 0.0], 1.0), ([0.0, 0.0, 0.0], -1.0), ([0.0, 0.6, 0.8], 0.0)]);
    check("box(1, 0.5, 0.25)", &[([2.0, 0.0, 0.0], 1.0), ([0.0; 3], -0.25), ([2.0, 1.5, 0.0], r2), ([0.9, 0.0, 0.0], -0.1)]);
    check("roundbox(1, 0.5, 0.25, 0.1)", &[([2.0, 0.0, 0.0], 1.0), ([0.0; 3], -0.25), ([1.9, 1.4, 0.0], r2 - 0.1)]);
    check("torus(1, 0.25)", &[([1.0, 0.0, 0.0], -0.25), ([0.0, 0.0, 0.0], 0.75), ([0.0, 2.0, 0.0], 0.75), ([1.0, 0.0, 1.0], 0.75)]);
    check("cylinder(0.5, 1)", &[([1.5, 0.0, 0.0], 1.0), ([0.0, 0.0, 3.0], 2.0), ([0.0; 3], -0.5), ([1.5, 0.0, 2.0], r2)]);
    check("capsule(0, 0, 0, 0, 0, 2, 0.5)", &[([1.0, 0.0, 1.0], 0.5), ([0.0, 0.0, -1.0], 0.5), ([0.0, 0.0, 3.0], 0.5), ([0.0, 0.0, 1.0], -0.5)]);
    check("capsule(1, 1, 1, 1, 1, 1, 0.5)", &[([1.0, 1.0, 2.0], 0.5)]);
    check("plane(0, 0, 2, 0.5)", &[([7.0, -3.0, 1.5], 1.0), ([0.0, 0.0, 0.0], -0.5)]);
    check("plane(1, 1, 0, 0)", &[([1.0, 1.0, 5.0], r2)]);
    // The octahedron is a bound: exact on the faces' normals, below the distance elsewhere.
    let s3 = 3f64.sqrt();
    check("octahedron(1)", &[([1.0, 1.0, 1.0], 2.0 / s3), ([0.0; 3], -1.0 / s3)]);
    let oct = f("octahedron(1)");
    assert!(at(&oct, [2.0, 0.0, 0.0]) <= 1.0);
}

#[test]
fn transforms_move_rotate_and_scale_shapes_by_substitution() {
    check("translate(1, 2, 3, sphere(0.5))", &[([1.0, 2.0, 3.0], -0.5), ([1.0, 2.0, 4.0], 0.5)]);
    // A quarter turn about z maps the box's long x axis onto y.
    check("rotate(0, 0, 1, pi/2, box(1, 0.5, 0.2))", &[([0.0, 1.5, 0.0], 0.5), ([1.5, 0.0, 0.0], 1.0)]);
    check("rotate(0, 0, 2, pi/2, translate(1, 0, 0, sphere(0.25)))", &[([0.0, 1.0, 0.0], -0.25)]);
    // About an oblique axis: a point on the axis does not move; a third of a
    // turn about (1,1,1) permutes the coordinates.
    check("rotate(1, 1, 1, 2*pi/3, translate(1, 0, 0, sphere(0.25)))", &[([0.0, 1.0, 0.0], -0.25)]);
    check("scale(2, sphere(1))", &[([3.0, 0.0, 0.0], 1.0), ([0.0; 3], -2.0)]);
    check("scale(0.5, box(1, 1, 1))", &[([1.5, 0.0, 0.0], 1.0)]);
    // Definitions and arbitrary expressions are transformed too.
    check("a = sphere(1); union(a, translate(3, 0, 0, a))", &[([3.0, 0.0, 0.0], -1.0), ([1.5, 0.0, 0.0], 0.5)]);
    check("translate(0, 0, 1, z)", &[([5.0, 5.0, 1.0], 0.0), ([0.0, 0.0, 3.0], 2.0)]);
    // t is not a coordinate.
    check("translate(1, 1, 1, x + t)", &[([2.0, 0.0, 0.0], 1.0)]);
}

#[test]
fn quarter_turns_cost_no_arithmetic() {
    let plain = f("box(1, 0.5, 0.2)").ir.live().len();
    let turned = f("rotate(0, 0, 1, pi/2, box(1, 0.5, 0.2))").ir.live().len();
    assert!(turned <= plain + 1, "{turned} vs {plain} operations");
    assert_eq!(f("translate(0, 0, 0, sphere(1))").ir.live().len(), f("sphere(1)").ir.live().len());
}

#[test]
fn operators_follow_their_definitions() {
    let a = |p: [f64; 3]| ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()) - 1.0;
    let b = |p: [f64; 3]| (((p[0] - 1.2).powi(2) + p[1] * p[1] + p[2] * p[2]).sqrt()) - 0.5;
    let d = |u: f64, v: f64, k: f64| k / 6.0 * (1.0 - (u - v).abs() / k).max(0.0).powi(3);
    let pa = "sphere(1)";
    let pb = "translate(1.2, 0, 0, sphere(0.5))";
    let pts = [[0.9, 0.1, 0.0], [1.1, 0.3, 0.2], [0.0, 0.0, 0.0], [2.0, 1.0, 0.0], [1.0, 0.0, 0.0]];
    for p in pts {
        let (u, v) = (a(p), b(p));
        check(&format!("union({pa}, {pb})"), &[(p, u.min(v))]);
        check(&format!("intersect({pa}, {pb})"), &[(p, u.max(v))]);
        check(&format!("subtract({pa}, {pb})"), &[(p, u.max(-v))]);
        check(&format!("smooth_union({pa}, {pb}, 0.3)"), &[(p, u.min(v) - d(u, v, 0.3))]);
        check(&format!("smooth_intersect({pa}, {pb}, 0.3)"), &[(p, u.max(v) + d(u, v, 0.3))]);
        check(&format!("smooth_subtract({pa}, {pb}, 0.3)"), &[(p, u.max(-v) + d(u, -v, 0.3))]);
    }
    check("union(x, y, z)", &[([1.0, -2.0, 3.0], -2.0)]);
    check("subtract(x, y, z)", &[([1.0, -2.0, 3.0], 2.0)]);
}

/// A deterministic point cloud in a box.
fn points(b: [f64; 6], n: usize) -> Vec<[f64; 3]> {
    let mut s = 0x9e3779b97f4a7c15u64;
    let mut r = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n).map(|_| [b[0] + (b[1] - b[0]) * r(), b[2] + (b[3] - b[2]) * r(), b[4] + (b[5] - b[4]) * r()]).collect()
}

/// The largest |f(p) - f(q)| / |p - q| of `src` on random pairs in the box
/// `b`, far apart and 1e-3 of that apart.
fn lipschitz_ratio(src: &str, b: [f64; 6]) -> f64 {
    let g = f(src);
    let pts = points(b, 1500);
    let mut worst: f64 = 0.0;
    for w in pts.windows(2) {
        for (p, q) in [(w[0], w[1]), (w[0], [w[0][0] + 1e-3 * (w[1][0] - w[0][0]), w[0][1] + 1e-3 * (w[1][1] - w[0][1]), w[0][2] + 1e-3 * (w[1][2] - w[0][2])])] {
            let dist = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
            worst = worst.max((at(&g, p) - at(&g, q)).abs() / dist);
        }
    }
    worst
}

/// The scenes are 1-Lipschitz, so sphere tracing's step |f(p)| never
/// passes the surface: |f(p) - f(q)| <= |p - q| on random pairs, near and far.
#[test]
fn scenes_and_smooth_operators_are_1_lipschitz() {
    let mut cases: Vec<(String, [f64; 6])> = crate::catalog::suite("sdf")
        .unwrap()
        .into_iter()
        .map(|n| {
            let e = crate::catalog::lookup(n).unwrap();
            (e.formula, e.header.bbox)
        })
        .collect();
    cases.push(("smooth_subtract(smooth_union(box(1,0.4,0.4), torus(0.8,0.3), 0.5), rotate(1,2,3,0.7,cylinder(0.3,2)), 0.2)".into(), [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0]));
    cases.push(("scale(0.7, smooth_intersect(octahedron(1), roundbox(0.7,0.7,0.7,0.2), 0.4))".into(), [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0]));
    for (src, b) in cases {
        let worst = lipschitz_ratio(&src, b);
        assert!(worst <= 1.0 + 1e-6, "{}: Lipschitz ratio {worst}", &src[..src.len().min(60)]);
    }
}

/// Formulas with every profile, extrude, revolve and modifier (the ones
/// the kernels are validated for too).
const PROFILE_SCENES: [&str; 6] = [
    "extrude(0.3, polygon(-1, -1, 1, -1, 0.2, 0, 1, 1, -1, 1))",
    "union(circle(0.5), rect(1, 0.2), roundrect(0.3, 1.2, 0.1), capsule2d(-1, 0.5, 1, 1, 0.2))",
    "shell(0.1, union(extrude(0.5, capsule2d(-1, 0, 1, 0.5, 0.3)), revolve(0.5, circle(0.2)), revolve(1, roundrect(0.3, 0.5, 0.1))))",
    "offset(0.2, infill(0.5, 0.05, box(1, 1, 1)))",
    "smooth_union(extrude(0.2, rect(1, 0.5)), rotate(1, 0, 0, pi/2, extrude(0.4, polygon(0, 0, 1, 0, 0, 1))), 0.3)",
    "revolve(0.8, polygon(0, 0.6, 0.6, 0, 0.2, 0, 0.2, -0.4, -0.2, -0.4, -0.2, 0, -0.6, 0))",
];

/// Profiles are exact 2D distances and extrude, revolve, offset, shell and
/// infill keep the bound: still 1.
#[test]
fn profiles_extrusions_and_modifiers_are_1_lipschitz() {
    for src in PROFILE_SCENES {
        let worst = lipschitz_ratio(src, [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0]);
        assert!(worst <= 1.0 + 1e-6, "{src}: Lipschitz ratio {worst}");
        assert!(worst > 0.9, "{src}: Lipschitz ratio {worst}, is it a distance?");
    }
}

/// `displace(a, f, s)` is s + a·n with |∇n| <= 1.92 f: the bound its
/// documentation tells users to pass with --lipschitz.
#[test]
fn displace_raises_the_bound_by_its_noise_gradient() {
    for (a, freq) in [(0.1, 3.0), (0.05, 10.0)] {
        let src = format!("displace({a}, {freq}, torus(1, 0.3))");
        let worst = lipschitz_ratio(&src, [-2.0, 2.0, -2.0, 2.0, -1.0, 1.0]);
        let bound = 1.0 + crate::sdf::NOISE_GRADIENT * a * freq;
        assert!(worst <= bound, "{src}: Lipschitz ratio {worst} above {bound}");
        assert!(worst > 1.0 + 0.3 * (bound - 1.0), "{src}: Lipschitz ratio {worst}: does the noise displace?");
    }
}

fn diag(src: &str) -> String {
    Formula::compile("<formula>", src).expect_err("expected an error").diagnostic.render("<formula>", src, false)
}

#[test]
fn bad_arguments_point_at_the_argument() {
    assert_eq!(
        diag("scale(-1, sphere(1))"),
        "error: invalid argument to 'scale': the scale factor must be positive, got -1\n  ┌─ <formula>:1:7\n  │\n1 │ scale(-1, sphere(1))\n  │       ^^ this argument\n  │\n  = usage: scale(s, shape)\n\n"
    );
    assert_eq!(
        diag("smooth_union(x, y, 0)"),
        "error: invalid argument to 'smooth_union': the blend range k must be positive, got 0\n  ┌─ <formula>:1:20\n  │\n1 │ smooth_union(x, y, 0)\n  │                    ^ this argument\n  │\n  = usage: smooth_union(a, b, k)\n\n"
    );
    assert!(diag("plane(0, 0, 0, 1)").starts_with("error: invalid argument to 'plane': the plane's normal (nx, ny, nz) must not be zero\n"));
    assert!(diag("rotate(0, 0, 0, 1, x)").starts_with("error: invalid argument to 'rotate': the rotation axis (ax, ay, az) must not be zero\n"));
    assert!(diag("box(1, 2)").starts_with("error: wrong number of arguments to 'box': expected 3, found 2\n"));
    assert!(diag("union(x)").starts_with("error: wrong number of arguments to 'union': expected 2 or more, found 1\n"));
    assert!(diag("spher(1)").contains("= did you mean 'sphere'?"));
    assert!(diag("box = 1; box").starts_with("error: cannot define 'box': the name is reserved\n"));
    assert!(diag("sphere + 1").starts_with("error: function 'sphere' used without arguments\n"));
}

#[test]
fn profiles_and_modifiers_report_bad_arguments() {
    assert_eq!(
        diag("polygon(0, 0, 1, 0, 0, 1, 2)"),
        "error: wrong number of arguments to 'polygon': expected an even number from 6 to 32 (3 to 16 vertices), found 7\n  ┌─ <formula>:1:1\n  │\n1 │ polygon(0, 0, 1, 0, 0, 1, 2)\n  │ ^^^^^^^^^^^^^^^^^^^^^^^^^^^^ 7 arguments\n\n"
    );
    assert_eq!(
        diag("circle(0)"),
        "error: invalid argument to 'circle': the radius r must be positive, got 0\n  ┌─ <formula>:1:8\n  │\n1 │ circle(0)\n  │        ^ this argument\n  │\n  = usage: circle(r)\n\n"
    );
    assert_eq!(
        diag("extrude(-1, circle(1))"),
        "error: invalid argument to 'extrude': the half height h must be positive, got -1\n  ┌─ <formula>:1:9\n  │\n1 │ extrude(-1, circle(1))\n  │         ^^ this argument\n  │\n  = usage: extrude(h, shape)\n\n"
    );
    let first = |src: &str| diag(src).lines().next().unwrap().to_string();
    let polygon_count = "error: wrong number of arguments to 'polygon': expected an even number from 6 to 32 (3 to 16 vertices), found";
    assert_eq!(first("polygon(0, 0, 1, 0)"), format!("{polygon_count} 4"));
    assert_eq!(first(&format!("polygon({})", ["0, 0"; 17].join(", "))), format!("{polygon_count} 34"));
    let cases = [
        ("revolve(-1, circle(1))", "'revolve': the distance R from the axis must not be negative, got -1"),
        ("shell(0, sphere(1))", "'shell': the wall thickness t must be positive, got 0"),
        ("infill(0, 0.1, sphere(1))", "'infill': the period must be positive, got 0"),
        ("infill(1, -0.1, sphere(1))", "'infill': the sheet thickness must be positive, got -0.1"),
        ("displace(1, 0, sphere(1))", "'displace': the frequency f must be positive, got 0"),
        ("displace(-0.5, 1, sphere(1))", "'displace': the amplitude a must not be negative, got -0.5"),
    ];
    for (src, message) in cases {
        assert_eq!(first(src), format!("error: invalid argument to {message}"));
    }
    // Non-constant arguments are not checked; 16 vertices are allowed.
    f("circle(t)");
    f(&format!("polygon({})", (0..16).map(|k| format!("cos({k}*pi/8), sin({k}*pi/8)")).collect::<Vec<_>>().join(", ")));
}

/// Distance fields are ordinary formulas: every evaluator and kernel
/// (interval, affine, scalar; bisection and sphere tracing) validates.
#[test]
fn every_kernel_validates_for_the_scenes() {
    let catalog = crate::catalog::suite("sdf").unwrap().into_iter().map(|n| (n.to_string(), crate::catalog::lookup(n).unwrap().compile().unwrap().ir));
    let profiles = PROFILE_SCENES.iter().chain(&["displace(0.05, 4, revolve(1, rect(0.2, 0.4)))"]).map(|s| (s.to_string(), f(s).ir));
    for (name, ir) in catalog.chain(profiles) {
        let name = &name[..name.len().min(40)];
        for d in [Domain::Scalar, Domain::Interval, Domain::Affine] {
            validate(&crate::field::compiled::eval_shader(&ir, d)).unwrap_or_else(|e| panic!("{name} {d:?}: {e}"));
        }
        validate(&crate::kernel::render_shader(&ir, Domain::Interval)).unwrap_or_else(|e| panic!("{name} bisect: {e}"));
        for (shadows, glass) in [(false, false), (true, false), (false, true), (true, true)] {
            let wgsl = crate::kernel::sphere_shader(&ir, crate::render::SphereFeatures { shadows, glass, synchronized: false });
            validate(&wgsl).unwrap_or_else(|e| panic!("{name} sphere (shadows {shadows}, glass {glass}): {e}"));
            // The traversal only sees the scalar evaluator; unused rays are not compiled.
            assert!(wgsl.contains("fn eval_s(") && !wgsl.contains("fn eval_ia(") && !wgsl.contains("fn eval_ra("));
            assert_eq!(wgsl.contains("fn glass("), glass);
            assert_eq!(wgsl.matches("march(").count(), 2 + usize::from(shadows), "{name}: march definition and call sites");
            assert_eq!(wgsl.matches("trace(").count(), 2 + usize::from(glass), "{name}: trace definition and call sites");
            assert!(!wgsl.lines().any(|l| l.trim().starts_with("//!")), "{name}: a section marker is left");
        }
    }
}

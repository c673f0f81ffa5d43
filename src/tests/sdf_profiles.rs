//! The 2D profiles, `extrude`, `revolve` and the modifiers on the CPU,
//! each against facts computed here independently of `src/sdf`: hand-picked
//! distances, the 3D primitives they must reproduce (an extruded circle is
//! a capped cylinder), a brute-force distance and a winding-number inside
//! test for polygons, and the definitions of the gyroid sheet and noise
//! written out from their specification. The bounds by sampling, the
//! diagnostics and the kernels are in `src/tests/sphere_sdf.rs`.

use super::common;

use common::points;

use super::sdf_common::{at, check, close, f};

/// `a` and `b` agree within `tol` at random points of [-s, s]³.
#[track_caller]
fn same_field(a: &str, b: &str, s: f64, tol: f64) {
    let (fa, fb) = (f(a), f(b));
    for p in points(s, 2000, a.len() as u64) {
        let (u, v) = (at(&fa, p), at(&fb, p));
        assert!((u - v).abs() <= tol, "{a} vs {b} at {p:?}: {u} vs {v}");
    }
}

#[test]
fn profiles_are_exact_2d_distances_independent_of_z() {
    let r2 = 2f64.sqrt();
    check("circle(1)", &[([2.0, 0.0, 5.0], 1.0), ([0.0, 0.0, -3.0], -1.0), ([0.6, 0.8, 7.0], 0.0)]);
    check("rect(1, 0.5)", &[([2.0, 0.0, 0.0], 1.0), ([0.0, 0.0, 9.0], -0.5), ([2.0, 1.5, -4.0], r2), ([0.9, 0.0, 0.0], -0.1), ([-1.0, 0.2, 0.0], 0.0)]);
    // Inner rectangle (0.75, 0.25): the outer corner region is a quarter circle.
    check("roundrect(1, 0.5, 0.25)", &[([2.0, 0.0, 0.0], 1.0), ([0.0, 0.0, 1.0], -0.5), ([1.75, 1.25, 0.0], r2 - 0.25), ([0.0, -0.5, 0.0], 0.0)]);
    check("capsule2d(0, 0, 2, 0, 0.5)", &[([1.0, 1.0, 9.0], 0.5), ([-1.0, 0.0, 0.0], 0.5), ([3.0, 0.0, 0.0], 0.5), ([1.0, 0.0, 0.0], -0.5), ([2.0, 3.0, 0.0], 2.5)]);
    // a = b: a disc around a.
    check("capsule2d(1, 1, 1, 1, 0.5)", &[([1.0, 2.0, 3.0], 0.5), ([1.0, 1.0, 0.0], -0.5)]);
    // The right triangle (0,0), (2,0), (0,2): edges x = 0, y = 0, x + y = 2.
    let tri = "polygon(0, 0, 2, 0, 0, 2)";
    check(tri, &[([-1.0, 0.5, 0.0], 1.0), ([0.5, 0.5, 4.0], -0.5), ([2.0, 1.9, 0.0], 1.9 / r2), ([3.0, -1.0, 0.0], r2), ([0.4, 1.0, 0.0], -0.4)]);
    check(tri, &[([2.0, 0.0, 0.0], 0.0), ([1.0, 1.0, 0.0], 0.0), ([0.0, 0.7, 0.0], 0.0)]);
    // A repeated vertex adds a zero-length edge and changes nothing.
    same_field("polygon(0, 0, 2, 0, 2, 0, 0, 2)", tri, 3.0, 1e-12);
}

/// The guards of a segment whose ends are not constants: at t = 0 the
/// segment from (0, 0) to (t, 0) is a point, and the field stays finite.
#[test]
fn a_segment_of_variable_length_may_collapse() {
    let g = f("capsule2d(0, 0, t, 0, 0.5)");
    let v = |p: [f64; 3], t: f64| crate::reference::eval_scalar(&g.ir, [p[0], p[1], p[2], t], &[]);
    assert!(close(v([0.0, 1.0, 0.0], 0.0), 0.5));
    assert!(close(v([3.0, 0.0, 0.0], 0.0), 2.5));
    assert!(close(v([3.0, 0.0, 0.0], 2.0), 0.5));
}

#[test]
fn a_square_polygon_is_a_rect_in_either_orientation() {
    let ccw = "polygon(-0.5, -0.5, 0.5, -0.5, 0.5, 0.5, -0.5, 0.5)";
    let cw = "polygon(-0.5, -0.5, -0.5, 0.5, 0.5, 0.5, 0.5, -0.5)";
    same_field(ccw, "rect(0.5, 0.5)", 2.0, 1e-12);
    same_field(cw, "rect(0.5, 0.5)", 2.0, 1e-12);
    // Points inside, not only around it.
    same_field(ccw, "rect(0.5, 0.5)", 0.6, 1e-12);
}

/// Inside by the winding number (an angle sum, not a crossing count).
fn inside(v: &[[f64; 2]], p: [f64; 3]) -> bool {
    let mut turn = 0.0;
    for i in 0..v.len() {
        let (a, b) = (v[i], v[(i + 1) % v.len()]);
        let (ax, ay, bx, by) = (a[0] - p[0], a[1] - p[1], b[0] - p[0], b[1] - p[1]);
        turn += (ax * by - ay * bx).atan2(ax * bx + ay * by);
    }
    turn.abs() > std::f64::consts::PI
}

/// The least distance from p to the polygon's edges, by projection.
fn distance(v: &[[f64; 2]], p: [f64; 3]) -> f64 {
    let mut best = f64::INFINITY;
    for i in 0..v.len() {
        let (a, b) = (v[i], v[(i + 1) % v.len()]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
        let (qx, qy) = (a[0] + t * dx, a[1] + t * dy);
        best = best.min(((p[0] - qx).powi(2) + (p[1] - qy).powi(2)).sqrt());
    }
    best
}

fn polygon_src(v: &[[f64; 2]]) -> String {
    let coords: Vec<String> = v.iter().flat_map(|c| [c[0].to_string(), c[1].to_string()]).collect();
    format!("polygon({})", coords.join(", "))
}

#[test]
fn polygons_match_a_brute_force_distance_and_winding_number() {
    let star: Vec<[f64; 2]> = (0..10)
        .map(|k| {
            let (r, a) = (if k % 2 == 0 { 1.0 } else { 0.4 }, std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::PI / 5.0);
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    let shapes: Vec<Vec<[f64; 2]>> = vec![
        vec![[-1.0, -0.5], [1.2, -0.3], [0.1, 1.1]],
        vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]],
        star,
        // Clockwise and with 16 vertices, the most a polygon takes.
        (0..16).map(|k| { let a = -(k as f64) * std::f64::consts::TAU / 16.0; let r = if k % 2 == 0 { 1.5 } else { 1.0 }; [r * a.cos(), r * a.sin()] }).collect(),
    ];
    for v in shapes {
        let src = polygon_src(&v);
        let g = f(&src);
        let (mut ins, mut outs) = (0, 0);
        for p in points(2.5, 3000, v.len() as u64) {
            let (got, d) = (at(&g, p), distance(&v, p));
            let want = if inside(&v, p) { -d } else { d };
            assert!((got - want).abs() <= 1e-12, "{src} at {p:?}: {got}, expected {want}");
            if want < 0.0 { ins += 1 } else { outs += 1 }
        }
        assert!(ins > 100 && outs > 100, "{src}: {ins} points inside, {outs} outside");
    }
}

/// On the lines y = a vertex's y, where a step of the sign is at ½, the
/// value is the exact one scaled by a factor in [0, 1]: never of the wrong
/// sign and never beyond the distance. The L-shape has horizontal edges.
#[test]
fn polygons_on_a_vertex_height_stay_within_the_distance() {
    let shapes: [&[[f64; 2]]; 2] = [
        &[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]],
        &[[-1.0, -0.5], [1.2, -0.3], [0.1, 1.1], [0.3, -0.3]],
    ];
    for v in shapes {
        let g = f(&polygon_src(v));
        let mut exact = 0;
        for (k, mut p) in points(2.5, 600, 5).into_iter().enumerate() {
            p[1] = v[k % v.len()][1];
            let d = distance(v, p);
            let want = if inside(v, p) { -d } else { d };
            let got = at(&g, p);
            assert!(got * want >= 0.0 && got.abs() <= d + 1e-12, "{} at {p:?}: {got}, distance {want}", polygon_src(v));
            exact += usize::from((got - want).abs() <= 1e-12);
        }
        assert!(exact > 0, "{}: not exact anywhere", polygon_src(v));
    }
}

#[test]
fn extrusions_and_revolutions_are_the_3d_primitives() {
    same_field("extrude(0.7, circle(0.5))", "cylinder(0.5, 0.7)", 2.0, 1e-12);
    same_field("extrude(0.5, rect(1, 0.3))", "box(1, 0.3, 0.5)", 2.0, 1e-12);
    same_field("revolve(1, circle(0.25))", "torus(1, 0.25)", 2.0, 1e-12);
    same_field("revolve(0, rect(0.5, 0.7))", "cylinder(0.5, 0.7)", 2.0, 1e-12);
    // The profile's y is the solid's z: a ring moved up by 0.5.
    same_field("revolve(1, translate(0, 0.5, 0, circle(0.2)))", "translate(0, 0, 0.5, torus(1, 0.2))", 2.0, 1e-12);
    // A washer: the rectangle |x' | <= 0.25, |z| <= 0.5 around radius 1.
    check("revolve(1, rect(0.25, 0.5))", &[([1.0, 0.0, 0.0], -0.25), ([0.0, 0.0, 0.0], 0.75), ([0.0, -1.0, 1.5], 1.0)]);
    // An extruded triangle: the cap above the triangle and the side faces.
    check("extrude(1, polygon(0, 0, 2, 0, 0, 2))", &[([0.5, 0.5, 3.0], 2.0), ([0.5, 0.5, 0.0], -0.5), ([0.5, 0.5, 0.8], -0.2), ([-1.0, 0.5, 2.0], 2f64.sqrt())]);
}

#[test]
fn offset_and_shell_move_and_hollow_the_surface() {
    check("offset(0.5, sphere(1))", &[([2.0, 0.0, 0.0], 0.5), ([0.0; 3], -1.5)]);
    check("offset(-0.25, box(1, 1, 1))", &[([0.0; 3], -0.75), ([2.0, 0.0, 0.0], 1.25)]);
    check("shell(0.2, sphere(1))", &[([1.0, 0.0, 0.0], -0.1), ([0.0; 3], 0.9), ([2.0, 0.0, 0.0], 0.9), ([0.0, 1.1, 0.0], 0.0)]);
}

#[test]
fn infill_cuts_the_shape_to_a_gyroid_sheet() {
    let (period, thickness) = (0.7, 0.1);
    let k = 2.0 * std::f64::consts::PI / period;
    let sheet = |p: [f64; 3]| {
        let (x, y, z) = (k * p[0], k * p[1], k * p[2]);
        let g = x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos();
        g.abs() / (k * 6f64.sqrt()) - thickness / 2.0
    };
    let g = f("infill(0.7, 0.1, sphere(1.2))");
    let mut inside = 0;
    for p in points(1.5, 3000, 7) {
        let ball = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.2;
        let want = ball.max(sheet(p));
        assert!(close(at(&g, p), want), "at {p:?}: {}, expected {want}", at(&g, p));
        inside += usize::from(want < 0.0);
    }
    // The sheet is a fraction of the ball, but not empty.
    assert!(inside > 50 && inside < 1500, "{inside} of 3000 points inside");
}

/// The noise written out from its specification, not from `NOISE_WAVES`.
fn spec_noise(p: [f64; 3], f: f64) -> f64 {
    let dirs = [[0.6, 0.8, 0.0], [0.0, 0.6, 0.8], [0.8, 0.0, 0.6], [0.48, 0.64, 0.6]];
    let (m, w, phi) = ([1.0, 1.7, 2.9, 4.3], [0.4, 0.3, 0.2, 0.1], [0.0, 1.3, 2.1, 4.2]);
    (0..4).map(|k| w[k] * (f * m[k] * (dirs[k][0] * p[0] + dirs[k][1] * p[1] + dirs[k][2] * p[2]) + phi[k]).sin()).sum()
}

#[test]
fn the_noise_table_is_the_specified_one() {
    use crate::sdf::{noise, NOISE_GRADIENT, NOISE_WAVES};
    let mut weights = 0.0;
    let mut gradient = 0.0;
    for (a, m, w, _) in NOISE_WAVES {
        assert!(((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt() - 1.0).abs() < 1e-15, "{a:?} is not a unit vector");
        weights += w;
        gradient += w * m;
    }
    assert!((weights - 1.0).abs() < 1e-12 && (gradient - NOISE_GRADIENT).abs() < 1e-12, "{weights} {gradient}");
    for p in points(3.0, 500, 3) {
        assert!((noise(p, 2.5) - spec_noise(p, 2.5)).abs() < 1e-12);
    }
}

#[test]
fn displace_adds_bounded_noise_with_a_bounded_gradient() {
    let freq = 3.0;
    // The lowered form computes in the order `noise` documents: equal bits.
    let n = f("displace(1, 3, 0)");
    let g = f("displace(0.2, 3, sphere(1))");
    let h = 1e-6;
    let mut steepest: f64 = 0.0;
    for p in points(2.0, 2000, 11) {
        let v = at(&n, p);
        assert_eq!(v, crate::sdf::noise(p, freq), "at {p:?}");
        assert!(v.abs() <= 1.0);
        let sphere = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0;
        assert!(close(at(&g, p), sphere + 0.2 * spec_noise(p, freq)));
        let mut grad = 0.0;
        for i in 0..3 {
            let (mut a, mut b) = (p, p);
            a[i] += h;
            b[i] -= h;
            grad += ((spec_noise(a, freq) - spec_noise(b, freq)) / (2.0 * h)).powi(2);
        }
        steepest = steepest.max(grad.sqrt());
    }
    assert!(steepest <= crate::sdf::NOISE_GRADIENT * freq, "|grad n| = {steepest}");
    // A bound that is not loose by an order of magnitude.
    assert!(steepest > 0.5 * freq, "|grad n| = {steepest}");
}

/// The new forms lower to blobtree nodes; where they cannot, the reason
/// points at the form (the compiled field renders those).
#[test]
fn the_scene_path_lowers_the_new_forms_or_says_why_not() {
    for src in ["extrude(1, circle(1))", "union(sphere(1), shell(0.1, box(1, 1, 1)))", "scale(2, offset(0.1, revolve(1, polygon(0, 0, 1, 0, 0, 1))))"] {
        assert!(crate::scene::from_formula(&f(src), &[]).is_ok(), "{src}");
    }
    for (src, at, reason) in [
        ("translate(1, 0, 0, displace(0.1, 2, sphere(1)))", "displace", "a transform over 'displace' is not a blobtree node (its pattern is fixed in the world): transform its operand instead"),
        ("union(sphere(1), circle(2))", "circle", "a 2D profile is a blobtree node only inside extrude or revolve"),
        ("extrude(1, sphere(1))", "sphere", "extrude and revolve take a 2D profile here (circle, rect, roundrect, capsule2d or polygon)"),
    ] {
        let e = crate::scene::from_formula(&f(src), &[]).expect_err(src);
        assert_eq!(e.reason, reason, "{src}");
        let start = e.span.start as usize;
        assert_eq!(&src[start..start + at.len()], at, "{src}: {:?}", e.span);
    }
}

// Bisection's root search for a compiled field, one point of f a step (the
// ITP method), spliced into cells.wgsl at `//!splice:narrow`; its
// two-points-a-step form is root_search_two_points.wgsl (src/kernel.rs chooses).

// The root in cell [cell.x, cell.y], with fa, fb = f − c at its ends, from
// one call site of f (lavapipe runs every call site of a loop body on
// every cell, for the lanes that need it or not: ten sites here cost more
// than the cell's enclosure).
// - Monotone (`leaf` false): the unique root, by the ITP method
//   (itp_point) down to the eps width along the ray (fa, fb bracket it).
// - A leaf: an enclosure can contain 0 a little before the surface
//   (overestimation), so when f does not change sign across the cell we
//   look up to LOOKAHEAD cells further for a sign change (IA overestimates
//   most where the gradient is nearly perpendicular to the ray) and bisect
//   there 10 times; without one (a tangent root or a feature thinner than a
//   cell) the cell's midpoint is the answer.
// (`slope`, the bracket's slope enclosure, is for root_search_two_points.wgsl.)
fn narrow(ray: Ray, cell: vec2<f32>, f_lo: f32, f_hi: f32, c: f32, leaf: bool, slope: vec2<f32>) -> f32 {
    var a = cell.x;
    var b = cell.y;
    var fa = f_lo;
    var fb = f_hi;
    var mode = narrow_mode(leaf, fa, fb);
    if (mode == NARROW_ITP && fa == 0.0) { return a; }
    if (mode == NARROW_ITP && fb == 0.0) { return b; }
    let w = cell.y - cell.x;
    let itp = itp_cell(w, ray.eps_s);
    var n = 0u;
    loop {
        var s = 0.5 * (a + b);
        if (mode == NARROW_ITP) {
            if (n >= 40u || !(b - a > ray.eps_s)) { break; }
            s = itp_point(a, b, fa, fb, n, itp, ray.eps_s);
        } else if (mode == NARROW_BISECT) {
            if (n >= 10u) { break; }
        } else {
            if (n >= LOOKAHEAD || !(b < ray.s_exit)) { return 0.5 * (cell.x + cell.y); }
            s = min(b + w, ray.s_exit);
        }
        let fm = field_ray(ray.o, ray.dir, s) - c;
        n = n + 1u;
        if (mode == NARROW_LOOK) {
            a = b;
            fa = fb;
            b = s;
            fb = fm;
            if (brackets(fa, fb)) {
                mode = NARROW_BISECT;
                n = 0u;
            }
        } else if (mode == NARROW_BISECT) {
            if ((fa <= 0.0) == (fm <= 0.0)) { a = s; fa = fm; } else { b = s; }
        } else if ((fm <= 0.0) == (fa <= 0.0)) {
            a = s;
            fa = fm;
        } else {
            b = s;
            fb = fm;
        }
    }
    return 0.5 * (a + b);
}

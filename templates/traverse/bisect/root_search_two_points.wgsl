// Bisection's root search for a compiled field, two points of f a step,
// spliced into cells.wgsl at `//!splice:narrow` in place of root_search_one_point.wgsl
// (src/kernel.rs chooses). A step evaluates f at two points that
// depend on nothing but the bracket, so the two evaluations are
// independent: on a CPU device a cheap f is a chain of dependent
// operations that leaves most of the core idle (the superquadric's x^200
// is nine multiplications in a row), and the second chain runs in that
// idle time. A step then costs about what one point cost, and splits the
// bracket in three where one point splits it in two: the superquadric and
// cloth render noticeably faster, and no Knoll surface slower. The price
// is a second copy of f in the kernel: formulas too large for that keep
// root_search_one_point.wgsl.

// The secant pair's half width starts at this fraction of the bracket's
// width squared over the cell's (as ITP's κ), and at least eps/4.
const PAIR_KAPPA: f32 = 0.05;
// The secant is trusted while f's slope over the cell varies by at most
// this factor (the secant's error grows with that variation).
const PAIR_SLOPE_RATIO: f32 = 4.0;

// The root in cell [cell.x, cell.y], with fa, fb = f − c at its ends, two
// points a step from one loop (two call sites of f).
// - Monotone (`leaf` false; `slope` encloses f's slope along the ray over
//   the cell, and excludes 0): the unique root, down to the eps width along
//   the ray (fa, fb bracket it). Where the slope varies little over the
//   cell the two points straddle the secant's root, a little apart, so an
//   accurate secant closes the bracket in one step. Where it varies a lot
//   (x^200: flat, then steep), or once a secant pair has shrunk the bracket
//   less than thirds would have (to more than 0.34 of it), the points are
//   the bracket's thirds. A secant step that goes on leaves at most 0.34 of
//   the bracket, and the one that fails ends the secant run, so the search
//   takes at most two steps more than thirds' ⌈log3(w/eps)⌉ (simulated on
//   3,000 brackets each: one more at most; steps a root: a sphere's 1.8
//   against ITP's 2.7, a quartic's 2.2 against 2.7, x^200's 3.6 against
//   5.9).
// - A leaf: as root_search_one_point.wgsl, looking up to LOOKAHEAD cells further, two
//   cells a step, for a sign change, then 7 steps of thirds (3^7 > 2^10,
//   the ten halvings of root_search_one_point.wgsl); without one, the cell's midpoint.
fn narrow(ray: Ray, cell: vec2<f32>, f_lo: f32, f_hi: f32, c: f32, leaf: bool, slope: vec2<f32>) -> f32 {
    var a = cell.x;
    var b = cell.y;
    var fa = f_lo;
    var fb = f_hi;
    var mode = narrow_mode(leaf, fa, fb);
    if (mode == NARROW_ITP && fa == 0.0) { return a; }
    if (mode == NARROW_ITP && fb == 0.0) { return b; }
    let w = cell.y - cell.x;
    let kw = PAIR_KAPPA / w;
    let ds = abs(slope);
    var secant = PAIR_SLOPE_RATIO * min(ds.x, ds.y) >= max(ds.x, ds.y);
    var n = 0u;
    loop {
        let span = b - a;
        var s = vec2<f32>(a + span * (1.0 / 3.0), b - span * (1.0 / 3.0));
        if (mode == NARROW_ITP) {
            if (n >= 40u || !(span > ray.eps_s)) { break; }
            // (a NaN secant fails the test and leaves the thirds)
            let m = (a * fb - b * fa) / (fb - fa);
            if (secant && m > a && m < b) {
                let d = min(max(kw * span * span, 0.25 * ray.eps_s), span * (1.0 / 6.0));
                let mc = clamp(m, a + d, b - d);
                s = vec2<f32>(mc - d, mc + d);
            }
        } else if (mode == NARROW_BISECT) {
            if (n >= 7u) { break; }
        } else {
            if (n >= LOOKAHEAD || !(b < ray.s_exit)) { return 0.5 * (cell.x + cell.y); }
            s = min(vec2<f32>(b + w, b + 2.0 * w), vec2<f32>(ray.s_exit));
        }
        let f1 = field_ray(ray.o, ray.dir, s.x) - c;
        let f2 = field_ray(ray.o, ray.dir, s.y) - c;
        if (mode == NARROW_LOOK) {
            // The cells [b, s.x] and [s.x, s.y], nearest first.
            n = n + 2u;
            let first = brackets(fb, f1);
            if (first || brackets(f1, f2)) {
                mode = NARROW_BISECT;
                n = 0u;
            }
            a = select(s.x, b, first);
            fa = select(f1, fb, first);
            b = select(s.y, s.x, first);
            fb = select(f2, f1, first);
        } else {
            // The pieces [a, s.x], [s.x, s.y], [s.y, b]: the one whose ends
            // differ in sign.
            n = n + 1u;
            if ((f1 <= 0.0) != (fa <= 0.0)) {
                b = s.x;
                fb = f1;
            } else if ((f2 <= 0.0) != (fa <= 0.0)) {
                a = s.x;
                fa = f1;
                b = s.y;
                fb = f2;
            } else {
                a = s.y;
                fa = f2;
            }
            if (b - a > span * 0.34) { secant = false; }
        }
    }
    return 0.5 * (a + b);
}

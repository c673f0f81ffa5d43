// Bisection's cells with the scalar work inline (the compiled field): the
// mean-value midpoint, a monotone cell's ends and regula falsi, a leaf's
// sign test and refinement each call f where they need it. Every call site
// is a copy of the generated evaluator; for an interpreted field, whose
// copies are whole interpreters, cells_probe.wgsl runs the same steps from
// one call site instead (each frame here is 10-45 % faster, so both are kept).

// Whether the host runs several rounds of `main` over these cells (kernel.wgsl).
const CELLS_ROUNDS: bool = false;

// Stackless bisection of the ray between depths s_lo and s_hi. Cells (d, k)
// cover [k, k+1] / 2^d of the segment; rejecting a cell climbs over every
// finished level at once (the trailing one bits of k) and steps right.
fn traverse(ray: Ray, s_lo: f32, s_hi: f32, d_max: u32, budget: u32) -> Hit {
    var h = Hit(0.0, STATUS_MISS, 0u, 0u, 0u);
    var d = 0u;
    var k = 0u;
    let len = s_hi - s_lo;
    let d_last = d_max + EXTRA_LEVELS;
    loop {
        if (h.iters >= budget || field_exhausted()) {
            // Budget exhausted (the traversal's, or an interpreted field's
            // work limit): report it, and keep the nearest cell that may
            // still hold the surface as the best guess.
            h.status = STATUS_UNRESOLVED;
            h.s = cell_s(s_lo, len, d, k).x;
            return h;
        }
        h.iters = h.iters + 1u;
        let c = cell_s(s_lo, len, d, k);
        // From depth U.mono_depth on, cells are evaluated together with the
        // enclosure of f's derivative along the ray: where it excludes 0, f
        // is monotone on the cell, which then holds a root iff f changes
        // sign across it, and that root is unique (found by scalar solving).
        let slope = d >= U.mono_depth;
        let q = cell_enclosure(ray.o, ray.dir, c.x, c.y, slope);
        var r = q.xy;
        var monotone = false;
        if (slope) {
            monotone = q.z > 0.0 || q.w < 0.0;
            if (!monotone) { r = mean_value(c, r, q.zw, field(ray.o + ray.dir * (0.5 * (c.x + c.y)))); }
        }
        h.evals = h.evals + 1u;
        var descend = false;
        if (keep_cell(r)) {
            let finite = is_finite_range(r);
            var f0 = 0.0;
            var f1 = 0.0;
            if (monotone) {
                f0 = field(ray.o + ray.dir * c.x);
                f1 = field(ray.o + ray.dir * c.y);
                monotone = abs(f0) < F.inf && abs(f1) < F.inf;
            }
            if (monotone) {
                // At most one root per isovalue, and one exactly when f - c
                // changes sign; the nearest of them is the hit.
                var best = F.inf;
                for (var i = 0u; i < ISO_COUNT; i = i + 1u) {
                    let c_i = iso_value(i);
                    if (brackets(f0 - c_i, f1 - c_i)) {
                        let s_i = solve(ray, c.x, c.y, f0 - c_i, f1 - c_i, c_i);
                        if (s_i < best) { best = s_i; h.iso = i; }
                    }
                }
                if (best < F.inf && accept_hit(ray.o + ray.dir * best)) {
                    h.s = best;
                    h.status = STATUS_HIT;
                    return h;
                }
            } else if (d < d_max || (!finite && d < d_last)) {
                descend = true;
            } else {
                let i = first_iso(r);
                if (finite || sign_change(ray, c.x, c.y, iso_value(i))) {
                    let s_hit = refine(ray, c.x, c.y, iso_value(i));
                    if (accept_hit(ray.o + ray.dir * s_hit)) {
                        h.iso = i;
                        h.s = s_hit;
                        h.status = STATUS_HIT;
                        return h;
                    }
                }
            }
        }
        if (descend) {
            d = d + 1u;
            k = k * 2u;
        } else {
            let up = countTrailingZeros(~k);
            if (up >= d) { return h; } // the whole segment is done
            d = d - up;
            k = (k >> up) + 1u;
        }
    }
    return h;
}

// The unique root of a monotone f in [a, b] (fa, fb of opposite signs or
// zero): Illinois regula falsi down to the eps width along the ray.
fn solve(ray: Ray, s0: f32, s1: f32, f0: f32, f1: f32, c: f32) -> f32 {
    var a = s0;
    var b = s1;
    var fa = f0;
    var fb = f1;
    if (fa == 0.0) { return a; }
    if (fb == 0.0) { return b; }
    var side = 0;
    for (var i = 0; i < 40 && b - a > ray.eps_s; i = i + 1) {
        var m = (a * fb - b * fa) / (fb - fa);
        if (!(m > a && m < b)) { m = 0.5 * (a + b); }
        let fm = field(ray.o + ray.dir * m) - c;
        if ((fm <= 0.0) == (fa <= 0.0)) {
            a = m;
            fa = fm;
            if (side == -1) { fb = 0.5 * fb; }
            side = -1;
        } else {
            b = m;
            fb = fm;
            if (side == 1) { fa = 0.5 * fa; }
            side = 1;
        }
    }
    return 0.5 * (a + b);
}

fn sign_change(ray: Ray, t0: f32, t1: f32, c: f32) -> bool {
    return brackets(field(ray.o + ray.dir * t0) - c, field(ray.o + ray.dir * t1) - c);
}

// Root position for the hit cell [t0, t1]. An enclosure can contain 0 a
// little before the surface (overestimation), so when f does not change sign
// across the cell we look up to LOOKAHEAD cells further for a sign change
// (IA overestimates most where the gradient is nearly perpendicular to the
// ray; scalar evaluations only) and bisect there; without one (a tangent root or
// a feature thinner than a cell) the cell's midpoint is the answer.
fn refine(ray: Ray, t0: f32, t1: f32, c: f32) -> f32 {
    let w = t1 - t0;
    var a = t0;
    var b = t1;
    var fa = field(ray.o + ray.dir * a) - c;
    var fb = field(ray.o + ray.dir * b) - c;
    var found = (fa <= 0.0 && fb >= 0.0) || (fa >= 0.0 && fb <= 0.0);
    for (var k = 0u; k < LOOKAHEAD && !found && b < ray.s_exit; k = k + 1u) {
        a = b;
        fa = fb;
        b = min(b + w, ray.s_exit);
        fb = field(ray.o + ray.dir * b) - c;
        found = (fa <= 0.0 && fb >= 0.0) || (fa >= 0.0 && fb <= 0.0);
    }
    if (!found) {
        return 0.5 * (t0 + t1);
    }
    for (var i = 0; i < 10; i = i + 1) {
        let m = 0.5 * (a + b);
        let fm = field(ray.o + ray.dir * m) - c;
        if ((fa <= 0.0) == (fm <= 0.0)) { a = m; fa = fm; } else { b = m; }
    }
    return 0.5 * (a + b);
}

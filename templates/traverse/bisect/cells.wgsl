// Bisection's cells for a compiled field. lavapipe runs every call site
// inside a loop on every pass for all lanes of a SIMD bundle, needed or
// not, and each call site of f is a copy of the generated evaluator; so a
// cell costs one derivative enclosure and two call sites of f (visit), and
// the root finding (narrow) and a leaf's sign test run after the cell loop,
// once per bracket. For an interpreted field, whose copies are whole
// interpreters, cells_resumable.wgsl runs a cell's scalar work from one call
// site instead (its phases made the compiled field's frames slower).

// Whether the host runs several rounds of `main` over these cells (kernel.wgsl).
const CELLS_ROUNDS: bool = false;
// Whether a hit carries its gradient (kernel.wgsl computes it here).
const CELLS_GRADIENT: bool = false;

// A secondary ray's segment [s_lo, s_hi], bisected to depth d_max (`grad`
// is for cells_resumable.wgsl: here the kernel takes the hit's gradient itself).
fn traverse(ray: Ray, s_lo: f32, s_hi: f32, d_max: u32, budget: u32, grad: bool) -> Hit {
    return bisect_runs(ray, vec2<f32>(s_lo, s_hi), d_max, budget, Runs(vec2<u32>(0u), vec2<f32>(0.0), vec2<f32>(0.0), 1.0));
}

// Primary ray from depth s_from on: the candidate slab runs of the tile,
// nearest first, in one bisection loop.
fn trace_primary(ray: Ray, mask: vec2<u32>, s_from: f32, seg: vec2<f32>, dr: vec2<f32>, inv_len: f32) -> Hit {
    var m = mask;
    let lim = vec2<f32>(max(seg.x, s_from), seg.y);
    let first = next_run(&m, lim, dr);
    if (!(first.x < first.y)) { return no_hit(); }
    let h = bisect_runs(ray, first, depth_for((first.y - first.x) / inv_len), g_budget, Runs(m, lim, dr, inv_len));
    g_evals = g_evals + h.evals;
    g_budget = g_budget - min(g_budget, h.iters);
    return h;
}

// The candidate slab runs a primary ray has left after its current one:
// the slab bits `m`, the ray's depth limits `lim`, the slabs' depth range
// `dr`, and 1/|dir| (a secondary ray has none: m = 0).
struct Runs { m: vec2<u32>, lim: vec2<f32>, dr: vec2<f32>, inv_len: f32 }

// Stackless bisection of the ray, run after run: the first segment `first`
// to depth d_max0, then the runs left in `runs`. Cells (d, k) cover
// [k, k+1] / 2^d of the segment; rejecting a cell climbs over every
// finished level at once (the trailing one bits of k) and steps right, and
// past the segment's end onto the next run. One loop for all runs: a lane
// whose run is done goes on with its next while the others of its SIMD
// bundle still bisect theirs (a loop per run made each run cost the
// bundle at least one pass of the whole cell code).
fn bisect_runs(ray: Ray, first: vec2<f32>, d_max0: u32, budget: u32, runs: Runs) -> Hit {
    var h = no_hit();
    var m = runs.m; // a pointer argument must be a whole variable (naga's SPIR-V back end)
    var d = 0u;
    var k = 0u;
    var s_lo = first.x;
    var len = first.y - first.x;
    var d_max = d_max0;
    var d_last = d_max + EXTRA_LEVELS;
    // The field's per-ray state (a compiled field's nodes of degree ≤ 2
    // along the ray, src/field/compiled/ray_forms.rs): every cell and point below
    // is on this ray, between `first.x` and its exit.
    field_begin_ray(ray.o, ray.dir, first.x, ray.s_exit - first.x);
    // The cell at (d, k) is done (its root was turned down by accept_hit):
    // the cell loop steps past it first.
    var skip = false;
    // One pass of this loop per root bracket found; the cell loop inside it
    // bisects until a cell brackets a root, which narrow() then closes in
    // on out here: inside, its loop would be one more pass of f on every
    // cell (lavapipe runs it under a mask for lanes that do not need it).
    loop {
        var found = false; // the cell at (d, k) brackets a root, or is a leaf
        var cell = vec2<f32>(0.0);
        var fc = vec2<f32>(0.0); // f - c_i at the cell's ends
        var iso = 0u;
        var leaf = false;
        var cell_r = vec2<f32>(0.0); // a leaf's enclosure, or a bracket's slope enclosure
        loop {
            var descend = false;
            if (!skip) {
                if (h.iters >= budget || field_exhausted()) {
                    // Budget exhausted (the traversal's, or an interpreted field's
                    // work limit): report it, and keep the nearest cell that may
                    // still hold the surface as the best guess.
                    h.status = STATUS_UNRESOLVED;
                    h.s = cell_s(s_lo, len, d, k).x;
                    return h;
                }
                h.iters = h.iters + 1u;
                h.evals = h.evals + 1u;
                let c = cell_s(s_lo, len, d, k);
                // The enclosure is asked for here, not in visit(): lavapipe
                // inlines the field's whole code into every function on the
                // path from the entry point, one copy per function.
                if (CELL_F_MID) { g_cell_s_mid = 0.5 * (c.x + c.y); }
                let q = cell_enclosure(ray.o, ray.dir, c.x, c.y, d >= U.mono_depth);
                let v = visit(ray, c, d, d_max, d_last, q);
                descend = v.kind == VISIT_DESCEND;
                if (v.kind >= VISIT_BRACKET) {
                    found = true;
                    cell = c;
                    fc = v.fc;
                    iso = v.iso;
                    leaf = v.kind == VISIT_LEAF;
                    cell_r = v.r;
                }
            }
            skip = false;
            if (found) { break; }
            if (descend) {
                d = d + 1u;
                k = k * 2u;
            } else {
                let up = countTrailingZeros(~k);
                if (up < d) {
                    d = d - up;
                    k = (k >> up) + 1u;
                } else {
                    // The whole segment is done: on to the next run, if any.
                    let nxt = next_run(&m, runs.lim, runs.dr);
                    if (!(nxt.x < nxt.y)) { return h; }
                    s_lo = nxt.x;
                    len = nxt.y - nxt.x;
                    d_max = depth_for(len / runs.inv_len);
                    d_last = d_max + EXTRA_LEVELS;
                    d = 0u;
                    k = 0u;
                }
            }
        }
        if (leaf) {
            // f at a leaf's ends; without a finite enclosure, only a sign
            // change is taken for a root.
            let f0 = field_ray(ray.o, ray.dir, cell.x);
            let f1 = field_ray(ray.o, ray.dir, cell.y);
            iso = first_iso(cell_r);
            fc = vec2<f32>(f0, f1) - vec2<f32>(iso_value(iso));
            if (!(is_finite_range(cell_r) || brackets(fc.x, fc.y))) {
                skip = true;
                continue;
            }
        }
        let s_hit = narrow(ray, cell, fc.x, fc.y, iso_value(iso), leaf, cell_r);
        if (accept_hit(ray.o + ray.dir * s_hit)) {
            h.iso = iso;
            h.s = s_hit;
            h.status = STATUS_HIT;
            return h;
        }
        skip = true;
    }
    return h;
}

// What visit() found in a cell: nothing (step past it), a reason to
// descend, a root bracket (monotone: `fc` is f − c at its ends, for
// isovalue `iso`, and `r` the enclosure of f's slope over the cell) or a
// leaf (its enclosure `r`; its sign test comes after the cell loop).
const VISIT_NONE: u32 = 0u;
const VISIT_DESCEND: u32 = 1u;
const VISIT_BRACKET: u32 = 2u;
const VISIT_LEAF: u32 = 3u;
struct Visit { kind: u32, fc: vec2<f32>, iso: u32, r: vec2<f32> }

// One cell c at depth d, given q: its enclosure and, from depth
// U.mono_depth on, the enclosure of f's derivative along the ray (else the
// whole line; cell_enclosure's `slope`). Where that excludes 0, f is
// monotone on the cell, which then holds a root iff f changes sign across
// it, and that root is unique (found by scalar solving). Two call sites of
// f: the midpoint for the mean-value form, or a monotone cell's near end;
// then its far end.
fn visit(ray: Ray, c: vec2<f32>, d: u32, d_max: u32, d_last: u32, q: vec4<f32>) -> Visit {
    var v = Visit(VISIT_NONE, vec2<f32>(0.0), 0u, vec2<f32>(0.0));
    let slope = d >= U.mono_depth;
    var r = q.xy;
    var monotone = slope && (q.z > 0.0 || q.w < 0.0);
    // The mean-value form needs a finite slope (an interpreted tree may give
    // none), and f is evaluated only where it is used: a branch no lane of
    // a SIMD group takes is skipped, so a cell costs its enclosure alone.
    let mv = slope && !monotone && is_finite_range(q.zw);
    // f at the midpoint comes from the enclosure's pass where the field
    // computes it there (CELL_F_MID).
    var f_a = 0.0;
    if (CELL_F_MID) { f_a = g_cell_f_mid; }
    if ((mv && !CELL_F_MID) || monotone) { f_a = field_ray(ray.o, ray.dir, select(c.x, 0.5 * (c.x + c.y), mv)); }
    if (mv) { r = mean_value(c, r, q.zw, f_a, 0.5 * (c.x + c.y)); }
    if (!keep_cell(r)) { return v; }
    let deeper = d < d_max || (!is_finite_range(r) && d < d_last);
    var f1 = 0.0;
    if (monotone) {
        f1 = field_ray(ray.o, ray.dir, c.y);
        // A monotone cell whose ends are not finite is bisected like any other.
        monotone = abs(f_a) < F.inf && abs(f1) < F.inf;
    }
    if (monotone) {
        v.iso = nearest_iso(f_a, f1);
        if (v.iso < ISO_COUNT) {
            v.kind = VISIT_BRACKET;
            v.fc = vec2<f32>(f_a, f1) - vec2<f32>(iso_value(v.iso));
            v.r = q.zw;
        }
    } else if (deeper) {
        v.kind = VISIT_DESCEND;
    } else {
        v.kind = VISIT_LEAF;
        v.r = r;
    }
    return v;
}

// The isovalue whose root a monotone cell holds nearest its start, f0 and
// f1 its ends (ISO_COUNT: none). At most one root per isovalue, and one
// exactly when f − c changes sign; f is monotone, so the nearest root is
// that of the bracketed isovalue nearest f0.
fn nearest_iso(f0: f32, f1: f32) -> u32 {
    var iso = ISO_COUNT;
    var gap = F.inf;
    for (var i = 0u; i < ISO_COUNT; i = i + 1u) {
        let c_i = iso_value(i);
        if (brackets(f0 - c_i, f1 - c_i) && abs(c_i - f0) < gap) {
            gap = abs(c_i - f0);
            iso = i;
        }
    }
    return iso;
}

// How narrow() (root_search_one_point.wgsl or root_search_two_points.wgsl, spliced below) closes
// in on a root: one point or two a step in a monotone cell, looking
// further along the ray for a sign change of a leaf, then bisecting (or
// splitting in thirds) the bracket it finds.
const NARROW_ITP: u32 = 0u;
const NARROW_LOOK: u32 = 1u;
const NARROW_BISECT: u32 = 2u;
// The first of those for a cell whose ends are f0, f1 (as f − c).
fn narrow_mode(leaf: bool, f0: f32, f1: f32) -> u32 {
    return select(NARROW_ITP, select(NARROW_LOOK, NARROW_BISECT, brackets(f0, f1)), leaf);
}

//!splice:root_search

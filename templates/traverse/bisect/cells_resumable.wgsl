// Bisection's cells for an interpreted field (the tape): the scalar work on
// a cell (the mean-value midpoint, a monotone cell's ends and its root search,
// a leaf's sign test and refinement; the steps of cells.wgsl) runs as
// phases of an inner loop with one call of f. A shader compiler inlines
// every call site, and lavapipe compiles each inlined copy of the
// interpreter in full: one site instead of ten.

// Whether the host runs several rounds of `main` over these cells (kernel.wgsl).
const CELLS_ROUNDS: bool = true;
// Whether a hit carries its gradient: here it is found by the cell work's
// one call of f (phase PH_GRAD), where a call of `gradient` in kernel.wgsl
// was one more inlined interpreter, and by forward differences from a point
// f was evaluated at already.
const CELLS_GRADIENT: bool = true;

// Primary ray from depth s_from on: the candidate slab runs of the tile,
// nearest first, each bisected by a traverse of its own (a suspended pixel
// resumes in the run that holds its cell).
fn trace_primary(ray: Ray, mask: vec2<u32>, s_from: f32, seg: vec2<f32>, dr: vec2<f32>, inv_len: f32) -> Hit {
    var m = mask;
    let lim = vec2<f32>(max(seg.x, s_from), seg.y);
    var hit = no_hit();
    loop {
        let run = next_run(&m, lim, dr);
        if (!(run.x < run.y)) { break; }
        hit = traverse(ray, run.x, run.y, depth_for((run.y - run.x) / inv_len), g_budget, true);
        g_evals = g_evals + hit.evals;
        g_budget = g_budget - min(g_budget, hit.iters);
        if (hit.status != STATUS_MISS) { break; }
    }
    return hit;
}

// Stackless bisection of the ray between depths s_lo and s_hi. Cells (d, k)
// cover [k, k+1] / 2^d of the segment; rejecting a cell climbs over every
// finished level at once (the trailing one bits of k) and steps right.
//
// One enclosure call and one scalar call: a shader compiler inlines every
// call site of the field, and lavapipe compiles each inlined copy in full
// (an interpreted field's copy is its whole interpreter), so the scalar
// work on a cell (the mean-value midpoint, a monotone cell's ends and
// the root search, a leaf's sign test and refinement) is a sequence of phases
// (`Probe`, probe.wgsl) run by an inner loop, one evaluation of f per
// iteration. The inner loop keeps the enclosure out of those iterations.
// With `grad`, a hit's gradient is found there too (PH_GRAD).
fn traverse(ray: Ray, s_lo: f32, s_hi: f32, d_max: u32, budget: u32, grad: bool) -> Hit {
    var h = no_hit();
    var d = 0u;
    var k = 0u;
    if (g_resume.y != RESUME_NONE && g_resume.x == bitcast<u32>(s_lo)) {
        // Resuming a suspended pixel at its cell (kernel.wgsl, g_at).
        d = g_resume.y & 31u;
        k = g_resume.y >> 5u;
        g_resume.y = RESUME_NONE;
    }
    // The field's per-ray state (a compiled field's nodes along the ray,
    // src/field/compiled/ray_forms.rs, for its cell enclosures): every cell below
    // lies on this ray between s_lo and its exit.
    field_begin_ray(ray.o, ray.dir, s_lo, ray.s_exit - s_lo);
    let len = s_hi - s_lo;
    let d_last = d_max + EXTRA_LEVELS;
    var c = vec2<f32>(0.0);
    var r = vec2<f32>(0.0);
    var D = vec2<f32>(0.0);
    var p = probe_idle();
    loop {
        // Budget exhausted (the traversal's, or an interpreted field's work
        // limit): report it, and keep the nearest cell that may still hold
        // the surface as the best guess, with its gradient (a guess can be
        // drawn like a hit) from the cell work's call of f below.
        let give_up = h.iters >= budget || field_exhausted();
        if (give_up) {
            h.status = STATUS_UNRESOLVED;
            h.s = cell_s(s_lo, len, d, k).x;
            if (!grad || field_exhausted()) { return h; }
            p.best = h.s;
            p.s_last = -F.inf; // the stencil starts at the guess itself
            probe_gradient(&p, ray);
        } else {
            h.iters = h.iters + 1u;
            c = cell_s(s_lo, len, d, k);
            g_at = vec2<u32>(bitcast<u32>(s_lo), d | (k << 5u));
            let q = probe_cell(&p, ray, s_lo, len, d, k);
            h.evals = h.evals + 1u;
            r = q.xy;
            D = q.zw;
            probe_decide(&p, c, r, d, d_max, d_last);
        }
        // The cell's scalar work, one evaluation of f per iteration (the
        // test at the end: code after a break still runs for the lanes
        // left, so a test at the top would cost an evaluation).
        if (probe_scalar(p.phase)) {
            loop {
                // Looking ahead can pass the run's end, where the field's
                // program for the tile does not hold (fields/tape_tiles.wgsl),
                // and so can the root it finds. The gradient's points leave
                // the ray: most stay in the run's slabs of the tile's frustum
                // (those of a pixel on the tile's edge may not).
                let on_ray = p.phase != PH_GRAD;
                let s = p.s;
                let q = probe_point(p, ray);
                var inside = s <= s_hi;
                if (!on_ray) { inside = in_frustum(q, g_tile_frustum, vec2<f32>(s_lo, s_hi)); }
                field_in_tile(inside);
                let f = field(q);
                if (p.phase == PH_MEAN) {
                    r = mean_value(c, r, D, f, s);
                    p.phase = PH_DECIDE;
                } else if (on_ray) {
                    probe_step(&p, ray, c, f);
                } else {
                    gradient_step(&p, f);
                }
                // The last value on the ray: a monotone cell's end, or where
                // the gradient starts.
                if (on_ray) {
                    p.s_last = s;
                    p.f_last = f;
                }
                probe_decide(&p, c, r, d, d_max, d_last);
                probe_found(&p, ray, grad);
                if (!probe_scalar(p.phase)) { break; }
            }
        }
        if (give_up || p.phase == PH_HIT) {
            if (!give_up) {
                h.iso = p.best_iso;
                h.s = p.best;
                h.status = STATUS_HIT;
            }
            h.g = p.g / gradient_step_size();
            return h;
        }
        if (p.phase == PH_DESCEND) {
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

// The enclosure of f over cell (d, k) of the segment from s_lo of length
// len (its one call site), and the start of the cell's scalar work in p.
// From depth U.mono_depth on, cells are evaluated together with the
// enclosure of f's derivative along the ray: where it excludes 0, f is
// monotone on the cell, which then holds a root iff f changes sign across
// it, and that root is unique (found by scalar solving). Otherwise the
// slope tightens the enclosure (the mean-value form, which needs f at the
// midpoint).
fn probe_cell(p: ptr<function, Probe>, ray: Ray, s_lo: f32, len: f32, d: u32, k: u32) -> vec4<f32> {
    let c = cell_s(s_lo, len, d, k);
    let slope = d >= U.mono_depth;
    // The midpoint as its children's shared end is computed, so a monotone
    // child takes f there from this evaluation. (Only a field that computes
    // f there in the enclosure's pass, CELL_F_MID, needs it before: it
    // would be one more value held across the enclosure.)
    if (CELL_F_MID) { g_cell_s_mid = cell_s(s_lo, len, d + 1u, 2u * k).y; }
    var q = cell_enclosure(ray.o, ray.dir, c.x, c.y, slope);
    (*p).monotone = slope && (q.z > 0.0 || q.w < 0.0);
    (*p).phase = PH_DECIDE;
    // The mean-value form needs a finite slope, and f at the midpoint: the
    // field's from the enclosure's pass, else evaluated next.
    if (slope && !(*p).monotone && is_finite_range(q.zw)) {
        if (CELL_F_MID) {
            q = vec4<f32>(mean_value(c, q.xy, q.zw, g_cell_f_mid, g_cell_s_mid), q.zw);
            (*p).s_last = g_cell_s_mid;
            (*p).f_last = g_cell_f_mid;
        } else {
            (*p).phase = PH_MEAN;
            (*p).s = cell_s(s_lo, len, d + 1u, 2u * k).y;
        }
    }
    return q;
}

// Phases of a cell's scalar work (traverse). PH_CELL: the cell's enclosure;
// PH_DECIDE: reject the cell or start its scalar work; PH_MEAN: f at the midpoint;
// PH_ENDS: f at a monotone cell's two ends; PH_SOLVE: the root search (ITP) for one
// isovalue; PH_LEAF: f − c at a leaf's ends; PH_LOOK: looking further along
// the ray for a sign change; PH_BISECT: bisecting the bracket found. The
// others say what comes next: PH_SPLIT (descend or test the leaf),
// PH_FOUND (a root at `best`), PH_DESCEND, PH_ADVANCE (next cell).
const PH_CELL: u32 = 0u;
const PH_MEAN: u32 = 1u;
const PH_ENDS: u32 = 2u;
const PH_SOLVE: u32 = 3u;
const PH_LEAF: u32 = 4u;
const PH_LOOK: u32 = 5u;
const PH_BISECT: u32 = 6u;
const PH_SPLIT: u32 = 7u;
const PH_FOUND: u32 = 8u;
const PH_DESCEND: u32 = 9u;
const PH_ADVANCE: u32 = 10u;
const PH_DECIDE: u32 = 11u;
const PH_GRAD: u32 = 12u;
const PH_HIT: u32 = 13u;

// A cell's scalar work in progress: f is evaluated at `s` next; [a, b] with
// fa, fb is the bracket being narrowed (f minus the isovalue `c`), `n` the
// steps taken in the phase; `best` the nearest root so far, of `best_iso`;
// f_last = f(s_last) the last evaluation on the ray (hi_known: it is the
// monotone cell's far end, f1, PH_ENDS); `gp` the point the
// gradient's forward differences `g` start from (PH_GRAD).
struct Probe {
    phase: u32,
    n: u32,
    s: f32,
    a: f32,
    b: f32,
    fa: f32,
    fb: f32,
    f0: f32,
    f1: f32,
    c: f32,
    iso: u32,
    best: f32,
    best_iso: u32,
    monotone: bool,
    finite: bool,
    s_last: f32,
    f_last: f32,
    hi_known: bool,
    gp: vec3<f32>,
    g: vec3<f32>,
}

// Whether the phase evaluates f.
fn probe_scalar(phase: u32) -> bool { return (phase >= PH_MEAN && phase <= PH_BISECT) || phase == PH_GRAD; }

// After the cell's enclosure is final (PH_DECIDE): reject the cell, or start
// on its scalar work; not monotone (PH_SPLIT, also when a monotone cell's
// ends are not finite): descend, or at the last level test the cell itself.
fn probe_decide(p: ptr<function, Probe>, c: vec2<f32>, r: vec2<f32>, d: u32, d_max: u32, d_last: u32) {
    if ((*p).phase == PH_DECIDE) {
        (*p).finite = is_finite_range(r);
        if (!keep_cell(r)) {
            (*p).phase = PH_ADVANCE;
        } else if ((*p).monotone) {
            // An end where f was evaluated last (the parent's mean-value
            // midpoint, or the left sibling's far end) is not evaluated again.
            let lo = (*p).s_last == c.x;
            (*p).hi_known = (*p).s_last == c.y;
            (*p).f0 = (*p).f_last;
            (*p).f1 = (*p).f_last;
            (*p).phase = PH_ENDS;
            (*p).n = select(0u, 1u, lo);
            (*p).s = select(c.x, c.y, lo);
        } else {
            (*p).phase = PH_SPLIT;
        }
    }
    if ((*p).phase == PH_SPLIT) {
        if (d < d_max || (!(*p).finite && d < d_last)) {
            (*p).phase = PH_DESCEND;
        } else {
            probe_leaf(p, c, first_iso(r));
        }
    }
}

fn probe_idle() -> Probe {
    return Probe(PH_CELL, 0u, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0u, 0.0, 0u, false, false, -F.inf, 0.0, false, vec3<f32>(0.0), vec3<f32>(0.0));
}

// Where the phase evaluates f: on the ray at s, or (PH_GRAD) the
// gradient's base point gp (n = 0) and one stencil step from it along x,
// y, z (n = 1, 2, 3).
fn probe_point(p: Probe, ray: Ray) -> vec3<f32> {
    let axis = vec3<f32>(f32(p.n == 1u), f32(p.n == 2u), f32(p.n == 3u));
    return select(ray.o + ray.dir * p.s, p.gp + axis * gradient_step_size(), p.phase == PH_GRAD);
}

// A root found (PH_FOUND): turned down by the hook (PH_ADVANCE), a hit
// (PH_HIT), or, with `grad`, a hit whose gradient comes next (PH_GRAD).
// Forward differences start from the last point f was evaluated at on the
// ray when it lies within eps of the root (the root search and bisection end
// on a bracket of that width, so it nearly always does): three evaluations
// where central differences take six. Otherwise from the root, after one
// more evaluation there. Their error is O(step) against f's curvature,
// like that of the base point's offset.
fn probe_found(p: ptr<function, Probe>, ray: Ray, grad: bool) {
    if ((*p).phase != PH_FOUND) { return; }
    let q = ray.o + ray.dir * (*p).best;
    if (!accept_hit(q)) {
        (*p).phase = PH_ADVANCE;
        return;
    }
    (*p).phase = PH_HIT;
    if (grad) { probe_gradient(p, ray); }
}

// Starts the gradient at p.best (PH_GRAD): from the last point on the ray
// when it is within eps of it (its f known), else from p.best itself.
fn probe_gradient(p: ptr<function, Probe>, ray: Ray) {
    let near = abs((*p).s_last - (*p).best) <= ray.eps_s;
    (*p).gp = ray.o + ray.dir * select((*p).best, (*p).s_last, near);
    (*p).n = select(0u, 1u, near);
    (*p).g = vec3<f32>(0.0);
    (*p).phase = PH_GRAD;
}

// One evaluation f of the gradient's stencil (PH_GRAD): the base point's
// value (n = 0), then one difference per axis; PH_HIT after the third.
fn gradient_step(p: ptr<function, Probe>, f: f32) {
    let n = (*p).n;
    if (n == 0u) { (*p).f_last = f; }
    let axis = vec3<f32>(f32(n == 1u), f32(n == 2u), f32(n == 3u));
    (*p).g = (*p).g + axis * (f - (*p).f_last);
    (*p).n = n + 1u;
    if (n == 3u) { (*p).phase = PH_HIT; }
}

// One evaluation f = f(s) taken into the phase it was asked for.
fn probe_step(p: ptr<function, Probe>, ray: Ray, c: vec2<f32>, f: f32) {
    switch ((*p).phase) {
        case PH_ENDS: {
            if ((*p).n == 0u) { (*p).f0 = f; } else { (*p).f1 = f; }
            if ((*p).n == 0u && !(*p).hi_known) {
                (*p).n = 1u;
                (*p).s = c.y;
            } else if (abs((*p).f0) < F.inf && abs((*p).f1) < F.inf) {
                // At most one root per isovalue, and one exactly when f − c
                // changes sign; the nearest of them is the hit.
                (*p).iso = 0u;
                (*p).best = F.inf;
                next_solve(p, ray, c);
            } else {
                (*p).monotone = false;
                (*p).phase = PH_SPLIT;
            }
        }
        case PH_SOLVE: {
            solve_step(p, f - (*p).c);
            if ((*p).n >= 40u || !((*p).b - (*p).a > ray.eps_s)) {
                take_root(p, 0.5 * ((*p).a + (*p).b));
                (*p).iso = (*p).iso + 1u;
                next_solve(p, ray, c);
            } else {
                (*p).s = solve_point(*p, ray, c);
            }
        }
        case PH_LEAF: {
            if ((*p).n == 0u) {
                (*p).fa = f - (*p).c;
                (*p).n = 1u;
                (*p).s = c.y;
            } else {
                (*p).fb = f - (*p).c;
                let found = brackets((*p).fa, (*p).fb);
                // A non-finite enclosure proves nothing: without a sign change there is no root.
                (*p).n = 0u;
                if (!(*p).finite && !found) { (*p).phase = PH_ADVANCE; } else { refine_next(p, ray, c, found); }
            }
        }
        case PH_LOOK: {
            (*p).fb = f - (*p).c;
            (*p).n = (*p).n + 1u;
            refine_next(p, ray, c, brackets((*p).fa, (*p).fb));
        }
        default: { // PH_BISECT
            if (((*p).fa <= 0.0) == (f - (*p).c <= 0.0)) {
                (*p).a = (*p).s;
                (*p).fa = f - (*p).c;
            } else {
                (*p).b = (*p).s;
            }
            (*p).n = (*p).n + 1u;
            if ((*p).n == 10u) {
                (*p).best = 0.5 * ((*p).a + (*p).b);
                (*p).phase = PH_FOUND;
            } else {
                (*p).s = 0.5 * ((*p).a + (*p).b);
            }
        }
    }
}

// The next isovalue (from p.iso on) whose f − c changes sign across the
// monotone cell: its root search starts, or the scan ends with the nearest
// root found (PH_FOUND) or none (PH_ADVANCE).
fn next_solve(p: ptr<function, Probe>, ray: Ray, c: vec2<f32>) {
    loop {
        if ((*p).iso >= ISO_COUNT) {
            (*p).phase = select(PH_ADVANCE, PH_FOUND, (*p).best < F.inf);
            return;
        }
        let c_i = iso_value((*p).iso);
        let fa = (*p).f0 - c_i;
        let fb = (*p).f1 - c_i;
        if (brackets(fa, fb)) {
            if (fa == 0.0) {
                take_root(p, c.x);
            } else if (fb == 0.0) {
                take_root(p, c.y);
            } else if (!(c.y - c.x > ray.eps_s)) {
                take_root(p, 0.5 * (c.x + c.y));
            } else {
                (*p).c = c_i;
                (*p).a = c.x;
                (*p).b = c.y;
                (*p).fa = fa;
                (*p).fb = fb;
                (*p).n = 0u;
                (*p).phase = PH_SOLVE;
                (*p).s = solve_point(*p, ray, c);
                return;
            }
        }
        (*p).iso = (*p).iso + 1u;
    }
}

// The next point of a monotone cell c's root search (itp_point).
fn solve_point(p: Probe, ray: Ray, c: vec2<f32>) -> f32 {
    let w = c.y - c.x;
    return itp_point(p.a, p.b, p.fa, p.fb, p.n, itp_cell(w, ray.eps_s), ray.eps_s);
}

// One step of the root search with fm = f(p.s) − c: the end of the bracket
// on fm's side moves to p.s.
fn solve_step(p: ptr<function, Probe>, fm: f32) {
    if ((fm <= 0.0) == ((*p).fa <= 0.0)) {
        (*p).a = (*p).s;
        (*p).fa = fm;
    } else {
        (*p).b = (*p).s;
        (*p).fb = fm;
    }
    (*p).n = (*p).n + 1u;
}

// A root s of isovalue p.iso: kept when nearer than the best so far.
fn take_root(p: ptr<function, Probe>, s: f32) {
    if (s < (*p).best) {
        (*p).best = s;
        (*p).best_iso = (*p).iso;
    }
}

// A leaf cell whose enclosure contains isovalue `iso`: f − c at its ends
// first (PH_LEAF).
fn probe_leaf(p: ptr<function, Probe>, c: vec2<f32>, iso: u32) {
    (*p).iso = iso;
    (*p).best_iso = iso;
    (*p).c = iso_value(iso);
    (*p).a = c.x;
    (*p).b = c.y;
    (*p).n = 0u;
    (*p).s = c.x;
    (*p).phase = PH_LEAF;
}

// Root position for the hit cell c. An enclosure can contain 0 a little
// before the surface (overestimation), so when f does not change sign
// across the cell we look up to LOOKAHEAD cells further for a sign change
// (IA overestimates most where the gradient is nearly perpendicular to the
// ray) and bisect there 10 times; without one (a tangent root or a feature
// thinner than a cell) the cell's midpoint is the answer (as `refine` in
// cells.wgsl). `found`: [a, b] brackets a sign change; p.n: the cells
// looked ahead so far.
fn refine_next(p: ptr<function, Probe>, ray: Ray, c: vec2<f32>, found: bool) {
    if (found) {
        (*p).n = 0u;
        (*p).s = 0.5 * ((*p).a + (*p).b);
        (*p).phase = PH_BISECT;
    } else if ((*p).n < LOOKAHEAD && (*p).b < ray.s_exit) {
        (*p).a = (*p).b;
        (*p).fa = (*p).fb;
        (*p).b = min((*p).b + (c.y - c.x), ray.s_exit);
        (*p).s = (*p).b;
        (*p).phase = PH_LOOK;
    } else {
        (*p).best = 0.5 * (c.x + c.y);
        (*p).phase = PH_FOUND;
    }
}

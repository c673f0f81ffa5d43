// isotrace render kernel: one invocation per pixel, Knoll et al.'s stackless
// interval bisection along the primary ray.
//
// The ray is clipped to the domain box and reparametrised to t in [0, 1].
// Cells are addressed by an integer index k at depth d: cell (d, k) covers
// t in [k, k+1] / 2^d, exact in f32 for d <= 24. Rejecting a cell moves to
// the next one in depth-first order without a stack: the trailing one bits
// of k say how many levels to climb (Knoll tests the float modulus of t; the
// integer form is exact on every device and needs no loop).
//
// The field source provides the enclosures (cell_enclosure, slab_range)
// and the scalar field(p); the traversal never sees the number
// domain or where the field comes from.

// Pass group bindings after the pixel records (src/kernel/bindings.rs):
// tile_masks, the tile pass's result, the candidate slabs of each 8x8 tile (xy: slab bits, z:
// enclosures the tile pass spent on the tile, w: the field's program for
// the tile, see field_enter_tile).
// tile_list, tile_ids: the tiles that have candidate slabs (`count` of them, ids in tile_ids),
// and the indirect dispatch of `main` over them: (x, 1, 1) with
// x = ceil(count / TILES_PER_GROUP).
struct TileList { x: atomic<u32>, y: u32, z: u32, count: atomic<u32> }
// resume: per pixel, across the rounds of `main` in one submission (an interpreted
// field that reaches its work limit is resumed by the next round, whose
// dispatch starts lavapipe's loop count afresh): x the state (0: not traced,
// 1: suspended, 2: done), y the start of the segment being bisected (f32
// bits), z the evaluations so far, w the cell of that segment being worked
// on (d | k << 5). Zeroed with each dispatch.
const RESUME_NEW: u32 = 0u;
const RESUME_SUSPENDED: u32 = 1u;
const RESUME_DONE: u32 = 2u;
// env_image (frame group): environment image for reflections and the background (equirectangular,
// rgba8 packed; one dummy texel when the environment is procedural): a
// frame resource.

// Extra bisection levels below d_max for cells whose enclosure is not
// finite (division by an interval containing 0): such a cell is a hit only
// once it is this much smaller than eps and the scalar function changes sign.
const EXTRA_LEVELS: u32 = 6u;
// The tile pass cuts each tile's view frustum into this many depth slabs.
const SLABS: u32 = 64u;

// Compile-time configuration of the modalities (shadows, layers,
// reflections, colour mode) and the user's hooks: code for a modality is
// only generated when it is asked for.
//!splice:config

// Zero test that stays conservative when an end is NaN.
fn may_contain_zero(r: vec2<f32>) -> bool { return !(r.x > 0.0 || r.y < 0.0); }
fn iso_value(i: u32) -> f32 { return U.iso[i / 4u][i % 4u]; }
// The rejection test with several isovalues: does the enclosure contain any?
fn may_contain_iso(r: vec2<f32>) -> bool {
    for (var i = 0u; i < ISO_COUNT; i = i + 1u) {
        if (may_contain_zero(r - vec2<f32>(iso_value(i)))) { return true; }
    }
    return false;
}
// The first isovalue the enclosure contains.
fn first_iso(r: vec2<f32>) -> u32 {
    for (var i = 0u; i < ISO_COUNT; i = i + 1u) {
        if (may_contain_zero(r - vec2<f32>(iso_value(i)))) { return i; }
    }
    return 0u;
}
fn brackets(f0: f32, f1: f32) -> bool { return (f0 <= 0.0 && f1 >= 0.0) || (f0 >= 0.0 && f1 <= 0.0); }
fn is_finite_range(r: vec2<f32>) -> bool { return abs(r.x) < F.inf && abs(r.y) < F.inf; }

// The ray: points o + s * dir, where dir is the unnormalised pixel direction
// (forward component 1), so s is the depth along the camera's forward axis.
struct Ray { o: vec3<f32>, dir: vec3<f32>, s_exit: f32, eps_s: f32 }
// A hit's gradient g is f's at the hit when the cells compute it
// (CELLS_GRADIENT: an interpreted field's, from the one call site of its
// cell work) and asked to; zero otherwise.
struct Hit { s: f32, status: u32, evals: u32, iters: u32, iso: u32, g: vec3<f32> }
fn no_hit() -> Hit { return Hit(0.0, STATUS_MISS, 0u, 0u, 0u, vec3<f32>(0.0)); }

// The stencil of a hit's gradient: half the termination width.
fn gradient_step_size() -> f32 { return 0.5 * F.eps; }
// The frustum of the pixel's tile (tile_frustum), for cells_resumable.wgsl.
var<private> g_tile_frustum: vec4<f32>;
// A point of the cell the traversal sets before cell_enclosure (the
// mean-value form's midpoint), and f there where the field source computes
// it in the enclosure's pass (CELL_F_MID: FieldSource::cell_midpoint).
var<private> g_cell_s_mid: f32;
var<private> g_cell_f_mid: f32;
// The gradient at hit h (at p) for shading and the normal: the cells' own
// (CELLS_GRADIENT: an interpreted field's, found by its cell work's one call
// of f), else central differences here, six evaluations of f.
fn hit_gradient(h: Hit, p: vec3<f32>) -> vec3<f32> {
    if (CELLS_GRADIENT) { return h.g; }
    return gradient(p, gradient_step_size());
}

fn cell_s(lo: f32, len: f32, d: u32, k: u32) -> vec2<f32> {
    let w = exp2(-f32(d));
    let t0 = f32(k) * w;
    return vec2<f32>(lo + len * t0, lo + len * (t0 + w));
}

// Closing in on the unique root of a monotone f in a bracket [a, b] (fa,
// fb: f − c at its ends, of opposite signs), down to the eps width: the
// ITP method (Oliveira and Takahashi 2020). The point after step j of a
// search that started on a cell of width w:
// - the regula falsi point,
// - pushed toward the midpoint by κ·(b − a)²/w, and by at least eps/4: a
//   secant that has all but found the root then lands just past it, and
//   the far end moves too (plain regula falsi keeps one end for good;
//   Illinois halves its value, a step more for smooth f and many more
//   where f is steep, as x^200 at a superquadric's face),
// - kept within r_j of the midpoint, so that the search never takes more
//   than one step beyond bisection's: r_j = eps/2 · 2^(n − j) − (b − a)/2,
//   with n bisection's steps from w down to eps, plus one.
// Counted in steps a hit on the 16 Knoll surfaces: fewer than Illinois on
// each, and half as many on the superquadric (whose worst pixels gain
// most). κ = 0.1 took fewer on the polynomials and more on the
// transcendental surfaces, whose steps cost most (cloth and water);
// κ = 0.05 keeps those as few as Illinois.
const ITP_KAPPA: f32 = 0.05;
// What every step of a search on a cell of width w uses: κ/w, and the
// power of two at or above w/eps from the bits (its mantissa rounded up
// into the exponent; no exp2 or log2, which cost lavapipe more than a cheap
// f's evaluation). Worked out once per search: lavapipe does not move loop-
// invariant divisions out of a loop.
struct ItpCell { kw: f32, up: u32 }
fn itp_cell(w: f32, eps: f32) -> ItpCell {
    return ItpCell(ITP_KAPPA / w, (bitcast<u32>(w / eps) + 0x007fffffu) & 0xff800000u);
}
fn itp_point(a: f32, b: f32, fa: f32, fb: f32, j: u32, c: ItpCell, eps: f32) -> f32 {
    let mid = 0.5 * (a + b);
    let m = (a * fb - b * fa) / (fb - fa);
    let push = max(c.kw * (b - a) * (b - a), 0.25 * eps);
    // (a NaN secant fails the test and leaves the midpoint)
    var t = mid;
    if (m > a && m < b && push <= abs(mid - m)) { t = m + sign(mid - m) * push; }
    // r_j = eps/2 · 2^(n − j) − (b − a)/2, 2^n from c.up.
    let r = 0.5 * eps * bitcast<f32>(c.up + ((1u - min(j, 40u)) << 23u)) - 0.5 * (b - a);
    return select(mid - sign(mid - t) * r, t, abs(t - mid) <= r);
}

//!splice:cells

// The mean-value form (both cell variants): f on the cell [c.x, c.y] lies in f(m) + D·[-h, h]
// with m its midpoint (fm = f(m)), h its half width (the larger distance from
// m to an end, where m is not the exact midpoint) and D the enclosure of
// f's slope along the ray, which the monotonicity test computed anyway (the
// mean value theorem; min, max and abs have slopes in the hull D, jumps and
// poles give D the whole line). Its excess over f's true range shrinks with
// h² where the natural enclosure's shrinks with h, so it rejects cells that
// merely pass near the surface in far fewer levels. The result is
// intersected with the natural enclosure `r`, padded by the f32 error of
// f(m).
fn mean_value(c: vec2<f32>, r: vec2<f32>, D: vec2<f32>, fm: f32, m: f32) -> vec2<f32> {
    let spread = max(abs(D.x), abs(D.y)) * max(m - c.x, c.y - m) + 1e-6 * (abs(r.x) + abs(r.y)) + 1e-6 * abs(fm);
    if (!(abs(fm) < F.inf && spread < F.inf)) { return r; }
    return vec2<f32>(max(r.x, fm - spread), min(r.y, fm + spread));
}

// Cells looked ahead for a sign change when a leaf's refinement finds none.
const LOOKAHEAD: u32 = 16u;

//!splice:shading



// Depths from the start of slab k0 to the end of slab k1 of the depth range
// dr (the last slab ends exactly at dr.y).
fn slab_span(dr: vec2<f32>, k0: u32, k1: u32) -> vec2<f32> {
    let ds = (dr.y - dr.x) / f32(SLABS);
    return vec2<f32>(dr.x + ds * f32(k0), select(dr.x + ds * f32(k1 + 1u), dr.y, k1 == SLABS - 1u));
}

// Depth range [s_near, s_far] of the domain (box, or box and clip ball)
// along the forward axis.
// The eight corners are written out, not looped over, for kernels made with
// naga's loop counter (user `--inline` WGSL, `gpu::Author`): lavapipe
// unrolls this loop and then needs one more round of its whole optimisation
// loop per corner to fold the counter's tests away.
fn corner_depth(m: vec3<bool>) -> f32 {
    return dot(select(F.box_min.xyz, F.box_max.xyz, m) - F.eye.xyz, F.forward.xyz);
}
fn depth_range() -> vec2<f32> {
    let s0 = corner_depth(vec3<bool>(false, false, false));
    let s1 = corner_depth(vec3<bool>(true, false, false));
    let s2 = corner_depth(vec3<bool>(false, true, false));
    let s3 = corner_depth(vec3<bool>(true, true, false));
    let s4 = corner_depth(vec3<bool>(false, false, true));
    let s5 = corner_depth(vec3<bool>(true, false, true));
    let s6 = corner_depth(vec3<bool>(false, true, true));
    let s7 = corner_depth(vec3<bool>(true, true, true));
    var lo = min(min(min(s0, s1), min(s2, s3)), min(min(s4, s5), min(s6, s7)));
    var hi = max(max(max(s0, s1), max(s2, s3)), max(max(s4, s5), max(s6, s7)));
    let radius = F.box_max.w;
    if (radius > 0.0) {
        let s = dot(0.5 * (F.box_min.xyz + F.box_max.xyz) - F.eye.xyz, F.forward.xyz);
        lo = max(lo, s - radius);
        hi = min(hi, s + radius);
    }
    return vec2<f32>(max(lo, 1e-6 * max(hi, 1.0)), hi);
}


// Per-invocation bookkeeping shared by primary and secondary rays.
var<private> g_budget: u32;
var<private> g_evals: u32;
// Where the primary ray's bisection is (set by traverse for every cell): the
// start of the segment being bisected (f32 bits) and its cell d | k << 5.
// Where an interpreted field stops at its work limit, the next round resumes
// at that very cell, without descending to it again (a descent costs an
// enclosure a level, and a long tape only affords a dozen evaluations a
// round); everything before the cell is proven free of the surface.
var<private> g_at: vec2<u32>;
// The cell traverse starts at when its segment starts at g_resume.x (one
// use: RESUME_NONE afterwards).
var<private> g_resume: vec2<u32>;
const RESUME_NONE: u32 = 0xffffffffu;
// Only a lone primary ray resumes: secondary rays reuse traverse (and
// g_at), and layers would need their own state.
// CELLS_ROUNDS (the cells part): whether the host runs several rounds of
// `main` (an interpreted field); a compiled field never touches `resume`.
const RESUMABLE: bool = LAYERS == 1u && !SHADOWS && REFLECT == 0u;

// The d_max of a segment of world length `len` (through i32: see
// pack_levels).
fn depth_for(len: f32) -> u32 {
    return bitcast<u32>(i32(clamp(ceil(log2(len / F.eps)), 0.0, 18.0)));
}

// The 64-bit mask of bits [0, n), n in 0..=64 (as two u32: low, high).
fn bits_below(n: u32) -> vec2<u32> {
    let lo = select(0xffffffffu, (1u << (n & 31u)) - 1u, n < 32u);
    let hi = select(0u, select(0xffffffffu, (1u << (n & 31u)) - 1u, n < 64u), n > 32u);
    return vec2<u32>(lo, hi);
}
// The lowest set bit of a 64-bit mask (64 when none).
fn lowest_bit(v: vec2<u32>) -> u32 {
    return select(32u + countTrailingZeros(v.y), countTrailingZeros(v.x), v.x != 0u);
}

// The next run of consecutive candidate slabs in `m` (taken out of it),
// clipped to `lim`: its depths (lo, hi), or lo >= hi when none is left.
// Bit arithmetic instead of loops over the bits: this runs on every cell
// of every lane under lavapipe's masks.
fn next_run(m: ptr<function, vec2<u32>>, lim: vec2<f32>, dr: vec2<f32>) -> vec2<f32> {
    loop {
        if ((*m).x == 0u && (*m).y == 0u) { return vec2<f32>(1.0, 0.0); }
        let k = lowest_bit(*m);
        let end = lowest_bit(~(*m) & ~bits_below(k)); // one past the run
        *m = *m & ~bits_below(end);
        let span = slab_span(dr, k, end - 1u);
        let lo = max(lim.x, span.x);
        let hi = min(lim.y, span.y);
        if (lo < hi) { return vec2<f32>(lo, hi); }
    }
    return vec2<f32>(1.0, 0.0);
}

// A secondary ray (shadow, reflection) from point o along unit direction
// u, clipped to the domain, from depth s_from up to s_to; with the hit's
// gradient if `grad` (where the cells compute it, CELLS_GRADIENT).
fn trace_secondary(o: vec3<f32>, u: vec3<f32>, s_from: f32, s_to: f32, eps: f32, grad: bool) -> Hit {
    let seg = clip_domain(o, u);
    let lo = max(seg.x, s_from);
    let hi = min(seg.y, s_to);
    if (!(lo < hi)) { return no_hit(); }
    let ray = Ray(o, u, hi, eps);
    let h = traverse(ray, lo, hi, bitcast<u32>(i32(clamp(ceil(log2((hi - lo) / eps)), 0.0, 18.0))), g_budget, grad);
    g_evals = g_evals + h.evals;
    g_budget = g_budget - min(g_budget, h.iters);
    return h;
}

//!splice:modalities

// Shading of a hit with gradient g: colour mode, point light, shadow,
// reflections.
fn shade_hit(o: vec3<f32>, unit: vec3<f32>, p: vec3<f32>, g: vec3<f32>, depth: f32, iso: u32, dr: vec2<f32>) -> vec3<f32> {
    var n = normalize(g);
    if (!(dot(g, g) > 0.0)) { n = -unit; }
    if (dot(n, unit) > 0.0) { n = -n; }
    let depth01 = clamp((depth - dr.x) / max(dr.y - dr.x, 1e-20), 0.0, 1.0);
    var c = shade(p, unit, g, depth01, iso, shadow_visibility(p, n));
    let refl = reflection(p, n, unit);
    return final_color(p, unit, n, c * (1.0 - refl.w) + refl.xyz);
}

//!splice:tiles

// One invocation per pixel; a workgroup runs TILES_PER_GROUP queued 8x8
// tiles.
@compute @workgroup_size(8, 8, 4)
fn main(@builtin(local_invocation_id) lid: vec3<u32>,
        @builtin(local_invocation_index) li: u32,
        @builtin(workgroup_id) wid: vec3<u32>,
        @builtin(num_workgroups) groups: vec3<u32>) {
    // Before any lane returns (the field may count work per SIMD bundle).
    field_entry(li);
    load_uniforms();
    let dr = depth_range();
    var mask = vec2<u32>(0xffffffffu, 0xffffffffu);
    var share = 0u;
    var list = 0u;
    // With the tile pass, `main` runs over the queued tiles (indirect
    // dispatch); without it, over all tiles.
    let slot = (wid.y * groups.x + wid.x) * TILES_PER_GROUP + lid.z;
    var t = slot;
    if ((F.flags & FLAG_NO_TILE_CULLING) == 0u) {
        if (slot >= atomicLoad(&tile_list.count)) { return; }
        t = tile_ids[slot];
        let m = tile_masks[t];
        mask = m.xy;
        share = tile_share(m.z, lid.y * 8u + lid.x);
        list = m.w;
    } else if (slot >= tiles_x() * tiles_y()) {
        return;
    }
    let tile = vec2<u32>(t % tiles_x(), t / tiles_x());
    let gid = tile * 8u + tile_pixel(lid.xy);
    g_tile_frustum = tile_frustum(tile, 1u);

    // ---- Per-pixel traversal of the candidate slabs, nearest first; with
    // transparency, continued after each hit for up to LAYERS surfaces.
    if (gid.x >= F.tile_size.x || gid.y >= F.tile_size.y) { return; }
    let px = F.tile_origin + gid.xy;
    let idx = gid.y * F.tile_size.x + gid.x;
    let dir = primary_dir(px);
    let inv_len = 1.0 / length(dir);
    let unit = dir * inv_len;
    let o = F.eye.xyz;

    g_budget = U.max_iter;
    g_evals = share; // this pixel's share of the tile pass
    var rs = vec4<u32>(RESUME_NEW, 0u, 0u, 0u);
    if (CELLS_ROUNDS) { rs = resume[idx]; }
    if (rs.x == RESUME_DONE) { return; } // finished in an earlier round
    var acc = vec3<f32>(0.0);
    var transmit = 1.0;
    var normal = vec3<f32>(0.0);
    var depth = F.inf;
    var status = STATUS_MISS;
    var first_iso = 0u;
    var d_ray = 0u;
    let seg = clip_domain(o, dir);
    if (seg.x < seg.y) {
        let ray = Ray(o, dir, seg.y, F.eps * inv_len);
        d_ray = depth_for((seg.y - seg.x) / inv_len);
        var s_from = seg.x;
        g_resume = vec2<u32>(0u, RESUME_NONE);
        if (rs.x == RESUME_SUSPENDED) {
            // The run that held the cell starts at rs.y: trace_primary
            // computes the same segment, and traverse starts at the cell.
            s_from = max(seg.x, bitcast<f32>(rs.y));
            g_evals = rs.z;
            g_resume = rs.yw;
        }
        g_at = vec2<u32>(bitcast<u32>(s_from), 0u);
        for (var layer = 0u; layer < LAYERS; layer = layer + 1u) {
            // Inside the tile's candidate slabs the field may run its
            // program for the tile; shading leaves them (shadow and
            // reflection rays). The hit's gradient stays: a compiled
            // field's term lists hold over slabs padded for its stencil
            // (fields/loop_tiles.wgsl); a tape's cells found it already.
            field_enter_tile(list);
            let hit = trace_primary(ray, mask, s_from, seg, dr, inv_len);
            field_in_tile(true);
            let surface = g_surface;
            let p = o + dir * hit.s;
            let dist = hit.s / inv_len;
            var g = vec3<f32>(0.0);
            if (hit.status != STATUS_MISS) { g = hit_gradient(hit, p); }
            field_leave_frustum();
            if (hit.status == STATUS_MISS) { break; }
            var c = shade_hit(o, unit, p, g, hit.s, hit.iso + surface, dr);
            g_surface = surface;
            if (hit.status == STATUS_UNRESOLVED) { c = unresolved_color(c, px); }
            if (layer == 0u) {
                status = hit.status;
                depth = dist;
                first_iso = hit.iso + surface;
                normal = select(-unit, normalize(g), dot(g, g) > 0.0);
            }
            let alpha = select(1.0, U.opacity, LAYERS > 1u);
            acc = acc + transmit * alpha * c;
            transmit = transmit * (1.0 - alpha);
            if (hit.status == STATUS_UNRESOLVED) { break; }
            // Continue behind this surface, past its eps cell.
            s_from = hit.s + 2.0 * ray.eps_s;
        }
    }
    // Resumable: the next round takes the ray on at the cell g_at. A
    // resumed pixel that stopped at the cell it resumed at (one cell's work
    // is past the limit) is given up: more rounds would repeat it.
    let stuck = rs.x == RESUME_SUSPENDED && all(g_at == rs.yw);
    if (CELLS_ROUNDS) {
        resume[idx] = vec4<u32>(select(RESUME_DONE, RESUME_SUSPENDED, RESUMABLE && field_exhausted() && !stuck), g_at.x, g_evals, g_at.y);
    }
    if (field_exhausted()) {
        // An interpreted field gave up on an evaluation (its work limit):
        // nothing this pixel found is proven.
        status = STATUS_UNRESOLVED;
        acc = unresolved_color(acc + transmit * background(unit), px);
        transmit = 0.0;
    }
    var color = vec4<f32>(acc + transmit * background(unit), select(0.0, 1.0, status != STATUS_MISS));
    write_pixel(idx, color.xyz, status, normal, depth, pack_info(g_evals, d_ray, first_iso));
}

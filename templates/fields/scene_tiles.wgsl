// The scene field's pre-passes (before the traversal, every dispatch):
// which primitives matter to each 8x8 tile and at which depths, and the
// pruned trees the tile's rays then evaluate, one per depth slab. Zanni
// 2024 builds a tile A-buffer with depth ranges and synchronises a tile's
// rays over them; here a tile's list holds every primitive whose augmented
// bounding sphere (the bounding volume of {f_p <= r_p+}) meets the tile's
// frustum, with the depths the sphere spans, and the pruned trees of the tile's
// depth slabs are built here, once per tile and slab, for the trace to
// read: each ray walks the slabs on its own (no workgroup barriers in the
// tracing kernel), or with `--scene-walk tile` the tile's rays walk them
// together, each slab's pruned tree copied into workgroup memory (scene_sync.wgsl).
//
// Why it is exact: a primitive missing from a slab's pruned tree has its region
// {f_p <= r_p+} outside the frustum or outside the slab's padded depths, so
// no ray of the tile meets its surface there, and the sparse (masked) field
// agrees with the full one where it matters (the ranges of interest, eq.
// 13-16); within that part of the frustum it is a distance bound of the
// same surface (scene.wgsl clamps it to the slab).

// scene_tile_prims, scene_tile_count, scene_tile_pruned (field group,
// src/field/scene/source.rs): per tile, active primitives appended here (up to SCENE_TILE_MAX), their
// count (may exceed the maximum: overflow), and SCENE_PRUNED_MAX words of
// the slab table and the pruned trees (scene.wgsl), which the host copies
// into the texture the trace reads them from.
// scene_tile_len: per tile, for the statistics, the total length of its slabs' pruned trees with
// the slab count in bits 24-27 and bit 28 set for a union or comb tile, or
// SCENE_WHOLE_TREE when the tile evaluates the whole tree (its list
// overflowed); and the active count.
// scene_tile_depth: per entry of scene_tile_prims, the view depths (z along the camera's
// forward axis) its primitive's ball spans.

fn scene_tiles_x() -> u32 { return (F.tile_size.x + 7u) / 8u; }
fn scene_tiles_y() -> u32 { return (F.tile_size.y + 7u) / 8u; }

// Can the ball (c, r) meet the frustum through pixel directions su x sv
// (screen coordinates at unit depth)? Conservative: the four side planes
// and the eye plane.
fn ball_meets_frustum(c: vec3<f32>, r: f32, su: vec2<f32>, sv: vec2<f32>) -> bool {
    let q = c - F.eye.xyz;
    let x = dot(q, F.right.xyz);
    let y = dot(q, F.up.xyz);
    let z = dot(q, F.forward.xyz);
    if (z < -r) { return false; }
    // Plane through the eye containing the right axis's screen limit sx:
    // points with x - sx z <= 0 are left of it (normal (1, 0, -sx)).
    let dl = (su.x * z - x) / sqrt(1.0 + su.x * su.x);
    let dr = (x - su.y * z) / sqrt(1.0 + su.y * su.y);
    let db = (sv.x * z - y) / sqrt(1.0 + sv.x * sv.x);
    let dt = (y - sv.y * z) / sqrt(1.0 + sv.y * sv.y);
    return dl <= r && dr <= r && db <= r && dt <= r;
}

// Screen coordinate sx of pixel column i (centre), and its inverse.
fn scene_sx(i: f32) -> f32 { return ((i + 0.5) / f32(F.size.x) * 2.0 - 1.0) * F.tan_half_fov * f32(F.size.x) / f32(F.size.y); }
fn scene_col(sx: f32) -> f32 { return (sx / (F.tan_half_fov * f32(F.size.x) / f32(F.size.y)) + 1.0) * 0.5 * f32(F.size.x) - 0.5; }
fn scene_row(sy: f32) -> f32 { return (1.0 - sy / F.tan_half_fov) * 0.5 * f32(F.size.y) - 0.5; }

// The radius of a primitive's ball as the tiles see it. A traversal may
// stop where f is below its termination width, not only at f = 0 (sphere
// tracing's screen-space criterion: half a pixel at the depth): the ball
// grows by that much, so a near miss of a primitive is seen as with the
// whole tree.
fn scene_reach(ball: vec4<f32>) -> f32 {
    let z = dot(ball.xyz - F.eye.xyz, F.forward.xyz);
    return ball.w + max(F.eps, 2.0 * F.tan_half_fov / f32(F.size.y) * max(z + ball.w, 0.0));
}

// The smallest of a, b and the ball around their lens: a ball holding
// their intersection (a radius < 0: they do not meet). The lens's circle
// bounds it when each centre is on its own side of the circle's plane.
// Padded for f32's errors: h^2 = a^2 - x^2 cancels for a thin lens.
fn scene_meet(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    if (!(b.w < F.inf)) { return a; }
    if (!(a.w < F.inf)) { return b; }
    let d = length(b.xyz - a.xyz);
    if (d > a.w + b.w) { return vec4<f32>(a.xyz, -1.0); }
    var best = select(a, b, b.w < a.w);
    let x = (d * d + a.w * a.w - b.w * b.w) / (2.0 * d);
    if (d > 0.0 && x >= 0.0 && x <= d) {
        let e = 1e-6 * (d + a.w + b.w);
        let h = sqrt(max(a.w * a.w - x * x, 0.0) + 4.0 * a.w * e) + e;
        if (h < best.w) { best = vec4<f32>(a.xyz + (b.xyz - a.xyz) * (x / d), h); }
    }
    return best;
}

// Where primitive k can matter, widened by the termination width
// (scene_reach): its ABV's ball met with its limit ball (src/scene/reach.rs),
// each widened first. A radius < 0: nowhere.
fn scene_tight_ball(k: u32) -> vec4<f32> {
    let a = scene_balls[2u * k];
    let l = scene_balls[2u * k + 1u];
    return scene_meet(vec4<f32>(a.xyz, scene_reach(a)), vec4<f32>(l.xyz, select(l.w, scene_reach(l), l.w < F.inf)));
}

// Pass 1, one invocation per primitive: the tiles whose frustum its ball
// meets, from the ball's projected screen rectangle; append it there.
@compute @workgroup_size(64)
fn scene_scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    load_uniforms();
    let k = gid.x + gid.y * 65535u * 64u;
    // The primitive count, not the buffer's length (its padding).
    if (k >= scene_prim_count()) { return; }
    let ball = scene_tight_ball(k);
    if (ball.w < 0.0) { return; }
    let node = scene_prims[k];
    let nx = scene_tiles_x();
    let ny = scene_tiles_y();
    var t0 = vec2<u32>(0u);
    var t1 = vec2<u32>(nx - 1u, ny - 1u);
    let q = ball.xyz - F.eye.xyz;
    let z = dot(q, F.forward.xyz);
    let r = ball.w;
    if (abs(r) < F.inf && z - r > 1e-6 * max(z, 1.0)) {
        // In front of the eye: bound x / z and y / z over the ball.
        let x = dot(q, F.right.xyz);
        let y = dot(q, F.up.xyz);
        let sx0 = (x - r) / select(z + r, z - r, x - r < 0.0);
        let sx1 = (x + r) / select(z - r, z + r, x + r < 0.0);
        let sy0 = (y - r) / select(z + r, z - r, y - r < 0.0);
        let sy1 = (y + r) / select(z - r, z + r, y + r < 0.0);
        let c0 = floor(scene_col(sx0)) - f32(F.tile_origin.x);
        let c1 = ceil(scene_col(sx1)) - f32(F.tile_origin.x);
        let r0 = floor(scene_row(sy1)) - f32(F.tile_origin.y);
        let r1 = ceil(scene_row(sy0)) - f32(F.tile_origin.y);
        if (c1 < 0.0 || r1 < 0.0 || c0 > f32(F.tile_size.x) || r0 > f32(F.tile_size.y)) { return; }
        t0 = vec2<u32>(u32(max(c0, 0.0)) / 8u, u32(max(r0, 0.0)) / 8u);
        t1 = min(vec2<u32>(u32(max(c1, 0.0)) / 8u, u32(max(r1, 0.0)) / 8u), vec2<u32>(nx - 1u, ny - 1u));
    } else if (abs(r) < F.inf && z < -r) {
        return; // wholly behind the eye
    }
    for (var ty = t0.y; ty <= t1.y; ty = ty + 1u) {
        for (var tx = t0.x; tx <= t1.x; tx = tx + 1u) {
            let fr = tile_frustum(vec2<u32>(tx, ty), 1u);
            if (abs(r) < F.inf && !ball_meets_frustum(ball.xyz, r, fr.xy, fr.zw)) { continue; }
            let t = ty * nx + tx;
            let slot = atomicAdd(&scene_tile_count[t], 1u);
            if (slot < SCENE_TILE_MAX) {
                scene_tile_prims[t * SCENE_TILE_MAX + slot] = node;
                scene_tile_depth[t * SCENE_TILE_MAX + slot] = vec2<f32>(z - r, z + r);
            }
        }
    }
}

fn scene_is_left(i: u32) -> bool { return ((scene_node(i).x >> 30u) & 1u) != 0u; }
fn scene_fast(i: u32) -> u32 { return scene_node(i).z; }

// Swaps entries i and j of the list at `base` (nodes and depths).
fn scene_swap(base: u32, i: u32, j: u32) {
    let n = scene_tile_prims[base + i];
    let d = scene_tile_depth[base + i];
    scene_tile_prims[base + i] = scene_tile_prims[base + j];
    scene_tile_depth[base + i] = scene_tile_depth[base + j];
    scene_tile_prims[base + j] = n;
    scene_tile_depth[base + j] = d;
}

// Moves entry `start` down the max-heap of node indices over [0, end).
fn scene_sift(base: u32, start: u32, end: u32) {
    var root = start;
    loop {
        var c = 2u * root + 1u;
        if (c >= end) { break; }
        if (c + 1u < end && scene_tile_prims[base + c] < scene_tile_prims[base + c + 1u]) { c = c + 1u; }
        if (scene_tile_prims[base + root] >= scene_tile_prims[base + c]) { break; }
        scene_swap(base, root, c);
        root = c;
    }
}

// Loop iterations of the pruning pass's traversals so far, for this tile:
// past SCENE_PRUNE_WORK a pruned tree is not built (the tile falls back to fewer
// slabs, then to the whole tree) rather than cut short by lavapipe's loop
// cap (65,535 iterations, the heap sort included).
const SCENE_PRUNE_WORK: u32 = 40000u;
var<private> g_prune_work: u32;

// Is entry j of a tile's list in the depths [lo, hi]?
fn scene_in_slab(j: u32, lo: f32, hi: f32) -> bool {
    let d = scene_tile_depth[j];
    return d.x <= hi && d.y >= lo;
}

// The first entry from `k` on of the tile's list (base, count) in [lo, hi].
fn scene_next_member(base: u32, count: u32, k0: u32, lo: f32, hi: f32) -> u32 {
    var k = k0;
    loop {
        if (k >= count || scene_in_slab(base + k, lo, hi)) { break; }
        k = k + 1u;
    }
    g_prune_work = g_prune_work + (k - k0) + 1u;
    return k;
}

// The sparse bottom-up traversal over the tree's structure only (which
// operands are missing depends on the tree, not on field values) for the
// entries of the tile's node-sorted list (base, count) in depths [lo, hi],
// writing the pruned tree, the post-order node list the slab's rays
// evaluate, from word `at` (at most `room` words). Fast ancestors and
// clamping after Zanni §5.1 (as reconstructed and checked in
// src/scene/sparse.rs). Returns (length, 1 when it fitted).
fn scene_build_pruned(base: u32, count: u32, lo: f32, hi: f32, at: u32, room: u32) -> vec2<u32> {
    let n = scene_node_count();
    let root = n - 1u;
    var vlen = 0u;
    var s_present: array<bool, SCENE_MAX_STACK>;
    var s_anc: array<u32, SCENE_MAX_STACK>;
    var s_start: array<u32, SCENE_MAX_STACK>;
    var sp = 0u;
    var present = false;
    var ok = true;
    var k = scene_next_member(base, count, 0u, lo, hi);
    loop {
        if (g_prune_work > SCENE_PRUNE_WORK) { ok = false; }
        if (k >= count || !ok) { break; }
        var b = scene_tile_prims[base + k];
        let k_next = scene_next_member(base, count, k + 1u, lo, hi);
        var nxt = n + 1u;
        if (k_next < count) { nxt = scene_tile_prims[base + k_next]; }
        k = k_next;
        if (vlen + 2u > room) { ok = false; break; }
        present = true;
        var start = vlen;
        scene_tile_pruned[at + vlen] = scene_entry(b);
        vlen = vlen + 1u;
        loop {
            if (b == root) { break; }
            g_prune_work = g_prune_work + 1u;
            if (g_prune_work > SCENE_PRUNE_WORK) { ok = false; break; }
            var anc = scene_fast(b);
            if (sp > 0u) { anc = min(anc, s_anc[sp - 1u]); }
            if (anc > nxt) {
                if (sp >= SCENE_MAX_STACK) { ok = false; break; }
                s_present[sp] = present; s_anc[sp] = anc; s_start[sp] = start;
                sp = sp + 1u;
                break;
            }
            let m = anc;
            let left = scene_is_left(b);
            let pop_a = sp > 0u && !left && s_anc[sp - 1u] == m;
            let pop_b = sp > 0u && !left && (scene_is_left(m) || m == root) && min(scene_fast(m), s_anc[sp - 1u]) >= s_anc[sp - 1u] && !pop_a;
            var lp = false;
            var rp = false;
            if (pop_a || pop_b) {
                sp = sp - 1u;
                lp = s_present[sp];
                rp = present;
                start = s_start[sp];
            } else if (left) {
                lp = present;
            } else {
                rp = present;
            }
            let kind = node_type(scene_node(m).x);
            // A unary node (its operand is a left one) needs only that.
            if (lp && (rp || kind >= NODE_OFFSET)) {
                if (vlen >= room) { ok = false; break; }
                present = true;
                // A sharp operator whose right operand is a plain leaf (the
                // last entry, its operand's root) is fused into it.
                let last = scene_tile_pruned[at + vlen - 1u];
                let sharp = kind == NODE_UNION || kind == NODE_INTERSECTION || kind == NODE_DIFFERENCE;
                if (rp && sharp && (last >> 31u) != 0u && entry_type(last) == 0u) {
                    scene_tile_pruned[at + vlen - 1u] = last | (kind << SCENE_ENTRY_ROW_BITS);
                } else {
                    scene_tile_pruned[at + vlen] = scene_entry(m);
                    vlen = vlen + 1u;
                }
            } else {
                // Binary codes come three a style: union, intersection, difference.
                let cls = (kind - NODE_UNION) % 3u;
                if (kind < NODE_OFFSET && cls == 0u) {
                    present = lp || rp;
                } else if (kind < NODE_OFFSET && cls == 2u) {
                    present = lp;
                } else {
                    present = false;
                }
                if (!present) { vlen = start; }
            }
            b = m;
        }
    }
    // A stack overflow (or a bug) leaves the stack non-empty: not fitted.
    // An empty pruned tree (nothing present) means no surface in the slab.
    return vec2<u32>(select(0u, vlen, present), select(0u, 1u, ok && sp == 0u));
}

// Four words of a tile's slab table (scene.wgsl), at tile word w.
fn scene_table_write(w: u32, v: vec4<u32>) {
    scene_tile_pruned[w] = v.x;
    scene_tile_pruned[w + 1u] = v.y;
    scene_tile_pruned[w + 2u] = v.z;
    scene_tile_pruned[w + 3u] = v.w;
}

// Writes the balls of the tile's list (base, count) from tile word `at`
// (centre, radius as scene_reach widens it; four words each) when there are
// at most SCENE_RAY_BALLS, all finite, and they fit in `room` (their
// scene_tight_ball, as the scatter listed them). Returns the
// word the slab table keeps for field_ray_range: their offset `off` in the
// tile's words and their count << 16, or 0 for none (the ray then takes the
// tile's depths alone).
fn scene_write_balls(base: u32, count: u32, at: u32, room: u32, off: u32) -> u32 {
    if (count > SCENE_UNION_MAX || 4u * count > room) { return 0u; }
    for (var i = 0u; i < count; i = i + 1u) {
        let ball = scene_tight_ball(scene_node(scene_tile_prims[base + i]).w);
        if (!(ball.w < F.inf)) { return 0u; }
        scene_table_write(at + 4u * i, bitcast<vec4<u32>>(ball));
    }
    return off | (count << 16u);
}

// The margin of a tile whose primitives span view depths [lo, hi]: 2 % of
// the depths, and no less than a few pixels there (so that a step clamped
// near a slab's end stays well above the termination width).
fn scene_margin(lo: f32, hi: f32) -> f32 {
    let pixel = 2.0 * F.tan_half_fov / f32(F.size.y) * max(hi, 0.0);
    return max(0.02 * (hi - lo), max(8.0 * pixel, 4.0 * F.eps));
}

// A union tile: a list of at most SCENE_UNION_MAX primitives, each with
// only sharp unions above it (NODE_UNION_PATH_BIT) and a finite ball. The
// tile's field is then the least of its members' values, and so is a
// ray's over the members whose balls it meets (the others' surfaces are
// off the ray, as a primitive off the tile's frustum is off its rays): the
// pruned tree is the members' leaves, in any order, and their balls follow it, so
// each ray picks its own members (scene.wgsl, field_ray_range) and
// evaluates only those, the whole depth range in one slab.
//
// A comb tile (`comb`; its list sorted by node index): every member hangs
// off the tree's left spine of union-style operators (NODE_COMB_BIT), so
// the pruned tree of any of its subsets is a chain in post-order, each
// member after the first joined by its own operator (the sparse rule: an
// operator with one operand present is that operand). The pruned tree holds two
// words a member, its leaf and its operator, and a ray evaluates the
// chain of its own members. Writes the tile's table and returns true, or
// false for a tile that is neither.
fn scene_chain_tile(t: u32, base: u32, count: u32, tb: u32, comb: bool) -> bool {
    if (count == 0u || count > SCENE_UNION_MAX) { return false; }
    let bit = select(NODE_UNION_PATH_BIT, NODE_COMB_BIT, comb);
    var front = F.inf;
    var back = -F.inf;
    for (var i = 0u; i < count; i = i + 1u) {
        if ((scene_node(scene_tile_prims[base + i]).x & bit) == 0u) { return false; }
        let dv = scene_tile_depth[base + i];
        front = min(front, dv.x);
        back = max(back, dv.y);
    }
    let words = select(count, 2u * count, comb);
    let vbase = tb + SCENE_TABLE_WORDS;
    let balls = scene_write_balls(base, count, vbase + words, SCENE_PRUNED_MAX - SCENE_TABLE_WORDS - words, SCENE_TABLE_WORDS + words);
    if (balls == 0u) { return false; }
    for (var i = 0u; i < count; i = i + 1u) {
        let b = scene_tile_prims[base + i];
        if (comb) {
            // The bottom leaf's parent is not its own operator, but it is
            // the spine's first node: never joined (nothing comes before).
            scene_tile_pruned[vbase + 2u * i] = scene_entry(b);
            scene_tile_pruned[vbase + 2u * i + 1u] = scene_entry(min(scene_node(b).x & NODE_PARENT_MASK, scene_node_count() - 1u));
        } else {
            scene_tile_pruned[vbase + i] = scene_entry(b);
        }
    }
    let margin = scene_margin(front, back);
    let mode = select(SCENE_UNION_TILE, SCENE_COMB_TILE, comb);
    scene_table_write(tb, vec4<u32>(1u, bitcast<u32>(margin), bitcast<u32>(front - margin), bitcast<u32>(back + margin)));
    scene_table_write(tb + 4u, vec4<u32>(SCENE_TABLE_WORDS, words, bitcast<u32>(-F.inf), balls | mode));
    // Statistics: one slab, and bit 28 for a chain tile.
    scene_tile_len[t] = vec2<u32>(words | (1u << 24u) | (1u << 28u), count);
    return true;
}

// Pass 2, one invocation per tile: sort the tile's active primitives by
// node index, cut the depths they span into up to SCENE_SLABS_MAX slabs of
// equal depth (Zanni's depth ranges; one slab for a short list), and write
// each slab's pruned tree. A slab's members are the primitives whose depths
// meet the slab widened by a margin: its pruned tree is then exact a margin beyond
// the slab, so a ray's steps never stop at a slab's end (the field clamps
// them to the widened slab, scene.wgsl). Views that do not fit fall back
// to one slab, a list that overflowed or a stack too deep to the whole tree.
@compute @workgroup_size(64)
fn scene_prune(@builtin(global_invocation_id) gid: vec3<u32>) {
    load_uniforms();
    let t = gid.x;
    let nt = scene_tiles_x() * scene_tiles_y();
    if (t >= nt) { return; }
    let count = atomicLoad(&scene_tile_count[t]);
    let tb = t * SCENE_PRUNED_MAX;
    if (count > SCENE_TILE_MAX || (F.flags & FLAG_SCENE_FULL) != 0u) {
        scene_table_write(tb, vec4<u32>(0u));
        scene_tile_len[t] = vec2<u32>(SCENE_WHOLE_TREE, count);
        return;
    }
    let base = t * SCENE_TILE_MAX;
    // The depths the list spans.
    var zlo = F.inf;
    var zhi = -F.inf;
    var front = F.inf;
    var back = -F.inf;
    for (var i = 0u; i < count; i = i + 1u) {
        let dv = scene_tile_depth[base + i];
        if (abs(dv.x) < F.inf) { zlo = min(zlo, dv.x); }
        if (abs(dv.y) < F.inf) { zhi = max(zhi, dv.y); }
        front = min(front, dv.x);
        back = max(back, dv.y);
    }
    // A union chain is tried on the list as the scatter left it, a comb on
    // the list sorted, from one call site of scene_chain_tile (as
    // scene_build_pruned and scene_sift have one each below): lavapipe
    // inlines every call, and compiles each copy anew at a noticeable
    // cost.
    for (var round = 0u; round < 2u; round = round + 1u) {
        if (round == 1u) {
            // A heap sort by node index (its iterations are bounded by
            // 2 n log2 n whatever the order the scatter's atomics left: an
            // insertion sort of 459 entries ran past lavapipe's silent loop
            // cap, leaving lists unsorted depending on that order).
            // Heapify (i from count / 2 down), then take the top down (e
            // from count): one loop, one call site of scene_sift.
            var i = count / 2u;
            var e = count;
            loop {
                let heapify = i > 0u;
                if (!heapify && e <= 1u) { break; }
                if (heapify) {
                    i = i - 1u;
                } else {
                    e = e - 1u;
                    scene_swap(base, 0u, e);
                }
                scene_sift(base, select(0u, i, heapify), select(e, count, heapify));
            }
        }
        if (scene_chain_tile(t, base, count, tb, round == 1u)) { return; }
    }
    let margin = scene_margin(zlo, zhi);
    var slabs = select(1u, SCENE_SLABS_MAX, count > SCENE_SLAB_MIN_LIST && zhi > zlo);
    // The pruned trees follow the slab table; offsets count from the tile's start.
    let vbase = tb + SCENE_TABLE_WORDS;
    let room = SCENE_PRUNED_MAX - SCENE_TABLE_WORDS;
    var total = 0u;
    var fitted = true;
    var k = 0u;
    loop {
        if (k >= slabs) { break; }
        let c0 = select(zlo + (zhi - zlo) * f32(k) / f32(slabs), -F.inf, k == 0u);
        let c1 = select(zlo + (zhi - zlo) * f32(k + 1u) / f32(slabs), F.inf, k + 1u == slabs);
        let r = scene_build_pruned(base, count, c0 - margin, c1 + margin, vbase + total, room - total);
        if (r.y == 0u) {
            // The slabs' pruned trees do not fit: one pruned tree of the whole list
            // instead, from the start.
            if (slabs > 1u) {
                slabs = 1u;
                total = 0u;
                k = 0u;
                continue;
            }
            fitted = false;
            break;
        }
        scene_table_write(tb + 4u * (k + 1u), vec4<u32>(SCENE_TABLE_WORDS + total, r.x, bitcast<u32>(c0), 0u));
        total = total + r.x;
        k = k + 1u;
    }
    if (!fitted) {
        scene_table_write(tb, vec4<u32>(0u));
        scene_tile_len[t] = vec2<u32>(SCENE_WHOLE_TREE, count);
        return;
    }
    // The depths where the tile's primitives are: no surface lies outside
    // them in the tile's frustum, so primary rays are traced only there
    // (eq. 21-22 at the ends of the list; an empty list: no steps at all).
    scene_table_write(tb, vec4<u32>(slabs, bitcast<u32>(margin), bitcast<u32>(front - margin), bitcast<u32>(back + margin)));
    // A short list's balls after the pruned trees, for each ray's own range.
    scene_tile_pruned[tb + 7u] = select(0u, scene_write_balls(base, count, vbase + total, room - total, SCENE_TABLE_WORDS + total), count <= SCENE_RAY_BALLS);
    // Statistics: the pruned trees' total length, the slab count in bits 24-27.
    scene_tile_len[t] = vec2<u32>(total | (slabs << 24u), count);
}

// Formula leaves on intervals (scene_formula.wgsl; bisection's kernels).

// An enclosure whose NaN ends (never from the interpreter's ops, but not
// assumed) are widened to the line.
fn scene_no_nan(r: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(select(r.x, -iso_inf(), iso_is_nan(r.x)), select(r.y, iso_inf(), iso_is_nan(r.y)));
}

// The leaf over the local box q (r2, r3: its third and fourth rows), before
// its frame's scale: the value of max(f/L, B), B the box distance, and with
// `slope` its slope along the local direction dl (else the whole line).
// f/L and f'/L come from one run of the tape's value or derivative program,
// in RAA along the cell's segment for a leaf that takes it (seg: the
// segment's local half-vector and f32 error, w < 0 for none), else on
// intervals over q; rounded outward. B by its centred form, its slope
// within [-|dl|, |dl|]; max is monotone in both, its slope ia_dmax's. An
// empty enclosure (f undefined over the whole box) is the leaf's absence,
// with no slope; a refused run is the whole line.
fn scene_leaf_ia(q: SceneBox, seg: vec4<f32>, r2: vec4<f32>, r3: vec4<f32>, dl: vec3<f32>, slope: bool) -> vec4<f32> {
    let directory = scene_use_tape(u32(r2.w));
    let affine = (SCENE_FEATURES & FEATURE_FORMULA_AFFINE) != 0u && seg.w >= 0.0 && directory.y != 0u;
    var t: vec4<f32>;
    if (affine) {
        t = scene_leaf_tape_ra(q, seg.xyz, seg.w, dl, slope);
    } else {
        let lo = scene_lo(q);
        let hi = scene_hi(q);
        t = tape_enclosure_ia(vec2<f32>(lo.x, hi.x), vec2<f32>(lo.y, hi.y), vec2<f32>(lo.z, hi.z), vec2<f32>(F.time), vec2<f32>(dl.x), vec2<f32>(dl.y), vec2<f32>(dl.z), slope);
    }
    let f = scene_no_nan(ia_pad(t.xy * r3.w, 0.0, 2.4e-7));
    let df = scene_no_nan(ia_pad(t.zw * r3.w, 0.0, 2.4e-7));
    let c = q.c - r2.xyz;
    let b = scene_centred(sd_box(c, r3.xyz), length(q.r), length(c) + length(r3.xyz));
    let m = length(dl) * (1.0 + 1e-6);
    let absent = ia_is_empty(t.xy);
    let v = select(max(f, b), vec2<f32>(iso_inf()), absent);
    let dv = select(scene_no_nan(ia_dmax(f, b, df, vec2<f32>(-m, m))), ia_whole(), absent);
    return vec4<f32>(v, dv);
}

// The segment argument of scene_leaf_ia for a leaf with frame rows r0, r1
// over the world box b: the cell's half-vector in the local frame and its
// f32 error (scene_local_box's, and the segment's ends'), or w = -1 where
// b is not a cell's segment (`along` false: a warp's box of it).
fn scene_leaf_segment(r0: vec4<f32>, r1: vec4<f32>, b: SceneBox, q: SceneBox, along: bool) -> vec4<f32> {
    let v = scene_local(r0, vec4<f32>(0.0), g_cell_half.xyz);
    let e = 2e-6 * (length(q.c) + length(v) + dot(r0, r0) * (length(b.c) + length(r1.xyz) + length(g_cell_half.xyz)));
    return select(vec4<f32>(0.0, 0.0, 0.0, -1.0), vec4<f32>(v, e), along && g_cell_half.w > 0.0);
}

// The leaf with frame rows r0, r1 over the world box b (o: its first row;
// `along`: b is the box of the cell being enclosed): scene_leaf_ia's value.
fn scene_formula_ia(r0: vec4<f32>, r1: vec4<f32>, b: SceneBox, r2: vec4<f32>, o: u32, along: bool) -> vec2<f32> {
    let q = scene_local_box(r0, r1, b);
    return scene_leaf_ia(q, scene_leaf_segment(r0, r1, b, q, along), r2, scene_param(o + 3u), vec3<f32>(0.0), false).xy;
}

// A cell of the ray o + dir·[s0, s1] where the tree being evaluated is one
// unwarped formula leaf (a tile's pruned tree, or the whole tree): the
// leaf's value and its slope along the ray (scene_leaf_ia with the ray's
// local direction, times the frame's scale s), so that the traversal's
// monotonicity test applies as it does to a formula. (1, 0, 0, 0), an
// empty value, where the tree is anything else.
fn scene_leaf_cell(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32) -> vec4<f32> {
    let len = scene_pruned_len();
    let full = len == SCENE_WHOLE_TREE;
    let n = select(len, scene_node_count(), full);
    if (n != 1u) { return vec4<f32>(1.0, 0.0, 0.0, 0.0); }
    var e: u32;
    if (full) { e = scene_entry(0u); } else { e = scene_slab_entry(0u); }
    let row = entry_row(e);
    let r0 = scene_param(row);
    let r1 = scene_param(row + 1u);
    // The whole form word: a warp's bits make it another form.
    if ((e >> 31u) == 0u || u32(r1.w) != FORM_FORMULA) { return vec4<f32>(1.0, 0.0, 0.0, 0.0); }
    let a = o + dir * s0;
    let b = o + dir * s1;
    let wb = scene_box(min(a, b), max(a, b));
    let q = scene_local_box(r0, r1, wb);
    let r = scene_leaf_ia(q, scene_leaf_segment(r0, r1, wb, q, true), scene_param(row + 2u), scene_param(row + 3u), scene_local(r0, vec4<f32>(0.0), dir), true);
    let s = 1.0 / dot(r0, r0);
    let v = ia_pad(r.xy * s, 0.0, 2.4e-7);
    let dv = ia_pad(r.zw * s, 0.0, 2.4e-7);
    // The scene's pad of a tree's enclosure (surf_ia).
    let padded = ia_pad(v, 1e-6 * (1.0 + length(0.5 * (a + b)) + length(0.5 * abs(b - a))), 1e-6);
    return vec4<f32>(select(padded, v, abs(v) >= vec2<f32>(F.inf)), dv);
}

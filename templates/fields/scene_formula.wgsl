// Formula leaves (src/scene/leaf.rs): a formula run from its tape by the
// tape interpreter (templates/fields/tape.wgsl, instantiated for the scene
// by src/field/scene/mod.rs), within a box of the leaf's frame:
// max(f / L, distance to the box). The tapes texture (src/field/scene/
// leaves.rs) holds (leaf count, 0, 0, 0), then each leaf's first texel,
// then the tapes. A leaf's rows: frame, (box centre, leaf index), (box
// half extents, 1 / L).

// Makes leaf k's tape the one tape_word reads.
fn scene_use_tape(k: u32) {
    g_tape_base = 0u;
    g_tape_base = tape_word(1u + k).x;
}

// The leaf's value at local point q (r2: its third row, o: its first).
// Where f is undefined or its run was refused, +inf: the leaf is absent
// there (and a refused run's pixel is reported by the work limit).
fn scene_formula(q: vec3<f32>, r2: vec4<f32>, o: u32) -> f32 {
    scene_use_tape(u32(r2.w));
    tape_point_s(q.x, q.y, q.z, F.time);
    let st = tape_run_s(0u);
    let r3 = scene_param(o + 3u);
    let f = tape_reg_s(tape_word(1u).x) * r3.w;
    let v = select(f, iso_inf(), st != TAPE_DONE || iso_is_nan(f));
    return max(v, sd_box(q - r2.xyz, r3.xyz));
}

// The leaf over the local box q: the tape's enclosure (scaled by 1/L and
// widened by f32's rounding of the product) and the box distance's
// centred form, joined by max (monotone in both). An empty enclosure (f
// undefined over the whole box) is the leaf's absence; a refused run is
// the whole line.
fn scene_formula_ia(q: SceneBox, r2: vec4<f32>, o: u32) -> vec2<f32> {
    scene_use_tape(u32(r2.w));
    let lo = scene_lo(q);
    let hi = scene_hi(q);
    let e = tape_enclosure_ia(vec2<f32>(lo.x, hi.x), vec2<f32>(lo.y, hi.y), vec2<f32>(lo.z, hi.z), vec2<f32>(F.time), ia_whole(), ia_whole(), ia_whole(), false).xy;
    let r3 = scene_param(o + 3u);
    // An end that is NaN (never from the interpreter's ops, but not
    // assumed) widens to the line.
    var f = e * r3.w;
    f = f + vec2<f32>(-1.0, 1.0) * 2.4e-7 * abs(f);
    f = select(f, vec2<f32>(-iso_inf(), f.y), iso_is_nan(f.x));
    f = select(f, vec2<f32>(f.x, iso_inf()), iso_is_nan(f.y));
    f = select(f, vec2<f32>(iso_inf()), e.x > e.y);
    let c = q.c - r2.xyz;
    let b = scene_centred(sd_box(c, r3.xyz), length(q.r), length(c) + length(r3.xyz));
    return max(f, b);
}

// A cell of the ray o + dir·[s0, s1] where the tree being evaluated is one
// unwarped formula leaf (a tile's pruned tree, or the whole tree): the
// leaf's value and its slope along the ray from one run of its tape's
// derivative program (f and f' along the local direction), so that the
// traversal's monotonicity test applies as it does to a formula. The
// value is s·max(f/L, B), B the box distance, whose slope lies in
// [-|dl|, |dl|] (dl the ray's local direction); max's slope is ia_dmax's.
// (1, 0, 0, 0), an empty value, where the tree is anything else.
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
    let r2 = scene_param(row + 2u);
    let r3 = scene_param(row + 3u);
    let a = o + dir * s0;
    let b = o + dir * s1;
    let q = scene_local_box(r0, r1, scene_box(min(a, b), max(a, b)));
    let dl = scene_local(r0, vec4<f32>(0.0), dir);
    scene_use_tape(u32(r2.w));
    let lo = scene_lo(q);
    let hi = scene_hi(q);
    let t = tape_enclosure_ia(vec2<f32>(lo.x, hi.x), vec2<f32>(lo.y, hi.y), vec2<f32>(lo.z, hi.z), vec2<f32>(F.time), vec2<f32>(dl.x), vec2<f32>(dl.y), vec2<f32>(dl.z), true);
    // f/L and f'/L, widened by the product's rounding; an empty value (f
    // undefined over the box) is the leaf's absence, with no slope.
    var f = t.xy * r3.w;
    f = f + vec2<f32>(-1.0, 1.0) * 2.4e-7 * abs(f);
    var df = t.zw * r3.w;
    df = df + vec2<f32>(-1.0, 1.0) * 2.4e-7 * abs(df);
    let c = q.c - r2.xyz;
    let bv = scene_centred(sd_box(c, r3.xyz), length(q.r), length(c) + length(r3.xyz));
    let m = length(dl) * (1.0 + 1e-6);
    var v = max(f, bv);
    var dv = ia_dmax(f, bv, df, vec2<f32>(-m, m));
    let s = 1.0 / dot(r0, r0);
    v = v * s + vec2<f32>(-1.0, 1.0) * 2.4e-7 * abs(v * s);
    dv = dv * s + vec2<f32>(-1.0, 1.0) * 2.4e-7 * abs(dv * s);
    let absent = t.x > t.y;
    v = select(v, vec2<f32>(F.inf), absent);
    dv = select(dv, ia_whole(), absent || iso_is_nan(dv.x) || iso_is_nan(dv.y));
    // The scene's pad of a tree's enclosure (surf_ia).
    let padded = ia_pad(v, 1e-6 * (1.0 + length(0.5 * (a + b)) + length(0.5 * abs(b - a))), 1e-6);
    return vec4<f32>(select(padded, v, abs(v) >= vec2<f32>(F.inf)), dv);
}

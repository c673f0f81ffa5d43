// Formula leaves (src/scene/leaf.rs): a formula run from its tape by the
// tape interpreter (templates/fields/tape.wgsl, instantiated for the scene
// by src/field/scene/mod.rs), within a box of the leaf's frame:
// max(f / L, distance to the box). The tapes texture (src/field/scene/
// leaves.rs) holds (leaf count, the loop iterations of a value run of every
// leaf node, summed, 0, 0), then each leaf's directory word (its first
// texel, 1 where its cells are enclosed in RAA, 0, 0), then the tapes. A
// leaf's rows: frame, (box centre, leaf index), (box half extents, 1 / L).

// Makes leaf k's tape the one tape_word reads; returns its directory word.
fn scene_use_tape(k: u32) -> vec4<u32> {
    g_tape_base = 0u;
    let w = tape_word(1u + k);
    g_tape_base = w.x;
    return w;
}

// The leaf's value at local point q (r2: its third row, o: its first).
// Where f is undefined or its run was refused, +inf: the leaf is absent
// there (and a refused run's pixel is reported by the work limit).
fn scene_formula(q: vec3<f32>, r2: vec4<f32>, o: u32) -> f32 {
    _ = scene_use_tape(u32(r2.w));
    tape_point_s(q.x, q.y, q.z, F.time);
    let st = tape_run_s(0u);
    let r3 = scene_param(o + 3u);
    let f = tape_reg_s(tape_word(1u).x) * r3.w;
    let v = select(f, iso_inf(), st != TAPE_DONE || iso_is_nan(f));
    return max(v, sd_box(q - r2.xyz, r3.xyz));
}

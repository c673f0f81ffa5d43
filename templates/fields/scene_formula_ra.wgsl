// Formula leaves in reduced affine arithmetic, for bisection's cells (a
// scene with FEATURE_FORMULA_AFFINE; scene_formula_ia.wgsl calls it).

// The tape's value and slope ranges over a cell's segment: the local
// point runs along c + e1 v (c: the segment's midpoint, v: half the
// segment, both local), so x, y and z are exact forms in the ray
// parameter e1 and correlated terms of a polynomial cancel, as RAA's do
// along a compiled formula's ray. `err` covers f32's error in c and v
// (q: the segment's local box, whose centre is c).
fn scene_leaf_tape_ra(q: SceneBox, v: vec3<f32>, err: f32, dl: vec3<f32>, slope: bool) -> vec4<f32> {
    return tape_enclosure_ra(vec3<f32>(q.c.x, v.x, err), vec3<f32>(q.c.y, v.y, err), vec3<f32>(q.c.z, v.z, err), ra_const(F.time),
        ra_const(dl.x), ra_const(dl.y), ra_const(dl.z), slope);
}

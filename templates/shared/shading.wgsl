// Shading helpers every traversal uses.

// The gradient of f by central differences with stencil h (the field
// source's scalar field: a traversal scaling it, as sphere tracing divides
// by the Lipschitz bound, changes only its length).
// One call of field in a loop, not six: a shader compiler inlines every
// call site, and on lavapipe's SIMD lanes each inlined copy costs a masked
// pass even where no lane needs it (a miss); a loop no lane enters runs
// its body once. Same arithmetic: g.x = (0 + f(p + dx)) + (-f(p - dx)).
fn gradient(p: vec3<f32>, h: f32) -> vec3<f32> {
    var g = vec3<f32>(0.0);
    for (var k = 0u; k < 6u; k = k + 1u) {
        let axis = vec3<f32>(f32(k / 2u == 0u), f32(k / 2u == 1u), f32(k / 2u == 2u));
        let s = select(1.0, -1.0, (k & 1u) == 1u);
        g = g + axis * (s * field(p + s * (axis * h)));
    }
    return g / (2.0 * h);
}

// The gradient of f at p by forward differences from f(p) = fp, known
// already (the sphere tracer's last fixed-point evaluation): three
// evaluations where central differences take six, for a direction as
// good as theirs at this h (its error is O(h) against the surface's
// curvature; h is half the hit width).
fn gradient_at(p: vec3<f32>, h: f32, fp: f32) -> vec3<f32> {
    var g = vec3<f32>(0.0);
    for (var k = 0u; k < 3u; k = k + 1u) {
        let axis = vec3<f32>(f32(k == 0u), f32(k == 1u), f32(k == 2u));
        g = g + axis * (field(p + axis * h) - fp);
    }
    return g / h;
}

// A heat map colour for v in [0, 1].
fn heat(v: f32) -> vec3<f32> {
    let x = clamp(v, 0.0, 1.0);
    return clamp(vec3<f32>(1.5 * x, 1.5 * x - 0.5, 3.0 * x - 2.0) + vec3<f32>(0.0, 0.0, 0.4 * (1.0 - x)), vec3<f32>(0.0), vec3<f32>(1.0));
}

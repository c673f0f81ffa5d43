// Shading helpers every traversal uses.

// The gradient of f by central differences with stencil h (the field
// source's scalar field: a traversal scaling it, as sphere tracing divides
// by the Lipschitz bound, changes only its length).
fn gradient(p: vec3<f32>, h: f32) -> vec3<f32> {
    let dx = vec3<f32>(h, 0.0, 0.0);
    let dy = vec3<f32>(0.0, h, 0.0);
    let dz = vec3<f32>(0.0, 0.0, h);
    return vec3<f32>(field(p + dx) - field(p - dx), field(p + dy) - field(p - dy), field(p + dz) - field(p - dz)) / (2.0 * h);
}

// A heat map colour for v in [0, 1].
fn heat(v: f32) -> vec3<f32> {
    let x = clamp(v, 0.0, 1.0);
    return clamp(vec3<f32>(1.5 * x, 1.5 * x - 0.5, 3.0 * x - 2.0) + vec3<f32>(0.0, 0.0, 0.4 * (1.0 - x)), vec3<f32>(0.0), vec3<f32>(1.0));
}

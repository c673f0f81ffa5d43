// Nodes of degree at most 2 in x, y, z restricted to a ray (src/codegen/
// ray_forms.rs): field_begin_ray works out a + b t + c t² of each along the
// ray p0 + dir t, and their magnitudes over the ray's extent in the domain,
// from which the pads come.

// 32 f32 roundings (2^-19) of the largest terms: the coefficients' own
// rounding to f32, their computation here (a handful of operations each)
// and a cell's evaluation (a + t (b + c t): three more).
const RAY_PAD: f32 = 1.9e-6;

// A v for the symmetric A of a quadratic's terms of degree 2: `sq` the
// coefficients of x², y², z², `cr` those of xy, xz, yz.
fn quad_sym(sq: vec3<f32>, cr: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    return sq * v + 0.5 * vec3<f32>(cr.x * v.y + cr.y * v.z, cr.x * v.x + cr.z * v.z, cr.y * v.x + cr.z * v.y);
}

// k + g·p + p·A p on the line p0 + d t: (a, b, c) of a + b t + c t².
fn ray_quad(k: f32, g: vec3<f32>, sq: vec3<f32>, cr: vec3<f32>, p0: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    let ap = quad_sym(sq, cr, p0);
    return vec3<f32>(k + dot(g + ap, p0), dot(g + 2.0 * ap, d), dot(d, quad_sym(sq, cr, d)));
}

// k + g·p on the line p0 + d t.
fn ray_lin(k: f32, g: vec3<f32>, p0: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(k + dot(g, p0), dot(g, d), 0.0);
}

// The vertex t_v = -b / 2c of a + b t + c t² and the value there, for
// ia_ray: a division per ray, not per cell (c = 0: not finite, never used).
fn ray_vertex(q: vec3<f32>) -> vec2<f32> {
    let tv = -0.5 * q.y / q.z;
    return vec2<f32>(tv, q.x + tv * (q.y + q.z * tv));
}

fn field_ray(o: vec3<f32>, dir: vec3<f32>, s: f32) -> f32 {
    let p = o + dir * s;
    return eval_s_ray(p.x, p.y, p.z, F.time, s - g_ray_ref);
}

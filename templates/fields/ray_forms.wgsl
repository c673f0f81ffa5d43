// Nodes of degree at most 2 in x, y, z restricted to a ray (src/field/compiled/
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

// A node of degree ≤ 2 in x, y, z restricted to the ray (src/field/compiled/
// ray_forms.rs): q = (a, b, c, pad) of a + b t + c t², v = (the slope's
// pad, the vertex t_v, the value there), worked out once per ray. Over the
// cell [t0, t1]: the values at the ends and, when t_v is inside, at the
// vertex, widened by the pad (their rounding). Exact up to that, where
// the cell's box overestimates a sum of several variables' terms.
fn ia_ray(q: vec4<f32>, v: vec3<f32>, t0: f32, t1: f32) -> vec2<f32> {
    let fa = q.x + t0 * (q.y + q.z * t0);
    let fb = q.x + t1 * (q.y + q.z * t1);
    let fv = select(fa, v.z, v.y > t0 && v.y < t1);
    return vec2<f32>(min(min(fa, fb), fv) - q.w, max(max(fa, fb), fv) + q.w);
}
// ia_ray of a node of degree 1 (c = 0, no vertex).
fn ia_ray_lin(q: vec4<f32>, v: vec3<f32>, t0: f32, t1: f32) -> vec2<f32> {
    let fa = q.x + q.y * t0;
    let fb = q.x + q.y * t1;
    return vec2<f32>(min(fa, fb) - q.w, max(fa, fb) + q.w);
}
// The slope of a node of degree 1: b widened by its pad, the same on
// every cell (v.yz, worked out with the ray).
fn ia_ray_slope_lin(q: vec4<f32>, v: vec3<f32>, t0: f32, t1: f32) -> vec2<f32> { return v.yz; }
// Its slope along the ray, b + 2 c t over the cell, widened by its pad.
fn ia_ray_slope(q: vec4<f32>, v: vec3<f32>, t0: f32, t1: f32) -> vec2<f32> {
    let sa = q.y + 2.0 * q.z * t0;
    let sb = q.y + 2.0 * q.z * t1;
    return vec2<f32>(min(sa, sb) - v.x, max(sa, sb) + v.x);
}
// A product of squares k·Q² with Q such a node (src/field/compiled/ray_forms.rs,
// `squares`): Q's range over the cell squared, times k's enclosure; its
// slope 2k·Q·Q'; its value at t.
fn ia_ray_sq(k: vec2<f32>, q: vec4<f32>, v: vec3<f32>, t0: f32, t1: f32) -> vec2<f32> {
    return ia_mul(ia_sqr(ia_ray(q, v, t0, t1)), k);
}
fn ia_ray_sq_slope(k: vec2<f32>, q: vec4<f32>, v: vec3<f32>, t0: f32, t1: f32) -> vec2<f32> {
    return ia_mul(ia_mul(ia_ray(q, v, t0, t1), ia_ray_slope(q, v, t0, t1)), 2.0 * k);
}
fn s_ray_sq(k: f32, q: vec4<f32>, v: vec3<f32>, t: f32) -> f32 {
    let a = s_ray(q, v, t);
    return k * a * a;
}
// Its value at t (the scalar domain's).
fn s_ray(q: vec4<f32>, v: vec3<f32>, t: f32) -> f32 { return q.x + t * (q.y + q.z * t); }
fn s_ray_lin(q: vec4<f32>, v: vec3<f32>, t: f32) -> f32 { return q.x + q.y * t; }

fn field_ray(o: vec3<f32>, dir: vec3<f32>, s: f32) -> f32 {
    let p = o + dir * s;
    return eval_s_ray(p.x, p.y, p.z, F.time, s - g_ray_ref);
}

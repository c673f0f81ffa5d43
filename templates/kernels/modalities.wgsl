// isotrace modalities of Knoll et al. (section 5.2): each part is spliced
// into the render kernel only when the user asks for it; otherwise the
// stub of the same name (a constant) takes its place and costs nothing.

//!part:shadows
// A shadow ray from the point light to the hit point, reparametrised like a
// primary ray and traversed with its own, coarser eps (U.light.w). Any root
// before the hit point (less a small offset, so the surface does not shadow
// itself) puts the point in shadow.
fn shadow_visibility(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let to_p = p - U.light.xyz;
    let dist = length(to_p);
    let u = to_p / dist;
    let offset = 4.0 * U.light.w;
    if (dist <= offset) { return 1.0; }
    let h = trace_secondary(U.light.xyz, u, 0.0, dist - offset, U.light.w);
    return select(1.0, 0.0, h.status != STATUS_MISS);
}
//!part:no_shadows
fn shadow_visibility(p: vec3<f32>, n: vec3<f32>) -> f32 { return 1.0; }

//!part:reflections
// Up to REFLECT mirror bounces with the same traversal; the colour of each
// bounce is weighted by U.reflectivity, and a path that leaves the domain
// sees the environment. The start point is offset along the normal so the
// ray does not find the surface it leaves.
fn reflection(p0: vec3<f32>, n0: vec3<f32>, unit0: vec3<f32>) -> vec4<f32> {
    let k = U.reflectivity;
    var p = p0;
    var n = n0;
    var u = reflect(unit0, n0);
    var acc = vec3<f32>(0.0);
    var w = k; // the weight of what the next bounce sees
    for (var b = 0u; b < REFLECT; b = b + 1u) {
        let o = p + n * (4.0 * U.eps);
        let h = trace_secondary(o, u, 0.0, U.inf, U.eps);
        if (h.status == STATUS_MISS) {
            acc = acc + w * environment(u);
            w = 0.0;
            break;
        }
        let q = o + u * h.s;
        let g = gradient(q, 0.5 * U.eps);
        var m = normalize(g);
        if (dot(m, u) > 0.0) { m = -m; }
        let c = shade(q, u, g, 0.5, h.iso, shadow_visibility(q, m));
        if (b + 1u == REFLECT) {
            acc = acc + w * c;
            w = 0.0;
        } else {
            acc = acc + w * (1.0 - k) * c;
            w = w * k;
        }
        p = q;
        n = m;
        u = reflect(u, m);
    }
    // rgb: the reflected light, already weighted; w: the share it replaces.
    return vec4<f32>(acc, k);
}
//!part:no_reflections
fn reflection(p0: vec3<f32>, n0: vec3<f32>, unit0: vec3<f32>) -> vec4<f32> { return vec4<f32>(0.0); }

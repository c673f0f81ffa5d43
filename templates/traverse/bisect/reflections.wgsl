// isotrace bisection modality, spliced into the kernel only when asked for;
// otherwise reflections_off.wgsl takes its place.
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
        let o = p + n * (4.0 * F.eps);
        let h = trace_secondary(o, u, 0.0, F.inf, F.eps, true);
        if (h.status == STATUS_MISS) {
            acc = acc + w * environment(u);
            w = 0.0;
            break;
        }
        let q = o + u * h.s;
        let g = hit_gradient(h, q);
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

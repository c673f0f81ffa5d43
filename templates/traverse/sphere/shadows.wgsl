// Sphere tracing: shadow rays, spliced in only when asked for (else shadows_off.wgsl).
// A shadow ray towards the key light from p offset along n (technique 3).
fn shadow(p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, fp: f32) -> Lit {
    if ((F.flags & FLAG_SHADOWS) == 0u || dot(n, l) <= 0.0) { return Lit(1.0, 0u); }
    field_leave_frustum(); // the shadow ray leaves the pixel's frustum
    let q = offset(p, n, fp);
    let r = clip_ray(q, l);
    let s = march(q, l, 0.0, max(r.y, 0.0), U.max_steps, Crit(U.eps_min, 0.0, false));
    return Lit(select(1.0, 0.0, s.status == STATUS_HIT), s.steps);
}

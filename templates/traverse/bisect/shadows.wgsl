// isotrace bisection modality, spliced into the kernel only when asked for;
// otherwise shadows_off.wgsl takes its place.
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
    let h = trace_secondary(U.light.xyz, u, 0.0, dist - offset, U.light.w, false);
    return select(1.0, 0.0, h.status != STATUS_MISS);
}

// Sphere tracing: absorbing glass, spliced in only when asked for (else glass_off.wgsl).
// What refracted and reflected rays see: the background with a bright sky
// and stripes around the up axis, so that refraction is visible.
fn environment(dir: vec3<f32>) -> vec3<f32> {
    let h = dot(dir, F.up.xyz);
    let a = atan2(dot(dir, F.right.xyz), dot(dir, F.forward.xyz));
    let stripes = 0.5 + 0.5 * sin(10.0 * a);
    let sky = mix(vec3<f32>(0.25, 0.28, 0.35), vec3<f32>(0.85, 0.9, 1.0), smoothstep(-0.1, 0.6, h));
    return background(dir) + sky * (0.35 + 0.65 * stripes) * smoothstep(-0.3, 0.1, h);
}

// Absorbing glass: refract into the object (origin offset inwards by
// technique 3), find the exit (through the interior, or backwards from the
// bound with technique 5), refract out and attenuate by the thickness.
fn glass(p: vec3<f32>, dir: vec3<f32>, g: vec3<f32>, fp: f32) -> Shade {
    var out = Shade(vec3<f32>(0.0), 0u);
    let n = normalize(g);
    if (dot(n, dir) > 0.0) { return shade(p, dir, g, fp); } // seen from inside: plain
    field_leave_frustum(); // the refracted ray leaves the pixel's frustum
    let eta = 1.0 / 1.5;
    let r1 = refract(dir, n, eta);
    let q = offset(p, -n, fp);
    let span = clip_ray(q, r1);
    let diag = length(F.box_max.xyz - F.box_min.xyz);
    let ex = trace(q, r1, 0.0, max(span.y, 0.0), U.max_steps, Crit(U.eps_min, 0.0, true));
    out.steps = ex.steps;
    let e = q + r1 * ex.t;
    let ne = normalize(gradient(e, 0.5 * F.eps));
    var r2 = refract(r1, -ne, 1.5);
    if (dot(r2, r2) == 0.0) { r2 = reflect(r1, -ne); }
    let absorb = vec3<f32>(3.0, 1.2, 0.5) / diag;
    let transmitted = environment(r2) * exp(-absorb * ex.t);
    let fresnel = 0.04 + 0.96 * pow(1.0 - max(dot(-dir, n), 0.0), 5.0);
    let l = U.light.xyz;
    let spec = pow(max(dot(reflect(-l, n), -dir), 0.0), 60.0);
    out.color = mix(transmitted, environment(reflect(dir, n)), fresnel) + vec3<f32>(0.6 * spec);
    return out;
}

fn surface(p: vec3<f32>, dir: vec3<f32>, g: vec3<f32>, fp: f32) -> Shade {
    if ((F.flags & FLAG_GLASS) != 0u) { return glass(p, dir, g, fp); }
    return shade(p, dir, g, fp);
}

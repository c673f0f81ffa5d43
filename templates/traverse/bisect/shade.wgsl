// Shading of the bisection traversal: lights, colour modes and the
// environment. Spliced into traverse/bisect/kernel.wgsl; COLOR_MODE, SHADOWS, ENV_MODE
// come from the generated configuration. (Normal and work heat-map colours
// are made on the CPU from the EXR channels: `--color normal|steps`.)


// A perceptual blue-green-yellow ramp for t in [0, 1] (viridis-like).
fn ramp(t: f32) -> vec3<f32> {
    let x = clamp(t, 0.0, 1.0);
    let c0 = vec3<f32>(0.267, 0.005, 0.329);
    let c1 = vec3<f32>(0.229, 0.322, 0.546);
    let c2 = vec3<f32>(0.128, 0.567, 0.551);
    let c3 = vec3<f32>(0.369, 0.789, 0.383);
    let c4 = vec3<f32>(0.993, 0.906, 0.144);
    let k = x * 4.0;
    if (k < 1.0) { return mix(c0, c1, k); }
    if (k < 2.0) { return mix(c1, c2, k - 1.0); }
    if (k < 3.0) { return mix(c2, c3, k - 2.0); }
    return mix(c3, c4, k - 3.0);
}

// Colours of the isovalues (index 0 is the plain surface's warm orange).
fn iso_color(i: u32) -> vec3<f32> {
    switch (i % 8u) {
        case 0u: { return vec3<f32>(0.90, 0.55, 0.25); }
        case 1u: { return vec3<f32>(0.35, 0.75, 0.40); }
        case 2u: { return vec3<f32>(0.85, 0.30, 0.45); }
        case 3u: { return vec3<f32>(0.95, 0.85, 0.30); }
        case 4u: { return vec3<f32>(0.55, 0.45, 0.85); }
        case 5u: { return vec3<f32>(0.30, 0.80, 0.85); }
        case 6u: { return vec3<f32>(0.80, 0.80, 0.80); }
        default: { return vec3<f32>(0.60, 0.40, 0.25); }
    }
}

// Procedural environment: a sky gradient above a dark horizon (and, with
// ENV_MODE 1, a checkered ground), or an equirectangular image (ENV_MODE 2).
fn environment(dir: vec3<f32>) -> vec3<f32> {
    if (ENV_MODE == 2u) {
        let w = f32(U.env_size.x);
        let h = f32(U.env_size.y);
        let u = 0.5 + atan2(dir.y, dir.x) / 6.28318531;
        let v = 0.5 - asin(clamp(dir.z, -1.0, 1.0)) / 3.14159265;
        let px = min(u32(u * w), U.env_size.x - 1u);
        let py = min(u32(v * h), U.env_size.y - 1u);
        let c = unpack4x8unorm(env_image[py * U.env_size.x + px]).xyz;
        return c * c; // sRGB-ish to linear
    }
    let up = dir.z;
    if (ENV_MODE == 1u && up < 0.0) {
        let p = dir / max(-up, 1e-3);
        let cell = (i32(floor(p.x * 2.0)) + i32(floor(p.y * 2.0))) & 1;
        let c = select(vec3<f32>(0.12), vec3<f32>(0.55), cell == 0);
        return mix(c, vec3<f32>(0.16, 0.18, 0.23), clamp(1.0 + up * 4.0, 0.0, 1.0));
    }
    let s = 0.5 + 0.5 * up;
    return mix(vec3<f32>(0.055, 0.06, 0.075), vec3<f32>(0.16, 0.18, 0.23), s);
}

// The background seen by primary rays: the environment.
fn background(dir: vec3<f32>) -> vec3<f32> { return environment(dir); }

// Base colour of a surface point by the colour mode. `front` is true on the
// side the gradient points to (f > 0, "outside").
fn base_color(g: vec3<f32>, n: vec3<f32>, depth01: f32, iso: u32, front: bool) -> vec3<f32> {
    if (COLOR_MODE == COLOR_GRADIENT) {
        // |grad f| on a log scale, 1e-2 .. 1e3 (Knoll et al. Fig. 5).
        return ramp((log2(max(length(g), 1e-30)) * 0.30103 + 2.0) / 5.0);
    }
    if (COLOR_MODE == COLOR_DEPTH) { return ramp(1.0 - depth01); }
    if (ISO_COUNT > 1u || iso > 0u || CSG_COLORS) { return select(0.6 * iso_color(iso), iso_color(iso), front); }
    return select(vec3<f32>(0.30, 0.52, 0.90), vec3<f32>(0.90, 0.55, 0.25), front);
}

// Two-sided Phong with a point light; `visible` is the shadow term (1: lit).
fn shade(p: vec3<f32>, dir: vec3<f32>, g: vec3<f32>, depth01: f32, iso: u32, visible: f32) -> vec3<f32> {
    var n = normalize(g);
    let front = !(dot(n, dir) > 0.0);
    if (!front) { n = -n; }
    let base = base_color(g, normalize(g), depth01, iso, front);
    let l = normalize(U.light.xyz - p);
    let diff = max(dot(n, l), 0.0) * visible;
    let r = reflect(-l, n);
    let spec = pow(max(dot(r, -dir), 0.0), 40.0) * visible;
    let fill = 0.25 * max(dot(n, -dir), 0.0);
    return base * (0.12 + 0.70 * diff + fill) + vec3<f32>(0.35 * spec);
}


// An inline WGSL library for isotrace (use with --inline examples/inline/bumps.wgsl).
//
// bump(v) = v / (1 + v^2), with its three versions: scalar, interval and
// affine. It is monotone on [-1, 1] and decreasing outside, with extrema
// -1/2 at v = -1 and 1/2 at v = 1; the interval version uses that.
fn s_bump(v: f32) -> f32 { return v / (1.0 + v * v); }

fn ia_bump(v: vec2<f32>) -> vec2<f32> {
    var lo = min(s_bump(v.x), s_bump(v.y));
    var hi = max(s_bump(v.x), s_bump(v.y));
    if (v.x <= -1.0 && v.y >= -1.0) { lo = -0.5; }
    if (v.x <= 1.0 && v.y >= 1.0) { hi = 0.5; }
    return vec2<f32>(lo - 1e-6, hi + 1e-6);
}

fn ra_bump(v: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_bump(ra_range(v))); }

// Colour hits by height: a hook that replaces the final colour.
fn hook_shade(p: vec3<f32>, dir: vec3<f32>, n: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    return mix(c, vec3<f32>(0.2, 0.6, 1.0), clamp(0.5 + p.z, 0.0, 1.0) * 0.5);
}

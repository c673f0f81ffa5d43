// The camera model of the CLI (Camera in src/render/mod.rs), and rays
// against the domain.

// Screen coordinates (sx, sy) of pixel px's centre at unit depth.
fn pixel_dir(px: vec2<u32>) -> vec2<f32> {
    let W = f32(F.size.x);
    let H = f32(F.size.y);
    return vec2<f32>(((f32(px.x) + 0.5) / W * 2.0 - 1.0) * F.tan_half_fov * W / H,
                     (1.0 - (f32(px.y) + 0.5) / H * 2.0) * F.tan_half_fov);
}

// The frustum through the pixel centres of the `side` x `side` 8x8 tiles
// from `tile` on (in this dispatch): the ranges of their pixel_dir
// coordinates, x then y.
fn tile_frustum(tile: vec2<u32>, side: u32) -> vec4<f32> {
    let t_lo = F.tile_origin + tile * 8u;
    let t_hi = min(t_lo + vec2<u32>(8u * side - 1u), F.tile_origin + F.tile_size - vec2<u32>(1u));
    let a = pixel_dir(t_lo);
    let b = pixel_dir(t_hi);
    return vec4<f32>(a.x, b.x, b.y, a.y);
}

// The primary ray direction through pixel px, unnormalised (its forward
// component is 1, so the ray parameter is the depth).
fn primary_dir(px: vec2<u32>) -> vec3<f32> {
    let sxy = pixel_dir(px);
    return F.forward.xyz + sxy.x * F.right.xyz + sxy.y * F.up.xyz;
}

// Entry and exit parameter of o + dir s in the box [lo, hi] (entry > exit:
// missed).
fn ray_box(o: vec3<f32>, dir: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> vec2<f32> {
    let inv = 1.0 / dir;
    let ta = (lo - o) * inv;
    let tb = (hi - o) * inv;
    let tmin = min(ta, tb);
    let tmax = max(ta, tb);
    return vec2<f32>(max(max(tmin.x, tmin.y), tmin.z), min(min(tmax.x, tmax.y), tmax.z));
}

// The part s >= 0 of o + dir s inside the domain: the box, and the clip
// ball around its centre if any (dir need not be unit).
fn clip_domain(o: vec3<f32>, dir: vec3<f32>) -> vec2<f32> {
    var r = ray_box(o, dir, F.box_min.xyz, F.box_max.xyz);
    r.x = max(r.x, 0.0);
    let radius = F.box_max.w;
    if (radius > 0.0) {
        let oc = o - 0.5 * (F.box_min.xyz + F.box_max.xyz);
        let a = dot(dir, dir);
        let b = dot(oc, dir) / a;
        let disc = b * b - (dot(oc, oc) - radius * radius) / a;
        if (disc < 0.0) { return vec2<f32>(1.0, -1.0); }
        let q = sqrt(disc);
        r = vec2<f32>(max(r.x, -b - q), min(r.y, -b + q));
    }
    return r;
}

// The pixel record every traversal writes (decoded by src/render/record.rs),
// in the pass group, in two planes of the dispatch's n pixels:
//   pixels[idx], the head, every pixel:
//     x  colour: linear RGB as sqrt-encoded 10-bit unorm (r low); bits 30-31: status
//     y  work (16 bits, saturated: inclusion evaluations or marching steps)
//        | d_ray << 16 (5 bits) | isovalue / surface index << 21
//        d_ray: the ray's bisection depth; of a miss the statistics read only
//        whether it is 0 (the ray does not cross the domain), and bisection's
//        tile pass writes 0 or 1 there for the pixels of an empty tile
//   pixels[n + idx], the tail, written only where the status is not MISS:
//     x  unit normal, octahedral, pack2x16snorm
//     y  depth (f32 bits): distance from the eye along the unit ray
//        (a miss's depth is +inf and its normal 0, by its status)
// A miss, most of a frame's pixels, is 8 bytes: at 1024² the records are
// written by the kernel and read by the host every frame, and on a CPU
// device their cost is memory traffic. With the four words side by side
// every miss still touched its whole 16 bytes; in planes the tile pass's
// empty tiles write half the lines and the statistics read half the
// bytes. Each plane is
// stored a vec2<u32> at a time: lavapipe writes a vector per lane at once,
// where a struct of four fields took four bounds-checked stores.
// pixels: the pass group's records (src/kernel/bindings.rs).

// The pixels of this dispatch: the tail plane starts there.
fn pixel_count() -> u32 { return F.tile_size.x * F.tile_size.y; }

// sqrt encoding keeps dark colours precise (10 bits of sqrt(c) beat the
// 8-bit sRGB output everywhere).
fn pack_color(c: vec3<f32>, status: u32) -> u32 {
    return pack_levels(sqrt(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0))) * 1023.0, status);
}
// The colour word of 10-bit levels `q` (0..1023, unrounded). Through i32:
// lavapipe converts f32 to u32 one lane at a time with clamps (a dozen
// scalar instructions a lane), f32 to i32 in one vector instruction; the
// levels are small and non-negative, so the bits are the same.
fn pack_levels(q: vec3<f32>, status: u32) -> u32 {
    let l = bitcast<vec3<u32>>(vec3<i32>(round(q)));
    return l.x | (l.y << 10u) | (l.z << 20u) | (status << 30u);
}
fn pack_normal(n: vec3<f32>) -> u32 {
    let l1 = abs(n.x) + abs(n.y) + abs(n.z);
    var p = n.xy / max(l1, 1e-30);
    if (n.z < 0.0) {
        p = (vec2<f32>(1.0) - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
    }
    return pack2x16snorm(p);
}
fn pack_info(work: u32, d_ray: u32, iso: u32) -> u32 {
    return min(work, 0xffffu) | (min(d_ray, 31u) << 16u) | (min(iso, 255u) << 21u);
}
fn write_pixel(idx: u32, color: vec3<f32>, status: u32, normal: vec3<f32>, depth: f32, info: u32) {
    pixels[idx] = vec2<u32>(pack_color(color, status), info);
    if (status != STATUS_MISS) {
        pixels[pixel_count() + idx] = vec2<u32>(pack_normal(normal), bitcast<u32>(depth));
    }
}

// How a pixel whose traversal ran out of budget is drawn: its position is a
// best guess, so by default it must not look like a hit. Diagonal magenta
// stripes 3 pixels wide over the shaded guess (the frame-global pixel `px`
// keeps the stripes continuous across dispatch tiles); solid magenta; or
// the guess alone when the user asks for it (src/render/settings.rs
// `Unresolved`).
fn unresolved_color(c: vec3<f32>, px: vec2<u32>) -> vec3<f32> {
    let magenta = vec3<f32>(1.0, 0.0, 1.0);
    if ((F.flags & FLAG_UNRESOLVED_GUESS) != 0u) { return c; }
    if ((F.flags & FLAG_UNRESOLVED_SOLID) != 0u) { return magenta; }
    return select(c, magenta, ((px.x + px.y) / 3u) % 2u == 0u);
}

// The pixel of its 8x8 tile that invocation `lid` of an 8x8 layer takes.
// Each run of 8 invocations (one SIMD bundle on lavapipe) takes a 4x2 block
// rather than a row of 8: a bundle's loops run until its slowest lane is
// done, and closer rays need more alike work (a few percent fewer bundle
// iterations of bisection over the Knoll frames).
fn tile_pixel(lid: vec2<u32>) -> vec2<u32> {
    let i = lid.y * 8u + lid.x;
    let b = i / 8u;
    return vec2<u32>((b % 2u) * 4u + i % 4u, (b / 2u) * 2u + (i % 8u) / 4u);
}

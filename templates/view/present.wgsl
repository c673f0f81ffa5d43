// The viewer's present pass: draws a frame's pixel records
// (templates/shared/pixels.wgsl) onto the page's canvas, decoded exactly as
// src/render/record.rs `convert` and src/output.rs `srgb8` do for a PNG, so
// the canvas holds the bytes `isotrace render -o view.png` writes. A coarse
// frame (fewer records than canvas pixels) is stretched, nearest record.

// ---- The Present block and the shared constants, generated from src/layout.rs.
//!splice:uniforms

// ---- The bindings, generated from src/view/present.rs: the frame's records
// (heads, then tails), the Present block P, and the records of a scene's
// selected node traced alone.
//!splice:bindings

// Record i of n as the four words (colour, normal, depth, work) of the
// functions below. A miss's tail is whatever an earlier frame left there:
// they read its normal and depth only for hits.
fn record_at(i: u32, n: u32) -> vec4<u32> {
    let head = records[i];
    let tail = records[n + i];
    return vec4<u32>(head.x, tail.x, tail.y, head.y);
}

// `convert`'s colour: 10-bit sqrt-encoded channels, squared.
fn record_color(r: vec4<u32>) -> vec3<f32> {
    let q = vec3<f32>(vec3<u32>(r.x, r.x >> 10u, r.x >> 20u) & vec3<u32>(0x3ffu)) / 1023.0;
    return q * q;
}

// `octahedral`: the unit normal of two snorm16 halves.
fn record_normal(r: vec4<u32>) -> vec3<f32> {
    var p = unpack2x16snorm(r.y);
    let z = 1.0 - abs(p.x) - abs(p.y);
    if (z < 0.0) {
        p = (vec2<f32>(1.0) - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
    }
    let n = vec3<f32>(p, z);
    let l = length(n);
    return select(vec3<f32>(0.0, 0.0, 1.0), n / l, l > 0.0);
}

// `output::heat`: black, purple, red, orange, pale yellow.
fn heat(v: f32) -> vec3<f32> {
    var stops = array<vec3<f32>, 5>(vec3<f32>(0.0, 0.0, 0.02), vec3<f32>(0.27, 0.03, 0.45), vec3<f32>(0.78, 0.13, 0.30), vec3<f32>(0.98, 0.55, 0.05), vec3<f32>(1.0, 1.0, 0.75));
    let x = clamp(v, 0.0, 1.0) * 4.0;
    let k = min(u32(floor(x)), 3u);
    let c = mix(stops[k], stops[k + 1u], x - f32(k));
    return pow(c, vec3<f32>(2.2));
}

// The linear colour `output::recolor` gives a record in `mode`.
fn present_linear(r: vec4<u32>, mode: u32, steps_max: u32) -> vec3<f32> {
    // As `Record::status`: only HIT and UNRESOLVED count as hits.
    let status = r.x >> 30u;
    let hit = status == STATUS_HIT || status == STATUS_UNRESOLVED;
    if (mode == PRESENT_NORMAL) {
        return select(vec3<f32>(0.0), pow(0.5 + 0.5 * record_normal(r), vec3<f32>(2.2)), hit);
    }
    if (mode == PRESENT_STEPS) {
        return heat(f32(r.w & 0xffffu) / f32(max(steps_max, 1u)));
    }
    return record_color(r);
}

// `srgb8`: the 8-bit sRGB level of a linear value, as a float 0..255.
fn srgb8(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    let s = select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
    return floor(s * 255.0 + 0.5);
}

struct VertexOut {
    @builtin(position) pos: vec4<f32>,
}

// One triangle that covers the canvas.
@vertex
fn vs(@builtin(vertex_index) i: u32) -> VertexOut {
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return VertexOut(vec4<f32>(xy * 2.0 - 1.0, 0.0, 1.0));
}

@fragment
fn fs(v: VertexOut) -> @location(0) vec4<f32> {
    let px = vec2<u32>(v.pos.xy);
    let rec = min(px * P.size / max(P.canvas, vec2<u32>(1u)), P.size - vec2<u32>(1u));
    let i = rec.y * P.size.x + rec.x;
    let n = P.size.x * P.size.y;
    let r = record_at(i, n);
    var c = present_linear(r, P.mode, P.steps_max);
    if (P.highlight != 0u) {
        let s = selection[i];
        let d = bitcast<f32>(r.z);
        if ((s.x >> 30u) == STATUS_HIT && (r.x >> 30u) == STATUS_HIT && abs(bitcast<f32>(selection[n + i].y) - d) <= 1e-3 * d) {
            c = mix(c, vec3<f32>(1.0, 0.35, 0.0), 0.55);
        }
    }
    return vec4<f32>(srgb8(c) / 255.0, 1.0);
}

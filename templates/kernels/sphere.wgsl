// isotrace sphere tracing kernel: one invocation per pixel, for formulas
// that are signed distance bounds: |f(p)| / L <= the distance from p to
// f = 0, which holds when f is L-Lipschitz (L = --lipschitz, applied as
// U.inv_lipschitz).
//
// Enhanced sphere tracing after Keinert et al. 2014, every technique
// switchable through the uniforms so its effect can be measured:
//   1. over-relaxation with the overlap test and fallback (Listing 2), U.omega;
//   2. screen-space aware intersection choice: stop when the unbounding
//      sphere is below half a pixel, and on an exhausted budget return the
//      candidate with the smallest radius / pixel-size (FLAG_SCREEN);
//   3. dynamic epsilon for secondary rays (shadow and refraction rays):
//      the origin moves 2 max(eps_min, |f(p)|) along the normal (FLAG_DYNAMIC_EPS);
//   4. discontinuity reduction: U.fixpoint iterations p <- p + d (f(p) - err(|p - o|));
//   5. convex bounding volume (U.bound_kind): rays are clipped to it, and a
//      ray that starts inside the (convex) object is traced backwards from
//      the far side of the bound instead of through the interior.
//
// The traversal only calls the scalar evaluator eval_s (spliced in below);
// it never sees how the formula was written.
//
// Sections between `//!if:NAME`, `//!else` and `//!end` lines are kept or
// dropped by src/gpu/sphere.rs: shadow and refraction rays are compiled in
// only when asked for, because lavapipe pays for inlined code that never runs.

struct Uniforms {
    eye: vec4<f32>,
    forward: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    box_min: vec4<f32>,
    box_max: vec4<f32>,     // w: radius of the clip sphere around the box centre, 0 for none
    bound_a: vec4<f32>,     // bound sphere: centre, radius; bound box: min corner
    bound_b: vec4<f32>,     // bound box: max corner
    light: vec4<f32>,       // unit direction towards the key light (upper left, in front of the objects)
    size: vec2<u32>,        // whole image, pixels
    tile_origin: vec2<u32>, // this dispatch's first pixel
    tile_size: vec2<u32>,
    max_steps: u32,         // per ray (primary, shadow and refraction rays each)
    flags: u32,
    fixpoint: u32,          // technique 4 iterations, 0 = off
    bound_kind: u32,        // 0 none, 1 sphere, 2 box
    tan_half_fov: f32,
    eps: f32,               // absolute threshold without technique 2; normal stencil
    inf: f32,
    time: f32,
    omega: f32,             // technique 1, 1 = off
    inv_lipschitz: f32,     // 1 / --lipschitz
    pixel_radius: f32,      // half a pixel at unit distance: tan(fov/2) / height
    min_step: f32,          // smallest forward step (Zanni et al.), 0 = none
    eps_min: f32,           // technique 3's minimum offset; threshold of secondary rays
    color_mode: u32,        // 0 shaded, 1 f(p) / err(t) at the hit (technique 4's picture)
    params: array<vec4<f32>, 16>,
}

// One pixel's result, packed to 28 bytes like the bisect kernel's.
struct Pixel {
    color_rg: u32,  // pack2x16unorm(r, g), linear
    color_ba: u32,  // pack2x16unorm(b, a); a = 1 on hits
    normal_xy: u32, // pack2x16snorm(n.x, n.y)
    normal_z: u32,  // pack2x16snorm(n.z, 0)
    depth: f32,     // distance from the eye along the unit ray; +inf on misses
    steps: u32,     // marching steps of every ray of the pixel (fixed-point iterations and normals are not counted)
    info: u32,      // status | sor_fallbacks << 8
    ratio: f32,     // largest |f(p_i+1) - f(p_i)| / |p_i+1 - p_i| seen on the primary ray (> 1: not a distance bound)
}

const STATUS_MISS: u32 = 0u;
const STATUS_HIT: u32 = 1u;
const STATUS_UNCONVERGED: u32 = 2u;

const FLAG_DEBUG: u32 = 1u;
const FLAG_SCREEN: u32 = 2u;
const FLAG_DYNAMIC_EPS: u32 = 4u;
const FLAG_SHADOWS: u32 = 8u;
const FLAG_GLASS: u32 = 16u;

// Bisection steps when a step lands on the far side of the surface (only a
// formula that is not a distance bound, or --min-step, can do that).
const BRACKET_STEPS: i32 = 24;

// Uniforms from a read-only storage buffer, copied to a private variable at
// the entry point (why: see bisect.wgsl).
@group(0) @binding(0) var<storage, read> Ubuf: Uniforms;
var<private> U: Uniforms;
@group(0) @binding(1) var<storage, read_write> pixels: array<Pixel>;

fn iso_inf() -> f32 { return U.inf; }
fn iso_param(i: u32) -> f32 { return U.params[i / 4u][i % 4u]; }

//!splice:library

//!splice:evaluator

// The distance bound: f / L.
fn field(p: vec3<f32>) -> f32 { return eval_s(p.x, p.y, p.z, U.time) * U.inv_lipschitz; }

// Termination rule of one march: converged when |f| < e0 + e1 * t (t along
// this march). Primary rays with technique 2 use half a pixel at the eye
// distance; otherwise a fixed width. `best` returns the best candidate, not
// the last point, when the budget runs out.
struct Crit { e0: f32, e1: f32, best: bool }
struct March { t: f32, status: u32, steps: u32, fallbacks: u32, f: f32, ratio: f32 }

fn threshold(c: Crit, t: f32) -> f32 { return max(c.e0 + c.e1 * t, 1e-30); }

// Scalar bisection of a sign change of f between a (start side) and b.
fn bracket(o: vec3<f32>, d: vec3<f32>, a0: f32, b0: f32) -> f32 {
    var a = a0;
    var b = b0;
    let fa = field(o + d * a) < 0.0;
    for (var i = 0; i < BRACKET_STEPS; i = i + 1) {
        let m = 0.5 * (a + b);
        if ((field(o + d * m) < 0.0) == fa) { a = m; } else { b = m; }
    }
    return 0.5 * (a + b);
}

// Over-relaxed sphere tracing of o + d t over [t0, t1] (Keinert et al.,
// Listing 2) with the screen-space candidate, the fixed-point
// post-process, a minimum step and a sign-change bracket.
fn march(o: vec3<f32>, d: vec3<f32>, t0: f32, t1: f32, budget: u32, c: Crit) -> March {
    var m = March(t0, STATUS_MISS, 0u, 0u, 0.0, 0.0);
    var f_safe = 0.0;
    var omega = U.omega;
    var t = t0;
    var fsign = 1.0;
    var prev_radius = 0.0;
    var stride = 0.0;         // the step taken to reach t
    var t_safe = t0;          // last point whose unbounding sphere was accepted
    var cand_err = U.inf;
    var cand_t = t0;
    loop {
        if (m.steps >= budget) {
            m.status = STATUS_UNCONVERGED;
            m.t = select(t_safe, cand_t, c.best);
            break;
        }
        let v = field(o + d * t);
        m.steps = m.steps + 1u;
        if (m.steps == 1u && v < 0.0) { fsign = -1.0; } // start inside: march to the boundary
        let signed = fsign * v;
        let radius = abs(signed);
        let sor_fail = omega > 1.0 && (radius + prev_radius) < stride;
        if (sor_fail) {
            // The spheres do not overlap: go back to p_fallback and continue
            // with plain sphere tracing.
            stride = stride - omega * stride;
            omega = 1.0;
            m.fallbacks = m.fallbacks + 1u;
        } else {
            if (signed < 0.0) {
                // Past the surface: f is not a distance bound here (or the
                // minimum step jumped in). The root is bracketed.
                m.t = bracket(o, d, t_safe, t);
                m.steps = m.steps + u32(BRACKET_STEPS);
                m.status = STATUS_HIT;
                break;
            }
            // How fast f changed since the last accepted point: a distance
            // bound changes no faster than the distance (ratio <= 1).
            if (m.steps > 1u && t != t_safe) { m.ratio = max(m.ratio, abs(signed - f_safe) / abs(t - t_safe)); }
            // The spheres overlap, so [t_safe, t] holds no surface: beyond
            // t1 the ray has left the domain. (After a failed over-relaxed
            // step the fallback comes first, even beyond t1.)
            if (t > t1) { break; }
            stride = max(signed * omega, U.min_step);
            t_safe = t;
            f_safe = signed;
            let err = radius / threshold(c, t);
            if (err < cand_err) {
                cand_err = err;
                cand_t = t;
            }
            if (err < 1.0) {
                m.t = t;
                m.status = STATUS_HIT;
                break;
            }
        }
        prev_radius = radius;
        t = t + stride;
    }
    if (m.status != STATUS_MISS) {
        // Technique 4: move to the level set f = err(t), which varies
        // smoothly over the screen, instead of wherever the march stopped.
        for (var i = 0u; i < U.fixpoint; i = i + 1u) {
            m.t = clamp(m.t + (fsign * field(o + d * m.t) - threshold(c, m.t)), t0, max(t1, t0));
        }
        m.f = fsign * field(o + d * m.t);
    }
    return m;
}

// Entry and exit of o + d t in the bounding volume (t0 > t1: missed).
fn bound_range(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    if (U.bound_kind == 1u) {
        let oc = o - U.bound_a.xyz;
        let b = dot(oc, d);
        let disc = b * b - (dot(oc, oc) - U.bound_a.w * U.bound_a.w);
        if (disc < 0.0) { return vec2<f32>(1.0, -1.0); }
        let q = sqrt(disc);
        return vec2<f32>(-b - q, -b + q);
    }
    if (U.bound_kind == 2u) { return slab(o, d, U.bound_a.xyz, U.bound_b.xyz); }
    return vec2<f32>(-U.inf, U.inf);
}

fn slab(o: vec3<f32>, d: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> vec2<f32> {
    let inv = 1.0 / d;
    let ta = (lo - o) * inv;
    let tb = (hi - o) * inv;
    let tmin = min(ta, tb);
    let tmax = max(ta, tb);
    return vec2<f32>(max(max(tmin.x, tmin.y), tmin.z), min(min(tmax.x, tmax.y), tmax.z));
}

// The part of o + d t (t >= 0) inside the domain: box, clip ball, bound.
fn clip_ray(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    var r = slab(o, d, U.box_min.xyz, U.box_max.xyz);
    r.x = max(r.x, 0.0);
    let radius = U.box_max.w;
    if (radius > 0.0) {
        let oc = o - 0.5 * (U.box_min.xyz + U.box_max.xyz);
        let b = dot(oc, d);
        let disc = b * b - (dot(oc, oc) - radius * radius);
        if (disc < 0.0) { return vec2<f32>(1.0, -1.0); }
        let q = sqrt(disc);
        r = vec2<f32>(max(r.x, -b - q), min(r.y, -b + q));
    }
    let bv = bound_range(o, d);
    return vec2<f32>(max(r.x, bv.x), min(r.y, bv.y));
}

// First surface point along o + d t, t in [t0, t1]. With a convex bound,
// a ray that starts inside the object is traced backwards from t1 (on the
// bound) instead of through the interior (technique 5). `c` is given for
// the forward direction.
fn trace(o: vec3<f32>, d: vec3<f32>, t0: f32, t1: f32, c: Crit) -> March {
    // One call of march either way (lavapipe inlines every call site).
    let back = U.bound_kind != 0u && t1 > t0 && field(o + d * t0) < 0.0;
    var o2 = o;
    var d2 = d;
    var r = vec2<f32>(t0, t1);
    var c2 = c;
    if (back) {
        o2 = o + d * t1;
        d2 = -d;
        r = vec2<f32>(0.0, t1 - t0);
        c2 = Crit(c.e0 + c.e1 * t1, -c.e1, c.best);
    }
    var m = march(o2, d2, r.x, r.y, U.max_steps, c2);
    if (back) {
        m.steps = m.steps + 1u;
        // A backward miss can only come from rounding (the start is inside):
        // then the far bound itself is the answer.
        m.t = select(t1 - m.t, t0, m.status == STATUS_MISS);
        if (m.status == STATUS_MISS) { m.status = STATUS_HIT; }
    }
    return m;
}

fn gradient(p: vec3<f32>, h: f32) -> vec3<f32> {
    let dx = vec3<f32>(h, 0.0, 0.0);
    let dy = vec3<f32>(0.0, h, 0.0);
    let dz = vec3<f32>(0.0, 0.0, h);
    return vec3<f32>(field(p + dx) - field(p - dx), field(p + dy) - field(p - dy), field(p + dz) - field(p - dz)) / (2.0 * h);
}

fn background(dir: vec3<f32>) -> vec3<f32> {
    let s = 0.5 + 0.5 * dot(dir, U.up.xyz);
    return mix(vec3<f32>(0.055, 0.06, 0.075), vec3<f32>(0.16, 0.18, 0.23), s);
}

// Technique 3: a secondary ray starts 2 max(eps_min, |f(p)|) away from the
// surface point p along n (a fixed eps_min when switched off).
fn offset(p: vec3<f32>, n: vec3<f32>, fp: f32) -> vec3<f32> {
    var e = U.eps_min;
    if ((U.flags & FLAG_DYNAMIC_EPS) != 0u) { e = 2.0 * max(U.eps_min, abs(fp)); }
    return p + n * e;
}

struct Shade { color: vec3<f32>, steps: u32 }
struct Lit { lit: f32, steps: u32 }

//!if:shadows
// A shadow ray towards the key light from p offset along n (technique 3).
fn shadow(p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, fp: f32) -> Lit {
    if ((U.flags & FLAG_SHADOWS) == 0u || dot(n, l) <= 0.0) { return Lit(1.0, 0u); }
    let q = offset(p, n, fp);
    let r = clip_ray(q, l);
    let s = march(q, l, 0.0, max(r.y, 0.0), U.max_steps, Crit(U.eps_min, 0.0, false));
    return Lit(select(1.0, 0.0, s.status == STATUS_HIT), s.steps);
}
//!else
fn shadow(p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, fp: f32) -> Lit { return Lit(1.0, 0u); }
//!end

// Two-sided Phong as in the bisect kernel (f > 0 side warm, the other cool),
// with an optional shadow ray towards the key light.
fn shade(p: vec3<f32>, dir: vec3<f32>, g: vec3<f32>, fp: f32) -> Shade {
    var out = Shade(vec3<f32>(0.0), 0u);
    var n = normalize(g);
    var base = vec3<f32>(0.90, 0.55, 0.25);
    if (dot(n, dir) > 0.0) {
        n = -n;
        base = vec3<f32>(0.30, 0.52, 0.90);
    }
    let l = U.light.xyz;
    let sh = shadow(p, n, l, fp);
    out.steps = sh.steps;
    let lit = sh.lit;
    let diff = max(dot(n, l), 0.0) * lit;
    let r = reflect(-l, n);
    let spec = pow(max(dot(r, -dir), 0.0), 40.0) * lit;
    let fill = 0.15 * max(dot(n, -dir), 0.0);
    out.color = base * (0.10 + 0.80 * diff + fill) + vec3<f32>(0.35 * spec);
    return out;
}

//!if:glass
// What refracted and reflected rays see: the background with a bright sky
// and stripes around the up axis, so that refraction is visible.
fn environment(dir: vec3<f32>) -> vec3<f32> {
    let h = dot(dir, U.up.xyz);
    let a = atan2(dot(dir, U.right.xyz), dot(dir, U.forward.xyz));
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
    let eta = 1.0 / 1.5;
    let r1 = refract(dir, n, eta);
    let q = offset(p, -n, fp);
    let span = clip_ray(q, r1);
    let diag = length(U.box_max.xyz - U.box_min.xyz);
    let ex = trace(q, r1, 0.0, max(span.y, 0.0), Crit(U.eps_min, 0.0, true));
    out.steps = ex.steps;
    let e = q + r1 * ex.t;
    let ne = normalize(gradient(e, 0.5 * U.eps));
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
    if ((U.flags & FLAG_GLASS) != 0u) { return glass(p, dir, g, fp); }
    return shade(p, dir, g, fp);
}
//!else
fn surface(p: vec3<f32>, dir: vec3<f32>, g: vec3<f32>, fp: f32) -> Shade { return shade(p, dir, g, fp); }
//!end

fn heat(v: f32) -> vec3<f32> {
    let x = clamp(v, 0.0, 1.0);
    return clamp(vec3<f32>(1.5 * x, 1.5 * x - 0.5, 3.0 * x - 2.0) + vec3<f32>(0.0, 0.0, 0.4 * (1.0 - x)), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn pixel_dir(px: vec2<u32>) -> vec2<f32> {
    let W = f32(U.size.x);
    let H = f32(U.size.y);
    return vec2<f32>(((f32(px.x) + 0.5) / W * 2.0 - 1.0) * U.tan_half_fov * W / H,
                     (1.0 - (f32(px.y) + 0.5) / H * 2.0) * U.tan_half_fov);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    U = Ubuf;
    if (gid.x >= U.tile_size.x || gid.y >= U.tile_size.y) { return; }
    let px = U.tile_origin + gid.xy;
    let idx = gid.y * U.tile_size.x + gid.x;
    let sxy = pixel_dir(px);
    let d = normalize(U.forward.xyz + sxy.x * U.right.xyz + sxy.y * U.up.xyz);
    let o = U.eye.xyz;

    var color = vec4<f32>(background(d), 0.0);
    var normal = vec3<f32>(0.0);
    var depth = U.inf;
    var steps = 0u;
    var status = STATUS_MISS;
    var fallbacks = 0u;
    var ratio = 0.0;
    let seg = clip_ray(o, d);
    if (seg.x < seg.y) {
        let screen = (U.flags & FLAG_SCREEN) != 0u;
        var c = Crit(U.eps, 0.0, false);
        if (screen) { c = Crit(0.0, U.pixel_radius, true); }
        let h = trace(o, d, seg.x, seg.y, c);
        steps = h.steps;
        fallbacks = h.fallbacks;
        ratio = h.ratio;
        status = h.status;
        // On an exhausted budget the best candidate (technique 2) or the last
        // point is drawn as a best guess, and counted as unconverged.
        if (status != STATUS_MISS) {
            let p = o + d * h.t;
            let g = gradient(p, 0.5 * U.eps);
            let s = surface(p, d, g, h.f);
            steps = steps + s.steps;
            var col = s.color;
            if (U.color_mode == 1u) { col = heat(h.f / threshold(c, h.t)); }
            normal = normalize(g);
            if (!(dot(g, g) > 0.0)) { normal = -d; }
            color = vec4<f32>(col, 1.0);
            depth = h.t;
        }
    }
    if (status == STATUS_UNCONVERGED && (U.flags & FLAG_DEBUG) != 0u) { color = vec4<f32>(1.0, 0.0, 1.0, 1.0); }
    let cl = clamp(color, vec4<f32>(0.0), vec4<f32>(1.0));
    pixels[idx] = Pixel(pack2x16unorm(cl.xy), pack2x16unorm(cl.zw), pack2x16snorm(normal.xy),
                        pack2x16snorm(vec2<f32>(normal.z, 0.0)), depth, steps, status | (min(fallbacks, 0xffffffu) << 8u), ratio);
}

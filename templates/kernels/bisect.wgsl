// isotrace render kernel: one invocation per pixel, Knoll et al.'s stackless
// interval bisection along the primary ray.
//
// The ray is clipped to the domain box and reparametrised to t in [0, 1].
// Cells are addressed by an integer index k at depth d: cell (d, k) covers
// t in [k, k+1] / 2^d, exact in f32 for d <= 24. Rejecting a cell moves to
// the next one in depth-first order without a stack: the trailing one bits
// of k say how many levels to climb (Knoll tests the float modulus of t; the
// integer form is exact on every device and needs no loop).
//
// The inclusion function (interval or affine) is spliced in as
// cell_range(); the traversal never sees the number domain.

struct Uniforms {
    eye: vec4<f32>,
    forward: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    box_min: vec4<f32>,
    box_max: vec4<f32>,     // w: radius of the clip sphere around the box centre, 0 for none
    size: vec2<u32>,        // whole image, pixels
    tile_origin: vec2<u32>, // this dispatch's first pixel
    tile_size: vec2<u32>,
    max_iter: u32,
    flags: u32,             // bit 0: debug-unresolved colour
    tan_half_fov: f32,
    eps: f32,
    inf: f32,
    time: f32,
    params: array<vec4<f32>, 16>,
}

struct Pixel {
    color: vec4<f32>,        // linear RGB, alpha = 1 on hits
    normal_depth: vec4<f32>, // unit normal, distance from the eye along the unit ray
    info: vec4<u32>,         // inclusion evaluations, status, depth reached, 0
}

const STATUS_MISS: u32 = 0u;
const STATUS_HIT: u32 = 1u;
const STATUS_UNRESOLVED: u32 = 2u;
// Extra bisection levels below d_max for cells whose enclosure is not
// finite (division by an interval containing 0): such a cell is a hit only
// once it is this much smaller than eps and the scalar function changes sign.
const EXTRA_LEVELS: u32 = 6u;

@group(0) @binding(0) var<uniform> U: Uniforms;
@group(0) @binding(1) var<storage, read_write> pixels: array<Pixel>;

fn iso_inf() -> f32 { return U.inf; }
fn iso_param(i: u32) -> f32 { return U.params[i / 4u][i % 4u]; }

//!splice:library

//!splice:evaluators

//!splice:inclusion

fn f_at(p: vec3<f32>) -> f32 { return eval_s(p.x, p.y, p.z, U.time); }

// Zero test that stays conservative when an end is NaN.
fn may_contain_zero(r: vec2<f32>) -> bool { return !(r.x > 0.0 || r.y < 0.0); }
fn is_finite_range(r: vec2<f32>) -> bool { return abs(r.x) < U.inf && abs(r.y) < U.inf; }

struct Hit { t: f32, status: u32, evals: u32, depth: u32 }

fn traverse(pe: vec3<f32>, dir: vec3<f32>, d_max: u32) -> Hit {
    var h = Hit(0.0, STATUS_MISS, 0u, 0u);
    var d = 0u;
    var k = 0u;
    let d_last = d_max + EXTRA_LEVELS;
    for (var it = 0u; it < U.max_iter; it = it + 1u) {
        let w = exp2(-f32(d));
        let t0 = f32(k) * w;
        let t1 = t0 + w;
        let r = cell_range(pe, dir, t0, t1);
        h.evals = h.evals + 1u;
        var descend = false;
        if (may_contain_zero(r)) {
            let finite = is_finite_range(r);
            if (d < d_max || (!finite && d < d_last)) {
                descend = true;
            } else if (finite || sign_change(pe, dir, t0, t1)) {
                h.t = refine(pe, dir, t0, t1);
                h.status = STATUS_HIT;
                h.depth = d;
                return h;
            }
        }
        if (descend) {
            d = d + 1u;
            k = k * 2u;
        } else {
            // Climb over every finished level (trailing ones of k), then step right.
            let up = countTrailingZeros(~k);
            if (up >= d) { return h; } // the whole segment is done
            d = d - up;
            k = (k >> up) + 1u;
        }
    }
    // Iteration budget exhausted: report it, and keep the nearest cell that
    // may still hold the surface as the best guess.
    h.status = STATUS_UNRESOLVED;
    h.t = f32(k) * exp2(-f32(d));
    h.depth = d;
    return h;
}

fn sign_change(pe: vec3<f32>, dir: vec3<f32>, t0: f32, t1: f32) -> bool {
    let f0 = f_at(pe + dir * t0);
    let f1 = f_at(pe + dir * t1);
    return (f0 <= 0.0 && f1 >= 0.0) || (f0 >= 0.0 && f1 <= 0.0);
}

// Root position for the hit cell [t0, t1]. An enclosure can contain 0 a
// little before the surface (overestimation), so when f does not change sign
// across the cell we look up to LOOKAHEAD cells further (IA overestimates most where the gradient is nearly perpendicular to the ray) for a sign change
// (scalar evaluations only) and bisect there; without one (a tangent root or
// a feature thinner than a cell) the cell's midpoint is the answer.
const LOOKAHEAD: i32 = 16;
fn refine(pe: vec3<f32>, dir: vec3<f32>, t0: f32, t1: f32) -> f32 {
    let w = t1 - t0;
    var a = t0;
    var b = t1;
    var fa = f_at(pe + dir * a);
    var fb = f_at(pe + dir * b);
    var found = (fa <= 0.0 && fb >= 0.0) || (fa >= 0.0 && fb <= 0.0);
    for (var k = 0; k < LOOKAHEAD && !found && b < 1.0; k = k + 1) {
        a = b;
        fa = fb;
        b = min(b + w, 1.0);
        fb = f_at(pe + dir * b);
        found = (fa <= 0.0 && fb >= 0.0) || (fa >= 0.0 && fb <= 0.0);
    }
    if (!found) {
        return 0.5 * (t0 + t1);
    }
    for (var i = 0; i < 12; i = i + 1) {
        let m = 0.5 * (a + b);
        let fm = f_at(pe + dir * m);
        if ((fa <= 0.0) == (fm <= 0.0)) { a = m; fa = fm; } else { b = m; }
    }
    return 0.5 * (a + b);
}

fn gradient(p: vec3<f32>, h: f32) -> vec3<f32> {
    let dx = vec3<f32>(h, 0.0, 0.0);
    let dy = vec3<f32>(0.0, h, 0.0);
    let dz = vec3<f32>(0.0, 0.0, h);
    return vec3<f32>(f_at(p + dx) - f_at(p - dx), f_at(p + dy) - f_at(p - dy), f_at(p + dz) - f_at(p - dz)) / (2.0 * h);
}

fn background(dir: vec3<f32>) -> vec3<f32> {
    let s = 0.5 + 0.5 * dot(dir, U.up.xyz);
    return mix(vec3<f32>(0.055, 0.06, 0.075), vec3<f32>(0.16, 0.18, 0.23), s);
}

// Two-sided Phong: the side the gradient points to (f > 0, "outside") is
// warm, the other side cool, so open surfaces read clearly.
fn shade(p: vec3<f32>, dir: vec3<f32>, g: vec3<f32>) -> vec3<f32> {
    var n = normalize(g);
    var base = vec3<f32>(0.90, 0.55, 0.25);
    if (dot(n, dir) > 0.0) {
        n = -n;
        base = vec3<f32>(0.30, 0.52, 0.90);
    }
    let l = normalize(-dir + 0.6 * U.up.xyz - 0.4 * U.right.xyz);
    let diff = max(dot(n, l), 0.0);
    let r = reflect(-l, n);
    let spec = pow(max(dot(r, -dir), 0.0), 40.0);
    let fill = 0.25 * max(dot(n, -dir), 0.0);
    return base * (0.12 + 0.70 * diff + fill) + vec3<f32>(0.35 * spec);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= U.tile_size.x || gid.y >= U.tile_size.y) { return; }
    let px = U.tile_origin + gid.xy;
    let idx = gid.y * U.tile_size.x + gid.x;
    let W = f32(U.size.x);
    let H = f32(U.size.y);
    let sx = ((f32(px.x) + 0.5) / W * 2.0 - 1.0) * U.tan_half_fov * W / H;
    let sy = (1.0 - (f32(px.y) + 0.5) / H * 2.0) * U.tan_half_fov;
    let dir = normalize(U.forward.xyz + sx * U.right.xyz + sy * U.up.xyz);
    let o = U.eye.xyz;

    var out = Pixel(vec4<f32>(background(dir), 0.0), vec4<f32>(0.0, 0.0, 0.0, U.inf), vec4<u32>(0u));
    // Slab test against the domain box.
    let inv = 1.0 / dir;
    let ta = (U.box_min.xyz - o) * inv;
    let tb = (U.box_max.xyz - o) * inv;
    let tmin = min(ta, tb);
    let tmax = max(ta, tb);
    var t_enter = max(max(max(tmin.x, tmin.y), tmin.z), 0.0);
    var t_exit = min(min(tmax.x, tmax.y), tmax.z);
    let radius = U.box_max.w;
    if (radius > 0.0) {
        // Intersect with the clip ball as well.
        let oc = o - 0.5 * (U.box_min.xyz + U.box_max.xyz);
        let b = dot(oc, dir);
        let disc = b * b - (dot(oc, oc) - radius * radius);
        if (disc < 0.0) {
            t_exit = -1.0;
        } else {
            let q = sqrt(disc);
            t_enter = max(t_enter, -b - q);
            t_exit = min(t_exit, -b + q);
        }
    }
    if (t_enter < t_exit) {
        let pe = o + dir * t_enter;
        let seg = dir * (t_exit - t_enter);
        let len = t_exit - t_enter;
        let d_max = u32(clamp(ceil(log2(len / U.eps)), 0.0, 18.0));
        let h = traverse(pe, seg, d_max);
        out.info = vec4<u32>(h.evals, h.status, h.depth, 0u);
        if (h.status != STATUS_MISS) {
            let p = pe + seg * h.t;
            let g = gradient(p, 0.5 * U.eps);
            var c = shade(p, dir, g);
            if (h.status == STATUS_UNRESOLVED && (U.flags & 1u) != 0u) {
                c = vec3<f32>(1.0, 0.0, 1.0);
            }
            var n = normalize(g);
            if (!(dot(g, g) > 0.0)) { n = -dir; }
            out.color = vec4<f32>(c, 1.0);
            out.normal_depth = vec4<f32>(n, t_enter + h.t * len);
        }
    }
    pixels[idx] = out;
}

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
// The traversal only calls the field source's scalar dist(p); it never
// sees where the field comes from.
//
// Shadow and refraction rays are spliced in (shadows.wgsl, glass.wgsl) only
// when asked for, because lavapipe pays for inlined code that never runs;
// their *_off.wgsl stand-ins take their place otherwise. So is the tile
// pass (tiles.wgsl), for a field that knows which tiles are empty (a scene).

// Per-pixel sphere tracing statistics in the pass group after the pixel
// ray_stats (pass group) records: bits 0-15 over-relaxation fallbacks (saturated); bit 31 the
// primary ray saw f / L change faster than LIPSCHITZ_SLACK per unit of
// distance (not a distance bound); bits 16-30 the largest such rate as a
// half float without its sign (the estimate of the Lipschitz bound needed).

// Bisection steps when a step lands on the far side of the surface (only a
// formula that is not a distance bound, or --min-step, can do that).
const BRACKET_STEPS: i32 = 24;

// The distance bound: f / L.
fn dist(p: vec3<f32>) -> f32 { return field(p) * U.inv_lipschitz; }

// Termination rule of one march: converged when |f| < e0 + e1 * t (t along
// this march). Primary rays with technique 2 use half a pixel at the eye
// distance; otherwise a fixed width. `best` returns the best candidate, not
// the last point, when the budget runs out.
struct Crit { e0: f32, e1: f32, best: bool }
// f: the signed distance bound at the result (its sign the march's); raw:
// the field's own value there (for the normal).
struct March { t: f32, status: u32, steps: u32, fallbacks: u32, f: f32, ratio: f32, raw: f32 }

fn threshold(c: Crit, t: f32) -> f32 { return max(c.e0 + c.e1 * t, 1e-30); }

// Scalar bisection of a sign change of f between a (start side) and b.
fn bracket(o: vec3<f32>, d: vec3<f32>, a0: f32, b0: f32) -> f32 {
    // One call site of dist (see gradient): iteration -1 finds fa's side.
    var a = a0;
    var b = b0;
    var fa = false;
    for (var i = -1; i < BRACKET_STEPS; i = i + 1) {
        let m = select(0.5 * (a + b), a, i < 0);
        let neg = dist(o + d * m) < 0.0;
        if (i < 0) { fa = neg; } else if (neg == fa) { a = m; } else { b = m; }
    }
    return 0.5 * (a + b);
}

// Over-relaxed sphere tracing of o + d t over [t0, t1] (Keinert et al.,
// Listing 2) with the screen-space candidate, the fixed-point
// post-process, a minimum step and a sign-change bracket.
fn march(o: vec3<f32>, d: vec3<f32>, t0: f32, t1: f32, budget: u32, c: Crit) -> March {
    var m = March(t0, STATUS_MISS, 0u, 0u, 0.0, 0.0, 0.0);
    var f_safe = 0.0;
    var omega = U.omega;
    var t = t0;
    var fsign = 1.0;
    var prev_radius = 0.0;
    var stride = 0.0;         // the step taken to reach t
    var t_safe = t0;          // last point whose unbounding sphere was accepted
    var cand_err = F.inf;
    var cand_t = t0;
    var probing = false;      // t is the midpoint probe of a step out of the domain
    var tree_safe = 0u;       // the field's pruned tree at t_safe (field_tree)
    loop {
        // Stop before lavapipe's silent loop cap as well: the steps, the
        // field's own loop iterations so far, and room for the normal and
        // the fixed-point iterations after a hit.
        if (m.steps >= budget || g_field_work + m.steps + (8u + U.fixpoint) * field_cost() >= LOOP_LIMIT) {
            m.status = STATUS_UNRESOLVED;
            m.t = select(t_safe, cand_t, c.best);
            break;
        }
        let v = dist(o + d * t);
        m.steps = m.steps + 1u;
        if (m.steps == 1u && v < 0.0) { fsign = -1.0; } // start inside: march to the boundary
        let signed = fsign * v;
        let radius = abs(signed);
        let sor_fail = !probing && omega > 1.0 && (radius + prev_radius) < stride;
        if (sor_fail) {
            // The spheres do not overlap: go back to p_fallback and continue
            // with plain sphere tracing.
            stride = stride - omega * stride;
            omega = 1.0;
            m.fallbacks = m.fallbacks + 1u;
        } else {
            if (signed < 0.0) {
                // Past the surface: f is not a distance bound here (or the
                // minimum step or over-relaxation jumped in). The rate of
                // change across the step is at most 1 for a distance bound,
                // so it counts as evidence too. The root is bracketed.
                if (m.steps > 1u && t <= t1 && field_tree() == tree_safe) { m.ratio = max(m.ratio, (f_safe - signed) / max(t - t_safe, 1e-30)); }
                m.t = bracket(o, d, t_safe, t);
                m.steps = m.steps + u32(BRACKET_STEPS);
                m.status = STATUS_HIT;
                break;
            }
            // How fast f changed since the last accepted point: a distance
            // bound changes no faster than the distance (ratio <= 1).
            // Samples beyond the domain do not count: f far outside says
            // nothing about the bound where the surface is; nor do two
            // samples of different pruned trees of a scene (a deeper slab's pruned tree
            // may hold a primitive the shallower one rightly left out).
            if (m.steps > 1u && t != t_safe && t <= t1 && field_tree() == tree_safe) { m.ratio = max(m.ratio, abs(signed - f_safe) / abs(t - t_safe)); }
            // The spheres overlap, so [t_safe, t] holds no surface: beyond
            // t1 the ray has left the domain. (After a failed over-relaxed
            // step the fallback comes first, even beyond t1.)
            if (probing) { break; } // the probe saw no sign change: a miss
            if (t > t1) {
                // That step claims [t_safe, t1] empty. When it spans a large
                // part of the segment, check the claim once at the midpoint
                // (the next iteration evaluates it, through the one call site
                // of dist and bracket: lavapipe inlines every call): a sign
                // change there means f is no distance bound with this L. The
                // rate seen (> 2 / omega) counts the pixel as a violation,
                // and the root is bracketed instead of missed.
                if (t1 - t_safe > 0.25 * (t1 - t0)) {
                    probing = true;
                    t = 0.5 * (t_safe + t1);
                    continue;
                }
                break;
            }
            stride = max(signed * omega, U.min_step);
            t_safe = t;
            f_safe = signed;
            tree_safe = field_tree();
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
        // One call site of dist: the last iteration takes f at the result.
        for (var i = 0u; i <= U.fixpoint; i = i + 1u) {
            let raw = field(o + d * m.t);
            let v = fsign * raw * U.inv_lipschitz;
            if (i == U.fixpoint) { m.f = v; m.raw = raw; } else { m.t = clamp(m.t + (v - threshold(c, m.t)), t0, max(t1, t0)); }
        }
    }
    return m;
}

// Entry and exit of o + d t in the bounding volume (t0 > t1: missed).
fn bound_range(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    if (U.bound_kind == BOUND_SPHERE) {
        let oc = o - U.bound_a.xyz;
        let b = dot(oc, d);
        let disc = b * b - (dot(oc, oc) - U.bound_a.w * U.bound_a.w);
        if (disc < 0.0) { return vec2<f32>(1.0, -1.0); }
        let q = sqrt(disc);
        return vec2<f32>(-b - q, -b + q);
    }
    if (U.bound_kind == BOUND_BOX) { return ray_box(o, d, U.bound_a.xyz, U.bound_b.xyz); }
    return vec2<f32>(-F.inf, F.inf);
}

// The part of o + d t (t >= 0) inside the domain and the bound.
fn clip_ray(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let r = clip_domain(o, d);
    let bv = bound_range(o, d);
    return vec2<f32>(max(r.x, bv.x), min(r.y, bv.y));
}

// First surface point along o + d t, t in [t0, t1], in at most `budget`
// steps. With a convex bound, a ray that starts inside the object is traced
// backwards from t1 (on the bound) instead of through the interior
// (technique 5). `c` is given for the forward direction.
fn trace(o: vec3<f32>, d: vec3<f32>, t0: f32, t1: f32, budget: u32, c: Crit) -> March {
    // One call of march either way (lavapipe inlines every call site).
    var at_t0 = 0.0;
    var back = false;
    if (U.bound_kind != BOUND_NONE && t1 > t0) {
        at_t0 = field(o + d * t0);
        back = at_t0 < 0.0;
    }
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
    var m = march(o2, d2, r.x, r.y, budget, c2);
    if (back) {
        m.steps = m.steps + 1u;
        // A backward miss can only come from rounding (the start is inside):
        // then the far bound itself is the answer.
        m.t = select(t1 - m.t, t0, m.status == STATUS_MISS);
        if (m.status == STATUS_MISS) {
            m.status = STATUS_HIT;
            m.raw = at_t0;
        }
    }
    return m;
}

fn background(dir: vec3<f32>) -> vec3<f32> {
    let s = 0.5 + 0.5 * dot(dir, F.up.xyz);
    return mix(vec3<f32>(0.055, 0.06, 0.075), vec3<f32>(0.16, 0.18, 0.23), s);
}

// Technique 3: a secondary ray starts 2 max(eps_min, |f(p)|) away from the
// surface point p along n (a fixed eps_min when switched off).
fn offset(p: vec3<f32>, n: vec3<f32>, fp: f32) -> vec3<f32> {
    var e = U.eps_min;
    if ((F.flags & FLAG_DYNAMIC_EPS) != 0u) { e = 2.0 * max(U.eps_min, abs(fp)); }
    return p + n * e;
}

struct Shade { color: vec3<f32>, steps: u32 }
struct Lit { lit: f32, steps: u32 }

//!splice:shadows

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

//!splice:glass

// The bits of a non-negative rate as a half float without its sign (its
// mantissa truncated, tiny rates flushed to 0, large ones to +inf): written
// by hand because pack2x16float needs a capability WGSL does not promise.
fn half_bits(v: f32) -> u32 {
    let b = bitcast<u32>(max(v, 0.0));
    let e = i32((b >> 23u) & 0xffu) - 112;
    if (e >= 31) { return 0x7c00u; }
    if (e <= 0) { return 0u; }
    return (u32(e) << 10u) | ((b >> 13u) & 0x3ffu);
}

//!splice:tiles

// The termination rule of a primary ray.
fn primary_crit() -> Crit {
    if ((F.flags & FLAG_SCREEN) != 0u) { return Crit(0.0, U.pixel_radius, true); }
    return Crit(F.eps, 0.0, false);
}

// The part of the primary ray o + d t to trace: the domain (and bound) met
// with where the field says its surface can be (a scene: the depths, or
// the balls, of its tile's primitives).
fn primary_segment(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let clip = clip_ray(o, d);
    let near = field_ray_range(o, d);
    return vec2<f32>(max(clip.x, near.x), min(clip.y, near.y));
}

// A march that took no step: a ray that meets nothing.
fn missed_ray(t: f32) -> March { return March(t, STATUS_MISS, 0u, 0u, 0.0, 0.0, 0.0); }

// Shades and writes pixel px (record idx) of the primary ray along d: h is
// its march from the eye, g the field's gradient at h's point (taken by the
// caller, under the pruned tree the march evaluated), c its termination rule.
fn finish_pixel(px: vec2<u32>, idx: u32, d: vec3<f32>, h: March, g: vec3<f32>, c: Crit) {
    var color = vec4<f32>(background(d), 0.0);
    var normal = vec3<f32>(0.0);
    var depth = F.inf;
    var steps = h.steps;
    var status = h.status;
    // On an exhausted budget the best candidate (technique 2) or the last
    // point is drawn as a best guess, and counted as unconverged.
    if (status != STATUS_MISS) {
        let p = F.eye.xyz + d * h.t;
        let s = surface(p, d, g, h.f);
        steps = steps + s.steps;
        var col = s.color;
        if (U.color_mode == COLOR_FIELD) { col = heat(h.f / threshold(c, h.t)); }
        normal = normalize(g);
        if (!(dot(g, g) > 0.0)) { normal = -d; }
        color = vec4<f32>(col, 1.0);
        depth = h.t;
    }
    // An interpreted field that gave up on an evaluation proves nothing here.
    if (field_exhausted()) { status = STATUS_UNRESOLVED; }
    if (status == STATUS_UNRESOLVED) { color = vec4<f32>(unresolved_color(color.xyz, px), 1.0); }
    // d_ray 1 marks a ray that crosses the domain (at least one step), so the
    // hit / miss means of the statistics count the same pixels as bisection's.
    write_pixel(idx, color.xyz, status, normal, depth, pack_info(steps, select(0u, 1u, steps > 0u), 0u));
    let violated = select(0u, 0x80000000u, h.ratio > LIPSCHITZ_SLACK);
    ray_stats[idx] = min(h.fallbacks, 0xffffu) | (half_bits(h.ratio) << 16u) | violated;
}

//!splice:primary

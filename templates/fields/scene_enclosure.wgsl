// Interval enclosures of the scene field over a box, for bisection: the
// interpreter of scene.wgsl again, node for node, on intervals (the IA
// library's ia_* operations), so a blobtree is bisected as a formula is
// (Knoll et al.): a cell or slab is skipped only where its enclosure
// excludes the isovalue. No Lipschitz bound is taken on trust:
// - a primitive whose local field is an exact distance, or a 1-Lipschitz
//   bound of one (the types with `Lipschitz::One`, the profiles, the
//   shared box, revolved, octahedron and plane forms), is enclosed by its
//   value at the box's centre plus or minus the box's half-diagonal:
//   |f(p) - f(c)| <= |p - c| is a property of the function itself. Frames
//   are turns and uniform scalings, and the world field s d(q) keeps it;
// - a density primitive, a voxel grid, a warp, a unary node, an operator
//   and a join are enclosed by interval arithmetic on their formulas.
//
// Pruned trees: a tile's pruned tree holds every primitive whose bounding
// volume meets the tile's frustum (one slab a tile when bisecting). Beyond
// its volume a primitive's value is past its operators' ranges, where they
// are sharp and leave their other operand's sign (and its value near the
// surface) as it is, so within the frustum the pruned tree's field has the
// whole tree's zero set and signs. A cell's segment and a tile-pass slab
// lie in the frustum; their boxes stick out of it, which only widens the
// enclosure of that field (docs/scenes.md, "Bisecting a scene").

// A box as centre and half-extents.
struct SceneBox { c: vec3<f32>, r: vec3<f32> }

// The segment of the cell being enclosed: its world half-vector in xyz, w
// = 1 (w = 0: not a cell's segment, as the tile pass's slabs). A formula
// leaf whose cells are enclosed in RAA runs along it
// (scene_formula_ra.wgsl).
var<private> g_cell_half: vec4<f32>;

// The box lo..hi, its extents rounded up so that c +- r holds it.
fn scene_box(lo: vec3<f32>, hi: vec3<f32>) -> SceneBox {
    let c = 0.5 * lo + 0.5 * hi;
    return SceneBox(c, max(hi - c, c - lo) * (1.0 + 4e-7));
}
// The box's low and high corners, rounded outward.
fn scene_lo(b: SceneBox) -> vec3<f32> { return b.c - b.r - 1.2e-7 * abs(b.c); }
fn scene_hi(b: SceneBox) -> vec3<f32> { return b.c + b.r + 1.2e-7 * abs(b.c); }

// [v - w, v + w] for a 1-Lipschitz field whose value at the centre of a box
// of half-diagonal w is v, widened by f32's error in v (relative to the
// magnitudes m it was computed from).
fn scene_centred(v: f32, w: f32, m: f32) -> vec2<f32> {
    let e = 1e-6 * w + 4e-6 * m;
    return vec2<f32>(v - w - e, v + w + e);
}

// The local box of a frame (r0, r1: scene_local) over box b: the centre's
// image and the half-extents through |M|, M the frame's linear part (the
// image of a box under a linear map lies in that box).
fn scene_local_box(r0: vec4<f32>, r1: vec4<f32>, b: SceneBox) -> SceneBox {
    let z = vec4<f32>(0.0);
    let mx = scene_local(r0, z, vec3<f32>(1.0, 0.0, 0.0));
    let my = scene_local(r0, z, vec3<f32>(0.0, 1.0, 0.0));
    let mz = scene_local(r0, z, vec3<f32>(0.0, 0.0, 1.0));
    let c = scene_local(r0, r1, b.c);
    let r = abs(mx) * b.r.x + abs(my) * b.r.y + abs(mz) * b.r.z;
    // f32's error in c: of p - centre, then of the turn.
    let e = 1e-6 * (length(c) + dot(r0, r0) * (length(b.c) + length(r1.xyz)));
    return SceneBox(c, r * (1.0 + 1e-6) + e);
}

// dot(a, p) over the box.
fn scene_dot_ia(a: vec3<f32>, b: SceneBox) -> vec2<f32> {
    let m = dot(a, b.c);
    let w = dot(abs(a), b.r) * (1.0 + 1e-6) + 1e-6 * dot(abs(a), abs(b.c));
    return vec2<f32>(m - w, m + w);
}

// A voxel grid (scene_grid) over the local box q. Its value is
// nondecreasing in both the trilinear value g at the nearest point of the
// grid's box and the distance h to that box, so it runs from its value at
// (min g, min h) to its value at (max g, max h). Over a box whose nearest
// points lie in one cell, g is multilinear there and takes its extremes at
// the corners of that box; over a box that meets several cells, the whole
// line (bisection splits it until it is in one cell; a loop over more
// samples would count against lavapipe's loop cap).
fn scene_grid_ia(q: SceneBox, r2: vec4<f32>, o: u32) -> vec2<f32> {
    let n = r2.xyz;
    let origin = scene_param(o + 3u);
    let lo = origin.xyz;
    let hi = lo + (n - 1.0) * origin.w;
    let qlo = scene_lo(q);
    let qhi = scene_hi(q);
    let clo = clamp(qlo, lo, hi);
    let chi = clamp(qhi, lo, hi);
    // The cells of both ends, from slightly widened coordinates: a point on
    // a face between cells may be taken in either.
    let ulo = (clo - lo) * r2.w - 1e-4;
    let uhi = (chi - lo) * r2.w + 1e-4;
    let i = clamp(floor(ulo), vec3<f32>(0.0), n - 2.0);
    let one_cell = all(clamp(floor(uhi), vec3<f32>(0.0), n - 2.0) == i);
    let tlo = clamp((clo - lo) * r2.w - i, vec3<f32>(0.0), vec3<f32>(1.0));
    let thi = clamp((chi - lo) * r2.w - i, vec3<f32>(0.0), vec3<f32>(1.0));
    let nx = u32(n.x);
    let sz = nx * u32(n.y);
    let k = u32(i.x) + nx * u32(i.y) + sz * u32(i.z);
    let row = o + GRID_ROWS;
    let s000 = scene_sample(row, k);
    let s100 = scene_sample(row, k + 1u);
    let s010 = scene_sample(row, k + nx);
    let s110 = scene_sample(row, k + nx + 1u);
    let s001 = scene_sample(row, k + sz);
    let s101 = scene_sample(row, k + sz + 1u);
    let s011 = scene_sample(row, k + sz + nx);
    let s111 = scene_sample(row, k + sz + nx + 1u);
    // Along x at both ends of the box's x range (x: at tlo.x, y: at thi.x).
    let x00 = mix(vec2<f32>(s000), vec2<f32>(s100), vec2<f32>(tlo.x, thi.x));
    let x10 = mix(vec2<f32>(s010), vec2<f32>(s110), vec2<f32>(tlo.x, thi.x));
    let x01 = mix(vec2<f32>(s001), vec2<f32>(s101), vec2<f32>(tlo.x, thi.x));
    let x11 = mix(vec2<f32>(s011), vec2<f32>(s111), vec2<f32>(tlo.x, thi.x));
    // The eight corners: (x end) x (y end) x (z end).
    let y0l = mix(x00, x10, vec2<f32>(tlo.y));
    let y0h = mix(x00, x10, vec2<f32>(thi.y));
    let y1l = mix(x01, x11, vec2<f32>(tlo.y));
    let y1h = mix(x01, x11, vec2<f32>(thi.y));
    let c0 = mix(y0l, y1l, vec2<f32>(tlo.z));
    let c1 = mix(y0l, y1l, vec2<f32>(thi.z));
    let c2 = mix(y0h, y1h, vec2<f32>(tlo.z));
    let c3 = mix(y0h, y1h, vec2<f32>(thi.z));
    let gmin = min(min(min(c0.x, c0.y), min(c1.x, c1.y)), min(min(c2.x, c2.y), min(c3.x, c3.y)));
    let gmax = max(max(max(c0.x, c0.y), max(c1.x, c1.y)), max(max(c2.x, c2.y), max(c3.x, c3.y)));
    let ge = 1e-6 * max(abs(gmin), abs(gmax));
    let g = select(vec2<f32>(-F.inf, F.inf), vec2<f32>(gmin - ge, gmax + ge), one_cell);
    // The distance to the grid's box: per axis, nearest and farthest.
    let dmin = max(max(lo - qhi, qlo - hi), vec3<f32>(0.0));
    let dmax = max(max(lo - qlo, qhi - hi), vec3<f32>(0.0));
    let h = vec2<f32>(length(dmin), length(dmax) * (1.0 + 1e-6));
    return select(g + h, sqrt(g * g + h * h), g >= vec2<f32>(0.0));
}

// The shape of a primitive's record (scene_shape) over box b: the centred
// form of its distance, or the enclosure of a type whose field is not one
// (primitive_enclosures: src/sdf/primitive, spliced in by
// src/field/scene/mod.rs; the voxel grid).
fn scene_shape_ia(r0: vec4<f32>, r1: vec4<f32>, r2: vec4<f32>, b: SceneBox, o: u32, along: bool) -> vec2<f32> {
    let form = u32(r1.w) & 15u;
    // A formula leaf's value at the centre is no part of its enclosure:
    // its tape is not run for it.
    let formula = (SCENE_FEATURES & FEATURE_FORMULA) != 0u && form == FORM_FORMULA;
    let v = scene_shape(r0, r1, r2, b.c, o, !formula);
    var e = scene_centred(v, length(b.r), abs(v) + length(b.c) + length(r1.xyz));
    //!splice:primitive_enclosures
    if ((SCENE_FEATURES & FEATURE_GRID) != 0u) {
        if (form == FORM_GRID) { e = scene_grid_ia(scene_local_box(r0, r1, b), r2, o) / dot(r0, r0); }
    }
    if ((SCENE_FEATURES & FEATURE_FORMULA) != 0u) {
        if (formula) { e = scene_formula_ia(r0, r1, b, r2, o, along) / dot(r0, r0); }
    }
    return e;
}

// A warp's box (scene_warp): the warp frame's box over b, turned by the
// interval angle k q.z (twist) or k q.x (bend); the range of the frame
// point's distance rho from the axis; the warp's row (s_A, k, clamp
// radius, clamp floor). The interval turn holds at every radius: the
// enclosure needs no bound of the warp's stretch.
struct SceneWarpBox { b: SceneBox, rho: vec2<f32>, w: vec4<f32> }

fn scene_warp_box(r1: vec4<f32>, b: SceneBox, o: u32) -> SceneWarpBox {
    let a0 = scene_param(o - 4u);
    let a1 = scene_param(o - 3u);
    let a2 = scene_param(o - 2u);
    let w = scene_param(o - 1u);
    let q = SceneBox(vec3<f32>(dot(a0.xyz, b.c) + a0.w, dot(a1.xyz, b.c) + a1.w, dot(a2.xyz, b.c) + a2.w),
                     vec3<f32>(dot(abs(a0.xyz), b.r), dot(abs(a1.xyz), b.r), dot(abs(a2.xyz), b.r)) * (1.0 + 1e-6) + 1e-6 * length(b.c));
    let lo = scene_lo(q);
    let hi = scene_hi(q);
    let X = vec2<f32>(lo.x, hi.x);
    let Y = vec2<f32>(lo.y, hi.y);
    let bend = (u32(r1.w) >> FORM_WARP_SHIFT) == 2u;
    let a = ia_scale(select(vec2<f32>(lo.z, hi.z), X, bend), w.y);
    let c = ia_cos(a);
    let s = ia_sin(a);
    let cx = ia_mul(c, X);
    let sy = ia_mul(s, Y);
    let cy = ia_mul(c, Y);
    let sx = ia_mul(s, X);
    let tx = select(ia_add(cx, sy), ia_sub(cx, sy), bend);
    let ty = select(ia_sub(cy, sx), ia_add(sx, cy), bend);
    let near = max(max(lo.xy, -hi.xy), vec2<f32>(0.0));
    let far = max(abs(lo.xy), abs(hi.xy));
    let rho = vec2<f32>(length(near), length(far));
    return SceneWarpBox(scene_box(vec3<f32>(tx.x, ty.x, lo.z), vec3<f32>(tx.y, ty.y, hi.z)), rho, w);
}

// scene_warp_value over ranges: f = s_A d, and beyond the clamp radius
// min(f, max(f S(R)/S(rho), floor)), the scene's field (the clamp keeps
// sphere tracing's bound, and a blend above the warp sees the clamped
// value, so bisection encloses the same field). S grows with rho: the
// ratio runs between its values at rho's ends.
fn scene_warp_value_ia(wb: SceneWarpBox, bend: bool, d: vec2<f32>) -> vec2<f32> {
    let w = wb.w;
    let f = ia_scale(d, w.x);
    let s_r = scene_stretch(bend, w.y, w.z);
    let ratio = vec2<f32>(s_r / scene_stretch(bend, w.y, wb.rho.y), s_r / scene_stretch(bend, w.y, wb.rho.x));
    let clamped = min(f, max(ia_mul(f, ia_pad(ratio, 0.0, 1e-6)), vec2<f32>(w.w)));
    let hull = vec2<f32>(min(f.x, clamped.x), max(f.y, clamped.y));
    return select(select(hull, f, wb.rho.y <= w.z), clamped, wb.rho.x > w.z);
}

// A primitive over box b: warped or not, the shape's code inlined once
// (scene_primitive).
fn scene_primitive_ia(r0: vec4<f32>, r1: vec4<f32>, r2: vec4<f32>, b: SceneBox, o: u32) -> vec2<f32> {
    var at = b;
    var warped = false;
    var wb: SceneWarpBox;
    if ((SCENE_FEATURES & FEATURE_WARP) != 0u) {
        warped = u32(r1.w) >= (1u << FORM_WARP_SHIFT);
        if (warped) {
            wb = scene_warp_box(r1, b, o);
            at = wb.b;
        }
    }
    var e = scene_shape_ia(r0, r1, r2, at, o, !warped);
    if ((SCENE_FEATURES & FEATURE_WARP) != 0u) {
        if (warped) { e = scene_warp_value_ia(wb, (u32(r1.w) >> FORM_WARP_SHIFT) == 2u, e); }
    }
    return e;
}

// A unary node over box b on operand range v (scene_unary; unary_enclosures:
// src/sdf/unary).
fn scene_unary_ia(ty: u32, k: vec4<f32>, v: vec2<f32>, b: SceneBox) -> vec2<f32> {
    var r = v;
    //!splice:unary_enclosures
    return r;
}

// scene_blend over |a - b| in t and beta in beta_r: it falls with t and
// grows with beta (d/dbeta (beta - t)^3 / beta^2 >= 0 for beta >= t).
fn scene_blend_ia(t: vec2<f32>, beta_r: vec2<f32>) -> vec2<f32> {
    let h = max(beta_r.yx - t, vec2<f32>(0.0));
    let b2 = max(beta_r.yx * beta_r.yx, vec2<f32>(1e-30));
    return (h * h * h / (6.0 * b2)).yx;
}

// scene_blend_range over x: it falls as x grows.
fn scene_blend_range_ia(x: vec2<f32>, beta: f32, r_o: f32) -> vec2<f32> {
    return beta * max(1.0 - 6.0 * x.yx / max(6.0 * r_o - beta, 1e-30), vec2<f32>(0.0));
}

// Operator `ty` on operand ranges a and b (scene_operator): the sharp
// operators and joins from their ends (each is nondecreasing in both
// operands, src/sdf/join), Zanni's G by interval arithmetic on its
// formula, with the hull of the blended and the sharp value where the box
// may be on both sides of the operator's range.
fn scene_operator_ia(ty: u32, k: vec4<f32>, a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let cls = (ty - NODE_UNION) % 3u;
    let uni = cls == 0u;
    let c = select(b, ia_neg(b), cls == 2u);
    let beta = k.x;
    let r_o = k.y;
    let sharp = select(max(a, c), min(a, c), uni);
    var r = sharp;
    if (beta > 0.0) {
        let lo = min(a, c);
        let hi = max(a, c);
        let t = ia_abs(a - c.yx);
        let b0 = scene_blend_ia(t, vec2<f32>(beta));
        let x = select(ia_abs(hi + b0), lo - b0.yx, uni);
        let g = scene_blend_ia(t, scene_blend_range_ia(x, beta, r_o));
        let blended = select(hi + g, lo - g.yx, uni);
        let m = select(max(ia_abs(a), ia_abs(c)), max(a, c), uni);
        let hull = vec2<f32>(min(sharp.x, blended.x), max(sharp.y, blended.y));
        r = select(select(hull, blended, m.y <= r_o), sharp, m.x > r_o);
    }
    if ((SCENE_FEATURES & FEATURE_JOIN) != 0u) {
        let s = select(-1.0, 1.0, uni);
        let lo_end = s * scene_join(ty, s * a.x, s * c.x, k.z);
        let hi_end = s * scene_join(ty, s * a.y, s * c.y, k.z);
        r = select(r, vec2<f32>(lo_end, hi_end), ty >= NODE_JOIN_FIRST && ty <= NODE_JOIN_LAST);
    }
    return r;
}

// The interval value stack below its top, as the scalar one
// (scene.wgsl): its four upper intervals in two vector registers
// (g_scene_near_ia[0].xy the one below the top), the rest in an array.
var<private> g_scene_near_ia: array<vec4<f32>, 2>;
var<private> g_scene_stack_ia: array<vec2<f32>, SCENE_MAX_STACK>;

fn scene_push_ia(v: vec2<f32>, sp: u32) {
    let n0 = g_scene_near_ia[0];
    let n1 = g_scene_near_ia[1];
    if (sp >= 4u) { g_scene_stack_ia[min(sp - 4u, SCENE_MAX_STACK - 1u)] = n1.zw; }
    g_scene_near_ia[0] = vec4<f32>(v, n0.xy);
    g_scene_near_ia[1] = vec4<f32>(n0.zw, n1.xy);
}
fn scene_pop_ia(sp: u32) -> vec2<f32> {
    let n0 = g_scene_near_ia[0];
    let n1 = g_scene_near_ia[1];
    var deep = vec2<f32>(0.0);
    if (sp > 4u) { deep = g_scene_stack_ia[min(sp - 5u, SCENE_MAX_STACK - 1u)]; }
    g_scene_near_ia[0] = vec4<f32>(n0.zw, n1.xy);
    g_scene_near_ia[1] = vec4<f32>(n1.zw, deep);
    return n0.xy;
}

// A fused sharp operator on intervals (scene_fused's).
fn scene_fused_ia(ty: u32, top: vec2<f32>, v: vec2<f32>) -> vec2<f32> {
    let cls = (ty - NODE_UNION) % 3u;
    let c = select(v, ia_neg(v), cls == 2u);
    return select(max(top, c), min(top, c), cls == 0u);
}

// One node of an enclosure (scene_step on intervals, with its branches).
fn scene_step_ia(e: u32, b: SceneBox, sp: ptr<function, u32>, top: ptr<function, vec2<f32>>) {
    let o = entry_row(e);
    let leaf = (e >> 31u) != 0u;
    let ty = entry_type(e);
    if (leaf) {
        var v: vec2<f32>;
        if ((SCENE_FEATURES & FEATURE_SHAPES) != 0u) {
            v = scene_primitive_ia(scene_param(o), scene_param(o + 1u), scene_param(o + 2u), b, o);
        } else {
            let c = scene_param(o + 1u);
            let d = length(b.c - c.xyz) - scene_param(o + 2u).w;
            v = scene_centred(d, length(b.r), abs(d) + length(b.c) + length(c.xyz));
        }
        if (ty != 0u) {
            *top = scene_fused_ia(ty, *top, v);
        } else {
            scene_push_ia(*top, *sp);
            *sp = *sp + 1u;
            *top = v;
        }
        return;
    }
    let k = scene_param(o);
    if ((SCENE_FEATURES & FEATURE_UNARY) != 0u && ty >= NODE_OFFSET) {
        *top = scene_unary_ia(ty, k, *top, b);
        return;
    }
    let below = scene_pop_ia(*sp);
    *sp = *sp - 1u;
    *top = scene_operator_ia(ty, k, below, *top);
}

// The enclosure of the field over the box X x Y x Z: the nodes of the
// pruned tree (or the whole tree) in post-order, as field() runs them. Past
// the work limit, the whole line (the pixel is reported: field_exhausted).
fn surf_ia(X: vec2<f32>, Y: vec2<f32>, Z: vec2<f32>, T: vec2<f32>) -> vec2<f32> {
    let lo = vec3<f32>(X.x, Y.x, Z.x);
    let hi = vec3<f32>(X.y, Y.y, Z.y);
    if (!(all(abs(lo) < vec3<f32>(F.inf)) && all(abs(hi) < vec3<f32>(F.inf)))) { return ia_whole(); }
    let b = scene_box(lo, hi);
    let len = scene_pruned_len();
    let full = len == SCENE_WHOLE_TREE;
    let n = select(len, scene_node_count(), full);
    let own = g_ray_own;
    let fuse = select(0u, NODE_UNION << SCENE_ENTRY_ROW_BITS, scene_union());
    let wanted = select(n, g_ray_len, own);
    let steps = scene_admit(wanted);
    var sp = 0u;
    var top = vec2<f32>(F.inf);
    var j = 0u;
    for (; j < steps; j = j + 1u) {
        let at = select(j, g_ray_list[min(j, 2u * SCENE_UNION_MAX - 1u)], own);
        var e: u32;
        if (full) { e = scene_entry(at); } else { e = scene_slab_entry(at) | fuse; }
        scene_step_ia(e, b, &sp, &top);
    }
    g_field_work = g_field_work + j;
    if (steps < wanted) { return ia_whole(); }
    // An empty tree's +inf stays as it is (padding it would give NaN).
    let padded = ia_pad(top, 1e-6 * (1.0 + length(b.c) + length(b.r)), 1e-6);
    return select(padded, top, abs(top) >= vec2<f32>(F.inf));
}

// Bisection's cells: the range over the segment's box, with no slope (a
// tree's cells are not taken as monotone; the mean-value form has no slope
// to use either), but for a tree that is one formula leaf, whose tape has
// a derivative program (scene_leaf_cell).
fn cell_enclosure(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32, slope: bool) -> vec4<f32> {
    // Leaves in RAA run along the segment (scene_formula_ia.wgsl).
    g_cell_half = vec4<f32>(dir * (0.5 * (s1 - s0)), 1.0);
    var r = vec4<f32>(1.0, 0.0, 0.0, 0.0);
    if ((SCENE_FEATURES & FEATURE_FORMULA) != 0u && slope) { r = scene_leaf_cell(o, dir, s0, s1); }
    if (!(r.x <= r.y)) { r = vec4<f32>(cell_range(o, dir, s0, s1), -F.inf, F.inf); }
    g_cell_half = vec4<f32>(0.0);
    return r;
}
fn field_ray(o: vec3<f32>, dir: vec3<f32>, s: f32) -> f32 { return field(o + dir * s); }
fn field_begin_ray(o: vec3<f32>, dir: vec3<f32>, s_ref: f32, len: f32) {}

// Bisection's tile pass and per-pixel pass enter tile t's pruned tree; the
// tile's entry of the pass (its `list`) is t + 1, 0 for the whole tree (a
// kernel without the tile pass).
var<private> g_scene_bisect_tile: u32;
fn field_tile_begin(t: u32, tile: vec2<u32>, block: bool) -> vec3<u32> {
    scene_tile_pass_limit();
    scene_enter_tile(t);
    g_scene_bisect_tile = t;
    return vec3<u32>(0xffffffffu, 0xffffffffu, 0u);
}
fn field_slab_begin(record: bool) {}
fn field_slab_end(hold: bool) {}
fn field_tile_done(mask: vec2<u32>, n: u32, block: bool) -> u32 { return g_scene_bisect_tile + 1u; }
fn field_enter_tile(list: u32) {
    if (list == 0u) { field_leave_frustum(); } else { scene_enter_tile(list - 1u); }
}
// Points off the ray near a hit (its gradient) stay where the pruned tree
// has the whole tree's value: near the surface in the tile's frustum.
fn field_in_tile(inside: bool) {}

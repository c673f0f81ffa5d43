// The scene field source: a blobtree kept as data (src/scene/linear.rs lays
// it out) and evaluated by one fixed interpreter, so editing, adding or
// removing primitives of the compiled-in types changes buffers only and
// never recompiles. The node and operator functions are the formula
// language's distance forms (src/sdf.rs) and Zanni's compact smooth
// operators G (eq. 12-18), in the same arithmetic as the reference
// (src/scene/eval.rs).
//
// Node word x: isLeaf (bit 31) | isLeft (bit 30) | type (bits 22-29; a
// leaf's union-path and comb flags in bits 29 and 28) | parent (bits
// 0-21); y: the node's first vec4 in scene_params; z: its fast ancestor.
// Nodes and parameters are textures, read with textureLoad: lavapipe
// loads from a storage buffer at a per-lane address one lane and one
// component at a time, a texel fetch is a vector gather (several
// times faster per node; src/scene/linear.rs, TEXTURE_WIDTH). A
// primitive's record: 3 rows of M = [R^T / s | -R^T t / s] (local point
// q = M (p, 1)), (s, half extents), (rounding, major radius or offset,
// form, 0). An operator's record: (beta, r_o, 0, 0).
//
// Node type codes and SCENE_MAX_STACK come from Rust (src/scene/linear.rs,
// spliced before this file), and so does SCENE_FEATURES: the FEATURE_* bits
// of the node types the scene uses. Code for the others sits behind
// constant-false conditions that the driver's compiler removes, so a scene
// of basic primitives runs the interpreter it ran before profiles, unary
// nodes and displacements existed (a kernel per feature set, cached).

// scene_nodes and scene_params (field group, src/field/scene/source.rs).
fn scene_texel(i: u32) -> vec2<u32> { return vec2<u32>(i & (SCENE_TEX_WIDTH - 1u), i >> SCENE_TEX_SHIFT); }
// Node i (texel 0 holds the node count).
fn scene_node(i: u32) -> vec4<u32> { return textureLoad(scene_nodes, scene_texel(i + 1u), 0); }
fn scene_node_count() -> u32 { return textureLoad(scene_nodes, vec2<u32>(0u, 0u), 0).x; }
fn scene_prim_count() -> u32 { return textureLoad(scene_nodes, vec2<u32>(0u, 0u), 0).y; }
fn scene_param(i: u32) -> vec4<f32> { return textureLoad(scene_params, scene_texel(i), 0); }

fn node_type(w: u32) -> u32 { return (w >> 22u) & 0xffu; }

// The box, profile and grid distances are in scene_shapes.wgsl, the formula
// leaves in scene_formula.wgsl (appended).

// The local point A(p - c)/s of a primitive's frame rows: r0 = Q, its
// quaternion divided by sqrt(s) (an unnormalised quaternion scales as it
// turns), r1.xyz = c (src/scene/linear.rs).
fn scene_local(r0: vec4<f32>, r1: vec4<f32>, p: vec3<f32>) -> vec3<f32> {
    let v = p - r1.xyz;
    let u = r0.xyz;
    let w = r0.w;
    return (w * w - dot(u, u)) * v + 2.0 * dot(u, v) * u + 2.0 * w * cross(u, v);
}

// The distance of the primitive whose record starts at row o with rows
// r0..r2 (the layout of src/scene/linear.rs), at p. One branch-free formula
// for every basic type: the lanes of a SIMD bundle may hold primitives of
// different types (a union tile's rays take their own members), and
// lavapipe runs every arm of a switch that some lane takes, one after
// another under masks. Profiles, grids and formula leaves (with `cases`;
// the interval side runs a formula leaf itself) and the types with a case
// of their own (primitive_cases: src/sdf/primitive, spliced in by
// src/field/scene/mod.rs) only where the scene has them.
fn scene_shape(r0: vec4<f32>, r1: vec4<f32>, r2: vec4<f32>, p: vec3<f32>, o: u32, cases: bool) -> f32 {
    let q = scene_local(r0, r1, p);
    let form = u32(r1.w) & 15u;
    let revolved = form == FORM_REVOLVED;
    // A revolved form: R in place of its y extent, which bounds nothing.
    let v = select(q, vec3<f32>(length(q.xy) - r2.y, 0.0, q.z), revolved);
    var d = sd_box(v, select(r2.xyz, vec3<f32>(r2.x, 1e30, r2.z), revolved)) - r2.w;
    d = select(d, (abs(q.x) + abs(q.y) + abs(q.z) - r2.x) * 0.57735027, form == FORM_OCTAHEDRON);
    d = select(d, dot(r2.xyz, q), form == FORM_PLANE);
    if ((SCENE_FEATURES & FEATURE_PROFILE) != 0u) {
        // A branch: SIMD groups without a profile's lane skip it.
        if (cases && (form == FORM_EXTRUDE || form == FORM_REVOLVE)) { d = scene_profiled(q, r2, form, o); }
    }
    //!splice:primitive_cases
    if ((SCENE_FEATURES & FEATURE_GRID) != 0u) {
        // A branch: the eight sample fetches only on a grid's lanes.
        if (cases && form == FORM_GRID) { d = scene_grid(q, r2, o); }
    }
    if ((SCENE_FEATURES & FEATURE_FORMULA) != 0u) {
        // A branch: the tape's run only on a formula leaf's lanes.
        if (cases && form == FORM_FORMULA) { d = scene_formula(q, r2, o); }
    }
    // s = 1/|Q|^2.
    return d / dot(r0, r0);
}

// The stretch of a twist ((a + sqrt(a^2 + 4)) / 2) or a bend (1 + a) within
// radius rho of its axis, a = |k| rho (src/sdf/warp.rs).
fn scene_stretch(bend: bool, k: f32, rho: f32) -> f32 {
    let a = abs(k) * rho;
    return select((a + sqrt(a * a + 4.0)) * 0.5, 1.0 + a, bend);
}

// A warped primitive (src/scene/warp.rs): its warp's rows come before its
// own, (A^-1 as 3 rows, (s_A, k, clamp radius, clamp floor)). The frame
// point q, turned by -k q.z (twist) or k q.x (bend) about z, is where the
// primitive's own rows are evaluated; the value is then scaled by s_A and,
// beyond the clamp radius, scaled down by the ratio of stretches, to no
// less than the floor.
struct SceneWarp {
    point: vec3<f32>,
    // (s_A, k, clamp radius, clamp floor).
    w: vec4<f32>,
    rho: f32,
    bend: bool,
}

fn scene_warp(r1: vec4<f32>, p: vec3<f32>, o: u32) -> SceneWarp {
    let p4 = vec4<f32>(p, 1.0);
    let q = vec3<f32>(dot(scene_param(o - 4u), p4), dot(scene_param(o - 3u), p4), dot(scene_param(o - 2u), p4));
    let w = scene_param(o - 1u);
    let bend = (u32(r1.w) >> FORM_WARP_SHIFT) == 2u;
    let a = w.y * select(q.z, q.x, bend);
    let c = cos(a);
    let s = sin(a);
    let twisted = vec3<f32>(c * q.x + s * q.y, c * q.y - s * q.x, q.z);
    let bent = vec3<f32>(c * q.x - s * q.y, s * q.x + c * q.y, q.z);
    return SceneWarp(select(twisted, bent, bend), w, length(q.xy), bend);
}

fn scene_warp_value(sw: SceneWarp, d: f32) -> f32 {
    let f = sw.w.x * d;
    let far = min(f, max(f * (scene_stretch(sw.bend, sw.w.y, sw.w.z) / scene_stretch(sw.bend, sw.w.y, sw.rho)), sw.w.w));
    return select(f, far, sw.rho > sw.w.z);
}

// A primitive: warped or not. The shape's code is inlined once: a warp only
// moves the point it is evaluated at and changes the value after.
fn scene_primitive(r0: vec4<f32>, r1: vec4<f32>, r2: vec4<f32>, p: vec3<f32>, o: u32) -> f32 {
    var at = p;
    var warped = false;
    var sw: SceneWarp;
    if ((SCENE_FEATURES & FEATURE_WARP) != 0u) {
        // A branch: the warp's rows are fetched only on its lanes.
        warped = u32(r1.w) >= (1u << FORM_WARP_SHIFT);
        if (warped) {
            sw = scene_warp(r1, p, o);
            at = sw.point;
        }
    }
    var d = scene_shape(r0, r1, r2, at, o, true);
    if ((SCENE_FEATURES & FEATURE_WARP) != 0u) {
        if (warped) { d = scene_warp_value(sw, d); }
    }
    return d;
}

// A unary node of type `ty` with record k (its type's row) on operand
// value v at p: the case of its type (unary_cases: src/sdf/unary, a file a
// type, spliced in by src/field/scene/mod.rs), those with a feature of
// their own only where the scene has it.
fn scene_unary(ty: u32, k: vec4<f32>, v: f32, p: vec3<f32>) -> f32 {
    var r = v;
    //!splice:unary_cases
    return r;
}

// Zanni's blend d(a, b, beta) = beta/6 max(1 - |a - b|/beta, 0)^3, NaN-free.
fn scene_blend(a: f32, b: f32, beta: f32) -> f32 {
    let h = max(beta - abs(a - b), 0.0);
    return h * h * h / (6.0 * max(beta * beta, 1e-30));
}

// b_r(x, beta, r_o) = beta max(1 - 6x / (6 r_o - beta), 0) (eq. 18); the
// host guarantees 6 r_o > beta for smooth operators.
fn scene_blend_range(x: f32, beta: f32, r_o: f32) -> f32 {
    return beta * max(1.0 - 6.0 * x / max(6.0 * r_o - beta, 1e-30), 0.0);
}

// The join `ty` of x and y with size s as a union: the case of its join
// (join_cases: src/sdf/join, a file a join, spliced in by
// src/field/scene/mod.rs); an intersection is the negated union of the
// negated operands, which is the same arithmetic as its own formula
// (negation and min/max are exact).
fn scene_join(ty: u32, x: f32, y: f32, s: f32) -> f32 {
    var j = min(x, y);
    //!splice:join_cases
    return j;
}

// Operator `ty` with record k = (beta, r_o, join size, 0) on operands a
// (left) and b (right), branch-free for the reason above. G (eq. 12, 17):
// the compact blend where both operands are in the operator's range R_o,
// sharp CSG elsewhere and for the sharp operators (beta = 0). The codes
// come three a style from NODE_UNION (union, intersection, difference).
fn scene_operator(ty: u32, k: vec4<f32>, a: f32, b: f32) -> f32 {
    let cls = (ty - NODE_UNION) % 3u;
    let uni = cls == 0u;
    let c = select(b, -b, cls == 2u);
    let beta = k.x;
    let r_o = k.y;
    let lo = min(a, c);
    let hi = max(a, c);
    let b0 = scene_blend(a, c, beta);
    let x = select(abs(hi + b0), lo - b0, uni);
    let g = scene_blend(a, c, scene_blend_range(x, beta, r_o));
    let blended = select(hi + g, lo - g, uni);
    let outside = select(abs(a) > r_o || abs(c) > r_o, a > r_o || c > r_o, uni);
    var r = select(select(hi, lo, uni), blended, beta > 0.0 && !outside);
    if ((SCENE_FEATURES & FEATURE_JOIN) != 0u) {
        let m = select(-1.0, 1.0, uni);
        r = select(r, m * scene_join(ty, m * a, m * c, k.z), ty >= NODE_JOIN_FIRST && ty <= NODE_JOIN_LAST);
    }
    return r;
}

// scene_prims, scene_balls (field group): per primitive, its node index and
// its augmented bounding ball (centre, radius; an infinite radius for
// unbounded primitives such as planes).
// Each tile's first SCENE_TABLE_WORDS tile words are its slab table, the
// pruned trees follow: (slab count, margin, first and last depth of its
// primitives; 0 slabs: the whole tree), then per slab (its first tile word
// in the tile, its length, the view depth where its core begins, 0).
// Written by the pruning pass (scene_tiles.wgsl) and read, like the
// pruned trees, as texels: once per pixel, where storage loads would run lane by
// lane.
const SCENE_TABLE_WORDS: u32 = 4u * (SCENE_SLABS_MAX + 1u);

const SCENE_NO_TILE: u32 = 0xffffffffu;
// A node as a pruned tree holds it: isLeaf (bit 31), type (bits
// SCENE_ENTRY_ROW_BITS to 30) and its first parameter row (the bits below):
// what the interpreter needs, without a fetch of the node's own texel. A
// leaf's type is 0 (its rows say its form), or in a pruned tree the sharp union,
// intersection or difference whose right operand it is, fused into it
// (scene_tiles.wgsl): the operator then costs no node of its own.
fn scene_entry(i: u32) -> u32 {
    let w = scene_node(i);
    let leaf = (w.x & 0x80000000u) != 0u;
    return (w.x & 0x80000000u) | (select(node_type(w.x), 0u, leaf) << SCENE_ENTRY_ROW_BITS) | w.y;
}
fn entry_type(e: u32) -> u32 { return (e >> SCENE_ENTRY_ROW_BITS) & 0x3fu; }
fn entry_row(e: u32) -> u32 { return e & ((1u << SCENE_ENTRY_ROW_BITS) - 1u); }

// scene_pruned_tex (field group): the tiles' pruned trees (scene_entry words), copied from scene_tile_pruned by
// the host after the pruning pass: a texel fetch per node instead of a
// storage load, which lavapipe runs lane by lane at a per-lane address.
// SCENE_PRUNED_TEX_WIDTH texels a row, SCENE_PRUNED_MAX a tile.
fn scene_pruned_node(i: u32) -> u32 {
    return textureLoad(scene_pruned_tex, vec2<u32>(i % SCENE_PRUNED_TEX_WIDTH, i / SCENE_PRUNED_TEX_WIDTH), 0).x;
}

// The tile whose pruned tree this invocation's field evaluates: set for a
// primary ray (its point stays in the tile's frustum), cleared for
// secondary rays, which leave it and need the whole tree.
var<private> g_scene_tile: u32 = SCENE_NO_TILE;

// The pruned tree this invocation evaluates: its length (SCENE_WHOLE_TREE: the
// whole tree) and first word in scene_tile_pruned.
var<private> g_scene_len: u32 = SCENE_WHOLE_TREE;
var<private> g_scene_vbase: u32 = 0u;

// A tile's depth slabs (Zanni's depth ranges; each ray walks them on its
// own, or the tile's rays together with scene_sync.wgsl):
// the pruned tree of slab k holds the primitives whose bounding volume meets the
// tile's frustum within the slab's depths widened by a margin. The current
// slab's core depths (view-space z; the slab is used there) and its padded
// depths (its pruned tree is exact there).
var<private> g_scene_core: vec2<f32>;
var<private> g_scene_pad: vec2<f32>;

// The tile's slab table, read once per pixel: each slab's core start
// (+inf past the last), first tile word and pruned-tree length, and the margin.
// Changing slabs then reads registers only (a storage read at a per-lane
// address runs lane by lane on lavapipe, and every evaluation runs the
// change under a mask whether or not any lane changes).
var<private> g_slab_start: vec4<f32>;
var<private> g_slab_off: vec4<u32>;
var<private> g_slab_len: vec4<u32>;
var<private> g_slab_margin: f32;
var<private> g_slab_count: u32 = 0u;
// The view depths where the tile's primitives are (written by the pruning
// pass; the whole line outside a tile).
var<private> g_scene_depths: vec2<f32>;
// The tile's balls for a ray's own range (field_ray_range): their first
// tile word in the tile | their count << 16 | SCENE_UNION_TILE for a
// union tile (scene_tiles.wgsl); 0 for none.
var<private> g_scene_balls: u32 = 0u;
// In a union or comb tile, the pruned-tree entries this ray evaluates, in order,
// and their count (g_ray_own: a list is in use): a union tile's members
// whose balls the ray meets, a comb tile's the same with each one's
// operator after it but the first's (the chain of the members present).
// Set for all members on entering a pixel, then by field_ray_range for the
// ray, a member at a time (scene_ray_add) in the members' order.
var<private> g_ray_list: array<u32, 2 * SCENE_UNION_MAX>;
var<private> g_ray_len: u32 = 0u;
var<private> g_ray_own: bool = false;
// Appends member i's entries to the list.
fn scene_ray_add(i: u32) {
    let comb = scene_comb();
    g_ray_list[min(g_ray_len, 2u * SCENE_UNION_MAX - 1u)] = select(i, 2u * i, comb);
    g_ray_len = g_ray_len + 1u;
    if (comb && g_ray_len > 1u) {
        g_ray_list[min(g_ray_len, 2u * SCENE_UNION_MAX - 1u)] = 2u * i + 1u;
        g_ray_len = g_ray_len + 1u;
    }
}
fn scene_union() -> bool { return (g_scene_balls & SCENE_UNION_TILE) != 0u; }
fn scene_comb() -> bool { return (g_scene_balls & SCENE_COMB_TILE) != 0u; }

// Counts the changes of the evaluated pruned tree (slab or whole tree): two values
// of f taken under different pruned trees are values of different fields (each
// exact only near its slab), so the traversal's check of how fast f changes
// compares only values of one pruned tree (field_tree).
var<private> g_scene_epoch: u32 = 0u;
fn field_tree() -> u32 { return g_scene_epoch; }

// Makes slab k (0-based) of the current tile the one evaluated.
fn scene_use_slab(k: u32) {
    g_scene_epoch = g_scene_epoch + 1u;
    let lo = select(g_slab_start[min(k, 3u)], -F.inf, k == 0u);
    let hi = select(g_slab_start[min(k + 1u, 3u)], F.inf, k >= 3u);
    g_scene_core = vec2<f32>(lo, hi);
    g_scene_pad = vec2<f32>(lo - g_slab_margin, hi + g_slab_margin);
    g_scene_len = g_slab_len[min(k, 3u)];
    g_scene_vbase = g_scene_tile * SCENE_PRUNED_MAX + g_slab_off[min(k, 3u)];
}

// The slab whose core holds view depth z.
fn scene_find_slab(z: f32) {
    let s = g_slab_start;
    scene_use_slab(u32(z >= s.y) + u32(z >= s.z) + u32(z >= s.w));
}

fn field_enter_pixel(px: vec2<u32>) {
    let t = (px - F.tile_origin) / 8u;
    scene_enter_tile(t.y * ((F.tile_size.x + 7u) / 8u) + t.x);
}

// Makes tile t's slab table and its first slab's pruned tree the ones
// evaluated (the whole tree for a tile without a table).
fn scene_enter_tile(t: u32) {
    g_scene_tile = t;
    let tb = g_scene_tile * SCENE_PRUNED_MAX;
    let slabs = scene_pruned_node(tb);
    if (slabs == 0u) {
        field_leave_frustum();
        return;
    }
    g_slab_margin = bitcast<f32>(scene_pruned_node(tb + 1u));
    g_scene_depths = vec2<f32>(bitcast<f32>(scene_pruned_node(tb + 2u)), bitcast<f32>(scene_pruned_node(tb + 3u)));
    g_scene_balls = scene_pruned_node(tb + 7u);
    g_ray_own = scene_union() || scene_comb();
    if (g_ray_own) {
        g_ray_len = 0u;
        for (var i = 0u; i < ((g_scene_balls >> 16u) & 0xffu); i = i + 1u) { scene_ray_add(i); }
    }
    g_slab_count = slabs;
    g_slab_start = vec4<f32>(F.inf);
    for (var k = 0u; k < slabs; k = k + 1u) {
        let e = tb + 4u * (k + 1u);
        g_slab_off[k] = scene_pruned_node(e);
        g_slab_len[k] = scene_pruned_node(e + 1u);
        g_slab_start[k] = bitcast<f32>(scene_pruned_node(e + 2u));
    }
    scene_use_slab(0u);
}
fn field_leave_frustum() {
    g_scene_epoch = g_scene_epoch + 1u;
    g_scene_tile = SCENE_NO_TILE;
    g_scene_len = SCENE_WHOLE_TREE;
    g_scene_vbase = 0u;
    g_scene_core = vec2<f32>(-F.inf, F.inf);
    g_scene_pad = g_scene_core;
    g_scene_depths = g_scene_core;
    g_scene_balls = 0u;
    g_ray_own = false;
}

// Whether no primitive meets tile t's frustum (its pruning pass found none:
// a slab table whose depths are empty; 0 slabs is the whole tree), so that
// no ray of the tile meets the surface (field_ray_range is empty there).
fn field_tile_empty(t: u32) -> bool {
    let tb = t * SCENE_PRUNED_MAX;
    if (scene_pruned_node(tb) == 0u) { return false; }
    return bitcast<f32>(scene_pruned_node(tb + 2u)) > bitcast<f32>(scene_pruned_node(tb + 3u));
}

// The part of the ray o + d t where the current tile's primitives are (no
// surface lies elsewhere in the tile's frustum): view depth z is
// dot(o - eye, forward) + t dot(d, forward).
fn field_ray_range(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let k = dot(d, F.forward.xyz);
    let z0 = dot(o - F.eye.xyz, F.forward.xyz);
    let inside = g_scene_depths.x <= -F.inf && g_scene_depths.y >= F.inf;
    if (inside || !(k > 0.0)) { return select(vec2<f32>(-F.inf, F.inf), vec2<f32>(F.inf, -F.inf), g_scene_depths.x > g_scene_depths.y); }
    let tile = (g_scene_depths - z0) / k;
    if (g_scene_balls == 0u) { return tile; }
    return scene_balls_range(o, d, tile);
}

// The part of the ray o + d t (|d| = 1) within `range` that the tile's
// balls cover, as one interval from the first ball's entry to the last
// one's exit (empty when it meets none): the surface in the tile's frustum
// lies in their union, as the tile's depths say of the whole tile. In a
// union or comb tile the balls met within `range` are the ray's members
// (scene_ray_add).
fn scene_balls_range(o: vec3<f32>, d: vec3<f32>, range: vec2<f32>) -> vec2<f32> {
    let at = g_scene_tile * SCENE_PRUNED_MAX + (g_scene_balls & 0xffffu);
    let n = (g_scene_balls >> 16u) & 0xffu;
    var lo = F.inf;
    var hi = -F.inf;
    if (g_ray_own) { g_ray_len = 0u; }
    for (var i = 0u; i < n; i = i + 1u) {
        let w = at + 4u * i;
        let c = bitcast<vec3<f32>>(vec3<u32>(scene_pruned_node(w), scene_pruned_node(w + 1u), scene_pruned_node(w + 2u)));
        let r = bitcast<f32>(scene_pruned_node(w + 3u));
        // The distance of c from the line, from the perpendicular itself
        // (b^2 - |oc|^2 + r^2 cancels badly for a small far ball), padded
        // by f32's error in it.
        let oc = c - o;
        let b = dot(oc, d);
        let h = oc - b * d;
        let rr = r + 1e-6 * length(oc);
        let disc = rr * rr - dot(h, h);
        if (disc >= 0.0) {
            let s = sqrt(disc);
            lo = min(lo, b - s);
            hi = max(hi, b + s);
            if (g_ray_own && b + s >= range.x && b - s <= range.y) { scene_ray_add(i); }
        }
    }
    return vec2<f32>(max(range.x, lo), min(range.y, hi));
}

// The node list this invocation evaluates: the slab's pruned tree, or (length
// SCENE_WHOLE_TREE) the whole tree.
fn scene_pruned_len() -> u32 { return g_scene_len; }

// Loop iterations one evaluation costs: its nodes, and at most the runs of
// every formula leaf of the tree (scene_leaves_cost; 0 without leaves).
fn field_cost() -> u32 {
    let len = scene_pruned_len();
    return select(len, scene_node_count(), len == SCENE_WHOLE_TREE) + scene_leaves_cost();
}

// The interpreter's value stack below its top (the top is the step's
// `top`): its four upper values in a vector register (g_scene_near.x the
// one below the top), the rest in a module-scope array. lavapipe reads and
// writes a private array at a per-lane index one lane at a time, where the
// vector's shifts are a few register moves, and the generated scenes need
// two or three values; the array is reached only by deeper stacks. It is
// at module scope so that it is zero-initialised once per invocation, not
// on every call (a function-scope array is, and that cost more than the
// whole traversal of a small scene).
var<private> g_scene_near: vec4<f32>;
var<private> g_scene_stack: array<f32, SCENE_MAX_STACK>;

// Pushes v under the top, with `sp` values below the top before.
fn scene_push(v: f32, sp: u32) {
    if (sp >= 4u) { g_scene_stack[min(sp - 4u, SCENE_MAX_STACK - 1u)] = g_scene_near.w; }
    g_scene_near = vec4<f32>(v, g_scene_near.xyz);
}
// Pops the value below the top, with `sp` values below the top before.
fn scene_pop(sp: u32) -> f32 {
    let v = g_scene_near.x;
    var deep = 0.0;
    if (sp > 4u) { deep = g_scene_stack[min(sp - 5u, SCENE_MAX_STACK - 1u)]; }
    g_scene_near = vec4<f32>(g_scene_near.yzw, deep);
    return v;
}

// A sharp union, intersection or difference fused into its right operand's
// leaf (type `ty`): the top as its left operand, the leaf's value v as its
// right one.
fn scene_fused(ty: u32, top: f32, v: f32) -> f32 {
    let cls = (ty - NODE_UNION) % 3u;
    let c = select(v, -v, cls == 2u);
    return select(max(top, c), min(top, c), cls == 0u);
}

// One node of an evaluation: a leaf pushes its primitive's value, or
// combines it into the top through its fused sharp operator; an operator
// pops its left operand into the top; a unary node changes the top. The
// lanes of a SIMD group mostly take the same node (a tile's rays walk its
// pruned tree in step), so the primitive's and the operator's code sit
// behind branches that lavapipe skips when no lane takes them.
fn scene_step(e: u32, p: vec3<f32>, sp: ptr<function, u32>, top: ptr<function, f32>) {
    let o = entry_row(e);
    let leaf = (e >> 31u) != 0u;
    let ty = entry_type(e);
    if (leaf) {
        var v: f32;
        if ((SCENE_FEATURES & FEATURE_SHAPES) != 0u) {
            v = scene_primitive(scene_param(o), scene_param(o + 1u), scene_param(o + 2u), p, o);
        } else {
            // Plain spheres only: the centre row (after the frame's
            // first), then the radius.
            v = length(p - scene_param(o + 1u).xyz) - scene_param(o + 2u).w;
        }
        if (ty != 0u) {
            *top = scene_fused(ty, *top, v);
        } else {
            scene_push(*top, *sp);
            *sp = *sp + 1u;
            *top = v;
        }
        return;
    }
    let k = scene_param(o);
    if ((SCENE_FEATURES & FEATURE_UNARY) != 0u && ty >= NODE_OFFSET) {
        *top = scene_unary(ty, k, *top, p);
        return;
    }
    let below = scene_pop(*sp);
    *sp = *sp - 1u;
    *top = scene_operator(ty, k, below, *top);
}

// The field: the nodes of the pruned tree (or of the whole tree), in post-order,
// on a value stack (Zanni's Algorithm 4). An empty pruned tree has no surface
// (in its slab: the value is the distance to the slab's end).
fn field(p: vec3<f32>) -> f32 {
    let z = dot(p - F.eye.xyz, F.forward.xyz);
    if (SCENE_SYNC) {
        // The workgroup's slab is the only pruned tree at hand: beyond its padded
        // depths it says nothing, and 0 there makes an over-relaxed step
        // fall back and a plain one end the slab's march (the ray's march
        // is clamped to the slab's core, the next slab's march goes on).
        if (z < g_scene_pad.x || z >= g_scene_pad.y) { return 0.0; }
    } else if (z < g_scene_core.x || z >= g_scene_core.y) {
        scene_find_slab(z);
    }
    let len = scene_pruned_len();
    let full = len == SCENE_WHOLE_TREE;
    let n = select(len, scene_node_count(), full);
    // A union or comb tile's ray takes its own entries from its list, in
    // one loop with the others (a second loop would be a second inlined
    // copy of the interpreter): a union tile's entries are leaves with a
    // fused union.
    let own = g_ray_own;
    let fuse = select(0u, NODE_UNION << SCENE_ENTRY_ROW_BITS, scene_union());
    let steps = scene_admit(select(n, g_ray_len, own));
    var sp = 0u;
    var top = F.inf;
    var j = 0u;
    for (; j < steps; j = j + 1u) {
        let at = select(j, g_ray_list[min(j, 2u * SCENE_UNION_MAX - 1u)], own);
        // A pruned tree holds packed entries; the whole tree's nodes are packed
        // here (a branch, not a select, which would fetch both).
        var e: u32;
        if (full) { e = scene_entry(at); } else { e = scene_slab_entry(at) | fuse; }
        scene_step(e, p, &sp, &top);
    }
    g_field_work = g_field_work + j;
    // The pruned tree is exact only within the slab's padded depths: a positive
    // value is no larger than the distance to them, so no step leaves the
    // slab (a ray's depth changes no faster than t). Inside stays inside.
    return select(top, min(top, min(g_scene_pad.y - z, z - g_scene_pad.x)), top > 0.0);
}

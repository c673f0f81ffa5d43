// The scene field source: a blobtree kept as data (src/scene/linear.rs lays
// it out) and evaluated by one fixed interpreter, so editing, adding or
// removing primitives of the compiled-in types changes buffers only and
// never recompiles. The node and operator functions are the formula
// language's distance forms (src/sdf.rs) and Zanni's compact smooth
// operators G (eq. 12-18), in the same arithmetic as the reference
// (src/scene/eval.rs).
//
// Node word x: isLeaf (bit 31) | isLeft (bit 30) | type (bits 22-29) |
// parent (bits 0-21); y: the node's first vec4 in scene_params; z: its fast
// ancestor. A primitive's record: 3 rows of M = [R^T / s | -R^T t / s]
// (local point q = M (p, 1)), then its parameters, the first vec4 starting
// with the scale s. An operator's record: (beta, r_o, 0, 0).
//
// Node type codes and SCENE_MAX_STACK come from Rust (src/scene/linear.rs,
// spliced before this file).

@group(1) @binding(0) var<storage, read> scene_nodes: array<vec4<u32>>;
@group(1) @binding(1) var<storage, read> scene_params: array<vec4<f32>>;

fn node_type(w: u32) -> u32 { return (w >> 22u) & 0xffu; }
fn node_is_leaf(w: u32) -> bool { return (w >> 31u) != 0u; }

fn sd_box(q: vec3<f32>, h: vec3<f32>) -> f32 {
    let d = abs(q) - h;
    return length(max(d, vec3<f32>(0.0))) + min(max(d.x, max(d.y, d.z)), 0.0);
}

// The distance of primitive `ty` whose record starts at `o`, at p.
fn scene_primitive(ty: u32, o: u32, p: vec3<f32>) -> f32 {
    let p4 = vec4<f32>(p, 1.0);
    let q = vec3<f32>(dot(scene_params[o], p4), dot(scene_params[o + 1u], p4), dot(scene_params[o + 2u], p4));
    let a = scene_params[o + 3u];
    let s = a.x;
    var d = 0.0;
    switch (ty) {
        case NODE_SPHERE: { d = length(q) - a.y; }
        case NODE_BOX: { d = sd_box(q, a.yzw); }
        case NODE_ROUND_BOX: {
            let r = scene_params[o + 4u].x;
            d = sd_box(q, a.yzw - vec3<f32>(r)) - r;
        }
        case NODE_CAPSULE: {
            let b = scene_params[o + 4u];
            let pa = q - a.yzw;
            let ba = b.xyz - a.yzw;
            let h = clamp(dot(pa, ba) / max(dot(ba, ba), 1e-12), 0.0, 1.0);
            d = length(pa - ba * h) - b.w;
        }
        case NODE_TORUS: { d = length(vec2<f32>(length(q.xy) - a.y, q.z)) - a.z; }
        case NODE_CYLINDER: {
            let e = vec2<f32>(length(q.xy) - a.y, abs(q.z) - a.z);
            d = min(max(e.x, e.y), 0.0) + length(max(e, vec2<f32>(0.0)));
        }
        case NODE_OCTAHEDRON: { d = (abs(q.x) + abs(q.y) + abs(q.z) - a.y) * 0.57735027; }
        case NODE_PLANE: { d = dot(a.yzw, q) - scene_params[o + 4u].x; }
        default: { d = F.inf; }
    }
    return s * d;
}

// Zanni's blend d(a, b, beta) = beta/6 max(1 - |a - b|/beta, 0)^3, NaN-free.
fn scene_blend(a: f32, b: f32, beta: f32) -> f32 {
    let h = max(beta - abs(a - b), 0.0);
    return h * h * h / (6.0 * max(beta * beta, 1e-30));
}

// b_r(x, beta, r_o) = beta max(1 - 6x / (6 r_o - beta), 0) (eq. 18); the
// host guarantees 6 r_o > beta.
fn scene_blend_range(x: f32, beta: f32, r_o: f32) -> f32 {
    return beta * max(1.0 - 6.0 * x / (6.0 * r_o - beta), 0.0);
}

// Operator `ty` with record at `o` on operands a (left) and b (right).
fn scene_operator(ty: u32, o: u32, a: f32, b: f32) -> f32 {
    switch (ty) {
        case NODE_UNION: { return min(a, b); }
        case NODE_INTERSECTION: { return max(a, b); }
        case NODE_DIFFERENCE: { return max(a, -b); }
        default: {}
    }
    let k = scene_params[o];
    let beta = k.x;
    let r_o = k.y;
    // G (eq. 12, 17): the compact blend where both operands are in the
    // operator's range R_o, sharp CSG elsewhere.
    if (ty == NODE_SMOOTH_UNION) {
        if (a > r_o || b > r_o) { return min(a, b); }
        let x = min(a, b) - scene_blend(a, b, beta);
        let br = scene_blend_range(x, beta, r_o);
        return min(a, b) - scene_blend(a, b, br);
    }
    let c = select(b, -b, ty == NODE_SMOOTH_DIFFERENCE);
    if (abs(a) > r_o || abs(c) > r_o) { return max(a, c); }
    let x = abs(max(a, c) + scene_blend(a, c, beta));
    let br = scene_blend_range(x, beta, r_o);
    return max(a, c) + scene_blend(a, c, br);
}

// Per primitive: its node index and its augmented bounding ball (centre,
// radius; an infinite radius for unbounded primitives such as planes).
@group(1) @binding(2) var<storage, read> scene_prims: array<u32>;
@group(1) @binding(3) var<storage, read> scene_balls: array<vec4<f32>>;

const SCENE_NO_TILE: u32 = 0xffffffffu;
// The tile whose pruned view this invocation's field evaluates: set for a
// primary ray (its point stays in the tile's frustum), cleared for
// secondary rays, which leave it and need the whole tree.
var<private> g_scene_tile: u32 = SCENE_NO_TILE;

// Its view length, read once per pixel (SCENE_VIEW_FULL: the whole tree).
var<private> g_scene_len: u32 = SCENE_VIEW_FULL;
fn field_enter_pixel(px: vec2<u32>) {
    let t = (px - F.tile_origin) / 8u;
    g_scene_tile = t.y * ((F.tile_size.x + 7u) / 8u) + t.x;
    g_scene_len = scene_tile_len[g_scene_tile].x;
}
fn field_leave_frustum() { g_scene_tile = SCENE_NO_TILE; g_scene_len = SCENE_VIEW_FULL; }

// The node list this invocation evaluates: the tile's view, or (length
// SCENE_VIEW_FULL) the whole tree.
fn scene_view_len() -> u32 { return g_scene_len; }

// The scene bounds its own work by the traversal's guard (field_cost):
// it never gives up on an evaluation.
fn field_exhausted() -> bool { return false; }

// Loop iterations one evaluation costs.
fn field_cost() -> u32 {
    let len = scene_view_len();
    return select(len, arrayLength(&scene_nodes), len == SCENE_VIEW_FULL);
}

// The interpreter's value stack: module scope, so it is zero-initialised
// once per invocation, not on every call (a function-scope array is, and
// that cost more than the whole traversal of a small scene on lavapipe).
var<private> g_scene_stack: array<f32, SCENE_MAX_STACK>;

// The field: the nodes of the view (or of the whole tree), in post-order,
// on a value stack (Zanni's Algorithm 4). An empty view has no surface.
fn field(p: vec3<f32>) -> f32 {
    let len = scene_view_len();
    let full = len == SCENE_VIEW_FULL;
    let n = select(len, arrayLength(&scene_nodes), full);
    if (n == 0u) { return F.inf; }
    let vbase = select(g_scene_tile * SCENE_VIEW_MAX, 0u, full);
    var sp = 0u;
    for (var k = 0u; k < n; k = k + 1u) {
        var i = k;
        if (!full) { i = scene_tile_view[vbase + k]; }
        let w = scene_nodes[i];
        let ty = node_type(w.x);
        if (node_is_leaf(w.x)) {
            g_scene_stack[min(sp, SCENE_MAX_STACK - 1u)] = scene_primitive(ty, w.y, p);
            sp = sp + 1u;
        } else {
            let b = g_scene_stack[min(sp - 1u, SCENE_MAX_STACK - 1u)];
            let a = g_scene_stack[min(sp - 2u, SCENE_MAX_STACK - 1u)];
            sp = sp - 1u;
            g_scene_stack[min(sp - 1u, SCENE_MAX_STACK - 1u)] = scene_operator(ty, w.y, a, b);
        }
    }
    g_field_work = g_field_work + n;
    return g_scene_stack[0];
}

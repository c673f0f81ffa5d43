// The scene's side of the synchronised walk (traverse/sphere/
// primary_sync.wgsl, Zanni et al.'s Algorithm 3; appended to scene.wgsl in
// place of scene_sync_off.wgsl): the workgroup is one tile, it loads the
// pruned tree of the depth slab it is in into workgroup memory, and every ray of
// the tile evaluates that shared copy until the workgroup moves on.
const SCENE_SYNC: bool = true;

var<workgroup> scene_sync_pruned: array<u32, SCENE_PRUNED_MAX>;

// Entry j of the pruned tree evaluated (the copy of the current slab's).
fn scene_slab_entry(j: u32) -> u32 { return scene_sync_pruned[j]; }

// The depth slabs the tile's workgroup walks: one for a tile that
// evaluates the whole tree (no slab table).
fn field_sync_slabs() -> u32 { return select(g_slab_count, 1u, g_scene_tile == SCENE_NO_TILE); }

// Makes slab k the one evaluated and copies its pruned tree into workgroup memory,
// invocation li (of 64) taking every 64th entry. Every invocation of the
// workgroup calls it, then a barrier.
fn field_sync_load(k: u32, li: u32) {
    if (g_scene_tile == SCENE_NO_TILE) { return; }
    scene_use_slab(k);
    for (var i = li; i < g_scene_len; i = i + 64u) {
        scene_sync_pruned[i] = scene_pruned_node(g_scene_vbase + i);
    }
}

// The part of the ray o + d t whose view depths are the core of the slab
// loaded (the whole line for the whole tree).
fn field_sync_range(o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let kd = dot(d, F.forward.xyz);
    if (g_scene_tile == SCENE_NO_TILE || !(kd > 0.0)) { return vec2<f32>(-F.inf, F.inf); }
    let z0 = dot(o - F.eye.xyz, F.forward.xyz);
    return (g_scene_core - z0) / kd;
}

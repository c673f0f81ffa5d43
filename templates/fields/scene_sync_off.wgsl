// Each ray walks its tile's depth slabs on its own (scene_sync.wgsl is the
// synchronised walk): entry j of the current slab's pruned tree, from the texture.
const SCENE_SYNC: bool = false;
fn scene_slab_entry(j: u32) -> u32 { return scene_pruned_node(g_scene_vbase + j); }

// Sphere tracing's tile pass over a scene (spliced into
// traverse/sphere/kernel.wgsl at `//!splice:tiles`; tiles_off.wgsl for
// other fields): one invocation per 8x8 tile. The scene's views pass has
// found which primitives meet each tile's frustum; a tile where none does
// shows no surface, so its pixels are background, written here, and the
// tile is left out of `main`, which runs by indirect dispatch over the
// others. lavapipe runs a kernel's code for every lane under a mask, so a
// `main` invocation that only finds its ray's range empty still paid for a
// masked pass of the whole trace (most of a sparse scene's frame).

// tile_list, tile_ids (pass group): the tiles `main` runs on (`count` of them, ids in tile_ids), and its
// indirect dispatch: (x, 1, 1) with x = count (one tile a workgroup).
struct TileList { x: atomic<u32>, y: u32, z: u32, count: atomic<u32> }

fn tiles_x() -> u32 { return (F.tile_size.x + 7u) / 8u; }

// The 8x8 tile workgroup `wid` of `main` works on (x >= tiles_x(): none).
fn main_tile(wid: vec3<u32>, groups: vec3<u32>) -> vec2<u32> {
    let slot = wid.y * groups.x + wid.x;
    if (slot >= atomicLoad(&tile_list.count)) { return vec2<u32>(0xffffffffu); }
    let t = tile_ids[slot];
    return vec2<u32>(t % tiles_x(), t / tiles_x());
}

@compute @workgroup_size(8, 8)
fn tiles(@builtin(global_invocation_id) gid: vec3<u32>) {
    load_uniforms();
    let tile = gid.xy;
    if (tile.x >= tiles_x() || tile.y * 8u >= F.tile_size.y) { return; }
    let t = tile.y * tiles_x() + tile.x;
    if (!field_tile_empty(t)) {
        let slot = atomicAdd(&tile_list.count, 1u);
        tile_ids[slot] = t;
        atomicAdd(&tile_list.x, 1u);
        return;
    }
    // What `main` writes for a ray that meets nothing.
    for (var li = 0u; li < 64u; li = li + 1u) {
        let g = tile * 8u + vec2<u32>(li % 8u, li / 8u);
        if (g.x >= F.tile_size.x || g.y >= F.tile_size.y) { continue; }
        let idx = g.y * F.tile_size.x + g.x;
        let d = normalize(primary_dir(F.tile_origin + g));
        write_pixel(idx, background(d), STATUS_MISS, vec3<f32>(0.0), F.inf, pack_info(0u, 0u, 0u));
        ray_stats[idx] = 0u;
    }
}

// The per-pixel pass of sphere tracing over a scene, synchronised per tile
// (Zanni et al. 2024, Algorithm 3; spliced into traverse/sphere/kernel.wgsl
// at `//!splice:primary` in place of primary.wgsl): the workgroup is the
// 8x8 tile, and it walks the tile's depth slabs front to back together.
// For each slab it copies the slab's pruned view (built once per tile and
// slab by the scene's views pass) into workgroup memory, then every ray of
// the tile that is still marching sphere-traces the part of its range that
// lies in the slab, evaluating that shared view; a ray that hits stops, the
// others go on to the next slab, and the walk ends when no ray is left
// (a workgroup counter read uniformly, where the paper uses subgroupAnd).
// The field side is the scene's field_sync_* functions (scene_sync.wgsl).

// Rays of the tile still marching, and that count and the slab count as
// uniform values (barriers need uniform control flow).
var<workgroup> sync_live: atomic<u32>;
var<workgroup> sync_alive: u32;
var<workgroup> sync_slabs: u32;

// Whether any ray of the workgroup still marches (`marching`: this one's).
fn sync_any(li: u32, marching: bool) -> bool {
    if (li == 0u) { atomicStore(&sync_live, 0u); }
    workgroupBarrier();
    if (marching) { atomicAdd(&sync_live, 1u); }
    workgroupBarrier();
    if (li == 0u) { sync_alive = atomicLoad(&sync_live); }
    return workgroupUniformLoad(&sync_alive) != 0u;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(local_invocation_id) lid: vec3<u32>,
        @builtin(local_invocation_index) li: u32,
        @builtin(workgroup_id) wid: vec3<u32>,
        @builtin(num_workgroups) groups: vec3<u32>) {
    load_uniforms();
    // No early return: every invocation reaches the barriers.
    let tile = main_tile(wid, groups);
    let gid = tile * 8u + lid.xy;
    let here = tile.x != 0xffffffffu && gid.x < F.tile_size.x && gid.y < F.tile_size.y;
    let px = F.tile_origin + gid.xy;
    let d = normalize(primary_dir(px));
    // Pixels past the frame's edge enter too: they share the copying.
    if (tile.x != 0xffffffffu) { field_enter_pixel(px); }
    let o = F.eye.xyz;
    let c = primary_crit();
    let seg = primary_segment(o, d);
    var h = missed_ray(seg.x);
    var g = vec3<f32>(0.0);
    var marching = here && seg.x < seg.y;
    // The tile's first pixel is in the frame whenever the tile is.
    if (li == 0u) { sync_slabs = select(0u, field_sync_slabs(), here); }
    let slabs = workgroupUniformLoad(&sync_slabs);
    for (var k = 0u; k < slabs; k = k + 1u) {
        if (!sync_any(li, marching)) { break; }
        field_sync_load(k, li);
        workgroupBarrier();
        if (marching) {
            let r = field_sync_range(o, d);
            let a = max(max(seg.x, r.x), h.t);
            let b = min(seg.y, r.y);
            if (a < b) {
                let m = trace(o, d, a, b, U.max_steps - min(h.steps, U.max_steps), c);
                let ratio = max(h.ratio, m.ratio);
                let steps = h.steps + m.steps;
                let fallbacks = h.fallbacks + m.fallbacks;
                h = m;
                h.steps = steps;
                h.fallbacks = fallbacks;
                h.ratio = ratio;
                if (m.status == STATUS_MISS) {
                    h.t = b;
                } else {
                    g = gradient_at(o + d * m.t, 0.5 * F.eps, m.raw);
                    marching = false;
                }
            }
            if (b >= seg.y) { marching = false; }
        }
        // The next slab's copy overwrites this one's view.
        workgroupBarrier();
    }
    if (here) { finish_pixel(px, gid.y * F.tile_size.x + gid.x, d, h, g, c); }
}

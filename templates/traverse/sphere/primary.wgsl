// The per-pixel pass of sphere tracing (spliced into
// traverse/sphere/kernel.wgsl at `//!splice:primary`): each primary ray is
// traced on its own; a scene's ray changes depth slabs (and views) as it
// goes (primary_sync.wgsl: the rays of a tile walk them together).

@compute @workgroup_size(8, 8)
fn main(@builtin(local_invocation_id) lid: vec3<u32>,
        @builtin(workgroup_id) wid: vec3<u32>,
        @builtin(num_workgroups) groups: vec3<u32>) {
    load_uniforms();
    // This workgroup's 8x8 tile: the dispatch's tiles in order, or after a
    // tile pass (tiles.wgsl) the tiles it queued.
    let tile = main_tile(wid, groups);
    let gid = tile * 8u + tile_pixel(lid.xy);
    if (tile.x == 0xffffffffu || gid.x >= F.tile_size.x || gid.y >= F.tile_size.y) { return; }
    let px = F.tile_origin + gid.xy;
    let d = normalize(primary_dir(px));
    // The primary ray stays in this pixel's tile frustum: a field may
    // evaluate only what matters there (the scene's pruned view).
    field_enter_pixel(px);
    let o = F.eye.xyz;
    let c = primary_crit();
    let seg = primary_segment(o, d);
    var h = missed_ray(seg.x);
    var g = vec3<f32>(0.0);
    if (seg.x < seg.y) {
        h = trace(o, d, seg.x, seg.y, U.max_steps, c);
        if (h.status != STATUS_MISS) { g = gradient_at(o + d * h.t, 0.5 * F.eps, h.raw); }
    }
    finish_pixel(px, gid.y * F.tile_size.x + gid.x, d, h, g, c);
}

// Bisection's tile pass, spliced into traverse/bisect/kernel.wgsl (at
// `//!splice:tiles`) and sharing its bindings, uniforms and helpers.

// ---- Tile pass (its own dispatch, before `main`): which depth slabs of
// each 8x8 tile's view frustum may hold the surface. One invocation per
// tile encloses f over the frustum through the tile's pixel centres, cut
// into SLABS depth slabs, coarse to fine: 8 slabs of 8 first, and the 8 fine
// slabs only inside a coarse slab that may hold the surface (an empty tile
// costs 8 enclosures, not 64). Slabs proven root-free are skipped by every
// ray of the tile. Tiles with a candidate slab are queued for `main`, the
// others get their background here. The field sees the slabs go by
// (field_slab_begin, field_slab_end): a tape notes its min/max choices over
// each fine slab that may hold the surface and shortens itself for the tile
// (fields/tape_tiles.wgsl). A tape also runs a block
// pass first, through this entry point: the same loop over 16 x 16-pixel
// blocks and the 8 coarse slabs only, which shortens the tape per block and
// leaves each tile the slabs its block may hold; the tile pass then runs
// the block's shorter tape.
//
// One invocation per tile, not per slab: the per-slab form (a workgroup per
// tile sharing its mask through workgroup memory and barriers) cost a large
// fixed price a frame on lavapipe before doing any work, for its thousands
// of workgroups with barriers; this form has neither.
const COARSE: u32 = 8u;
// Tiles per workgroup of `main` (its workgroup is 8x8xTILES_PER_GROUP).
const TILES_PER_GROUP: u32 = 4u;
// A field's block pass takes blocks of FIELD_BLOCK x FIELD_BLOCK tiles (16 x
// 16 pixels; src/gpu/renderer.rs dispatches 8 x 8 blocks a workgroup).
const FIELD_BLOCK: u32 = 2u;

fn tiles_x() -> u32 { return (F.tile_size.x + 7u) / 8u; }
fn tiles_y() -> u32 { return (F.tile_size.y + 7u) / 8u; }

// Can the surface be in the part [s.x, s.y] of the frustum through pixel
// directions su × sv? Only inside the domain: rays are clipped to it, and a
// surface that goes on past it (a height field's sheet past the box, the
// Barth surfaces' cones past their clip ball) would otherwise keep every
// tile whose frustum meets the surface outside.
fn slab_may_hold(s: vec2<f32>, su: vec2<f32>, sv: vec2<f32>) -> bool {
    return slab_meets_domain(s, su, sv) && keep_cell(slab_range(F.eye.xyz, F.forward.xyz, F.right.xyz, F.up.xyz, s, su, sv));
}

// Whether the axis-aligned box around the frustum part (eye + S (forward +
// U right + V up), S in s, U in su, V in sv; s.x > 0) meets the domain's box
// and its clip ball if any, both widened by a millionth of the box's size
// against rounding.
fn slab_meets_domain(s: vec2<f32>, su: vec2<f32>, sv: vec2<f32>) -> bool {
    let d_lo = F.forward.xyz + min(su.x * F.right.xyz, su.y * F.right.xyz) + min(sv.x * F.up.xyz, sv.y * F.up.xyz);
    let d_hi = F.forward.xyz + max(su.x * F.right.xyz, su.y * F.right.xyz) + max(sv.x * F.up.xyz, sv.y * F.up.xyz);
    let lo = F.eye.xyz + min(s.x * d_lo, s.y * d_lo);
    let hi = F.eye.xyz + max(s.x * d_hi, s.y * d_hi);
    let size = F.box_max.xyz - F.box_min.xyz;
    let pad = 1e-6 * size + vec3<f32>(1e-30);
    let radius = F.box_max.w;
    // The box's nearest point to the ball's centre.
    let c = 0.5 * (F.box_min.xyz + F.box_max.xyz);
    let gap = max(max(lo - c, c - hi), vec3<f32>(0.0));
    let in_ball = radius <= 0.0 || length(gap) <= radius * (1.0 + 1e-6) + 1e-6 * length(size);
    return all(lo <= F.box_max.xyz + pad) && all(hi >= F.box_min.xyz - pad) && in_ball;
}

// Whether point q lies inside the tile's frustum `frustum` (tile_frustum)
// between depths s.x and s.y, with a margin against rounding: there the
// tile's candidate slabs hold it, if those depths bound a run of them.
fn in_frustum(q: vec3<f32>, frustum: vec4<f32>, s: vec2<f32>) -> bool {
    let d = q - F.eye.xyz;
    let depth = dot(d, F.forward.xyz);
    let uv = vec2<f32>(dot(d, F.right.xyz), dot(d, F.up.xyz)) / depth;
    let m = 1e-5 * vec2<f32>(frustum.y - frustum.x, frustum.w - frustum.z);
    return depth >= s.x * (1.0 + 1e-5) && depth <= s.y * (1.0 - 1e-5)
        && all(uv >= frustum.xz + m) && all(uv <= frustum.yw - m);
}

// Pixel `li` (0..63) of a tile's share of the tile pass's `n` enclosures.
fn tile_share(n: u32, li: u32) -> u32 { return n / 64u + select(0u, 1u, li < n % 64u); }

@compute @workgroup_size(8, 8)
fn tiles(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) li: u32, @builtin(num_workgroups) groups: vec3<u32>) {
    field_entry(li); // before any lane returns
    load_uniforms();
    // A dispatch two layers deep is the field's block pass (a tape's: one
    // invocation per FIELD_BLOCK x FIELD_BLOCK tiles, before the tile pass,
    // see fields/tape_tiles.wgsl); its first layer does nothing. The block
    // pass shares this entry point and its one enclosure call site: a second
    // entry point would compile the field once more.
    let block = groups.z == 2u;
    if (block && gid.z == 0u) { return; }
    let side = select(1u, FIELD_BLOCK, block);
    let tile = gid.xy * side;
    if (tile.x >= tiles_x() || tile.y >= tiles_y()) { return; }
    let t = tile.y * tiles_x() + tile.x;
    let dr = depth_range();
    let frustum = tile_frustum(tile, side);
    let su = frustum.xy;
    let sv = frustum.zw;
    let fine = SLABS / COARSE;
    var mask = vec2<u32>(0u);
    // The slabs the field's block pass left to this tile (all of them
    // without one), and the share of the block pass's enclosures it counts.
    let given = field_tile_begin(t, tile, block);
    var n = given.z;
    // One loop and one enclosure call site for both levels: the coarse slab
    // c (j == fine), then its fine slabs j = 0..fine-1 if it may hold the
    // surface. A second call site would double this pass's compile time
    // (the field is inlined at each one) for the same work. The block pass
    // stays at the coarse slabs.
    var c = 0u;
    var j = fine;
    if (dr.x >= dr.y) { c = COARSE; }
    while (c < COARSE) {
        let coarse = j == fine;
        let k = c * fine + select(j, 0u, coarse);
        // The slab's bits in the 64-bit mask: the fine slab's, or the
        // coarse slab's eight.
        let bits = select(vec2<u32>(1u << (k & 31u), 0u), vec2<u32>(0u, 1u << (k & 31u)), k >= 32u);
        let span = select(bits, select(vec2<u32>(0xffu << (k & 31u), 0u), vec2<u32>(0u, 0xffu << (k & 31u)), k >= 32u), coarse);
        let allowed = any((given.xy & span) != vec2<u32>(0u));
        n = n + select(0u, 1u, allowed);
        // A field that records what it saw (a tape's choices) does so over
        // the slabs of the mask: the fine ones, or a block's coarse ones.
        let leaf = !coarse || block;
        field_slab_begin(leaf && allowed);
        let hold = allowed && slab_may_hold(slab_span(dr, k, select(k, k + fine - 1u, coarse)), su, sv);
        field_slab_end(hold);
        if (!leaf) {
            if (hold) { j = 0u; } else { c = c + 1u; }
            continue;
        }
        if (hold) { mask = mask | span; }
        if (coarse) {
            c = c + 1u;
        } else {
            j = j + 1u;
            if (j == fine) { c = c + 1u; }
        }
    }
    // The field's shortened program for the tile (a tape's list), or the
    // block's entry: one call site for both (the field inlines its
    // shortening there).
    let queued = mask.x != 0u || mask.y != 0u;
    var list = 0u;
    if (queued || block) { list = field_tile_done(mask, n, block); }
    if (block) { return; }
    if (queued) {
        // Rays of this tile may meet the surface: queue it for `main`, and
        // count a workgroup of `main` for every TILES_PER_GROUP tiles.
        tile_masks[t] = vec4<u32>(mask, n, list);
        let slot = atomicAdd(&tile_list.count, 1u);
        tile_ids[slot] = t;
        if (slot % TILES_PER_GROUP == 0u) { atomicAdd(&tile_list.x, 1u); }
        return;
    }
    // No slab of this tile holds the surface: its pixels are background,
    // written here, and the large per-pixel kernel never runs for them.
    // This loop is most of the pass on a mostly empty frame (the sphere at
    // 1024²: 900k records), so it does little per pixel: the direction
    // steps by a pixel (it is affine in the pixel), and a miss's level is
    // only whether the ray crosses the domain (all the statistics read of it).
    let d0 = primary_dir(F.tile_origin + tile * 8u);
    let step_x = primary_dir(F.tile_origin + tile * 8u + vec2<u32>(1u, 0u)) - d0;
    let step_y = primary_dir(F.tile_origin + tile * 8u + vec2<u32>(0u, 1u)) - d0;
    let bg = background_tile(d0, step_x, step_y);
    // The rays that cross a convex domain (box, ball, or both) from the eye
    // form a convex cone: when the tile's four corner rays cross it, every
    // ray of the tile does.
    var corners = 0u;
    for (var c = 0u; c < 4u; c = c + 1u) {
        let seg = clip_domain(F.eye.xyz, d0 + f32(7u * (c & 1u)) * step_x + f32(7u * (c >> 1u)) * step_y);
        corners = corners + select(0u, 1u, seg.x < seg.y);
    }
    for (var li = 0u; li < 64u; li = li + 1u) {
        let g = tile * 8u + vec2<u32>(li % 8u, li / 8u);
        if (g.x >= F.tile_size.x || g.y >= F.tile_size.y) { continue; }
        let u = f32(li % 8u);
        let v = f32(li / 8u);
        var crosses = 1u;
        if (corners < 4u) {
            let seg = clip_domain(F.eye.xyz, d0 + u * step_x + v * step_y);
            crosses = select(0u, 1u, seg.x < seg.y);
        }
        var color = 0u;
        if (ENV_MODE == 0u) {
            color = pack_levels(bg.c00 + u * bg.cu + v * (bg.cv + u * bg.cuv), STATUS_MISS);
        } else {
            color = pack_color(background(normalize(d0 + u * step_x + v * step_y)), STATUS_MISS);
        }
        pixels[g.y * F.tile_size.x + g.x] = vec2<u32>(color, pack_info(tile_share(n, li), crosses, 0u));
    }
}

// The sky's colour code (pack_color's 10-bit sqrt levels, unrounded) over
// a tile, bilinear in the pixel from its corners: c00 + u cu + v (cv + u
// cuv) at pixel (u, v) of the tile. The sky is a linear ramp in the unit
// direction's height, smooth over a tile's few milliradians, so the
// bilinear form stays close to the exact code (f64, against its second
// derivatives over 7 pixels): within 0.002 of a level at a 40° field of
// view from 512² up, 0.04 at 120°; rounded, 0.04 % of the sphere's pixels
// at 512² and 40° move by one 8-bit step, 0.5 % at 120°. Per pixel it
// costs four multiply-adds, where normalize, the ramp and three square
// roots took a noticeable part of a fast frame (the 4-bretzel's). (Only
// ENV_MODE 0: the checker and an image have edges.)
struct TileSky { c00: vec3<f32>, cu: vec3<f32>, cv: vec3<f32>, cuv: vec3<f32> }
fn background_tile(d0: vec3<f32>, step_x: vec3<f32>, step_y: vec3<f32>) -> TileSky {
    let c00 = sky_code(d0);
    let cu = (sky_code(d0 + 7.0 * step_x) - c00) * (1.0 / 7.0);
    let cv = (sky_code(d0 + 7.0 * step_y) - c00) * (1.0 / 7.0);
    let cuv = (sky_code(d0 + 7.0 * (step_x + step_y)) - c00 - 7.0 * (cu + cv)) * (1.0 / 49.0);
    return TileSky(c00, cu, cv, cuv);
}
fn sky_code(d: vec3<f32>) -> vec3<f32> {
    return sqrt(clamp(background(normalize(d)), vec3<f32>(0.0), vec3<f32>(1.0))) * 1023.0;
}

// Distance functions of the scene's primitive forms that need more than a
// line (boxes, polygon profiles, voxel grids), appended to scene.wgsl by
// field::scene::scene_interpreter: the interpreter there picks among
// them per node.

fn sd_box(q: vec3<f32>, h: vec3<f32>) -> f32 {
    let d = abs(q) - h;
    return length(max(d, vec3<f32>(0.0))) + min(max(d.x, max(d.y, d.z)), 0.0);
}

fn sd_box2(u: vec2<f32>, h: vec2<f32>) -> f32 {
    let d = abs(u) - h;
    return length(max(d, vec2<f32>(0.0))) + min(max(d.x, d.y), 0.0);
}

// Vertex k of the polygon whose vertices start at row `row`, two a row.
fn scene_vertex(row: u32, k: u32) -> vec2<f32> {
    let t = scene_param(row + k / 2u);
    return select(t.xy, t.zw, (k & 1u) == 1u);
}

// The signed distance to a closed polygon of n vertices, even-odd sign
// (src/scene/profile.rs, after Quilez's sdPolygon).
fn scene_polygon(u: vec2<f32>, row: u32, n: u32) -> f32 {
    let v0 = scene_vertex(row, 0u);
    var d = dot(u - v0, u - v0);
    var s = 1.0;
    var vj = scene_vertex(row, n - 1u);
    for (var i = 0u; i < n; i = i + 1u) {
        let vi = scene_vertex(row, i);
        let e = vj - vi;
        let w = u - vi;
        let b = w - e * clamp(dot(w, e) / dot(e, e), 0.0, 1.0);
        d = min(d, dot(b, b));
        let c = vec3<bool>((u.y >= vi.y), (u.y < vj.y), (e.x * w.y > e.y * w.x));
        if (all(c) || !any(c)) { s = -s; }
        vj = vi;
    }
    return s * sqrt(d);
}

// An extruded or revolved profile of form `form` at local point q (rows:
// r2 = (e, half height, r), row o + 3 (R, polygon vertices), row o + 4 the
// segment (a, b), vertices from row o + PROFILE_ROWS): box2(u - a - (b - a)
// h, e) - r for every profile but the polygon (each profile's row:
// src/sdf/profile; src/scene/rows.rs, profile_rows).
fn scene_profiled(q: vec3<f32>, r2: vec4<f32>, form: u32, o: u32) -> f32 {
    let revolve = form == FORM_REVOLVE;
    let rn = scene_param(o + 3u);
    let u = select(q.xy, vec2<f32>(length(q.xy) - rn.x, q.z), revolve);
    let seg = scene_param(o + 4u);
    let ba = seg.zw - seg.xy;
    let h = clamp(dot(u - seg.xy, ba) / max(dot(ba, ba), 1e-30), 0.0, 1.0);
    var d2 = sd_box2(u - seg.xy - ba * h, r2.xy) - r2.w;
    if ((SCENE_FEATURES & FEATURE_POLYGON) != 0u) {
        // Only a polygon's lanes loop.
        let n = min(u32(rn.y), MAX_POLYGON);
        if (n >= 3u) { d2 = scene_polygon(u, o + PROFILE_ROWS, n); }
    }
    let w = vec2<f32>(d2, abs(q.z) - r2.z);
    let extruded = min(max(w.x, w.y), 0.0) + length(max(w, vec2<f32>(0.0)));
    return select(extruded, d2, revolve);
}

// Sample k of the grid whose samples start at row `row`, four a row.
fn scene_sample(row: u32, k: u32) -> f32 {
    return scene_param(row + k / 4u)[k & 3u];
}

// A voxel grid at local point q (rows: r2 = (nx, ny, nz, 1/spacing), row
// o + 3 (origin, spacing), samples from row o + GRID_ROWS, x fastest): the trilinear interpolation of the cell
// holding the point nearest q in the grid's box, extended outside the box
// by sqrt(g^2 + h^2) (g >= 0) or g + h (g < 0), h the distance to the box
// (src/scene/grid.rs, Grid::eval).
fn scene_grid(q: vec3<f32>, r2: vec4<f32>, o: u32) -> f32 {
    let n = r2.xyz;
    let origin = scene_param(o + 3u);
    let lo = origin.xyz;
    let c = clamp(q, lo, lo + (n - 1.0) * origin.w);
    let u = (c - lo) * r2.w;
    let i = clamp(floor(u), vec3<f32>(0.0), n - 2.0);
    let t = clamp(u - i, vec3<f32>(0.0), vec3<f32>(1.0));
    let nx = u32(n.x);
    let sz = nx * u32(n.y);
    let k = u32(i.x) + nx * u32(i.y) + sz * u32(i.z);
    let row = o + GRID_ROWS;
    let x00 = mix(scene_sample(row, k), scene_sample(row, k + 1u), t.x);
    let x10 = mix(scene_sample(row, k + nx), scene_sample(row, k + nx + 1u), t.x);
    let x01 = mix(scene_sample(row, k + sz), scene_sample(row, k + sz + 1u), t.x);
    let x11 = mix(scene_sample(row, k + sz + nx), scene_sample(row, k + sz + nx + 1u), t.x);
    let g = mix(mix(x00, x10, t.y), mix(x01, x11, t.y), t.z);
    let h = length(q - c);
    return select(g + h, sqrt(g * g + h * h), g >= 0.0);
}

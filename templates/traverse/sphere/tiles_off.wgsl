// Without a tile pass (a field that knows nothing per tile): `main` runs
// one workgroup per 8x8 tile of the dispatch.
fn main_tile(wid: vec3<u32>, groups: vec3<u32>) -> vec2<u32> { return wid.xy; }

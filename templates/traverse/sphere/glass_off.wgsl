// No glass (stands in for glass.wgsl).
fn surface(p: vec3<f32>, dir: vec3<f32>, g: vec3<f32>, fp: f32) -> Shade { return shade(p, dir, g, fp); }

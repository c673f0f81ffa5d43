// No reflections (stands in for reflections.wgsl).
fn reflection(p0: vec3<f32>, n0: vec3<f32>, unit0: vec3<f32>) -> vec4<f32> { return vec4<f32>(0.0); }

// The interval an affine form stands for, without affine_range.wgsl's NaN
// test: only in a compiled formula's kernel whose forms cannot overflow for
// the inputs it admits (src/codegen/magnitude.rs; `ra_safe` makes any other
// input's enclosure the whole line). The test was a quarter of the CPU time
// of @city's cold first frame in RAA.
fn ra_range(a: vec3<f32>) -> vec2<f32> {
    let r = abs(a.y) + a.z;
    return vec2<f32>(a.x - r, a.x + r);
}

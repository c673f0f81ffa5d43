// The interval an affine form stands for, without affine_range.wgsl's NaN
// test: only in a compiled formula's kernel whose forms cannot overflow for
// the inputs it admits (src/analysis/magnitude.rs; `ra_safe` makes any other
// input's enclosure the whole line). The test is a large part of what
// lavapipe compiles and runs for a big RAA formula.
fn ra_range(a: vec3<f32>) -> vec2<f32> {
    let r = abs(a.y) + a.z;
    return vec2<f32>(a.x - r, a.x + r);
}

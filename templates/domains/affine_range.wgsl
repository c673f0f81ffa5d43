// The interval an affine form stands for, x0 +- (|x1| + x2), with the NaN
// test: the affine library's (affine.wgsl) reading of every range.
// A NaN end (0 * inf or inf - inf in a form that overflowed or is
// unbounded) means unbounded: lavapipe's min/max would silently drop it.
// (ra_radius and iso_is_nan written out: this runs hundreds of times in a
// big formula, and lavapipe clones every helper call before it simplifies.)
// affine_range_bounded.wgsl is the same without the test.
fn ra_range(a: vec3<f32>) -> vec2<f32> {
    let r = abs(a.y) + a.z;
    let i = vec2<f32>(a.x - r, a.x + r);
    let b = bitcast<vec2<u32>>(i) & vec2<u32>(0x7fffffffu);
    return select(i, vec2<f32>(-iso_inf(), iso_inf()), max(b.x, b.y) > 0x7f800000u);
}

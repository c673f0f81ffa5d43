// Derivative helpers of the affine domain (after derivative.wgsl).
fn ra_dmin(a: vec3<f32>, b: vec3<f32>, da: vec3<f32>, db: vec3<f32>) -> vec3<f32> {
    return ra_from_ia(ia_dmin(ra_range(a), ra_range(b), ra_range(da), ra_range(db)));
}
fn ra_dmax(a: vec3<f32>, b: vec3<f32>, da: vec3<f32>, db: vec3<f32>) -> vec3<f32> {
    return ra_from_ia(ia_dmax(ra_range(a), ra_range(b), ra_range(da), ra_range(db)));
}
fn ra_dpown(a: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return ra_scale(ra_pown(a, ra_const(max(n.x - 1.0, 0.0))), n.x);
}
fn ra_dsign(a: vec3<f32>, da: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_dsign(ra_range(a), ra_range(da))); }
fn ra_dfloor(a: vec3<f32>, da: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_dfloor(ra_range(a), ra_range(da))); }

// f = (mix(atan2(y, x), clamp(z, (-1), 1), 0.25) - clamp(x^2, 0, sqrt((1 + y^2))))
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = y;
    let v1 = x;
    let v2 = ra_atan2(v0, v1);
    let v3 = z;
    let v4 = ra_const(1.0);
    let v5 = ra_const(-1.0);
    let v6 = ra_clamp(v3, v5, v4);
    let v7 = ra_const(0.25);
    let v8 = ra_mix(v2, v6, v7);
    let v9 = ra_sqr(v1);
    let v10 = ra_const(0.0);
    let v11 = ra_sqr(v0);
    let v12 = ra_add(v4, v11);
    let v13 = ra_sqrt(v12);
    let v14 = ra_clamp(v9, v10, v13);
    let v15 = ra_sub(v8, v14);
    return select(v15, ra_empty(), ra_is_empty(v13));
}

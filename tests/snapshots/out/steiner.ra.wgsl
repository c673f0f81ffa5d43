// f = ((((x^2 * y^2) + (y^2 * z^2)) + (x^2 * z^2)) - (z * (x * y)))
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = x;
    let v1 = ra_sqr(v0);
    let v2 = y;
    let v3 = ra_sqr(v2);
    let v4 = ra_mul(v1, v3);
    let v5 = z;
    let v6 = ra_sqr(v5);
    let v7 = ra_mul(v3, v6);
    let v8 = ra_add(v4, v7);
    let v9 = ra_mul(v1, v6);
    let v10 = ra_add(v8, v9);
    let v11 = ra_mul(v0, v2);
    let v12 = ra_mul(v5, v11);
    let v13 = ra_sub(v10, v12);
    return v13;
}

// f = (((x^2 + y^2) + z^2) - 1)
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = ra_const(1.0);
    let v1 = x;
    let v2 = ra_sqr(v1);
    let v3 = y;
    let v4 = ra_sqr(v3);
    let v5 = ra_add(v2, v4);
    let v6 = z;
    let v7 = ra_sqr(v6);
    let v8 = ra_add(v5, v7);
    let v9 = ra_sub(v8, v0);
    return v9;
}

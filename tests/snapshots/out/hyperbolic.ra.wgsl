// f = ((sinh(x) + (cosh(y) * tanh(z))) - 2)
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = x;
    let v1 = ra_sinh(v0);
    let v2 = y;
    let v3 = ra_cosh(v2);
    let v4 = z;
    let v5 = ra_tanh(v4);
    let v6 = ra_mul(v3, v5);
    let v7 = ra_add(v1, v6);
    let v8 = ra_const(2.0);
    let v9 = ra_sub(v7, v8);
    return v9;
}

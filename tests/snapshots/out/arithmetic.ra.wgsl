// f = ((((((x + y) * (z - 1)) / (2 + x^2)) - (-y)) + (z / 3.141592653589793)) - (x * 2.718281828459045))
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = x;
    let v1 = y;
    let v2 = ra_add(v0, v1);
    let v3 = z;
    let v4 = ra_const(1.0);
    let v5 = ra_sub(v3, v4);
    let v6 = ra_mul(v2, v5);
    let v7 = ra_const(2.0);
    let v8 = ra_sqr(v0);
    let v9 = ra_add(v7, v8);
    let v10 = ra_div(v6, v9);
    let v11 = ra_neg(v1);
    let v12 = ra_sub(v10, v11);
    let v13 = vec3<f32>(3.1415925, 0.0, 1.1920929e-7);
    let v14 = ra_mul(v3, vec3<f32>(0.3183099, 0.0, 0.0));
    let v15 = ra_add(v12, v14);
    let v16 = vec3<f32>(2.7182817, 0.0, 1.1920929e-7);
    let v17 = ra_mul(v0, v16);
    let v18 = ra_sub(v15, v17);
    return v18;
}

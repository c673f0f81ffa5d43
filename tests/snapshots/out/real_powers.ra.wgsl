// f = (((pow((x^2 + 1), 0.25) + pow(abs(y), 1.5)) + pow(z^2, x)) - 0.5)
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = x;
    let v1 = ra_sqr(v0);
    let v2 = ra_const(1.0);
    let v3 = ra_add(v1, v2);
    let v4 = ra_const(0.25);
    let v5 = ra_pow(v3, v4);
    let v6 = y;
    let v7 = ra_abs(v6);
    let v8 = ra_const(1.5);
    let v9 = ra_pow(v7, v8);
    let v10 = ra_add(v5, v9);
    let v11 = z;
    let v12 = ra_sqr(v11);
    let v13 = ra_pow(v12, v0);
    let v14 = ra_add(v10, v13);
    let v15 = ra_const(0.5);
    let v16 = ra_sub(v14, v15);
    return select(v16, ra_empty(), ra_is_empty(v5) || ra_is_empty(v9) || ra_is_empty(v13));
}

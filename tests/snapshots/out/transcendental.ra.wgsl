// f = (((((sqrt((x^2 + y^2)) + exp((-z))) + log((x^2 + 1))) + (sin(x) * cos(y))) - tan((z / 4))) + atan((x * y)))
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = x;
    let v1 = ra_sqr(v0);
    let v2 = y;
    let v3 = ra_sqr(v2);
    let v4 = ra_add(v1, v3);
    let v5 = ra_sqrt(v4);
    let v6 = z;
    let v7 = ra_neg(v6);
    let v8 = ra_exp(v7);
    let v9 = ra_add(v5, v8);
    let v10 = ra_const(1.0);
    let v11 = ra_add(v1, v10);
    let v12 = ra_log(v11);
    let v13 = ra_add(v9, v12);
    let v14 = ra_sin(v0);
    let v15 = ra_cos(v2);
    let v16 = ra_mul(v14, v15);
    let v17 = ra_add(v13, v16);
    let v18 = ra_const(4.0);
    let v19 = ra_mul(v6, vec3<f32>(0.25, 0.0, 0.0));
    let v20 = ra_tan(v19);
    let v21 = ra_sub(v17, v20);
    let v22 = ra_mul(v0, v2);
    let v23 = ra_atan(v22);
    let v24 = ra_add(v21, v23);
    return select(v24, ra_empty(), ra_is_empty(v5) || ra_is_empty(v12));
}

// f = max((((((x^2)^2)^2 + ((y^2)^2)^2) + ((z^2)^2)^2) - 1), (-min(min(((y^2 + z^2) - 0.25), ((x^2 + z^2) - 0.25)), ((x^2 + y^2) - 0.25))))
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = ra_const(0.25);
    let v1 = x;
    let v2 = ra_sqr(v1);
    let v3 = ra_sqr(v2);
    let v4 = ra_sqr(v3);
    let v5 = y;
    let v6 = ra_sqr(v5);
    let v7 = ra_sqr(v6);
    let v8 = ra_sqr(v7);
    let v9 = ra_add(v4, v8);
    let v10 = z;
    let v11 = ra_sqr(v10);
    let v12 = ra_sqr(v11);
    let v13 = ra_sqr(v12);
    let v14 = ra_add(v9, v13);
    let v15 = ra_const(1.0);
    let v16 = ra_sub(v14, v15);
    let v17 = ra_add(v6, v11);
    let v18 = ra_sub(v17, v0);
    let v19 = ra_add(v2, v11);
    let v20 = ra_sub(v19, v0);
    let v21 = ra_min(v18, v20);
    let v22 = ra_add(v2, v6);
    let v23 = ra_sub(v22, v0);
    let v24 = ra_min(v21, v23);
    let v25 = ra_neg(v24);
    let v26 = ra_max(v16, v25);
    return v26;
}

// f = max((((((x^2)^2)^2 + ((y^2)^2)^2) + ((z^2)^2)^2) - 1), (-min(min(((y^2 + z^2) - 0.25), ((x^2 + z^2) - 0.25)), ((x^2 + y^2) - 0.25))))
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = s_const(0.25);
    let v1 = x;
    let v2 = s_sqr(v1);
    let v3 = s_sqr(v2);
    let v4 = s_sqr(v3);
    let v5 = y;
    let v6 = s_sqr(v5);
    let v7 = s_sqr(v6);
    let v8 = s_sqr(v7);
    let v9 = s_add(v4, v8);
    let v10 = z;
    let v11 = s_sqr(v10);
    let v12 = s_sqr(v11);
    let v13 = s_sqr(v12);
    let v14 = s_add(v9, v13);
    let v15 = s_const(1.0);
    let v16 = s_sub(v14, v15);
    let v17 = s_add(v6, v11);
    let v18 = s_sub(v17, v0);
    let v19 = s_add(v2, v11);
    let v20 = s_sub(v19, v0);
    let v21 = s_min(v18, v20);
    let v22 = s_add(v2, v6);
    let v23 = s_sub(v22, v0);
    let v24 = s_min(v21, v23);
    let v25 = s_neg(v24);
    let v26 = s_max(v16, v25);
    return v26;
}

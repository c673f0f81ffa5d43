// f = (((((sqrt((x^2 + y^2)) + exp((-z))) + log((x^2 + 1))) + (sin(x) * cos(y))) - tan((z / 4))) + atan((x * y)))
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = x;
    let v1 = s_sqr(v0);
    let v2 = y;
    let v3 = s_sqr(v2);
    let v4 = s_add(v1, v3);
    let v5 = s_sqrt(v4);
    let v6 = z;
    let v7 = s_neg(v6);
    let v8 = s_exp(v7);
    let v9 = s_add(v5, v8);
    let v10 = s_const(1.0);
    let v11 = s_add(v1, v10);
    let v12 = s_log(v11);
    let v13 = s_add(v9, v12);
    let v14 = s_sin(v0);
    let v15 = s_cos(v2);
    let v16 = s_mul(v14, v15);
    let v17 = s_add(v13, v16);
    let v18 = s_const(4.0);
    let v19 = s_div(v6, v18);
    let v20 = s_tan(v19);
    let v21 = s_sub(v17, v20);
    let v22 = s_mul(v0, v2);
    let v23 = s_atan(v22);
    let v24 = s_add(v21, v23);
    return select(v24, s_empty(), s_is_empty(v5) || s_is_empty(v12));
}

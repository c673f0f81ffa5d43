// f = (((((sqrt((x^2 + y^2)) + exp((-z))) + log((x^2 + 1))) + (sin(x) * cos(y))) - tan((z / 4))) + atan((x * y)))
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = x;
    let v1 = ia_sqr(v0);
    let v2 = y;
    let v3 = ia_sqr(v2);
    let v4 = ia_add(v1, v3);
    let v5 = ia_sqrt(v4);
    let v6 = z;
    let v7 = ia_neg(v6);
    let v8 = ia_exp(v7);
    let v9 = ia_add(v5, v8);
    let v10 = ia_const(1.0);
    let v11 = ia_add(v1, v10);
    let v12 = ia_log(v11);
    let v13 = ia_add(v9, v12);
    let v14 = ia_sin(v0);
    let v15 = ia_cos(v2);
    let v16 = ia_mul(v14, v15);
    let v17 = ia_add(v13, v16);
    let v18 = ia_const(4.0);
    let v19 = ia_mul(v6, vec2<f32>(0.25, 0.25));
    let v20 = ia_tan(v19);
    let v21 = ia_sub(v17, v20);
    let v22 = ia_mul(v0, v2);
    let v23 = ia_atan(v22);
    let v24 = ia_add(v21, v23);
    return select(v24, ia_empty(), ia_is_empty(v5) || ia_is_empty(v12));
}

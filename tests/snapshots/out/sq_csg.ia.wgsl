// f = max((((((x^2)^2)^2 + ((y^2)^2)^2) + ((z^2)^2)^2) - 1), (-min(min(((y^2 + z^2) - 0.25), ((x^2 + z^2) - 0.25)), ((x^2 + y^2) - 0.25))))
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = ia_const(0.25);
    let v1 = x;
    let v2 = ia_sqr(v1);
    let v3 = ia_sqr(v2);
    let v4 = ia_sqr(v3);
    let v5 = y;
    let v6 = ia_sqr(v5);
    let v7 = ia_sqr(v6);
    let v8 = ia_sqr(v7);
    let v9 = ia_add(v4, v8);
    let v10 = z;
    let v11 = ia_sqr(v10);
    let v12 = ia_sqr(v11);
    let v13 = ia_sqr(v12);
    let v14 = ia_add(v9, v13);
    let v15 = ia_const(1.0);
    let v16 = ia_sub(v14, v15);
    let v17 = ia_add(v6, v11);
    let v18 = ia_sub(v17, v0);
    let v19 = ia_add(v2, v11);
    let v20 = ia_sub(v19, v0);
    let v21 = ia_min(v18, v20);
    let v22 = ia_add(v2, v6);
    let v23 = ia_sub(v22, v0);
    let v24 = ia_min(v21, v23);
    let v25 = ia_neg(v24);
    let v26 = ia_max(v16, v25);
    return v26;
}

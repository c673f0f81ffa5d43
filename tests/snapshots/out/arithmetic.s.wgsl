// f = ((((((x + y) * (z - 1)) / (2 + x^2)) - (-y)) + (z / 3.141592653589793)) - (x * 2.718281828459045))
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = x;
    let v1 = y;
    let v2 = s_add(v0, v1);
    let v3 = z;
    let v4 = s_const(1.0);
    let v5 = s_sub(v3, v4);
    let v6 = s_mul(v2, v5);
    let v7 = s_const(2.0);
    let v8 = s_sqr(v0);
    let v9 = s_add(v7, v8);
    let v10 = s_div(v6, v9);
    let v11 = s_neg(v1);
    let v12 = s_sub(v10, v11);
    let v13 = s_const(3.1415927);
    let v14 = s_div(v3, v13);
    let v15 = s_add(v12, v14);
    let v16 = s_const(2.7182817);
    let v17 = s_mul(v0, v16);
    let v18 = s_sub(v15, v17);
    return v18;
}

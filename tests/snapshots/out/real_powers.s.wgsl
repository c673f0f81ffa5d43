// f = (((pow((x^2 + 1), 0.25) + pow(abs(y), 1.5)) + pow(z^2, x)) - 0.5)
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = x;
    let v1 = s_sqr(v0);
    let v2 = s_const(1.0);
    let v3 = s_add(v1, v2);
    let v4 = s_const(0.25);
    let v5 = s_pow(v3, v4);
    let v6 = y;
    let v7 = s_abs(v6);
    let v8 = s_const(1.5);
    let v9 = s_pow(v7, v8);
    let v10 = s_add(v5, v9);
    let v11 = z;
    let v12 = s_sqr(v11);
    let v13 = s_pow(v12, v0);
    let v14 = s_add(v10, v13);
    let v15 = s_const(0.5);
    let v16 = s_sub(v14, v15);
    return select(v16, s_empty(), s_is_empty(v5) || s_is_empty(v9) || s_is_empty(v13));
}

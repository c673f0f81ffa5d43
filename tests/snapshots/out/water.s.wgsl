// f = ((z - ((0.1 * sin((t + (4 * x)))) * cos(((0.7 * t) + (3 * y))))) - (0.05 * sin((((x * 7) - (y * 5)) + (t * 1.3)))))
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = s_const(0.7);
    let v1 = t;
    let v2 = s_mul(v0, v1);
    let v3 = s_const(0.1);
    let v4 = s_const(4.0);
    let v5 = x;
    let v6 = s_mul(v4, v5);
    let v7 = s_add(v1, v6);
    let v8 = s_sin(v7);
    let v9 = s_mul(v3, v8);
    let v10 = s_const(3.0);
    let v11 = y;
    let v12 = s_mul(v10, v11);
    let v13 = s_add(v2, v12);
    let v14 = s_cos(v13);
    let v15 = s_mul(v9, v14);
    let v16 = s_const(0.05);
    let v17 = s_const(7.0);
    let v18 = s_mul(v5, v17);
    let v19 = s_const(5.0);
    let v20 = s_mul(v11, v19);
    let v21 = s_sub(v18, v20);
    let v22 = s_const(1.3);
    let v23 = s_mul(v1, v22);
    let v24 = s_add(v21, v23);
    let v25 = s_sin(v24);
    let v26 = s_mul(v16, v25);
    let v27 = z;
    let v28 = s_sub(v27, v15);
    let v29 = s_sub(v28, v26);
    return v29;
}

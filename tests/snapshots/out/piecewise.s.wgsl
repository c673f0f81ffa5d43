// f = ((max(max((-1), max(z, max(x, y))), max((abs(x) - 1), min(y, z))) + min(z, min(sign(x), floor((y * 3))))) - 0.5)
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = x;
    let v1 = s_abs(v0);
    let v2 = s_const(1.0);
    let v3 = s_sub(v1, v2);
    let v4 = y;
    let v5 = z;
    let v6 = s_min(v4, v5);
    let v7 = s_const(-1.0);
    let v8 = s_max(v0, v4);
    let v9 = s_max(v5, v8);
    let v10 = s_max(v7, v9);
    let v11 = s_max(v3, v6);
    let v12 = s_max(v10, v11);
    let v13 = s_sign(v0);
    let v14 = s_const(3.0);
    let v15 = s_mul(v4, v14);
    let v16 = s_floor(v15);
    let v17 = s_min(v13, v16);
    let v18 = s_min(v5, v17);
    let v19 = s_add(v12, v18);
    let v20 = s_const(0.5);
    let v21 = s_sub(v19, v20);
    return v21;
}

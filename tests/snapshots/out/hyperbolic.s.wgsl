// f = ((sinh(x) + (cosh(y) * tanh(z))) - 2)
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = x;
    let v1 = s_sinh(v0);
    let v2 = y;
    let v3 = s_cosh(v2);
    let v4 = z;
    let v5 = s_tanh(v4);
    let v6 = s_mul(v3, v5);
    let v7 = s_add(v1, v6);
    let v8 = s_const(2.0);
    let v9 = s_sub(v7, v8);
    return v9;
}

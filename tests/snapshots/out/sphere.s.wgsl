// f = (((x^2 + y^2) + z^2) - 1)
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = s_const(1.0);
    let v1 = x;
    let v2 = s_sqr(v1);
    let v3 = y;
    let v4 = s_sqr(v3);
    let v5 = s_add(v2, v4);
    let v6 = z;
    let v7 = s_sqr(v6);
    let v8 = s_add(v5, v7);
    let v9 = s_sub(v8, v0);
    return v9;
}

// f = ((((x^2 * y^2) + (y^2 * z^2)) + (x^2 * z^2)) - (z * (x * y)))
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = x;
    let v1 = s_sqr(v0);
    let v2 = y;
    let v3 = s_sqr(v2);
    let v4 = s_mul(v1, v3);
    let v5 = z;
    let v6 = s_sqr(v5);
    let v7 = s_mul(v3, v6);
    let v8 = s_add(v4, v7);
    let v9 = s_mul(v1, v6);
    let v10 = s_add(v8, v9);
    let v11 = s_mul(v0, v2);
    let v12 = s_mul(v5, v11);
    let v13 = s_sub(v10, v12);
    return v13;
}

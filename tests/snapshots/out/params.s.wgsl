// f = ((((a * x^2) + (b * y^2)) - (c * z)) + sin(t))
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = s_const(iso_param(0u));
    let v1 = x;
    let v2 = s_sqr(v1);
    let v3 = s_mul(v0, v2);
    let v4 = s_const(iso_param(1u));
    let v5 = y;
    let v6 = s_sqr(v5);
    let v7 = s_mul(v4, v6);
    let v8 = s_add(v3, v7);
    let v9 = s_const(iso_param(2u));
    let v10 = z;
    let v11 = s_mul(v9, v10);
    let v12 = s_sub(v8, v11);
    let v13 = t;
    let v14 = s_sin(v13);
    let v15 = s_add(v12, v14);
    return v15;
}

// f = (((((x^2)^2 + (y^2)^3) + (((z^2)^2)^2)^25) + (x^2 * (x^2)^3)) - 1)
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = x;
    let v1 = s_sqr(v0);
    let v2 = s_sqr(v1);
    let v3 = y;
    let v4 = s_sqr(v3);
    let w5_b = s_pw_lift(v4);
    let w5_s0 = s_pw_sq(w5_b);
    let w5_m0 = s_pw_mul(w5_s0, w5_b);
    let v5 = s_pw_odd(v4, w5_m0);
    let v6 = s_add(v2, v5);
    let v7 = z;
    let v8 = s_sqr(v7);
    let v9 = s_sqr(v8);
    let v10 = s_sqr(v9);
    let w11_b = s_pw_lift(v10);
    let w11_s0 = s_pw_sq(w11_b);
    let w11_m0 = s_pw_mul(w11_s0, w11_b);
    let w11_s1 = s_pw_sq(w11_m0);
    let w11_s2 = s_pw_sq(w11_s1);
    let w11_s3 = s_pw_sq(w11_s2);
    let w11_m3 = s_pw_mul(w11_s3, w11_b);
    let v11 = s_pw_odd(v10, w11_m3);
    let v12 = s_add(v6, v11);
    let w13_b = s_pw_lift(v1);
    let w13_s0 = s_pw_sq(w13_b);
    let w13_m0 = s_pw_mul(w13_s0, w13_b);
    let v13 = s_pw_odd(v1, w13_m0);
    let v14 = s_mul(v1, v13);
    let v15 = s_add(v12, v14);
    let v16 = s_const(1.0);
    let v17 = s_sub(v15, v16);
    return v17;
}

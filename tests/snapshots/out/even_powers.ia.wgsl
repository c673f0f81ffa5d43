// f = (((((x^2)^2 + (y^2)^3) + (((z^2)^2)^2)^25) + (x^2 * (x^2)^3)) - 1)
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = x;
    let v1 = ia_sqr(v0);
    let v2 = ia_sqr(v1);
    let v3 = y;
    let v4 = ia_sqr(v3);
    let w5_b = ia_pw_lift(v4);
    let w5_s0 = ia_pw_sq(w5_b);
    let w5_m0 = ia_pw_mul(w5_s0, w5_b);
    let v5 = ia_pw_odd(v4, w5_m0);
    let v6 = ia_add(v2, v5);
    let v7 = z;
    let v8 = ia_sqr(v7);
    let v9 = ia_sqr(v8);
    let v10 = ia_sqr(v9);
    let w11_b = ia_pw_lift(v10);
    let w11_s0 = ia_pw_sq(w11_b);
    let w11_m0 = ia_pw_mul(w11_s0, w11_b);
    let w11_s1 = ia_pw_sq(w11_m0);
    let w11_s2 = ia_pw_sq(w11_s1);
    let w11_s3 = ia_pw_sq(w11_s2);
    let w11_m3 = ia_pw_mul(w11_s3, w11_b);
    let v11 = ia_pw_odd(v10, w11_m3);
    let v12 = ia_add(v6, v11);
    let w13_b = ia_pw_lift(v1);
    let w13_s0 = ia_pw_sq(w13_b);
    let w13_m0 = ia_pw_mul(w13_s0, w13_b);
    let v13 = ia_pw_odd(v1, w13_m0);
    let v14 = ia_mul_nonneg(v1, v13);
    let v15 = ia_add(v12, v14);
    let v16 = ia_const(1.0);
    let v17 = ia_sub(v15, v16);
    return v17;
}

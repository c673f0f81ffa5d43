// f = ((((x^3 + y^5) - z^7) + (x - y)^9) - (0.5 * (1 / x^3)))
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = x;
    let w1_b = ia_pw_lift(v0);
    let w1_s0 = ia_pw_sq(w1_b);
    let w1_m0 = ia_pw_mul(w1_s0, w1_b);
    let v1 = ia_pw_odd(v0, w1_m0);
    let v2 = y;
    let w3_b = ia_pw_lift(v2);
    let w3_s0 = ia_pw_sq(w3_b);
    let w3_s1 = ia_pw_sq(w3_s0);
    let w3_m1 = ia_pw_mul(w3_s1, w3_b);
    let v3 = ia_pw_odd(v2, w3_m1);
    let v4 = ia_add(v1, v3);
    let v5 = z;
    let w6_b = ia_pw_lift(v5);
    let w6_s0 = ia_pw_sq(w6_b);
    let w6_m0 = ia_pw_mul(w6_s0, w6_b);
    let w6_s1 = ia_pw_sq(w6_m0);
    let w6_m1 = ia_pw_mul(w6_s1, w6_b);
    let v6 = ia_pw_odd(v5, w6_m1);
    let v7 = ia_sub(v4, v6);
    let v8 = ia_sub(v0, v2);
    let w9_b = ia_pw_lift(v8);
    let w9_s0 = ia_pw_sq(w9_b);
    let w9_s1 = ia_pw_sq(w9_s0);
    let w9_s2 = ia_pw_sq(w9_s1);
    let w9_m2 = ia_pw_mul(w9_s2, w9_b);
    let v9 = ia_pw_odd(v8, w9_m2);
    let v10 = ia_add(v7, v9);
    let v11 = ia_const(0.5);
    let v12 = ia_const(1.0);
    let v13 = ia_div(v12, v1);
    let v14 = ia_mul(v11, v13);
    let v15 = ia_sub(v10, v14);
    return v15;
}

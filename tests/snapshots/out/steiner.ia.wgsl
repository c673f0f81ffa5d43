// f = ((((x^2 * y^2) + (y^2 * z^2)) + (x^2 * z^2)) - (z * (x * y)))
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = x;
    let v1 = ia_sqr(v0);
    let v2 = y;
    let v3 = ia_sqr(v2);
    let v4 = ia_mul_nonneg(v1, v3);
    let v5 = z;
    let v6 = ia_sqr(v5);
    let v7 = ia_mul_nonneg(v3, v6);
    let v8 = ia_add(v4, v7);
    let v9 = ia_mul_nonneg(v1, v6);
    let v10 = ia_add(v8, v9);
    let v11 = ia_mul(v0, v2);
    let v12 = ia_mul(v5, v11);
    let v13 = ia_sub(v10, v12);
    return v13;
}

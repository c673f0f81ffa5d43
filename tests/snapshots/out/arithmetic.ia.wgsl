// f = ((((((x + y) * (z - 1)) / (2 + x^2)) - (-y)) + (z / 3.141592653589793)) - (x * 2.718281828459045))
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = x;
    let v1 = y;
    let v2 = ia_add(v0, v1);
    let v3 = z;
    let v4 = ia_const(1.0);
    let v5 = ia_sub(v3, v4);
    let v6 = ia_mul(v2, v5);
    let v7 = ia_const(2.0);
    let v8 = ia_sqr(v0);
    let v9 = ia_add(v7, v8);
    let v10 = ia_div(v6, v9);
    let v11 = ia_neg(v1);
    let v12 = ia_sub(v10, v11);
    let v13 = vec2<f32>(3.1415925, 3.1415927);
    let v14 = ia_mul(v3, vec2<f32>(0.31830987, 0.3183099));
    let v15 = ia_add(v12, v14);
    let v16 = vec2<f32>(2.7182817, 2.718282);
    let v17 = ia_mul(v0, v16);
    let v18 = ia_sub(v15, v17);
    return v18;
}

// f = (((pow((x^2 + 1), 0.25) + pow(abs(y), 1.5)) + pow(z^2, x)) - 0.5)
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = x;
    let v1 = ia_sqr(v0);
    let v2 = ia_const(1.0);
    let v3 = ia_add(v1, v2);
    let v4 = ia_const(0.25);
    let v5 = ia_pow(v3, v4);
    let v6 = y;
    let v7 = ia_abs(v6);
    let v8 = ia_const(1.5);
    let v9 = ia_pow(v7, v8);
    let v10 = ia_add(v5, v9);
    let v11 = z;
    let v12 = ia_sqr(v11);
    let v13 = ia_pow(v12, v0);
    let v14 = ia_add(v10, v13);
    let v15 = ia_const(0.5);
    let v16 = ia_sub(v14, v15);
    return select(v16, ia_empty(), ia_is_empty(v5) || ia_is_empty(v9) || ia_is_empty(v13));
}

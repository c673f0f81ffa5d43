// f = ((((a * x^2) + (b * y^2)) - (c * z)) + sin(t))
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = ia_const(iso_param(0u));
    let v1 = x;
    let v2 = ia_sqr(v1);
    let v3 = ia_mul(v0, v2);
    let v4 = ia_const(iso_param(1u));
    let v5 = y;
    let v6 = ia_sqr(v5);
    let v7 = ia_mul(v4, v6);
    let v8 = ia_add(v3, v7);
    let v9 = ia_const(iso_param(2u));
    let v10 = z;
    let v11 = ia_mul(v9, v10);
    let v12 = ia_sub(v8, v11);
    let v13 = t;
    let v14 = ia_sin(v13);
    let v15 = ia_add(v12, v14);
    return v15;
}

// f = ((sinh(x) + (cosh(y) * tanh(z))) - 2)
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = x;
    let v1 = ia_sinh(v0);
    let v2 = y;
    let v3 = ia_cosh(v2);
    let v4 = z;
    let v5 = ia_tanh(v4);
    let v6 = ia_mul(v3, v5);
    let v7 = ia_add(v1, v6);
    let v8 = ia_const(2.0);
    let v9 = ia_sub(v7, v8);
    return v9;
}

// f = (((x^2 + y^2) + z^2) - 1)
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = ia_const(1.0);
    let v1 = x;
    let v2 = ia_sqr(v1);
    let v3 = y;
    let v4 = ia_sqr(v3);
    let v5 = ia_add(v2, v4);
    let v6 = z;
    let v7 = ia_sqr(v6);
    let v8 = ia_add(v5, v7);
    let v9 = ia_sub(v8, v0);
    return v9;
}

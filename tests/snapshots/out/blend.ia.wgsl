// f = (mix(atan2(y, x), clamp(z, (-1), 1), 0.25) - clamp(x^2, 0, sqrt((1 + y^2))))
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = y;
    let v1 = x;
    let v2 = ia_atan2(v0, v1);
    let v3 = z;
    let v4 = ia_const(1.0);
    let v5 = ia_const(-1.0);
    let v6 = ia_clamp(v3, v5, v4);
    let v7 = ia_const(0.25);
    let v8 = ia_mix(v2, v6, v7);
    let v9 = ia_sqr(v1);
    let v10 = ia_const(0.0);
    let v11 = ia_sqr(v0);
    let v12 = ia_add(v4, v11);
    let v13 = ia_sqrt(v12);
    let v14 = ia_clamp(v9, v10, v13);
    let v15 = ia_sub(v8, v14);
    return select(v15, ia_empty(), ia_is_empty(v13));
}

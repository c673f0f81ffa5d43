// f = ((z - ((0.1 * sin((t + (4 * x)))) * cos(((0.7 * t) + (3 * y))))) - (0.05 * sin((((x * 7) - (y * 5)) + (t * 1.3)))))
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = vec2<f32>(0.7, 0.70000005);
    let v1 = t;
    let v2 = ia_mul(v0, v1);
    let v3 = vec2<f32>(0.099999994, 0.1);
    let v4 = ia_const(4.0);
    let v5 = x;
    let v6 = ia_mul(v4, v5);
    let v7 = ia_add(v1, v6);
    let v8 = ia_sin(v7);
    let v9 = ia_mul(v3, v8);
    let v10 = ia_const(3.0);
    let v11 = y;
    let v12 = ia_mul(v10, v11);
    let v13 = ia_add(v2, v12);
    let v14 = ia_cos(v13);
    let v15 = ia_mul(v9, v14);
    let v16 = vec2<f32>(0.049999997, 0.05);
    let v17 = ia_const(7.0);
    let v18 = ia_mul(v5, v17);
    let v19 = ia_const(5.0);
    let v20 = ia_mul(v11, v19);
    let v21 = ia_sub(v18, v20);
    let v22 = vec2<f32>(1.3, 1.3000001);
    let v23 = ia_mul(v1, v22);
    let v24 = ia_add(v21, v23);
    let v25 = ia_sin(v24);
    let v26 = ia_mul(v16, v25);
    let v27 = z;
    let v28 = ia_sub(v27, v15);
    let v29 = ia_sub(v28, v26);
    return v29;
}

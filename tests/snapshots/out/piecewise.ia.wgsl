// f = ((max(max((-1), max(z, max(x, y))), max((abs(x) - 1), min(y, z))) + min(z, min(sign(x), floor((y * 3))))) - 0.5)
fn eval_ia(x: vec2<f32>, y: vec2<f32>, z: vec2<f32>, t: vec2<f32>) -> vec2<f32> {
    let v0 = x;
    let v1 = ia_abs(v0);
    let v2 = ia_const(1.0);
    let v3 = ia_sub(v1, v2);
    let v4 = y;
    let v5 = z;
    let v6 = ia_min(v4, v5);
    let v7 = ia_const(-1.0);
    let v8 = ia_max(v0, v4);
    let v9 = ia_max(v5, v8);
    let v10 = ia_max(v7, v9);
    let v11 = ia_max(v3, v6);
    let v12 = ia_max(v10, v11);
    let v13 = ia_sign(v0);
    let v14 = ia_const(3.0);
    let v15 = ia_mul(v4, v14);
    let v16 = ia_floor(v15);
    let v17 = ia_min(v13, v16);
    let v18 = ia_min(v5, v17);
    let v19 = ia_add(v12, v18);
    let v20 = ia_const(0.5);
    let v21 = ia_sub(v19, v20);
    return v21;
}

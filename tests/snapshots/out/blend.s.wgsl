// f = (mix(atan2(y, x), clamp(z, (-1), 1), 0.25) - clamp(x^2, 0, sqrt((1 + y^2))))
fn eval_s(x: f32, y: f32, z: f32, t: f32) -> f32 {
    let v0 = y;
    let v1 = x;
    let v2 = s_atan2(v0, v1);
    let v3 = z;
    let v4 = s_const(1.0);
    let v5 = s_const(-1.0);
    let v6 = s_clamp(v3, v5, v4);
    let v7 = s_const(0.25);
    let v8 = s_mix(v2, v6, v7);
    let v9 = s_sqr(v1);
    let v10 = s_const(0.0);
    let v11 = s_sqr(v0);
    let v12 = s_add(v4, v11);
    let v13 = s_sqrt(v12);
    let v14 = s_clamp(v9, v10, v13);
    let v15 = s_sub(v8, v14);
    return select(v15, s_empty(), s_is_empty(v13));
}

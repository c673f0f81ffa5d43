// f = ((z - ((0.1 * sin((t + (4 * x)))) * cos(((0.7 * t) + (3 * y))))) - (0.05 * sin((((x * 7) - (y * 5)) + (t * 1.3)))))
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = vec3<f32>(0.70000005, 0.0, 2.9802322e-8);
    let v1 = t;
    let v2 = ra_mul(v0, v1);
    let v3 = vec3<f32>(0.099999994, 0.0, 3.7252903e-9);
    let v4 = ra_const(4.0);
    let v5 = x;
    let v6 = ra_mul(v4, v5);
    let v7 = ra_add(v1, v6);
    let v8 = ra_sin(v7);
    let v9 = ra_mul(v3, v8);
    let v10 = ra_const(3.0);
    let v11 = y;
    let v12 = ra_mul(v10, v11);
    let v13 = ra_add(v2, v12);
    let v14 = ra_cos(v13);
    let v15 = ra_mul(v9, v14);
    let v16 = vec3<f32>(0.049999997, 0.0, 1.8626451e-9);
    let v17 = ra_const(7.0);
    let v18 = ra_mul(v5, v17);
    let v19 = ra_const(5.0);
    let v20 = ra_mul(v11, v19);
    let v21 = ra_sub(v18, v20);
    let v22 = vec3<f32>(1.3, 0.0, 5.9604645e-8);
    let v23 = ra_mul(v1, v22);
    let v24 = ra_add(v21, v23);
    let v25 = ra_sin(v24);
    let v26 = ra_mul(v16, v25);
    let v27 = z;
    let v28 = ra_sub(v27, v15);
    let v29 = ra_sub(v28, v26);
    return v29;
}

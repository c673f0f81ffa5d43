// f = ((max(max((-1), max(z, max(x, y))), max((abs(x) - 1), min(y, z))) + min(z, min(sign(x), floor((y * 3))))) - 0.5)
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = x;
    let v1 = ra_abs(v0);
    let v2 = ra_const(1.0);
    let v3 = ra_sub(v1, v2);
    let v4 = y;
    let v5 = z;
    let v6 = ra_min(v4, v5);
    let v7 = ra_const(-1.0);
    let v8 = ra_max(v0, v4);
    let v9 = ra_max(v5, v8);
    let v10 = ra_max(v7, v9);
    let v11 = ra_max(v3, v6);
    let v12 = ra_max(v10, v11);
    let v13 = ra_sign(v0);
    let v14 = ra_const(3.0);
    let v15 = ra_mul(v4, v14);
    let v16 = ra_floor(v15);
    let v17 = ra_min(v13, v16);
    let v18 = ra_min(v5, v17);
    let v19 = ra_add(v12, v18);
    let v20 = ra_const(0.5);
    let v21 = ra_sub(v19, v20);
    return v21;
}

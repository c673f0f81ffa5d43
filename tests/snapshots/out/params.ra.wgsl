// f = ((((a * x^2) + (b * y^2)) - (c * z)) + sin(t))
fn eval_ra(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let v0 = ra_const(iso_param(0u));
    let v1 = x;
    let v2 = ra_sqr(v1);
    let v3 = ra_mul(v0, v2);
    let v4 = ra_const(iso_param(1u));
    let v5 = y;
    let v6 = ra_sqr(v5);
    let v7 = ra_mul(v4, v6);
    let v8 = ra_add(v3, v7);
    let v9 = ra_const(iso_param(2u));
    let v10 = z;
    let v11 = ra_mul(v9, v10);
    let v12 = ra_sub(v8, v11);
    let v13 = t;
    let v14 = ra_sin(v13);
    let v15 = ra_add(v12, v14);
    return v15;
}

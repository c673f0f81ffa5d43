var<private> g_poly_mid: f32;

// Polynomial nodes of degree 3 to 6 in x, y, z restricted to a ray (src/
// codegen/ray_polys.rs): field_begin_ray works out their coefficients
// c0 + c1 u + ... + cn uⁿ along the ray, u = t − g_poly_mid from the middle
// of its extent in the domain (pa = c0..c3, pb = c4..c6 and the pad's
// scale in f32 roundings; pm, pn the magnitude's), and a cell [t0, t1]
// encloses the node by the polynomial's Bernstein coefficients over the
// cell, widened by pads worked out per cell (below): the range of
// a polynomial lies between its least and greatest Bernstein coefficient,
// and they converge to it quadratically as the cell shrinks. Intervals
// over the cell's box lose the dependency between the node's terms (the
// 4-bretzel's (x² + y²)³ − 4x²y², which nearly cancels on its surface).
//
// How. The Taylor coefficients at t0 (Horner's synthetic division, n(n+1)/2
// multiply-adds) give the polynomial in u = (t − t0)/h on [0, 1], whose
// power coefficients convert to Bernstein ones by fixed weights C(i,k) /
// C(n,k). The slope's come the same way from the derivative's Taylor
// coefficients (k·T_k), not from differences of the value's divided by h,
// which would amplify their rounding on a small cell by 1/h. Each result is
// (value lo, hi, slope lo, hi) before the pads. The four ray_polyN_bern are
// this one algorithm written out for degrees 3 to 6: straight-line scalar
// code, no arrays or loops for lavapipe to lower (a call's value and slope
// share one after inlining).

// The magnitude polynomial m (pm = m0..m3, pn = m4..m6) and its first
// two derivatives at τ = |t0 − mid| + (t1 − t0), which bounds |t − mid|
// over the cell: bounds of the terms that the Taylor shift to t0 and the
// Bernstein weights round (m), and of the value's and the slope's rates of
// change (m', m'') for the rounding of the cell's ends themselves.
fn ray_poly_magnitude(pm: vec4<f32>, pn: vec4<f32>, tau: f32) -> vec3<f32> {
    let v = pm.x + tau * (pm.y + tau * (pm.z + tau * (pm.w + tau * (pn.x + tau * (pn.y + tau * pn.z)))));
    let d = pm.y + tau * (2.0 * pm.z + tau * (3.0 * pm.w + tau * (4.0 * pn.x + tau * (5.0 * pn.y + tau * 6.0 * pn.z))));
    let d2 = 2.0 * pm.z + tau * (6.0 * pm.w + tau * (12.0 * pn.x + tau * (20.0 * pn.y + tau * 30.0 * pn.z)));
    return vec3<f32>(v, d, d2);
}

// The pads of a cell [t0, t1] (from the ray's start; u0 = t0 − mid): the
// counted roundings (pb.w) of the magnitude, and the rounding of the cell's
// ends as the polynomial sees them (t0 − mid after s0 − start: up to 2^-23
// of |t0| + |u0| each) times the value's and the slope's rates of change.
fn ray_poly_pads(pb: vec4<f32>, pm: vec4<f32>, pn: vec4<f32>, t0: f32, t1: f32) -> vec2<f32> {
    let u0 = t0 - g_poly_mid;
    let tau = abs(u0) + (t1 - t0);
    let m = ray_poly_magnitude(pm, pn, tau);
    let shift = 1.2e-7 * (max(abs(t0), abs(t1)) + tau);
    return pb.w * m.xy + shift * m.yz;
}

// A node's enclosure over the cell [t0, t1] (from the ray's start) of its
// Bernstein bounds b (ray_polyN_bern) and its state: the value's, and the
// slope's.
fn ia_ray_poly(b: vec4<f32>, pb: vec4<f32>, pm: vec4<f32>, pn: vec4<f32>, t0: f32, t1: f32) -> vec2<f32> {
    return ray_poly_widen(b.xy, ray_poly_pads(pb, pm, pn, t0, t1).x);
}
fn ia_ray_poly_slope(b: vec4<f32>, pb: vec4<f32>, pm: vec4<f32>, pn: vec4<f32>, t0: f32, t1: f32) -> vec2<f32> {
    return ray_poly_widen(b.zw, ray_poly_pads(pb, pm, pn, t0, t1).y);
}

// [lo, hi] widened by the pad; the whole line where a coefficient or the
// magnitude overflowed f32 on this ray (a NaN end or pad fails both tests).
fn ray_poly_widen(r: vec2<f32>, pad: f32) -> vec2<f32> {
    return select(vec2<f32>(-F.inf, F.inf), vec2<f32>(r.x - pad, r.y + pad), r.x <= r.y && pad >= 0.0);
}

// Degree 3.
fn ray_poly3_bern(pa: vec4<f32>, pb: vec4<f32>, t0: f32, t1: f32) -> vec4<f32> {
    let u0 = t0 - g_poly_mid;
    var a0 = pa.x;
    var a1 = pa.y;
    var a2 = pa.z;
    var a3 = pa.w;
    a2 = a2 + u0 * a3; a1 = a1 + u0 * a2; a0 = a0 + u0 * a1;
    a2 = a2 + u0 * a3; a1 = a1 + u0 * a2;
    a2 = a2 + u0 * a3;
    let h = t1 - t0;
    let h1 = h;
    let h2 = h1 * h;
    let h3 = h2 * h;
    let c0 = a0;
    let c1 = a1 * h1;
    let c2 = a2 * h2;
    let c3 = a3 * h3;
    let e0 = a1;
    let e1 = 2.0 * a2 * h1;
    let e2 = 3.0 * a3 * h2;
    let b0 = c0;
    let b1 = c0 + 0.3333333333333333 * c1;
    let b2 = c0 + 0.6666666666666666 * c1 + 0.3333333333333333 * c2;
    let b3 = c0 + c1 + c2 + c3;
    let g0 = e0;
    let g1 = e0 + 0.5 * e1;
    let g2 = e0 + e1 + e2;
    return vec4<f32>(min(min(min(b0, b1), b2), b3), max(max(max(b0, b1), b2), b3), min(min(g0, g1), g2), max(max(g0, g1), g2));
}

// Degree 4.
fn ray_poly4_bern(pa: vec4<f32>, pb: vec4<f32>, t0: f32, t1: f32) -> vec4<f32> {
    let u0 = t0 - g_poly_mid;
    var a0 = pa.x;
    var a1 = pa.y;
    var a2 = pa.z;
    var a3 = pa.w;
    var a4 = pb.x;
    a3 = a3 + u0 * a4; a2 = a2 + u0 * a3; a1 = a1 + u0 * a2; a0 = a0 + u0 * a1;
    a3 = a3 + u0 * a4; a2 = a2 + u0 * a3; a1 = a1 + u0 * a2;
    a3 = a3 + u0 * a4; a2 = a2 + u0 * a3;
    a3 = a3 + u0 * a4;
    let h = t1 - t0;
    let h1 = h;
    let h2 = h1 * h;
    let h3 = h2 * h;
    let h4 = h3 * h;
    let c0 = a0;
    let c1 = a1 * h1;
    let c2 = a2 * h2;
    let c3 = a3 * h3;
    let c4 = a4 * h4;
    let e0 = a1;
    let e1 = 2.0 * a2 * h1;
    let e2 = 3.0 * a3 * h2;
    let e3 = 4.0 * a4 * h3;
    let b0 = c0;
    let b1 = c0 + 0.25 * c1;
    let b2 = c0 + 0.5 * c1 + 0.16666666666666666 * c2;
    let b3 = c0 + 0.75 * c1 + 0.5 * c2 + 0.25 * c3;
    let b4 = c0 + c1 + c2 + c3 + c4;
    let g0 = e0;
    let g1 = e0 + 0.3333333333333333 * e1;
    let g2 = e0 + 0.6666666666666666 * e1 + 0.3333333333333333 * e2;
    let g3 = e0 + e1 + e2 + e3;
    return vec4<f32>(min(min(min(min(b0, b1), b2), b3), b4), max(max(max(max(b0, b1), b2), b3), b4), min(min(min(g0, g1), g2), g3), max(max(max(g0, g1), g2), g3));
}

// Degree 5.
fn ray_poly5_bern(pa: vec4<f32>, pb: vec4<f32>, t0: f32, t1: f32) -> vec4<f32> {
    let u0 = t0 - g_poly_mid;
    var a0 = pa.x;
    var a1 = pa.y;
    var a2 = pa.z;
    var a3 = pa.w;
    var a4 = pb.x;
    var a5 = pb.y;
    a4 = a4 + u0 * a5; a3 = a3 + u0 * a4; a2 = a2 + u0 * a3; a1 = a1 + u0 * a2; a0 = a0 + u0 * a1;
    a4 = a4 + u0 * a5; a3 = a3 + u0 * a4; a2 = a2 + u0 * a3; a1 = a1 + u0 * a2;
    a4 = a4 + u0 * a5; a3 = a3 + u0 * a4; a2 = a2 + u0 * a3;
    a4 = a4 + u0 * a5; a3 = a3 + u0 * a4;
    a4 = a4 + u0 * a5;
    let h = t1 - t0;
    let h1 = h;
    let h2 = h1 * h;
    let h3 = h2 * h;
    let h4 = h3 * h;
    let h5 = h4 * h;
    let c0 = a0;
    let c1 = a1 * h1;
    let c2 = a2 * h2;
    let c3 = a3 * h3;
    let c4 = a4 * h4;
    let c5 = a5 * h5;
    let e0 = a1;
    let e1 = 2.0 * a2 * h1;
    let e2 = 3.0 * a3 * h2;
    let e3 = 4.0 * a4 * h3;
    let e4 = 5.0 * a5 * h4;
    let b0 = c0;
    let b1 = c0 + 0.2 * c1;
    let b2 = c0 + 0.4 * c1 + 0.1 * c2;
    let b3 = c0 + 0.6 * c1 + 0.3 * c2 + 0.1 * c3;
    let b4 = c0 + 0.8 * c1 + 0.6 * c2 + 0.4 * c3 + 0.2 * c4;
    let b5 = c0 + c1 + c2 + c3 + c4 + c5;
    let g0 = e0;
    let g1 = e0 + 0.25 * e1;
    let g2 = e0 + 0.5 * e1 + 0.16666666666666666 * e2;
    let g3 = e0 + 0.75 * e1 + 0.5 * e2 + 0.25 * e3;
    let g4 = e0 + e1 + e2 + e3 + e4;
    return vec4<f32>(min(min(min(min(min(b0, b1), b2), b3), b4), b5), max(max(max(max(max(b0, b1), b2), b3), b4), b5), min(min(min(min(g0, g1), g2), g3), g4), max(max(max(max(g0, g1), g2), g3), g4));
}

// Degree 6.
fn ray_poly6_bern(pa: vec4<f32>, pb: vec4<f32>, t0: f32, t1: f32) -> vec4<f32> {
    let u0 = t0 - g_poly_mid;
    var a0 = pa.x;
    var a1 = pa.y;
    var a2 = pa.z;
    var a3 = pa.w;
    var a4 = pb.x;
    var a5 = pb.y;
    var a6 = pb.z;
    a5 = a5 + u0 * a6; a4 = a4 + u0 * a5; a3 = a3 + u0 * a4; a2 = a2 + u0 * a3; a1 = a1 + u0 * a2; a0 = a0 + u0 * a1;
    a5 = a5 + u0 * a6; a4 = a4 + u0 * a5; a3 = a3 + u0 * a4; a2 = a2 + u0 * a3; a1 = a1 + u0 * a2;
    a5 = a5 + u0 * a6; a4 = a4 + u0 * a5; a3 = a3 + u0 * a4; a2 = a2 + u0 * a3;
    a5 = a5 + u0 * a6; a4 = a4 + u0 * a5; a3 = a3 + u0 * a4;
    a5 = a5 + u0 * a6; a4 = a4 + u0 * a5;
    a5 = a5 + u0 * a6;
    let h = t1 - t0;
    let h1 = h;
    let h2 = h1 * h;
    let h3 = h2 * h;
    let h4 = h3 * h;
    let h5 = h4 * h;
    let h6 = h5 * h;
    let c0 = a0;
    let c1 = a1 * h1;
    let c2 = a2 * h2;
    let c3 = a3 * h3;
    let c4 = a4 * h4;
    let c5 = a5 * h5;
    let c6 = a6 * h6;
    let e0 = a1;
    let e1 = 2.0 * a2 * h1;
    let e2 = 3.0 * a3 * h2;
    let e3 = 4.0 * a4 * h3;
    let e4 = 5.0 * a5 * h4;
    let e5 = 6.0 * a6 * h5;
    let b0 = c0;
    let b1 = c0 + 0.16666666666666666 * c1;
    let b2 = c0 + 0.3333333333333333 * c1 + 0.06666666666666667 * c2;
    let b3 = c0 + 0.5 * c1 + 0.2 * c2 + 0.05 * c3;
    let b4 = c0 + 0.6666666666666666 * c1 + 0.4 * c2 + 0.2 * c3 + 0.06666666666666667 * c4;
    let b5 = c0 + 0.8333333333333334 * c1 + 0.6666666666666666 * c2 + 0.5 * c3 + 0.3333333333333333 * c4 + 0.16666666666666666 * c5;
    let b6 = c0 + c1 + c2 + c3 + c4 + c5 + c6;
    let g0 = e0;
    let g1 = e0 + 0.2 * e1;
    let g2 = e0 + 0.4 * e1 + 0.1 * e2;
    let g3 = e0 + 0.6 * e1 + 0.3 * e2 + 0.1 * e3;
    let g4 = e0 + 0.8 * e1 + 0.6 * e2 + 0.4 * e3 + 0.2 * e4;
    let g5 = e0 + e1 + e2 + e3 + e4 + e5;
    return vec4<f32>(min(min(min(min(min(min(b0, b1), b2), b3), b4), b5), b6), max(max(max(max(max(max(b0, b1), b2), b3), b4), b5), b6), min(min(min(min(min(g0, g1), g2), g3), g4), g5), max(max(max(max(max(g0, g1), g2), g3), g4), g5));
}

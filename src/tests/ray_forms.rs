//! Bisection's interval cells on rays, on the device (`gpu::eval::eval_ray_cells`):
//! the cell enclosure of a compiled formula, with the nodes of degree ≤ 2 in
//! x, y, z that it takes from their polynomial along the ray
//! (`field::compiled::ray_forms`), holds f64 samples of f and of its slope along the
//! ray over the cell, and the scalar field on the ray is f at the cell's ends.

use super::common;

use common::gpu;
use crate::gpu::eval::{eval_ray_cells, CellEnclosure, RayCell};
use crate::Formula;

/// A small deterministic generator (xorshift), uniform in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Random cells of rays through the cube [-a, a]³: an origin near it, a
/// direction of length 0.5 to 2, the ray's part [s_ref, s_ref + len], and a
/// cell of it from the whole part down to 2^-12 of it.
fn cells(a: f64, n: usize, seed: u64) -> Vec<RayCell> {
    let mut r = Rng(seed);
    (0..n)
        .map(|_| {
            let o = [0, 1, 2].map(|_| r.range(-1.5 * a, 1.5 * a) as f32);
            let scale = r.range(0.5, 2.0);
            let d: [f64; 3] = [0, 1, 2].map(|_| r.range(-1.0, 1.0));
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-3);
            let dir = d.map(|c| (c / l * scale) as f32);
            let s_ref = r.range(0.0, 1.0) as f32;
            let len = (r.range(0.5, 3.0) * a / scale) as f32;
            let w = len as f64 * 2f64.powf(-r.range(0.0, 12.0));
            let s0 = s_ref as f64 + r.range(0.0, len as f64 - w);
            RayCell { o, dir, s_ref, len, cell: [s0 as f32, (s0 + w) as f32] }
        })
        .collect()
}

/// f64 samples of f and of its slope along the ray over each cell lie in the
/// device's enclosures (up to a millionth of the values' size), and the
/// scalar ends are f's. Returns the mean ratio of the value enclosure's
/// width to the sampled range's.
fn check(src: &str, a: f64, seed: u64) -> f64 {
    check_at(src, a, seed, [0.0; 3])
}

/// [`check`] with the cells' rays moved by `at` (the cube about it).
fn check_at(src: &str, a: f64, seed: u64, at: [f32; 3]) -> f64 {
    let f = Formula::compile("<test>", src).unwrap();
    let cs: Vec<RayCell> = cells(a, 400, seed).into_iter().map(|c| RayCell { o: [0, 1, 2].map(|k| c.o[k] + at[k]), ..c }).collect();
    let got: Vec<CellEnclosure> = eval_ray_cells(gpu(), &f.ir, &cs).unwrap();
    let eval = |c: &RayCell, s: f64| {
        let p = [0, 1, 2].map(|k| c.o[k] as f64 + c.dir[k] as f64 * s);
        crate::reference::eval_scalar(&f.ir, [p[0], p[1], p[2], 0.0], &[])
    };
    let mut ratios = vec![];
    for (c, e) in cs.iter().zip(&got) {
        let [s0, s1] = c.cell.map(f64::from);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..=64 {
            let s = s0 + (s1 - s0) * k as f64 / 64.0;
            let v = eval(c, s);
            let tol = 1e-6 * (1.0 + v.abs());
            assert!(f64::from(e.value[0]) - tol <= v && v <= f64::from(e.value[1]) + tol, "{src}: f({s}) = {v} outside {:?} on {c:?}", e.value);
            let h = 1e-4 * (s1 - s0).max(1e-6);
            let slope = (eval(c, s + h) - eval(c, s - h)) / (2.0 * h);
            let stol = 1e-3 * (1.0 + slope.abs());
            assert!(f64::from(e.slope[0]) - stol <= slope && slope <= f64::from(e.slope[1]) + stol, "{src}: f'({s}) = {slope} outside {:?} on {c:?}", e.slope);
            lo = lo.min(v);
            hi = hi.max(v);
        }
        for (k, s) in [s0, s1].into_iter().enumerate() {
            let v = eval(c, s);
            assert!((f64::from(e.ends[k]) - v).abs() <= 1e-5 * (1.0 + v.abs()), "{src}: field_ray({s}) = {} against {v} on {c:?}", e.ends[k]);
        }
        if hi > lo {
            ratios.push((f64::from(e.value[1]) - f64::from(e.value[0])) / (hi - lo));
        }
    }
    ratios.iter().sum::<f64>() / ratios.len() as f64
}

#[test]
fn cell_enclosures_on_rays_hold_f64_samples() {
    let icos = &common::catalog_formula("icos.csg");
    let bretzel = &common::catalog_formula("4-bretzel");
    let steiner = &common::catalog_formula("steiner");
    let bilinear: Vec<String> = (0..40).map(|i| format!("({:.3}*x-y)*(z+{:.3})", 0.5 + i as f64 * 0.013, i as f64 * 0.021 - 0.3)).collect();
    let sum = format!("x^2 + y^2 + z^2 - 1 + 0.004*({})", bilinear.join(" + "));
    let cases: &[(&str, f64)] = &[
        (icos, 1.4),
        ("x*y + y*z + z*x + 0.3*x - 0.2", 1.0),
        ("(x - 0.2)^2/0.8 + 2*(y + 0.1)^2 + (1.5*z)^2 - 0.3*x*z - 0.7", 1.2),
        ("((x^2 + y^2 - 0.64)^2 + (z^2 - 1)^2)*((y^2 + z^2 - 0.64)^2 + (x^2 - 1)^2)*((z^2 + x^2 - 0.64)^2 + (y^2 - 1)^2) - 0.04", 1.5),
        ("max(x^8 + y^8 + z^8 - 1, -min(min(y^2 + z^2 - 0.25, x^2 + z^2 - 0.25), x^2 + y^2 - 0.25))", 1.5),
        ("sqrt((x - 0.3)^2 + y^2) - 0.5 + 0.1*sin(4*z)", 1.0),
        (&sum, 1.6),
        // Products of squares k·Q² (the 4-bretzel's 4x²y², Steiner's
        // x²y²), with a negative and an inexact factor, and a lone xy.
        (bretzel, 1.2),
        (steiner, 1.0),
        ("-0.3*x^2*z^2 + y^2*(x^2*1.7) - (y^2*z^2)/3 + x*y + x^2 + y^2 + z^2 - 1", 1.2),
    ];
    for (k, (src, a)) in cases.iter().enumerate() {
        check(src, *a, 0x9e37_79b9_7f4a_7c15 ^ k as u64);
    }
    // A formula that is one quadric as a whole is enclosed exactly, up to
    // its pad (2^-19 of its terms' size, which is most of the narrowest
    // cells' ranges): the sphere's enclosures are 1.6 % wider than its
    // sampled ranges on average; over the cells' boxes they are 2.7 times
    // as wide as that.
    let ratio = check("x^2 + y^2 + z^2 - 1", 1.5, 7);
    assert!(ratio < 1.05, "mean width over sampled range {ratio}");
    // So is a product of squares, through the square of xy's polynomial.
    let ratio = check("4*x^2*y^2 - 0.01", 1.2, 8);
    assert!(ratio < 1.05, "4x²y²: mean width over sampled range {ratio}");
    // Polynomials of degree 3 to 6 (`field::compiled::ray_polys`): Bernstein
    // enclosures of their polynomials along the ray, on average within
    // 1.05-1.35 times the sampled ranges (the pads, which grow with the
    // test rays' long extents, are most of the rest): the 4-bretzel's
    // (x² + y²)³ − 4x²y², the decocube's factor, a quintic with a product
    // of two sums, a negated cubic divided by a constant, and a sum of a
    // square and a product. Over the cells' boxes the first is enclosed
    // 2.4 times as wide on average (below).
    for (k, (src, most)) in [
        ("(x^2 + y^2)^3 - 4*x^2*y^2", 1.5),
        ("(x^2 + y^2 - 0.64)^2 + (z^2 - 1)^2", 1.5),
        ("(x + 0.5*y)*(x^2 + z^2 - 1)^2 - y^3*z^2 + 0.1", 1.5),
        ("-(x^3 - 3*x*y^2)/2 + z - 0.2", 1.5),
        ("(x*y - z)^2 + (x + y)*(y - z)*(z + 0.3)", 1.5),
    ]
    .into_iter()
    .enumerate()
    {
        let ratio = check(src, 1.2, 20 + k as u64);
        assert!(ratio < most, "{src}: mean width over sampled range {ratio}");
    }
    assert!(box_widening("x^2 + y^2 + z^2 - 1", 1.5, 7) > 1.3, "the sphere over the boxes");
    let w = box_widening("(x^2 + y^2)^3 - 4*x^2*y^2", 1.2, 20);
    assert!(w > 2.0, "the 4-bretzel's sextic over the boxes: {w}");
}

/// A polynomial moved away from the origin and scaled is enclosed on the
/// ray as tightly as where it is: its degree-2 nodes are taken in powers of
/// p − their centre (`Quad::centred`). In powers of p, ((x − 2.6)/0.22)²
/// has terms of some 300 where it is 3, and the pads of their roundings
/// would let a scaled tanglecube's last cells include 0 a hundredth from
/// its surface (false hits, where a max takes its slope away).
#[test]
fn moved_polynomials_are_enclosed_as_tightly_on_the_ray() {
    let tangle = "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8";
    let here = check(&format!("scale(0.22, {tangle})"), 0.7, 31);
    let moved = check_at(&format!("translate(2.6, 0, 0, scale(0.22, {tangle}))"), 0.7, 31, [2.6, 0.0, 0.0]);
    assert!(moved < 1.2 * here && moved < 1.6, "enclosures {moved} times the sampled ranges moved, {here} in place");
    let far = check_at("translate(30, -20, 5, (x^2 + y^2 - 0.64)^2 + (z^2 - 1)^2 - 0.1)", 1.2, 32, [30.0, -20.0, 5.0]);
    assert!(far < 1.6, "the decocube's factor moved far: {far}");
}

/// How many times wider, on average, the interval enclosures of `src` over
/// the cells' boxes are than its enclosures on the ray.
fn box_widening(src: &str, a: f64, seed: u64) -> f64 {
    let f = Formula::compile("<test>", src).unwrap();
    let cs = cells(a, 400, seed);
    let boxes: Vec<crate::gpu::eval::Box8> = cs
        .iter()
        .map(|c| {
            let end = |s: f32| [0, 1, 2].map(|k| c.o[k] + c.dir[k] * s);
            let (a, b) = (end(c.cell[0]), end(c.cell[1]));
            [a[0].min(b[0]), a[0].max(b[0]), a[1].min(b[1]), a[1].max(b[1]), a[2].min(b[2]), a[2].max(b[2]), 0.0, 0.0]
        })
        .collect();
    let over_box = crate::gpu::eval::eval_boxes(gpu(), &f.ir, crate::ir::Domain::Interval, &boxes, &[]).unwrap();
    let got = eval_ray_cells(gpu(), &f.ir, &cs).unwrap();
    got.iter().zip(&over_box).map(|(g, b)| f64::from(b[1] - b[0]) / f64::from(g.value[1] - g.value[0]).max(1e-30)).sum::<f64>() / cs.len() as f64
}

//! Polynomial subexpressions of degree 3 to 6 restricted to the ray.
//!
//! Along a ray p = p0 + dir·t a polynomial of degree n in x, y, z is a
//! polynomial of degree n in t alone. [`super::ray_forms`] takes nodes of
//! degree ≤ 2 from the ray with their exact range; a node of higher degree
//! whose terms depend on each other loses most where they cancel, which is
//! on the surface: the 4-bretzel's (x² + y²)³ − 4x²y² is zero along its
//! curve while each term is near 1, and the decocube's
//! (x² + y² − 0.64)² + (z² − 1)² adds two squares whose ranges over a
//! cell's box are independent. Such a node's coefficients along the ray are
//! worked out once per ray (`field_begin_ray`), composed from its operands'
//! (products are convolutions), and a cell encloses it by the polynomial's
//! Bernstein coefficients over the cell (templates/fields/ray_polys.wgsl and
//! [`bernstein_functions`]), whose overestimate shrinks with the square of
//! the cell.
//!
//! Rounding. Every value on the ray (cells, slopes, the root search's
//! points) is of the same f32 coefficients. Each coefficient's error is
//! counted in f32 roundings of the terms' magnitudes, which the same
//! composition on the operands' magnitudes bounds over the ray's extent in
//! the domain; the count grows with the operations that compose it, and the
//! cell's Taylor shift and Bernstein weights add a few per degree. The
//! enclosure is widened by twice that many roundings of the magnitude.

use super::ray_forms::Quad;
use crate::ir::{Ir, NodeId, Op};
use std::fmt::Write;

/// The highest degree taken from the ray: the cell's work grows with its
/// square (degree 6: about 100 operations a cell).
pub(crate) const MAX_DEGREE: u32 = 6;

/// Each node's degree as a polynomial in x, y, z, counted by its form
/// (a product's degree is the sum of its operands'); None where it is not
/// a polynomial (functions, divisions by non-constants or by a constant
/// whose inverse is not a normal f32, time).
pub(crate) fn degrees(ir: &Ir, forms: &[Option<Quad>]) -> Vec<Option<u32>> {
    let mut d: Vec<Option<u32>> = Vec::with_capacity(ir.nodes.len());
    for (id, op) in ir.nodes.iter().enumerate() {
        let g = |n: &NodeId| d[*n as usize];
        let deg = match op {
            _ if forms[id].is_some() => Some(if forms[id].is_some_and(|q| q.constant().is_some()) { 0 } else if forms[id].is_some_and(|q| q.linear()) { 1 } else { 2 }),
            Op::Neg(a) => g(a),
            Op::Add(a, b) | Op::Sub(a, b) => g(a).zip(g(b)).map(|(a, b)| a.max(b)),
            Op::Mul(a, b) => g(a).zip(g(b)).map(|(a, b)| a.saturating_add(b)),
            Op::PowI(a, e) if *e <= MAX_DEGREE => g(a).map(|a| a.saturating_mul(*e)),
            Op::Div(a, b) if forms[*b as usize].is_some_and(|q| q.constant().is_some_and(|k| ((1.0 / k) as f32).is_normal())) => g(a),
            _ => None,
        };
        d.push(deg);
    }
    d
}

/// Whether node `id` (a polynomial of degree 3 to [`MAX_DEGREE`]) gains from
/// the ray: a sum, a difference or a product of two non-constant nodes, whose
/// operands move together along the ray, or such a node negated, scaled or
/// offset by a constant. A power of one node is not (intervals take it
/// from its operand's range exactly), nor a node `exact` already takes from
/// the ray (a product of squares k·Q²).
pub(crate) fn worth(ir: &Ir, deg: &[Option<u32>], exact: &dyn Fn(NodeId) -> bool, id: NodeId) -> bool {
    let nonconst = |n: &NodeId| deg[*n as usize].is_some_and(|d| d > 0);
    if exact(id) || !deg[id as usize].is_some_and(|d| (3..=MAX_DEGREE).contains(&d)) {
        return false;
    }
    match ir.nodes[id as usize] {
        Op::Neg(a) | Op::Div(a, _) => worth(ir, deg, exact, a),
        Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) if !nonconst(&a) => worth(ir, deg, exact, b),
        Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) if !nonconst(&b) => worth(ir, deg, exact, a),
        Op::Add(..) | Op::Sub(..) | Op::Mul(..) => true,
        _ => false,
    }
}

/// One node's coefficients along the ray: for each power of t, the WGSL
/// names of its value and of its magnitude's bound; and the roundings its
/// computation may have made, in units of the magnitude.
#[derive(Clone)]
struct Coeffs {
    value: Vec<String>,
    magnitude: Vec<String>,
    roundings: u32,
}

/// Writes the coefficients of nodes along the ray into `field_begin_ray`'s
/// body: polynomials in t − `g_poly_mid`, about the middle `pm` of the
/// ray's extent in the domain (`dir`, and `ad` = |dir| for the magnitudes,
/// as `Quad::magnitude_along` needs). A magnitude polynomial (the
/// same composition of the operands' terms' absolute values) bounds the
/// terms at |t − g_poly_mid| ≤ τ by its value at τ; about the middle τ is
/// at most half the extent, where about one end it is the whole (the
/// 4-bretzel's (x² + y²)³ along a ray through its box: 17,500 about the
/// end against about 110 about the middle).
pub(crate) struct Writer<'a> {
    ir: &'a Ir,
    forms: &'a [Option<Quad>],
    deg: &'a [Option<u32>],
    done: Vec<Option<Coeffs>>,
    lists: usize,
}

impl<'a> Writer<'a> {
    pub(crate) fn new(ir: &'a Ir, forms: &'a [Option<Quad>], deg: &'a [Option<u32>]) -> Writer<'a> {
        Writer { ir, forms, deg, done: vec![None; ir.nodes.len()], lists: 0 }
    }

    /// The per-ray state of a polynomial node taken from the ray
    /// (`g_pa{id}`, `g_pb{id}`: its coefficients and the pad's scale;
    /// `g_pm{id}`, `g_pn{id}`: its magnitude's; see ray_polys.wgsl) and the
    /// lines of `field_begin_ray` that set it.
    pub(crate) fn node(&mut self, id: NodeId, decls: &mut String, body: &mut String) {
        let c = self.coeffs(id, body);
        let at = |v: &[String], k: usize| v.get(k).map_or("0.0", String::as_str).to_string();
        let ulps = 2 * (c.roundings + 8 * c.value.len() as u32 + 8);
        let scale = crate::codegen::lit((ulps as f64 * f64::powi(2.0, -24)) as f32);
        let (v, m) = (&c.value, &c.magnitude);
        let _ = writeln!(decls, "var<private> g_pa{id}: vec4<f32>;\nvar<private> g_pb{id}: vec4<f32>;\nvar<private> g_pm{id}: vec4<f32>;\nvar<private> g_pn{id}: vec4<f32>;");
        let _ = writeln!(body, "    g_pa{id} = vec4<f32>({}, {}, {}, {});", at(v, 0), at(v, 1), at(v, 2), at(v, 3));
        let _ = writeln!(body, "    g_pb{id} = vec4<f32>({}, {}, {}, {scale});", at(v, 4), at(v, 5), at(v, 6));
        let _ = writeln!(body, "    g_pm{id} = vec4<f32>({}, {}, {}, {});", at(m, 0), at(m, 1), at(m, 2), at(m, 3));
        let _ = writeln!(body, "    g_pn{id} = vec4<f32>({}, {}, {}, 0.0);", at(m, 4), at(m, 5), at(m, 6));
    }

    /// The coefficients of node `id`, written (with its operands') into `body` once.
    fn coeffs(&mut self, id: NodeId, body: &mut String) -> Coeffs {
        if let Some(c) = &self.done[id as usize] {
            return c.clone();
        }
        let c = match (self.forms[id as usize], self.ir.nodes[id as usize]) {
            (Some(q), _) => {
                let n = self.deg[id as usize].expect("a form has a degree") as usize;
                let _ = writeln!(body, "    let u{id} = {};\n    let w{id} = {};", q.along("pm", "dir"), q.magnitude_along(&["pm"], "ad"));
                let comp = ["x", "y", "z"];
                Coeffs { value: (0..=n).map(|k| format!("u{id}.{}", comp[k])).collect(), magnitude: (0..=n).map(|k| format!("w{id}.{}", comp[k])).collect(), roundings: 8 }
            }
            (None, Op::Neg(a)) => {
                let a = self.coeffs(a, body);
                self.bind(id, body, a.value.iter().map(|v| format!("-{v}")).collect(), a.magnitude, a.roundings)
            }
            (None, Op::Add(a, b)) => self.sum(id, a, b, "+", body),
            (None, Op::Sub(a, b)) => self.sum(id, a, b, "-", body),
            (None, Op::Mul(a, b)) => {
                let (a, b) = (self.coeffs(a, body), self.coeffs(b, body));
                self.product(id, &a, &b, body)
            }
            (None, Op::PowI(_, 0)) => self.bind(id, body, vec!["1.0".into()], vec!["1.0".into()], 0),
            (None, Op::PowI(a, e)) => {
                let a = self.coeffs(a, body);
                let mut acc = a.clone();
                for _ in 1..e {
                    acc = self.product(id, &acc, &a, body);
                }
                acc
            }
            (None, Op::Div(a, b)) => {
                let k = self.forms[b as usize].and_then(|q| q.constant()).expect("a division by a constant");
                let a = self.coeffs(a, body);
                let r = crate::codegen::lit((1.0 / k) as f32);
                let m = crate::codegen::lit((1.0 / k).abs() as f32);
                self.bind(id, body, a.value.iter().map(|v| format!("{v} * {r}")).collect(), a.magnitude.iter().map(|v| format!("{v} * {m}")).collect(), a.roundings + 2)
            }
            (None, op) => unreachable!("node {id} ({op:?}) has a degree but no polynomial form"),
        };
        self.done[id as usize] = Some(c.clone());
        c
    }

    fn sum(&mut self, id: NodeId, a: NodeId, b: NodeId, sign: &str, body: &mut String) -> Coeffs {
        let (a, b) = (self.coeffs(a, body), self.coeffs(b, body));
        let n = a.value.len().max(b.value.len());
        let pick = |v: &[String], k: usize| v.get(k).cloned();
        let value = (0..n)
            .map(|k| match (pick(&a.value, k), pick(&b.value, k)) {
                (Some(x), Some(y)) => format!("{x} {sign} {y}"),
                (Some(x), None) => x,
                (None, Some(y)) => if sign == "-" { format!("-{y}") } else { y },
                (None, None) => unreachable!("k < n"),
            })
            .collect();
        let magnitude = (0..n).map(|k| [pick(&a.magnitude, k), pick(&b.magnitude, k)].into_iter().flatten().collect::<Vec<_>>().join(" + ")).collect();
        self.bind(id, body, value, magnitude, a.roundings.max(b.roundings) + 1)
    }

    /// The product of two coefficient lists (a convolution), bound to fresh names.
    fn product(&mut self, id: NodeId, a: &Coeffs, b: &Coeffs, body: &mut String) -> Coeffs {
        let n = a.value.len() + b.value.len() - 1;
        let conv = |x: &[String], y: &[String]| -> Vec<String> {
            (0..n).map(|k| (0..=k).filter(|i| *i < x.len() && k - i < y.len()).map(|i| format!("{} * {}", x[i], y[k - i])).collect::<Vec<_>>().join(" + ")).collect()
        };
        let value = conv(&a.value, &b.value);
        let magnitude = conv(&a.magnitude, &b.magnitude);
        let steps = a.value.len().min(b.value.len()) as u32;
        self.bind(id, body, value, magnitude, a.roundings + b.roundings + steps + 1)
    }

    /// Binds coefficient expressions to names `r{id}_{j}_{k}` (values) and
    /// `n{id}_{j}_{k}` (magnitudes), `j` counting the lists made.
    fn bind(&mut self, id: NodeId, body: &mut String, value: Vec<String>, magnitude: Vec<String>, roundings: u32) -> Coeffs {
        let j = self.lists;
        self.lists += 1;
        let mut c = Coeffs { value: Vec::new(), magnitude: Vec::new(), roundings };
        for (k, (v, m)) in value.iter().zip(&magnitude).enumerate() {
            let _ = writeln!(body, "    let r{id}_{j}_{k} = {v};\n    let n{id}_{j}_{k} = {m};");
            c.value.push(format!("r{id}_{j}_{k}"));
            c.magnitude.push(format!("n{id}_{j}_{k}"));
        }
        c
    }
}


/// `ray_poly{n}_bern` for each degree n from 3 to [`MAX_DEGREE`], which
/// follow templates/fields/ray_polys.wgsl (whose header describes the
/// algorithm): the Taylor shift of the coefficients to the cell's start, the
/// powers of its width, and the Bernstein coefficients of the value (degree
/// n) and of the slope (degree n − 1) with their least and greatest.
pub(crate) fn bernstein_functions() -> String {
    (3..=MAX_DEGREE as usize).map(bernstein_function).collect()
}

/// `ray_poly{n}_bern`, written out as straight-line code.
fn bernstein_function(n: usize) -> String {
    const COEFFS: [&str; 7] = ["pa.x", "pa.y", "pa.z", "pa.w", "pb.x", "pb.y", "pb.z"];
    let mut s = format!("\n// Degree {n}.\nfn ray_poly{n}_bern(pa: vec4<f32>, pb: vec4<f32>, t0: f32, t1: f32) -> vec4<f32> {{\n    let u0 = t0 - g_poly_mid;\n");
    for (k, c) in COEFFS.iter().enumerate().take(n + 1) {
        let _ = writeln!(s, "    var a{k} = {c};");
    }
    // Horner's synthetic division by (u − u0), n times: round r leaves a_r final.
    for r in 0..n {
        let steps: Vec<String> = (r..n).rev().map(|j| format!("a{j} = a{j} + u0 * a{};", j + 1)).collect();
        let _ = writeln!(s, "    {}", steps.join(" "));
    }
    s.push_str("    let h = t1 - t0;\n    let h1 = h;\n");
    for k in 2..=n {
        let _ = writeln!(s, "    let h{k} = h{} * h;", k - 1);
    }
    s.push_str("    let c0 = a0;\n");
    for k in 1..=n {
        let _ = writeln!(s, "    let c{k} = a{k} * h{k};");
    }
    s.push_str("    let e0 = a1;\n");
    for k in 1..n {
        let _ = writeln!(s, "    let e{k} = {}.0 * a{} * h{k};", k + 1, k + 1);
    }
    bernstein_rows(&mut s, "b", "c", n);
    bernstein_rows(&mut s, "g", "e", n - 1);
    let fold = |f: &str, v: &str, m: usize| (1..=m).fold(format!("{v}0"), |acc, k| format!("{f}({acc}, {v}{k})"));
    let _ = writeln!(s, "    return vec4<f32>({}, {}, {}, {});\n}}", fold("min", "b", n), fold("max", "b", n), fold("min", "g", n - 1), fold("max", "g", n - 1));
    s
}

/// The Bernstein coefficients `{b}0..{b}m` of the polynomial of degree `m`
/// in u ∈ [0, 1] whose power coefficients are `{c}0..{c}m`:
/// b_k = Σ_{i ≤ k} C(k, i) / C(m, i) · c_i.
fn bernstein_rows(s: &mut String, b: &str, c: &str, m: usize) {
    for k in 0..=m {
        let terms: Vec<String> = (0..=k)
            .map(|i| match bernstein_weight(k, i, m) {
                w if w == 1.0 => format!("{c}{i}"),
                w => format!("{} * {c}{i}", crate::codegen::lit(w)),
            })
            .collect();
        let _ = writeln!(s, "    let {b}{k} = {};", terms.join(" + "));
    }
}

/// C(k, i) / C(m, i) as the f32 nearest the exact ratio: binomials of
/// degree ≤ [`MAX_DEGREE`] are integers exact in f32, and IEEE division
/// rounds their quotient once, to nearest.
fn bernstein_weight(k: usize, i: usize, m: usize) -> f32 {
    binomial(k, i) as f32 / binomial(m, i) as f32
}

fn binomial(n: usize, k: usize) -> u64 {
    (0..k as u64).fold(1, |acc, j| acc * (n as u64 - j) / (j + 1))
}

#[cfg(test)]
mod tests {
    /// Every Bernstein weight written into the WGSL is the f32 nearest
    /// C(k, i) / C(m, i): no f32 neighbour of the literal lies closer to the
    /// exact ratio (the products with the small denominator are exact in f64).
    #[test]
    fn bernstein_weights_are_the_nearest_f32_of_exact_ratios() {
        let wgsl = super::bernstein_functions();
        let mut checked = 0;
        for n in 3..=super::MAX_DEGREE as usize {
            let body = wgsl.split(&format!("fn ray_poly{n}_bern(")).nth(1).expect("a function per degree");
            for (row, m) in [("b", n), ("g", n - 1)] {
                for k in 0..=m {
                    let line = body.lines().find(|l| l.starts_with(&format!("    let {row}{k} = "))).expect("a row per coefficient");
                    let terms: Vec<&str> = line.trim_end_matches(';').split(" = ").nth(1).expect("a value").split(" + ").collect();
                    assert_eq!(terms.len(), k + 1, "{line}");
                    for (i, term) in terms.iter().enumerate() {
                        let (p, q) = (super::binomial(k, i) as f64, super::binomial(m, i) as f64);
                        let w: f32 = term.split_once(" * ").map_or(Ok(1.0), |(w, _)| w.parse()).expect("an f32 literal");
                        let miss = |x: f32| (f64::from(x) * q - p).abs();
                        let (down, up) = (f32::from_bits(w.to_bits() - 1), f32::from_bits(w.to_bits() + 1));
                        assert!(miss(w) <= miss(down) && miss(w) <= miss(up), "{line}: {w} is not the f32 nearest {p}/{q}");
                        assert_eq!(term.contains(" * "), p != q, "{line}: weight 1 is written as the bare coefficient");
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, (3..=6).map(|n| (n + 1) * (n + 2) / 2 + n * (n + 1) / 2).sum::<usize>());
    }
}

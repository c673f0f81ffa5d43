//! Subexpressions of degree at most 2 in x, y, z, restricted to the ray.
//!
//! Along a ray p = p0 + dir·t such a node is a polynomial a + b·t + c·t² in
//! t alone. Its coefficients are worked out once per ray
//! (`field_begin_ray`, which bisection calls as it starts a ray), and a
//! cell [t0, t1] then encloses the node by the polynomial's values at the
//! ends and at its vertex: the exact range over the cell up to rounding,
//! where intervals over the cell's box overestimate it (x² + y² + z² − 1
//! over a box adds up three independent ranges) and recompute every
//! product and sum for every cell. The slope along the ray is b + 2c·t,
//! exact too, and the scalar value at a point of the ray three operations.
//! icos.csg's ten planes |n·p| and its ball, the decocube's three
//! x² + y² − 0.64 and sq.csg's three cylinders are such nodes.
//!
//! Products of squares. A node k·x²·y² (the 4-bretzel's 4x²y², Steiner's
//! x²y²) is k·(xy)², and xy along the ray is a + b·t + c·t² too: its range
//! over the cell squared is k·x²·y²'s exact range, where the product of
//! x²'s and y²'s ranges over the cell's box is not (x and y move together
//! along the ray). Such nodes, k·Q² with Q of degree 2, are taken from the
//! ray through Q's polynomial (the 4-bretzel takes fewer evaluations a
//! pixel).
//!
//! Rounding. The coefficients are computed in f32 from the nodes' f64
//! coefficients rounded to f32; every evaluation on the ray uses those same
//! coefficients, so the cells' enclosures, the slopes and the scalar
//! values are of one polynomial, which differs from the formula's by a few
//! f32 roundings of its largest terms over the ray's extent in the domain.
//! Each enclosure is widened by 32 such roundings (`RAY_PAD` in
//! templates/fields/ray_forms.wgsl). A form is written in powers of p − c
//! about its centre c ([`Quad::centred`]): a translated and scaled square,
//! ((x − 2.6)/0.22)², has terms in powers of p of some 300 where its value
//! is 3, and pads of their roundings wide enough to keep a scaled
//! tanglecube's cells from excluding 0 a hundredth of a unit from its
//! surface. (p − c rounds as p0 does: the ray the forms describe moves by
//! an f32 rounding of |p| + |c|.)

use super::ray_polys;
use crate::codegen::{f32_enclosure, lit};
use crate::ir::{Ir, NodeId, Op, Var};
use std::fmt::Write;

/// The monomials of a form, in this order: 1, x, y, z, x², y², z², xy, xz, yz.
const MONOMIALS: usize = 10;

/// A polynomial of degree at most 2 in x, y, z: its coefficients over
/// [`MONOMIALS`], in f64 (the IR's literals).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Quad([f64; MONOMIALS]);

/// The slot of the product of monomials `i` and `j` (both of degree ≤ 1).
fn product_slot(i: usize, j: usize) -> Option<usize> {
    match (i.min(j), i.max(j)) {
        (0, k) => Some(k),
        (a, b) if a == b => Some(3 + a),
        (1, 2) => Some(7),
        (1, 3) => Some(8),
        (2, 3) => Some(9),
        _ => None,
    }
}

impl Quad {
    fn var(slot: usize) -> Quad {
        let mut c = [0.0; MONOMIALS];
        c[slot] = 1.0;
        Quad(c)
    }

    fn scaled(self, k: f64) -> Quad {
        Quad(self.0.map(|c| c * k))
    }

    fn plus(self, o: Quad, sign: f64) -> Quad {
        Quad(std::array::from_fn(|i| self.0[i] + sign * o.0[i]))
    }

    /// The constant, if the form has no variable.
    pub(crate) fn constant(self) -> Option<f64> {
        (self.0[1..] == [0.0; MONOMIALS - 1]).then_some(self.0[0])
    }

    /// Whether every term is of degree ≤ 1.
    pub(crate) fn linear(self) -> bool {
        self.0[4..] == [0.0; MONOMIALS - 4]
    }

    /// The product of two forms, if its degree is at most 2.
    fn times(self, o: Quad) -> Option<Quad> {
        if let Some(k) = self.constant() {
            return Some(o.scaled(k));
        }
        if let Some(k) = o.constant() {
            return Some(self.scaled(k));
        }
        if !(self.linear() && o.linear()) {
            return None;
        }
        let mut c = [0.0; MONOMIALS];
        for i in 0..4 {
            for j in 0..4 {
                let slot = product_slot(i, j).expect("monomials of degree ≤ 1");
                c[slot] += self.0[i] * o.0[j];
            }
        }
        Some(Quad(c))
    }

    /// Its monomials other than the constant.
    fn terms(self) -> usize {
        self.0[1..].iter().filter(|c| **c != 0.0).count()
    }

    /// Whether it is worth taking from the ray: two or more monomials, or
    /// one product of two variables (xy over the cell's box is the product
    /// of two ranges that move together along the ray; c·x or c·x² alone is
    /// as tight over the box and cheaper).
    fn worth_a_form(self) -> bool {
        self.terms() >= 2 || (self.terms() == 1 && self.0[7..] != [0.0; MONOMIALS - 7])
    }

    /// The form's value and gradient at `c`.
    fn at(self, c: [f64; 3]) -> (f64, [f64; 3]) {
        let [k, bx, by, bz, xx, yy, zz, xy, xz, yz] = self.0;
        let [x, y, z] = c;
        let value = k + bx * x + by * y + bz * z + xx * x * x + yy * y * y + zz * z * z + xy * x * y + xz * x * z + yz * y * z;
        let grad = [bx + 2.0 * xx * x + xy * y + xz * z, by + 2.0 * yy * y + xy * x + yz * z, bz + 2.0 * zz * z + xz * x + yz * y];
        (value, grad)
    }

    /// The form in powers of p − c with c its centre (an f32 point): where
    /// a translated form is small, its terms in powers of p are large and
    /// cancel, ((x − 2.6)/0.22)² is 20.7x² − 107x + 140, and the pads,
    /// which count roundings of the terms' magnitudes, grow with them. The
    /// centre: along each axis with a square, where the square's part of
    /// the form is least; a form of degree 1, the point of its zero plane
    /// nearest the origin. None where that leaves a larger constant term.
    fn centred(self) -> Option<([f32; 3], Quad)> {
        let c: [f64; 3] = if self.linear() {
            let b = [self.0[1], self.0[2], self.0[3]];
            let n = b.iter().map(|v| v * v).sum::<f64>();
            if n == 0.0 {
                return None;
            }
            b.map(|v| -self.0[0] * v / n)
        } else {
            std::array::from_fn(|i| if self.0[4 + i] != 0.0 { -self.0[1 + i] / (2.0 * self.0[4 + i]) } else { 0.0 })
        };
        let c32 = c.map(|v| v as f32);
        if c32 == [0.0; 3] || !c32.iter().all(|v| v.is_finite()) {
            return None;
        }
        let (k, g) = self.at(c32.map(f64::from));
        if !(k.abs() < self.0[0].abs()) {
            return None;
        }
        let mut q = self.0;
        q[0] = k;
        q[1..4].copy_from_slice(&g);
        let q = Quad(q);
        q.0.iter().all(|v| (*v as f32).is_finite()).then_some((c32, q))
    }

    /// The WGSL call that works out (a, b, c) of the form along the line
    /// `p0 + d t` (`ray_lin` or `ray_quad` of templates/fields/ray_forms.wgsl),
    /// in powers of p − its centre where it has one ([`Quad::centred`]).
    pub(crate) fn along(&self, p0: &str, d: &str) -> String {
        match self.centred() {
            Some((c, q)) => q.call(&format!("({p0} - {})", vec3(c)), d, false),
            None => self.call(p0, d, false),
        }
    }

    /// [`Quad::along`] with the coefficients made absolute, at the largest
    /// |p − centre| over `points` (with `d` absolute too): the magnitudes of
    /// the terms [`Quad::along`] computes, from which its pads come.
    pub(crate) fn magnitude_along(&self, points: &[&str], d: &str) -> String {
        let (c, q) = self.centred().map_or((None, *self), |(c, q)| (Some(c), q));
        let at = |p: &str| match c {
            Some(c) => format!("abs({p} - {})", vec3(c)),
            None => format!("abs({p})"),
        };
        let p = points.iter().map(|p| at(p)).reduce(|a, b| format!("max({a}, {b})")).unwrap_or_default();
        q.call(&p, d, true)
    }

    fn call(&self, p0: &str, d: &str, abs: bool) -> String {
        let c = |i: usize| lit(if abs { self.0[i].abs() as f32 } else { self.0[i] as f32 });
        let v = |i: usize| format!("vec3<f32>({}, {}, {})", c(i), c(i + 1), c(i + 2));
        match self.linear() {
            true => format!("ray_lin({}, {}, {p0}, {d})", c(0), v(1)),
            false => format!("ray_quad({}, {}, {}, {}, {p0}, {d})", c(0), v(1), v(4), v(7)),
        }
    }
}

/// An f32 point as a WGSL vector.
fn vec3(c: [f32; 3]) -> String {
    format!("vec3<f32>({}, {}, {})", lit(c[0]), lit(c[1]), lit(c[2]))
}

/// The form of each node (None where it is not a polynomial of degree ≤ 2
/// in x, y, z or a coefficient is not a finite f32).
fn forms(ir: &Ir) -> Vec<Option<Quad>> {
    let mut f: Vec<Option<Quad>> = Vec::with_capacity(ir.nodes.len());
    for op in &ir.nodes {
        let g = |n: &NodeId| f[*n as usize];
        let form = match op {
            Op::Const(c) => Some(Quad([*c, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            Op::Var(Var::X) => Some(Quad::var(1)),
            Op::Var(Var::Y) => Some(Quad::var(2)),
            Op::Var(Var::Z) => Some(Quad::var(3)),
            Op::Neg(a) => g(a).map(|a| a.scaled(-1.0)),
            Op::Add(a, b) => g(a).zip(g(b)).map(|(a, b)| a.plus(b, 1.0)),
            Op::Sub(a, b) => g(a).zip(g(b)).map(|(a, b)| a.plus(b, -1.0)),
            Op::Mul(a, b) => g(a).zip(g(b)).and_then(|(a, b)| a.times(b)),
            Op::PowI(a, 2) => g(a).and_then(|a| a.times(a)),
            Op::Div(a, b) => g(a).zip(g(b).and_then(|b| b.constant())).filter(|(_, k)| *k != 0.0).map(|(a, k)| a.scaled(1.0 / k)),
            _ => None,
        };
        f.push(form.filter(|q| q.0.iter().all(|c| c.is_finite() && (*c as f32).is_finite())));
    }
    f
}

/// Each node as k·Q² with Q a form (None where it is not such a product
/// of squares: a square of a form, a product of two such whose forms
/// multiply to degree ≤ 2, and their multiples by constants).
fn squares(ir: &Ir, f: &[Option<Quad>]) -> Vec<Option<(f64, Quad)>> {
    let mut s: Vec<Option<(f64, Quad)>> = Vec::with_capacity(ir.nodes.len());
    for op in &ir.nodes {
        let g = |n: &NodeId| s[*n as usize];
        let k = |n: &NodeId| f[*n as usize].and_then(Quad::constant);
        let sq = match op {
            Op::PowI(a, 2) => f[*a as usize].map(|q| (1.0, q)),
            Op::Neg(a) => g(a).map(|(c, q)| (-c, q)),
            Op::Mul(a, b) => match (k(a), k(b)) {
                (Some(c), _) => g(b).map(|(d, q)| (c * d, q)),
                (_, Some(c)) => g(a).map(|(d, q)| (c * d, q)),
                _ => g(a).zip(g(b)).and_then(|((c, p), (d, q))| p.times(q).map(|q| (c * d, q))),
            },
            Op::Div(a, b) => g(a).zip(k(b)).filter(|(_, c)| *c != 0.0).map(|((d, q), c)| (d / c, q)),
            _ => None,
        };
        s.push(sq.filter(|(c, q)| c.is_finite() && (*c as f32).is_finite() && *c != 0.0 && q.constant().is_none()));
    }
    s
}

/// A node taken from the ray.
#[derive(Debug, Clone, Copy)]
enum Taken {
    /// Of degree ≤ 2: its form.
    Form(Quad),
    /// k·Q²: k and Q.
    Square(f64, Quad),
    /// A polynomial of degree 3 to 6 ([`ray_polys`]), by its degree.
    Poly(u32),
}

/// The nodes a bisected compiled field takes from the ray
/// ([`ray_nodes`]), with their forms, and the polynomials' part of
/// `field_begin_ray` (declarations, body).
pub(crate) struct RayForms {
    forms: Vec<Option<Taken>>,
    polys: (String, String),
}

/// Most live nodes of a formula whose nodes are taken from the ray. The
/// scalar field on the ray is a second copy of the scalar evaluator
/// (`eval_s_ray`): no longer to compile (it replaces `field(p)` at the
/// traversal's call sites), but more text, and the kernel of a formula of
/// thousands of nodes near the 500 KB limit would cross it (the city with
/// three more copies of its blocks, 2,628 operations, would grow by about
/// a quarter, and `auto` would take the tape). Such formulas are
/// compile-bound; they are written without ray forms.
pub(crate) const MAX_NODES: usize = 1500;

/// The nodes to take from the ray, each the root or used by a node that
/// is evaluated and not taken from the ray itself:
/// - forms of two or more monomials, or of one product of two variables
///   ([`Quad::worth_a_form`]);
/// - products k·Q² of degree > 2 with Q of degree 2 ([`squares`]), other
///   than a square alone: the square of a form taken from the ray is
///   already exact, and of a monomial x² too over the box;
/// - polynomials of degree 3 to 6 whose terms depend on each other
///   ([`ray_polys::worth`]), by their Bernstein coefficients.
///
/// None for a formula of several surfaces (level-set CSG), whose cells
/// have no slope, for one of more than [`MAX_NODES`] live nodes, and where
/// no node qualifies.
///
/// A node a rerolled loop computes (`term_loops::Plan::skips`) is evaluated in
/// the loop, never from the ray: its coefficients would be worked out for
/// every ray and never read.
pub(crate) fn ray_nodes(ir: &Ir) -> Option<RayForms> {
    let plan = super::term_loops::plan(ir);
    nodes_on_ray(ir, |n| plan.skips(n))
}

/// [`ray_nodes`] as the code would take them with every node written out
/// (what `term_loops` asks, to leave such terms written out).
pub(crate) fn written_out_ray_nodes(ir: &Ir) -> Option<RayForms> {
    nodes_on_ray(ir, |_| false)
}

fn nodes_on_ray(ir: &Ir, in_loop: impl Fn(NodeId) -> bool) -> Option<RayForms> {
    let live = ir.live();
    if ir.is_csg() || live.len() > MAX_NODES {
        return None;
    }
    let f = forms(ir);
    let sq = squares(ir, &f);
    let deg = ray_polys::degrees(ir, &f);
    let product = |id: usize| sq[id].filter(|(_, q)| !q.linear() && f[id].is_none() && !matches!(ir.nodes[id], Op::PowI(_, 2)));
    let exact = |id: NodeId| f[id as usize].is_some() || sq[id as usize].is_some();
    let poly = |id: usize| ray_polys::worth(ir, &deg, &exact, id as NodeId);
    // From the root down: a node is evaluated if an evaluated node not taken
    // from the ray uses it, and taken if it is evaluated and qualifies.
    let take = |id: usize| match (f[id], product(id)) {
        (Some(q), _) => q.worth_a_form().then_some(Taken::Form(q)),
        (None, Some((k, q))) => Some(Taken::Square(k, q)),
        (None, None) if poly(id) => deg[id].map(Taken::Poly),
        (None, None) => None,
    };
    let mut evaluated = vec![false; ir.nodes.len()];
    let mut forms: Vec<Option<Taken>> = vec![None; ir.nodes.len()];
    evaluated[ir.root as usize] = true;
    for &id in live.iter().rev() {
        let id = id as usize;
        if !evaluated[id] {
            continue;
        }
        forms[id] = if in_loop(id as NodeId) { None } else { take(id) };
        if forms[id].is_none() {
            for a in ir.nodes[id].operands() {
                evaluated[a as usize] = true;
            }
        }
    }
    let mut polys = (String::new(), String::new());
    let mut writer = ray_polys::Writer::new(ir, &f, &deg);
    for (id, _) in forms.iter().enumerate().filter(|(_, t)| matches!(t, Some(Taken::Poly(_)))) {
        writer.node(id as NodeId, &mut polys.0, &mut polys.1);
    }
    forms.iter().any(Option::is_some).then_some(RayForms { forms, polys })
}

impl RayForms {
    /// Whether it takes a polynomial of degree 3 to 6 from the ray.
    pub(crate) fn has_polynomials(&self) -> bool {
        self.forms.iter().any(|t| matches!(t, Some(Taken::Poly(_))))
    }

    /// Whether node `id` is taken from the ray.
    pub(crate) fn has(&self, id: NodeId) -> bool {
        self.forms.get(id as usize).is_some_and(Option::is_some)
    }

    /// Whether node `id` is taken from the ray in the domain with prefix
    /// `p`. A polynomial of degree 3 to 6 is taken for cells (`ia`) only:
    /// the scalar field at a point computes it from the point, whose
    /// roundings are of its own terms' size, where its coefficients along
    /// the ray carry roundings of the expansion's (up to 100 times the
    /// value on the 4-bretzel's rays); the cells' pads cover the difference.
    pub(crate) fn takes(&self, id: NodeId, p: &str) -> bool {
        match self.forms.get(id as usize) {
            Some(Some(Taken::Poly(_))) => p == "ia",
            Some(Some(_)) => true,
            _ => false,
        }
    }

    /// The value of node `id` in the domain with prefix `p` (`s` or `ia`)
    /// at `args` (`tr`: the ray parameter from the ray's start; `t0, t1`: a cell's).
    pub(crate) fn rhs(&self, id: NodeId, p: &str, args: &str) -> String {
        match self.forms[id as usize].expect("a node taken from the ray") {
            Taken::Square(k, _) => format!("{p}_ray_sq({}, g_q{id}, g_qv{id}, {args})", factor(k, p == "ia")),
            Taken::Form(q) => format!("{p}_ray{}(g_q{id}, g_qv{id}, {args})", if q.linear() { "_lin" } else { "" }),
            Taken::Poly(n) => format!("ia_ray_poly({}, g_pb{id}, g_pm{id}, g_pn{id}, {args})", bern(n, id, args)),
        }
    }

    /// The slope along the ray of node `id` over the cell `t0, t1`.
    pub(crate) fn slope(&self, id: NodeId) -> String {
        match self.forms[id as usize].expect("a node taken from the ray") {
            Taken::Square(k, _) => format!("ia_ray_sq_slope({}, g_q{id}, g_qv{id}, t0, t1)", factor(k, true)),
            Taken::Form(q) => format!("ia_ray_slope{}(g_q{id}, g_qv{id}, t0, t1)", if q.linear() { "_lin" } else { "" }),
            Taken::Poly(n) => format!("ia_ray_poly_slope({}, g_pb{id}, g_pm{id}, g_pn{id}, t0, t1)", bern(n, id, "t0, t1")),
        }
    }

    /// The per-ray state (`g_q{id}`: a, b, c and the value's pad; `g_qv{id}`:
    /// the slope's pad, then the vertex and the value there, or for a node
    /// of degree 1 its slope's enclosure) and
    /// `field_begin_ray`, which works it out for a ray o + dir·s from
    /// s = s_ref over a length `len`.
    pub(crate) fn setup(&self) -> String {
        let mut out = String::from("var<private> g_ray_ref: f32;\n");
        let mut body = String::new();
        let quads = self.forms.iter().enumerate().filter_map(|(i, t)| match t {
            Some(Taken::Form(q) | Taken::Square(_, q)) => Some((i, *q)),
            _ => None,
        });
        for (id, q) in quads {
            let _ = writeln!(out, "var<private> g_q{id}: vec4<f32>;\nvar<private> g_qv{id}: vec3<f32>;");
            let _ = writeln!(body, "    let q{id} = {};\n    let m{id} = {};", q.along("p0", "dir"), q.magnitude_along(&["p0", "p1"], "ad"));
            let _ = writeln!(body, "    g_q{id} = vec4<f32>(q{id}, RAY_PAD * (m{id}.x + len * (m{id}.y + len * m{id}.z)));");
            // The vertex, or for a node of degree 1 its slope (b ± pad).
            let _ = writeln!(body, "    let e{id} = RAY_PAD * (m{id}.y + 2.0 * len * m{id}.z);");
            let rest = if q.linear() { format!("q{id}.y - e{id}, q{id}.y + e{id}") } else { format!("ray_vertex(q{id})") };
            let _ = writeln!(body, "    g_qv{id} = vec3<f32>(e{id}, {rest});");
        }
        let (decls, polys) = &self.polys;
        let mid = match polys.is_empty() {
            true => "",
            false => "    g_poly_mid = 0.5 * len;\n    let pm = p0 + dir * g_poly_mid;\n",
        };
        let template = match polys.is_empty() {
            true => include_str!("../../../templates/fields/ray_forms.wgsl").to_string(),
            false => [include_str!("../../../templates/fields/ray_forms.wgsl"), include_str!("../../../templates/fields/ray_polys.wgsl")].join("\n") + &ray_polys::bernstein_functions(),
        };
        let _ = write!(
            out,
            "{decls}{template}\nfn field_begin_ray(o: vec3<f32>, dir: vec3<f32>, s_ref: f32, len: f32) {{\n    \
             let p0 = o + dir * s_ref;\n    let p1 = p0 + dir * len;\n    let ad = abs(dir);\n    g_ray_ref = s_ref;\n{body}{mid}{polys}}}\n"
        );
        out
    }
}

/// The Bernstein bounds over the cell `args` of polynomial node `id` of
/// degree `n` (value and slope: one call after inlining, shared by both).
fn bern(n: u32, id: NodeId, args: &str) -> String {
    format!("ray_poly{n}_bern(g_pa{id}, g_pb{id}, {args})")
}

/// The factor k of k·Q² in WGSL: its f32 enclosure for intervals, else
/// the nearest f32.
fn factor(k: f64, interval: bool) -> String {
    let (n, lo, hi) = f32_enclosure(k);
    if interval { format!("vec2<f32>({}, {})", lit(lo), lit(hi)) } else { lit(n) }
}

/// The hooks of a compiled field without ray forms: the scalar field at a
/// point of the ray is the field at that point.
pub(crate) const NO_RAY_FORMS: &str = "fn field_begin_ray(o: vec3<f32>, dir: vec3<f32>, s_ref: f32, len: f32) {}\n\
    fn field_ray(o: vec3<f32>, dir: vec3<f32>, s: f32) -> f32 { return field(o + dir * s); }\n";

//! Which nodes are monomials c·x^a·y^b·z^c: a constant times powers of the
//! space variables (through products, negations, integer powers and
//! divisions by a constant). The semantic pass collects like monomials of
//! a sum; the compiled field computes a long sum of unlike ones in one loop.

use crate::ir::{Ir, NodeId, Op, Var};

/// c · x^exps[0] · y^exps[1] · z^exps[2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Monomial {
    /// The coefficient, folded in f64 as the semantic pass folds constants.
    pub coef: f64,
    /// The powers of x, y and z.
    pub exps: [u32; 3],
}

/// Each live node's monomial form, where it is one with a finite f32
/// coefficient and every power at most `max_exponent`.
pub fn monomials(ir: &Ir, live: &[NodeId], max_exponent: u32) -> Vec<Option<Monomial>> {
    let mut m: Vec<Option<Monomial>> = vec![None; ir.nodes.len()];
    for &n in live {
        let g = |a: NodeId| m[a as usize];
        let mono = match ir.nodes[n as usize] {
            Op::Const(c) => Some(Monomial { coef: c, exps: [0; 3] }),
            Op::Var(v @ (Var::X | Var::Y | Var::Z)) => {
                let mut exps = [0; 3];
                exps[v as usize] = 1;
                Some(Monomial { coef: 1.0, exps })
            }
            Op::Neg(a) => g(a).map(|a| Monomial { coef: -a.coef, ..a }),
            Op::Mul(a, b) => g(a).zip(g(b)).map(|(a, b)| Monomial { coef: a.coef * b.coef, exps: [0, 1, 2].map(|i| a.exps[i] + b.exps[i]) }),
            Op::PowI(a, k) => g(a).map(|a| Monomial { coef: a.coef.powi(k.min(i32::MAX as u32) as i32), exps: a.exps.map(|e| e.saturating_mul(k)) }),
            Op::Div(a, b) => g(a).zip(g(b)).filter(|(_, b)| b.exps == [0; 3] && b.coef != 0.0).map(|(a, b)| Monomial { coef: a.coef / b.coef, ..a }),
            _ => None,
        };
        m[n as usize] = mono.filter(|x| x.coef.is_finite() && (x.coef as f32).is_finite() && x.exps.iter().all(|&e| e <= max_exponent));
    }
    m
}

/// A polynomial in x, y, z: its monomials' coefficients by their powers
/// packed five bits each (x lowest), in increasing order, none zero.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Polynomial {
    /// (packed powers, coefficient).
    pub terms: Vec<(u16, f64)>,
}

/// The largest power [`Polynomial`] packs (five bits): the largest the
/// Horner loops' run-time power takes.
pub const POLYNOMIAL_MAX_EXPONENT: u32 = crate::ir::POWN_MAX_EXPONENT;

impl Polynomial {
    fn monomial(m: Monomial) -> Option<Polynomial> {
        if m.exps.iter().any(|&e| e > POLYNOMIAL_MAX_EXPONENT) {
            return None;
        }
        let terms = if m.coef == 0.0 { vec![] } else { vec![(pack(m.exps), m.coef)] };
        Some(Polynomial { terms })
    }
    /// The monomials.
    pub fn monomials(&self) -> impl Iterator<Item = Monomial> + '_ {
        self.terms.iter().map(|&(k, coef)| Monomial { coef, exps: unpack(k) })
    }
    /// `self + sign·other`.
    pub fn add(&self, other: &Polynomial, sign: f64) -> Polynomial {
        let (a, b) = (&self.terms, &other.terms);
        let (mut i, mut j) = (0, 0);
        let mut terms = Vec::with_capacity(a.len() + b.len());
        while i < a.len() || j < b.len() {
            let (k, c) = match (a.get(i), b.get(j)) {
                (Some(&(ka, ca)), Some(&(kb, cb))) if ka == kb => {
                    (i, j) = (i + 1, j + 1);
                    (ka, ca + sign * cb)
                }
                (Some(&(ka, ca)), Some(&(kb, _))) if ka < kb => {
                    i += 1;
                    (ka, ca)
                }
                (Some(&(ka, ca)), None) => {
                    i += 1;
                    (ka, ca)
                }
                (_, Some(&(kb, cb))) => {
                    j += 1;
                    (kb, sign * cb)
                }
                (None, None) => unreachable!("the loop runs while one is left"),
            };
            if c != 0.0 {
                terms.push((k, c));
            }
        }
        Polynomial { terms }
    }
    /// `self · m`, `None` past the largest power.
    fn times(&self, m: Monomial) -> Option<Polynomial> {
        let mut terms = Vec::with_capacity(self.terms.len());
        for &(k, c) in &self.terms {
            let e = unpack(k);
            let exps = [0, 1, 2].map(|i| e[i] + m.exps[i]);
            if exps.iter().any(|&x| x > POLYNOMIAL_MAX_EXPONENT) {
                return None;
            }
            let coef = c * m.coef;
            if coef != 0.0 {
                terms.push((pack(exps), coef));
            }
        }
        Some(Polynomial { terms })
    }
    /// The one monomial, if it is one (or zero).
    fn single(&self) -> Option<Monomial> {
        match self.terms[..] {
            [] => Some(Monomial { coef: 0.0, exps: [0; 3] }),
            [(k, coef)] => Some(Monomial { coef, exps: unpack(k) }),
            _ => None,
        }
    }
}

fn pack(e: [u32; 3]) -> u16 {
    (e[0] | e[1] << 5 | e[2] << 10) as u16
}

fn unpack(k: u16) -> [u32; 3] {
    let k = u32::from(k);
    [k & 31, k >> 5 & 31, k >> 10 & 31]
}

/// Each live node's expansion, where it is a sum of monomials times
/// monomials: products and powers only of single monomials (a Horner form
/// or a sum written term by term, never a product of two sums, whose
/// expansion would hold more terms than the formula has operations), with
/// powers up to [`POLYNOMIAL_MAX_EXPONENT`] and finite f32 coefficients.
/// The expansions together hold at most `budget` monomials; past it the
/// remaining nodes have none.
pub fn polynomials(ir: &Ir, live: &[NodeId], mut budget: usize) -> Vec<Option<Polynomial>> {
    let monos = monomials(ir, live, POLYNOMIAL_MAX_EXPONENT);
    let mut p: Vec<Option<Polynomial>> = vec![None; ir.nodes.len()];
    for &n in live {
        let g = |a: NodeId| p[a as usize].as_ref();
        let poly = match (monos[n as usize], ir.nodes[n as usize]) {
            (Some(m), _) => Polynomial::monomial(m),
            (None, Op::Add(a, b)) => g(a).zip(g(b)).map(|(a, b)| a.add(b, 1.0)),
            (None, Op::Sub(a, b)) => g(a).zip(g(b)).map(|(a, b)| a.add(b, -1.0)),
            (None, Op::Neg(a)) => g(a).map(|a| Polynomial::default().add(a, -1.0)),
            (None, Op::Mul(a, b)) => match (g(a), g(b)) {
                (Some(a), Some(b)) => match (a.single(), b.single()) {
                    (_, Some(m)) => a.times(m),
                    (Some(m), _) => b.times(m),
                    _ => None,
                },
                _ => None,
            },
            (None, Op::Div(a, b)) => match (g(a), monos[b as usize]) {
                (Some(a), Some(d)) if d.exps == [0; 3] && d.coef != 0.0 => a.times(Monomial { coef: 1.0 / d.coef, exps: [0; 3] }),
                _ => None,
            },
            _ => None,
        }
        .filter(|q| q.terms.len() <= budget && q.terms.iter().all(|&(_, c)| c.is_finite() && (c as f32).is_finite()));
        if let Some(q) = &poly {
            budget -= q.terms.len();
        }
        p[n as usize] = poly;
    }
    p
}

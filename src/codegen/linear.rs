//! Subexpressions affine in x, y, z, found so that a cell's enclosure can
//! take them from the segment's ends ([`super::emit_body_on`]).

use crate::ir::{Ir, NodeId, Op, Var};

/// c0 + cx x + cy y + cz z, in f64 (the IR's literals).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Linear([f64; 4]);

impl Linear {
    fn scaled(self, k: f64) -> Linear {
        Linear(self.0.map(|c| c * k))
    }

    fn plus(self, o: Linear, sign: f64) -> Linear {
        Linear([0, 1, 2, 3].map(|i| self.0[i] + sign * o.0[i]))
    }

    /// The constant, if the form has no variable.
    fn constant(self) -> Option<f64> {
        (self.0[1..] == [0.0; 3]).then_some(self.0[0])
    }

    fn variables(self) -> usize {
        self.0[1..].iter().filter(|c| **c != 0.0).count()
    }

    /// The WGSL enclosure over the segment from `a` to `b`.
    pub(crate) fn segment_rhs(&self, a: &str, b: &str) -> String {
        let l = |c: f64| super::lit(c as f32);
        let [c0, cx, cy, cz] = self.0;
        format!("ia_seg({}, vec3<f32>({}, {}, {}), {a}, {b})", l(c0), l(cx), l(cy), l(cz))
    }
}

/// The affine form of each node (None where it is not affine in x, y, z
/// or a coefficient is not a finite f32).
fn forms(ir: &Ir) -> Vec<Option<Linear>> {
    let mut f: Vec<Option<Linear>> = Vec::with_capacity(ir.nodes.len());
    for op in &ir.nodes {
        let g = |n: &NodeId| f[*n as usize];
        let form = match op {
            Op::Const(c) => Some(Linear([*c, 0.0, 0.0, 0.0])),
            Op::Var(Var::X) => Some(Linear([0.0, 1.0, 0.0, 0.0])),
            Op::Var(Var::Y) => Some(Linear([0.0, 0.0, 1.0, 0.0])),
            Op::Var(Var::Z) => Some(Linear([0.0, 0.0, 0.0, 1.0])),
            Op::Neg(a) => g(a).map(|a| a.scaled(-1.0)),
            Op::Add(a, b) => g(a).zip(g(b)).map(|(a, b)| a.plus(b, 1.0)),
            Op::Sub(a, b) => g(a).zip(g(b)).map(|(a, b)| a.plus(b, -1.0)),
            Op::Mul(a, b) => match (g(a), g(b)) {
                (Some(a), Some(b)) => match (a.constant(), b.constant()) {
                    (Some(k), _) => Some(b.scaled(k)),
                    (_, Some(k)) => Some(a.scaled(k)),
                    _ => None,
                },
                _ => None,
            },
            Op::Div(a, b) => g(a).zip(g(b).and_then(|b| b.constant())).filter(|(_, k)| *k != 0.0).map(|(a, k)| a.scaled(1.0 / k)),
            _ => None,
        };
        f.push(form.filter(|l| l.0.iter().all(|c| c.is_finite() && (*c as f32).is_finite())));
    }
    f
}

/// The nodes to enclose from a segment's ends: affine in two or more of
/// x, y, z (in one, the segment's box is as tight) and used by a live node
/// that is not affine, or a surface itself.
pub(crate) fn segment_nodes(ir: &Ir) -> Vec<Option<Linear>> {
    let f = forms(ir);
    let mut wanted = vec![false; ir.nodes.len()];
    for id in ir.live() {
        if f[id as usize].is_none() {
            for a in ir.nodes[id as usize].operands() {
                wanted[a as usize] = true;
            }
        }
    }
    wanted[ir.root as usize] = true;
    for s in &ir.surfaces {
        wanted[s.f as usize] = true;
    }
    f.into_iter().zip(wanted).map(|(l, w)| l.filter(|l| w && l.variables() >= 2)).collect()
}

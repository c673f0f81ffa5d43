//! Sums that mix many monomials with other terms (`sin(x) + 0.3*x^5*y +
//! …`, written term by term): the monomials are gathered into one sum after
//! the other terms, a polynomial node of their own, which the plan computes
//! as a Horner loop ([`super::horner`]). A sum made only of monomials, or a
//! Horner form the semantic pass wrote, is such a node already.

use super::super::balance::{chain, interior_nodes};
use super::horner::{EXPANSION_BUDGET, MIN_MONOMIALS};
use crate::analysis::monomials::{polynomials, Monomial, Polynomial};
use crate::ir::{Ir, NodeId, Op, Var};

/// A sum to write again: its terms that are not polynomials (as written,
/// with their signs) and the expansion of the others.
struct Rewrite {
    others: Vec<(NodeId, bool)>,
    poly: Polynomial,
}

/// `ir` with its long sums of monomials rewritten, or `None` when it has
/// none.
pub(crate) fn monomial_sums(ir: &Ir) -> Option<Ir> {
    let live = ir.live();
    let rewrites = find(ir, &live);
    if rewrites.iter().all(Option::is_none) {
        return None;
    }
    let mut out = Ir { nodes: vec![], spans: vec![], root: 0, surfaces: ir.surfaces.clone(), params: ir.params.clone(), externs: ir.externs.clone() };
    // One node a variable, which every rewritten monomial reads.
    let span = ir.spans[ir.root as usize];
    for v in [Var::X, Var::Y, Var::Z] {
        out.nodes.push(Op::Var(v));
        out.spans.push(span);
    }
    let mut map = vec![NodeId::MAX; ir.nodes.len()];
    for &n in &live {
        let span = ir.spans[n as usize];
        let mut push = |op: Op| {
            out.nodes.push(op);
            out.spans.push(span);
            (out.nodes.len() - 1) as NodeId
        };
        map[n as usize] = match (&rewrites[n as usize], ir.nodes[n as usize]) {
            (None, Op::Var(v @ (Var::X | Var::Y | Var::Z))) => v as NodeId,
            (None, op) => push(op.with_operands(|o| map[o as usize])),
            (Some(r), _) => {
                let written: Vec<(NodeId, bool)> = r.others.iter().map(|&(t, plus)| (map[t as usize], plus)).collect();
                let monos: Vec<(NodeId, bool)> = r.poly.monomials().map(|m| (written_out(&mut push, m), true)).collect();
                let poly = sum(&mut push, monos.into_iter());
                sum(&mut push, written.into_iter().chain([(poly, true)]))
            }
        };
    }
    out.root = map[ir.root as usize];
    for s in &mut out.surfaces {
        s.f = map[s.f as usize];
        for c in &mut s.conditions {
            c.0 = map[c.0 as usize];
        }
    }
    Some(compact(&out))
}

/// The sums to rewrite, outermost first: those with terms that are not
/// polynomials and others whose expansion together holds
/// [`MIN_MONOMIALS`] monomials or more. Nodes inside a rewritten one are
/// not candidates.
fn find(ir: &Ir, live: &[NodeId]) -> Vec<Option<Rewrite>> {
    let polys = polynomials(ir, live, EXPANSION_BUDGET);
    let interior = interior_nodes(ir, live);
    let mut covered = vec![false; ir.nodes.len()];
    let mut rewrites: Vec<Option<Rewrite>> = (0..ir.nodes.len()).map(|_| None).collect();
    for &n in live.iter().rev() {
        if covered[n as usize] {
            continue;
        }
        let sum_head = matches!(ir.nodes[n as usize], Op::Add(..) | Op::Sub(..)) && !interior[n as usize];
        if !sum_head {
            continue;
        }
        let (terms, others): (Vec<_>, Vec<_>) = chain(ir, &interior, n).0.into_iter().partition(|&(t, _)| polys[t as usize].is_some());
        if others.is_empty() {
            continue;
        }
        let poly = terms.iter().fold(Polynomial::default(), |acc, &(t, plus)| acc.add(polys[t as usize].as_ref().expect("a polynomial term"), if plus { 1.0 } else { -1.0 }));
        if poly.terms.len() < MIN_MONOMIALS {
            continue;
        }
        let mut stack: Vec<NodeId> = terms.iter().map(|&(t, _)| t).collect();
        while let Some(m) = stack.pop() {
            if !std::mem::replace(&mut covered[m as usize], true) {
                stack.extend(ir.nodes[m as usize].operands());
            }
        }
        rewrites[n as usize] = Some(Rewrite { others, poly });
    }
    rewrites
}

/// `m` as c · x^a · y^b · z^c with its variables' nodes.
fn written_out(push: &mut impl FnMut(Op) -> NodeId, m: Monomial) -> NodeId {
    let mut acc = push(Op::Const(m.coef));
    for (v, &e) in m.exps.iter().enumerate().filter(|&(_, &e)| e > 0) {
        let factor = if e == 1 { v as NodeId } else { push(Op::PowI(v as NodeId, e)) };
        acc = push(Op::Mul(acc, factor));
    }
    acc
}

/// The left-deep sum of `terms` (node, added), in order.
fn sum(push: &mut impl FnMut(Op) -> NodeId, terms: impl Iterator<Item = (NodeId, bool)>) -> NodeId {
    let mut acc: Option<NodeId> = None;
    for (t, plus) in terms {
        acc = Some(match (acc, plus) {
            (None, true) => t,
            (None, false) => push(Op::Neg(t)),
            (Some(a), true) => push(Op::Add(a, t)),
            (Some(a), false) => push(Op::Sub(a, t)),
        });
    }
    acc.expect("a sum has terms")
}

/// `ir` without the nodes no output reads (the rewritten terms' old nodes).
fn compact(ir: &Ir) -> Ir {
    let live = ir.live();
    let mut map = vec![NodeId::MAX; ir.nodes.len()];
    let mut out = Ir { nodes: Vec::with_capacity(live.len()), spans: Vec::with_capacity(live.len()), root: 0, surfaces: ir.surfaces.clone(), params: ir.params.clone(), externs: ir.externs.clone() };
    for &n in &live {
        out.nodes.push(ir.nodes[n as usize].with_operands(|o| map[o as usize]));
        out.spans.push(ir.spans[n as usize]);
        map[n as usize] = (out.nodes.len() - 1) as NodeId;
    }
    out.root = map[ir.root as usize];
    for s in &mut out.surfaces {
        s.f = map[s.f as usize];
        for c in &mut s.conditions {
            c.0 = map[c.0 as usize];
        }
    }
    out
}


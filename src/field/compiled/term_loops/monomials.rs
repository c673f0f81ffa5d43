//! Long sums of unlike monomials as one run. A program that writes a
//! polynomial term by term (`0.004*x^3*y^7*z^2 + …`) gives every term its
//! own powers, so no two neighbours have one shape and no run forms: 2,800
//! such terms, written out, are a kernel lavapipe builds for minutes, and
//! as a tape a frame of minutes. Here every monomial of degree 3 or more
//! in such a sum is written `c · pown(x, a) · pown(y, b) · pown(z, e)`
//! ([`Func2::PowN`]), one shape whatever its powers, after the sum's other
//! terms: the run finder ([`super::plan`]) makes them a loop whose table
//! holds each term's coefficient and exponents.
//!
//! Terms of degree 2 or less stay as written: the compiled field takes
//! such nodes whole from the ray (`ray_forms`), exactly. Each rewritten
//! term encloses what the written term does: c·x^a·y^b·z^e, the powers by
//! the same rules (the even-power rule on a square, an odd power's ends
//! raised), a power of 0 as 1. The sum is an inclusion in whatever order
//! its terms come.

use super::super::balance::{chain, interior_nodes};
use crate::analysis::monomials::{polynomials, Monomial, Polynomial};
use crate::ir::{Func2, Ir, NodeId, Op, Var};

/// Fewest monomials of degree 3 or more in one rewritten sum: below it the
/// written-out terms build soon enough, and each keeps its own powers'
/// code.
pub const MIN_MONOMIALS: usize = 64;

/// Lowest degree rewritten ([`ray_forms`](super::super::ray_forms) takes
/// lower ones from the ray).
const MIN_DEGREE: u32 = 3;

/// Most monomials the expansions of all nodes hold together (a Horner
/// form's nodes each hold the monomials below them).
const EXPANSION_BUDGET: usize = 1 << 21;

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
    // One node a variable: the terms' shapes name their inputs by node.
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
                let (low, high): (Vec<Monomial>, Vec<Monomial>) = r.poly.monomials().partition(|m| m.degree() < MIN_DEGREE);
                let vars = variables(&high);
                let low = low.into_iter().map(|m| (written_out(&mut push, m), true)).collect::<Vec<_>>();
                let high = high.into_iter().map(|m| (term(&mut push, m, &vars), true)).collect::<Vec<_>>();
                sum(&mut push, written.into_iter().chain(low).chain(high))
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

/// The sums to rewrite, outermost first: each sum's polynomial terms
/// expanded together, where they hold [`MIN_MONOMIALS`] of degree 3 or
/// more; and a polynomial no polynomial uses (a Horner form under a
/// product), where it does. Nodes inside a rewritten one are not
/// candidates.
fn find(ir: &Ir, live: &[NodeId]) -> Vec<Option<Rewrite>> {
    let polys = polynomials(ir, live, EXPANSION_BUDGET);
    let interior = interior_nodes(ir, live);
    let mut top = vec![false; ir.nodes.len()];
    top[ir.root as usize] = true;
    for s in &ir.surfaces {
        top[s.f as usize] = true;
        for &(g, _) in &s.conditions {
            top[g as usize] = true;
        }
    }
    for &n in live {
        if polys[n as usize].is_none() {
            for o in ir.nodes[n as usize].operands() {
                top[o as usize] = true;
            }
        }
    }
    let mut covered = vec![false; ir.nodes.len()];
    let mut rewrites: Vec<Option<Rewrite>> = (0..ir.nodes.len()).map(|_| None).collect();
    for &n in live.iter().rev() {
        if covered[n as usize] {
            continue;
        }
        let sum_head = matches!(ir.nodes[n as usize], Op::Add(..) | Op::Sub(..)) && !interior[n as usize];
        let (terms, others) = match sum_head {
            true => chain(ir, &interior, n).0.into_iter().partition(|&(t, _)| polys[t as usize].is_some()),
            false if top[n as usize] && polys[n as usize].is_some() => (vec![(n, true)], vec![]),
            false => continue,
        };
        let poly = terms.iter().fold(Polynomial::default(), |acc, &(t, plus)| acc.add(polys[t as usize].as_ref().expect("a polynomial term"), if plus { 1.0 } else { -1.0 }));
        if poly.monomials().filter(|m| m.degree() >= MIN_DEGREE).count() < MIN_MONOMIALS {
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

/// `m` (degree below [`MIN_DEGREE`]) as the semantic pass writes it:
/// c · x^a · y^b · z^c with its variables' nodes.
fn written_out(push: &mut impl FnMut(Op) -> NodeId, m: Monomial) -> NodeId {
    let mut acc = push(Op::Const(m.coef));
    for (v, &e) in m.exps.iter().enumerate().filter(|&(_, &e)| e > 0) {
        let factor = if e == 1 { v as NodeId } else { push(Op::PowI(v as NodeId, e)) };
        acc = push(Op::Mul(acc, factor));
    }
    acc
}

/// The variables any of `monos` raises to a power (each rewritten term
/// takes all of them, so that every term has one shape).
fn variables(monos: &[Monomial]) -> Vec<Var> {
    let mut used = [false; 3];
    for m in monos {
        for (u, &e) in used.iter_mut().zip(&m.exps) {
            *u |= e > 0;
        }
    }
    [Var::X, Var::Y, Var::Z].into_iter().zip(used).filter(|&(_, u)| u).map(|(v, _)| v).collect()
}

/// `m` as `c · pown(v₁, e₁) · pown(v₂, e₂) · …` over `vars`, every node
/// but the variables its own (a shared power would make the terms differ
/// in shape).
fn term(push: &mut impl FnMut(Op) -> NodeId, m: Monomial, vars: &[Var]) -> NodeId {
    let mut acc = push(Op::Const(m.coef));
    for &v in vars {
        let k = push(Op::Const(f64::from(m.exps[v as usize])));
        let power = push(Op::Call2(Func2::PowN, v as NodeId, k));
        acc = push(Op::Mul(acc, power));
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


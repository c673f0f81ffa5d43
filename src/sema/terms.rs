//! Like terms collected: in a sum (a tree of `+`, `−` and negations), the
//! monomials c·x^a·y^b·z^c of the same powers become one term with the sum
//! of their coefficients.
//!
//! Why: a long sum of monomials of small degree has few distinct ones (a,
//! b, c below 7: at most 343), and written out it is a formula of thousands
//! of operations whose compiled kernel lavapipe builds for minutes and whose
//! tape runs for tens of seconds a frame. Collected, it is a few hundred
//! terms. Enclosures stay enclosures of the same function, and are never
//! wider: c₁·M + c₂·M ⊇ (c₁ + c₂)·M in interval and affine arithmetic
//! (subdistributivity), much narrower where coefficients cancel. The
//! coefficients are summed in f64, as the semantic pass folds constants.

use super::{Builder, SemaError};
use crate::diag::Span;
use crate::analysis::monomials::{monomials, Monomial};
use crate::ir::{Func2, Ir, NodeId, Op, SurfaceIr, Var};
use std::collections::HashMap;

/// Nodes the flattening of all sums may visit: a DAG of shared sums can
/// stand for exponentially many terms, and a chain of n partial sums each
/// used elsewhere (`sin(a₁) + sin(a₂) + …`, aᵢ = aᵢ₋₁ + x) for n²/2. Past
/// it the remaining sums are left as written (2,200 such partial sums, 62
/// KB of formula: `isotrace wgsl` in 0.16 s here).
const VISIT_BUDGET: usize = 1 << 20;

/// Passes of [`collect_once`] at most: each can make constants that an
/// enclosing sum collects in the next (`x + 2 + pow(x, y - y)`: the power
/// becomes 1, then 2 + 1 is 3), one level of such nesting a pass.
const MAX_PASSES: usize = 8;

/// The IR with the like terms of every sum collected, repeated while a
/// pass collects something (up to [`MAX_PASSES`]), so that the result is
/// what the same formula written out collected would give.
pub(super) fn collect(mut ir: Ir) -> Result<Ir, SemaError> {
    for _ in 0..MAX_PASSES {
        match collect_once(&ir)? {
            Some(next) => ir = next,
            None => break,
        }
    }
    Ok(ir)
}

/// The IR with the like terms of every sum collected; None when no sum has
/// two monomials of the same powers. The nodes are pushed again through the
/// semantic pass's builder, so what a collection makes constant is folded
/// as it would have been if written so (a power whose exponent cancelled
/// to 0 is 1).
fn collect_once(ir: &Ir) -> Result<Option<Ir>, SemaError> {
    let live = ir.live();
    let monos = monomials(ir, &live, super::MAX_EXPONENT);
    let roots = sum_roots(ir, &live);
    let mut budget = VISIT_BUDGET;
    let plans: HashMap<NodeId, Vec<Term>> = roots.iter().filter_map(|&r| plan(ir, &monos, r, &mut budget).map(|p| (r, p))).collect();
    if plans.is_empty() {
        return Ok(None);
    }
    let mut b = Builder { params: ir.params.clone(), externs: ir.externs.clone(), ..Builder::default() };
    let mut new_id = vec![NodeId::MAX; ir.nodes.len()];
    for &n in &live {
        let span = ir.spans[n as usize];
        new_id[n as usize] = match plans.get(&n) {
            Some(terms) => sum(&mut b, terms, &new_id, span)?,
            None => match ir.nodes[n as usize].with_operands(|o| new_id[o as usize]) {
                Op::Call2(Func2::Pow, a, e) => b.pow_nodes(a, e, span, span)?,
                op => b.push(op, span)?,
            },
        };
    }
    let surfaces = ir
        .surfaces
        .iter()
        .map(|s| SurfaceIr { f: new_id[s.f as usize], conditions: s.conditions.iter().map(|&(g, less)| (new_id[g as usize], less)).collect() })
        .collect();
    Ok(Some(Ir { nodes: b.nodes, spans: b.spans, root: new_id[ir.root as usize], surfaces, params: b.params, externs: b.externs }))
}

/// Sums that are not themselves a term of a sum: `+` and `−` nodes used
/// by anything but `+`, `−` and negation, or drawn.
fn sum_roots(ir: &Ir, live: &[NodeId]) -> Vec<NodeId> {
    let sumlike = |op: &Op| matches!(op, Op::Add(..) | Op::Sub(..) | Op::Neg(_));
    let mut root = vec![false; ir.nodes.len()];
    for s in &ir.surfaces {
        root[s.f as usize] = true;
        for &(g, _) in &s.conditions {
            root[g as usize] = true;
        }
    }
    for &n in live {
        let op = ir.nodes[n as usize];
        if !sumlike(&op) {
            for a in op.operands() {
                root[a as usize] = true;
            }
        }
    }
    live.iter().copied().filter(|&n| root[n as usize] && matches!(ir.nodes[n as usize], Op::Add(..) | Op::Sub(..))).collect()
}

/// A term of a collected sum.
#[derive(Debug, Clone, Copy)]
enum Term {
    /// An original node, added (true) or subtracted.
    Node(NodeId, bool),
    /// A collected monomial.
    Mono(Monomial),
}

/// The collected terms of sum `root`, in the order of their first
/// appearance; `None` when no two of its monomials have the same powers
/// (or flattening it would pass what is left of `budget`).
fn plan(ir: &Ir, monos: &[Option<Monomial>], root: NodeId, budget: &mut usize) -> Option<Vec<Term>> {
    let mut terms: Vec<Term> = Vec::new();
    let mut slot: HashMap<[u32; 3], usize> = HashMap::new();
    let mut collided = false;
    let mut stack = vec![(root, true)];
    while let Some((n, plus)) = stack.pop() {
        if *budget == 0 {
            return None;
        }
        *budget -= 1;
        match ir.nodes[n as usize] {
            // Pushed right first: terms come off in the written order.
            Op::Add(a, b) => stack.extend([(b, plus), (a, plus)]),
            Op::Sub(a, b) => stack.extend([(b, !plus), (a, plus)]),
            Op::Neg(a) => stack.push((a, !plus)),
            _ => match monos[n as usize] {
                Some(m) => {
                    let coef = if plus { m.coef } else { -m.coef };
                    match slot.get(&m.exps) {
                        Some(&i) => {
                            collided = true;
                            if let Term::Mono(t) = &mut terms[i] {
                                t.coef += coef;
                            }
                        }
                        None => {
                            slot.insert(m.exps, terms.len());
                            terms.push(Term::Mono(Monomial { coef, exps: m.exps }));
                        }
                    }
                }
                None => terms.push(Term::Node(n, plus)),
            },
        }
    }
    let finite = terms.iter().all(|t| !matches!(t, Term::Mono(m) if !(m.coef.is_finite() && (m.coef as f32).is_finite())));
    (collided && finite).then_some(terms)
}

/// x^a · y^b · z^c as the semantic pass writes powers (None for the
/// constant monomial).
fn powers(b: &mut Builder, exps: [u32; 3], span: Span) -> Result<Option<NodeId>, SemaError> {
    let mut acc: Option<NodeId> = None;
    for (v, &e) in [Var::X, Var::Y, Var::Z].iter().zip(&exps) {
        if e == 0 {
            continue;
        }
        let var = b.push(Op::Var(*v), span)?;
        let p = b.powi(var, e, span)?;
        acc = Some(match acc {
            Some(a) => b.push(Op::Mul(a, p), span)?,
            None => p,
        });
    }
    Ok(acc)
}

/// Collected monomials from this many on are written in nested Horner
/// form. In the power form every product of shared powers (x^a·y^b, …)
/// stays alive until its last term: the 343 monomials of a degree-6 sum in
/// x, y and z kept 58 values alive at once (the tape's 64-register kernel,
/// 686 instructions); in Horner form 14 (the 16-register kernel, 643), and
/// its 512² frame took half the time. Below this count the power form's
/// enclosures are kept as they were (every catalog formula).
const HORNER_FROM: usize = 64;

/// The sum of `terms`, the original nodes mapped by `new_id`; monomials
/// whose coefficients cancelled are left out.
fn sum(b: &mut Builder, terms: &[Term], new_id: &[NodeId], span: Span) -> Result<NodeId, SemaError> {
    let monos: Vec<Monomial> = terms.iter().filter_map(|t| match t {
        Term::Mono(m) if m.coef != 0.0 => Some(*m),
        _ => None,
    }).collect();
    let horner = monos.len() >= HORNER_FROM;
    let mut acc: Option<NodeId> = None;
    for t in terms {
        let (node, plus) = match *t {
            Term::Node(n, plus) => (new_id[n as usize], plus),
            Term::Mono(m) if m.coef == 0.0 || horner => continue,
            Term::Mono(m) => match powers(b, m.exps, span)? {
                Some(p) if m.coef.abs() == 1.0 => (p, m.coef > 0.0),
                Some(p) => {
                    let mag = b.push(Op::Const(m.coef.abs()), span)?;
                    (b.push(Op::Mul(mag, p), span)?, m.coef > 0.0)
                }
                None => (b.push(Op::Const(m.coef), span)?, true),
            },
        };
        acc = Some(add(b, acc, node, plus, span)?);
    }
    if horner {
        let h = nested(b, &monos, 0, span)?;
        acc = Some(add(b, acc, h, true, span)?);
    }
    match acc {
        Some(a) => Ok(a),
        None => b.push(Op::Const(0.0), span),
    }
}

/// `acc` plus or minus `node` (`node` itself, or its negation, first).
fn add(b: &mut Builder, acc: Option<NodeId>, node: NodeId, plus: bool, span: Span) -> Result<NodeId, SemaError> {
    match (acc, plus) {
        (None, true) => Ok(node),
        (None, false) => b.push(Op::Neg(node), span),
        (Some(a), true) => b.push(Op::Add(a, node), span),
        (Some(a), false) => b.push(Op::Sub(a, node), span),
    }
}

/// The distinct monomials `monos` as a Horner form in variable `v` (x, y,
/// z) whose coefficients are such forms in the variables after it.
fn nested(b: &mut Builder, monos: &[Monomial], v: usize, span: Span) -> Result<NodeId, SemaError> {
    if v == 3 {
        // One monomial is left: the powers are all spent.
        return b.push(Op::Const(monos.iter().map(|m| m.coef).sum()), span);
    }
    let mut groups: std::collections::BTreeMap<u32, Vec<Monomial>> = std::collections::BTreeMap::new();
    for m in monos {
        groups.entry(m.exps[v]).or_default().push(*m);
    }
    let var = b.push(Op::Var([Var::X, Var::Y, Var::Z][v]), span)?;
    let mut acc: Option<(NodeId, u32)> = None;
    for (&e, group) in groups.iter().rev() {
        let p = nested(b, group, v + 1, span)?;
        acc = Some(match acc {
            None => (p, e),
            Some((a, prev)) => {
                let step = b.powi(var, prev - e, span)?;
                let scaled = b.push(Op::Mul(a, step), span)?;
                (b.push(Op::Add(scaled, p), span)?, e)
            }
        });
    }
    let (a, low) = acc.expect("at least one monomial");
    if low == 0 {
        return Ok(a);
    }
    let step = b.powi(var, low, span)?;
    b.push(Op::Mul(a, step), span)
}

#[cfg(test)]
mod tests {
    use crate::ir::{Ir, Op};
    use crate::reference::eval_scalar;

    fn ir(src: &str) -> Ir {
        crate::Formula::compile("<t>", src).unwrap().ir
    }

    fn same_values(a: &Ir, b: &Ir) {
        for p in [[0.3, -1.2, 0.7, 0.0], [1.5, 0.25, 2.0, 0.0], [-0.8, 0.9, 1.1, 0.0]] {
            let (u, v) = (eval_scalar(a, p, &[]), eval_scalar(b, p, &[]));
            assert!((u - v).abs() <= 1e-12 * (1.0 + u.abs()), "{u} vs {v} at {p:?}");
        }
    }

    #[test]
    fn like_monomials_become_one_term() {
        let a = ir("2*x^2*y + 3*y*x^2 - x + 4*x - 1 + z^0.5");
        let b = ir("5*x^2*y + 3*x - 1 + z^0.5");
        same_values(&a, &b);
        assert_eq!(a.nodes.len(), b.nodes.len(), "{:?} vs {:?}", a.nodes, b.nodes);
        // Through negation, subtraction and division by a constant.
        same_values(&ir("x*y - (y*x/2 - 3*x*y)"), &ir("3.5*x*y"));
        assert_eq!(ir("x*y - (y*x/2 - 3*x*y)").nodes.len(), ir("3.5*x*y").nodes.len());
    }

    #[test]
    fn constants_a_collection_makes_are_collected_too() {
        // y - y collects to 0, the power to 1, and then 2 + 1 to 3: as if
        // `x + 3` had been written (found by src/tests/frontend_fuzz.rs).
        let a = ir("x + 2 + pow(x, y - y)");
        assert_eq!(a.live().len(), ir("x + 3").live().len(), "{:?}", a.nodes);
        same_values(&a, &ir("x + 3"));
    }

    #[test]
    fn cancelling_terms_leave_the_rest() {
        let a = ir("x*y*z + sin(x) - z*y*x");
        assert!(!a.nodes.iter().any(|op| matches!(op, Op::Mul(..))), "{:?}", a.nodes);
        same_values(&a, &ir("sin(x)"));
        assert!(matches!(ir("x - x").nodes[..], [Op::Const(c)] if c == 0.0));
    }

    #[test]
    fn sums_without_like_terms_are_left_as_written() {
        // t is not collected, nor are other terms than monomials.
        assert_eq!(ir("t*x + t*x").nodes.len(), 4);
        assert_eq!(ir("sin(x) + sin(x)").nodes.len(), 3);
        let a = ir("(x + y)*(x - y) + x*y");
        assert_eq!(a.nodes.len(), 7, "{:?}", a.nodes);
        assert!(matches!(a.nodes[a.root as usize], Op::Add(..)));
        let b = ir("x^2 + y^2 + z^2 - 1");
        assert!(matches!(b.nodes[b.root as usize], Op::Sub(_, one) if b.nodes[one as usize] == Op::Const(1.0)));
    }
}

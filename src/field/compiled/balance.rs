//! Long sums rebalanced for the compiled field. A program writes a sum of
//! many terms as one chain `((t1 + t2) + t3) + …`, and lavapipe's LLVM
//! back end builds such a chain in time that grows steeply with its
//! length: a sum of a few hundred square roots `sqrt((x-a)^2 + …)` builds
//! several times sooner as a balanced tree, the same code otherwise (a
//! chain of another operation, such as a min of spheres, builds as soon
//! either way). So before the compiled field is generated, every chain of
//! additions and subtractions of at least [`MIN_TERMS`] terms becomes a
//! balanced tree of the same terms in the same order, signs carried to
//! where two subtrees meet.
//!
//! A sum whose terms have one shape is a loop instead ([`super::term_loops`],
//! which takes those square roots too); what is balanced is a long sum of
//! mixed shapes.
//!
//! Every domain's enclosure of a reassociated sum still holds the sum (the
//! interval and affine sums are inclusions whatever the order); only their
//! rounding differs. A chain of which a loop computes a part
//! ([`super::term_loops`]) is left alone: the loop accumulates in the order
//! written.

use crate::ir::{Ir, NodeId, Op};

/// Shortest chain rebalanced: a formula a person types keeps its order
/// (and its pictures, bit for bit).
pub const MIN_TERMS: usize = 32;

/// `ir` with its long chains of + and − balanced, or `None` when it has
/// none. A chain with a node for which `fixed` holds (a loop's, or the sum
/// a loop computes) keeps its form: rebalanced around a loop, the loop
/// planned again on the new tree drew a different picture of a sum of 200
/// reciprocals (868 hits of 1,360 at 256²), so a chain with a loop in it
/// is left to the loop.
pub fn balanced(ir: &Ir, fixed: impl Fn(NodeId) -> bool) -> Option<Ir> {
    let live = ir.live();
    let interior = interior_nodes(ir, &live);
    // The terms of each long chain (at its head), and the sums inside them,
    // which their heads compute.
    let mut long: Vec<Option<Vec<(NodeId, bool)>>> = vec![None; ir.nodes.len()];
    let mut absorbed = vec![false; ir.nodes.len()];
    for &n in live.iter().filter(|&&n| is_sum(&ir.nodes[n as usize]) && !interior[n as usize]) {
        let (terms, inside) = chain(ir, &interior, n);
        if terms.len() >= MIN_TERMS && !fixed(n) && !inside.iter().any(|&m| fixed(m)) {
            long[n as usize] = Some(terms);
            for m in inside {
                absorbed[m as usize] = true;
            }
        }
    }
    if long.iter().all(Option::is_none) {
        return None;
    }
    let mut out = Ir { nodes: vec![], spans: vec![], root: 0, surfaces: ir.surfaces.clone(), params: ir.params.clone(), externs: ir.externs.clone() };
    let mut map = vec![NodeId::MAX; ir.nodes.len()];
    for &n in &live {
        if absorbed[n as usize] {
            continue;
        }
        let op = ir.nodes[n as usize];
        let span = ir.spans[n as usize];
        let push = |out: &mut Ir, op: Op| {
            out.nodes.push(op);
            out.spans.push(span);
            (out.nodes.len() - 1) as NodeId
        };
        map[n as usize] = if let Some(terms) = &long[n as usize] {
            let leaves: Vec<(NodeId, bool)> = terms.iter().map(|&(l, plus)| (map[l as usize], plus)).collect();
            let (top, plus) = tree(&leaves, &mut |a| push(&mut out, a));
            if plus { top } else { push(&mut out, Op::Neg(top)) }
        } else {
            let ops: Vec<NodeId> = op.operands().iter().map(|&o| map[o as usize]).collect();
            push(&mut out, super::term_loops::with_operands(op, &ops))
        };
    }
    out.root = map[ir.root as usize];
    for s in &mut out.surfaces {
        s.f = map[s.f as usize];
        for c in &mut s.conditions {
            c.0 = map[c.0 as usize];
        }
    }
    Some(out)
}

fn is_sum(op: &Op) -> bool {
    matches!(op, Op::Add(..) | Op::Sub(..))
}

/// Sums used once, by another sum: the inside of a chain, which its head
/// computes.
pub(super) fn interior_nodes(ir: &Ir, live: &[NodeId]) -> Vec<bool> {
    let mut uses = vec![0u32; ir.nodes.len()];
    let mut by_sum = vec![false; ir.nodes.len()];
    for &n in live {
        let op = &ir.nodes[n as usize];
        for o in op.operands() {
            uses[o as usize] += 1;
            by_sum[o as usize] |= is_sum(op);
        }
    }
    uses[ir.root as usize] += 1;
    for s in &ir.surfaces {
        uses[s.f as usize] += 1;
        for &(g, _) in &s.conditions {
            uses[g as usize] += 1;
        }
    }
    (0..ir.nodes.len()).map(|n| uses[n] == 1 && by_sum[n] && is_sum(&ir.nodes[n])).collect()
}

/// The terms of the chain headed by `n`, in order, each with its sign
/// (true: added), and the sums inside it.
pub(super) fn chain(ir: &Ir, interior: &[bool], n: NodeId) -> (Vec<(NodeId, bool)>, Vec<NodeId>) {
    let (mut terms, mut inside) = (vec![], vec![]);
    // Depth-first, right operand pushed first so terms come out in order.
    let mut stack = vec![(n, true)];
    while let Some((m, plus)) = stack.pop() {
        let sum = m == n || interior[m as usize];
        match ir.nodes[m as usize] {
            Op::Add(a, b) if sum => stack.extend([(b, plus), (a, plus)]),
            Op::Sub(a, b) if sum => stack.extend([(b, !plus), (a, plus)]),
            _ => terms.push((m, plus)),
        }
        if sum && m != n {
            inside.push(m);
        }
    }
    (terms, inside)
}

/// A balanced tree over `leaves` (new node ids with their signs), built
/// with `push`: its top and whether it is added (false: the tree computes
/// the negated sum).
fn tree(leaves: &[(NodeId, bool)], push: &mut impl FnMut(Op) -> NodeId) -> (NodeId, bool) {
    if let [one] = leaves {
        return *one;
    }
    let (l, r) = leaves.split_at(leaves.len() / 2);
    let (a, pa) = tree(l, push);
    let (b, pb) = tree(r, push);
    match (pa, pb) {
        (true, true) => (push(Op::Add(a, b)), true),
        (true, false) => (push(Op::Sub(a, b)), true),
        (false, true) => (push(Op::Sub(b, a)), true),
        (false, false) => (push(Op::Add(a, b)), false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(ir: &Ir, p: [f64; 3]) -> f64 {
        crate::reference::eval_scalar(ir, [p[0], p[1], p[2], 0.0], &[])
    }

    #[test]
    fn a_long_chain_becomes_a_balanced_tree_of_the_same_sum() {
        let terms: Vec<String> = (0..40).map(|i| format!("{}(x - {}.5)*(y + {})", if i % 3 == 1 { "- " } else { "+ " }, i, i % 7)).collect();
        let src = format!("z - 1 {}", terms.join(" "));
        let f = crate::Formula::compile("<t>", &src).unwrap();
        let b = balanced(&f.ir, |_| false).expect("a chain of 41 terms");
        for p in [[0.3, -0.7, 0.2], [1.5, 2.0, -3.0], [-4.0, 0.1, 9.0]] {
            let (want, got) = (eval(&f.ir, p), eval(&b, p));
            assert!((want - got).abs() <= 1e-9 * want.abs().max(1.0), "{want} {got}");
        }
        // Depth: a chain of 41 is 40 deep; balanced, 6 sums.
        let depth = |ir: &Ir| {
            let mut d = vec![0usize; ir.nodes.len()];
            for (i, op) in ir.nodes.iter().enumerate() {
                d[i] = op.operands().iter().map(|&o| d[o as usize] + usize::from(is_sum(op))).max().unwrap_or(0);
            }
            d[ir.root as usize]
        };
        assert!(depth(&f.ir) >= 40 && depth(&b) <= 8, "{} {}", depth(&f.ir), depth(&b));
    }

    /// A run of 30 terms of one shape is a loop, and its chain keeps its
    /// form; a long chain elsewhere (here under an exp) is balanced, and
    /// the loop is planned again as it was.
    #[test]
    fn a_chain_with_a_loop_keeps_its_form_and_others_are_balanced() {
        let distinct: Vec<String> = (0..40).map(|i| format!("{}(x - {}.5)*(y + {})", if i % 3 == 1 { "- " } else { "+ " }, i, i % 7)).collect();
        let run: Vec<String> = (0..30).map(|i| format!("+ 0.{:02}*sin({}.25*z)", i + 1, i + 2)).collect();
        for (src, balances) in [(format!("z - 1 {} {}", distinct.join(" "), run.join(" ")), false), (format!("exp(-(z {})) {}", distinct.join(" "), run.join(" ")), true)] {
            let f = crate::Formula::compile("<t>", &src).unwrap();
            let plan = crate::field::compiled::term_loops::plan(&f.ir);
            assert_eq!(plan.loops.len(), 1);
            let b = balanced(&f.ir, |n| plan.skips(n) || plan.loop_at(n).is_some());
            assert_eq!(b.is_some(), balances, "{src}");
            let Some(b) = b else { continue };
            let again = crate::field::compiled::term_loops::plan(&b);
            assert_eq!((again.loops.len(), again.iterations(), &again.table), (1, plan.iterations(), &plan.table));
            let p = [0.3, -0.7, 0.2];
            assert!((eval(&f.ir, p) - eval(&b, p)).abs() < 1e-9);
        }
    }

    #[test]
    fn short_chains_and_shared_sums_keep_their_form() {
        let f = crate::Formula::compile("<t>", "x^2 + y^2 + z^2 - 1").unwrap();
        assert!(balanced(&f.ir, |_| false).is_none());
        // A sum used twice is a term of both chains, never split.
        let terms: Vec<String> = (0..40).map(|i| format!("(x - {i})^2")).collect();
        let src = format!("s = x + y + z;\ns*s + {} - s", terms.join(" + "));
        let f = crate::Formula::compile("<t>", &src).unwrap();
        let b = balanced(&f.ir, |_| false).expect("a chain of 42 terms");
        // Nodes a loop computes are left alone.
        assert!(balanced(&f.ir, |_| true).is_none());
        let p = [0.25, -1.5, 2.0];
        assert!((eval(&f.ir, p) - eval(&b, p)).abs() < 1e-6);
    }
}

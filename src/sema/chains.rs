//! Long `min` and `max` trees written as chains. A program that writes a
//! union of a thousand shapes often nests it as a balanced tree
//! (`min(min(a, b), min(c, d))`, a divide and conquer over its list), where
//! a person writes `min(a, b, c, …)`. The compiled field makes a chain of
//! same-shaped terms a loop (`field::compiled::term_loops`), with per-tile term lists
//! for unions; a balanced tree of 1,100 boxes (63 KB) was written out
//! instead, and its first 512² frame took over two minutes.
//!
//! So a tree of one of these operations with at least [`MIN_LEAVES`]
//! operands becomes a chain of the same operands, grouped by shape: the
//! operands of the shape seen first, in their order, then those of the
//! next shape. A program that writes a scene of boxes, balls and cylinders
//! in no order (961 of them, 60 KB) had no two same-shaped terms side by
//! side, so no loop, and its first 512² frame took over 200 s as a tape;
//! grouped, its chain is three loops. The scalar and interval `min` and
//! `max` are exact, commutative and associative, so their values are the
//! tree's (the same f64 value at every point, up to the sign of a zero);
//! an affine `min` of other operands is another enclosure of the same
//! function. Shorter trees, which people write, keep their form.

use std::collections::HashMap;
use std::hash::{DefaultHasher, Hash, Hasher};

use super::{Builder, SemaError};
use crate::ir::{Func2, Ir, NodeId, Op, SurfaceIr};

/// Fewest operands a tree rewritten as a chain has. Balanced trees of
/// boxes (`max(|x − a|, |y − b|, |z − c|) − r`), cold at 512², written out
/// → as a chain: 225 boxes 1.06 → 1.47 s (written out, each box's code is a
/// few operations with its constants inline, and it compiles in 0.6 s),
/// 400 boxes 3.95 → 1.57 s, 600 boxes over 100 s → 2.3 s.
pub const MIN_LEAVES: usize = 256;

/// `ir` with its long `min` and `max` trees as chains (itself when it has
/// none).
pub(super) fn chain(ir: Ir) -> Result<Ir, SemaError> {
    let live = ir.live();
    let mut users = vec![0u32; ir.nodes.len()];
    for &n in &live {
        for o in ir.nodes[n as usize].operands() {
            users[o as usize] += 1;
        }
    }
    for s in &ir.surfaces {
        users[s.f as usize] += 1;
        for &(g, _) in &s.conditions {
            users[g as usize] += 1;
        }
    }
    let op_of = |n: NodeId| match ir.nodes[n as usize] {
        Op::Call2(f @ (Func2::Min | Func2::Max), ..) => Some(f),
        _ => None,
    };
    // An operand folded into its user's tree: the same operation, used once.
    let inner = |n: NodeId, f: Func2| op_of(n) == Some(f) && users[n as usize] == 1;
    // Nodes folded into their user's tree: only a tree's top node is one.
    let mut folded = vec![false; ir.nodes.len()];
    for &u in &live {
        if let Some(f) = op_of(u) {
            for o in ir.nodes[u as usize].operands() {
                folded[o as usize] |= inner(o, f);
            }
        }
    }
    let mut trees: Vec<Option<Vec<NodeId>>> = vec![None; ir.nodes.len()];
    let mut any = false;
    for &n in &live {
        let Some(f) = op_of(n) else { continue };
        if folded[n as usize] || ir.nodes[n as usize].operands().iter().all(|&o| !inner(o, f)) {
            continue;
        }
        let leaves = leaves(&ir, n, &inner, f);
        if leaves.len() >= MIN_LEAVES {
            trees[n as usize] = Some(leaves);
            any = true;
        }
    }
    if !any {
        return Ok(ir);
    }
    let shape = shapes(&ir);
    for t in trees.iter_mut().flatten() {
        *t = grouped(t, &shape);
    }
    let mut b = Builder { params: ir.params.clone(), externs: ir.externs.clone(), ..Builder::default() };
    let mut new_id = vec![NodeId::MAX; ir.nodes.len()];
    for &n in &live {
        let span = ir.spans[n as usize];
        new_id[n as usize] = match (&trees[n as usize], ir.nodes[n as usize]) {
            (Some(leaves), Op::Call2(f, ..)) => {
                let mut acc = new_id[leaves[0] as usize];
                for &l in &leaves[1..] {
                    acc = b.push(Op::Call2(f, acc, new_id[l as usize]), span)?;
                }
                acc
            }
            // Nodes inside a rewritten tree are pushed too, and read by
            // nothing: `compact` drops them.
            (_, op) => b.push(op.with_operands(|o| new_id[o as usize]), span)?,
        };
    }
    let surfaces = ir
        .surfaces
        .iter()
        .map(|s| SurfaceIr { f: new_id[s.f as usize], conditions: s.conditions.iter().map(|&(g, less)| (new_id[g as usize], less)).collect() })
        .collect();
    Ok(Ir { nodes: b.nodes, spans: b.spans, root: new_id[ir.root as usize], surfaces, params: b.params, externs: b.externs })
}

/// The operands of the tree of `f` at `top`, left to right (an explicit
/// stack: a degenerate tree is as deep as it is long).
fn leaves(ir: &Ir, top: NodeId, inner: &impl Fn(NodeId, Func2) -> bool, f: Func2) -> Vec<NodeId> {
    let mut out = Vec::new();
    let mut stack = vec![top];
    while let Some(n) = stack.pop() {
        if n != top && !inner(n, f) {
            out.push(n);
            continue;
        }
        let ops = ir.nodes[n as usize].operands();
        stack.extend(ops.iter().rev());
    }
    out
}

/// A key per node for its shape: its operations and variables, with every
/// constant alike and a commutative node's operands in either order (the
/// front end orders them by when each was first written). Same-shaped
/// terms can be one loop (`field::compiled::term_loops` decides; this only brings them
/// together).
fn shapes(ir: &Ir) -> Vec<u64> {
    let mut key = Vec::with_capacity(ir.nodes.len());
    for op in &ir.nodes {
        let mut h = DefaultHasher::new();
        let mut kids: Vec<u64> = op.operands().iter().map(|&o| key[o as usize]).collect();
        match *op {
            Op::Const(_) => 0u8.hash(&mut h),
            Op::Var(v) => (1u8, v).hash(&mut h),
            Op::Param(i) => (2u8, i).hash(&mut h),
            Op::Add(..) | Op::Mul(..) | Op::Call2(Func2::Min | Func2::Max, ..) => {
                kids.sort_unstable();
                std::mem::discriminant(op).hash(&mut h);
            }
            _ => std::mem::discriminant(op).hash(&mut h),
        }
        match *op {
            Op::PowI(_, n) => n.hash(&mut h),
            Op::Call1(f, _) => f.hash(&mut h),
            Op::Call2(f, ..) => f.hash(&mut h),
            Op::Call3(f, ..) => f.hash(&mut h),
            Op::User(u, _, n) => (u, n).hash(&mut h),
            _ => {}
        }
        kids.hash(&mut h);
        key.push(h.finish());
    }
    key
}

/// `leaves` grouped by shape, the groups in the order their first operand
/// comes, each in its own order.
fn grouped(leaves: &[NodeId], shape: &[u64]) -> Vec<NodeId> {
    let mut group_of: HashMap<u64, usize> = HashMap::new();
    let mut groups: Vec<Vec<NodeId>> = Vec::new();
    for &l in leaves {
        let next = groups.len();
        let g = *group_of.entry(shape[l as usize]).or_insert(next);
        if g == next {
            groups.push(Vec::new());
        }
        groups[g].push(l);
    }
    groups.concat()
}

#[cfg(test)]
mod tests {
    use crate::ir::{Func2, Op};

    /// `n` boxes as a balanced `min` tree, and as `min(b1, b2, …)`.
    fn boxes(n: usize) -> (String, String) {
        let items: Vec<String> = (0..n).map(|i| format!("max(abs(x-{:.3}),max(abs(y-{:.3}),abs(z-{:.3})))-0.05", (0.37 * i as f64).sin(), (0.53 * i as f64).cos(), (0.11 * i as f64).sin())).collect();
        fn tree(a: &[String]) -> String {
            match a.len() {
                1 => a[0].clone(),
                n => format!("min({}, {})", tree(&a[..n / 2]), tree(&a[n / 2..])),
            }
        }
        (tree(&items), format!("min({})", items.join(", ")))
    }

    /// Min nodes with a min operand (a chain of n operands has n − 2; a
    /// balanced tree about as many, but two of them under some nodes).
    fn nested_twice(src: &str) -> usize {
        let ir = crate::Formula::compile("<t>", src).unwrap().ir;
        let min = |n: u32| matches!(ir.nodes[n as usize], Op::Call2(Func2::Min, ..));
        ir.live().into_iter().filter(|&n| min(n) && ir.nodes[n as usize].operands().iter().all(|&o| min(o))).count()
    }

    #[test]
    fn a_long_balanced_union_becomes_a_chain_with_the_same_values() {
        let (tree, variadic) = boxes(300);
        // A chain: no min node has two min operands.
        assert_eq!(nested_twice(&tree), 0);
        let t = crate::Formula::compile("<tree>", &tree).unwrap().ir;
        assert_eq!(crate::field::compiled::term_loops::plan(&t).loops.len(), 1);
        let v = crate::Formula::compile("<chain>", &variadic).unwrap().ir;
        for i in 0..500 {
            let p = [(1.3 * i as f64).sin() * 1.2, (0.7 * i as f64).cos() * 1.2, (0.9 * i as f64).sin() * 1.2, 0.0];
            let (a, b) = (crate::reference::eval_scalar(&t, p, &[]), crate::reference::eval_scalar(&v, p, &[]));
            assert_eq!(a.to_bits(), b.to_bits(), "at {p:?}");
        }
        // Shorter trees keep their form.
        assert!(nested_twice(&boxes(200).0) > 50);
    }

    /// Balls, boxes and cylinders by turns, 300 of them: grouped by shape,
    /// three loops, with the values of the formula as written (f64 `min`
    /// is exact in any order; 500 points, ±0 alike).
    #[test]
    fn a_long_union_of_mixed_shapes_is_grouped_by_shape() {
        let items: Vec<String> = (0..300)
            .map(|i| {
                let (a, b, c) = ((0.37 * i as f64).sin(), (0.53 * i as f64).cos(), (0.11 * i as f64).sin());
                match i % 3 {
                    0 => format!("sqrt((x-{a:.3})^2+(y-{b:.3})^2+(z-{c:.3})^2)-0.1"),
                    1 => format!("max(abs(x-{a:.3}),max(abs(y-{b:.3}),abs(z-{c:.3})))-0.05"),
                    _ => format!("max(sqrt((x-{a:.3})^2+(y-{b:.3})^2)-0.04,abs(z-{c:.3})-0.2)"),
                }
            })
            .collect();
        let src = format!("min({})", items.join(", "));
        let ir = crate::Formula::compile("<mixed>", &src).unwrap().ir;
        assert_eq!(crate::field::compiled::term_loops::plan(&ir).loops.len(), 3);
        // The same formula as a fold of two-operand mins, which no rewrite touches.
        let each: Vec<_> = items.iter().map(|t| crate::Formula::compile("<t>", t).unwrap().ir).collect();
        for i in 0..500 {
            let p = [(1.3 * i as f64).sin() * 1.2, (0.7 * i as f64).cos() * 1.2, (0.9 * i as f64).sin() * 1.2, 0.0];
            let written = each.iter().map(|t| crate::reference::eval_scalar(t, p, &[])).fold(f64::INFINITY, f64::min);
            assert_eq!(crate::reference::eval_scalar(&ir, p, &[]), written, "at {p:?}");
        }
        // One shape in a tree of 300 keeps its order.
        let (tree, _) = boxes(300);
        let t = crate::Formula::compile("<tree>", &tree).unwrap().ir;
        assert_eq!(crate::field::compiled::term_loops::plan(&t).loops.len(), 1);
    }
}

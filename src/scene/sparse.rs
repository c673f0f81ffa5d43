//! The sparse bottom-up traversal (Zanni et al. 2024 §5, as the brief §1.4
//! reconstructs it): evaluate the field of the active primitives A by
//! visiting only the nodes above them, jumping along fast ancestors, and
//! build the pruned view (the post-order list of the operators that see two
//! present operands) that Algorithm 4 evaluates with a plain stack.
//!
//! This is the CPU port the GPU traversal is checked against. It equals the
//! masked evaluation ([`Scene::eval_masked`]) bit for bit, with parent or
//! fast ancestors, directly or through the view (src/tests/scene_model.rs), and
//! its stack is empty at the end; a chain of unary nodes the layout merged
//! (`fold.rs`) runs as one node, so there only up to the rounding of the
//! merged parameter.
//!
//! The loop, for each active primitive b in index order, climbs from b:
//! the next node is a = ANC(b), clamped to the ancestor of the stack top;
//! if a lies above the next active primitive, b's value waits on the stack
//! (the next primitive joins it lower down); otherwise the value meets a's
//! other operand, popped from the stack when it is pending there
//! (popRequiredA: the top waits for exactly a; popRequiredB: b is a right
//! operand whose ancestor chain, clamped, reaches no higher than the top's),
//! or missing (∅) and resolved by the selection rules.

use super::linear::Linear;
use super::operator::select_kind;
use super::{Node, Operator, Scene};

/// Which ancestor index the traversal climbs by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ancestors {
    /// The parent: one operator per step.
    Parent,
    /// The fast ancestor: skips operators that only select.
    Fast,
}

/// A traversal's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Traversal<V> {
    /// The root's value; `None` (∅) when no active primitive decides it.
    pub value: Option<V>,
    /// The pruned view: post-order indices of the active primitives and of
    /// the operators with both operands present, in evaluation order.
    pub view: Vec<u32>,
    /// Nodes visited (loop turns).
    pub visits: u32,
    /// The deepest the traversal stack got.
    pub max_stack: u32,
}

/// A bad active list.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SparseError {
    /// Not in increasing order (or repeated).
    #[error("active primitives must be in increasing order: {0} follows {1}")]
    NotSorted(u32, u32),
    /// Not a primitive of the tree.
    #[error("node {0} is not a primitive of the scene")]
    NotPrimitive(u32),
}

struct Entry<V> {
    node: u32,
    value: Option<V>,
    anc: u32,
    view_start: usize,
}

fn check_active(lin: &Linear, active: &[u32]) -> Result<(), SparseError> {
    for (k, &b) in active.iter().enumerate() {
        if b as usize >= lin.len() || !lin.is_leaf(b) {
            return Err(SparseError::NotPrimitive(b));
        }
        if k > 0 && active[k - 1] >= b {
            return Err(SparseError::NotSorted(b, active[k - 1]));
        }
    }
    Ok(())
}

/// The operator at post-order index `m`.
pub fn operator_at(lin: &Linear, scene: &Scene, m: u32) -> Operator {
    match scene.nodes()[lin.order[m as usize]] {
        Node::Operator { op, .. } => op,
        _ => unreachable!("node {m} is not a binary operator"),
    }
}

/// The unary node at post-order index `m`.
#[cfg(test)]
pub fn unary_at(lin: &Linear, scene: &Scene, m: u32) -> super::Unary {
    if let Some(op) = lin.folded_unary(m) {
        return op;
    }
    match scene.nodes()[lin.order[m as usize]] {
        Node::Unary { op, .. } => op,
        _ => unreachable!("node {m} is not a unary node"),
    }
}

/// How a traversal computes values: `prim(b)` evaluates primitive b,
/// `op(m, l, r)` binary operator m with both operands present, `un(m, v)`
/// unary node m with its operand present.
struct Eval<P, O, U> {
    prim: P,
    op: O,
    un: U,
}

/// The traversal over any value type (see [`Eval`]). A unary node's
/// operand is a left one (linear.rs), so the climb reaches it with no
/// pending operand: present, it joins the view; missing, it is missing.
fn walk<V: Copy, P: FnMut(u32) -> V, O: FnMut(u32, V, V) -> V, U: FnMut(u32, V) -> V>(
    lin: &Linear,
    scene: &Scene,
    active: &[u32],
    anc: Ancestors,
    ev: Eval<P, O, U>,
) -> Result<Traversal<V>, SparseError> {
    let Eval { mut prim, mut op, mut un } = ev;
    check_active(lin, active)?;
    let n = lin.len() as u32;
    let root = n - 1;
    let anc_of = |i: u32| match anc {
        Ancestors::Fast => lin.fast[i as usize],
        Ancestors::Parent => lin.parent[i as usize],
    };
    let mut stack: Vec<Entry<V>> = Vec::new();
    let (mut view, mut visits, mut max_stack) = (Vec::new(), 0u32, 0u32);
    let mut f = None;
    for (k, &first) in active.iter().enumerate() {
        let next = active.get(k + 1).copied().unwrap_or(n + 1);
        let (mut b, mut start) = (first, view.len());
        f = Some(prim(first));
        view.push(first);
        loop {
            visits += 1;
            if b == root {
                break;
            }
            let mut a = anc_of(b);
            if let Some(top) = stack.last() {
                a = a.min(top.anc); // clamping (markers #1, #2)
            }
            if a > next {
                // Shadowed: the next active primitive lies under a.
                stack.push(Entry { node: b, value: f, anc: a, view_start: start });
                max_stack = max_stack.max(stack.len() as u32);
                break;
            }
            // Every step climbs (a > b in post-order), so the loop ends; a
            // broken stack would make it descend, which is a bug, not a hang.
            assert!(a > b, "the traversal would descend from node {b} to {a}");
            let (m, left) = (a, lin.is_left[b as usize]);
            let pop = stack.last().is_some_and(|top| {
                let pop_a = !left && top.anc == m;
                let pop_b = !left && (lin.is_left[m as usize] || m == root) && anc_of(m).min(top.anc) >= top.anc;
                pop_a || pop_b
            });
            let (l, r) = if pop {
                let e = stack.pop().expect("checked");
                debug_assert!(e.node < b);
                start = e.view_start;
                (e.value, f)
            } else if left {
                (f, None)
            } else {
                (None, f)
            };
            f = match (l, r) {
                (Some(l), None) if lin.is_unary(m) => {
                    view.push(m);
                    Some(un(m, l))
                }
                (Some(l), Some(r)) => {
                    view.push(m);
                    Some(op(m, l, r))
                }
                _ => {
                    let v = if lin.is_unary(m) {
                        None
                    } else {
                        let kind = operator_at(lin, scene, m).kind;
                        select_kind(kind, l.is_some(), r.is_some()).and_then(|keep_left| if keep_left { l } else { r })
                    };
                    if v.is_none() {
                        view.truncate(start);
                    }
                    v
                }
            };
            b = m;
        }
    }
    assert!(stack.is_empty(), "the traversal stack is not empty at the end");
    Ok(Traversal { value: f, view, visits, max_stack })
}

/// The field of the active primitives `active` (post-order indices,
/// increasing) at `p`, by the sparse traversal.
#[cfg(test)]
pub fn traverse(lin: &Linear, scene: &Scene, p: [f64; 3], active: &[u32], anc: Ancestors) -> Result<Traversal<f64>, SparseError> {
    let ev = Eval {
        prim: |b| primitive_value(lin, scene, b, p),
        op: |m, l, r| operator_at(lin, scene, m).apply(l, r),
        un: |m, v| unary_at(lin, scene, m).apply(v, p),
    };
    walk(lin, scene, active, anc, ev)
}

/// The pruned view only: which operators evaluate depends on the tree and
/// on A, not on field values, so one view serves a whole depth range.
/// `value` is `Some(())` when the view is not empty.
pub fn build_view(lin: &Linear, scene: &Scene, active: &[u32], anc: Ancestors) -> Result<Traversal<()>, SparseError> {
    walk(lin, scene, active, anc, Eval { prim: |_| (), op: |_, _, _| (), un: |_, _| () })
}

/// The value of primitive `b` (a post-order index) at `p`.
#[cfg(test)]
pub fn primitive_value(lin: &Linear, scene: &Scene, b: u32, p: [f64; 3]) -> f64 {
    match &scene.nodes()[lin.order[b as usize]] {
        Node::Primitive(prim) => prim.distance(p),
        _ => unreachable!("node {b} is an operator"),
    }
}

/// Algorithm 4: the view evaluated with a stack; `None` for an empty view.
#[cfg(test)]
pub fn eval_view(lin: &Linear, scene: &Scene, p: [f64; 3], view: &[u32]) -> Option<f64> {
    let mut stack: Vec<f64> = Vec::new();
    for &i in view {
        if lin.is_leaf(i) {
            stack.push(primitive_value(lin, scene, i, p));
        } else if lin.is_unary(i) {
            let v = stack.pop().expect("a unary node in the view has its operand");
            stack.push(unary_at(lin, scene, i).apply(v, p));
        } else {
            let r = stack.pop().expect("an operator in the view has two operands");
            let l = stack.pop().expect("an operator in the view has two operands");
            stack.push(operator_at(lin, scene, i).apply(l, r));
        }
    }
    assert!(stack.len() <= 1, "the view leaves {} values", stack.len());
    stack.pop()
}

/// The active set at `p` as the A-buffer would give it: every primitive
/// whose ABV contains p (planes always), as post-order indices.
pub fn active_at(lin: &Linear, p: [f64; 3]) -> Vec<u32> {
    lin.abvs.iter().zip(&lin.primitives).filter(|(a, _)| a.contains(p)).map(|(_, &k)| k).collect()
}

/// Node visits of the traversal at sample points, parent against fast.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Probe {
    /// Points probed.
    pub points: usize,
    /// Points where no ABV contains the point (no traversal).
    pub empty: usize,
    /// Mean |A| over the other points.
    pub active_mean: f64,
    /// Largest |A|.
    pub active_max: usize,
    /// Mean node visits per traversal with fast ancestors.
    pub visits_fast: f64,
    /// Mean node visits per traversal with parents.
    pub visits_parent: f64,
    /// Mean length of the pruned view.
    pub view_mean: f64,
    /// Deepest traversal stack (fast ancestors).
    pub max_stack_fast: u32,
    /// Deepest traversal stack (parents).
    pub max_stack_parent: u32,
}

/// Runs the traversal (views only: visits do not depend on values) at
/// each point with both ancestor kinds.
pub fn probe(lin: &Linear, scene: &Scene, points: &[[f64; 3]]) -> Probe {
    let mut pr = Probe { points: points.len(), ..Probe::default() };
    let (mut sum_a, mut fast, mut parent, mut view) = (0usize, 0u64, 0u64, 0usize);
    for &p in points {
        let a = active_at(lin, p);
        if a.is_empty() {
            pr.empty += 1;
            continue;
        }
        sum_a += a.len();
        pr.active_max = pr.active_max.max(a.len());
        let tf = build_view(lin, scene, &a, Ancestors::Fast).expect("ABV order is increasing");
        let tp = build_view(lin, scene, &a, Ancestors::Parent).expect("ABV order is increasing");
        fast += tf.visits as u64;
        parent += tp.visits as u64;
        view += tf.view.len();
        pr.max_stack_fast = pr.max_stack_fast.max(tf.max_stack);
        pr.max_stack_parent = pr.max_stack_parent.max(tp.max_stack);
    }
    let k = (points.len() - pr.empty).max(1) as f64;
    pr.active_mean = sum_a as f64 / k;
    pr.visits_fast = fast as f64 / k;
    pr.visits_parent = parent as f64 / k;
    pr.view_mean = view as f64 / k;
    pr
}

/// `count` points spread over the scene's primitives: each inside the
/// bounding box of a randomly chosen bounded primitive's ABV, where the
/// A-buffer has work (deterministic for a seed).
pub fn probe_points(lin: &Linear, count: usize, seed: u64) -> Vec<[f64; 3]> {
    let bounded: Vec<_> = lin.abvs.iter().map(|a| a.aabb()).filter(|b| b.is_bounded()).collect();
    if bounded.is_empty() {
        return Vec::new();
    }
    let mut rng = super::generate::Rng::new(seed);
    (0..count)
        .map(|_| {
            let b = &bounded[rng.below(bounded.len() as u64) as usize];
            [0, 1, 2].map(|k| rng.range(b.min[k], b.max[k]))
        })
        .collect()
}

//! Chains of unary nodes folded for the GPU, and the depth the GPU can
//! evaluate.
//!
//! The GPU interpreter (templates/fields/scene.wgsl) runs a tile's pruned
//! pruned tree node by node, and every evaluation of a pixel shares one budget of
//! loop iterations ([`LOOP_LIMIT`]: lavapipe stops an invocation after
//! 65,535). A pruned tree leaves out an operator whose other operand is missing,
//! but never a unary node above a present primitive (it changes the value),
//! nor an operator whose other operand holds a plane (always present). A
//! primitive under a chain of such nodes costs the whole chain at every
//! step of every ray near it: a sphere under 8,000 offsets left no room for
//! a single step.
//!
//! So a scene is laid out from its *folded* tree: consecutive unary nodes
//! that are exactly one node are merged (offsets add up, an offset over a
//! shell widens the shell, equal infills are one, displacements of one
//! frequency add their amplitudes), and nodes that change nothing (an
//! offset of 0, a displacement of amplitude 0) are left out. The scene
//! itself is not changed: files, edits and messages keep its node indices.
//! What still cannot be pruned is then limited to [`MAX_UNPRUNED_DEPTH`]
//! nodes on any path, at load, with the path of the primitive that needs
//! more.

use super::roi::{self, Abv, Roi};
use super::{Node, NodeId, Scene, SceneError, Unary};
use crate::layout::LOOP_LIMIT;

/// The most nodes above a primitive that no pruned tree can leave out
/// (unary nodes, operators whose other operand holds a plane), after
/// folding. A pruned tree holds at most 1,024 words (`SCENE_PRUNED_MAX`), so this
/// leaves room for the primitives of a tile, and a pixel gets some 110
/// evaluations of such a pruned tree within [`LOOP_LIMIT`]: sphere tracing a
/// chain of 512 shells converges with room to spare, where 2,500 left
/// pixels unconverged and 8,000 drew nothing.
pub const MAX_UNPRUNED_DEPTH: usize = 512;

/// A scene's folded tree: the nodes the GPU evaluates, and for each the
/// scene node it stands for (a merged chain: its top node).
pub struct Folded {
    /// The folded tree, in post-order (node k's operands come before k).
    pub scene: Scene,
    /// The scene node of each folded node.
    pub origin: Vec<NodeId>,
}

/// `outer(inner(v))` as one unary node, when it is exactly one (for
/// every operand value and point): None otherwise, or when the merged
/// parameter would not be finite.
pub fn compose(outer: Unary, inner: Unary) -> Option<Unary> {
    let merged = match (outer, inner) {
        // (v − b) − a.
        (Unary::Offset { distance: a }, Unary::Offset { distance: b }) => Unary::Offset { distance: a + b },
        // |v| − t/2 − d, a shell while it stays one (t + 2d > 0).
        (Unary::Offset { distance: d }, Unary::Shell { thickness: t }) if t + 2.0 * d > 0.0 => Unary::Shell { thickness: t + 2.0 * d },
        // max(max(v, g), g).
        (Unary::Infill { .. }, Unary::Infill { .. }) if outer == inner => outer,
        // v + b·n(p) + a·n(p), one noise at one frequency.
        (Unary::Displace { amplitude: a, frequency: f }, Unary::Displace { amplitude: b, frequency: g }) if f == g => Unary::Displace { amplitude: a + b, frequency: f },
        _ => return None,
    };
    merged.values().iter().all(|v| v.is_finite()).then_some(merged)
}

/// Whether the node changes no value: v − 0, v + 0·n(p).
fn is_identity(op: Unary) -> bool {
    matches!(op, Unary::Offset { distance } if distance == 0.0) || matches!(op, Unary::Displace { amplitude, .. } if amplitude == 0.0)
}

/// The folded tree of `scene`, or None when nothing folds (the scene is
/// laid out as it is).
pub fn fold(scene: &Scene) -> Option<Folded> {
    let nodes = scene.nodes();
    let folds = |n: &Node| match *n {
        Node::Unary { op, child } => is_identity(op) || matches!(nodes[child], Node::Unary { op: inner, .. } if compose(op, inner).is_some()),
        _ => false,
    };
    if !nodes.iter().any(folds) {
        return None;
    }
    // Built in the scene's post-order, so when a unary node is reached its
    // operand's folded node is the last one pushed.
    let mut out: Vec<Node> = Vec::with_capacity(nodes.len());
    let mut origin: Vec<NodeId> = Vec::with_capacity(nodes.len());
    let mut at = vec![0usize; nodes.len()];
    for &i in scene.post_order() {
        at[i] = match &nodes[i] {
            Node::Primitive(_) => push(&mut out, &mut origin, nodes[i].clone(), i),
            &Node::Operator { op, left, right } => push(&mut out, &mut origin, Node::Operator { op, left: at[left], right: at[right] }, i),
            &Node::Unary { op, child } => {
                let c = at[child];
                match out[c] {
                    _ if is_identity(op) => c,
                    Node::Unary { op: inner, child: below } => match compose(op, inner) {
                        Some(m) if is_identity(m) => {
                            out.pop();
                            origin.pop();
                            below
                        }
                        Some(m) => {
                            out[c] = Node::Unary { op: m, child: below };
                            origin[c] = i;
                            c
                        }
                        None => push(&mut out, &mut origin, Node::Unary { op, child: c }, i),
                    },
                    _ => push(&mut out, &mut origin, Node::Unary { op, child: c }, i),
                }
            }
        };
    }
    let post = (0..out.len()).collect();
    let root = out.len() - 1;
    Some(Folded { scene: Scene { nodes: out, root, post }, origin })
}

fn push(out: &mut Vec<Node>, origin: &mut Vec<NodeId>, n: Node, i: NodeId) -> usize {
    out.push(n);
    origin.push(i);
    out.len() - 1
}

/// Refuses a (folded) scene with a primitive under more than
/// [`MAX_UNPRUNED_DEPTH`] nodes that no pruned tree can leave out; `name` gives
/// the scene node a folded node stands for, for the message.
pub fn check_depth(scene: &Scene, roi: &[Roi], name: &dyn Fn(NodeId) -> NodeId) -> Result<(), SceneError> {
    let nodes = scene.nodes();
    let mut always = vec![false; nodes.len()];
    for &i in scene.post_order() {
        always[i] = match &nodes[i] {
            Node::Primitive(p) => matches!(roi::abv(p, roi[i].hi), Abv::Always),
            n => n.children().iter().any(|&c| always[c]),
        };
    }
    // Per node: the unary nodes and the operators over a plane above it.
    let mut kept = vec![(0usize, 0usize); nodes.len()];
    let mut worst: Option<((usize, usize), NodeId)> = None;
    for &i in scene.post_order().iter().rev() {
        let (u, o) = kept[i];
        match nodes[i] {
            Node::Unary { child, .. } => kept[child] = (u + 1, o),
            Node::Operator { left, right, .. } => {
                kept[left] = (u, o + usize::from(always[right]));
                kept[right] = (u, o + usize::from(always[left]));
            }
            Node::Primitive(_) => {
                if u + o > worst.map_or(MAX_UNPRUNED_DEPTH, |((u, o), _)| u + o) {
                    worst = Some((kept[i], i));
                }
            }
        }
    }
    let Some(((u, o), i)) = worst else { return Ok(()) };
    let what = match o {
        0 => format!("{u} unary nodes above this primitive run"),
        _ => format!("{} nodes above this primitive run ({u} unary nodes, {o} operators whose other operand holds a plane)", u + o),
    };
    Err(SceneError::at(
        name(i),
        "",
        format!(
            "{what} at every step of a ray near it, above the limit of {MAX_UNPRUNED_DEPTH} (a pixel's steps share {LOOP_LIMIT} loop iterations on the GPU); \
             use fewer (offsets in a row already count as one)"
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Builder, Primitive, Shape};

    fn chain(ops: &[Unary]) -> Scene {
        let mut b = Builder::default();
        let mut n = b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }));
        for &op in ops {
            n = b.unary(op, n);
        }
        b.finish(n).unwrap()
    }

    #[test]
    fn offsets_add_up_and_zero_offsets_vanish() {
        let off = |d| Unary::Offset { distance: d };
        let f = fold(&chain(&[off(0.25), off(0.0), off(0.5), Unary::Shell { thickness: 0.1 }, off(0.05)])).unwrap();
        assert_eq!(f.scene.nodes().len(), 3);
        assert_eq!(f.scene.nodes()[1], Node::Unary { op: off(0.75), child: 0 });
        assert_eq!(f.scene.nodes()[2], Node::Unary { op: Unary::Shell { thickness: 0.2 }, child: 1 });
        assert_eq!(f.origin, [0, 3, 5]);
        // A chain that adds up to nothing leaves the primitive alone.
        let f = fold(&chain(&[off(0.5), off(-0.5)])).unwrap();
        assert_eq!((f.scene.nodes().len(), f.scene.root(), f.origin.clone()), (1, 0, vec![0]));
        assert!(fold(&chain(&[off(0.5), Unary::Shell { thickness: 0.1 }])).is_none());
    }

    #[test]
    fn folded_chains_evaluate_as_the_scene() {
        let ops = [
            Unary::Displace { amplitude: 0.1, frequency: 2.0 },
            Unary::Displace { amplitude: 0.2, frequency: 2.0 },
            Unary::Infill { period: 0.5, thickness: 0.1 },
            Unary::Infill { period: 0.5, thickness: 0.1 },
            Unary::Offset { distance: -0.3 },
            Unary::Shell { thickness: 0.4 },
            Unary::Offset { distance: 0.1 },
        ];
        let s = chain(&ops);
        let f = fold(&s).unwrap();
        assert_eq!(f.scene.nodes().len(), 5);
        for p in [[0.3, -0.2, 0.9], [1.1, 0.0, 0.2], [0.0, 0.0, 0.0]] {
            let (a, b) = (s.eval(p), f.scene.eval(p));
            assert!((a - b).abs() < 1e-12, "{a} vs {b} at {p:?}");
        }
    }
}

//! Blobtree scenes (Zanni et al. 2024): a tree of primitives, binary
//! operators and unary nodes kept as data, so thousands of primitives need no shader
//! compilation, and evaluated sparsely, so the cost at a point follows the
//! primitives that matter there, not the size of the tree.
//!
//! The CPU side, in pipeline order:
//! - this module: the model ([`Scene`], [`Node`], [`Primitive`], [`Operator`],
//!   [`Unary`]), validated on construction, with the node types in
//!   `primitive`, `profile` (2D cross-sections), `grid` (voxel grids
//!   read from files), `operator` and `unary`;
//! - [`mod@format`]: the `.scene.json` file (docs/scene-format.md);
//! - `eval`: f64 reference evaluation, full and masked (inactive
//!   primitives are a missing operand ∅);
//! - `roi`: ranges of interest, augmented bounding volumes, Lipschitz
//!   bounds;
//! - [`linear`], `rows`, `patch`: the post-order buffers the GPU reads,
//!   their parameter rows, edits in place; `fold`: chains of unary nodes
//!   merged for them, and the depth the GPU evaluates; `extent`: how far
//!   out a scene may reach;
//! - `sparse`: the sparse bottom-up traversal, the GPU's oracle;
//! - `generate`: the paper's synthetic scenes (Fig. 16, Fig. 18);
//! - `formula`: the same field as formula text, for the compiled path;
//!   `lower` and `frame`: a formula of distance forms as a scene.
//!
//! ```
//! use isotrace::scene::{Builder, Operator, Primitive, Shape};
//! let mut b = Builder::default();
//! let s = b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }));
//! let c = b.primitive(Primitive::new(Shape::Box { half: [0.5, 0.5, 2.0] }).translated([1.0, 0.0, 0.0]));
//! let root = b.operator(Operator::UNION, s, c);
//! let scene = b.finish(root).unwrap();
//! assert_eq!(scene.eval([0.0, 0.0, 0.0]), -1.0);
//! ```

pub(crate) mod blob;
pub(crate) mod codes;
pub(crate) mod eval;
pub(crate) mod extent;
pub(crate) mod fold;
pub mod format;
pub(crate) mod placement;
pub(crate) mod formula;
internal_mod!(generate);
pub(crate) mod grid;
pub(crate) mod leaf;
pub mod linear;
pub(crate) mod lower;
internal_mod!(operator);
pub(crate) mod patch;
pub(crate) mod primitive;
pub(crate) mod profile;
pub(crate) mod reach;
pub(crate) mod roi;
pub(crate) mod rows;
pub(crate) mod sparse;
pub(crate) mod unary;
pub(crate) mod warp;

pub use leaf::FormulaLeaf;
pub use lower::{from_formula, NotBlobtree};
pub use operator::{Blend, Join, OpKind, Operator};
pub use primitive::{Primitive, Rotation, Shape, ShapeKind, Transform};
pub use profile::Profile;
pub use crate::sdf::unary::UnaryType;
pub use unary::Unary;

use std::collections::BTreeMap;

/// The most nodes a scene may have. The linear form keeps a node's parent
/// in 22 bits and uses the node count itself as "no parent", so any count
/// up to 2²² − 1 would fit; 4,000,000 is the round number below it.
pub const MAX_NODES: usize = 4_000_000;

/// The deepest tree accepted, in nodes from the root to a leaf. Every
/// algorithm here is iterative (a left comb of 111,110 primitives is 111,110
/// deep), so depth is limited only by the node count; what the GPU needs
/// bounded is the evaluation stack (`linear::MAX_STACK`) and the nodes
/// above a primitive that no pruned view leaves out, unary ones mostly
/// (`fold::MAX_UNPRUNED_DEPTH`, after merging chains of them).
pub const MAX_DEPTH: usize = MAX_NODES;

/// A node's index in [`Scene::nodes`].
pub type NodeId = usize;

/// A node of the tree.
#[derive(Debug, Clone, PartialEq)]
pub enum Node {
    /// A leaf.
    Primitive(Primitive),
    /// A binary operator over two other nodes.
    Operator {
        /// The operation.
        op: Operator,
        /// The left operand (the minuend of a difference).
        left: NodeId,
        /// The right operand.
        right: NodeId,
    },
    /// A function of one operand's value (offset, shell, infill, displace).
    Unary {
        /// The operation.
        op: Unary,
        /// The operand.
        child: NodeId,
    },
}

impl Node {
    /// The operands in order (left before right): none, one or two.
    pub fn children(&self) -> Children {
        match *self {
            Node::Primitive(_) => Children { ids: [0; 2], len: 0 },
            Node::Operator { left, right, .. } => Children { ids: [left, right], len: 2 },
            Node::Unary { child, .. } => Children { ids: [child, 0], len: 1 },
        }
    }
}

/// A node's operands, without an allocation.
#[derive(Debug, Clone, Copy)]
pub struct Children {
    ids: [NodeId; 2],
    len: usize,
}

impl std::ops::Deref for Children {
    type Target = [NodeId];
    fn deref(&self) -> &[NodeId] {
        &self.ids[..self.len]
    }
}

/// An invalid scene: the JSON path of the bad value and what is wrong
/// (`nodes[812].radius: must be > 0`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{path}: {reason}")]
pub struct SceneError {
    /// `nodes[812].radius`, `root`, `nodes`.
    pub path: String,
    /// What is wrong.
    pub reason: String,
}

impl SceneError {
    /// An error at `path`.
    pub fn new(path: impl Into<String>, reason: impl Into<String>) -> SceneError {
        SceneError { path: path.into(), reason: reason.into() }
    }

    /// An error at field `field` of node `i` (`field` may be empty: the node itself).
    pub fn at(i: usize, field: &str, reason: impl Into<String>) -> SceneError {
        let path = if field.is_empty() { format!("nodes[{i}]") } else { format!("nodes[{i}].{field}") };
        SceneError { path, reason: reason.into() }
    }
}

/// A valid scene: every parameter checked, and the nodes form one tree
/// (each node has at most one parent, every node is reachable from the root,
/// no cycles). Nodes may be stored in any order.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    nodes: Vec<Node>,
    root: NodeId,
    /// Children before parents, left subtree before right (post-order).
    post: Vec<NodeId>,
}

impl Scene {
    /// Validates `nodes` and `root` into a scene.
    pub fn new(nodes: Vec<Node>, root: NodeId) -> Result<Scene, SceneError> {
        let n = nodes.len();
        if n == 0 {
            return Err(SceneError::new("nodes", "a scene needs at least one node"));
        }
        if n > MAX_NODES {
            return Err(SceneError::new("nodes", format!("{n} nodes, above the limit of {MAX_NODES}")));
        }
        if root >= n {
            return Err(SceneError::new("root", format!("refers to nodes[{root}], but the scene has {n} nodes")));
        }
        for (i, node) in nodes.iter().enumerate() {
            check_node(i, node, n)?;
        }
        let parent = parents(&nodes, root)?;
        let post = post_order(&nodes, root);
        if post.len() < n {
            return Err(unreachable(&parent, &post, root, n));
        }
        let mut scene = Scene { nodes, root, post };
        scene.fit_warps();
        Ok(scene)
    }

    /// Clamps every warped primitive for its range of interest
    /// ([`warp::fit`]): a scene's field is defined with the clamps.
    fn fit_warps(&mut self) {
        let warped = |n: &Node| matches!(n, Node::Primitive(p) if p.warp.is_some());
        if !self.nodes.iter().any(warped) {
            return;
        }
        let roi = roi::ranges(self);
        for (i, n) in self.nodes.iter_mut().enumerate() {
            if let Node::Primitive(p) = n {
                p.warp = warp::fit(p, roi[i].hi);
            }
        }
    }

    /// The nodes, in their stored order.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The root's index.
    pub fn root(&self) -> NodeId {
        self.root
    }

    /// Every node, children before parents, left subtree before right.
    pub fn post_order(&self) -> &[NodeId] {
        &self.post
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Never true: a scene has at least one node.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Number of primitives.
    pub fn primitive_count(&self) -> usize {
        self.nodes.iter().filter(|n| matches!(n, Node::Primitive(_))).count()
    }

    /// The longest root-to-leaf path, in nodes (a lone primitive: 1).
    pub fn depth(&self) -> usize {
        let mut depth = vec![0usize; self.nodes.len()];
        depth[self.root] = 1;
        let mut max = 1;
        for &i in self.post.iter().rev() {
            for &c in self.nodes[i].children().iter() {
                depth[c] = depth[i] + 1;
                max = max.max(depth[i] + 1);
            }
        }
        max
    }

    /// Counts by type, for reports.
    pub fn summary(&self) -> Summary {
        let mut s = Summary { nodes: self.nodes.len(), depth: self.depth(), ..Summary::default() };
        for n in &self.nodes {
            match n {
                Node::Primitive(p) => {
                    s.primitives += 1;
                    *s.shapes.entry(p.shape.kind().name()).or_default() += 1;
                }
                Node::Operator { op, .. } => {
                    s.operators += 1;
                    *s.ops.entry(op.name()).or_default() += 1;
                }
                Node::Unary { op, .. } => {
                    s.operators += 1;
                    *s.ops.entry(op.kind().name()).or_default() += 1;
                }
            }
        }
        s
    }
}

/// Counts of a scene by type.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Summary {
    /// All nodes.
    pub nodes: usize,
    /// Leaves.
    pub primitives: usize,
    /// Operators, binary and unary.
    pub operators: usize,
    /// Longest root-to-leaf path, in nodes.
    pub depth: usize,
    /// Primitives per type name.
    pub shapes: BTreeMap<&'static str, usize>,
    /// Operators (binary and unary) per type name.
    pub ops: BTreeMap<&'static str, usize>,
}

fn check_node(i: usize, node: &Node, n: usize) -> Result<(), SceneError> {
    match node {
        Node::Primitive(p) => p.check().map_err(|(field, reason)| SceneError::at(i, &field, reason)),
        Node::Operator { op, left, right } => {
            op.check().map_err(|(field, reason)| SceneError::at(i, &field, reason))?;
            for (field, c) in [("left", *left), ("right", *right)] {
                if c >= n {
                    return Err(SceneError::at(i, field, format!("refers to nodes[{c}], but the scene has {n} nodes")));
                }
                if c == i {
                    return Err(SceneError::at(i, field, "refers to the node itself"));
                }
            }
            if left == right {
                return Err(SceneError::at(i, "right", format!("nodes[{right}] is already the left operand")));
            }
            Ok(())
        }
        Node::Unary { op, child } => {
            op.check().map_err(|(field, reason)| SceneError::at(i, &field, reason))?;
            if *child >= n {
                return Err(SceneError::at(i, "child", format!("refers to nodes[{child}], but the scene has {n} nodes")));
            }
            if *child == i {
                return Err(SceneError::at(i, "child", "refers to the node itself"));
            }
            Ok(())
        }
    }
}

/// The field name of operand `k` of `node` in a scene file.
fn operand_field(node: &Node, k: usize) -> &'static str {
    match node {
        Node::Unary { .. } => "child",
        _ => ["left", "right"][k],
    }
}

/// Each node's parent; errors for a node with two parents or a root with one.
fn parents(nodes: &[Node], root: NodeId) -> Result<Vec<Option<NodeId>>, SceneError> {
    let mut parent: Vec<Option<NodeId>> = vec![None; nodes.len()];
    for (i, node) in nodes.iter().enumerate() {
        for (k, &c) in node.children().iter().enumerate() {
            let field = operand_field(node, k);
            {
                if c == root {
                    return Err(SceneError::at(i, field, format!("refers to the root, nodes[{root}]")));
                }
                if let Some(p) = parent[c] {
                    return Err(SceneError::at(i, field, format!("nodes[{c}] is already an operand of nodes[{p}] (a node has one parent)")));
                }
                parent[c] = Some(i);
            }
        }
    }
    Ok(parent)
}

/// The nodes reachable from `root`, in post-order (iterative: trees may be
/// deep). Assumes each node has at most one parent, so it terminates.
fn post_order(nodes: &[Node], root: NodeId) -> Vec<NodeId> {
    let mut out = Vec::with_capacity(nodes.len());
    let mut stack = vec![(root, false)];
    while let Some((i, expanded)) = stack.pop() {
        let children = nodes[i].children();
        if expanded || children.is_empty() {
            out.push(i);
        } else {
            stack.push((i, true));
            stack.extend(children.iter().rev().map(|&c| (c, false)));
        }
    }
    out
}

/// The error for the first node not reached from the root: on a cycle
/// (following parents leads back to it), or detached.
fn unreachable(parent: &[Option<NodeId>], post: &[NodeId], root: NodeId, n: usize) -> SceneError {
    let mut seen = vec![false; n];
    for &i in post {
        seen[i] = true;
    }
    let u = (0..n).find(|&i| !seen[i]).expect("a node was not reached");
    let mut m = u;
    for _ in 0..n {
        match parent[m] {
            Some(p) if p == u => return SceneError::at(u, "", "is on a cycle (it is its own descendant)"),
            Some(p) => m = p,
            None => break,
        }
    }
    SceneError::at(u, "", format!("is not reachable from the root, nodes[{root}]"))
}

/// Builds a scene node by node: operands before the operators that use them.
#[derive(Debug, Clone, Default)]
pub struct Builder {
    nodes: Vec<Node>,
}

impl Builder {
    /// Adds a primitive.
    pub fn primitive(&mut self, p: Primitive) -> NodeId {
        self.nodes.push(Node::Primitive(p));
        self.nodes.len() - 1
    }

    /// Adds `op(child)`.
    pub fn unary(&mut self, op: Unary, child: NodeId) -> NodeId {
        self.nodes.push(Node::Unary { op, child });
        self.nodes.len() - 1
    }

    /// Adds `op(left, right)`.
    pub fn operator(&mut self, op: Operator, left: NodeId, right: NodeId) -> NodeId {
        self.nodes.push(Node::Operator { op, left, right });
        self.nodes.len() - 1
    }

    /// Combines `items` as a left comb, `op(op(op(i0, i1), i2), …)`, the
    /// shape whose evaluation stack stays at 2 values whatever the count.
    ///
    /// # Panics
    /// If `items` is empty.
    pub fn fold(&mut self, op: Operator, items: &[NodeId]) -> NodeId {
        let mut acc = items[0];
        for &i in &items[1..] {
            acc = self.operator(op, acc, i);
        }
        acc
    }

    /// Nodes so far.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// No nodes yet.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The scene rooted at `root`, validated.
    pub fn finish(self, root: NodeId) -> Result<Scene, SceneError> {
        Scene::new(self.nodes, root)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere() -> Node {
        Node::Primitive(Primitive::new(Shape::Sphere { radius: 1.0 }))
    }
    fn op(left: usize, right: usize) -> Node {
        Node::Operator { op: Operator::UNION, left, right }
    }

    #[test]
    fn structure_errors_name_the_node() {
        let e = |nodes: Vec<Node>, root| Scene::new(nodes, root).unwrap_err().to_string();
        assert_eq!(e(vec![], 0), "nodes: a scene needs at least one node");
        assert_eq!(e(vec![sphere()], 1), "root: refers to nodes[1], but the scene has 1 nodes");
        assert_eq!(e(vec![sphere(), op(0, 5)], 1), "nodes[1].right: refers to nodes[5], but the scene has 2 nodes");
        assert_eq!(e(vec![sphere(), op(0, 0)], 1), "nodes[1].right: nodes[0] is already the left operand");
        assert_eq!(e(vec![sphere(), op(0, 1)], 1), "nodes[1].right: refers to the node itself");
        assert_eq!(e(vec![sphere(), sphere(), op(0, 1), op(0, 2)], 3), "nodes[3].left: nodes[0] is already an operand of nodes[2] (a node has one parent)");
        assert_eq!(e(vec![sphere(), sphere(), op(0, 1)], 0), "nodes[2].left: refers to the root, nodes[0]");
        assert_eq!(e(vec![sphere(), sphere(), op(0, 1), sphere()], 2), "nodes[3]: is not reachable from the root, nodes[2]");
        // 3 and 4 form a cycle beside the tree 0-1-2.
        let nodes = vec![sphere(), sphere(), op(0, 1), op(4, 5), op(3, 6), sphere(), sphere()];
        assert_eq!(e(nodes, 2), "nodes[3]: is on a cycle (it is its own descendant)");
    }

    #[test]
    fn post_order_and_depth() {
        let s = Scene::new(vec![op(1, 2), sphere(), op(3, 4), sphere(), sphere()], 0).unwrap();
        assert_eq!(s.post_order(), &[1, 3, 4, 2, 0]);
        assert_eq!(s.depth(), 3);
        let sum = s.summary();
        assert_eq!((sum.nodes, sum.primitives, sum.operators), (5, 3, 2));
        assert_eq!(sum.shapes["sphere"], 3);
    }
}

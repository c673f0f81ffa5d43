//! f64 reference evaluation of a scene: the whole tree at a point, and the
//! masked tree, where inactive primitives are a missing operand ∅ and each
//! operator applies the selection rules of [`super::Operator::select`].
//!
//! The masked value is what the sparse traversal (`sparse.rs`) and the GPU
//! must reproduce bit for bit; the full value is what the masked one must
//! equal wherever the ranges of interest say so (`roi.rs`). Both walk the
//! stored post-order, so deep trees need no recursion.

use super::{Node, Scene};

impl Scene {
    /// The field at `p`.
    pub fn eval(&self, p: [f64; 3]) -> f64 {
        self.eval_nodes(p)[self.root()]
    }

    /// What one [`Scene::eval`] costs, in node evaluations: a formula
    /// leaf's operations count as nodes each.
    pub fn eval_cost(&self) -> usize {
        let leaf_ops = |n: &Node| match n {
            Node::Primitive(p) => match &p.shape {
                super::Shape::Formula(f) => f.ir.live().len(),
                _ => 0,
            },
            _ => 0,
        };
        self.nodes().iter().map(|n| 1 + leaf_ops(n)).sum()
    }

    /// Every node's value at `p`, indexed by node.
    pub fn eval_nodes(&self, p: [f64; 3]) -> Vec<f64> {
        let nodes = self.nodes();
        let mut v = vec![0.0; nodes.len()];
        for &i in self.post_order() {
            v[i] = match &nodes[i] {
                Node::Primitive(prim) => prim.distance(p),
                Node::Operator { op, left, right } => op.apply(v[*left], v[*right]),
                Node::Unary { op, child } => op.apply(v[*child], p),
            };
        }
        v
    }

    /// The field at `p` with only the primitives `active[i]` present
    /// (`active` is indexed by node; operators' entries are ignored).
    /// `None` is ∅: no active primitive decides the value here.
    pub fn eval_masked(&self, p: [f64; 3], active: &[bool]) -> Option<f64> {
        self.eval_masked_nodes(p, active)[self.root()]
    }

    /// Every node's masked value at `p`, indexed by node.
    pub fn eval_masked_nodes(&self, p: [f64; 3], active: &[bool]) -> Vec<Option<f64>> {
        let nodes = self.nodes();
        let mut v = vec![None; nodes.len()];
        for &i in self.post_order() {
            v[i] = match &nodes[i] {
                Node::Primitive(prim) => active[i].then(|| prim.distance(p)),
                Node::Operator { op, left, right } => op.select(v[*left], v[*right]),
                // A missing operand is above its range, so the node is above its own.
                Node::Unary { op, child } => v[*child].map(|c| op.apply(c, p)),
            };
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::{Builder, Operator, Primitive, Shape};

    #[test]
    fn masked_union_keeps_the_present_operand_and_intersection_drops_both() {
        let mut b = Builder::default();
        let s = b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }));
        let c = b.primitive(Primitive::new(Shape::Sphere { radius: 1.0 }).translated([3.0, 0.0, 0.0]));
        let u = b.operator(Operator::UNION, s, c);
        let scene = b.finish(u).unwrap();
        assert_eq!(scene.eval([0.0; 3]), -1.0);
        assert_eq!(scene.eval_masked([0.0; 3], &[false, true, false]), Some(2.0));
        assert_eq!(scene.eval_masked([0.0; 3], &[false, false, false]), None);
    }
}

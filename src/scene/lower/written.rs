//! Distances written out, as a program writes a point cloud or a union of
//! balls: `sqrt((x - a)^2 + (y - b)^2 + (z - c)^2) - r` is a ball,
//! `max(abs(x - a) - bx, abs(y - b) - by, abs(z - c) - bz)` a box in the
//! max norm (`maxbox`), and a `min` or `max` of shapes is their union or
//! intersection (the same fields: a ball's distance is that formula, and a
//! sharp union is the min of its operands). Anything else stays refused as
//! before.

use super::{not, NotBlobtree, Tree, Val, Walker};
use crate::diag::Span;
use crate::scene::{OpKind, Operator, Primitive, Shape, Transform};
use crate::syntax::ast::{BinOp, Call, Expr, ExprKind};
use std::rc::Rc;

impl Walker<'_> {
    /// `a - b` (at `span`) as a ball's distance, a sphere moved to its
    /// centre; `None` where it is not one.
    pub(super) fn ball(&mut self, a: &Expr, b: &Expr, span: Span) -> Option<Val> {
        let (center, radius) = self.ball_of(a, b)?;
        let leaf = Rc::new(Tree::Leaf(Primitive::new(Shape::Sphere { radius }), span));
        Some(Val::Shape(Rc::new(Tree::Moved(Transform { translate: center, ..Transform::default() }, leaf))))
    }

    /// The centre and radius (r > 0) of `a - b` as a ball's distance.
    fn ball_of(&mut self, a: &Expr, b: &Expr) -> Option<([f64; 3], f64)> {
        let ExprKind::Call(root) = &a.kind else { return None };
        if root.name != "sqrt" || root.args.len() != 1 {
            return None;
        }
        let mut terms = vec![];
        sum_terms(&root.args[0], &mut terms);
        let mut center: [Option<f64>; 3] = [None; 3];
        for t in terms {
            let ExprKind::Binary(BinOp::Pow, base, two) = &t.kind else { return None };
            if !matches!(two.kind, ExprKind::Number(v) if v == 2.0) {
                return None;
            }
            let (axis, at) = self.offset(base)?;
            if center[axis].replace(at).is_some() {
                return None;
            }
        }
        let radius = self.value(b)?;
        let center = [center[0]?, center[1]?, center[2]?];
        (radius > 0.0 && radius.is_finite() && center.iter().all(|c| c.is_finite())).then_some((center, radius))
    }

    /// `v`, `v - k`, `v + k`, `k - v` or `k + v` for a coordinate v: its
    /// axis and the k at which the square is 0.
    fn offset(&mut self, e: &Expr) -> Option<(usize, f64)> {
        let axis = |e: &Expr| match &e.kind {
            ExprKind::Name(n) if !self.defs.contains_key(n.as_str()) => ["x", "y", "z"].iter().position(|v| v == n),
            _ => None,
        };
        if let Some(k) = axis(e) {
            return Some((k, 0.0));
        }
        let ExprKind::Binary(op @ (BinOp::Add | BinOp::Sub), l, r) = &e.kind else { return None };
        match (axis(l), axis(r), op) {
            (Some(k), None, BinOp::Sub) => Some((k, self.value(r)?)),
            (Some(k), None, BinOp::Add) => Some((k, -self.value(r)?)),
            (None, Some(k), _) => {
                let v = self.value(l)?;
                Some((k, if *op == BinOp::Sub { v } else { -v }))
            }
            _ => None,
        }
    }

    /// A number, or `None` (not an error) where `e` is not one.
    fn value(&mut self, e: &Expr) -> Option<f64> {
        match self.eval(e) {
            Ok(Val::Num(v)) => Some(v),
            _ => None,
        }
    }

    /// `max(abs(X - a) - bx, abs(Y - b) - by, abs(Z - c) - bz)`, the axes in
    /// any order, each once (b > 0): a `maxbox` moved to (a, b, c); `None`
    /// where the call is not one.
    fn max_box(&mut self, c: &Call, span: Span) -> Option<Val> {
        if c.name != "max" || c.args.len() != 3 {
            return None;
        }
        let (mut center, mut half): ([Option<f64>; 3], [f64; 3]) = ([None; 3], [0.0; 3]);
        for arg in &c.args {
            let ExprKind::Binary(BinOp::Sub, abs, h) = &arg.kind else { return None };
            let ExprKind::Call(abs) = &abs.kind else { return None };
            if abs.name != "abs" || abs.args.len() != 1 {
                return None;
            }
            let (axis, at) = self.offset(&abs.args[0])?;
            if center[axis].replace(at).is_some() {
                return None;
            }
            half[axis] = self.value(h)?;
        }
        let center = [center[0]?, center[1]?, center[2]?];
        if !(half.iter().all(|h| *h > 0.0 && h.is_finite()) && center.iter().all(|c| c.is_finite())) {
            return None;
        }
        let leaf = Rc::new(Tree::Leaf(Primitive::new(Shape::MaxBox { half }), span));
        Some(Val::Shape(Rc::new(Tree::Moved(Transform { translate: center, ..Transform::default() }, leaf))))
    }

    /// `min(…)` / `max(…)`: of numbers a number, of shapes a union or an
    /// intersection; a box written in the max norm ([`Walker::max_box`]).
    pub(super) fn min_max(&mut self, c: &Call, span: Span) -> Result<Val, NotBlobtree> {
        if let Some(b) = self.max_box(c, span) {
            return Ok(b);
        }
        let vals: Vec<Val> = c.args.iter().map(|e| self.eval(e)).collect::<Result<_, _>>()?;
        if let Some((Val::Profile(_, span), _)) = vals.iter().zip(&c.args).find(|(v, _)| matches!(v, Val::Profile(..))) {
            return Err(not("a 2D profile is a blobtree node only inside extrude or revolve", *span));
        }
        if vals.iter().all(|v| matches!(v, Val::Num(_))) {
            let nums = vals.iter().filter_map(|v| if let Val::Num(x) = v { Some(*x) } else { None });
            let v = if c.name == "min" { nums.fold(f64::INFINITY, f64::min) } else { nums.fold(f64::NEG_INFINITY, f64::max) };
            return Ok(Val::Num(v));
        }
        let kind = if c.name == "min" { OpKind::Union } else { OpKind::Intersection };
        let mut acc: Option<Rc<Tree>> = None;
        for (v, e) in vals.into_iter().zip(&c.args) {
            let Val::Shape(t) = v else {
                return Err(not(format!("{} of a shape and a number is not a blobtree node", c.name), e.span));
            };
            acc = Some(match acc {
                None => t,
                Some(a) => Rc::new(Tree::Op(Operator::sharp(kind), a, t, span)),
            });
        }
        Ok(Val::Shape(acc.expect("min and max take at least one argument")))
    }
}

/// The terms of a sum `a + b + …` (any nesting).
fn sum_terms<'e>(e: &'e Expr, out: &mut Vec<&'e Expr>) {
    match &e.kind {
        ExprKind::Binary(BinOp::Add, a, b) => {
            sum_terms(a, out);
            sum_terms(b, out);
        }
        _ => out.push(e),
    }
}

//! The abstract syntax tree. Every node carries the [`Span`] of the text it
//! came from so later stages can point at it.

use crate::diag::Span;

/// A whole formula: definitions, then one or more surfaces.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// `name = expr;` lines, in order.
    pub definitions: Vec<Definition>,
    /// The surfaces drawn, in order (at least one).
    pub surfaces: Vec<Surface>,
}

impl Program {
    /// The first surface's function (the only one in most formulas).
    pub fn body(&self) -> &Expr {
        &self.surfaces[0].expr
    }
}

/// `expr [where cond {and cond}]`: the part of expr = 0 where every
/// condition holds (CSG by level-set conditions, Knoll et al. Fig. 9).
#[derive(Debug, Clone, PartialEq)]
pub struct Surface {
    /// The function whose zero set is drawn.
    pub expr: Expr,
    /// Conditions that restrict it.
    pub conditions: Vec<Condition>,
}

/// `lhs < rhs` or `lhs > rhs`.
#[derive(Debug, Clone, PartialEq)]
pub struct Condition {
    /// Left side.
    pub lhs: Expr,
    /// True for `<`, false for `>`.
    pub less: bool,
    /// Right side.
    pub rhs: Expr,
    /// The whole condition.
    pub span: Span,
}

/// `name = value;`
#[derive(Debug, Clone, PartialEq)]
pub struct Definition {
    /// The defined name.
    pub name: String,
    /// Where the name is written.
    pub name_span: Span,
    /// Its value.
    pub value: Expr,
}

/// Binary arithmetic operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `^`
    Pow,
}

impl BinOp {
    /// The operator as written.
    #[cfg(test)]
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Pow => "^",
        }
    }
}

/// An expression node.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// The text it covers.
    pub span: Span,
}

/// Expression variants.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)] // fields: the names say it
pub enum ExprKind {
    /// A numeric literal.
    Number(f64),
    /// A name: variable, constant, definition or parameter.
    Name(String),
    /// Unary minus (unary plus is dropped by the parser).
    Neg(Box<Expr>),
    /// `a op b`
    Binary(BinOp, Box<Expr>, Box<Expr>),
    /// `name(args…)` (boxed: keeps [`Expr`] small, and with it the
    /// parser's stack frames).
    Call(Box<Call>),
}

/// A call `name(args…)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    /// The function name.
    pub name: String,
    /// Where the name is written (the name only).
    pub name_span: Span,
    /// The arguments, in order.
    pub args: Vec<Expr>,
}

/// Dropped with an explicit stack: `x + x + … + x` is a left-deep tree as
/// tall as the chain is long, and the default recursive drop would overflow
/// a small thread stack on it.
impl Drop for Expr {
    fn drop(&mut self) {
        let leaf = |k: &ExprKind| matches!(k, ExprKind::Number(_) | ExprKind::Name(_));
        if leaf(&self.kind) {
            return;
        }
        let take = |e: &mut Expr| std::mem::replace(&mut e.kind, ExprKind::Number(0.0));
        let mut stack = vec![std::mem::replace(&mut self.kind, ExprKind::Number(0.0))];
        while let Some(kind) = stack.pop() {
            match kind {
                ExprKind::Number(_) | ExprKind::Name(_) => {}
                ExprKind::Neg(mut a) => stack.push(take(&mut a)),
                ExprKind::Binary(_, mut a, mut b) => {
                    stack.push(take(&mut a));
                    stack.push(take(&mut b));
                }
                ExprKind::Call(mut c) => stack.extend(c.args.iter_mut().map(take)),
            }
        }
    }
}

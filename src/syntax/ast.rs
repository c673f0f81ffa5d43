//! The abstract syntax tree. Every node carries the [`Span`] of the text it
//! came from so later stages can point at it.

use crate::diag::Span;

/// A whole formula: definitions, then the implicit function.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// `name = expr;` lines, in order.
    pub definitions: Vec<Definition>,
    /// The function whose zero set is drawn.
    pub body: Expr,
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
    /// `name(args…)`; `name_span` points at the name only.
    Call { name: String, name_span: Span, args: Vec<Expr> },
}

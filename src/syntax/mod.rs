//! Formula text → AST: lexer, recursive-descent parser and the syntax errors
//! they report. The parser follows `grammar/formula.ebnf` rule by rule.

pub mod ast;
pub mod lexer;
pub mod parser;

pub use ast::{BinOp, Expr, ExprKind, Program};
pub use parser::parse;

/// The names of the numeric functions, for suggestions and help (the
/// distance-field forms are listed by [`crate::sdf::FORMS`]).
pub fn function_names() -> Vec<&'static str> {
    let mut v: Vec<&str> = crate::ir::Func1::ALL.iter().map(|f| f.name()).collect();
    v.extend(["pow", "atan2", "min", "max", "clamp", "mix"]);
    v
}

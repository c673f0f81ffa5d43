//! Formula text → AST: lexer, recursive-descent parser and the syntax errors
//! they report. The parser follows `grammar/formula.ebnf` rule by rule.

pub mod ast;
pub mod lexer;
pub mod parser;

pub use ast::{BinOp, Call, Definition, Expr, ExprKind, Program};
pub use parser::{parse, SyntaxError};

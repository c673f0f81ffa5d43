//! Recursive-descent parser: one function per rule of `grammar/formula.ebnf`.
//!
//! The parser stops at the first error (isotrace is a CLI: one excellent
//! diagnostic beats a cascade). Nesting is bounded by [`MAX_DEPTH`] so that
//! 100,000 nested parentheses give an error, not a stack overflow.

use super::ast::{BinOp, Definition, Expr, ExprKind, Program};
use super::lexer::{lex, LexError, Tok, Token};
use crate::diag::{Diagnostic, Span};

/// Deepest nesting of parentheses / unary operators / calls accepted.
pub const MAX_DEPTH: usize = 200;
/// Largest formula accepted, in bytes.
pub const MAX_SOURCE_BYTES: usize = 64 * 1024;

/// Everything that can go wrong while parsing.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)] // fields: the names say it
pub enum SyntaxError {
    /// A lexical error.
    Lex(LexError),
    /// `expected X, found 'Y'`.
    Expected { expected: String, found: String, span: Span, hint: Option<String> },
    /// An opening parenthesis that is never closed.
    Unclosed { open: Span, found: String, span: Span },
    /// A `)` with no matching `(`.
    UnmatchedClose { span: Span },
    /// Nothing but whitespace and comments.
    Empty { span: Span },
    /// Nesting beyond [`MAX_DEPTH`].
    TooDeep { span: Span },
    /// Source beyond [`MAX_SOURCE_BYTES`].
    TooLarge { bytes: usize },
}

impl SyntaxError {
    /// Converts to the shared diagnostic form.
    pub fn to_diagnostic(&self) -> Diagnostic {
        match self {
            SyntaxError::Lex(LexError::BadChar { ch, span }) => {
                let what = if ch.is_ascii_control() { "control character" } else { "non-ASCII character" };
                Diagnostic::error(format!("{what} {:?} in formula", ch), *span, "not allowed here")
                    .with_note("formulas are plain ASCII: use `pi` for π, `*` for ×, `^2` for ²")
            }
            SyntaxError::Lex(LexError::Unexpected { ch, span }) => {
                Diagnostic::error(format!("unexpected character '{ch}'"), *span, "no token starts with this")
            }
            SyntaxError::Lex(LexError::InvalidNumber { text, span }) => {
                Diagnostic::error(format!("invalid number '{text}'"), *span, "not a number")
                    .with_note("numbers look like 2, 0.5, .5, 1e-3 or 2.5E+4")
            }
            SyntaxError::Expected { expected, found, span, hint } => {
                let d = Diagnostic::error(format!("expected {expected}, found {found}"), *span, format!("expected {expected}"));
                match hint {
                    Some(h) => d.with_note(h.clone()),
                    None => d,
                }
            }
            SyntaxError::Unclosed { open, found, span } => {
                Diagnostic::error(format!("unbalanced parenthesis: expected ')', found {found}"), *span, "expected ')'")
                    .with_label(*open, "this '(' is never closed")
            }
            SyntaxError::UnmatchedClose { span } => {
                Diagnostic::error("unbalanced parenthesis: ')' without a matching '('", *span, "no '(' before this")
            }
            SyntaxError::Empty { span } => Diagnostic::error("empty formula", *span, "expected an expression")
                .with_note("a formula is an expression in x, y, z such as `x^2 + y^2 + z^2 - 1`"),
            SyntaxError::TooDeep { span } => {
                Diagnostic::error(format!("formula nested too deeply (more than {MAX_DEPTH} levels)"), *span, "too deep here")
                    .with_note("name a sub-expression with a definition `a = ...;` to flatten it")
            }
            SyntaxError::TooLarge { bytes } => Diagnostic::plain(format!(
                "formula too large: {bytes} bytes (the limit is {MAX_SOURCE_BYTES} bytes)"
            )),
        }
    }
}

/// Parses a whole program.
pub fn parse(src: &str) -> Result<Program, SyntaxError> {
    if src.len() > MAX_SOURCE_BYTES {
        return Err(SyntaxError::TooLarge { bytes: src.len() });
    }
    let tokens = lex(src).map_err(SyntaxError::Lex)?;
    let mut p = Parser { src, tokens, pos: 0, depth: 0 };
    p.program()
}

struct Parser<'a> {
    src: &'a str,
    tokens: Vec<Token>,
    pos: usize,
    depth: usize,
}

impl Parser<'_> {
    fn current(&self) -> &Token {
        &self.tokens[self.pos]
    }
    fn at(&self, t: &Tok) -> bool {
        std::mem::discriminant(&self.current().tok) == std::mem::discriminant(t)
    }
    fn nth(&self, n: usize) -> &Tok {
        &self.tokens[(self.pos + n).min(self.tokens.len() - 1)].tok
    }
    fn bump(&mut self) -> Token {
        let t = self.tokens[self.pos].clone();
        if self.pos + 1 < self.tokens.len() {
            self.pos += 1;
        }
        t
    }
    fn found(&self) -> String {
        let t = self.current();
        t.tok.describe(&self.src[t.span.range()])
    }
    fn expected(&self, what: &str) -> SyntaxError {
        let t = self.current();
        if t.tok == Tok::RParen && what != "')'" {
            // A stray ')' is reported as an unbalanced parenthesis only when
            // nothing is open; inside a group the generic message is clearer.
            if self.depth == 0 {
                return SyntaxError::UnmatchedClose { span: t.span };
            }
        }
        let hint = match (&t.tok, what) {
            (Tok::Ident(_) | Tok::Number(_) | Tok::LParen, "an operator or end of formula") => {
                Some("write `*` for a product: `2*x`, not `2x`".to_string())
            }
            (Tok::Eq, _) => Some("definitions look like `name = expression;` before the formula".to_string()),
            _ => None,
        };
        SyntaxError::Expected { expected: what.to_string(), found: self.found(), span: t.span, hint }
    }
    fn enter(&mut self) -> Result<(), SyntaxError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(SyntaxError::TooDeep { span: self.current().span });
        }
        Ok(())
    }

    /// program = { definition } expression EOF
    fn program(&mut self) -> Result<Program, SyntaxError> {
        if self.at(&Tok::Eof) {
            return Err(SyntaxError::Empty { span: self.current().span });
        }
        let mut definitions = Vec::new();
        while matches!(self.current().tok, Tok::Ident(_)) && *self.nth(1) == Tok::Eq {
            definitions.push(self.definition()?);
        }
        if self.at(&Tok::Eof) {
            return Err(SyntaxError::Expected {
                expected: "an expression after the definitions".into(),
                found: self.found(),
                span: self.current().span,
                hint: Some("the last part of a formula is the function to draw, without `name =` and `;`".into()),
            });
        }
        let body = self.expression()?;
        if !self.at(&Tok::Eof) {
            if self.at(&Tok::Semi) {
                let t = self.current();
                return Err(SyntaxError::Expected {
                    expected: "end of formula".into(),
                    found: "';'".into(),
                    span: t.span,
                    hint: Some("only definitions `name = expression;` end with ';'".into()),
                });
            }
            return Err(self.expected("an operator or end of formula"));
        }
        Ok(Program { definitions, body })
    }

    /// definition = IDENT "=" expression ";"
    fn definition(&mut self) -> Result<Definition, SyntaxError> {
        let name_tok = self.bump();
        let Tok::Ident(name) = name_tok.tok else { unreachable!("definition starts with a name") };
        self.bump(); // '='
        let value = self.expression()?;
        if !self.at(&Tok::Semi) {
            return Err(if self.at(&Tok::Eof) {
                SyntaxError::Expected {
                    expected: "';' after the definition".into(),
                    found: self.found(),
                    span: self.current().span,
                    hint: Some(format!("`{name} = ...;` defines a name; the formula to draw follows it")),
                }
            } else {
                self.expected("an operator or ';'")
            });
        }
        self.bump();
        Ok(Definition { name, name_span: name_tok.span, value })
    }

    /// expression = sum
    fn expression(&mut self) -> Result<Expr, SyntaxError> {
        self.sum()
    }

    /// sum = product { ("+" | "-") product }
    fn sum(&mut self) -> Result<Expr, SyntaxError> {
        self.left_assoc(&[(Tok::Plus, BinOp::Add), (Tok::Minus, BinOp::Sub)], Self::product)
    }

    /// product = unary { ("*" | "/") unary }
    fn product(&mut self) -> Result<Expr, SyntaxError> {
        self.left_assoc(&[(Tok::Star, BinOp::Mul), (Tok::Slash, BinOp::Div)], Self::unary)
    }

    /// One left-associative precedence level.
    fn left_assoc(
        &mut self,
        ops: &[(Tok, BinOp)],
        next: fn(&mut Self) -> Result<Expr, SyntaxError>,
    ) -> Result<Expr, SyntaxError> {
        let mut lhs = next(self)?;
        while let Some(op) = ops.iter().find(|(t, _)| *t == self.current().tok).map(|(_, o)| *o) {
            self.bump();
            let rhs = next(self)?;
            let span = lhs.span.to(rhs.span);
            lhs = Expr { kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)), span };
        }
        Ok(lhs)
    }

    /// unary = ("-" | "+") unary | power
    fn unary(&mut self) -> Result<Expr, SyntaxError> {
        if self.at(&Tok::Minus) || self.at(&Tok::Plus) {
            self.enter()?;
            let op = self.bump();
            let inner = self.unary()?;
            self.depth -= 1;
            if op.tok == Tok::Plus {
                return Ok(inner);
            }
            let span = op.span.to(inner.span);
            return Ok(Expr { kind: ExprKind::Neg(Box::new(inner)), span });
        }
        self.power()
    }

    /// power = primary [ "^" unary ]
    fn power(&mut self) -> Result<Expr, SyntaxError> {
        let base = self.primary()?;
        if self.at(&Tok::Caret) {
            self.enter()?;
            self.bump();
            let exp = self.unary()?;
            self.depth -= 1;
            let span = base.span.to(exp.span);
            return Ok(Expr { kind: ExprKind::Binary(BinOp::Pow, Box::new(base), Box::new(exp)), span });
        }
        Ok(base)
    }

    /// primary = NUMBER | IDENT [ "(" arguments ")" ] | "(" expression ")"
    fn primary(&mut self) -> Result<Expr, SyntaxError> {
        let t = self.current().clone();
        match t.tok {
            Tok::Number(v) => {
                self.bump();
                Ok(Expr { kind: ExprKind::Number(v), span: t.span })
            }
            Tok::Ident(name) => {
                self.bump();
                if !self.at(&Tok::LParen) {
                    return Ok(Expr { kind: ExprKind::Name(name), span: t.span });
                }
                let open = self.bump().span;
                self.enter()?;
                let args = self.arguments()?;
                let close = self.close_paren(open)?;
                self.depth -= 1;
                Ok(Expr { kind: ExprKind::Call { name, name_span: t.span, args }, span: t.span.to(close) })
            }
            Tok::LParen => {
                let open = self.bump().span;
                self.enter()?;
                let inner = self.expression()?;
                let close = self.close_paren(open)?;
                self.depth -= 1;
                Ok(Expr { kind: inner.kind, span: open.to(close) })
            }
            Tok::Eof => Err(SyntaxError::Expected {
                expected: "an expression".into(),
                found: "end of formula".into(),
                span: t.span,
                hint: Some("the formula ends after an operator".into()),
            }),
            _ => Err(self.expected("an expression")),
        }
    }

    /// arguments = expression { "," expression }
    fn arguments(&mut self) -> Result<Vec<Expr>, SyntaxError> {
        let mut args = vec![self.expression()?];
        while self.at(&Tok::Comma) {
            self.bump();
            args.push(self.expression()?);
        }
        Ok(args)
    }

    fn close_paren(&mut self, open: Span) -> Result<Span, SyntaxError> {
        if self.at(&Tok::RParen) {
            return Ok(self.bump().span);
        }
        let t = self.current();
        if t.tok == Tok::Eof || t.tok == Tok::Semi {
            return Err(SyntaxError::Unclosed { open, found: self.found(), span: t.span });
        }
        Err(SyntaxError::Expected {
            expected: "')' or an operator".into(),
            found: self.found(),
            span: t.span,
            hint: None,
        })
    }
}

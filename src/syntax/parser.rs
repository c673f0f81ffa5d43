//! Recursive-descent parser: one function per rule of `grammar/formula.ebnf`.
//!
//! The parser stops at the first error (isotrace is a CLI: one excellent
//! diagnostic beats a cascade). Nesting is bounded by [`MAX_DEPTH`] so that
//! 100,000 nested parentheses give an error, not a stack overflow.

use super::ast::{BinOp, Call, Condition, Definition, Expr, ExprKind, Program, Surface};
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
                let code = format!("U+{:04X}", *ch as u32);
                if ch.is_control() {
                    Diagnostic::error(format!("control character {code} in formula"), *span, "not allowed here")
                        .with_note("besides printable ASCII only spaces, tabs and line breaks may appear in a formula")
                } else {
                    Diagnostic::error(format!("non-ASCII character '{ch}' ({code}) in formula"), *span, "not allowed here")
                        .with_note(ascii_hint(*ch))
                }
            }
            SyntaxError::Lex(LexError::Unexpected { ch, span }) => {
                let d = Diagnostic::error(format!("unexpected character '{ch}'"), *span, "no token starts with this");
                let hint = match ch {
                    '[' | ']' | '{' | '}' => Some("group with `(` and `)`"),
                    '|' => Some("write `abs(x)` for |x|"),
                    '<' | '>' | '!' => Some("the surface is where the formula is 0: write `lhs - (rhs)`, not a comparison"),
                    _ => None,
                };
                match hint {
                    Some(h) => d.with_note(h),
                    None => d,
                }
            }
            SyntaxError::Lex(LexError::InvalidNumber { text, span }) => {
                Diagnostic::error(format!("invalid number {}", crate::diag::quote_user_text(text, crate::diag::QUOTED_CHARS)), *span, "not a number")
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

/// What to write instead of a non-ASCII character.
fn ascii_hint(ch: char) -> String {
    let instead = match ch {
        '²' => Some("^2"),
        '³' => Some("^3"),
        'π' => Some("pi"),
        '×' | '·' | '⋅' | '∙' => Some("*"),
        '÷' | '∕' => Some("/"),
        '−' | '–' | '—' => Some("-"),
        _ => None,
    };
    match instead {
        Some(a) => format!("formulas are plain ASCII: write `{a}` for {ch}"),
        None => "formulas are plain ASCII: use `pi` for π, `*` for ×, `^2` for ²".to_string(),
    }
}

/// Parses a whole program.
pub fn parse(src: &str) -> Result<Program, SyntaxError> {
    if src.len() > MAX_SOURCE_BYTES {
        return Err(SyntaxError::TooLarge { bytes: src.len() });
    }
    let tokens = lex(src).map_err(SyntaxError::Lex)?;
    let mut p = Parser { src, tokens, pos: 0, depth: 0 };
    p.program().map_err(|e| *e)
}

/// Errors are boxed inside the parser: a small `Result` keeps the frames of
/// the recursive rules small, so [`MAX_DEPTH`] levels fit in a small stack.
type PResult<T> = Result<T, Box<SyntaxError>>;

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
    /// Moves past the current token and returns its span.
    fn bump(&mut self) -> Span {
        let span = self.tokens[self.pos].span;
        if self.pos + 1 < self.tokens.len() {
            self.pos += 1;
        }
        span
    }
    fn found(&self) -> String {
        let t = self.current();
        t.tok.describe(&self.src[t.span.range()])
    }
    /// `expected X, found 'Y'` at the current token. Out of line (and cold)
    /// so that building messages costs the recursive rules no stack.
    #[cold]
    #[inline(never)]
    fn expected(&self, what: &str) -> Box<SyntaxError> {
        let t = self.current();
        if t.tok == Tok::RParen && what != "')'" {
            // A stray ')' is reported as an unbalanced parenthesis only when
            // nothing is open; inside a group the generic message is clearer.
            if self.depth == 0 {
                return Box::new(SyntaxError::UnmatchedClose { span: t.span });
            }
        }
        Box::new(SyntaxError::Expected { expected: what.to_string(), found: self.found(), span: t.span, hint: self.hint(what) })
    }
    /// A note for common mistakes at the current token.
    fn hint(&self, what: &str) -> Option<String> {
        let prev = self.pos.checked_sub(1).map(|i| &self.tokens[i].tok);
        let after_operand = what.contains("an operator");
        match (&self.current().tok, prev) {
            (Tok::Ident(_) | Tok::Number(_) | Tok::LParen, Some(Tok::Ident(f)))
                if after_operand && super::function_names().contains(&f.as_str()) =>
            {
                Some(format!("arguments go in parentheses: `{f}(x)`"))
            }
            (Tok::Ident(_) | Tok::Number(_) | Tok::LParen, _) if after_operand => {
                Some("write `*` for a product: `2*x`, not `2x`".to_string())
            }
            (Tok::Lt | Tok::Gt, _) if after_operand => Some(
                "comparisons belong in level-set conditions (`f where g < 0`); the surface itself is where the formula is 0: write `lhs - (rhs)`".to_string(),
            ),
            (Tok::Star, Some(Tok::Star)) => Some("write `^` for a power: `x^2`, not `x**2`".to_string()),
            (Tok::Eq, _) if what == "an operator or end of formula" => Some(
                "the surface is where the formula is 0: write `lhs - (rhs)` instead of an equation `lhs = rhs`".to_string(),
            ),
            (Tok::Eq, _) => Some("definitions look like `name = expression;` before the formula".to_string()),
            (Tok::Eof, _) if what == "an expression" => Some("the formula ends after an operator".to_string()),
            _ => None,
        }
    }
    /// An error with a fixed hint at the current token.
    #[cold]
    #[inline(never)]
    fn expected_hint(&self, what: &str, hint: String) -> Box<SyntaxError> {
        let t = self.current();
        Box::new(SyntaxError::Expected { expected: what.to_string(), found: self.found(), span: t.span, hint: Some(hint) })
    }
    /// One nesting level deeper; `at` is the token that opens it (an
    /// operator or a '(') and is where a too-deep error points.
    fn enter(&mut self, at: Span) -> PResult<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(Box::new(SyntaxError::TooDeep { span: at }));
        }
        Ok(())
    }

    /// program = { definition } surface { ";" surface } [ ";" ] EOF
    fn program(&mut self) -> PResult<Program> {
        if self.at(&Tok::Eof) {
            return Err(Box::new(SyntaxError::Empty { span: self.current().span }));
        }
        let mut definitions = Vec::new();
        while matches!(self.current().tok, Tok::Ident(_)) && *self.nth(1) == Tok::Eq {
            definitions.push(self.definition()?);
        }
        if self.at(&Tok::Eof) {
            return Err(self.expected_hint(
                "an expression after the definitions",
                "the last part of a formula is the function to draw, without `name =` and `;`".into(),
            ));
        }
        let mut surfaces = vec![self.surface()?];
        // `;` separates surfaces, each after a `where` clause (elsewhere only
        // definitions end with ';').
        while self.at(&Tok::Semi) && !surfaces[surfaces.len() - 1].conditions.is_empty() {
            self.bump();
            if self.at(&Tok::Eof) {
                break;
            }
            surfaces.push(self.surface()?);
        }
        if !self.at(&Tok::Eof) {
            if self.at(&Tok::Semi) {
                return Err(self.expected_hint("end of formula", "only definitions `name = expression;` end with ';'".into()));
            }
            return Err(self.expected("an operator or end of formula"));
        }
        Ok(Program { definitions, surfaces })
    }

    /// surface = expression [ "where" condition { "and" condition } ]
    fn surface(&mut self) -> PResult<Surface> {
        let expr = self.expression()?;
        let mut conditions = Vec::new();
        if self.at_keyword("where") {
            self.bump();
            conditions.push(self.condition()?);
            while self.at_keyword("and") {
                self.bump();
                conditions.push(self.condition()?);
            }
        }
        Ok(Surface { expr, conditions })
    }

    /// condition = expression ( "<" | ">" ) expression
    fn condition(&mut self) -> PResult<Condition> {
        let lhs = self.expression()?;
        let less = match self.current().tok {
            Tok::Lt => true,
            Tok::Gt => false,
            _ => return Err(self.expected("'<' or '>'")),
        };
        self.bump();
        let rhs = self.expression()?;
        let span = lhs.span.to(rhs.span);
        Ok(Condition { lhs, less, rhs, span })
    }

    fn at_keyword(&self, k: &str) -> bool {
        matches!(&self.current().tok, Tok::Ident(n) if n == k)
    }

    /// definition = IDENT "=" expression ";"
    fn definition(&mut self) -> PResult<Definition> {
        let Tok::Ident(name) = self.current().tok.clone() else { unreachable!("definition starts with a name") };
        let name_span = self.bump();
        self.bump(); // '='
        let value = self.expression()?;
        if !self.at(&Tok::Semi) {
            return Err(if self.at(&Tok::Eof) {
                let hint = match name.as_str() {
                    "x" | "y" | "z" => format!(
                        "the surface is where the formula is 0: write `{name} - (...)` to draw `{name} = ...`"
                    ),
                    _ => format!("`{name} = ...;` defines a name; the formula to draw follows it"),
                };
                self.expected_hint("';' after the definition", hint)
            } else {
                self.expected("an operator or ';'")
            });
        }
        self.bump();
        Ok(Definition { name, name_span, value })
    }

    /// expression = sum
    #[inline(always)]
    fn expression(&mut self) -> PResult<Expr> {
        self.sum()
    }

    /// sum = product { ("+" | "-") product }
    fn sum(&mut self) -> PResult<Expr> {
        self.left_assoc(
            |t| match t {
                Tok::Plus => Some(BinOp::Add),
                Tok::Minus => Some(BinOp::Sub),
                _ => None,
            },
            Self::product,
        )
    }

    /// product = unary { ("*" | "/") unary }
    fn product(&mut self) -> PResult<Expr> {
        self.left_assoc(
            |t| match t {
                Tok::Star => Some(BinOp::Mul),
                Tok::Slash => Some(BinOp::Div),
                _ => None,
            },
            Self::unary,
        )
    }

    /// One left-associative precedence level (a loop: a long chain
    /// `a + b + c + …` costs no stack).
    #[inline(always)]
    fn left_assoc(&mut self, op: impl Fn(&Tok) -> Option<BinOp>, next: impl Fn(&mut Self) -> PResult<Expr>) -> PResult<Expr> {
        let mut lhs = next(self)?;
        while let Some(op) = op(&self.current().tok) {
            self.bump();
            let rhs = next(self)?;
            let span = lhs.span.to(rhs.span);
            lhs = Expr { kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)), span };
        }
        Ok(lhs)
    }

    /// unary = ("-" | "+") unary | power
    fn unary(&mut self) -> PResult<Expr> {
        let minus = self.at(&Tok::Minus);
        if minus || self.at(&Tok::Plus) {
            self.enter(self.current().span)?;
            let op = self.bump();
            let inner = self.unary()?;
            self.depth -= 1;
            if !minus {
                return Ok(inner);
            }
            let span = op.to(inner.span);
            return Ok(Expr { kind: ExprKind::Neg(Box::new(inner)), span });
        }
        self.power()
    }

    /// power = primary [ "^" unary ]
    #[inline(always)]
    fn power(&mut self) -> PResult<Expr> {
        let base = self.primary()?;
        if self.at(&Tok::Caret) {
            self.enter(self.current().span)?;
            self.bump();
            let exp = self.unary()?;
            self.depth -= 1;
            let span = base.span.to(exp.span);
            return Ok(Expr { kind: ExprKind::Binary(BinOp::Pow, Box::new(base), Box::new(exp)), span });
        }
        Ok(base)
    }

    /// primary = NUMBER | IDENT [ "(" arguments ")" ] | "(" expression ")"
    fn primary(&mut self) -> PResult<Expr> {
        let span = self.current().span;
        match &self.current().tok {
            &Tok::Number(v) => {
                self.bump();
                Ok(Expr { kind: ExprKind::Number(v), span })
            }
            Tok::Ident(name) => {
                let name = name.clone();
                self.bump();
                if !self.at(&Tok::LParen) {
                    return Ok(Expr { kind: ExprKind::Name(name), span });
                }
                let open = self.bump();
                self.enter(open)?;
                let args = self.arguments()?;
                let close = self.close_paren(open)?;
                self.depth -= 1;
                Ok(Expr { kind: ExprKind::Call(Box::new(Call { name, name_span: span, args })), span: span.to(close) })
            }
            Tok::LParen => {
                let open = self.bump();
                self.enter(open)?;
                let mut inner = self.expression()?;
                let close = self.close_paren(open)?;
                self.depth -= 1;
                // The group's span includes its parentheses.
                inner.span = open.to(close);
                Ok(inner)
            }
            _ => Err(self.expected("an expression")),
        }
    }

    /// arguments = expression { "," expression }
    fn arguments(&mut self) -> PResult<Vec<Expr>> {
        let mut args = vec![self.expression()?];
        while self.at(&Tok::Comma) {
            self.bump();
            args.push(self.expression()?);
        }
        Ok(args)
    }

    fn close_paren(&mut self, open: Span) -> PResult<Span> {
        if self.at(&Tok::RParen) {
            return Ok(self.bump());
        }
        Err(self.unclosed(open))
    }

    #[cold]
    #[inline(never)]
    fn unclosed(&self, open: Span) -> Box<SyntaxError> {
        let t = self.current();
        if t.tok == Tok::Eof || t.tok == Tok::Semi {
            return Box::new(SyntaxError::Unclosed { open, found: self.found(), span: t.span });
        }
        let what = "')' or an operator";
        Box::new(SyntaxError::Expected { expected: what.into(), found: self.found(), span: t.span, hint: self.hint(what) })
    }
}

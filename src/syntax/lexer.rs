//! Splits formula text into tokens. Rejects non-ASCII and control
//! characters with a span on the offending character.

use crate::diag::Span;

/// Token kinds.
#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    /// A number literal with its value.
    Number(f64),
    /// A name.
    Ident(String),
    /// `+`
    Plus,
    /// `-`
    Minus,
    /// `*`
    Star,
    /// `/`
    Slash,
    /// `^`
    Caret,
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `,`
    Comma,
    /// `;`
    Semi,
    /// `=`
    Eq,
    /// `<`
    Lt,
    /// `>`
    Gt,
    /// End of input.
    Eof,
}

impl Tok {
    /// How the token is quoted in `expected X, found 'Y'`.
    pub fn describe(&self, text: &str) -> String {
        match self {
            Tok::Eof => "end of formula".to_string(),
            _ => crate::diag::quote_user_text(text, crate::diag::QUOTED_CHARS),
        }
    }
}

/// A token and where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Token {
    /// Kind.
    pub tok: Tok,
    /// Location.
    pub span: Span,
}

/// Errors found while lexing.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)] // fields: the names say it
pub enum LexError {
    /// A character outside printable ASCII.
    BadChar { ch: char, span: Span },
    /// A character that no token starts with.
    Unexpected { ch: char, span: Span },
    /// A malformed number such as `1e` or `1.2.3`.
    InvalidNumber { text: String, span: Span },
}

/// Tokenises the whole input (comments and whitespace dropped).
pub fn lex(src: &str) -> Result<Vec<Token>, LexError> {
    let bytes = src.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if let Some(e) = bad_char(src, i) {
            return Err(e);
        }
        let start = i;
        let single = |t: Tok| Token { tok: t, span: Span::new(start, start + 1) };
        match c {
            b' ' | b'\t' | b'\n' | b'\r' => i += 1,
            b'#' => {
                // Comments are checked like the rest: printable ASCII only.
                while i < bytes.len() && bytes[i] != b'\n' {
                    if let Some(e) = bad_char(src, i) {
                        return Err(e);
                    }
                    i += 1;
                }
            }
            b'0'..=b'9' | b'.' => {
                i = number_end(bytes, i);
                let text = &src[start..i];
                let span = Span::new(start, i);
                // A well-formed literal beyond the f64 range parses to
                // infinity; the semantic pass reports it as out of range.
                match text.parse::<f64>() {
                    Ok(v) if valid_number_shape(text) => out.push(Token { tok: Tok::Number(v), span }),
                    _ => return Err(LexError::InvalidNumber { text: text.to_string(), span }),
                }
            }
            b'a'..=b'z' | b'A'..=b'Z' | b'_' => {
                while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                    i += 1;
                }
                out.push(Token { tok: Tok::Ident(src[start..i].to_string()), span: Span::new(start, i) });
            }
            _ => {
                let tok = match c {
                    b'+' => Tok::Plus,
                    b'-' => Tok::Minus,
                    b'*' => Tok::Star,
                    b'/' => Tok::Slash,
                    b'^' => Tok::Caret,
                    b'(' => Tok::LParen,
                    b')' => Tok::RParen,
                    b',' => Tok::Comma,
                    b';' => Tok::Semi,
                    b'=' => Tok::Eq,
                    b'<' => Tok::Lt,
                    b'>' => Tok::Gt,
                    _ => return Err(LexError::Unexpected { ch: c as char, span: Span::new(start, start + 1) }),
                };
                out.push(single(tok));
                i += 1;
            }
        }
    }
    out.push(Token { tok: Tok::Eof, span: Span::new(src.len(), src.len()) });
    Ok(out)
}

/// The error for the character at byte `i` if it is not printable ASCII
/// or whitespace (space, tab, CR, LF).
fn bad_char(src: &str, i: usize) -> Option<LexError> {
    let c = src.as_bytes()[i];
    if c.is_ascii() && (!c.is_ascii_control() || matches!(c, b'\t' | b'\n' | b'\r')) {
        return None;
    }
    let ch = src[i..].chars().next().unwrap_or('\u{fffd}');
    Some(LexError::BadChar { ch, span: Span::new(i, i + ch.len_utf8()) })
}

/// Greedy end of a number-like run: digits, dots, and an exponent with sign.
/// Over-consumes on purpose (`1.2.3`, `1e`, `2x`-free) so a malformed
/// literal is reported as one invalid number rather than two tokens.
fn number_end(b: &[u8], mut i: usize) -> usize {
    while i < b.len() {
        match b[i] {
            b'0'..=b'9' | b'.' => i += 1,
            b'e' | b'E' => {
                i += 1;
                if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
                    i += 1;
                }
            }
            _ => break,
        }
    }
    i
}

/// `digits [. [digits]] [exp]` or `. digits [exp]` exactly (Rust's parser
/// also accepts `inf`, `1.` etc. — we check the shape of the grammar).
fn valid_number_shape(t: &str) -> bool {
    let (mant, exp) = match t.find(['e', 'E']) {
        Some(k) => (&t[..k], Some(&t[k + 1..])),
        None => (t, None),
    };
    let ok_digits = |s: &str| !s.is_empty() && s.bytes().all(|c| c.is_ascii_digit());
    let mant_ok = match mant.split_once('.') {
        None => ok_digits(mant),
        Some((a, b)) => (ok_digits(a) && (b.is_empty() || ok_digits(b))) || (a.is_empty() && ok_digits(b)),
    };
    let exp_ok = exp.is_none_or(|e| ok_digits(e.strip_prefix(['+', '-']).unwrap_or(e)));
    mant_ok && exp_ok
}

//! Diagnostics shared by every stage.
//!
//! Each stage (syntax, sema, validate, gpu, …) has its own error enum whose
//! variants carry [`Span`]s. They are converted once into a [`Diagnostic`]
//! and rendered with `codespan-reporting`, so an error in a formula reads the
//! same way naga's WGSL errors do.

use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label};
use codespan_reporting::files::SimpleFile;
use codespan_reporting::term::{self, Config};

/// A byte range `start..end` into the formula source.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Span {
    /// First byte.
    pub start: u32,
    /// One past the last byte.
    pub end: u32,
}

impl Span {
    /// A span covering `start..end`.
    pub fn new(start: usize, end: usize) -> Span {
        Span { start: start as u32, end: end as u32 }
    }
    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span { start: self.start.min(other.start), end: self.end.max(other.end) }
    }
    /// As a `Range<usize>` for slicing and for codespan.
    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// Stops the command.
    Error,
    /// Printed, the command goes on.
    Warning,
}

/// A rendered-once error or warning: message, labelled spans, notes.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// One line: what is wrong.
    pub message: String,
    /// Spans in the source with a short label; the first is the primary one.
    pub labels: Vec<(Span, String)>,
    /// Extra lines (`= help: …`).
    pub notes: Vec<String>,
}

impl Diagnostic {
    /// An error with a primary label.
    pub fn error(message: impl Into<String>, span: Span, label: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Error,
            message: message.into(),
            labels: vec![(span, label.into())],
            notes: vec![],
        }
    }
    /// An error that points nowhere in the source (a file, a flag).
    pub fn plain(message: impl Into<String>) -> Self {
        Diagnostic { severity: Severity::Error, message: message.into(), labels: vec![], notes: vec![] }
    }
    /// A warning with a primary label.
    pub fn warning(message: impl Into<String>, span: Span, label: impl Into<String>) -> Self {
        Diagnostic { severity: Severity::Warning, ..Diagnostic::error(message, span, label) }
    }
    /// Adds a secondary label.
    pub fn with_label(mut self, span: Span, label: impl Into<String>) -> Self {
        self.labels.push((span, label.into()));
        self
    }
    /// Adds a note line.
    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    /// Renders like rustc/naga: `error: …`, the source line, a caret, notes.
    /// `name` is the file name shown in the header (`<formula>` for text
    /// given on the command line).
    ///
    /// Control characters in any of the text (source, name, message,
    /// labels, notes) are shown as visible symbols (`escape_controls`),
    /// so a hostile formula or `.iso` file cannot send escape sequences to
    /// the terminal; spans are moved with them so carets stay under the
    /// character they point at.
    pub fn render(&self, name: &str, source: &str, color: bool) -> String {
        let shown = Escaped::new(source);
        let name = escape_controls(name);
        let file = SimpleFile::new(name.as_ref(), shown.text.as_ref());
        let len = source.len() as u32;
        let labels = self
            .labels
            .iter()
            .enumerate()
            .map(|(i, (span, text))| {
                let r = shown.offset(span.start.min(len) as usize)..shown.offset(span.end.min(len) as usize);
                let l = if i == 0 { Label::primary((), r) } else { Label::secondary((), r) };
                l.with_message(escape_controls(text).into_owned())
            })
            .collect();
        let d = match self.severity {
            Severity::Error => CsDiagnostic::error(),
            Severity::Warning => CsDiagnostic::warning(),
        }
        .with_message(escape_controls(&self.message).into_owned())
        .with_labels(labels)
        .with_notes(self.notes.iter().map(|n| escape_controls(n).into_owned()).collect());
        let config = Config::default();
        if color {
            let mut buf = term::termcolor::Buffer::ansi();
            let _ = term::emit_to_write_style(&mut buf, &config, &file, &d);
            String::from_utf8_lossy(buf.as_slice()).into_owned()
        } else {
            let mut out = String::new();
            let _ = term::emit_to_string(&mut out, &config, &file, &d);
            out
        }
    }
}

/// The visible stand-in for a character that must not reach a terminal
/// raw: C0 controls (except tab and line feed) as their Unicode control
/// pictures (ESC → ␛ U+241B, NUL → ␀ U+2400), DEL as ␡ (U+2421), and C1
/// controls and bidirectional overrides (which reorder what a reader sees)
/// as U+FFFD. Each stand-in is one column wide, like a printable character.
fn stand_in(c: char, next: Option<char>) -> Option<char> {
    match c {
        '\t' | '\n' => None,
        // A line break written as CR LF stays a line break.
        '\r' if next == Some('\n') => None,
        '\u{0}'..='\u{1f}' => char::from_u32(0x2400 + c as u32),
        '\u{7f}' => Some('\u{2421}'),
        '\u{80}'..='\u{9f}' | '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}' => Some('\u{fffd}'),
        _ => None,
    }
}

/// `s` with every terminal control character replaced by a visible symbol
/// (see [`Diagnostic::render`]); borrowed when there is none. Use it for
/// any message that quotes user text before it is printed.
pub(crate) fn escape_controls(s: &str) -> std::borrow::Cow<'_, str> {
    Escaped::new(s).text
}

/// Escaped text and where each byte of the original went.
struct Escaped<'a> {
    text: std::borrow::Cow<'a, str>,
    /// New offset of each original byte offset (`len + 1` entries); empty
    /// when nothing was replaced.
    map: Vec<usize>,
}

impl<'a> Escaped<'a> {
    fn new(s: &'a str) -> Self {
        let mut chars = s.chars().peekable();
        let mut any = false;
        while let Some(c) = chars.next() {
            any |= stand_in(c, chars.peek().copied()).is_some();
        }
        if !any {
            return Escaped { text: std::borrow::Cow::Borrowed(s), map: vec![] };
        }
        let mut text = String::with_capacity(s.len() + 16);
        let mut map = Vec::with_capacity(s.len() + 1);
        let mut chars = s.chars().peekable();
        while let Some(c) = chars.next() {
            let shown = stand_in(c, chars.peek().copied()).unwrap_or(c);
            // Every byte of the character maps to where its stand-in starts.
            map.extend(std::iter::repeat_n(text.len(), c.len_utf8()));
            text.push(shown);
        }
        map.push(text.len());
        Escaped { text: std::borrow::Cow::Owned(text), map }
    }

    /// Where original byte `i` is in the escaped text.
    fn offset(&self, i: usize) -> usize {
        if self.map.is_empty() { i } else { self.map[i.min(self.map.len() - 1)] }
    }
}

/// Edit distance, for "did you mean" suggestions. Two rows reused for the
/// whole run: one allocation per call, not one per character of `a`.
pub(crate) fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cost = usize::from(ca != *cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// Longest name, in bytes, that [`closest`] looks for suggestions for: no
/// name it is compared with is anywhere near as long, and an edit distance
/// to a name of megabytes costs seconds for nothing.
pub(crate) const MAX_SUGGESTED_NAME: usize = 64;

/// The candidates closest to `name` (at most three, distance ≤ max(2, len/3)).
/// None for a name longer than [`MAX_SUGGESTED_NAME`]; a candidate whose
/// length alone differs by more than the limit is not compared.
pub(crate) fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    if name.len() > MAX_SUGGESTED_NAME {
        return vec![];
    }
    let limit = (name.len() / 3).max(2);
    let chars = name.chars().count();
    let mut scored: Vec<(usize, &str)> = candidates
        .into_iter()
        .filter(|c| c.chars().count().abs_diff(chars) <= limit)
        .map(|c| (levenshtein(name, c), c))
        .filter(|(d, _)| *d <= limit)
        .collect();
    scored.sort();
    scored.dedup();
    scored.into_iter().take(3).map(|(_, c)| c).collect()
}

/// How many characters of user text a message quotes (see [`quote_user_text`]).
pub(crate) const QUOTED_CHARS: usize = 60;

/// User text (a name, a type, a key from a file or a request) for a
/// message: in single quotes, every control character shown as a visible
/// symbol (line breaks and tabs too, so the text cannot start a line of
/// its own), and cut after `max` characters with an ellipsis and the
/// text's length: `'aaaa…' (52428800 bytes)`. A message then stays one
/// short line whatever the input holds.
pub(crate) fn quote_user_text(s: &str, max: usize) -> String {
    let (shown, cut) = visible_prefix(s, max);
    if cut { format!("'{shown}…' ({} bytes)", s.len()) } else { format!("'{shown}'") }
}

/// [`quote_user_text`] without the quotes: `aaaa… (52428800 bytes)` when
/// cut. `usize::MAX` keeps the whole text (a name from a report, printed
/// in a table).
pub(crate) fn user_text(s: &str, max: usize) -> String {
    let (shown, cut) = visible_prefix(s, max);
    if cut { format!("{shown}… ({} bytes)", s.len()) } else { shown }
}

/// The first `max` characters of `s` with control characters made
/// visible, and whether `s` goes on.
fn visible_prefix(s: &str, max: usize) -> (String, bool) {
    let mut out = String::with_capacity(s.len().min(4 * max.min(1 << 20)));
    let mut chars = s.chars();
    for c in chars.by_ref().take(max) {
        out.push(match c {
            '\u{0}'..='\u{1f}' => char::from_u32(0x2400 + c as u32).unwrap_or('\u{fffd}'),
            c => stand_in(c, None).unwrap_or(c),
        });
    }
    (out, chars.next().is_some())
}

/// A number for a message, short whatever its size: `NaN`, `infinity`,
/// five significant digits in exponent form from 1e16 on and below 1e-5
/// (`1e308`, `2.6881e43`), as Rust writes it otherwise (`0.5`, `1200`).
pub(crate) fn show_number(v: f64) -> String {
    if v.is_nan() {
        "NaN".into()
    } else if v.is_infinite() {
        if v > 0.0 { "infinity".into() } else { "-infinity".into() }
    } else if v != 0.0 && (v.abs() >= 1e16 || v.abs() < 1e-5) {
        let s = format!("{v:.4e}");
        let (mant, exp) = s.split_once('e').unwrap_or((&s, "0"));
        format!("{}e{exp}", mant.trim_end_matches('0').trim_end_matches('.'))
    } else {
        format!("{v}")
    }
}

/// A number for a message: at most 6 decimals, trailing zeros dropped, so
/// a bound computed in floating point (7/6 of 0.6) reads as written (0.7).
pub(crate) fn short_number(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_become_visible_and_carets_stay_aligned() {
        assert_eq!(escape_controls("a\x1b[31mb\0\x7f\u{9b}\tc\r\n"), "a\u{241b}[31mb\u{2400}\u{2421}\u{fffd}\tc\r\n");
        assert!(matches!(escape_controls("plain ascii"), std::borrow::Cow::Borrowed(_)));
        let d = Diagnostic::error("unexpected character '$'", Span::new(9, 10), "here");
        let out = d.render("<f>", "x\x1b[31m + $", false);
        assert!(!out.contains('\x1b'), "{out}");
        assert!(out.contains("1 │ x\u{241b}[31m + $\n  │          ^ here"), "{out}");
    }

    #[test]
    fn quoted_user_text_is_escaped_and_cut() {
        assert_eq!(quote_user_text("sphere", 60), "'sphere'");
        assert_eq!(quote_user_text("a\nb\x1b[2J\t", 60), "'a\u{240a}b\u{241b}[2J\u{2409}'");
        assert_eq!(quote_user_text(&"é".repeat(10), 4), "'éééé…' (20 bytes)");
        assert_eq!(quote_user_text("abcd", 4), "'abcd'");
    }

    #[test]
    fn suggestions_skip_long_names_and_far_lengths() {
        assert_eq!(closest("spher", ["sphere", "box", "shell"]), ["sphere"]);
        assert!(closest(&"a".repeat(65), ["sphere"]).is_empty());
        assert_eq!(levenshtein("kitten", "sitting"), 3);
        assert_eq!(show_number(1e308), "1e308");
        assert_eq!(show_number(-2.5e-7), "-2.5e-7");
        assert_eq!(show_number(1200.5), "1200.5");
    }
}

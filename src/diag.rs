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
    pub fn render(&self, name: &str, source: &str, color: bool) -> String {
        let file = SimpleFile::new(name, source);
        let len = source.len();
        let labels = self
            .labels
            .iter()
            .enumerate()
            .map(|(i, (span, text))| {
                let r = span.start.min(len as u32) as usize..span.end.min(len as u32) as usize;
                let l = if i == 0 { Label::primary((), r) } else { Label::secondary((), r) };
                l.with_message(text.clone())
            })
            .collect();
        let d = match self.severity {
            Severity::Error => CsDiagnostic::error(),
            Severity::Warning => CsDiagnostic::warning(),
        }
        .with_message(self.message.clone())
        .with_labels(labels)
        .with_notes(self.notes.clone());
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

/// Edit distance, for "did you mean" suggestions.
pub fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let cost = usize::from(ca != *cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The candidates closest to `name` (at most three, distance ≤ max(2, len/3)).
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    let limit = (name.len() / 3).max(2);
    let mut scored: Vec<(usize, &str)> = candidates
        .into_iter()
        .map(|c| (levenshtein(name, c), c))
        .filter(|(d, _)| *d <= limit)
        .collect();
    scored.sort();
    scored.dedup();
    scored.into_iter().take(3).map(|(_, c)| c).collect()
}

//! `--inline FILE.wgsl`: user WGSL spliced into the generated shaders
//! (Knoll et al. §4.1, §4.6).
//!
//! The file may define
//! - functions callable from the formula: a function `foo` of n arguments
//!   is written three times, `s_foo` (f32), `ia_foo` (`vec2<f32>` intervals)
//!   and `ra_foo` (`vec3<f32>` affine forms), like the built-in op libraries;
//! - hooks that replace parts of the traversal:
//!   `fn hook_reject(r: vec2<f32>) -> bool` (true: the cell with enclosure r
//!   may hold the surface; replaces the zero test),
//!   `fn hook_hit(p: vec3<f32>) -> bool` (false: drop this hit and go on),
//!   `fn hook_shade(p: vec3<f32>, dir: vec3<f32>, n: vec3<f32>, c: vec3<f32>) -> vec3<f32>`
//!   (the final colour of a hit).
//!
//! The text is validated by naga as part of every shader it goes into; an
//! error inside it is reported against the user's file.

use crate::diag::{Diagnostic, Span};

/// Largest inline file read, in bytes. Hand-written helper functions are a
/// few KiB; the bound keeps an endless or mistaken file (a FIFO, a binary)
/// from filling the memory before naga ever sees it.
pub const MAX_INLINE_BYTES: u64 = 1 << 20;

/// A parsed inline file.
#[derive(Debug, Clone, PartialEq)]
pub struct InlineWgsl {
    /// The file as named on the command line.
    pub path: String,
    /// Its text.
    pub text: String,
    /// User functions: name and number of arguments.
    pub functions: Vec<(String, usize)>,
    /// `hook_reject` is defined.
    pub reject: bool,
    /// `hook_hit` is defined.
    pub hit: bool,
    /// `hook_shade` is defined.
    pub shade: bool,
}

/// A `fn` found in the text: name, number of parameters, span of the name,
/// and the byte range of its parameter list (inside the parentheses).
struct FnDecl {
    name: String,
    arity: usize,
    span: Span,
    params: std::ops::Range<usize>,
}

/// Finds `fn name(params)` declarations (a light scan, not a parser: naga
/// parses the file for real once it is spliced).
fn declarations(text: &str) -> Vec<FnDecl> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut in_comment = false;
    while i + 3 < b.len() {
        if !in_comment && b[i] == b'/' && b[i + 1] == b'/' {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if b[i] == b'/' && b[i + 1] == b'*' {
            in_comment = true;
        }
        if in_comment && b[i] == b'*' && b[i + 1] == b'/' {
            in_comment = false;
        }
        let boundary = i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if !in_comment && boundary && text[i..].starts_with("fn") && b.get(i + 2).is_some_and(|c| c.is_ascii_whitespace()) {
            let mut j = i + 2;
            while j < b.len() && b[j].is_ascii_whitespace() {
                j += 1;
            }
            let start = j;
            while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
                j += 1;
            }
            let name = text[start..j].to_string();
            while j < b.len() && b[j].is_ascii_whitespace() {
                j += 1;
            }
            if j < b.len() && b[j] == b'(' && !name.is_empty() {
                let (mut depth, mut angle, mut commas, mut any) = (0i32, 0i32, 0usize, false);
                let mut k = j;
                while k < b.len() {
                    match b[k] {
                        b'(' => depth += 1,
                        b')' => {
                            depth -= 1;
                            if depth == 0 {
                                break;
                            }
                        }
                        b'<' => angle += 1,
                        b'>' => angle -= 1,
                        b',' if depth == 1 && angle == 0 => commas += 1,
                        c if !c.is_ascii_whitespace() && depth >= 1 => any = true,
                        _ => {}
                    }
                    k += 1;
                }
                // A trailing comma does not add a parameter.
                let inner = text[j + 1..k.min(text.len())].trim_end();
                let arity = if !any { 0 } else if inner.ends_with(',') { commas } else { commas + 1 };
                out.push(FnDecl { name, arity, span: Span::new(start, j), params: j + 1..k.min(text.len()) });
            }
            i = j;
            continue;
        }
        i += 1;
    }
    out
}

/// Reads the declarations of an inline file and checks that every user
/// function exists in all three domains with one arity.
pub fn parse_inline(path: &str, text: &str) -> Result<InlineWgsl, Diagnostic> {
    let decls = declarations(text);
    let mut functions: Vec<(String, usize)> = Vec::new();
    for d in &decls {
        let Some(base) = d.name.strip_prefix("s_").or(d.name.strip_prefix("ia_")).or(d.name.strip_prefix("ra_")) else { continue };
        if functions.iter().any(|(n, _)| n == base) {
            continue;
        }
        for prefix in ["s_", "ia_", "ra_"] {
            let want = format!("{prefix}{base}");
            match decls.iter().find(|e| e.name == want) {
                None => {
                    return Err(Diagnostic::error(
                        format!("inline function '{base}' has no {prefix} version"),
                        d.span,
                        "declared here",
                    )
                    .with_note(format!("a function callable from the formula needs s_{base} (f32), ia_{base} (vec2<f32>) and ra_{base} (vec3<f32>) with the same arguments")));
                }
                Some(e) if e.arity != d.arity => {
                    return Err(Diagnostic::error(
                        format!("'{want}' takes {} arguments but '{}' takes {}", e.arity, d.name, d.arity),
                        e.span,
                        "different number of arguments",
                    )
                    .with_label(d.span, "compared with this"));
                }
                Some(_) => {}
            }
        }
        if d.arity == 0 || d.arity > 4 {
            return Err(Diagnostic::error(format!("inline function '{base}' takes {} arguments; 1 to 4 are supported", d.arity), d.span, "here"));
        }
        functions.push((base.to_string(), d.arity));
    }
    for d in &decls {
        check_hook(text, d)?;
    }
    let has = |n: &str| decls.iter().any(|d| d.name == n);
    Ok(InlineWgsl { path: path.to_string(), text: text.to_string(), functions, reject: has("hook_reject"), hit: has("hook_hit"), shade: has("hook_shade") })
}

/// The hooks the bisection traversal calls, with the only signature each
/// may have (parameter types, return type): the generated code calls them
/// with exactly these types, so any other signature fails in isotrace's
/// code, where naga's message would point away from the user's file.
pub const HOOKS: [(&str, &[&str], &str); 3] = [
    ("hook_reject", &["vec2<f32>"], "bool"),
    ("hook_hit", &["vec3<f32>"], "bool"),
    ("hook_shade", &["vec3<f32>", "vec3<f32>", "vec3<f32>", "vec3<f32>"], "vec3<f32>"),
];

/// A WGSL type without spaces, its `vecNf` shorthand spelled out.
fn normal_type(t: &str) -> String {
    let t: String = t.chars().filter(|c| !c.is_whitespace()).collect();
    match t.as_str() {
        "vec2f" => "vec2<f32>".into(),
        "vec3f" => "vec3<f32>".into(),
        "vec4f" => "vec4<f32>".into(),
        _ => t,
    }
}

/// Splits a parameter list at its top-level commas.
fn split_params(list: &str) -> Vec<&str> {
    let (mut depth, mut start, mut out) = (0i32, 0, Vec::new());
    for (i, c) in list.char_indices() {
        match c {
            '<' | '(' => depth += 1,
            '>' | ')' => depth -= 1,
            ',' if depth == 0 => {
                out.push(&list[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&list[start..]);
    out.into_iter().filter(|p| !p.trim().is_empty()).collect()
}

/// Checks a hook's parameter and return types against [`HOOKS`].
fn check_hook(text: &str, d: &FnDecl) -> Result<(), Diagnostic> {
    let Some(&(name, want_params, want_ret)) = HOOKS.iter().find(|(n, _, _)| *n == d.name) else { return Ok(()) };
    let params: Vec<String> = split_params(&text[d.params.clone()]).iter().map(|p| normal_type(p.split_once(':').map_or("", |(_, t)| t))).collect();
    let after = text.get(d.params.end + 1..).unwrap_or("");
    let head = &after[..after.find('{').unwrap_or(after.len())];
    let ret = head.trim().strip_prefix("->").map(normal_type).unwrap_or_default();
    if params == want_params && ret == want_ret {
        return Ok(());
    }
    let names = ["r", "p", "dir", "n", "c"];
    let expected: Vec<String> = match name {
        "hook_reject" => vec![format!("r: {}", want_params[0])],
        "hook_hit" => vec![format!("p: {}", want_params[0])],
        _ => names[1..].iter().zip(want_params).map(|(n, t)| format!("{n}: {t}")).collect(),
    };
    let found = format!("({}){}", params.join(", "), if ret.is_empty() { String::new() } else { format!(" -> {ret}") });
    Err(Diagnostic::error(format!("hook '{name}' has the wrong signature"), d.span, format!("declared as {found}"))
        .with_note(format!("the traversal calls it as fn {name}({}) -> {want_ret}", expected.join(", "))))
}

/// Names a WGSL text declares at module scope (`fn`, `struct`, `const`,
/// `var`, `alias`, `override`), with their spans. A light scan like
/// `declarations`: it skips comments and everything inside braces, which
/// is all it needs to find the names two module parts would both define.
pub fn module_names(text: &str) -> Vec<(String, Span)> {
    let b = text.as_bytes();
    let ident = |mut i: usize| {
        while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
            i += 1;
        }
        i
    };
    let skip_space = |mut i: usize| {
        while i < b.len() && b[i].is_ascii_whitespace() {
            i += 1;
        }
        i
    };
    let (mut out, mut depth, mut i) = (Vec::new(), 0i32, 0);
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => i = text[i..].find('\n').map_or(b.len(), |n| i + n),
            b'/' if b.get(i + 1) == Some(&b'*') => i = text[i + 2..].find("*/").map_or(b.len(), |n| i + n + 4),
            b'{' => (depth, i) = (depth + 1, i + 1),
            b'}' => (depth, i) = (depth - 1, i + 1),
            c if c.is_ascii_alphabetic() || c == b'_' => {
                let end = ident(i);
                let word = &text[i..end];
                i = end;
                if depth != 0 || !matches!(word, "fn" | "struct" | "const" | "var" | "alias" | "override") {
                    continue;
                }
                let mut j = skip_space(i);
                if word == "var" && b.get(j) == Some(&b'<') {
                    j = text[j..].find('>').map_or(b.len(), |n| skip_space(j + n + 1));
                }
                let e = ident(j);
                if e > j {
                    out.push((text[j..e].to_string(), Span::new(j, e)));
                }
                i = e.max(i);
            }
            _ => i += 1,
        }
    }
    out
}

/// The user's arity for function `name`, if the file defines it.
impl InlineWgsl {
    /// Arity of user function `name`.
    pub fn arity(&self, name: &str) -> Option<usize> {
        self.functions.iter().find(|(n, _)| n == name).map(|&(_, a)| a)
    }
}

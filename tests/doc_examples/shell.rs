//! Shell command lines as the doc examples test reads them: words and operators, stages, the
//! arguments of an `isotrace` stage, and the files a command names as its outputs.

/// A word of a command line, or an unquoted operator.
#[derive(Debug, Clone, PartialEq)]
pub enum Word {
    Text(String),
    Op(String),
}

/// Splits a command line as a shell would into words and operators (quotes and backslashes
/// removed, no expansion); an unquoted `#` starting a word ends the line.
pub fn words(line: &str) -> Vec<Word> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut in_word = false;
    let mut chars = line.chars().peekable();
    let flush = |cur: &mut String, in_word: &mut bool, out: &mut Vec<Word>| {
        if *in_word {
            out.push(Word::Text(std::mem::take(cur)));
            *in_word = false;
        }
    };
    while let Some(c) = chars.next() {
        match c {
            '\'' => {
                in_word = true;
                for q in chars.by_ref() {
                    if q == '\'' {
                        break;
                    }
                    cur.push(q);
                }
            }
            '"' => {
                in_word = true;
                while let Some(q) = chars.next() {
                    match q {
                        '"' => break,
                        '\\' if matches!(chars.peek(), Some('"' | '\\' | '$' | '`')) => cur.push(chars.next().unwrap()),
                        _ => cur.push(q),
                    }
                }
            }
            '\\' => {
                in_word = true;
                if let Some(n) = chars.next() {
                    cur.push(n);
                }
            }
            '#' if !in_word => break,
            ' ' | '\t' => flush(&mut cur, &mut in_word, &mut out),
            '|' | '&' | ';' | '>' | '<' => {
                let fd = in_word && c == '>' && cur.chars().all(|d| d.is_ascii_digit());
                if !fd {
                    flush(&mut cur, &mut in_word, &mut out);
                }
                let mut op = if fd { std::mem::take(&mut cur) } else { String::new() };
                in_word = false;
                op.push(c);
                if matches!((c, chars.peek()), ('|', Some('|')) | ('&', Some('&')) | ('>', Some('>'))) {
                    op.push(chars.next().unwrap());
                }
                out.push(Word::Op(op));
            }
            _ => {
                in_word = true;
                cur.push(c);
            }
        }
    }
    flush(&mut cur, &mut in_word, &mut out);
    out
}

/// The stages of a command line: split at `|`, `||`, `&&`, `;` and `&`.
pub fn stages(words: &[Word]) -> Vec<Vec<Word>> {
    let mut out = vec![Vec::new()];
    for w in words {
        match w {
            Word::Op(op) if matches!(op.as_str(), "|" | "||" | "&&" | ";" | "&") => out.push(Vec::new()),
            _ => out.last_mut().unwrap().push(w.clone()),
        }
    }
    out
}

/// The arguments after `isotrace` when a stage runs it (assignments and `time` before it are
/// allowed), up to the first redirection.
pub fn isotrace_args(stage: &[Word]) -> Option<Vec<String>> {
    let mut it = stage.iter().skip_while(|w| matches!(w, Word::Text(t) if t == "time" || is_assignment(t)));
    match it.next() {
        Some(Word::Text(t)) if t == "isotrace" => {}
        _ => return None,
    }
    Some(it.map_while(|w| if let Word::Text(t) = w { Some(t.clone()) } else { None }).collect())
}

fn is_assignment(word: &str) -> bool {
    word.split_once('=').is_some_and(|(name, _)| !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
}

/// Files a command line's redirections write.
pub fn redirected(words: &[Word]) -> Vec<String> {
    let mut out = Vec::new();
    for pair in words.windows(2) {
        if let (Word::Op(op), Word::Text(file)) = (&pair[0], &pair[1]) {
            if op.ends_with('>') && file != "/dev/null" {
                out.push(file.clone());
            }
        }
    }
    out
}

/// The value of a flag: `--flag V`, `--flag=V` or (short flags) `-fV`.
fn flag_values(args: &[String], names: &[&str]) -> Vec<String> {
    let mut out = Vec::new();
    for (k, a) in args.iter().enumerate() {
        for name in names {
            if a == name {
                if let Some(v) = args.get(k + 1) {
                    out.push(v.clone());
                }
            } else if let Some(v) = a.strip_prefix(&format!("{name}=")) {
                out.push(v.to_string());
            } else if name.len() == 2 && a.len() > 2 && a.starts_with(name) && !a.starts_with("--") {
                out.push(a[2..].to_string());
            }
        }
    }
    out
}

/// The files (and, for `bench --out`, the directory) an isotrace command names as outputs.
pub fn outputs(args: &[String]) -> Vec<String> {
    let sub: Vec<&str> = args.iter().filter(|a| !a.starts_with('-')).take(2).map(String::as_str).collect();
    let mut files = flag_values(args, &["-o", "--output", "--export", "--markdown", "--out"]);
    if matches!(sub.first(), Some(&"bench")) || sub[..] == ["manifest", "merge"] {
        files.extend(flag_values(args, &["--json"]));
    }
    let frames = flag_values(args, &["--frames"]).first().and_then(|n| n.parse::<u64>().ok());
    let shard = flag_values(args, &["--shard"]).first().cloned();
    let mut out = Vec::new();
    for f in files.into_iter().filter(|f| f != "-") {
        match frames {
            Some(n) => out.extend(frame_names(&f, n, shard.as_deref())),
            None => out.push(f),
        }
    }
    out
}

/// The files of frame pattern `pattern` that shard `i/n` writes (all of them without a shard;
/// none to check for `auto`, whose shard comes from the environment).
fn frame_names(pattern: &str, frames: u64, shard: Option<&str>) -> Vec<String> {
    let (index, count) = match shard {
        None => (0, 1),
        Some(s) => match s.split_once('/').and_then(|(i, n)| Some((i.parse::<u64>().ok()?, n.parse::<u64>().ok()?))) {
            Some(p) => p,
            None => return Vec::new(),
        },
    };
    (0..frames).filter(|k| k % count == index).map(|k| frame_name(pattern, k)).collect()
}

/// Frame k's name: `%d`, `%0Nd` and `%%` as `render --frames` reads them.
fn frame_name(pattern: &str, k: u64) -> String {
    let mut out = String::new();
    let mut chars = pattern.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('%') => out.push('%'),
            Some('d') => out.push_str(&k.to_string()),
            Some('0') => {
                let width = chars.next().and_then(|w| w.to_digit(10)).unwrap_or(1) as usize;
                chars.next(); // the 'd'
                out.push_str(&format!("{k:0width$}"));
            }
            other => panic!("frame pattern '{pattern}': unexpected {other:?} after %"),
        }
    }
    out
}

//! Reading Rust sources without a parser: a small tokenizer (identifiers, `::`, punctuation;
//! comments, strings, char and number literals and lifetimes skipped), the module paths a file
//! names, and the extent of every function.

use std::collections::BTreeSet;

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    /// `::`
    Path,
    Punct(char),
}

#[derive(Debug, Clone)]
struct Token {
    tok: Tok,
    line: usize,
}

fn is_ident_start(c: char) -> bool {
    c == '_' || c.is_alphabetic()
}

fn is_ident_char(c: char) -> bool {
    c == '_' || c.is_alphanumeric()
}

/// Skips a string body starting after its opening quote at `i`; returns the index after the
/// closing quote. `hashes`: the raw string's `#` count (`None`: not raw, escapes apply).
fn skip_string(s: &[char], mut i: usize, hashes: Option<usize>, line: &mut usize) -> usize {
    while i < s.len() {
        let c = s[i];
        if c == '\n' {
            *line += 1;
        }
        match hashes {
            None if c == '\\' => {
                if s.get(i + 1) == Some(&'\n') {
                    *line += 1;
                }
                i += 2;
                continue;
            }
            None if c == '"' => return i + 1,
            Some(n) if c == '"' && (1..=n).all(|k| s.get(i + k) == Some(&'#')) => {
                return i + 1 + n;
            }
            _ => {}
        }
        i += 1;
    }
    i
}

/// The tokens of Rust source text, without comments, string, char and number literals and
/// lifetimes.
fn tokenize(text: &str) -> Vec<Token> {
    let s: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < s.len() {
        let c = s[i];
        let next = s.get(i + 1).copied();
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c == '/' && next == Some('/') {
            while i < s.len() && s[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < s.len() {
                if s[i] == '/' && s.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if s[i] == '*' && s.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if s[i] == '\n' {
                        line += 1;
                    }
                    i += 1;
                }
            }
        } else if c == '"' {
            i = skip_string(&s, i + 1, None, &mut line);
        } else if c == '\'' {
            if next == Some('\\') {
                // an escaped char literal: '\n', '\'', '\u{..}'
                i += 2;
                while i < s.len() && s[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if s.get(i + 2) == Some(&'\'') {
                i += 3; // 'x'
            } else {
                // a lifetime or label
                i += 1;
                while i < s.len() && is_ident_char(s[i]) {
                    i += 1;
                }
            }
        } else if c.is_ascii_digit() {
            while i < s.len()
                && (is_ident_char(s[i])
                    || (s[i] == '.' && s.get(i + 1).is_some_and(|d| d.is_ascii_digit())))
            {
                i += 1;
            }
        } else if is_ident_start(c) {
            let start = i;
            while i < s.len() && is_ident_char(s[i]) {
                i += 1;
            }
            let word: String = s[start..i].iter().collect();
            let prefix = matches!(word.as_str(), "r" | "b" | "br" | "c" | "cr");
            let raw = matches!(word.as_str(), "r" | "br" | "cr");
            if prefix && s.get(i) == Some(&'"') {
                i = skip_string(&s, i + 1, raw.then_some(0), &mut line);
            } else if raw && s.get(i) == Some(&'#') {
                let mut n = 0;
                while s.get(i + n) == Some(&'#') {
                    n += 1;
                }
                if s.get(i + n) == Some(&'"') {
                    i = skip_string(&s, i + n + 1, Some(n), &mut line);
                } else {
                    // a raw identifier r#name
                    i += 1;
                    let start = i;
                    while i < s.len() && is_ident_char(s[i]) {
                        i += 1;
                    }
                    let name: String = s[start..i].iter().collect();
                    out.push(Token {
                        tok: Tok::Ident(name),
                        line,
                    });
                }
            } else if word == "b" && s.get(i) == Some(&'\'') {
                // a byte literal b'x' / b'\n'
                i += 1;
                if s.get(i + 1) == Some(&'\\') || s.get(i) == Some(&'\\') {
                    i += 1;
                }
                while i < s.len() && s[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else {
                out.push(Token {
                    tok: Tok::Ident(word),
                    line,
                });
            }
        } else if c == ':' && next == Some(':') {
            out.push(Token {
                tok: Tok::Path,
                line,
            });
            i += 2;
        } else {
            out.push(Token {
                tok: Tok::Punct(c),
                line,
            });
            i += 1;
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Paths

fn ident(t: Option<&Token>) -> Option<&str> {
    match t.map(|t| &t.tok) {
        Some(Tok::Ident(s)) => Some(s),
        _ => None,
    }
}

fn is(t: Option<&Token>, tok: &Tok) -> bool {
    t.is_some_and(|t| &t.tok == tok)
}

/// One path of a `use` tree: its segments and the name it binds (`"*"` for a glob, `"_"`
/// for `as _`).
struct UsePath {
    path: Vec<String>,
    binds: String,
}

/// The paths of a `use` tree starting at `toks[*i]` (after `use`).
fn use_tree(toks: &[Token], i: &mut usize, prefix: &[String], out: &mut Vec<UsePath>) {
    if is(toks.get(*i), &Tok::Path) && prefix.is_empty() {
        // `use ::extern_crate::..`: not this crate
        *i += 1;
        let mut ignored = Vec::new();
        use_tree(toks, i, &["::".to_string()], &mut ignored);
        return;
    }
    match toks.get(*i).map(|t| &t.tok) {
        Some(Tok::Punct('{')) => {
            *i += 1;
            while *i < toks.len() && !is(toks.get(*i), &Tok::Punct('}')) {
                use_tree(toks, i, prefix, out);
                if is(toks.get(*i), &Tok::Punct(',')) {
                    *i += 1;
                }
            }
            *i += 1;
        }
        Some(Tok::Punct('*')) => {
            *i += 1;
            out.push(UsePath {
                path: prefix.to_vec(),
                binds: "*".into(),
            });
        }
        Some(Tok::Ident(seg)) => {
            *i += 1;
            let mut path = prefix.to_vec();
            // `a::{self, ..}` names `a` itself
            if seg != "self" || prefix.is_empty() {
                path.push(seg.clone());
            }
            if is(toks.get(*i), &Tok::Path) {
                *i += 1;
                use_tree(toks, i, &path, out);
            } else {
                let mut binds = path.last().cloned().unwrap_or_default();
                if ident(toks.get(*i)) == Some("as") {
                    binds = ident(toks.get(*i + 1)).unwrap_or("_").to_string();
                    *i += 2;
                }
                out.push(UsePath { path, binds });
            }
        }
        _ => *i += 1,
    }
}

/// Resolves `path` written in module `here` (whose file-level child modules are `children`)
/// to segments from the crate root; `None` for a path outside this crate or an item of the
/// current module.
fn absolute(path: &[String], here: &[String], children: &BTreeSet<String>) -> Option<Vec<String>> {
    let first = path.first()?;
    let (mut base, rest): (Vec<String>, &[String]) = match first.as_str() {
        "crate" | "$crate" => (Vec::new(), &path[1..]),
        "self" => (here.to_vec(), &path[1..]),
        "super" => {
            let mut b = here.to_vec();
            let mut k = 0;
            while path.get(k).is_some_and(|s| s == "super") {
                b.pop()?;
                k += 1;
            }
            (b, &path[k..])
        }
        name if children.contains(name) => (here.to_vec(), path),
        _ => return None,
    };
    base.extend(rest.iter().cloned());
    Some(base)
}

/// How a path is named.
#[derive(Debug, Clone, PartialEq)]
pub enum How {
    /// In a `use` item: `public` when it is a re-export (`pub use`, `pub(crate) use`, ..);
    /// `binds`: the name it brings into scope (`"*"` for a glob).
    Use { public: bool, binds: String },
    /// In an expression, a type, a pattern or a macro body.
    Path,
}

/// One module path a file names: the segments after resolving `crate`/`super`/`self` (and a
/// leading child module), from the crate root, and where it is written.
#[derive(Debug, Clone)]
pub struct Named {
    /// The module the path is written in, from the crate root (inline `mod x { .. }` included).
    pub scope: Vec<String>,
    pub module_path: Vec<String>,
    pub line: usize,
    /// The path as written.
    pub text: String,
    pub how: How,
}

/// The names of the `mod x;` / `mod x { .. }` declarations of a file: the roots of its
/// relative paths.
pub fn declared_modules(text: &str) -> BTreeSet<String> {
    module_declarations(&tokenize(text))
}

fn module_declarations(toks: &[Token]) -> BTreeSet<String> {
    let mut children = BTreeSet::new();
    for w in toks.windows(3) {
        if ident(Some(&w[0])) == Some("mod")
            && let Some(name) = ident(Some(&w[1]))
            && matches!(w[2].tok, Tok::Punct(';') | Tok::Punct('{'))
        {
            children.insert(name.to_string());
        }
    }
    children
}

/// The module paths a file names: every path that starts with `crate::`, `super::`,
/// `self::` or the name of a module the file declares, in `use` items (grouped ones
/// included) and in expressions, types and macro bodies. Comments, doc comments and string
/// literals are not read; `mod x;` declarations and visibilities (`pub(in crate::x)`) are
/// not paths. `module`: the file's module path from the crate root (empty for `lib.rs`).
pub fn named_paths(text: &str, module: &[String]) -> Vec<Named> {
    let toks = tokenize(text);
    let children = module_declarations(&toks);
    let mut out = Vec::new();
    // the module scope: inline `mod name {` blocks, closed at their brace depth
    let mut scope: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut pending_mod: Option<String> = None;
    // the token before is a `pub` visibility
    let mut public = false;
    let mut i = 0;
    while i < toks.len() {
        let here: Vec<String> = module
            .iter()
            .cloned()
            .chain(scope.iter().map(|(n, _)| n.clone()))
            .collect();
        let line = toks[i].line;
        let was_public = std::mem::take(&mut public);
        match &toks[i].tok {
            Tok::Punct('{') => {
                depth += 1;
                if let Some(name) = pending_mod.take() {
                    scope.push((name, depth));
                }
                i += 1;
            }
            Tok::Punct('}') => {
                if scope.last().is_some_and(|(_, d)| *d == depth) {
                    scope.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
            }
            Tok::Punct(';') => {
                pending_mod = None;
                i += 1;
            }
            Tok::Ident(w) if w == "mod" => {
                pending_mod = ident(toks.get(i + 1)).map(str::to_string);
                i += 1;
            }
            Tok::Ident(w) if w == "pub" => {
                // a visibility; `pub(in crate::a)` names no dependency
                public = true;
                i += 1;
                if is(toks.get(i), &Tok::Punct('(')) {
                    while i < toks.len() && !is(toks.get(i), &Tok::Punct(')')) {
                        i += 1;
                    }
                    i += 1;
                }
            }
            Tok::Ident(w) if w == "use" => {
                i += 1;
                let mut paths = Vec::new();
                while i < toks.len() && !is(toks.get(i), &Tok::Punct(';')) {
                    use_tree(&toks, &mut i, &[], &mut paths);
                }
                for UsePath { path, binds } in paths {
                    if let Some(abs) = absolute(&path, &here, &children) {
                        out.push(Named {
                            scope: here.clone(),
                            module_path: abs,
                            line,
                            text: path.join("::"),
                            how: How::Use {
                                public: was_public,
                                binds,
                            },
                        });
                    }
                }
            }
            Tok::Ident(w)
                if (matches!(w.as_str(), "crate" | "super" | "self") || children.contains(w))
                    && is(toks.get(i + 1), &Tok::Path)
                    && !(i > 0
                        && (is(toks.get(i - 1), &Tok::Path)
                            || is(toks.get(i - 1), &Tok::Punct('.')))) =>
            {
                let mut p = vec![w.clone()];
                i += 1;
                while is(toks.get(i), &Tok::Path)
                    && let Some(seg) = ident(toks.get(i + 1))
                {
                    p.push(seg.to_string());
                    i += 2;
                }
                if let Some(abs) = absolute(&p, &here, &children) {
                    out.push(Named {
                        scope: here.clone(),
                        module_path: abs,
                        line,
                        text: p.join("::"),
                        how: How::Path,
                    });
                }
            }
            _ => i += 1,
        }
    }
    out
}

/// The names of the items a crate root defines itself (outside its inline modules): `fn`,
/// `struct`, `enum`, `union`, `trait`, `type`, `const`, `static` and `macro_rules!`.
pub fn root_items(text: &str) -> BTreeSet<String> {
    let toks = tokenize(text);
    let mut out = BTreeSet::new();
    let mut depth = 0usize;
    for (i, t) in toks.iter().enumerate() {
        match &t.tok {
            Tok::Punct('{') => depth += 1,
            Tok::Punct('}') => depth = depth.saturating_sub(1),
            Tok::Ident(w) if depth == 0 => {
                let kind = matches!(
                    w.as_str(),
                    "fn" | "struct" | "enum" | "union" | "trait" | "type" | "const" | "static"
                );
                let name = if kind {
                    ident(toks.get(i + 1))
                } else if w == "macro_rules" && is(toks.get(i + 1), &Tok::Punct('!')) {
                    ident(toks.get(i + 2))
                } else {
                    None
                };
                if let Some(n) = name {
                    out.insert(n.to_string());
                }
            }
            _ => {}
        }
    }
    out
}

/// The module path of a source file relative to `src/`: `lib.rs` -> [], `a/b.rs` and
/// `a/b/mod.rs` -> [a, b].
pub fn module_of(rel: &str) -> Vec<String> {
    let rel = rel.strip_suffix(".rs").unwrap_or(rel);
    let mut parts: Vec<String> = rel.split('/').map(str::to_string).collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

// ---------------------------------------------------------------------------------------------
// Functions

/// Every function with a body: (name, line of `fn`, line of its closing brace).
pub fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let toks = tokenize(text);
    let mut out = Vec::new();
    for (i, t) in toks.iter().enumerate() {
        if ident(Some(t)) != Some("fn") {
            continue;
        }
        let Some(name) = ident(toks.get(i + 1)) else {
            continue; // a `fn(..)` pointer type
        };
        // the body: the first `{` outside () and []; none when `;` comes first
        let mut nest = 0i32;
        let mut j = i + 2;
        let mut body = None;
        while let Some(t) = toks.get(j) {
            match t.tok {
                Tok::Punct('(' | '[') => nest += 1,
                Tok::Punct(')' | ']') => nest -= 1,
                Tok::Punct(';') if nest == 0 => break,
                Tok::Punct('{') if nest == 0 => {
                    body = Some(j);
                    break;
                }
                _ => {}
            }
            j += 1;
        }
        let Some(open) = body else { continue };
        let mut depth = 0;
        for close in &toks[open..] {
            match close.tok {
                Tok::Punct('{') => depth += 1,
                Tok::Punct('}') => {
                    depth -= 1;
                    if depth == 0 {
                        out.push((name.to_string(), t.line, close.line));
                        break;
                    }
                }
                _ => {}
            }
        }
    }
    out
}

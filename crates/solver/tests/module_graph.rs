//! Structure checks of the solver crate's sources (`crates/solver/src/**/*.rs`):
//!
//! - **No import cycle among its files.** Every path that starts with `crate::`, `super::`
//!   or `self::` (in `use` items, grouped ones included, and in expressions and types such as
//!   `crate::problem::joints::joint_set(..)`), and every `use` of a child module declared in
//!   the same file (`mod vtu;` ... `pub use vtu::write_frame;`), is an edge from the file it is
//!   written in to the file that defines the module it names: the longest prefix of the path
//!   that is a module with a file (`a/b.rs` or `a/b/mod.rs`; an inline `mod tests { .. }`
//!   belongs to its file). Comments, doc comments and string literals are not read; `mod x;`
//!   declarations are not edges (a module owns its children); visibility paths
//!   (`pub(in crate::x)`) are not edges. A re-export is an edge: a `mod.rs` that re-exports
//!   its children's items depends on them, so a child that takes those items back through
//!   `super::Item` closes a cycle; children name their siblings instead
//!   (`super::frame::FrameData`). The test fails with every strongly connected component of
//!   more than one file, and the edges inside it.
//! - **No long function.** No `fn` in the sources is longer than [`MAX_FN_LINES`] lines,
//!   from the line of its `fn` keyword to its closing brace, except the few in
//!   [`LONG_FN_ALLOWED`] (table-like code, each with its reason).
//!
//! The parser is a small tokenizer (identifiers, `::`, punctuation; comments, strings and
//! char literals skipped), tested on an inline example below.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The longest function allowed outside [`LONG_FN_ALLOWED`] [lines].
const MAX_FN_LINES: usize = 150;

/// Functions allowed above [`MAX_FN_LINES`]: (file relative to `src/`, function name, why).
const LONG_FN_ALLOWED: &[(&str, &str, &str)] = &[];

// ---------------------------------------------------------------------------------------------
// Tokenizer

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
// Paths and the file graph

/// One module path a file names: the segments after resolving `crate`/`super`/`self`, from
/// the crate root, and where it is written.
#[derive(Debug, Clone)]
struct Named {
    module_path: Vec<String>,
    line: usize,
    text: String,
}

fn ident(t: Option<&Token>) -> Option<&str> {
    match t.map(|t| &t.tok) {
        Some(Tok::Ident(s)) => Some(s),
        _ => None,
    }
}

fn is(t: Option<&Token>, tok: &Tok) -> bool {
    t.is_some_and(|t| &t.tok == tok)
}

/// The paths of a `use` tree starting at `toks[*i]` (after `use`), each as its segments.
fn use_tree(toks: &[Token], i: &mut usize, prefix: &[String], out: &mut Vec<Vec<String>>) {
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
            out.push(prefix.to_vec());
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
                if ident(toks.get(*i)) == Some("as") {
                    *i += 2;
                }
                out.push(path);
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

/// The module paths a file names (see the module docs). `module`: the file's module path
/// from the crate root (empty for `lib.rs`).
fn named_paths(text: &str, module: &[String]) -> Vec<Named> {
    let toks = tokenize(text);
    // file-level `mod name;` / `mod name { .. }` declarations: relative `use` roots
    let mut children = BTreeSet::new();
    for w in toks.windows(3) {
        if ident(Some(&w[0])) == Some("mod")
            && let Some(name) = ident(Some(&w[1]))
            && matches!(w[2].tok, Tok::Punct(';') | Tok::Punct('{'))
        {
            children.insert(name.to_string());
        }
    }
    let mut out = Vec::new();
    // the module scope: inline `mod name {` blocks, closed at their brace depth
    let mut scope: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut pending_mod: Option<String> = None;
    let mut i = 0;
    while i < toks.len() {
        let here: Vec<String> = module
            .iter()
            .cloned()
            .chain(scope.iter().map(|(n, _)| n.clone()))
            .collect();
        let line = toks[i].line;
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
            Tok::Ident(w) if w == "pub" && is(toks.get(i + 1), &Tok::Punct('(')) => {
                // a visibility such as `pub(in crate::a)`: not a dependency
                while i < toks.len() && !is(toks.get(i), &Tok::Punct(')')) {
                    i += 1;
                }
                i += 1;
            }
            Tok::Ident(w) if w == "use" => {
                i += 1;
                let mut paths = Vec::new();
                while i < toks.len() && !is(toks.get(i), &Tok::Punct(';')) {
                    use_tree(&toks, &mut i, &[], &mut paths);
                }
                for p in paths {
                    if let Some(abs) = absolute(&p, &here, &children) {
                        out.push(Named {
                            module_path: abs,
                            line,
                            text: p.join("::"),
                        });
                    }
                }
            }
            Tok::Ident(w)
                if matches!(w.as_str(), "crate" | "super" | "self")
                    && is(toks.get(i + 1), &Tok::Path)
                    && !(i > 0 && is(toks.get(i - 1), &Tok::Path)) =>
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
                        module_path: abs,
                        line,
                        text: p.join("::"),
                    });
                }
            }
            _ => i += 1,
        }
    }
    out
}

/// The module path of a source file relative to `src/`: `lib.rs` -> [], `a/b.rs` and
/// `a/b/mod.rs` -> [a, b].
fn module_of(rel: &str) -> Vec<String> {
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

/// An edge of the file graph: where it is written and the path it names.
#[derive(Debug, Clone)]
struct Edge {
    line: usize,
    text: String,
}

/// The file graph of sources given as (path relative to `src/`, text): for each file, the
/// files it names, with the first place it names each.
fn file_graph(files: &[(String, String)]) -> BTreeMap<String, BTreeMap<String, Edge>> {
    let by_module: BTreeMap<Vec<String>, String> = files
        .iter()
        .map(|(f, _)| (module_of(f), f.clone()))
        .collect();
    let mut graph = BTreeMap::new();
    for (file, text) in files {
        let targets: &mut BTreeMap<String, Edge> = graph.entry(file.clone()).or_default();
        for n in named_paths(text, &module_of(file)) {
            let target = (0..=n.module_path.len())
                .rev()
                .find_map(|k| by_module.get(&n.module_path[..k]))
                .expect("the crate root is a module with a file");
            if target != file {
                targets.entry(target.clone()).or_insert(Edge {
                    line: n.line,
                    text: n.text,
                });
            }
        }
    }
    graph
}

/// The strongly connected components of more than one node (Tarjan), each sorted.
fn cycles(graph: &BTreeMap<String, BTreeMap<String, Edge>>) -> Vec<Vec<String>> {
    struct State<'a> {
        graph: &'a BTreeMap<String, BTreeMap<String, Edge>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let k = s.index.len();
        s.index.insert(v, k);
        s.low.insert(v, k);
        s.stack.push(v);
        s.on_stack.insert(v);
        let graph = s.graph;
        for w in graph.get(v).into_iter().flat_map(|t| t.keys()) {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(lw);
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.out.sort();
    s.out
}

/// A readable list of the cycles and the edges inside each.
fn describe(graph: &BTreeMap<String, BTreeMap<String, Edge>>, comps: &[Vec<String>]) -> String {
    let mut msg = String::new();
    for comp in comps {
        msg.push_str(&format!("cycle among {}:\n", comp.join(", ")));
        for a in comp {
            for (b, e) in &graph[a] {
                if comp.contains(b) {
                    msg.push_str(&format!("  {a}:{} -> {b}  ({})\n", e.line, e.text));
                }
            }
        }
    }
    msg
}

// ---------------------------------------------------------------------------------------------
// Functions

/// Every function with a body: (name, line of `fn`, line of its closing brace).
fn functions(text: &str) -> Vec<(String, usize, usize)> {
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

// ---------------------------------------------------------------------------------------------
// The checks on the crate

fn sources() -> Vec<(String, String)> {
    fn walk(dir: &Path, root: &Path, out: &mut Vec<(String, String)>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .expect("readable src directory")
            .map(|e| e.expect("directory entry").path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, root, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                let rel = p.strip_prefix(root).expect("under src").to_string_lossy();
                let text = std::fs::read_to_string(&p).expect("readable source");
                out.push((rel.replace('\\', "/"), text));
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = Vec::new();
    walk(&root, &root, &mut out);
    out
}

#[test]
fn no_import_cycle_among_the_solver_files() {
    let graph = file_graph(&sources());
    assert!(graph.len() > 10, "the sources were found");
    let comps = cycles(&graph);
    assert!(
        comps.is_empty(),
        "import cycles among crates/solver/src files (break each by moving the shared item \
         down, or by naming the sibling file instead of the parent's re-export):\n{}",
        describe(&graph, &comps)
    );
}

/// Prints the file graph (`cargo test -p fdem-solver --test module_graph -- --ignored
/// --nocapture`): each file and the files it uses, with the first line that uses each.
#[test]
#[ignore = "prints the graph; run on demand"]
fn print_the_file_graph() {
    for (file, targets) in file_graph(&sources()) {
        println!("{file}");
        for (t, e) in targets {
            println!("  -> {t}  ({}:{} {})", file, e.line, e.text);
        }
    }
}

#[test]
fn no_function_longer_than_the_limit() {
    let mut long = Vec::new();
    let mut allowed_seen = BTreeSet::new();
    for (file, text) in sources() {
        for (name, first, last) in functions(&text) {
            let n = last - first + 1;
            if n <= MAX_FN_LINES {
                continue;
            }
            if LONG_FN_ALLOWED
                .iter()
                .any(|(f, fun, _)| *f == file && *fun == name)
            {
                allowed_seen.insert((file.clone(), name.clone()));
                continue;
            }
            long.push(format!("{file}:{first}: fn {name} is {n} lines"));
        }
    }
    assert!(
        long.is_empty(),
        "functions longer than {MAX_FN_LINES} lines (split them, or add table-like code to \
         LONG_FN_ALLOWED with the reason):\n{}",
        long.join("\n")
    );
    for (f, fun, _) in LONG_FN_ALLOWED {
        assert!(
            allowed_seen.contains(&(f.to_string(), fun.to_string())),
            "{f}: fn {fun} is in LONG_FN_ALLOWED but no longer above the limit: remove it"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The checker's own tests

fn example() -> Vec<(String, String)> {
    let files = [
        (
            "lib.rs",
            "//! crate::c::x in a comment is no edge\npub mod a;\npub mod b;\npub mod c;\n\
             pub mod out;\npub use a::A;\n",
        ),
        // a -> b through a grouped use; b -> a through an expression path: a cycle
        (
            "a.rs",
            "use crate::{error::E, b::{self, Inner}};\n/* crate::c::Z */\npub struct A;\n",
        ),
        (
            "b.rs",
            "pub fn f() { let s = \"crate::c::q\"; crate::a::helper::<u8>(s); }\n\
             #[cfg(test)]\nmod tests {\n    use super::*;\n    use self::inner::X;\n}\n",
        ),
        // c names nothing of a or b (strings and char literals only)
        (
            "c.rs",
            "pub fn g() -> char { let _ = r#\"crate::a\"#; '{' }\n",
        ),
        ("error.rs", "pub struct E;\n"),
        // a parent re-exporting its child's item, and the child naming the re-export
        (
            "out/mod.rs",
            "mod frame;\nmod vtu;\npub use frame::Frame;\npub use self::vtu::write;\n",
        ),
        ("out/frame.rs", "pub struct Frame;\n"),
        (
            "out/vtu.rs",
            "use super::Frame;\npub fn write(_: &super::frame::Frame) {}\n",
        ),
    ];
    files
        .iter()
        .map(|(f, t)| (f.to_string(), t.to_string()))
        .collect()
}

#[test]
fn checker_finds_the_known_cycles_of_an_example() {
    let graph = file_graph(&example());
    let edges = |f: &str| graph[f].keys().cloned().collect::<Vec<_>>();
    assert_eq!(edges("lib.rs"), ["a.rs"]);
    assert_eq!(edges("a.rs"), ["b.rs", "error.rs"]);
    assert_eq!(edges("b.rs"), ["a.rs"]);
    assert!(edges("c.rs").is_empty());
    assert_eq!(edges("out/mod.rs"), ["out/frame.rs", "out/vtu.rs"]);
    assert_eq!(edges("out/vtu.rs"), ["out/frame.rs", "out/mod.rs"]);
    assert_eq!(graph["b.rs"]["a.rs"].line, 1);
    assert_eq!(
        cycles(&graph),
        [
            vec!["a.rs".to_string(), "b.rs".into()],
            vec!["out/mod.rs".to_string(), "out/vtu.rs".into()],
        ]
    );
    let msg = describe(&graph, &cycles(&graph));
    assert!(msg.contains("b.rs:1 -> a.rs  (crate::a::helper)"), "{msg}");
}

#[test]
fn functions_are_measured_from_fn_to_closing_brace() {
    let text = "trait T { fn decl(&self) -> [u8; 2]; }\n\
                fn short() {\n    let c = '}';\n    let s = \"}\";\n}\n\
                fn long<T: Into<f64>>(x: T)\n    -> f64\n{\n    let f = |y: f64| { y };\n\
                \n    f(x.into())\n}\n";
    assert_eq!(
        functions(text),
        [("short".to_string(), 2, 5), ("long".to_string(), 6, 12)]
    );
}

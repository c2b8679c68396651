//! Structure checks of the whole workspace: every crate's `src/` (`crates/*/src`) and the
//! `fdem` package's own `src/`.
//!
//! - **No import cycle among a crate's top-level modules.** A top-level module is one the
//!   crate root (`lib.rs`, `main.rs`) declares; a folder counts as one module with all its
//!   files (`x.rs` or `x/mod.rs`, and everything under `x/`), as does an inline
//!   `mod x { .. }` of the root. Every path that starts with `crate::`, `super::`, `self::`
//!   or a module the file declares, in `use` items and in expressions, types and macro
//!   bodies, is an edge from the module it is written in to the module it leads into.
//!   Comments and strings are not read; `mod x;` declarations and visibilities are not
//!   edges. The crate root is the crate's index: its top-level `pub use` items (re-exports)
//!   are not edges, and a path through one (`crate::Problem`, re-exported from `load`) leads
//!   to the module the re-export names. The root's own code (its functions, its private
//!   imports) is the node `(crate root)`, and a module depends on it only when it names an
//!   item the root defines itself (`crate::write_atomically`).
//!   Test modules (`#[cfg(test)]`) count as code of the module they are in: a unit test
//!   that loads a whole scene makes its module depend on the loading.
//! - **No import cycle among a crate's files**, with the same edges drawn between files,
//!   except between a module's file and the files of its children (one unit: a child that
//!   implements more of its parent's type, a parent that calls its child) and with the
//!   crate root: this adds the cycles among the files of one folder (`study/scene/runs.rs`
//!   and `study/scene/reference.rs` naming each other), which the module graph counts as
//!   one node.
//! - **No long function.** No `fn` is longer than [`MAX_FN_LINES`] lines, from the line of
//!   its `fn` keyword to its closing brace.
//! - **The crate graph** (`manifests.rs`): the workspace's crates depend on each other in
//!   the layers of `docs/architecture.md`, and its table lists exactly their dependencies.
//!
//! The failures list every cycle (strongly connected component) with the lines that make
//! it. The `PENDING_*` lists hold what crates/solver has today while it is being
//! restructured; each entry must still be found (an entry fixed must be removed), and no
//! other crate may have one.
//!
//! Run it alone with `cargo test --release -p fdem-time --test structure` (it lives in the
//! time crate, the one with the fewest dependencies, and reads the other crates' files
//! without building them); `-- --ignored --nocapture print_the_figures` prints the figures
//! (cycles and the longest function of each crate).

mod checker;
mod graph;
mod manifests;
mod rust_source;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use graph::{Graph, cycles, describe, file_graph, module_graph};
use rust_source::functions;

/// The longest function allowed [lines, from its `fn` line to its closing brace].
const MAX_FN_LINES: usize = 120;

/// The only crate that may have pending entries: it is being restructured.
const PENDING_CRATE: &str = "crates/solver";

/// Functions of crates/solver over [`MAX_FN_LINES`] today, to be split: (file from the
/// workspace root, function name).
const PENDING_LONG_FNS: &[(&str, &str)] = &[];

/// Cycles among the top-level modules of crates/solver today, to be broken: (crate folder,
/// the modules of the cycle, sorted).
const PENDING_MODULE_CYCLES: &[(&str, &[&str])] = &[];

/// Cycles among the files of crates/solver today, to be broken: (crate folder, the files
/// of the cycle relative to `src/`, sorted).
const PENDING_FILE_CYCLES: &[(&str, &[&str])] = &[];

/// One crate of the workspace: its folder relative to the workspace root (`.` for the
/// `fdem` package) and its sources.
struct Crate {
    dir: String,
    sources: Vec<(String, String)>,
}

impl Crate {
    /// The folder of its sources, from the workspace root (`src`, `crates/mesh/src`).
    fn src(&self) -> String {
        if self.dir == "." {
            "src".into()
        } else {
            format!("{}/src", self.dir)
        }
    }
}

/// The workspace's root folder: this test is in the time crate (`crates/time`), whose
/// dependencies are few and built first, so that it builds in seconds and reads every
/// crate's sources without compiling any of them.
fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `.rs` files under `root`, relative to it, sorted.
fn rust_files(root: &Path) -> Vec<(String, String)> {
    fn walk(dir: &Path, root: &Path, out: &mut Vec<(String, String)>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
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
    let mut out = Vec::new();
    walk(root, root, &mut out);
    out
}

/// The workspace's crates: the `fdem` package and every folder of `crates/` with a
/// `Cargo.toml` (the workspace's members are `.` and `crates/*`).
fn crates() -> Vec<Crate> {
    let root = workspace_root();
    let mut dirs = vec![".".to_string()];
    for c in manifests::member_dirs(&root) {
        dirs.push(c);
    }
    dirs.into_iter()
        .map(|dir| {
            let src = root.join(&dir).join("src");
            let sources = rust_files(&src);
            let roots: Vec<&str> = sources
                .iter()
                .map(|(f, _)| f.as_str())
                .filter(|f| matches!(*f, "lib.rs" | "main.rs"))
                .collect();
            assert_eq!(
                roots.len(),
                1,
                "{}: one crate root (lib.rs or main.rs) expected, found {roots:?}",
                src.display()
            );
            Crate { dir, sources }
        })
        .collect()
}

/// Compares the cycles found with the pending ones: the cycles not pending, and the pending
/// entries no longer found (each a line of the failure).
fn unexpected_cycles(
    what: &str,
    graph_of: fn(&graph::Sources) -> Graph,
    pending: &[(&str, &[&str])],
) -> Vec<String> {
    let mut problems = Vec::new();
    let mut seen = BTreeSet::new();
    for c in crates() {
        let graph = graph_of(&c.sources);
        for comp in cycles(&graph) {
            let is_pending = pending.iter().any(|(dir, nodes)| {
                *dir == c.dir && nodes.iter().copied().eq(comp.iter().map(String::as_str))
            });
            if is_pending {
                seen.insert((c.dir.clone(), comp));
                continue;
            }
            problems.push(format!(
                "{}: a cycle among the {what} {}:\n{}",
                c.src(),
                comp.join(", "),
                describe(&graph, &comp)
            ));
        }
    }
    for (dir, nodes) in pending {
        let nodes: Vec<String> = nodes.iter().map(|s| s.to_string()).collect();
        if !seen.contains(&(dir.to_string(), nodes.clone())) {
            problems.push(format!(
                "{dir}: the pending cycle among the {what} {} is no longer found: remove \
                 (or update) its entry",
                nodes.join(", ")
            ));
        }
    }
    problems
}

#[test]
fn no_import_cycle_among_top_level_modules() {
    let problems = unexpected_cycles("top-level modules", module_graph, PENDING_MODULE_CYCLES);
    assert!(
        problems.is_empty(),
        "import cycles among the top-level modules of a crate (break each by moving the \
         shared item into the lower module, or into a module of its own):\n{}",
        problems.join("\n")
    );
}

#[test]
fn no_import_cycle_among_files() {
    let problems = unexpected_cycles("files", file_graph, PENDING_FILE_CYCLES);
    assert!(
        problems.is_empty(),
        "import cycles among the files of a crate (break each by moving the shared item \
         down, or by naming the sibling file instead of the parent's re-export):\n{}",
        problems.join("\n")
    );
}

/// Every function longer than [`MAX_FN_LINES`]: (file from the workspace root, name, line
/// of `fn`, lines).
fn long_functions() -> Vec<(String, String, usize, usize)> {
    let mut out = Vec::new();
    for c in crates() {
        for (file, text) in &c.sources {
            for (name, first, last) in functions(text) {
                let n = last - first + 1;
                if n > MAX_FN_LINES {
                    out.push((format!("{}/{file}", c.src()), name, first, n));
                }
            }
        }
    }
    out
}

#[test]
fn no_function_longer_than_the_limit() {
    let long = long_functions();
    let mut problems = Vec::new();
    for (file, name, line, n) in &long {
        if !PENDING_LONG_FNS.contains(&(file.as_str(), name.as_str())) {
            problems.push(format!("{file}:{line}: fn {name} is {n} lines"));
        }
    }
    for (file, name) in PENDING_LONG_FNS {
        if !long.iter().any(|(f, n, _, _)| f == file && n == name) {
            problems.push(format!(
                "{file}: the pending fn {name} is no longer above {MAX_FN_LINES} lines (or \
                 no longer there): remove its entry"
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "functions longer than {MAX_FN_LINES} lines, from `fn` to the closing brace (split \
         them into named steps):\n{}",
        problems.join("\n")
    );
}

#[test]
fn pending_lists_name_only_the_crate_being_restructured() {
    let prefix = format!("{PENDING_CRATE}/src/");
    for (file, name) in PENDING_LONG_FNS {
        assert!(
            file.starts_with(&prefix),
            "{file}: fn {name} is pending outside {PENDING_CRATE}: split it instead"
        );
    }
    for (dir, nodes) in PENDING_MODULE_CYCLES.iter().chain(PENDING_FILE_CYCLES) {
        assert_eq!(
            *dir, PENDING_CRATE,
            "a pending cycle among {nodes:?} in {dir}: break it instead"
        );
    }
}

/// Prints each crate's figures: its cycles among top-level modules and among files, and
/// its longest function.
#[test]
#[ignore = "prints the figures; run on demand with --nocapture"]
fn print_the_figures() {
    for c in crates() {
        let modules = cycles(&module_graph(&c.sources));
        let files = cycles(&file_graph(&c.sources));
        let longest = c
            .sources
            .iter()
            .flat_map(|(f, t)| functions(t).into_iter().map(move |x| (f.clone(), x)))
            .max_by_key(|(_, (_, a, b))| b - a + 1);
        println!("{}:", c.src());
        println!("  cycles among top-level modules: {}", modules.len());
        for comp in &modules {
            println!("    {}", comp.join(", "));
        }
        println!("  cycles among files: {}", files.len());
        for comp in &files {
            println!("    {}", comp.join(", "));
        }
        if let Some((file, (name, a, b))) = longest {
            println!("  longest fn: {name} ({file}:{a}), {} lines", b - a + 1);
        }
    }
    for (file, name, line, n) in long_functions() {
        println!("long: {file}:{line} fn {name}: {n} lines");
    }
}

/// Prints one crate's module graph (`cargo test --release -p fdem-time --test structure
/// -- --ignored --nocapture print_the_module_graph`, with `STRUCTURE_CRATE=crates/mesh`; the
/// `fdem` package by default).
#[test]
#[ignore = "prints a graph; run on demand with --nocapture"]
fn print_the_module_graph() {
    let dir = std::env::var("STRUCTURE_CRATE").unwrap_or_else(|_| ".".into());
    let c = crates()
        .into_iter()
        .find(|c| c.dir == dir)
        .expect("STRUCTURE_CRATE names a crate folder");
    for (m, targets) in module_graph(&c.sources) {
        println!("{m}");
        for (t, places) in targets {
            let e = &places[0];
            println!("  -> {t}  ({}:{} {})", e.file, e.line, e.text);
        }
    }
}

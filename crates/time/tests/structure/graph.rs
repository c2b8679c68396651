//! The module and file graphs of one crate's sources, and their cycles.

use std::collections::{BTreeMap, BTreeSet};

use crate::rust_source::{How, Named, declared_modules, module_of, named_paths, root_items};

/// One place where a node names another: the file (relative to `src/`), the line and the
/// path as written.
#[derive(Debug, Clone)]
pub struct Edge {
    pub file: String,
    pub line: usize,
    pub text: String,
}

/// A directed graph: for each node, the nodes it names, with every place that names each.
pub type Graph = BTreeMap<String, BTreeMap<String, Vec<Edge>>>;

/// One crate's sources: (path relative to `src/`, text), sorted by path.
pub type Sources = [(String, String)];

/// The name of the crate root's node in the module graph.
pub const ROOT: &str = "(crate root)";

/// Where a path of the crate leads once the crate root's `use` items are followed.
enum Target {
    /// A module path from the crate root whose first segment is a top-level module, or empty
    /// for the root itself.
    Module(Vec<String>),
    /// An item the crate root defines itself.
    RootItem,
    /// Not in this crate's code (a re-export of another crate's item) or not known.
    Outside,
}

/// The crate root's names: its top-level modules, the items it defines and the names its
/// `use` items bring in (re-exports and imports, with the module path each leads to).
struct Root {
    file: String,
    modules: BTreeSet<String>,
    items: BTreeSet<String>,
    aliases: BTreeMap<String, Vec<String>>,
}

impl Root {
    fn of(files: &Sources) -> Root {
        let (file, text) = files
            .iter()
            .find(|(f, _)| module_of(f).is_empty())
            .expect("the crate has a root file (lib.rs or main.rs)");
        // the files' top-level modules, and inline ones (`pub mod driver { .. }` in lib.rs)
        let modules = files
            .iter()
            .filter_map(|(f, _)| module_of(f).first().cloned())
            .chain(declared_modules(text))
            .collect();
        let mut aliases = BTreeMap::new();
        for n in named_paths(text, &[]) {
            if let (true, How::Use { binds, .. }) = (n.scope.is_empty(), &n.how)
                && binds != "*"
                && binds != "_"
            {
                aliases.insert(binds.clone(), n.module_path.clone());
            }
        }
        Root {
            file: file.clone(),
            modules,
            items: root_items(text),
            aliases,
        }
    }

    /// Where `path` (from the crate root) leads: through the root's `use` items to a
    /// top-level module, to an item of the root itself, or outside the crate's code.
    fn target(&self, path: &[String]) -> Target {
        let mut p = path.to_vec();
        for _ in 0..16 {
            let Some(first) = p.first() else {
                return Target::Module(p);
            };
            if self.modules.contains(first) {
                return Target::Module(p);
            }
            if self.items.contains(first) {
                return Target::RootItem;
            }
            match self.aliases.get(first) {
                Some(to) => p = to.iter().chain(&p[1..]).cloned().collect(),
                None => return Target::Outside,
            }
        }
        Target::Outside
    }
}

/// Every path each file names, with where it leads; the crate root's re-exports (`pub use`
/// at its top level) are left out: the root is the crate's index, not a dependency of it.
fn resolved(files: &Sources) -> (Root, Vec<(String, Named, Target)>) {
    let root = Root::of(files);
    let mut out = Vec::new();
    for (file, text) in files {
        for n in named_paths(text, &module_of(file)) {
            let re_export = n.scope.is_empty() && matches!(n.how, How::Use { public: true, .. });
            if !re_export {
                let target = root.target(&n.module_path);
                out.push((file.clone(), n, target));
            }
        }
    }
    (root, out)
}

fn add(graph: &mut Graph, from: &str, to: &str, edge: Edge) {
    let targets = graph.entry(from.to_string()).or_default();
    if from != to {
        targets.entry(to.to_string()).or_default().push(edge);
    }
}

/// The graph of the crate's top-level modules: a module declared in the crate root, with
/// all its files and children (`x.rs`, `x/mod.rs`, `x/**`) or inline (`mod x { .. }`), is
/// one node; the crate root's own code is the node [`ROOT`]. A path written in module A
/// that leads into module B is an edge A -> B; a path that leads to an item the root
/// defines itself is an edge to [`ROOT`].
pub fn module_graph(files: &Sources) -> Graph {
    let (root, paths) = resolved(files);
    let node = |scope: &[String]| scope.first().map_or(ROOT.to_string(), Clone::clone);
    let mut graph = Graph::new();
    for m in &root.modules {
        graph.entry(m.clone()).or_default();
    }
    for (file, n, target) in paths {
        let to = match target {
            Target::Module(p) => node(&p),
            Target::RootItem => ROOT.to_string(),
            Target::Outside => continue,
        };
        let edge = Edge {
            file,
            line: n.line,
            text: n.text,
        };
        add(&mut graph, &node(&n.scope), &to, edge);
    }
    graph
}

/// The graph of the crate's files: a path written in file A that leads into a module
/// defined in file B (the longest prefix of the path that is a module with a file; an inline
/// module belongs to its file) is an edge A -> B, unless one of A and B is a module above
/// the other: a module and the files of its children are one unit (a child that implements
/// more of its parent's type, a parent that calls its child), and the crate root is above
/// every file (its cycles are the module graph's). So the file graph adds the cycles among
/// the files of one folder, which the module graph counts as one node.
pub fn file_graph(files: &Sources) -> Graph {
    let by_module: BTreeMap<Vec<String>, String> = files
        .iter()
        .map(|(f, _)| (module_of(f), f.clone()))
        .collect();
    let (root, paths) = resolved(files);
    let mut graph = Graph::new();
    for (f, _) in files {
        graph.entry(f.clone()).or_default();
    }
    for (file, n, target) in paths {
        let to = match target {
            Target::Module(p) => (0..=p.len())
                .rev()
                .find_map(|k| by_module.get(&p[..k]))
                .expect("the crate root is a module with a file")
                .clone(),
            Target::RootItem => root.file.clone(),
            Target::Outside => continue,
        };
        let (a, b) = (module_of(&file), module_of(&to));
        if a.starts_with(&b) || b.starts_with(&a) {
            continue;
        }
        let edge = Edge {
            file: file.clone(),
            line: n.line,
            text: n.text,
        };
        add(&mut graph, &file, &to, edge);
    }
    graph
}

/// The strongly connected components of more than one node (Tarjan), each sorted.
pub fn cycles(graph: &Graph) -> Vec<Vec<String>> {
    struct State<'a> {
        graph: &'a Graph,
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

/// A readable list of the edges inside a cycle: each edge with the places that make it (the
/// first few, and how many more).
pub fn describe(graph: &Graph, comp: &[String]) -> String {
    const SHOWN: usize = 3;
    let mut msg = String::new();
    for a in comp {
        for (b, places) in &graph[a] {
            if !comp.contains(b) {
                continue;
            }
            msg.push_str(&format!("    {a} -> {b}:\n"));
            for e in places.iter().take(SHOWN) {
                msg.push_str(&format!("      {}:{}  {}\n", e.file, e.line, e.text));
            }
            if places.len() > SHOWN {
                msg.push_str(&format!("      ({} more)\n", places.len() - SHOWN));
            }
        }
    }
    msg
}

//! The checker's own tests, on small examples.

use crate::graph::{ROOT, cycles, describe, file_graph, module_graph};
use crate::rust_source::functions;

fn sources(files: &[(&str, &str)]) -> Vec<(String, String)> {
    files
        .iter()
        .map(|(f, t)| (f.to_string(), t.to_string()))
        .collect()
}

/// Files with cycles at the file level: a -> b -> a, and two sibling files of a folder
/// naming each other (the folder's `mod.rs` and its children are one unit).
fn files_example() -> Vec<(String, String)> {
    sources(&[
        (
            "lib.rs",
            "//! crate::c::x in a comment is no edge\npub mod a;\npub mod b;\npub mod c;\n\
             pub mod out;\npub mod error;\npub use a::A;\n",
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
        // a parent re-exporting its children's items, a child naming the re-export, and two
        // siblings naming each other
        (
            "out/mod.rs",
            "mod frame;\nmod vtu;\npub use frame::Frame;\npub use self::vtu::write;\n",
        ),
        (
            "out/frame.rs",
            "pub struct Frame;\npub fn save() { super::vtu::write(&Frame) }\n",
        ),
        (
            "out/vtu.rs",
            "use super::Frame;\npub fn write(_: &super::frame::Frame) {}\n",
        ),
    ])
}

#[test]
fn file_graph_finds_the_known_cycles_of_an_example() {
    let graph = file_graph(&files_example());
    let edges = |f: &str| graph[f].keys().cloned().collect::<Vec<_>>();
    // the root's `pub use a::A` is a re-export, not an edge
    assert!(edges("lib.rs").is_empty());
    assert_eq!(edges("a.rs"), ["b.rs", "error.rs"]);
    assert_eq!(edges("b.rs"), ["a.rs"]);
    assert!(edges("c.rs").is_empty());
    // a parent and its children: no edges either way
    assert!(edges("out/mod.rs").is_empty());
    assert_eq!(edges("out/vtu.rs"), ["out/frame.rs"]);
    assert_eq!(edges("out/frame.rs"), ["out/vtu.rs"]);
    assert_eq!(graph["b.rs"]["a.rs"][0].line, 1);
    let comps = cycles(&graph);
    assert_eq!(
        comps,
        [
            vec!["a.rs".to_string(), "b.rs".into()],
            vec!["out/frame.rs".to_string(), "out/vtu.rs".into()],
        ]
    );
    let msg = describe(&graph, &comps[0]);
    assert!(msg.contains("b.rs:1  crate::a::helper"), "{msg}");
}

#[test]
fn module_graph_counts_a_folder_as_one_module() {
    let graph = module_graph(&files_example());
    let edges = |m: &str| graph[m].keys().cloned().collect::<Vec<_>>();
    assert_eq!(edges("a"), ["b", "error"]);
    // the cycle inside `out/` is inside one module
    assert!(edges("out").is_empty());
    assert_eq!(cycles(&graph), [vec!["a".to_string(), "b".into()]]);
}

/// A crate root that re-exports every module, an inline re-export module, a function of its
/// own that uses a module, and modules naming items through the root.
fn root_example() -> Vec<(String, String)> {
    sources(&[
        (
            "main.rs",
            "mod cmd;\nmod plot;\nmod store;\npub mod driver {\n    pub use crate::store::Db;\n}\n\
             pub use driver::Db;\npub use plot::draw as paint;\npub use fdem_mesh::excerpt;\n\
             fn main() { cmd::run(); }\n\
             fn write_atomically(_: &str) {}\n",
        ),
        // cmd uses plot by a leading child path and the root's re-exports
        (
            "cmd/mod.rs",
            "mod args;\npub fn run() { args::parse(); crate::paint(); crate::excerpt(); }\n",
        ),
        ("cmd/args.rs", "pub fn parse() {}\n"),
        // plot uses the root's own function: plot -> root -> cmd -> plot
        (
            "plot.rs",
            "pub fn draw() { crate::write_atomically(\"x\"); }\n",
        ),
        // store names `Db` through the root's re-export of the inline module: store -> driver
        // -> store
        (
            "store.rs",
            "pub struct Db;\npub fn open() -> crate::Db { Db }\n",
        ),
    ])
}

#[test]
fn module_graph_follows_the_roots_re_exports() {
    let graph = module_graph(&root_example());
    let edges = |m: &str| graph[m].keys().cloned().collect::<Vec<_>>();
    assert_eq!(edges(ROOT), ["cmd"]);
    // `crate::paint` leads to plot; `crate::excerpt` is another crate's item
    assert_eq!(edges("cmd"), ["plot"]);
    assert_eq!(edges("plot"), [ROOT]);
    assert_eq!(edges("driver"), ["store"]);
    assert_eq!(edges("store"), ["driver"]);
    assert_eq!(
        cycles(&graph),
        [
            vec![ROOT.to_string(), "cmd".into(), "plot".into()],
            vec!["driver".to_string(), "store".into()],
        ]
    );
    // the file graph leaves out a module's edges with its children and with the root
    let files = file_graph(&root_example());
    assert_eq!(files["cmd/mod.rs"].keys().collect::<Vec<_>>(), ["plot.rs"]);
    assert!(files["plot.rs"].is_empty());
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

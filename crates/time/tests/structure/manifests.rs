//! The crate graph: the workspace's crates and their dependencies on each other, read from
//! their `Cargo.toml` files, against the layers of the architecture guide and the table of
//! `docs/architecture.md`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use crate::workspace_root;

/// The layers of the architecture guide: a crate depends only on crates of a lower layer.
/// So fdem-time and fdem-mesh depend on no other crate of the workspace, fdem-contact and
/// fdem-fracture never depend on each other, and only fdem-solver and the crates above it
/// compose them. A new crate needs a layer here and a row in the guide's table.
const LAYERS: &[(&str, u32)] = &[
    ("fdem-figures", 0),
    ("fdem-time", 1),
    ("fdem-mesh", 1),
    ("fdem-contact", 2),
    ("fdem-fracture", 2),
    ("fdem-flow", 2),
    ("fdem-solver", 3),
    ("fdem-mpi", 4),
    ("fdem-python", 4),
    ("fdem", 5),
];

/// The guide whose table lists the crates and their dependencies.
const GUIDE: &str = "docs/architecture.md";

/// The header of that table.
const TABLE_HEADER: &str = "| layer | crate | folder | depends on |";

/// The kind of a dependency: `[dependencies]` and `[build-dependencies]` are what the crate
/// is built with; `[dev-dependencies]` only its tests, examples and benchmarks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    Normal,
    Dev,
}

/// One crate's manifest: its folder (`.`, `crates/mesh`), package name, and the packages
/// it depends on, by kind.
#[derive(Debug)]
struct Manifest {
    dir: String,
    name: String,
    deps: BTreeMap<Kind, BTreeSet<String>>,
}

/// A line without its comment (a `#` outside a string).
fn without_comment(line: &str) -> &str {
    let mut in_string = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_string = !in_string,
            '#' if !in_string => return &line[..i],
            _ => {}
        }
    }
    line
}

/// The value of `key = "value"` in a line, if the line sets it (also inside an inline
/// table: `{ package = "x", .. }`).
fn string_value(line: &str, key: &str) -> Option<String> {
    let at = line.find(key)?;
    let before = line[..at].chars().last();
    if before.is_some_and(|c| c.is_alphanumeric() || c == '-' || c == '_') {
        return None;
    }
    let rest = line[at + key.len()..].trim_start().strip_prefix('=')?;
    let rest = rest.trim_start().strip_prefix('"')?;
    Some(rest[..rest.find('"')?].to_string())
}

/// The kind of dependencies a table header holds, and the dependency it names itself
/// (`[dependencies.x]`): `dependencies`, `build-dependencies`, `dev-dependencies`, and the
/// same under `target.'cfg(..)'.`.
fn dependency_table(header: &str) -> Option<(Kind, Option<String>)> {
    let kind = |s: &str| match s {
        "dependencies" | "build-dependencies" => Some(Kind::Normal),
        "dev-dependencies" => Some(Kind::Dev),
        _ => None,
    };
    if let Some(k) = kind(header) {
        return Some((k, None));
    }
    if let Some(rest) = header.strip_prefix("target.") {
        let (_, last) = rest.rsplit_once('.')?;
        return kind(last).map(|k| (k, None));
    }
    let (table, name) = header.split_once('.')?;
    kind(table).map(|k| (k, Some(name.trim_matches('"').to_string())))
}

/// Reads `dir/Cargo.toml`: its package name and dependencies (any package; the workspace's
/// are picked out later). A dependency renamed with `package = ".."` counts under its
/// package's name.
fn manifest(dir: &str) -> Manifest {
    let path = workspace_root().join(dir).join("Cargo.toml");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut name = None;
    let mut deps: BTreeMap<Kind, BTreeSet<String>> = BTreeMap::new();
    let mut table = String::new();
    for raw in text.lines() {
        let line = without_comment(raw).trim();
        if let Some(h) = line.strip_prefix('[') {
            table = h.trim_matches(|c| c == '[' || c == ']').trim().to_string();
            if let Some((kind, Some(dep))) = dependency_table(&table) {
                deps.entry(kind).or_default().insert(dep);
            }
            continue;
        }
        if table == "package" && name.is_none() {
            name = string_value(line, "name");
        }
        let Some((kind, None)) = dependency_table(&table) else {
            continue;
        };
        let Some((key, _)) = line.split_once('=') else {
            continue;
        };
        let key = key
            .split('.')
            .next()
            .unwrap_or(key)
            .trim()
            .trim_matches('"');
        let package = string_value(line, "package").unwrap_or_else(|| key.to_string());
        deps.entry(kind).or_default().insert(package);
    }
    Manifest {
        dir: dir.to_string(),
        name: name.unwrap_or_else(|| panic!("{}: no [package] name", path.display())),
        deps,
    }
}

/// The member folders of the workspace other than `.`, from the root `Cargo.toml`'s
/// `members` (entries `"dir"` or `"dir/*"`), sorted.
pub fn member_dirs(root: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(root.join("Cargo.toml")).expect("the root Cargo.toml");
    let line = text
        .lines()
        .map(|l| without_comment(l).trim())
        .find(|l| l.starts_with("members"))
        .expect("the root Cargo.toml lists its workspace members on one line");
    let list = &line[line.find('[').expect("members = [..]") + 1..line.rfind(']').expect("]")];
    let mut out = Vec::new();
    for entry in list.split(',').map(|e| e.trim().trim_matches('"')) {
        if entry.is_empty() || entry == "." {
            continue;
        }
        if let Some(parent) = entry.strip_suffix("/*") {
            for e in std::fs::read_dir(root.join(parent)).expect("a members folder") {
                let p = e.expect("a directory entry").path();
                if p.join("Cargo.toml").is_file() {
                    let name = p.file_name().expect("a name").to_string_lossy().to_string();
                    out.push(format!("{parent}/{name}"));
                }
            }
        } else {
            out.push(entry.to_string());
        }
    }
    out.sort();
    out
}

/// Every crate of the workspace with its dependencies on the workspace's crates only.
fn workspace_manifests() -> Vec<Manifest> {
    let dirs = std::iter::once(".".to_string()).chain(member_dirs(&workspace_root()));
    let mut all: Vec<Manifest> = dirs.map(|d| manifest(&d)).collect();
    let names: BTreeSet<String> = all.iter().map(|m| m.name.clone()).collect();
    for m in &mut all {
        for set in m.deps.values_mut() {
            set.retain(|d| names.contains(d));
        }
    }
    all
}

fn layer(name: &str) -> Option<u32> {
    LAYERS.iter().find(|(n, _)| *n == name).map(|(_, l)| *l)
}

/// The crates' dependencies (of both kinds) point to a strictly lower layer: so there is
/// no cycle, time and mesh depend on no other crate, contact and fracture not on each
/// other, and only the solver and the crates above it compose them.
#[test]
fn crate_dependencies_point_down_the_layers() {
    let all = workspace_manifests();
    assert!(all.len() >= 8, "the workspace's crates were found: {all:?}");
    let mut problems = Vec::new();
    for m in &all {
        let Some(l) = layer(&m.name) else {
            problems.push(format!(
                "{}/Cargo.toml: {} has no layer: add it to LAYERS (crates/time/tests/structure/manifests.rs) \
                 and to the table of {GUIDE}",
                m.dir, m.name
            ));
            continue;
        };
        for (kind, deps) in &m.deps {
            for d in deps {
                let ld = layer(d).unwrap_or(u32::MAX);
                if ld >= l {
                    problems.push(format!(
                        "{}/Cargo.toml: {} (layer {l}) depends on {d} (layer {ld}) as a {} \
                         dependency: a crate may depend only on a lower layer ({GUIDE})",
                        m.dir,
                        m.name,
                        if *kind == Kind::Dev { "dev-" } else { "normal" }
                    ));
                }
            }
        }
    }
    for (name, _) in LAYERS {
        if !all.iter().any(|m| m.name == *name) {
            problems.push(format!(
                "LAYERS names {name}, which is no crate of the workspace"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// One row of the guide's table: (layer, crate, folder, dependencies).
type Row = (u32, String, String, BTreeSet<String>);

/// The words in backticks of a table cell.
fn quoted(cell: &str) -> Vec<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The rows of the crate table of the guide, with the line of each.
fn guide_table() -> Vec<(usize, Row)> {
    let text = std::fs::read_to_string(workspace_root().join(GUIDE)).expect("the guide");
    let lines: Vec<&str> = text.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim() == TABLE_HEADER)
        .unwrap_or_else(|| panic!("{GUIDE}: no table with the header `{TABLE_HEADER}`"));
    let mut rows = Vec::new();
    for (k, l) in lines.iter().enumerate().skip(start + 2) {
        if !l.trim_start().starts_with('|') {
            break;
        }
        let cells: Vec<&str> = l.trim().trim_matches('|').split('|').collect();
        assert_eq!(cells.len(), 4, "{GUIDE}:{}: four cells expected", k + 1);
        let layer = cells[0].trim().parse().unwrap_or_else(|_| {
            panic!("{GUIDE}:{}: the layer is a number", k + 1);
        });
        let name = quoted(cells[1]).into_iter().next();
        let folder = quoted(cells[2]).into_iter().next();
        let (Some(name), Some(folder)) = (name, folder) else {
            panic!("{GUIDE}:{}: the crate and its folder in backticks", k + 1);
        };
        rows.push((
            k + 1,
            (layer, name, folder, quoted(cells[3]).into_iter().collect()),
        ));
    }
    rows
}

/// The guide's table lists every crate once, in its folder and layer, with exactly the
/// crates it depends on (`[dependencies]` and `[build-dependencies]`).
#[test]
fn the_guides_crate_table_matches_the_manifests() {
    let rows = guide_table();
    let mut expected: BTreeMap<String, Row> = BTreeMap::new();
    for m in workspace_manifests() {
        let deps = m.deps.get(&Kind::Normal).cloned().unwrap_or_default();
        let l = layer(&m.name).unwrap_or(u32::MAX);
        expected.insert(m.name.clone(), (l, m.name, m.dir, deps));
    }
    let mut problems = Vec::new();
    let mut listed = BTreeSet::new();
    for (line, row) in &rows {
        let name = &row.1;
        if !listed.insert(name.clone()) {
            problems.push(format!("{GUIDE}:{line}: {name} is listed twice"));
        }
        match expected.get(name) {
            None => problems.push(format!(
                "{GUIDE}:{line}: {name} is no crate of the workspace"
            )),
            Some(e) if e != row => problems.push(format!(
                "{GUIDE}:{line}: the row of {name} says layer {}, folder `{}`, depends on \
                 {:?}; the manifests and LAYERS say layer {}, folder `{}`, depends on {:?}",
                row.0, row.2, row.3, e.0, e.2, e.3
            )),
            Some(_) => {}
        }
    }
    for name in expected.keys() {
        if !listed.contains(name) {
            problems.push(format!("{GUIDE}: the crate table has no row for {name}"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn manifest_lines_are_read_as_cargo_reads_them() {
    assert_eq!(without_comment("a = \"x#y\" # note"), "a = \"x#y\" ");
    assert_eq!(
        string_value("name = \"fdem-mesh\"", "name"),
        Some("fdem-mesh".into())
    );
    assert_eq!(string_value("rename = \"x\"", "name"), None);
    assert_eq!(
        string_value("m = { package = \"fdem-mesh\", path = \"..\" }", "package"),
        Some("fdem-mesh".into())
    );
    assert_eq!(dependency_table("dependencies"), Some((Kind::Normal, None)));
    assert_eq!(
        dependency_table("build-dependencies"),
        Some((Kind::Normal, None))
    );
    assert_eq!(
        dependency_table("target.'cfg(unix)'.dev-dependencies"),
        Some((Kind::Dev, None))
    );
    assert_eq!(
        dependency_table("dependencies.fdem-time"),
        Some((Kind::Normal, Some("fdem-time".into())))
    );
    assert_eq!(dependency_table("workspace.dependencies"), None);
    assert_eq!(dependency_table("package"), None);
    assert_eq!(
        quoted("`fdem-solver`, `fdem-time`"),
        ["fdem-solver", "fdem-time"]
    );
}

/// Every `.rs` file directly under the `tests/` of a crate whose `autotests` is off is
/// compiled: a module of its `tests/all.rs` (`#[path = "x.rs"]`) or a `[[test]]` of its
/// `Cargo.toml`. A file left out of both would silently never run.
#[test]
fn every_test_file_is_compiled() {
    let root = workspace_root();
    let mut problems = Vec::new();
    for dir in std::iter::once(".".to_string()).chain(member_dirs(&root)) {
        let manifest = std::fs::read_to_string(root.join(&dir).join("Cargo.toml"))
            .expect("a crate's Cargo.toml");
        let autotests_off = manifest
            .lines()
            .any(|l| without_comment(l).replace(' ', "") == "autotests=false");
        let tests = root.join(&dir).join("tests");
        let (true, Ok(entries)) = (autotests_off, std::fs::read_dir(&tests)) else {
            continue;
        };
        let all = std::fs::read_to_string(tests.join("all.rs")).unwrap_or_default();
        for e in entries {
            let name = e.expect("a directory entry").file_name();
            let name = name.to_string_lossy();
            if name.ends_with(".rs")
                && name != "all.rs"
                && !all.contains(&format!("#[path = \"{name}\"]"))
                && !manifest.contains(&format!("path = \"tests/{name}\""))
            {
                problems.push(format!(
                    "{dir}/tests/{name} is neither a module of tests/all.rs nor a [[test]] of \
                     Cargo.toml"
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

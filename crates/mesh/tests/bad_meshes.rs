//! Bad meshes give an error that names the fault (and the file and item), never a panic.

use crate::common;
use fdem_mesh::{MeshError, read_mesh_bytes};
use std::path::Path;

/// A 2x1 square of two triangles in Gmsh 2.2 with a physical surface "body" and a line
/// "bottom"; `extra_nodes` and `elements` are spliced in.
fn v22(nodes: &str, elements: &str) -> String {
    let ne = elements.lines().filter(|l| !l.trim().is_empty()).count();
    let nn = nodes.lines().filter(|l| !l.trim().is_empty()).count();
    format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 2 \"bottom\"\n2 1 \"body\"\n$EndPhysicalNames\n$Nodes\n{nn}\n{nodes}$EndNodes\n$Elements\n{ne}\n{elements}$EndElements\n"
    )
}

const NODES: &str = "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n";
const ELEMS: &str = "1 1 2 2 1 1 2\n2 2 2 1 1 1 2 3\n3 2 2 1 1 1 3 4\n";

fn read(s: &str) -> Result<fdem_mesh::Mesh, MeshError> {
    read_mesh_bytes(s.as_bytes(), "test.msh")
}

/// The reference small mesh reads, with its groups.
#[test]
fn good_small_mesh_reads() {
    let m = read(&v22(NODES, ELEMS)).unwrap();
    assert_eq!((m.n_nodes(), m.n_triangles()), (4, 2));
    assert_eq!(m.group("body").unwrap().triangles.len(), 2);
    assert_eq!(m.group("bottom").unwrap().edges.len(), 1);
    assert_eq!(m.boundary_edges.len(), 4);
    assert_eq!(m.edges.len(), 5);
}

/// A clockwise triangle is only a node-order fault: it is reversed and counted.
#[test]
fn clockwise_triangle_is_reoriented() {
    let m = read(&v22(NODES, "2 2 2 1 1 1 3 2\n3 2 2 1 1 1 3 4\n")).unwrap();
    assert_eq!(m.reoriented, 1);
    for t in 0..2 {
        assert!(m.area(fdem_mesh::TriId(t)) > 0.0);
    }
}

/// Zero area names the element tag.
#[test]
fn zero_area_triangle_is_an_error() {
    let nodes = "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n";
    let e = read(&v22(
        nodes,
        "7 2 2 1 1 1 2 5\n2 2 2 1 1 1 2 3\n3 2 2 1 1 1 3 4\n",
    ))
    .unwrap_err();
    assert!(matches!(e, MeshError::ZeroArea { element: 7, .. }), "{e}");
    assert!(e.to_string().contains("element 7"), "{e}");
}

/// Two nodes at the same place name both tags.
#[test]
fn duplicate_nodes_are_an_error() {
    let nodes = "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n9 1 1 0\n";
    let e = read(&v22(nodes, "2 2 2 1 1 1 2 3\n3 2 2 1 1 1 9 4\n")).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::DuplicateNodes {
                tag_a: 3,
                tag_b: 9,
                ..
            }
        ),
        "{e}"
    );
}

/// A node tag defined twice.
#[test]
fn duplicate_node_tag_is_an_error() {
    let nodes = "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n4 5 5 0\n";
    let e = read(&v22(nodes, ELEMS)).unwrap_err();
    assert!(
        matches!(e, MeshError::DuplicateNodeTag { node: 4, .. }),
        "{e}"
    );
}

/// A node no triangle uses names the node tag.
#[test]
fn unused_node_is_an_error() {
    let nodes = "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 3 3 0\n";
    let e = read(&v22(nodes, ELEMS)).unwrap_err();
    assert!(matches!(e, MeshError::UnusedNode { tag: 5, .. }), "{e}");
}

/// An element that refers to an undefined node.
#[test]
fn unknown_node_is_an_error() {
    let e = read(&v22(NODES, "2 2 2 1 1 1 2 8\n")).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::UnknownNode {
                element: 2,
                node: 8,
                ..
            }
        ),
        "{e}"
    );
}

/// Asking for a group that is not there lists the groups there are.
#[test]
fn missing_group_is_an_error_listing_the_groups() {
    let m = read(&v22(NODES, ELEMS)).unwrap();
    let e = m.group("load_top").unwrap_err();
    assert!(matches!(e, MeshError::MissingGroup { .. }));
    let s = e.to_string();
    assert!(
        s.contains("load_top") && s.contains("body") && s.contains("bottom"),
        "{s}"
    );
}

/// Quadrangles (type 3) and quadratic triangles (type 9) are refused by name.
#[test]
fn unsupported_element_type_is_an_error() {
    let e = read(&v22(NODES, "5 3 2 1 1 1 2 3 4\n")).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::UnsupportedElement {
                element: 5,
                gmsh_type: 3,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("quadrangle"));
}

/// Format versions other than 4.1 and 2.2 ASCII.
#[test]
fn unsupported_version_is_an_error() {
    let s = v22(NODES, ELEMS).replace("2.2 0 8", "3.0 0 8");
    assert!(matches!(
        read(&s).unwrap_err(),
        MeshError::UnsupportedVersion { .. }
    ));
}

fn cantilever(name: &str) -> Vec<u8> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name);
    std::fs::read(p).unwrap()
}

/// Every truncation of the three encodings (at 200 points through the file) is an error.
#[test]
fn truncated_files_are_errors() {
    for name in [
        "cantilever-coarse.msh",
        "cantilever-coarse-bin.msh",
        "cantilever-coarse-v22.msh",
    ] {
        let b = cantilever(name);
        assert!(read_mesh_bytes(&b, name).is_ok());
        for k in 0..200 {
            // keep at least the first byte; the last cuts lose the final $End line
            let len = 1 + (b.len() - 12) * k / 200;
            let r = read_mesh_bytes(&b[..len], name);
            assert!(r.is_err(), "{name} cut at {len} read without error");
        }
    }
}

/// A binary file with the endianness marker of a big-endian writer.
#[test]
fn binary_of_wrong_endianness_is_an_error() {
    let mut b = cantilever("cantilever-coarse-bin.msh");
    let pos = b.windows(8).position(|w| w == b"4.1 1 8\n").unwrap() + 8;
    assert_eq!(&b[pos..pos + 4], &1i32.to_le_bytes());
    b[pos..pos + 4].copy_from_slice(&1i32.to_be_bytes());
    let e = read_mesh_bytes(&b, "big.msh").unwrap_err();
    assert!(matches!(e, MeshError::WrongEndianness { .. }), "{e}");
}

/// Garbage, empty files, random bytes and random byte flips in valid files are errors or
/// (for harmless flips) meshes, never panics.
#[test]
fn garbage_never_panics() {
    for g in [
        &b""[..],
        b"   ",
        b"hello world",
        b"{\"nodes\": 3}",
        b"$MeshFormat\n",
        b"\x00\xff\x13",
    ] {
        assert!(read_mesh_bytes(g, "g").is_err());
    }
    let mut rng = common::Rng(12345);
    for _ in 0..200 {
        let n = (rng.next() * 400.0) as usize;
        let b: Vec<u8> = (0..n).map(|_| (rng.next() * 256.0) as u8).collect();
        assert!(read_mesh_bytes(&b, "random").is_err());
    }
    for name in [
        "cantilever-coarse.msh",
        "cantilever-coarse-bin.msh",
        "cantilever-coarse-v22.msh",
    ] {
        let b = cantilever(name);
        for _ in 0..300 {
            let mut c = b.clone();
            for _ in 0..3 {
                let i = (rng.next() * c.len() as f64) as usize;
                c[i] = (rng.next() * 256.0) as u8;
            }
            let _ = read_mesh_bytes(&c, name); // must return, not panic
        }
    }
}

/// JSON: good file reads; bad index, unknown field and bad syntax are errors naming the fault.
#[test]
fn json_mesh_reads_and_rejects_faults() {
    let good = r#"{"nodes": [[0,0],[1,0],[1,1],[0,1]], "triangles": [[0,1,2],[0,2,3]],
        "groups": [{"name": "body", "dim": 2, "triangles": [0, 1]},
                   {"name": "bottom", "dim": 1, "edges": [[1, 0]]},
                   {"name": "corner", "dim": 0, "nodes": [0]}]}"#;
    let m = read_mesh_bytes(good.as_bytes(), "m.json").unwrap();
    assert_eq!(
        m.group("bottom").unwrap().edges[0],
        [fdem_mesh::NodeId(0), fdem_mesh::NodeId(1)]
    );
    let bad_index = good.replace("[0,2,3]", "[0,2,7]");
    assert!(matches!(
        read_mesh_bytes(bad_index.as_bytes(), "m.json").unwrap_err(),
        MeshError::UnknownNode { node: 7, .. }
    ));
    let unknown = good.replace("\"groups\"", "\"grups\"");
    let e = read_mesh_bytes(unknown.as_bytes(), "m.json").unwrap_err();
    assert!(
        matches!(e, MeshError::Json { .. }) && e.to_string().contains("grups"),
        "{e}"
    );
    let e = read_mesh_bytes(b"{\"nodes\": [[0,0],", "m.json").unwrap_err();
    assert!(matches!(e, MeshError::Json { .. }), "{e}");
}

/// JSON round trip of a real mesh keeps nodes, triangles and groups.
#[test]
fn json_round_trip_keeps_the_mesh() {
    let a = fdem_mesh::read_mesh(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/notched-beam.msh"),
    )
    .unwrap();
    let dir = std::env::temp_dir().join(format!("fdem-mesh-json-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("nb.json");
    fdem_mesh::write_json(&a, &p).unwrap();
    let b = fdem_mesh::read_mesh(&p).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(a.nodes, b.nodes);
    assert_eq!(a.triangles, b.triangles);
    assert_eq!(a.regions, b.regions);
    assert_eq!(a.tri_region, b.tri_region);
    for (ga, gb) in a.groups.iter().zip(&b.groups) {
        assert_eq!(
            (&ga.name, ga.dim, &ga.nodes, &ga.edges, &ga.triangles),
            (&gb.name, gb.dim, &gb.nodes, &gb.edges, &gb.triangles)
        );
    }
}

/// Groups are sets: a node, an edge (in either direction) or a triangle listed twice in one
/// group is refused, naming the group and the entity, in JSON and in Gmsh files.
#[test]
fn class2_groups_that_repeat_entities_are_refused() {
    let good = r#"{"nodes": [[0,0],[1,0],[1,1],[0,1]], "triangles": [[0,1,2],[0,2,3]],
        "groups": [{"name": "body", "dim": 2, "triangles": [0, 1]},
                   {"name": "bottom", "dim": 1, "edges": [[1, 0]]},
                   {"name": "corner", "dim": 0, "nodes": [0, 1]}]}"#;
    assert!(read_mesh_bytes(good.as_bytes(), "m.json").is_ok());
    for (from, to, needle) in [
        (
            "[[1, 0]]",
            "[[1, 0], [0, 1]]",
            "the edge between nodes 0 and 1",
        ),
        (
            "[[1, 0]]",
            "[[1, 0], [1, 0]]",
            "the edge between nodes 1 and 0",
        ),
        ("[0, 1]}]", "[0, 1, 0]}]", "node 0"),
        ("[0, 1]}", "[0, 1, 1]}", "triangle 1"),
    ] {
        let bad = good.replacen(from, to, 1);
        assert_ne!(bad, good);
        let e = read_mesh_bytes(bad.as_bytes(), "m.json").unwrap_err();
        assert!(
            matches!(e, MeshError::RepeatedInGroup { .. }),
            "{to}: {e:?}"
        );
        let s = e.to_string();
        assert!(
            s.contains(needle) && s.contains("twice") && s.contains("m.json"),
            "{s}"
        );
    }
    // Gmsh: the line element of "bottom" given twice (second time reversed)
    let e = read(&v22(NODES, &format!("{ELEMS}4 1 2 2 1 2 1\n"))).unwrap_err();
    assert!(matches!(e, MeshError::RepeatedInGroup { .. }), "{e:?}");
    assert!(e.to_string().contains("\"bottom\""), "{e}");
}

/// A UTF-8 byte-order mark before a mesh is named as such.
#[test]
fn class1_a_byte_order_mark_before_a_mesh_is_named() {
    let good = r#"{"nodes": [[0,0],[1,0],[1,1]], "triangles": [[0,1,2]], "groups": []}"#;
    assert!(read_mesh_bytes(good.as_bytes(), "m.json").is_ok());
    let mut bom = vec![0xEF, 0xBB, 0xBF];
    bom.extend_from_slice(good.as_bytes());
    let e = read_mesh_bytes(&bom, "m.json").unwrap_err().to_string();
    assert!(e.contains("byte-order mark") && e.contains("m.json"), "{e}");
    // text after the mesh's object is refused, not ignored
    let e = read_mesh_bytes(format!("{good} {{}}").as_bytes(), "m.json").unwrap_err();
    assert!(e.to_string().contains("trailing"), "{e}");
}

//! The mesh build and the explode run partly in parallel (the edge keys and their sort, the
//! internal edges, the exploded node arrays): on a 100 x 100 grid of 20 000 triangles (many
//! rayon tasks), with and without groups, the built and exploded meshes are the same bit for
//! bit in pools of 1, 2 and 3 threads, the edges are those of the serial sort they replaced
//! (kept here as the reference), and the groups' edges and points are exploded as before
//! (checked against their definition).

use fdem_mesh::{EdgeId, Exploded, Mesh, MeshEdge, NodeId, PhysicalGroup, RawMesh, TriId, explode};

/// `n x n` cells of side 1/n, two triangles per cell (diagonals alternating, every other
/// triangle given clockwise), with a surface group of the left half, an edge group of the
/// bottom and a point group of two corners when `groups`.
fn grid(n: usize, groups: bool) -> RawMesh {
    let mut nodes = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let dy = if j > 0 && j < n {
                1e-3 * (i % 3) as f64
            } else {
                0.0
            };
            nodes.push([i as f64 / n as f64, j as f64 / n as f64 + dy]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                triangles.push([a, b, c]);
                triangles.push([a, d, c]);
            } else {
                triangles.push([a, b, d]);
                triangles.push([b, d, c]);
            }
        }
    }
    let group = |name: &str, dim: u8, tag: i64| PhysicalGroup {
        name: name.into(),
        dim,
        tag,
        nodes: Vec::new(),
        edges: Vec::new(),
        triangles: Vec::new(),
    };
    let mut gs = Vec::new();
    if groups {
        let mut left = group("left", 2, 1);
        left.triangles = (0..triangles.len())
            .filter(|t| (t / 2) % n < n / 2)
            .map(|t| TriId(t as u32))
            .collect();
        let mut bottom = group("bottom", 1, 2);
        bottom.edges = (0..n)
            .map(|i| [NodeId(id(i + 1, 0)), NodeId(id(i, 0))])
            .collect();
        let mut corners = group("corners", 0, 3);
        corners.nodes = vec![NodeId(id(0, 0)), NodeId(id(n, n))];
        gs = vec![left, bottom, corners];
    }
    RawMesh {
        path: "grid".into(),
        node_tags: (0..nodes.len() as u64).collect(),
        nodes,
        tri_tags: (0..triangles.len() as u64).collect(),
        triangles,
        groups: gs,
    }
}

/// Every value of a mesh (positions as bits).
fn mesh_key(m: &Mesh) -> String {
    let bits: Vec<[u64; 2]> = m.nodes.iter().map(|p| p.map(f64::to_bits)).collect();
    format!(
        "{bits:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {}",
        m.triangles,
        m.tri_region,
        m.regions,
        m.groups,
        m.edges,
        m.tri_edges,
        m.boundary_edges,
        m.node_tags,
        m.tri_tags,
        m.reoriented
    )
}

fn exploded_key(ex: &Exploded) -> String {
    format!(
        "{} {:?} {:?}",
        mesh_key(&ex.mesh),
        ex.original_node,
        ex.internal_edges
    )
}

/// The serial edge construction the build replaced: every (min, max, triangle, local edge)
/// key sorted on one thread, one edge per run of equal node pairs.
fn serial_edges(tris: &[[u32; 3]]) -> (Vec<MeshEdge>, Vec<[EdgeId; 3]>) {
    let mut keys = Vec::new();
    for (t, tri) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            keys.push((a.min(b), a.max(b), t as u32, k as u8));
        }
    }
    keys.sort();
    let (mut edges, mut tri_edges) = (Vec::new(), vec![[EdgeId(0); 3]; tris.len()]);
    let mut i = 0;
    while i < keys.len() {
        let shared = i + 1 < keys.len() && keys[i + 1].0 == keys[i].0 && keys[i + 1].1 == keys[i].1;
        let (_, _, t, k) = keys[i];
        let id = EdgeId(edges.len() as u32);
        tri_edges[t as usize][k as usize] = id;
        let right = shared.then(|| {
            let (_, _, t2, k2) = keys[i + 1];
            tri_edges[t2 as usize][k2 as usize] = id;
            TriId(t2)
        });
        let tri = tris[t as usize];
        edges.push(MeshEdge {
            nodes: [NodeId(tri[k as usize]), NodeId(tri[(k as usize + 1) % 3])],
            left: TriId(t),
            right,
        });
        i += if shared { 2 } else { 1 };
    }
    (edges, tri_edges)
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn build_and_explode_are_the_same_bits_on_any_number_of_threads() {
    for groups in [false, true] {
        let raw = grid(100, groups);
        let mut keys = Vec::new();
        for threads in [1, 2, 3] {
            let (mesh, whole, part) = in_pool(threads, || {
                let mesh = Mesh::from_parts(raw.clone()).unwrap();
                let whole = explode(&mesh, None).unwrap();
                let part = groups.then(|| explode(&mesh, Some(&["left"])).unwrap());
                (mesh, whole, part)
            });
            assert_eq!(mesh.triangles.len(), 20_000);
            assert_eq!(mesh.reoriented, 10_000);
            assert_eq!(
                (mesh.edges.clone(), mesh.tri_edges.clone()),
                serial_edges(&mesh.triangles)
            );
            assert_eq!(
                (whole.mesh.edges.clone(), whole.mesh.tri_edges.clone()),
                serial_edges(&whole.mesh.triangles)
            );
            assert_eq!(whole.internal_edges.len(), 29_800);
            keys.push(format!(
                "{} {} {}",
                mesh_key(&mesh),
                exploded_key(&whole),
                part.as_ref().map_or(String::new(), exploded_key)
            ));
            if let Some(part) = &part {
                check_groups(&mesh, part);
            }
        }
        assert!(
            keys[1] == keys[0],
            "2 threads differ from 1 (groups {groups})"
        );
        assert!(
            keys[2] == keys[0],
            "3 threads differ from 1 (groups {groups})"
        );
    }
}

/// The exploded groups from their definition: the point group holds every copy of its
/// original nodes; each bottom edge becomes the edge of its one triangle's copies, oriented
/// as that triangle runs (CCW: the outward normal points down, -y).
fn check_groups(mesh: &Mesh, ex: &Exploded) {
    let corners = ex.mesh.group("corners").unwrap();
    let orig = &mesh.group("corners").unwrap().nodes;
    let want: Vec<NodeId> = (0..ex.original_node.len())
        .filter(|&i| orig.contains(&ex.original_node[i]))
        .map(|i| NodeId(i as u32))
        .collect();
    assert!(
        want.len() > orig.len(),
        "the corner in the left group has copies"
    );
    assert_eq!(corners.nodes, want);
    let bottom = ex.mesh.group("bottom").unwrap();
    assert_eq!(bottom.edges.len(), 100);
    for e in &bottom.edges {
        let [a, b] = e.map(|n| ex.mesh.nodes[n.idx()]);
        assert!(a[1] == 0.0 && b[1] == 0.0 && b[0] > a[0], "{a:?} -> {b:?}");
    }
}

/// Two flat triangles in different rayon tasks: the first in triangle order is named, on any
/// number of threads.
#[test]
fn the_first_flat_triangle_is_named_on_any_number_of_threads() {
    let mut raw = grid(100, false);
    for t in [17_001, 3_001] {
        let [a, b, _] = raw.triangles[t];
        raw.triangles[t] = [a, b, a];
    }
    for threads in [1, 2, 3] {
        let e = in_pool(threads, || Mesh::from_parts(raw.clone())).unwrap_err();
        assert!(
            matches!(
                e,
                fdem_mesh::MeshError::ZeroArea {
                    tri: TriId(3_001),
                    element: 3_001,
                    ..
                }
            ),
            "{threads} thread(s): {e}"
        );
    }
}

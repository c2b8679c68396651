//! Every mesh in meshes/ loads with the node, triangle and group counts that meshio 5.3.5
//! reports for it (the table below was printed by `tests/python/mesh_counts.py --print`, which
//! also checks it against meshio), and the mesh is valid for the solver.

use fdem_mesh::{Elements, Material, read_mesh};
use std::path::Path;

/// (file, nodes, triangles, "group:dim:count,...") as meshio reports them; count is points,
/// lines or triangles of the group.
const MESHIO_COUNTS: &[(&str, usize, usize, &str)] = &[
    (
        "griffith-plate-coarse.msh",
        1151,
        2242,
        "crack:1:27,ligament:1:36,top:1:13,bottom:1:13,strip:2:446,bulk:2:1796",
    ),
    (
        "griffith-plate.msh",
        1677,
        3294,
        "crack:1:37,ligament:1:48,top:1:13,bottom:1:13,strip:2:976,bulk:2:2318",
    ),
    (
        "wing-crack.msh",
        1255,
        2388,
        "flaw:1:14,bottom:1:20,right:1:40,top:1:20,left:1:40,rock:2:2388",
    ),
    (
        "dfn-block.msh",
        1755,
        3428,
        "dfn:1:108,bottom:1:20,right:1:20,top:1:20,left:1:20,rock:2:3428",
    ),
    (
        "block-coarse.msh",
        230,
        406,
        "bottom:1:13,right:1:13,top:1:13,left:1:13,body:2:406",
    ),
    (
        "notched-beam-coarse.msh",
        975,
        1831,
        "support_left:0:1,support_right:0:1,load_top:0:1,bottom:1:46,notch:1:11,top:1:46,load:1:4,left:1:5,right:1:5,bulk:2:1194,fracture_zone:2:637",
    ),
    (
        "block.msh",
        1544,
        2936,
        "bottom:1:25,right:1:50,top:1:25,left:1:50,body:2:2936",
    ),
    (
        "disc-fracture.msh",
        469,
        864,
        "top:0:1,bottom:0:1,center:0:1,rim:1:72,body:2:864",
    ),
    (
        "disc-small.msh",
        217,
        384,
        "top:0:1,bottom:0:1,center:0:1,rim:1:48,body:2:384",
    ),
    (
        "hertz-disc.msh",
        3351,
        6526,
        "bottom:0:1,top:0:1,center:0:1,rim:1:174,body:2:6526",
    ),
    (
        "brazilian-disc.msh",
        9838,
        19298,
        "top:0:1,bottom:0:1,center:0:1,load_top:1:30,load_bottom:1:30,rim:1:316,body:2:19298",
    ),
    (
        "cantilever-coarse-bin.msh",
        375,
        636,
        "tip:0:1,root_mid:0:1,bottom:1:50,right:1:6,top:1:50,left:1:6,body:2:636",
    ),
    (
        "cantilever-coarse-v22.msh",
        375,
        636,
        "tip:0:1,root_mid:0:1,bottom:1:50,right:1:6,top:1:50,left:1:6,body:2:636",
    ),
    (
        "cantilever-coarse.msh",
        375,
        636,
        "tip:0:1,root_mid:0:1,bottom:1:50,right:1:6,top:1:50,left:1:6,body:2:636",
    ),
    (
        "cantilever-fine.msh",
        4910,
        9378,
        "tip:0:1,root_mid:0:1,bottom:1:200,right:1:20,top:1:200,left:1:20,body:2:9378",
    ),
    (
        "long-bar.msh",
        1761,
        3010,
        "probe_25:0:1,probe_50:0:1,probe_75:0:1,bottom:1:250,right:1:5,top:1:250,left:1:5,body:2:3010",
    ),
    (
        "notched-beam.msh",
        7477,
        14595,
        "support_left:0:1,support_right:0:1,load_top:0:1,bottom:1:140,notch:1:29,top:1:148,left:1:20,right:1:20,bulk:2:10694,fracture_zone:2:3901",
    ),
    (
        "plate-with-hole.msh",
        3590,
        6875,
        "bottom:1:54,right:1:20,top:1:20,left:1:54,hole:1:155,body:2:6875",
    ),
    (
        "thick-cylinder.msh",
        5124,
        9891,
        "bottom:1:41,outer:1:79,left:1:41,inner:1:194,body:2:9891",
    ),
];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .parent()
        .unwrap()
}

/// Node, triangle and per-group counts equal meshio's, for every file in meshes/.
#[test]
fn meshes_load_with_meshio_counts() {
    let mut files: Vec<_> = std::fs::read_dir(root().join("meshes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "msh"))
        .collect();
    files.sort();
    assert_eq!(
        files.len(),
        MESHIO_COUNTS.len(),
        "a mesh is not in the table"
    );
    for (name, nodes, tris, groups) in MESHIO_COUNTS {
        let m = read_mesh(root().join("meshes").join(name)).unwrap();
        assert_eq!(m.n_nodes(), *nodes, "{name}");
        assert_eq!(m.n_triangles(), *tris, "{name}");
        let got: Vec<String> = m
            .groups
            .iter()
            .map(|g| {
                let n = match g.dim {
                    0 => g.nodes.len(),
                    1 => g.edges.len(),
                    _ => g.triangles.len(),
                };
                format!("{}:{}:{}", g.name, g.dim, n)
            })
            .collect();
        assert_eq!(got.join(","), *groups, "{name}");
        assert_eq!(m.reoriented, 0, "{name}: gmsh writes CCW triangles");
        // Valid for the kernels: positive areas, total area equals the group areas.
        let el =
            Elements::new(&m, &vec![Material::new(1e9, 0.25, 2000.0); m.regions.len()]).unwrap();
        assert!(el.tris.iter().all(|t| t.area0 > 0.0));
    }
}

/// The three encodings of cantilever-coarse (4.1 ASCII, 4.1 binary, 2.2 ASCII) give the same
/// mesh: identical triangles and groups, positions equal to 1e-15 of the size (the ASCII files
/// hold 16 significant digits, the binary file the exact doubles).
#[test]
fn ascii_binary_and_v22_readers_agree() {
    let dir = root().join("meshes");
    let a = read_mesh(dir.join("cantilever-coarse.msh")).unwrap();
    for other in ["cantilever-coarse-bin.msh", "cantilever-coarse-v22.msh"] {
        let b = read_mesh(dir.join(other)).unwrap();
        assert_eq!(a.nodes.len(), b.nodes.len(), "{other}");
        let dmax = a
            .nodes
            .iter()
            .zip(&b.nodes)
            .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
            .fold(0.0, f64::max);
        assert!(dmax < 1e-15 * 10.0, "{other}: positions differ by {dmax}");
        assert_eq!(a.triangles, b.triangles, "{other}");
        assert_eq!(a.groups, b.groups, "{other}");
    }
}

/// Geometry of the specimens: areas of the body match the .geo geometry to the polygonal
/// approximation of arcs (relative error below (pi h / R)^2 / 6 bounds, stated per mesh).
#[test]
fn mesh_areas_match_geometry() {
    use std::f64::consts::PI;
    let dir = root().join("meshes");
    let area = |f: &str| {
        let m = read_mesh(dir.join(f)).unwrap();
        (0..m.n_triangles())
            .map(|t| m.area(fdem_mesh::TriId(t as u32)))
            .sum::<f64>()
    };
    let cases = [
        ("block.msh", 0.05 * 0.1, 1e-12),
        ("cantilever-fine.msh", 10.0, 1e-12),
        ("long-bar.msh", 0.02, 1e-12),
        ("notched-beam.msh", 0.2 * 0.05 - 0.002 * 0.01, 1e-12),
        ("notched-beam-coarse.msh", 0.2 * 0.05 - 0.002 * 0.01, 1e-12),
        ("block-coarse.msh", 0.05 * 0.05, 1e-12),
        ("griffith-plate-coarse.msh", 1.0, 1e-12),
        ("griffith-plate.msh", 1.0, 1e-12),
        ("wing-crack.msh", 0.05 * 0.1, 1e-12),
        ("dfn-block.msh", 1.0, 1e-12),
        // arcs: chord error of a segment of angle dt is R^2 (dt - sin dt)/2 ~ R^2 dt^3/12
        ("brazilian-disc.msh", PI * 0.025f64.powi(2), 1e-3),
        ("thick-cylinder.msh", PI / 4.0 * 3.0, 1e-3),
        ("plate-with-hole.msh", 0.01 - PI / 4.0 * 1e-4, 1e-4),
    ];
    for (f, exact, tol) in cases {
        let a = area(f);
        assert!(((a - exact) / exact).abs() < tol, "{f}: {a} vs {exact}");
    }
}

//! Writes CSV data of the static validations for docs/mesh.md figures (plotted by
//! scripts/plot_mesh_validation.py): hoop stress of every triangle of thick-cylinder.msh
//! against Lame, and sigma_xx of the triangles along x = 0 of plate-with-hole.msh against
//! Kirsch. `cargo run --release -p fdem-mesh --example validation_data -- OUTDIR`.

use fdem_mesh::{Elements, Material, Mesh, PlaneKind, TriId, read_mesh, solve_static};
use std::fmt::Write;

fn solve(m: &Mesh, mat: Material, load: &str, t: impl Fn([f64; 2]) -> [f64; 2]) -> Vec<[f64; 2]> {
    let el = Elements::new(m, &[mat]).unwrap();
    let mut f = vec![0.0; 2 * m.n_nodes()];
    for e in &m.group(load).unwrap().edges {
        let (a, b) = (m.nodes[e[0].idx()], m.nodes[e[1].idx()]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let l = d[0].hypot(d[1]);
        let tr = t([d[1] / l, -d[0] / l]);
        for k in [e[0], e[1]] {
            f[2 * k.idx()] += 0.5 * l * tr[0];
            f[2 * k.idx() + 1] += 0.5 * l * tr[1];
        }
    }
    let mut fixed = Vec::new();
    for (g, d) in [("left", 0), ("bottom", 1)] {
        for n in &m.group(g).unwrap().nodes {
            fixed.push((2 * n.idx() + d, 0.0));
        }
    }
    let u = solve_static(&el.stiffness(), &f, &fixed).unwrap();
    m.nodes
        .iter()
        .enumerate()
        .map(|(i, p)| [p[0] + u[2 * i], p[1] + u[2 * i + 1]])
        .collect()
}

fn main() {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes");
    // Lame, plane strain, inner pressure 1 MPa.
    let m = read_mesh(dir.join("thick-cylinder.msh")).unwrap();
    let mat = Material::new(200e9, 0.3, 7800.0);
    let x = solve(&m, mat, "inner", |n| [-1e6 * n[0], -1e6 * n[1]]);
    let el = Elements::new(&m, &[mat]).unwrap();
    let v = vec![[0.0; 2]; m.n_nodes()];
    let mut s = String::from("r,hoop_fem,radial_fem\n");
    for t in 0..m.n_triangles() {
        let c = m.triangles[t].map(|n| m.nodes[n as usize]);
        let c = [
            (c[0][0] + c[1][0] + c[2][0]) / 3.0,
            (c[0][1] + c[1][1] + c[2][1]) / 3.0,
        ];
        let r = c[0].hypot(c[1]);
        let (ct, st) = (c[0] / r, c[1] / r);
        let st_ = el.stress(TriId(t as u32), &x, &v);
        let hoop = st_.xx * st * st + st_.yy * ct * ct - 2.0 * st_.xy * st * ct;
        let rad = st_.xx * ct * ct + st_.yy * st * st + 2.0 * st_.xy * st * ct;
        writeln!(s, "{r},{hoop},{rad}").unwrap();
    }
    std::fs::write(out.join("lame.csv"), s).unwrap();
    // Kirsch, plane stress, remote tension 1 MPa along x; triangles with centroid x < 1 mm.
    let m = read_mesh(dir.join("plate-with-hole.msh")).unwrap();
    let mat = Material {
        plane: PlaneKind::Stress,
        ..Material::new(70e9, 0.3, 2700.0)
    };
    let x = solve(&m, mat, "right", |_| [1e6, 0.0]);
    let el = Elements::new(&m, &[mat]).unwrap();
    let v = vec![[0.0; 2]; m.n_nodes()];
    let mut s = String::from("y,sxx_fem\n");
    for t in 0..m.n_triangles() {
        let c = m.triangles[t].map(|n| m.nodes[n as usize]);
        let c = [
            (c[0][0] + c[1][0] + c[2][0]) / 3.0,
            (c[0][1] + c[1][1] + c[2][1]) / 3.0,
        ];
        if c[0] < 0.001 {
            writeln!(s, "{},{}", c[1], el.stress(TriId(t as u32), &x, &v).xx).unwrap();
        }
    }
    std::fs::write(out.join("kirsch.csv"), s).unwrap();
}

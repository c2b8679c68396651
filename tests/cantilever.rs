//! Cantilever 10 m x 1 m, plane stress, E = 200e3, nu = 0.3, clamped left end, uniform shear
//! traction of total 1 N on the right end (examples/cantilever-*.json).
//!
//! - The static solve equals an independent dense CST solve written here (1e-8).
//! - On the fine mesh (200 x 20 cells) the tip deflection is within 3 % of Timoshenko beam
//!   theory, `P L^3/(3 E I) + P L/(kappa G A)`, kappa = 5/6: 2.0156e-2 m.
//! - Dynamic relaxation converges to the static answer within 0.5 %.

use crate::common;

use fdem_mesh::JsonMesh;

/// Dense small-strain CST stiffness assembled from scratch (independent of the mesh crate).
fn dense_static_tip(mesh_file: &str) -> f64 {
    let m: JsonMesh = serde_json::from_str(
        &std::fs::read_to_string(common::root().join("examples/meshes").join(mesh_file)).unwrap(),
    )
    .unwrap();
    let (e, nu, t) = (200e3, 0.3, 1.0);
    let c = e / (1.0 - nu * nu);
    let d = [
        [c, c * nu, 0.0],
        [c * nu, c, 0.0],
        [0.0, 0.0, c * (1.0 - nu) / 2.0],
    ];
    let n = 2 * m.nodes.len();
    let mut k = vec![0.0; n * n];
    for tri in &m.triangles {
        let p = tri.map(|i| m.nodes[i as usize]);
        let a2 =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        // dN/dx = (y_b - y_c)/2A, dN/dy = (x_c - x_b)/2A for (a, b, c) cyclic.
        let mut bmat = [[0.0; 6]; 3];
        for a in 0..3 {
            let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
            let nx = (p[b][1] - p[cc][1]) / a2;
            let ny = (p[cc][0] - p[b][0]) / a2;
            bmat[0][2 * a] = nx;
            bmat[1][2 * a + 1] = ny;
            bmat[2][2 * a] = ny;
            bmat[2][2 * a + 1] = nx;
        }
        let area = 0.5 * a2.abs();
        for i in 0..6 {
            for j in 0..6 {
                let mut s = 0.0;
                for r in 0..3 {
                    for q in 0..3 {
                        s += bmat[r][i] * d[r][q] * bmat[q][j];
                    }
                }
                let (gi, gj) = (
                    2 * tri[i / 2] as usize + i % 2,
                    2 * tri[j / 2] as usize + j % 2,
                );
                k[gi * n + gj] += s * area * t;
            }
        }
    }
    let group = |name: &str| m.groups.iter().find(|g| g.name == name).unwrap();
    let mut f = vec![0.0; n];
    for e in &group("right").edges {
        let (a, b) = (m.nodes[e[0] as usize], m.nodes[e[1] as usize]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        f[2 * e[0] as usize + 1] -= 0.5 * len * t;
        f[2 * e[1] as usize + 1] -= 0.5 * len * t;
    }
    let mut fixed = vec![false; n];
    for e in &group("left").edges {
        for &i in e {
            fixed[2 * i as usize] = true;
            fixed[2 * i as usize + 1] = true;
        }
    }
    let free: Vec<usize> = (0..n).filter(|&i| !fixed[i]).collect();
    let nf = free.len();
    let mut a = vec![0.0; nf * nf];
    let mut b: Vec<f64> = free.iter().map(|&i| f[i]).collect();
    for (r, &i) in free.iter().enumerate() {
        for (q, &j) in free.iter().enumerate() {
            a[r * nf + q] = k[i * n + j];
        }
    }
    // Gaussian elimination without pivoting (K_ff is symmetric positive definite).
    for p in 0..nf {
        for r in p + 1..nf {
            let l = a[r * nf + p] / a[p * nf + p];
            if l != 0.0 {
                for q in p..nf {
                    a[r * nf + q] -= l * a[p * nf + q];
                }
                b[r] -= l * b[p];
            }
        }
    }
    let mut u = vec![0.0; nf];
    for r in (0..nf).rev() {
        let s: f64 = (r + 1..nf).map(|q| a[r * nf + q] * u[q]).sum();
        u[r] = (b[r] - s) / a[r * nf + r];
    }
    let tip = group("tip").nodes[0] as usize;
    u[free.iter().position(|&i| i == 2 * tip + 1).unwrap()]
}

fn static_tip(scene: &std::path::Path) -> f64 {
    let (_, out) = common::run(scene);
    let (h, rows) = common::histories(&out);
    common::column(&h, &rows, "u_y[tip]")[0]
}

const TIMOSHENKO: f64 = -(1000.0 / (3.0 * 200e3 / 12.0) + 10.0 / (5.0 / 6.0 * 200e3 / 2.6));

#[test]
fn static_cst_tip_deflection_equals_independent_dense_solve() {
    let scene = common::edited_example("cantilever-static.json", "cant-coarse", |v| {
        v["bodies"][0]["mesh"] = common::root()
            .join("examples/meshes/cantilever-coarse.json")
            .display()
            .to_string()
            .into();
    });
    let solver = static_tip(&scene);
    let dense = dense_static_tip("cantilever-coarse.json");
    // Same discrete problem, two independent solvers: agree to 1e-8 relative.
    assert!(
        ((solver - dense) / dense).abs() < 1e-8,
        "solver {solver:e} dense {dense:e}"
    );
    fdem_figures::record(7, format!("{:.1e}", ((solver - dense) / dense).abs()));
}

#[test]
fn fine_mesh_tip_deflection_within_3_percent_of_timoshenko() {
    let scene = common::edited_example("cantilever-static.json", "cant-fine", |_| {});
    let tip = static_tip(&scene);
    let err = (tip - TIMOSHENKO).abs() / TIMOSHENKO.abs();
    eprintln!("fine mesh tip {tip:e}, Timoshenko {TIMOSHENKO:e}, error {err:.4}");
    // CST is stiff in bending; 20 cells through the depth bring it within 3 %.
    assert!(err < 0.03, "error {err}");
    fdem_figures::record(8, format!("{tip:.5e} m ({:.2} %)", 100.0 * err));
}

#[test]
fn dynamic_relaxation_reaches_the_static_answer_within_half_a_percent() {
    let dr = common::edited_example("cantilever-relaxation.json", "cant-dr", |_| {});
    let (o, out) = common::run(&dr);
    assert_eq!(
        o.summary.converged,
        Some(true),
        "relaxation did not converge"
    );
    let (h, rows) = common::histories(&out);
    let tip_dr = *common::column(&h, &rows, "u_y[tip]").last().unwrap();
    let st = common::edited_example("cantilever-static.json", "cant-dr-static", |v| {
        v["bodies"][0]["mesh"] = common::root()
            .join("examples/meshes/cantilever-coarse.json")
            .display()
            .to_string()
            .into();
    });
    let tip_static = static_tip(&st);
    let err = ((tip_dr - tip_static) / tip_static).abs();
    eprintln!("relaxation {tip_dr:e}, static {tip_static:e}, error {err:e}");
    assert!(err < 5e-3, "error {err}");
    fdem_figures::record(9, format!("{err:.1e}"));
}

//! Small-strain stiffness (faer), the static solve on a patch, lumped mass, and the element
//! frequency bound against a dense eigen solve of the assembled mesh.

use crate::common;
use common::*;
use fdem_mesh::{ElasticLaw, Elements, ForceScratch, Material, PlaneKind, solve_static};
use nalgebra::{DMatrix, SymmetricEigen};

fn dense(el: &Elements) -> DMatrix<f64> {
    let k = el.stiffness();
    let n = k.nrows();
    let mut d = DMatrix::zeros(n, n);
    let (cp, ri, v) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for c in 0..n {
        for p in cp[c]..cp[c + 1] {
            d[(ri[p], c)] += v[p];
        }
    }
    d
}

/// K dx = -(d f_int/dx)(x0) dx exactly (to 1e-12 relative) for both laws at the reference:
/// the stiffness and the force derivative describe the same triangles.
#[test]
fn stiffness_equals_minus_force_derivative_at_reference() {
    let mesh = common::grid(5, 4, 1.0, 0.8, 0.5, 3);
    for law in [ElasticLaw::Munjiza, ElasticLaw::NeoHookean] {
        for plane in [PlaneKind::Strain, PlaneKind::Stress] {
            let el = elements(
                &mesh,
                Material {
                    law,
                    plane,
                    thickness: 0.3,
                    ..Material::new(7e10, 0.3, 2500.0)
                },
            );
            let k = dense(&el);
            let mut rng = Rng(8);
            let dx: Vec<[f64; 2]> = (0..mesh.n_nodes())
                .map(|_| [rng.next() - 0.5, rng.next() - 0.5])
                .collect();
            let mut df = vec![[0.0; 2]; mesh.n_nodes()];
            let v = vec![[0.0; 2]; mesh.n_nodes()];
            el.force_derivative(&mesh.nodes, &v, &dx, &mut df, &mut ForceScratch::new(&el));
            let kd = &k * nalgebra::DVector::from_column_slice(dx.as_flattened());
            let scale = kd.amax();
            for i in 0..kd.len() {
                assert!(
                    (kd[i] + df.as_flattened()[i]).abs() < 1e-12 * scale,
                    "{law:?} {plane:?} dof {i}"
                );
            }
            // symmetric, rigid modes in the kernel
            assert!((&k - k.transpose()).amax() < 1e-12 * k.amax());
        }
    }
}

/// Patch test of the static solve: prescribing the linear field u = (a x + b y, c x + d y) on
/// the boundary of an irregular mesh reproduces it at the interior nodes to 1e-10.
#[test]
fn static_solve_reproduces_linear_field() {
    let mesh = common::grid(8, 6, 2.0, 1.5, 0.6, 21);
    let el = elements(
        &mesh,
        Material {
            plane: PlaneKind::Stress,
            ..Material::new(2e11, 0.3, 7800.0)
        },
    );
    let k = el.stiffness();
    let u_exact = |p: [f64; 2]| [1e-3 * p[0] + 2e-4 * p[1], -3e-4 * p[0] + 5e-4 * p[1]];
    let mut fixed = Vec::new();
    for e in &mesh.boundary_edges {
        for n in mesh.edges[e.idx()].nodes {
            let u = u_exact(mesh.nodes[n.idx()]);
            fixed.push((2 * n.idx(), u[0]));
            fixed.push((2 * n.idx() + 1, u[1]));
        }
    }
    let f = vec![0.0; 2 * mesh.n_nodes()];
    let u = solve_static(&k, &f, &fixed).unwrap();
    for (i, p) in mesh.nodes.iter().enumerate() {
        let ue = u_exact(*p);
        assert!(
            (u[2 * i] - ue[0]).abs() < 1e-10 * 1e-3 && (u[2 * i + 1] - ue[1]).abs() < 1e-10 * 1e-3,
            "node {i}"
        );
    }
    // An unsupported body is reported, not solved.
    assert!(solve_static(&k, &f, &[]).is_err());
}

/// Lumped mass sums to rho * area * t (1e-12).
#[test]
fn lumped_mass_sums_to_body_mass() {
    let mesh = common::grid(6, 5, 1.2, 1.0, 0.5, 4);
    let el = elements(
        &mesh,
        Material {
            thickness: 0.05,
            ..Material::new(1e9, 0.2, 2000.0)
        },
    );
    let m: f64 = el.lumped_masses().iter().sum();
    assert!((m - 2000.0 * 1.2 * 0.05).abs() < 1e-12 * m);
}

/// The largest element frequency bound is never below the true highest frequency
/// sqrt(max eig(M^-1 K)) of the assembled free mesh (dense eigen solve), over random meshes,
/// nu from 0 to 0.49, both planes; and one element's own highest frequency is below its bound.
#[test]
fn frequency_bound_is_above_highest_frequency() {
    let mut worst: f64 = 0.0;
    for (seed, nu) in [(1, 0.0), (2, 0.2), (3, 0.3), (4, 0.45), (5, 0.49)] {
        for plane in [PlaneKind::Strain, PlaneKind::Stress] {
            for (nx, ny, jit) in [(1, 1, 0.0), (4, 3, 0.7), (6, 2, 0.9)] {
                let mesh = common::grid(nx, ny, 1.0, 0.7, jit, seed);
                let el = elements(
                    &mesh,
                    Material {
                        plane,
                        ..Material::new(3e10, nu, 2400.0)
                    },
                );
                let k = dense(&el);
                let m = el.lumped_masses();
                let n = k.nrows();
                let s = DMatrix::from_fn(n, n, |i, j| k[(i, j)] / (m[i / 2] * m[j / 2]).sqrt());
                let wmax = SymmetricEigen::new(s).eigenvalues.max().sqrt();
                let bound = el.max_frequency_bound(&mesh.nodes);
                assert!(
                    bound >= wmax * (1.0 - 1e-12),
                    "nu {nu} {plane:?} {nx}x{ny}: {bound} < {wmax}"
                );
                worst = worst.max(wmax / bound);
            }
        }
    }
    println!("largest omega_max / bound over the meshes: {worst:.3}");
    // the bound is not loose by more than a factor 2 on these meshes
    assert!(worst > 0.5, "bound too loose: {worst}");
    fdem_figures::record(16, format!("largest omega_max / bound {worst:.3}"));
}

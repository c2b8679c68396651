//! The initial stress of the triangles (a constant second Piola-Kirchhoff stress `S0` of the
//! reference state): at the reference positions the element forces are those of `S0` on the
//! boundary (`sum -A t S0 grad N` is the consistent load of `S0 n`), a rigid rotation `Q`
//! turns the stress into `Q S0 Q^T`, the force is minus the gradient of the energy
//! `W + S0 : E`, the directional derivative is exact, and the kernels stay thread-independent.

use crate::common;
use common::*;
use fdem_mesh::{ElasticLaw, Elements, ForceScratch, Material, PlaneKind, TriId};

const S0: [f64; 3] = [-12e6, -5e6, 3e6];

fn prestressed(mesh: &fdem_mesh::Mesh, law: ElasticLaw, xi: f64) -> Elements {
    let mut el = elements(
        mesh,
        Material {
            law,
            plane: PlaneKind::Strain,
            thickness: 0.1,
            damping_ratio: xi,
            ..Material::new(10e9, 0.25, 2700.0)
        },
    );
    // a field that varies from triangle to triangle
    let s0 = (0..el.len())
        .map(|t| {
            let k = 1.0 + 0.1 * (t % 7) as f64;
            [k * S0[0], k * S0[1], k * S0[2]]
        })
        .collect();
    el.set_initial_stress(s0);
    el
}

fn forces(el: &Elements, x: &[[f64; 2]], v: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut f = vec![[0.0; 2]; x.len()];
    el.internal_forces(x, v, &mut f, &mut ForceScratch::new(el));
    f
}

/// A uniform `S0` at the reference positions: no net force on interior nodes (to 1e-9 of
/// `|S0| h t`), and each boundary node's force is minus the consistent load of the traction
/// `S0 n` on its two boundary edges (to the same tolerance); the stress is `S0` (1e-9).
#[test]
fn uniform_initial_stress_forces_are_its_boundary_tractions() {
    let mesh = grid(6, 4, 2.0, 1.0, 0.6, 3);
    let mut el = elements(&mesh, Material::new(10e9, 0.25, 2700.0));
    el.set_initial_stress(vec![S0; el.len()]);
    let x = mesh.nodes.clone();
    let v = vec![[0.0; 2]; x.len()];
    let f = forces(&el, &x, &v);
    // consistent loads of S0 n on the boundary edges (outward normal), thickness 1
    let mut load = vec![[0.0; 2]; x.len()];
    for e in &mesh.boundary_edges {
        let me = &mesh.edges[e.idx()];
        let [a, b] = me.nodes.map(|n| n.0 as usize);
        let t = me.left;
        let tri = mesh.triangles[t.idx()];
        let c = tri
            .iter()
            .find(|&&n| n as usize != a && n as usize != b)
            .unwrap();
        let (pa, pb, pc) = (x[a], x[b], x[*c as usize]);
        let d = [pb[0] - pa[0], pb[1] - pa[1]];
        let mut n = [d[1], -d[0]]; // length-weighted normal
        if n[0] * (pc[0] - pa[0]) + n[1] * (pc[1] - pa[1]) > 0.0 {
            n = [-n[0], -n[1]];
        }
        let tr = [S0[0] * n[0] + S0[2] * n[1], S0[2] * n[0] + S0[1] * n[1]];
        for k in [a, b] {
            load[k][0] += 0.5 * tr[0];
            load[k][1] += 0.5 * tr[1];
        }
    }
    let scale = 12e6 * 2.0 / 6.0;
    let worst = f
        .iter()
        .zip(&load)
        .map(|(p, q)| (p[0] + q[0]).abs().max((p[1] + q[1]).abs()))
        .fold(0.0, f64::max);
    eprintln!(
        "uniform S0: largest |f_int + f_traction| = {:.2e} of |S0| h",
        worst / scale
    );
    assert!(worst < 1e-9 * scale, "{worst}");
    for t in 0..el.len() {
        let s = el.stress(TriId(t as u32), &x, &v);
        let d = [s.xx - S0[0], s.yy - S0[1], s.xy - S0[2]];
        assert!(d.iter().all(|d| d.abs() < 1e-9 * 12e6), "tri {t}: {s:?}");
    }
    fdem_figures::record_part(62, 1, fdem_figures::sci(worst / scale, 1));
}

/// A rigid rotation `Q` (plus a translation) of a prestressed body gives the stress
/// `Q S0 Q^T` in every triangle (to 1e-9 of |S0|): the initial stress turns with the material.
#[test]
fn rigid_rotation_rotates_the_initial_stress() {
    let mesh = grid(4, 3, 1.0, 1.0, 0.5, 9);
    for law in [ElasticLaw::Munjiza, ElasticLaw::NeoHookean] {
        let el = prestressed(&mesh, law, 0.0);
        let q = rot(0.7);
        let x = affine(&mesh.nodes, q, [3.0, -1.0]);
        let v = vec![[0.0; 2]; x.len()];
        for t in 0..el.len() {
            let s0 = el.initial_stress[t];
            let m = [s0[0], s0[2], s0[2], s0[1]];
            let r = mm(mm(q, m), [q[0], q[2], q[1], q[3]]);
            let s = el.stress(TriId(t as u32), &x, &v);
            for (a, b) in [(s.xx, r[0]), (s.yy, r[3]), (s.xy, r[1])] {
                assert!((a - b).abs() < 1e-9 * 12e6, "{law:?} tri {t}: {a} vs {b}");
            }
        }
    }
}

/// With the neo-Hookean law the force is minus the gradient of the strain energy including
/// `A0 t S0 : E` (central differences, step 1e-7, to 1e-6 of max |f|), at 20 % strain; and
/// `initial_stress_energy` is the part of `strain_energy` that the initial stress adds.
#[test]
fn force_is_minus_gradient_of_energy_with_initial_stress() {
    let mesh = grid(3, 2, 1.0, 1.0, 0.5, 13);
    let el = prestressed(&mesh, ElasticLaw::NeoHookean, 0.0);
    let mut rng = Rng(99);
    let x: Vec<[f64; 2]> = affine(&mesh.nodes, [1.2, 0.1, -0.05, 0.85], [0.0; 2])
        .into_iter()
        .map(|p| [p[0] + 0.02 * rng.next(), p[1] + 0.02 * rng.next()])
        .collect();
    let v = vec![[0.0; 2]; x.len()];
    let f = forces(&el, &x, &v);
    let fmax = f.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
    let h = 1e-7;
    for i in 0..x.len() {
        for d in 0..2 {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[i][d] += h;
            xm[i][d] -= h;
            let g = (el.strain_energy(&xp) - el.strain_energy(&xm)) / (2.0 * h);
            assert!((f[i][d] + g).abs() < 1e-6 * fmax, "node {i} dof {d}");
        }
    }
    let mut plain = el.clone();
    plain.set_initial_stress(Vec::new());
    let split = plain.strain_energy(&x) + el.initial_stress_energy(&x);
    assert!((split - el.strain_energy(&x)).abs() < 1e-12 * el.strain_energy(&x).abs());
}

/// The directional derivative with initial stress matches central differences of the force
/// (step 1e-6) to 1e-6 relative, both laws, with and without viscosity, at 15 % strain.
#[test]
fn force_derivative_with_initial_stress_matches_finite_differences() {
    let mesh = grid(3, 3, 1.0, 1.0, 0.5, 17);
    for law in [ElasticLaw::Munjiza, ElasticLaw::NeoHookean] {
        for xi in [0.0, 0.3] {
            let el = prestressed(&mesh, law, xi);
            let mut rng = Rng(5);
            let x: Vec<[f64; 2]> = affine(&mesh.nodes, [1.15, 0.1, 0.0, 0.9], [0.0; 2])
                .into_iter()
                .map(|p| [p[0] + 0.02 * rng.next(), p[1] + 0.02 * rng.next()])
                .collect();
            let v: Vec<[f64; 2]> = (0..x.len())
                .map(|_| [rng.next() - 0.5, rng.next() - 0.5])
                .collect();
            let dx: Vec<[f64; 2]> = (0..x.len())
                .map(|_| [rng.next() - 0.5, rng.next() - 0.5])
                .collect();
            let mut df = vec![[0.0; 2]; x.len()];
            el.force_derivative(&x, &v, &dx, &mut df, &mut ForceScratch::new(&el));
            let h = 1e-6;
            let shift = |s: f64| -> Vec<[f64; 2]> {
                x.iter()
                    .zip(&dx)
                    .map(|(a, b)| [a[0] + s * b[0], a[1] + s * b[1]])
                    .collect()
            };
            let (fp, fm) = (forces(&el, &shift(h), &v), forces(&el, &shift(-h), &v));
            let scale = df.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
            for i in 0..x.len() {
                for d in 0..2 {
                    let fd = (fp[i][d] - fm[i][d]) / (2.0 * h);
                    assert!(
                        (df[i][d] - fd).abs() < 1e-6 * scale,
                        "{law:?} xi {xi} node {i}"
                    );
                }
            }
        }
    }
}

/// The kernels with initial stress (buffered, owner-computes) give the same forces bit for
/// bit on 1 and 2 threads, and equal each other to 1e-13.
#[test]
fn prestressed_forces_identical_for_any_thread_count() {
    let mesh = grid(120, 90, 1.2, 0.9, 0.5, 23);
    let el = prestressed(&mesh, ElasticLaw::Munjiza, 0.1);
    let mut rng = Rng(3);
    let x: Vec<[f64; 2]> = mesh
        .nodes
        .iter()
        .map(|p| [p[0] * 1.01 + 1e-4 * rng.next(), p[1] + 1e-4 * rng.next()])
        .collect();
    let v: Vec<[f64; 2]> = (0..x.len()).map(|_| [rng.next(), rng.next()]).collect();
    let pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let f1 = pool(1).install(|| forces(&el, &x, &v));
    let f2 = pool(2).install(|| forces(&el, &x, &v));
    let bits = |a: &[[f64; 2]], b: &[[f64; 2]]| {
        a.iter()
            .zip(b)
            .all(|(p, q)| p[0].to_bits() == q[0].to_bits() && p[1].to_bits() == q[1].to_bits())
    };
    assert!(bits(&f1, &f2));
    let mut o = vec![[0.0; 2]; x.len()];
    el.internal_forces_owner(&x, &v, &mut o);
    let scale = f1
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max);
    assert!(
        f1.iter().zip(&o).all(
            |(a, b)| (a[0] - b[0]).abs() < 1e-13 * scale && (a[1] - b[1]).abs() < 1e-13 * scale
        )
    );
}

/// The frequency bound with an initial stress adds its largest principal magnitude to
/// `lam* + 2 mu`, and is the plain bound without one.
#[test]
fn frequency_bound_includes_the_initial_stress() {
    let mesh = grid(2, 2, 1.0, 1.0, 0.0, 1);
    let m = Material::new(10e9, 0.25, 2700.0);
    let mut el = elements(&mesh, m);
    let plain = el.frequency_bound(TriId(0), &mesh.nodes);
    el.set_initial_stress(vec![[-3e9, 1e9, 0.0]; el.len()]);
    let with = el.frequency_bound(TriId(0), &mesh.nodes);
    let m2 = el.materials[0];
    let ratio = ((m2.lam + 2.0 * m2.mu + 3e9) / (m2.lam + 2.0 * m2.mu)).sqrt();
    assert!(
        (with / plain - ratio).abs() < 1e-12,
        "{} vs {ratio}",
        with / plain
    );
}

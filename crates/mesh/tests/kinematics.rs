//! Finite-strain triangle kinematics: patch test, objectivity, small-strain limit, force
//! consistency with the energy, directional derivative, thread-count parity.

use crate::common;
use common::*;
use fdem_mesh::{ElasticLaw, Elements, ForceScratch, Material, PlaneKind, TriId};

const E: f64 = 10e9;
const NU: f64 = 0.25;
const RHO: f64 = 2700.0;

fn mat(law: ElasticLaw, plane: PlaneKind) -> Material {
    Material {
        law,
        plane,
        thickness: 0.1,
        ..Material::new(E, NU, RHO)
    }
}

fn forces(el: &Elements, x: &[[f64; 2]], v: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut f = vec![[0.0; 2]; x.len()];
    let mut s = ForceScratch::new(el);
    el.internal_forces(x, v, &mut f, &mut s);
    f
}

fn laws() -> [(ElasticLaw, PlaneKind); 4] {
    [
        (ElasticLaw::Munjiza, PlaneKind::Strain),
        (ElasticLaw::Munjiza, PlaneKind::Stress),
        (ElasticLaw::NeoHookean, PlaneKind::Strain),
        (ElasticLaw::NeoHookean, PlaneKind::Stress),
    ]
}

/// Patch test: a homogeneous deformation of an irregular mesh gives the same stress in
/// every triangle (to 1e-12 relative) and zero net force on interior nodes (to 1e-12 of the
/// force scale sigma * h * t).
#[test]
fn patch_test_uniform_stress_and_zero_interior_force() {
    let mesh = common::grid(7, 5, 2.0, 1.0, 0.6, 7);
    let fgrad = [1.01, 0.004, -0.003, 0.985];
    let (mut worst_s, mut worst_f): (f64, f64) = (0.0, 0.0);
    for (law, plane) in laws() {
        let el = elements(&mesh, mat(law, plane));
        let x = affine(&mesh.nodes, fgrad, [0.3, -0.1]);
        let v = vec![[0.0; 2]; x.len()];
        let s0 = el.stress(TriId(0), &x, &v);
        let scale = s0.von_mises();
        for t in 0..mesh.n_triangles() {
            let s = el.stress(TriId(t as u32), &x, &v);
            for (a, b) in [(s.xx, s0.xx), (s.yy, s0.yy), (s.xy, s0.xy), (s.zz, s0.zz)] {
                assert!((a - b).abs() < 1e-12 * scale, "{law:?} {plane:?} tri {t}");
                worst_s = worst_s.max((a - b).abs() / scale);
            }
        }
        let f = forces(&el, &x, &v);
        let boundary: std::collections::HashSet<u32> = mesh
            .boundary_edges
            .iter()
            .flat_map(|e| mesh.edges[e.idx()].nodes.map(|n| n.0))
            .collect();
        let fscale = scale * (2.0 / 7.0) * 0.1;
        let mut interior = 0;
        for (i, fi) in f.iter().enumerate() {
            if !boundary.contains(&(i as u32)) {
                interior += 1;
                assert!(fi[0].hypot(fi[1]) < 1e-12 * fscale, "node {i}: {fi:?}");
                worst_f = worst_f.max(fi[0].hypot(fi[1]) / fscale);
            }
        }
        assert_eq!(interior, 6 * 4);
    }
    fdem_figures::record(
        13,
        format!("stress {worst_s:.1e}, interior force {worst_f:.1e} (relative)"),
    );
}

/// Rigid rotations of 30, 90 and 180 degrees give zero stress: |f| < 1e-15 E l t about the
/// origin (docs/validation.md, element checks; l = 0.25 m cell), and < 1e-14 E l t with a translation of
/// 20 cells (round-off of the differences x1 - x0 grows with |x|/l), for both laws.
#[test]
fn rigid_rotation_gives_no_stress() {
    let mesh = common::grid(4, 4, 1.0, 1.0, 0.5, 3);
    let elt = E * 0.25 * 0.1;
    let mut worst = [0.0_f64; 2];
    for (law, plane) in laws() {
        let el = elements(&mesh, mat(law, plane));
        for deg in [30.0_f64, 90.0, 180.0] {
            for (k, (shift, tol)) in [([0.0, 0.0], 1e-15), ([5.0, -2.0], 1e-14)]
                .into_iter()
                .enumerate()
            {
                let x = affine(&mesh.nodes, rot(deg.to_radians()), shift);
                let v = vec![[0.0; 2]; x.len()];
                let f = forces(&el, &x, &v);
                let fmax = f.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
                assert!(
                    fmax < tol * elt,
                    "{law:?} {deg} {shift:?}: {:e}",
                    fmax / elt
                );
                worst[k] = worst[k].max(fmax / elt);
                for t in 0..mesh.n_triangles() {
                    let s = el.stress(TriId(t as u32), &x, &v);
                    assert!(s.von_mises() < 1e2 * tol * E, "{law:?} {deg} deg: {s:?}");
                }
            }
        }
    }
    fdem_figures::record_part(
        14,
        1,
        format!(
            "force {:.1e} `E l t` (about the origin), {:.1e} (shifted 20 cells)",
            worst[0], worst[1]
        ),
    );
}

/// Objectivity: stretch U then rotation R gives sigma(RU) = R sigma(U) R^T to 1e-12.
#[test]
fn rotated_stretch_gives_rotated_stress() {
    let mesh = common::grid(3, 3, 1.0, 1.0, 0.5, 11);
    let u = [1.2, 0.05, 0.05, 0.9];
    let mut worst: f64 = 0.0;
    for (law, plane) in laws() {
        let el = elements(&mesh, mat(law, plane));
        let v = vec![[0.0; 2]; mesh.n_nodes()];
        let s = el.stress(TriId(2), &affine(&mesh.nodes, u, [0.0; 2]), &v);
        for deg in [30.0_f64, 90.0, 180.0] {
            let r = rot(deg.to_radians());
            let sr = el.stress(TriId(2), &affine(&mesh.nodes, mm(r, u), [1.0; 2]), &v);
            let sm = [s.xx, s.xy, s.xy, s.yy];
            let rt = [r[0], r[2], r[1], r[3]];
            let expect = mm(mm(r, sm), rt);
            let scale = s.von_mises();
            assert!((sr.xx - expect[0]).abs() < 1e-12 * scale);
            assert!((sr.yy - expect[3]).abs() < 1e-12 * scale);
            assert!((sr.xy - expect[1]).abs() < 1e-12 * scale);
            assert!((sr.zz - s.zz).abs() < 1e-12 * scale);
            for d in [
                sr.xx - expect[0],
                sr.yy - expect[3],
                sr.xy - expect[1],
                sr.zz - s.zz,
            ] {
                worst = worst.max(d.abs() / scale);
            }
        }
    }
    fdem_figures::record_part(14, 2, format!("rotated stress {worst:.1e}"));
}

/// Small-strain limit: F = I + eps with |eps| = 1e-7 gives the linear plane stress / plane
/// strain Hooke answer to 1e-6 relative.
#[test]
fn small_strain_limit_is_hooke() {
    let mesh = common::grid(2, 2, 1.0, 1.0, 0.4, 5);
    let (exx, eyy, exy) = (1e-7, -0.4e-7, 0.3e-7);
    let mut worst: f64 = 0.0;
    for (law, plane) in laws() {
        let el = elements(&mesh, mat(law, plane));
        let x = affine(&mesh.nodes, [1.0 + exx, exy, exy, 1.0 + eyy], [0.0; 2]);
        let v = vec![[0.0; 2]; x.len()];
        let s = el.stress(TriId(1), &x, &v);
        let (sxx, syy, sxy, szz) = match plane {
            PlaneKind::Stress => {
                let c = E / (1.0 - NU * NU);
                (
                    c * (exx + NU * eyy),
                    c * (eyy + NU * exx),
                    E / (1.0 + NU) * exy,
                    0.0,
                )
            }
            PlaneKind::Strain => {
                let c = E / ((1.0 + NU) * (1.0 - 2.0 * NU));
                (
                    c * ((1.0 - NU) * exx + NU * eyy),
                    c * ((1.0 - NU) * eyy + NU * exx),
                    E / (1.0 + NU) * exy,
                    c * NU * (exx + eyy),
                )
            }
        };
        let scale = sxx.abs();
        for (a, b) in [(s.xx, sxx), (s.yy, syy), (s.xy, sxy), (s.zz, szz)] {
            assert!(
                (a - b).abs() < 1e-6 * scale,
                "{law:?} {plane:?}: {a} vs {b}"
            );
            worst = worst.max((a - b).abs() / scale);
        }
    }
    fdem_figures::record(15, format!("{worst:.1e}"));
}

/// Hyperelastic consistency: f = -dU/dx by central differences (step 1e-7 of the size) to
/// 1e-6 relative of max |f|, at 20 % strain.
#[test]
fn neo_hookean_force_is_minus_energy_gradient() {
    let mesh = common::grid(3, 2, 1.0, 1.0, 0.5, 13);
    let el = elements(&mesh, mat(ElasticLaw::NeoHookean, PlaneKind::Strain));
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
            let mut xp = x.clone();
            let mut xm = x.clone();
            xp[i][d] += h;
            xm[i][d] -= h;
            let g = (el.strain_energy(&xp) - el.strain_energy(&xm)) / (2.0 * h);
            assert!(
                (f[i][d] + g).abs() < 1e-6 * fmax,
                "node {i} dof {d}: {} vs {}",
                f[i][d],
                -g
            );
        }
    }
}

/// The directional derivative matches central differences of the force (step 1e-6) to
/// 1e-6 relative, for both laws, with and without viscosity, at 15 % strain.
#[test]
fn force_derivative_matches_finite_differences() {
    let mesh = common::grid(3, 3, 1.0, 1.0, 0.5, 17);
    for (law, plane) in laws() {
        for xi in [0.0, 0.3] {
            let el = elements(
                &mesh,
                Material {
                    damping_ratio: xi,
                    ..mat(law, plane)
                },
            );
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
            let mut s = ForceScratch::new(&el);
            el.force_derivative(&x, &v, &dx, &mut df, &mut s);
            let h = 1e-6;
            let xp: Vec<_> = x
                .iter()
                .zip(&dx)
                .map(|(a, b)| [a[0] + h * b[0], a[1] + h * b[1]])
                .collect();
            let xm: Vec<_> = x
                .iter()
                .zip(&dx)
                .map(|(a, b)| [a[0] - h * b[0], a[1] - h * b[1]])
                .collect();
            let (fp, fm) = (forces(&el, &xp, &v), forces(&el, &xm, &v));
            let scale = df.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
            for i in 0..x.len() {
                for d in 0..2 {
                    let fd = (fp[i][d] - fm[i][d]) / (2.0 * h);
                    assert!(
                        (df[i][d] - fd).abs() < 1e-6 * scale,
                        "{law:?} xi {xi} node {i}: {} vs {fd}",
                        df[i][d]
                    );
                }
            }
        }
    }
}

/// Forces, viscous included, are identical bit for bit on 1, 2 and 3 threads.
#[test]
fn forces_identical_for_any_thread_count() {
    let mesh = common::grid(120, 90, 1.2, 0.9, 0.5, 23);
    let el = elements(
        &mesh,
        Material {
            damping_ratio: 0.1,
            ..mat(ElasticLaw::Munjiza, PlaneKind::Strain)
        },
    );
    let mut rng = Rng(3);
    let x: Vec<[f64; 2]> = mesh
        .nodes
        .iter()
        .map(|p| [p[0] * 1.01 + 1e-4 * rng.next(), p[1] + 1e-4 * rng.next()])
        .collect();
    let v: Vec<[f64; 2]> = (0..x.len()).map(|_| [rng.next(), rng.next()]).collect();
    let run = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| forces(&el, &x, &v))
    };
    let f1 = run(1);
    for n in [2, 3] {
        let fnn = run(n);
        assert!(
            f1.iter()
                .zip(&fnn)
                .all(|(a, b)| a[0].to_bits() == b[0].to_bits() && a[1].to_bits() == b[1].to_bits())
        );
    }
    // Sanity: the forces are not trivially zero.
    assert!(f1.iter().any(|p| p[0].abs() > 1.0));
    // The buffered two-pass kernel: also thread-independent, and equal to round-off.
    let runb = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| {
                let mut f = vec![[0.0; 2]; x.len()];
                el.internal_forces_buffered(&x, &v, &mut f, &mut ForceScratch::new(&el));
                f
            })
    };
    let b1 = runb(1);
    let b2 = runb(2);
    assert!(
        b1.iter()
            .zip(&b2)
            .all(|(a, b)| a[0].to_bits() == b[0].to_bits() && a[1].to_bits() == b[1].to_bits())
    );
    let scale = f1
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max);
    assert!(
        f1.iter().zip(&b1).all(
            |(a, b)| (a[0] - b[0]).abs() < 1e-13 * scale && (a[1] - b[1]).abs() < 1e-13 * scale
        )
    );
}

/// Net force and net torque of the internal forces vanish (sigma symmetric): to 1e-12 of
/// sum |f| and sum |x x f|, at a large random deformation with damping.
#[test]
fn internal_forces_have_zero_resultant_and_torque() {
    let mesh = common::grid(5, 4, 1.0, 1.0, 0.5, 29);
    for (law, plane) in laws() {
        let el = elements(
            &mesh,
            Material {
                damping_ratio: 0.2,
                ..mat(law, plane)
            },
        );
        let mut rng = Rng(41);
        let x: Vec<[f64; 2]> = mesh
            .nodes
            .iter()
            .map(|p| [p[0] + 0.03 * rng.next(), p[1] + 0.03 * rng.next()])
            .collect();
        let v: Vec<[f64; 2]> = (0..x.len())
            .map(|_| [rng.next() - 0.5, rng.next() - 0.5])
            .collect();
        let f = forces(&el, &x, &v);
        let (mut sx, mut sy, mut tq, mut norm, mut tnorm) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (p, fi) in x.iter().zip(&f) {
            sx += fi[0];
            sy += fi[1];
            tq += p[0] * fi[1] - p[1] * fi[0];
            norm += fi[0].abs() + fi[1].abs();
            tnorm += (p[0] * fi[1]).abs() + (p[1] * fi[0]).abs();
        }
        assert!(
            sx.abs() < 1e-12 * norm && sy.abs() < 1e-12 * norm,
            "{law:?}"
        );
        assert!(tq.abs() < 1e-12 * tnorm, "{law:?}");
    }
}

//! Stress outputs, inversion check and material validation.

use crate::common;
use fdem_mesh::{Elements, Material, MeshError, PlaneKind, Stress, TriId};

/// Principal stresses, angle and von Mises of known tensors (1e-12).
#[test]
fn principal_and_von_mises_of_known_tensors() {
    // pure shear tau: principal +-tau at 45 deg, von Mises sqrt(3) tau
    let s = Stress {
        xx: 0.0,
        yy: 0.0,
        xy: 2.0,
        zz: 0.0,
    };
    let [s1, s2] = s.principal();
    assert!((s1 - 2.0).abs() < 1e-12 && (s2 + 2.0).abs() < 1e-12);
    assert!((s.principal_angle() - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
    assert!((s.von_mises() - 2.0 * 3f64.sqrt()).abs() < 1e-12);
    // uniaxial sigma: von Mises sigma; hydrostatic: 0
    let u = Stress {
        xx: -5.0,
        yy: 0.0,
        xy: 0.0,
        zz: 0.0,
    };
    assert!((u.von_mises() - 5.0).abs() < 1e-12);
    assert_eq!(u.principal(), [0.0, -5.0]);
    let h = Stress {
        xx: 3.0,
        yy: 3.0,
        xy: 0.0,
        zz: 3.0,
    };
    assert!(h.von_mises() < 1e-12);
}

/// Plane strain uniaxial strain eps_xx: sigma_zz = lam eps (Hooke, to 1e-6), von Mises from
/// all three normal stresses; plane stress: sigma_zz = 0.
#[test]
fn out_of_plane_stress_and_von_mises() {
    let mesh = common::grid(2, 2, 1.0, 1.0, 0.3, 2);
    let (e, nu, eps) = (1e9, 0.3, 1e-7);
    for plane in [PlaneKind::Strain, PlaneKind::Stress] {
        let el = common::elements(
            &mesh,
            Material {
                plane,
                ..Material::new(e, nu, 1000.0)
            },
        );
        let x = common::affine(&mesh.nodes, [1.0 + eps, 0.0, 0.0, 1.0], [0.0; 2]);
        let s = el.stress(TriId(0), &x, &x);
        let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let expect_zz = if plane == PlaneKind::Strain {
            lam * eps
        } else {
            0.0
        };
        assert!((s.zz - expect_zz).abs() < 1e-6 * s.xx.abs(), "{plane:?}");
        let vm =
            (0.5 * ((s.xx - s.yy).powi(2) + (s.yy - s.zz).powi(2) + (s.zz - s.xx).powi(2))).sqrt();
        assert!((s.von_mises() - vm).abs() < 1e-12 * vm);
    }
}

/// first_inverted finds the first triangle with non-positive area, and only it.
#[test]
fn first_inverted_finds_inverted_triangle() {
    let mesh = common::grid(3, 3, 1.0, 1.0, 0.0, 1);
    let el = common::elements(&mesh, Material::new(1e9, 0.3, 1000.0));
    assert_eq!(el.first_inverted(&mesh.nodes), None);
    let mut x = mesh.nodes.clone();
    // push the centre-ish node 5 (1/3, 1/3) far past its neighbours: inverts triangles
    x[5] = [2.0, 2.0];
    let t = el.first_inverted(&x).unwrap();
    assert!(fdem_mesh::tri_area(&x, mesh.triangles[t.idx()]) <= 0.0);
    for k in 0..t.idx() {
        assert!(fdem_mesh::tri_area(&x, mesh.triangles[k]) > 0.0);
    }
}

/// Material ranges and the region count are checked with errors naming the field.
#[test]
fn material_errors_name_the_field() {
    let mesh = common::grid(1, 1, 1.0, 1.0, 0.0, 1);
    let bad = [
        (Material::new(-1.0, 0.3, 1.0), "youngs_modulus"),
        (Material::new(1.0, 0.5, 1.0), "poisson_ratio"),
        (Material::new(1.0, 0.3, 0.0), "density"),
        (
            Material {
                thickness: 0.0,
                ..Material::new(1.0, 0.3, 1.0)
            },
            "thickness",
        ),
        (
            Material {
                damping_ratio: -0.1,
                ..Material::new(1.0, 0.3, 1.0)
            },
            "damping_ratio",
        ),
    ];
    for (m, field) in bad {
        let e = Elements::new(&mesh, &[m]).unwrap_err();
        assert!(
            matches!(e, MeshError::Material { field: f, .. } if f == field),
            "{e}"
        );
    }
    let e = Elements::new(&mesh, &[]).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::MaterialCount {
                regions: 1,
                given: 0,
                ..
            }
        ),
        "{e}"
    );
}

/// Viscous stress: a uniform velocity gradient L gives sigma = eta sym(L) on top of the elastic
/// stress (to 1e-12), with eta = 2 xi h sqrt(E rho), h the smallest altitude; a rigid spin
/// gives no viscous stress.
#[test]
fn viscous_stress_is_eta_times_rate_of_deformation() {
    let mesh = common::grid(1, 1, 1.0, 1.0, 0.0, 1);
    let (e, rho, xi) = (1e9, 2000.0, 0.2);
    let el = common::elements(
        &mesh,
        Material {
            damping_ratio: xi,
            ..Material::new(e, 0.25, rho)
        },
    );
    let zero = vec![[0.0; 2]; mesh.n_nodes()];
    let l = [0.3, 0.1, -0.2, -0.5];
    let v = common::affine(&mesh.nodes, l, [1.0, 2.0]);
    let s = el.stress(TriId(0), &mesh.nodes, &v);
    let h = 2.0 * 0.5 / 2f64.sqrt(); // right triangle of legs 1: 2A / hypotenuse
    let eta = 2.0 * xi * h * (e * rho).sqrt();
    assert!((el.tris[0].eta - eta).abs() < 1e-12 * eta);
    for (a, b) in [
        (s.xx, eta * l[0]),
        (s.yy, eta * l[3]),
        (s.xy, eta * 0.5 * (l[1] + l[2])),
    ] {
        assert!((a - b).abs() < 1e-12 * eta);
    }
    let spin = common::affine(&mesh.nodes, [0.0, -1.0, 1.0, 0.0], [0.0; 2]);
    let s = el.stress(TriId(0), &mesh.nodes, &spin);
    assert!(s.von_mises() < 1e-12 * eta);
    let s0 = el.stress(TriId(0), &mesh.nodes, &zero);
    assert_eq!(s0.von_mises(), 0.0);
}

/// NodeArrays: reference positions, zero velocity and force, masses summing to rho A t (1e-12).
#[test]
fn node_arrays_start_at_reference() {
    let mesh = common::grid(3, 2, 1.5, 1.0, 0.4, 6);
    let el = common::elements(&mesh, Material::new(1e9, 0.3, 1000.0));
    let n = fdem_mesh::NodeArrays::new(&mesh, &el);
    assert_eq!(n.len(), mesh.n_nodes());
    assert_eq!(n.x, mesh.nodes);
    assert!(n.v.iter().chain(&n.f).all(|p| *p == [0.0, 0.0]));
    let total: f64 = n.m.iter().sum();
    assert!((total - 1000.0 * 1.5).abs() < 1e-12 * total);
}

/// Viscous power: on a uniform velocity gradient L, `sum_e t A_e eta_e D:D` (each element
/// shape and thickness known), and equal to minus the power of the viscous part of the
/// internal forces, `f(x, v) - f(x, 0)` (to 1e-12); 0 without viscosity and under a rigid
/// spin.
#[test]
fn viscous_power_is_the_power_of_the_viscous_forces() {
    let mesh = common::grid(3, 2, 1.5, 1.0, 0.4, 6);
    let (e, rho, xi) = (1e9, 2000.0, 0.2);
    let el = common::elements(
        &mesh,
        Material {
            damping_ratio: xi,
            ..Material::new(e, 0.25, rho)
        },
    );
    let l = [0.3, 0.1, -0.2, -0.5];
    let v = common::affine(&mesh.nodes, l, [1.0, 2.0]);
    let mut sums = Vec::new();
    let p = el.viscous_power(&mesh.nodes, &v, &mut sums);
    // the kernel's own viscous forces
    let zero = vec![[0.0; 2]; mesh.n_nodes()];
    let mut scratch = fdem_mesh::ForceScratch::new(&el);
    let mut f_v = vec![[0.0; 2]; mesh.n_nodes()];
    let mut f_0 = vec![[0.0; 2]; mesh.n_nodes()];
    el.set_internal_forces(&mesh.nodes, &v, &mut f_v, &mut scratch);
    el.set_internal_forces(&mesh.nodes, &zero, &mut f_0, &mut scratch);
    let from_forces: f64 = -(0..mesh.n_nodes())
        .map(|i| (f_v[i][0] - f_0[i][0]) * v[i][0] + (f_v[i][1] - f_0[i][1]) * v[i][1])
        .sum::<f64>();
    // closed form: D = sym(L), D:D = Dxx^2 + Dyy^2 + 2 Dxy^2, t = 1
    let dxy = 0.5 * (l[1] + l[2]);
    let dd = l[0] * l[0] + l[3] * l[3] + 2.0 * dxy * dxy;
    let closed: f64 = el.tris.iter().map(|t| t.area0 * t.eta * dd).sum();
    assert!(p > 0.0);
    assert!((p - from_forces).abs() < 1e-12 * p, "{p} vs {from_forces}");
    assert!((p - closed).abs() < 1e-12 * p, "{p} vs {closed}");
    let spin = common::affine(&mesh.nodes, [0.0, -1.0, 1.0, 0.0], [0.0; 2]);
    assert!(el.viscous_power(&mesh.nodes, &spin, &mut sums).abs() < 1e-12 * p);
    let elastic = common::elements(&mesh, Material::new(e, 0.25, rho));
    assert_eq!(elastic.viscous_power(&mesh.nodes, &v, &mut sums), 0.0);
}

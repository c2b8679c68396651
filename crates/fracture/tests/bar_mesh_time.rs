//! The bar of joints in tension again, end to end with the real crates: the mesh crate's
//! `explode` gives the joints, its finite-strain elements (Munjiza's law, plane stress) the
//! triangle forces, and fdem-time's central difference advances a `SecondOrderSystem` whose
//! end-of-step hook commits the joints. The right end is pulled in increments of 1/100 of the
//! expected peak displacement; after each increment (with a predictor that scales the last
//! displacement field) the bar relaxes to static equilibrium under mass-proportional damping.
//! The peak load must be ft times the cross-section within 2 %.

use fdem_fracture::*;
use fdem_mesh::{ElasticLaw, Elements, ForceScratch, Material, Mesh, PlaneKind, explode};
use fdem_time::{CentralDifference, Integrator, SecondOrderSystem, State};

const E: f64 = 30e9;
const NU: f64 = 0.2;
const RHO: f64 = 2500.0;
const FT: f64 = 5e6;
const T: f64 = 0.1;

struct Bar {
    elements: Elements,
    escratch: ForceScratch,
    set: JointSet,
    state: JointState,
    jscratch: JointScratch,
    events: Vec<FractureEvent>,
    inv_mass: Vec<f64>,
    prescribed: Vec<usize>,
    is_free: Vec<bool>,
    alpha: f64,
    f: Vec<[f64; 2]>,
    residual: f64,
}

fn nodes(flat: &[f64]) -> &[[f64; 2]] {
    flat.as_chunks::<2>().0
}

impl SecondOrderSystem for Bar {
    fn n_dofs(&self) -> usize {
        self.inv_mass.len()
    }
    fn inv_mass(&self) -> &[f64] {
        &self.inv_mass
    }
    fn acceleration(&mut self, _t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        self.f.iter_mut().for_each(|fi| *fi = [0.0; 2]);
        self.elements
            .internal_forces(nodes(x), nodes(v), &mut self.f, &mut self.escratch);
        accumulate_joint_forces(
            &self.set,
            &self.state,
            nodes(x),
            &mut self.jscratch,
            &mut self.f,
        );
        let f = self.f.as_flattened();
        self.residual = 0.0;
        for i in 0..a.len() {
            a[i] = f[i] * self.inv_mass[i] - self.alpha * v[i];
            if self.is_free[i] {
                self.residual = self.residual.max(f[i].abs());
            }
        }
    }
    fn prescribed_dofs(&self) -> &[usize] {
        &self.prescribed
    }
    fn end_of_step(&mut self, t: f64, x: &[f64], _v: &[f64]) {
        commit_joints(
            &self.set,
            &mut self.state,
            nodes(x),
            t,
            &mut self.jscratch,
            &mut self.events,
        );
    }
}

#[test]
fn bar_from_exploded_mesh_breaks_at_ft_times_its_cross_section() {
    let (nx, ny, h) = (10usize, 2usize, 0.01);
    let (len, height) = (nx as f64 * h, ny as f64 * h);
    // connected structured mesh, then explode every triangle
    let mut xs = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            xs.push([i as f64 * h, j as f64 * h]);
        }
    }
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut tris = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mesh = Mesh::from_nodes_triangles(xs, tris).unwrap();
    let ex = explode(&mesh, None).unwrap();
    let x0 = ex.mesh.nodes.clone();
    let n = x0.len();
    let material = Material {
        law: ElasticLaw::Munjiza,
        plane: PlaneKind::Stress,
        thickness: T,
        ..Material::new(E, NU, RHO)
    };
    let elements = Elements::new(&ex.mesh, &[material]).unwrap();
    let joints: Vec<Joint> = ex
        .internal_edges
        .iter()
        .map(|e| {
            let [p, q] = [x0[e.nodes[0].idx()], x0[e.nodes[1].idx()]];
            Joint {
                nodes: e.nodes.map(|v| v.0),
                triangles: e.tris.map(|t| t.0),
                ref_length: (q[0] - p[0]).hypot(q[1] - p[1]),
                material: 0,
            }
        })
        .collect();
    assert_eq!(
        joints.len(),
        3 * nx * ny - nx - ny,
        "internal edges of the strip"
    );
    let jmat = JointMaterialInput {
        tensile_strength: FT,
        cohesion: 2.0 * FT,
        friction_angle_deg: 30.0,
        fracture_energy_i: 50.0,
        fracture_energy_ii: 500.0,
        penalty_normal: 10.0 * E,
        penalty_tangential: 10.0 * E,
    };
    let set = JointSet::new(&joints, &[jmat], n, T).unwrap();
    let state = JointState::new(&set, &x0);
    let mass = elements.lumped_masses();
    let omega2 =
        elements.max_frequency_bound(&x0).powi(2) + joint_omega_sq_bound(&set, &state, &mass);
    let dt = 0.8 * 2.0 / omega2.sqrt();

    let left: Vec<usize> = (0..n).filter(|&i| x0[i][0] < 1e-12).collect();
    let right: Vec<usize> = (0..n).filter(|&i| x0[i][0] > len - 1e-12).collect();
    let pin = *left.iter().find(|&&i| x0[i][1] < 1e-12).unwrap();
    let mut prescribed: Vec<usize> = left.iter().chain(&right).map(|&i| 2 * i).collect();
    prescribed.push(2 * pin + 1);
    let mut is_free = vec![true; 2 * n];
    prescribed.iter().for_each(|&d| is_free[d] = false);
    let c = (E / (RHO * (1.0 - NU * NU))).sqrt();
    let omega_b = (std::f64::consts::PI / len).powi(2) * c * height / 12f64.sqrt();
    let mut sys = Bar {
        jscratch: JointScratch::new(set.len()),
        escratch: ForceScratch::new(&elements),
        elements,
        set,
        state,
        events: Vec::new(),
        inv_mass: mass.iter().flat_map(|m| [1.0 / m, 1.0 / m]).collect(),
        prescribed,
        is_free,
        alpha: 2.0 * omega_b,
        f: vec![[0.0; 2]; n],
        residual: 0.0,
    };
    let mut st = State::new(0.0, x0.as_flattened().to_vec(), vec![0.0; 2 * n]);
    let mut cd = CentralDifference::new(2 * n);
    let x0f = x0.as_flattened().to_vec();
    let du = FT / E * len * 1.2 / 100.0;
    let tol = 1e-6 * FT * h * T;
    let (mut peak, mut steps) = (0.0f64, 0usize);
    for k in 1..=1000 {
        let u = k as f64 * du;
        // predictor and the new end displacement; the cached acceleration is stale
        let scale = if k > 1 { u / (u - du) } else { 0.0 };
        for d in 0..2 * n {
            st.x[d] = x0f[d] + scale * (st.x[d] - x0f[d]);
            if k == 1 && d % 2 == 0 {
                st.x[d] = x0f[d] + u * x0f[d] / len;
            }
        }
        for &i in &right {
            st.x[2 * i] = x0f[2 * i] + u;
        }
        cd.invalidate();
        for _ in 0..200_000 {
            cd.step(&mut sys, &mut st, dt);
            steps += 1;
            if sys.residual < tol || !sys.events.is_empty() {
                break;
            }
        }
        let reaction: f64 = right.iter().map(|&i| -sys.f[i][0]).sum();
        peak = peak.max(reaction);
        if !sys.events.is_empty() {
            break;
        }
    }
    let expected = FT * height * T;
    let err = peak / expected - 1.0;
    println!(
        "exploded-mesh bar: {} joints, peak {peak:.6e} N vs ft H t = {expected:.6e} N ({:+.3} %), {steps} steps, {} events",
        sys.set.len(),
        100.0 * err,
        sys.events.len()
    );
    assert!(!sys.events.is_empty(), "the bar must break");
    assert!(
        sys.events.iter().all(|e| e.mode == FractureMode::I),
        "{:?}",
        sys.events
    );
    // the required tolerance: 2 %
    assert!(err.abs() < 0.02, "peak {peak} vs {expected}");
    fdem_figures::record_part(
        40,
        2,
        format!("{:+.2} % (mesh and time crates)", 100.0 * err),
    );
}

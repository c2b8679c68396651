//! A bar of joints in tension breaks at a load of ft times its cross-section.
//!
//! Built from plain arrays (the mesh and time crates were not yet committed when this was
//! written): an exploded structured strip of 10 x 2 square cells of 1 cm (a bar 100 x 20 mm,
//! 0.1 m thick), each cut into two constant-strain triangles with a small-strain linear-elastic
//! plane-stress force written here, joints on every internal edge. The left end is held in x
//! (one node also in y), the right end is pulled in x in increments of 1/100 of the expected
//! peak displacement; after each increment (with a predictor that scales the last displacement
//! field) the bar is brought to static equilibrium by dynamic relaxation (explicit steps with
//! mass-proportional damping until the residual is below 1e-6 of ft h t). History
//! is committed after every relaxation step, so damage grows only along the relaxed path.

use crate::common;

use common::{Elastic, exploded_grid};
use fdem_fracture::*;

const E: f64 = 30e9;
const NU: f64 = 0.2;
const RHO: f64 = 2500.0;
const FT: f64 = 5e6;
const T: f64 = 0.1; // thickness (m)

#[test]
fn bar_of_joints_breaks_at_ft_times_its_cross_section() {
    let (nx, ny, h) = (10, 2, 0.01);
    let (len, height) = (nx as f64 * h, ny as f64 * h);
    let mesh = exploded_grid(nx, ny, h, h);
    let x0 = mesh.x.clone();
    let n = x0.len();
    let elastic = Elastic::new(&mesh.tris, &x0, E, NU, T);
    let mass = elastic.masses(RHO, n);
    let mat = JointMaterialInput {
        tensile_strength: FT,
        cohesion: 2.0 * FT,
        friction_angle_deg: 30.0,
        fracture_energy_i: 50.0,
        fracture_energy_ii: 500.0,
        penalty_normal: 10.0 * E,
        penalty_tangential: 10.0 * E,
    };
    let set = JointSet::new(&mesh.joints, &[mat], n, T).unwrap();
    let mut state = JointState::new(&set, &x0);
    let mut scratch = JointScratch::new(set.len());
    let mut events = Vec::new();

    // boundary conditions: fixed_x at x = 0, pulled at x = len, node at the origin fixed in y
    let left: Vec<usize> = (0..n).filter(|&i| x0[i][0] < 1e-12).collect();
    let right: Vec<usize> = (0..n).filter(|&i| x0[i][0] > len - 1e-12).collect();
    let pin_y = left.iter().copied().find(|&i| x0[i][1] < 1e-12).unwrap();
    let mut free = vec![[true; 2]; n];
    left.iter().chain(&right).for_each(|&i| free[i][0] = false);
    free[pin_y][1] = false;

    // time step from the element and joint bounds (docs/mesh.md and docs/fracture.md, section 8), safety 0.5
    let c2 = E / (RHO * (1.0 - NU * NU));
    let h_min = 2.0 * 0.5 * h * h / (h * 2f64.sqrt());
    let omega2 = 9.0 * c2 / (h_min * h_min) + joint_omega_sq_bound(&set, &state, &mass);
    let dt = 0.8 * 2.0 / omega2.sqrt();
    // damping: critical for the lowest (bending) mode, omega_b ~ (pi/L)^2 c H/sqrt(12)
    let omega_b = (std::f64::consts::PI / len).powi(2) * c2.sqrt() * height / 12f64.sqrt();
    let alpha = 2.0 * omega_b;

    let mut x = x0.clone();
    let mut v = vec![[0.0; 2]; n];
    let mut f = vec![[0.0; 2]; n];
    let u_peak_est = FT / E * len * 1.2; // elastic plus joint compliance, roughly
    let du = u_peak_est / 100.0;
    let tol = 1e-6 * FT * h * T;
    let (mut peak, mut steps, mut time) = (0.0f64, 0usize, 0.0);
    let mut load = Vec::new();
    'load: for k in 1..=1000 {
        let u = k as f64 * du;
        // predictor: scale the last equilibrium displacement field to the new end displacement,
        // so the relaxation starts near equilibrium and does not overshoot into damage
        let scale = if k > 1 { u / (u - du) } else { 1.0 };
        for i in 0..n {
            for d in 0..2 {
                x[i][d] = x0[i][d] + scale * (x[i][d] - x0[i][d]);
            }
        }
        for &i in &right {
            x[i][0] = x0[i][0] + u;
        }
        if k == 1 {
            for i in 0..n {
                x[i][0] = x0[i][0] + u * x0[i][0] / len;
            }
        }
        for _ in 0..200_000 {
            f.iter_mut().for_each(|a| *a = [0.0; 2]);
            elastic.add_forces(&x0, &x, &mut f);
            accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f);
            let mut res: f64 = 0.0;
            for i in 0..n {
                for d in 0..2 {
                    if free[i][d] {
                        res = res.max(f[i][d].abs());
                        v[i][d] += dt * (f[i][d] / mass[i] - alpha * v[i][d]);
                        x[i][d] += dt * v[i][d];
                    }
                }
            }
            time += dt;
            steps += 1;
            commit_joints(&set, &mut state, &x, time, &mut scratch, &mut events);
            if res < tol || !events.is_empty() {
                break;
            }
        }
        let reaction: f64 = right.iter().map(|&i| -f[i][0]).sum();
        load.push((u, reaction));
        peak = peak.max(reaction);
        if !events.is_empty() {
            break 'load;
        }
    }
    let expected = FT * height * T;
    let err = peak / expected - 1.0;
    println!(
        "bar: peak load {peak:.6e} N, ft H t = {expected:.6e} N, error {:.3} %, {} load steps, {steps} relaxation steps, first break at u = {:.3e} m, {} events",
        100.0 * err,
        load.len(),
        load.last().unwrap().0,
        events.len()
    );
    assert!(!events.is_empty(), "the bar must break");
    // all breaks are across the bar (vertical joints, mode I)
    assert!(
        events.iter().all(|e| e.mode == FractureMode::I),
        "{events:?}"
    );
    // one crack across the section: the broken joints lie in one column (x within h/100)
    let x_crack = events[0].position[0];
    assert!(
        events
            .iter()
            .all(|e| (e.position[0] - x_crack).abs() < 0.01 * h),
        "{events:?}"
    );
    // each broken joint dissipated G_I h t (slow loading: within 1e-4)
    for e in &events {
        let g = 50.0 * h * T;
        assert!(
            (e.energy_released / g - 1.0).abs() < 1e-4,
            "{} vs {g}",
            e.energy_released
        );
    }
    // the required tolerance: 2 %
    assert!(
        err.abs() < 0.02,
        "peak {peak} vs ft H t = {expected}: {:.3} %",
        100.0 * err
    );
    fdem_figures::record_part(40, 1, format!("{:+.2} % (plain arrays)", 100.0 * err));
}

//! The joint-force pass over a whole exploded mesh: conservation of linear and angular
//! momentum, serial-parallel bit parity, each joint's own evaluation, extremes, and the time-step bound.

use crate::common;

use common::{Exploded, Lcg, exploded_grid, perturbed};
use fdem_fracture::*;

fn material(p: f64) -> JointMaterialInput {
    JointMaterialInput {
        tensile_strength: 5e6,
        cohesion: 8e6,
        friction_angle_deg: 30.0,
        fracture_energy_i: 50.0,
        fracture_energy_ii: 200.0,
        penalty_normal: p,
        penalty_tangential: p,
    }
}

#[test]
fn joint_forces_conserve_linear_and_angular_momentum() {
    let mesh = exploded_grid(12, 10, 0.01, 0.008);
    let set = JointSet::new(&mesh.joints, &[material(3e11)], mesh.x.len(), 1.0).unwrap();
    // openings and slips up to 3e-5 m: most joints beyond their peak (o_p = 3.3e-7 m), many
    // in mixed mode, some in compression
    let x = perturbed(&mesh, 1.5e-5, 3);
    let state = JointState::new(&set, &x);
    let mut scratch = JointScratch::new(set.len());
    let mut f = vec![[0.0; 2]; x.len()];
    accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f);
    let (mut fx, mut fy, mut tq, mut fmax) = (0.0, 0.0, 0.0, 0.0f64);
    let c = [0.06, 0.04]; // torque about the mesh centre
    for (p, fi) in x.iter().zip(&f) {
        fx += fi[0];
        fy += fi[1];
        tq += (p[0] - c[0]) * fi[1] - (p[1] - c[1]) * fi[0];
        fmax = fmax.max(fi[0].abs()).max(fi[1].abs());
    }
    assert!(
        fmax > 1e3,
        "the test must load the joints: max |f| = {fmax}"
    );
    // round-off bounds: 1e-12 of max|f| (times the mesh size 0.12 m for the torque)
    assert!(
        fx.abs() < 1e-12 * fmax && fy.abs() < 1e-12 * fmax,
        "sum f = ({fx}, {fy})"
    );
    assert!(
        tq.abs() < 1e-12 * fmax * 0.12,
        "sum x x f = {tq}, max|f| = {fmax}"
    );
    let damaged = (0..set.len())
        .filter(|&j| state.joint_damage(j) > 0.0)
        .count();
    assert!(
        damaged > set.len() / 4,
        "only {damaged} of {} joints damaged",
        set.len()
    );
}

/// The positions of load step `s`: a stretch along x of 1e-4 per step plus `s` times the
/// perturbation `dx`.
fn loaded(mesh: &Exploded, dx: &[[f64; 2]], s: f64) -> Vec<[f64; 2]> {
    mesh.x
        .iter()
        .zip(dx)
        .map(|(p, d)| [p[0] + s * (d[0] + 1e-4 * p[0]), p[1] + s * d[1]])
        .collect()
}

/// The 60 x 40 grid of the runs below: its mesh, joint set, fresh state and pass scratch, and
/// the perturbation of its load steps.
fn grid() -> (Exploded, JointSet, JointState, JointScratch, Vec<[f64; 2]>) {
    let mesh = exploded_grid(60, 40, 0.005, 0.005);
    let set = JointSet::new(&mesh.joints, &[material(3e11)], mesh.x.len(), 1.0).unwrap();
    let state = JointState::new(&set, &mesh.x);
    let scratch = JointScratch::new(set.len());
    let dx = perturbed(&mesh, 1e-6, 11);
    (mesh, set, state, scratch, dx)
}

/// Forces, damage, histories and events after a run.
type Outcome = (Vec<[f64; 2]>, Vec<[f64; 2]>, Histories, Vec<FractureEvent>);

/// Runs 30 load steps (forces + commit) and returns the forces, histories and events.
fn run(threads: usize) -> Outcome {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let (mesh, set, mut state, mut scratch, dx) = grid();
        let mut f = vec![[0.0; 2]; mesh.x.len()];
        let mut events = Vec::new();
        for step in 1..=30 {
            let s = step as f64;
            let x = loaded(&mesh, &dx, s);
            f.iter_mut().for_each(|v| *v = [0.0; 2]);
            accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f);
            commit_joints(&set, &mut state, &x, s * 1e-6, &mut scratch, &mut events);
        }
        let d = state.history.damage.clone();
        (f, d, state.history, events)
    })
}

#[test]
fn serial_and_parallel_passes_are_bit_identical() {
    let (f1, d1, h1, e1) = run(1);
    let (f2, d2, h2, e2) = run(2);
    assert!(!e1.is_empty(), "the test must break joints");
    let bits = |v: &[[f64; 2]]| {
        v.iter()
            .flat_map(|p| p.map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        bits(&f1),
        bits(&f2),
        "forces differ between 1 and 2 threads"
    );
    assert_eq!(bits(&d1), bits(&d2), "damage differs");
    assert_eq!(h1, h2, "histories differ");
    assert_eq!(e1, e2, "events differ");
}

#[test]
fn stiff_penalty_and_sudden_large_motion_stay_finite() {
    // p = 1000 E for E = 30 GPa; a sudden opening of 10 cm, a crushing closure and a slide of
    // 1 m in one step on 1 cm joints
    let mesh = exploded_grid(6, 4, 0.01, 0.01);
    let set = JointSet::new(&mesh.joints, &[material(3e13)], mesh.x.len(), 1.0).unwrap();
    let mut state = JointState::new(&set, &mesh.x);
    let mut scratch = JointScratch::new(set.len());
    let mut events = Vec::new();
    let mut rng = Lcg(5);
    for (step, amp) in [0.1, 1.0, 0.01].into_iter().enumerate() {
        let x: Vec<[f64; 2]> = mesh
            .x
            .iter()
            .map(|p| [p[0] + amp * rng.next(), p[1] + amp * rng.next()])
            .collect();
        let mut f = vec![[0.0; 2]; x.len()];
        accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f);
        assert!(
            f.iter().flatten().all(|v| v.is_finite()),
            "non-finite force at step {step}"
        );
        commit_joints(&set, &mut state, &x, step as f64, &mut scratch, &mut events);
        let e = state.energy();
        assert!(e.work.is_finite() && e.stored.is_finite() && e.dissipated.is_finite());
    }
    // damage stays in [0, 1]; broken joints are exactly those with D = 1 at both points that
    // were open at both points when they broke: a fully damaged joint closed at a point stays
    let mut closed = 0;
    for j in 0..set.len() {
        let d = state.history.damage[j];
        assert!(
            d.iter().all(|v| (0.0..=1.0).contains(v)),
            "joint {j}: {d:?}"
        );
        if !state.intact[j] {
            assert_eq!(d, [1.0, 1.0], "joint {j}");
        } else if d == [1.0, 1.0] {
            let o = state.history.local[j];
            assert!(
                o[0] < 0.0 || o[2] < 0.0,
                "joint {j}: open and fully damaged"
            );
            closed += 1;
        }
    }
    println!("{closed} fully damaged joints closed at a point, not broken");
    assert!(
        state.n_broken > set.len() / 2,
        "{} of {} broken",
        state.n_broken,
        set.len()
    );
    assert_eq!(state.n_broken, events.len());
}

#[test]
fn time_step_bound_covers_the_largest_joint_frequency() {
    // a 3 x 2 exploded mesh, joints only: largest eigenvalue of M^-1 K by power iteration on
    // the symmetric M^-1/2 K M^-1/2, K from central differences of the forces at rest
    let mesh = exploded_grid(3, 2, 0.01, 0.01);
    let set = JointSet::new(&mesh.joints, &[material(3e11)], mesh.x.len(), 1.0).unwrap();
    let state = JointState::new(&set, &mesh.x);
    let mut scratch = JointScratch::new(set.len());
    let rho: f64 = 2500.0;
    let mass: Vec<f64> = vec![rho * 0.5e-4 / 3.0; mesh.x.len()];
    let n = 2 * mesh.x.len();
    let force = |u: &[f64], scratch: &mut JointScratch| {
        let x: Vec<[f64; 2]> = mesh
            .x
            .iter()
            .enumerate()
            .map(|(i, p)| [p[0] + u[2 * i], p[1] + u[2 * i + 1]])
            .collect();
        let mut f = vec![[0.0; 2]; x.len()];
        accumulate_joint_forces(&set, &state, &x, scratch, &mut f);
        f.as_flattened().to_vec()
    };
    let mut v: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
    let mut lambda = 0.0;
    for _ in 0..3000 {
        let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        v.iter_mut().for_each(|a| *a /= norm);
        // K w with w = M^-1/2 v, then M^-1/2
        let eps = 1e-12;
        let up: Vec<f64> = (0..n).map(|i| eps * v[i] / mass[i / 2].sqrt()).collect();
        let um: Vec<f64> = up.iter().map(|a| -a).collect();
        let (fp, fm) = (force(&up, &mut scratch), force(&um, &mut scratch));
        let kv: Vec<f64> = (0..n)
            .map(|i| -(fp[i] - fm[i]) / (2.0 * eps) / mass[i / 2].sqrt())
            .collect();
        lambda = v.iter().zip(&kv).map(|(a, b)| a * b).sum::<f64>();
        v = kv;
    }
    let bound = joint_omega_sq_bound(&set, &state, &mass);
    // rigorous bound, and not loose by more than 2.5x on this mesh
    assert!(
        lambda <= bound * (1.0 + 1e-6),
        "omega^2 = {lambda:e} above the bound {bound:e}"
    );
    assert!(
        bound < 2.5 * lambda,
        "bound {bound:e} too loose for omega^2 = {lambda:e}"
    );
    println!(
        "joints: omega_max^2 = {lambda:e}, bound = {bound:e}, ratio {:.3}",
        bound / lambda
    );
}

#[test]
fn commit_at_last_pass_without_position_copy_matches_the_checked_commit() {
    // Two runs of 6 steps, each step two force passes (a trial stage at other positions, then
    // the final ones; a PC-like step in every third, whose last pass is at the trial
    // positions): the checked commit (positions compared) and the commit told by the caller
    // (no copy of the positions kept; told only when the last pass was at the final
    // positions). Histories, energies and events equal bit for bit; some joints soften and
    // break on the way, so the reused and the re-evaluated trials both matter.
    let mesh = exploded_grid(12, 10, 0.01, 0.008);
    let set = JointSet::new(&mesh.joints, &[material(3e11)], mesh.x.len(), 1.0).unwrap();
    let run = |trusted: bool| {
        let mut state = JointState::new(&set, &mesh.x);
        let mut scratch = JointScratch::new(set.len());
        scratch.set_position_check(!trusted);
        let mut events = Vec::new();
        let mut f = vec![[0.0; 2]; mesh.x.len()];
        for step in 0..6u64 {
            let amp = 2e-7 * 5f64.powi(step as i32);
            let x_trial = perturbed(&mesh, amp, 100 + step);
            let x_final = perturbed(&mesh, amp, 200 + step);
            let last_at_final = step % 3 != 2;
            accumulate_joint_forces(&set, &state, &x_trial, &mut scratch, &mut f);
            if last_at_final {
                accumulate_joint_forces(&set, &state, &x_final, &mut scratch, &mut f);
            }
            if trusted && last_at_final {
                commit_joints_at_last_pass(
                    &set,
                    &mut state,
                    &x_final,
                    1.0,
                    &mut scratch,
                    &mut events,
                );
            } else {
                commit_joints(&set, &mut state, &x_final, 1.0, &mut scratch, &mut events);
            }
        }
        let e = state.energy();
        (state.history, e, events)
    };
    let (h1, e1, ev1) = run(false);
    let (h2, e2, ev2) = run(true);
    let softened = h1.damage.iter().filter(|d| **d != [0.0; 2]).count();
    assert!(
        softened > 0 && !ev1.is_empty(),
        "{softened} softened, {} broken",
        ev1.len()
    );
    assert_eq!(h1, h2, "histories differ");
    assert_eq!(e1, e2, "energies differ");
    assert_eq!(ev1, ev2, "events differ");
}

#[test]
fn in_place_pass_matches_the_trial_pass_and_its_commit() {
    // 30 load steps of a 60 x 40 exploded grid, each a pass and a commit at its positions:
    // the pass into the scratch's trial arrays (then swapped) against the pass that writes the
    // new history over the committed one, on 2 threads; plain joints and prestressed ones
    // (initial offsets). Forces, the newly softened lists, histories, energies and events
    // equal bit for bit, and joints soften and break on the way.
    let mesh = exploded_grid(60, 40, 0.005, 0.005);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let mut cases = Vec::new();
    for prestressed in [false, true] {
        let mut set = JointSet::new(&mesh.joints, &[material(3e11)], mesh.x.len(), 1.0).unwrap();
        if prestressed {
            let t0: Vec<[f64; 2]> = (0..set.len())
                .map(|j| [-1e6, 0.5e6 * ((j % 3) as f64 - 1.0)])
                .collect();
            set.set_initial_tractions(&t0).unwrap();
        }
        let run = |in_place: bool| {
            pool.install(|| {
                let mut state = JointState::new(&set, &mesh.x);
                let mut scratch = JointScratch::new(set.len());
                scratch.set_position_check(false);
                let mut events = Vec::new();
                let mut forces = Vec::new();
                let mut softened = Vec::new();
                let dx = perturbed(&mesh, 1e-6, 11);
                for step in 1..=30 {
                    let s = step as f64;
                    let x = loaded(&mesh, &dx, s);
                    let mut f = vec![[0.0; 2]; mesh.x.len()];
                    if in_place {
                        accumulate_joint_forces_committing(
                            &set,
                            &mut state,
                            &x,
                            &mut scratch,
                            &mut f,
                        );
                    } else {
                        accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f);
                    }
                    commit_joints_at_last_pass(
                        &set,
                        &mut state,
                        &x,
                        s * 1e-6,
                        &mut scratch,
                        &mut events,
                    );
                    forces.push(
                        f.iter()
                            .flat_map(|p| p.map(f64::to_bits))
                            .collect::<Vec<_>>(),
                    );
                    softened.push(scratch.newly_softened().to_vec());
                }
                (forces, softened, state.energy(), state.history, events)
            })
        };
        let (f1, s1, e1, h1, ev1) = run(false);
        let (f2, s2, e2, h2, ev2) = run(true);
        let n_softened: usize = s1.iter().map(Vec::len).sum();
        assert!(
            n_softened > 0 && !ev1.is_empty(),
            "prestressed {prestressed}: {n_softened} softened, {} broken",
            ev1.len()
        );
        assert!(f1 == f2, "prestressed {prestressed}: forces differ");
        assert_eq!(
            s1, s2,
            "prestressed {prestressed}: newly softened joints differ"
        );
        assert_eq!(h1, h2, "prestressed {prestressed}: histories differ");
        assert_eq!(e1, e2, "prestressed {prestressed}: energies differ");
        assert_eq!(ev1, ev2, "prestressed {prestressed}: events differ");
        cases.push(format!(
            "{}: {n_softened} softenings, {} breaks",
            if prestressed { "prestressed" } else { "plain" },
            ev1.len()
        ));
    }
    fdem_figures::record(94, format!("identical at every step; {}", cases.join("; ")));
}

/// Every joint's forces and new history from the pass are those of the joint evaluated on its
/// own (`evaluate`), bit for bit, at every step of a run that damages and breaks joints: the
/// pass's vectorised blocks of undamaged joints and its joint-by-joint path both put each
/// joint's results in that joint's places.
#[test]
fn the_pass_gives_each_joint_its_own_evaluation_bit_for_bit() {
    let (mesh, set, mut state, mut scratch, dx) = grid();
    let mut f = vec![[0.0; 2]; mesh.x.len()];
    let mut events = Vec::new();
    let (mut fresh, mut damaged) = (0usize, 0usize);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for step in 1..=30 {
        // ten small steps before any peak (the vectorised blocks), then up to the load at
        // which joints break
        let s = if step <= 10 {
            0.02 * step as f64
        } else {
            1.5 * (step - 10) as f64
        };
        let x = loaded(&mesh, &dx, s);
        let h = &state.history;
        let expected: Vec<Option<JointEval>> = (0..set.len())
            .map(|j| {
                state.intact[j].then(|| {
                    let hist = PointHistory {
                        damage: h.damage[j],
                        mode_mix: h.mode_mix[j],
                        shear_secant: h.shear_secant[j],
                    };
                    let m = &set.materials[set.material[j] as usize];
                    let (k, soft) = (set.consts(j), &set.softening[j]);
                    evaluate(m, &k, soft, &set.gather(j, &x), &hist, set.thickness)
                })
            })
            .collect();
        for j in (0..set.len()).filter(|&j| state.intact[j]) {
            if state.joint_damage(j) == 0.0 {
                fresh += 1;
            } else {
                damaged += 1;
            }
        }
        accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f);
        for (j, e) in expected.iter().enumerate() {
            let got = scratch.joint_forces(&set, j);
            let want = e.map_or([[0.0; 2]; 4], |e| e.forces);
            assert_eq!(
                bits(got.as_flattened()),
                bits(want.as_flattened()),
                "step {step}, joint {j}: forces"
            );
        }
        commit_joints(
            &set,
            &mut state,
            &x,
            step as f64 * 1e-6,
            &mut scratch,
            &mut events,
        );
        let h = &state.history;
        for (j, e) in expected.iter().enumerate() {
            // a joint that broke at this commit has its books closed by the break
            let Some(e) = e.filter(|_| state.intact[j]) else {
                continue;
            };
            let l = e.local;
            let want = [
                e.damage.as_slice(),
                &e.shear_secant,
                &[l[2], l[3], l[6], l[7]],
                &[l[0], l[4]],
                &[e.stored],
            ]
            .concat();
            let got = [
                h.damage[j].as_slice(),
                &h.shear_secant[j],
                &h.local[j],
                &h.normal[j],
                &[h.stored[j]],
            ]
            .concat();
            assert_eq!(bits(&got), bits(&want), "step {step}, joint {j}: history");
        }
    }
    assert!(!events.is_empty(), "the test must break joints");
    assert!(
        fresh > 10 * set.len() && damaged > set.len(),
        "{fresh} undamaged and {damaged} damaged joint-steps: both paths must run"
    );
    fdem_figures::record_part(
        146,
        3,
        format!(
            "the grid: {fresh} undamaged and {damaged} damaged joint-steps, {} breaks, identical",
            events.len()
        ),
    );
}

/// Every node's force is its starting value plus its joints' forces
/// (`JointScratch::joint_forces`) added one by one in increasing joint order, bit for bit:
/// through the pass's own gather, and range by range inside another pass over the nodes
/// (`joint_forces_ahead` and its committing variant, then `add_joint_forces`). With at most
/// two joints per node (an exploded mesh: each node's two slots in place, unused ones -0.0)
/// and with every joint doubled (up to four per node: the node-slot list). Starting values of
/// -0.0 at nodes without joints keep their sign.
#[test]
fn node_sums_add_each_joint_in_joint_order_bit_for_bit() {
    let mesh = exploded_grid(30, 20, 0.005, 0.005);
    let dx = perturbed(&mesh, 1e-6, 5);
    let bits = |v: &[[f64; 2]]| {
        v.iter()
            .flat_map(|p| p.map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    let mut cases = Vec::new();
    for doubled in [false, true] {
        let mut joints = mesh.joints.clone();
        if doubled {
            joints.extend_from_slice(&mesh.joints);
        }
        let set = JointSet::new(&joints, &[material(3e11)], mesh.x.len(), 1.0).unwrap();
        let most = set.node_offsets.windows(2).map(|w| w[1] - w[0]).max();
        assert_eq!(most, Some(if doubled { 4 } else { 2 }));
        let mut state = JointState::new(&set, &mesh.x);
        let mut scratch = JointScratch::new(set.len());
        let mut events = Vec::new();
        let f0: Vec<[f64; 2]> = (0..mesh.x.len())
            .map(|i| {
                if i % 3 == 0 {
                    [-0.0; 2]
                } else {
                    [1e-3 * i as f64, -1.0]
                }
            })
            .collect();
        for step in 1..=30 {
            let s = step as f64;
            let x = loaded(&mesh, &dx, s);
            let mut whole = f0.clone();
            accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut whole);
            let mut reference = f0.clone();
            for j in 0..set.len() {
                for (k, fk) in scratch.joint_forces(&set, j).iter().enumerate() {
                    let r = &mut reference[set.nodes[j][k] as usize];
                    r[0] += fk[0];
                    r[1] += fk[1];
                }
            }
            assert_eq!(
                bits(&whole),
                bits(&reference),
                "doubled {doubled}, step {step}"
            );
            for committing in [false, true] {
                if committing {
                    joint_forces_ahead_committing(&set, &mut state, &x, &mut scratch);
                } else {
                    joint_forces_ahead(&set, &state, &x, &mut scratch);
                }
                let mut ranged = f0.clone();
                for (i0, fc) in (0..).step_by(777).zip(ranged.chunks_mut(777)) {
                    add_joint_forces(&set, &scratch, i0, fc);
                }
                assert_eq!(
                    bits(&ranged),
                    bits(&whole),
                    "doubled {doubled}, committing {committing}, step {step}"
                );
            }
            commit_joints_at_last_pass(&set, &mut state, &x, s * 1e-6, &mut scratch, &mut events);
        }
        let damaged = (0..set.len())
            .filter(|&j| state.joint_damage(j) > 0.0)
            .count();
        assert!(
            damaged > 0 && !events.is_empty(),
            "doubled {doubled}: {damaged} damaged, {} broken",
            events.len()
        );
        cases.push(format!(
            "{} joints ({} per node at most), {} breaks",
            set.len(),
            most.unwrap_or(0),
            events.len()
        ));
    }
    fdem_figures::record_part(
        147,
        1,
        format!("identical at each of 30 steps: {}", cases.join(" and ")),
    );
}

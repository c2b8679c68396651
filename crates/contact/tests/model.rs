//! The contact model: friction history semantics (trial vs commit, reset, carry-over),
//! thread-count independence, conservation over a whole pass, the check point, and planes.

use crate::common;
use common::{Rng, cross, random_triangle};
use fdem_contact::{
    Contact, ContactError, ContactLaw, ContactLaws, ContactSettings, Family, RigidPlane,
    couple_force,
};

/// Two triangles: t fixed below, c overlapping its top edge by `d`, shifted by `sx`.
fn two(d: f64, sx: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let x = vec![
        [-1.0, 0.0],
        [0.0, -1.5],
        [1.0, 0.0],
        [-0.5 + sx, -d],
        [0.5 + sx, -d],
        [sx, 1.0],
    ];
    (x, vec![[0, 1, 2], [3, 4, 5]])
}

fn frictional() -> Contact {
    let law = ContactLaw {
        mu: 0.5,
        ..ContactLaw::with_penalty(1.0e6)
    };
    Contact::new(
        ContactSettings {
            buffer: 0.05,
            ..Default::default()
        },
        ContactLaws::uniform(1, law),
    )
}

#[test]
fn trial_evaluations_never_change_the_committed_friction_history() {
    // Same inputs before a commit give bit-identical forces, whatever was evaluated between.
    let (x, tris) = two(1e-3, 0.0);
    let mut c = frictional();
    c.update_detection(&x, &tris);
    let v1 = vec![
        [0.0; 2],
        [0.0; 2],
        [0.0; 2],
        [0.01, 0.0],
        [0.01, 0.0],
        [0.01, 0.0],
    ];
    let v2 = vec![
        [0.0; 2],
        [0.0; 2],
        [0.0; 2],
        [-0.3, 0.0],
        [-0.3, 0.0],
        [-0.3, 0.0],
    ];
    let dt = 1e-3;
    c.compute_forces(&x, &v1, &tris, &[], dt);
    let mut f1 = vec![[0.0; 2]; 6];
    c.add_forces(&tris, &mut f1);
    c.compute_forces(&x, &v2, &tris, &[], dt); // a trial stage
    c.compute_forces(&x, &v1, &tris, &[], dt);
    let mut f1b = vec![[0.0; 2]; 6];
    c.add_forces(&tris, &mut f1b);
    assert_eq!(f1, f1b);
    assert_eq!(c.energy(&x, &tris, &[]).friction_stored, 0.0);
    // After the commit, the next step starts from the stick force: it grows linearly.
    c.commit();
    let e1 = c.energy(&x, &tris, &[]).friction_stored;
    assert!(e1 > 0.0);
    c.compute_forces(&x, &v1, &tris, &[], dt);
    c.commit();
    let e2 = c.energy(&x, &tris, &[]).friction_stored;
    // The two long edges stick: their Ft doubles, so their stored energy quadruples; the
    // short side edges dipping by d slip at a constant cap (0.3 % of the total here).
    assert!((e2 / e1 - 4.0).abs() < 0.01, "{e1} {e2}");
    let mut ff = vec![[0.0; 2]; 6];
    c.add_family(Family::Friction, &tris, &mut ff);
    // Friction on c opposes its motion (+x).
    assert!(ff[3][0] + ff[4][0] + ff[5][0] < 0.0);
}

#[test]
fn friction_history_is_kept_across_redetection_and_reset_on_separation() {
    let (x, tris) = two(1e-3, 0.0);
    let mut c = frictional();
    c.update_detection(&x, &tris);
    let v = vec![
        [0.0; 2],
        [0.0; 2],
        [0.0; 2],
        [0.01, 0.0],
        [0.01, 0.0],
        [0.01, 0.0],
    ];
    c.compute_forces(&x, &v, &tris, &[], 1e-3);
    c.commit();
    let e = c.energy(&x, &tris, &[]).friction_stored;
    assert!(e > 0.0);
    c.invalidate();
    assert!(c.update_detection(&x, &tris));
    assert_eq!(c.energy(&x, &tris, &[]).friction_stored, e);
    // Separate by 0.01 (still within the buffer: the couple is kept) -> Ft = 0.
    let (x2, _) = two(-0.01, 0.0);
    assert!(!c.update_detection(&x2, &tris));
    assert_eq!(c.couples().len(), 1);
    c.compute_forces(&x2, &v, &tris, &[], 1e-3);
    c.commit();
    assert_eq!(c.energy(&x2, &tris, &[]).friction_stored, 0.0);
}

/// A dense random cloud of overlapping triangles with random velocities.
/// Positions, velocities, triangles.
type Cloud = (Vec<[f64; 2]>, Vec<[f64; 2]>, Vec<[u32; 3]>);

fn dense(seed: u64, n: usize) -> Cloud {
    let mut rng = Rng(seed);
    let side = (n as f64).sqrt() * 1.2;
    let mut x = Vec::new();
    let mut v = Vec::new();
    let mut tris = Vec::new();
    for i in 0..n {
        let c = [rng.range(0.0, side), rng.range(0.0, side)];
        let s = rng.range(0.5, 1.0);
        x.extend_from_slice(&random_triangle(&mut rng, c, s));
        for _ in 0..3 {
            v.push([rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)]);
        }
        let b = 3 * i as u32;
        tris.push([b, b + 1, b + 2]);
    }
    (x, v, tris)
}

fn run_pass(threads: usize, x: &[[f64; 2]], v: &[[f64; 2]], tris: &[[u32; 3]]) -> Vec<[f64; 2]> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let law = ContactLaw {
            mu: 0.4,
            damping: 3.0,
            ..ContactLaw::with_penalty(1.0e3)
        };
        let mut c = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
        c.walls.push(RigidPlane::new([0.0, 2.0], [0.0, 1.0], law));
        let mut f = vec![[0.0; 2]; x.len()];
        for _ in 0..3 {
            c.update_detection(x, tris);
            c.compute_forces(x, v, tris, &[], 1e-3);
            c.commit();
        }
        c.add_forces(tris, &mut f);
        f
    })
}

#[test]
fn force_pass_is_bit_identical_for_one_and_two_threads() {
    let (x, v, tris) = dense(21, 4000);
    let f1 = run_pass(1, &x, &v, &tris);
    let f2 = run_pass(2, &x, &v, &tris);
    assert!(f1.iter().any(|g| *g != [0.0, 0.0]));
    for (a, b) in f1.iter().zip(&f2) {
        assert_eq!(a[0].to_bits(), b[0].to_bits());
        assert_eq!(a[1].to_bits(), b[1].to_bits());
    }
}

#[test]
fn pass_results_equal_the_single_couple_kernel_while_couples_touch_separate_and_retouch() {
    // The pass skips work (box rejection, result slots written only for couples in contact,
    // trial friction cleared only where it may be non-zero): over 48 steps of a cloud moving
    // to and fro (its velocities reverse every 8 steps, so couples come into contact,
    // separate and touch again; redetections in between), every
    // couple's result must equal `couple_force` with an independently kept friction history,
    // bit for bit, and `active` must be set exactly for couples with a load or an invalid
    // triangle.
    let (mut x, mut v, tris) = dense(5, 600);
    // Each triangle moves rigidly (no triangle inverts; the check of invalid triangles comes
    // after the box test, so an inverted triangle far from the other is not reported).
    for t in &tris {
        let w = v[t[0] as usize];
        v[t[1] as usize] = w;
        v[t[2] as usize] = w;
    }
    let law = ContactLaw {
        mu: 0.4,
        damping: 3.0,
        // A soft tangential spring: edges stick for many steps, so a stale history would show.
        kt: 1.0,
        ..ContactLaw::with_penalty(1.0e3)
    };
    let mut c = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
    let dt = 0.02;
    let mut history: std::collections::HashMap<[u32; 2], [f64; 6]> = Default::default();
    let (mut n_checked, mut n_active_seen, mut n_retouched) = (0usize, 0usize, 0usize);
    // Per couple: 1 = in contact, 2 = released after a contact.
    let mut state: std::collections::HashMap<[u32; 2], u8> = Default::default();
    for step in 0..48 {
        if step % 8 == 0 && step > 0 {
            v.iter_mut().for_each(|w| *w = [-w[0], -w[1]]);
        }
        c.update_detection(&x, &tris);
        c.compute_forces(&x, &v, &tris, &[], dt);
        let mut next = std::collections::HashMap::new();
        for (cp, r) in c.couples().iter().zip(c.couple_results()) {
            let (ti, tj) = (tris[cp[0] as usize], tris[cp[1] as usize]);
            let nodes = [ti[0], ti[1], ti[2], tj[0], tj[1], tj[2]];
            let xs = nodes.map(|n| x[n as usize]);
            let vs = nodes.map(|n| v[n as usize]);
            let old = history.get(cp).copied().unwrap_or([0.0; 6]);
            let want = couple_force(&xs, &vs, &old, dt, &law);
            let loaded = want.invalid || want.fn_total > 0.0;
            assert_eq!(r.active, loaded, "couple {cp:?}");
            if loaded {
                assert_eq!(r.normal, want.normal, "couple {cp:?}");
                assert_eq!(r.friction, want.friction, "couple {cp:?}");
                assert_eq!(r.damping, want.damping, "couple {cp:?}");
                assert_eq!(r.total, want.total, "couple {cp:?}");
                assert_eq!(r.ft, want.ft, "couple {cp:?}");
                n_active_seen += 1;
            }
            let st = state.get(cp).copied().unwrap_or(0);
            if st == 2 && loaded {
                n_retouched += 1;
            }
            state.insert(
                *cp,
                if loaded {
                    1
                } else if st > 0 {
                    2
                } else {
                    0
                },
            );
            next.insert(*cp, if loaded { want.ft } else { [0.0; 6] });
            n_checked += 1;
        }
        history = next;
        c.commit();
        for (p, w) in x.iter_mut().zip(&v) {
            p[0] += dt * w[0];
            p[1] += dt * w[1];
        }
    }
    eprintln!(
        "checked {n_checked} couple results, {n_active_seen} in contact, {n_retouched} touching again, {} detections",
        c.n_detections()
    );
    assert!(n_active_seen > 1000 && n_retouched > 50 && c.n_detections() > 2);
}

#[test]
fn whole_pass_conserves_momentum_and_buffers_stay_put_once_warm() {
    // Triangle couples only (no planes): sum f = 0 and sum x × f = 0 to 1e-12 of sum |f|.
    let (x, v, tris) = dense(22, 3000);
    let law = ContactLaw {
        mu: 0.4,
        damping: 3.0,
        ..ContactLaw::with_penalty(1.0e3)
    };
    let mut c = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
    c.update_detection(&x, &tris);
    c.compute_forces(&x, &v, &tris, &[], 1e-3);
    let ptr = c.couple_results().as_ptr();
    for _ in 0..5 {
        c.update_detection(&x, &tris);
        c.compute_forces(&x, &v, &tris, &[], 1e-3);
        c.commit();
    }
    assert_eq!(
        ptr,
        c.couple_results().as_ptr(),
        "result buffer reallocated"
    );
    assert!(c.stats().n_active > 1000);
    let mut f = vec![[0.0; 2]; x.len()];
    c.add_forces(&tris, &mut f);
    let total: f64 = f.iter().map(|g| g[0].abs() + g[1].abs()).sum();
    let sx: f64 = f.iter().map(|g| g[0]).sum();
    let sy: f64 = f.iter().map(|g| g[1]).sum();
    let m: f64 = x.iter().zip(&f).map(|(p, g)| cross(*p, *g)).sum();
    let side = (3000f64).sqrt() * 1.2;
    assert!(
        sx.abs() < 1e-12 * total && sy.abs() < 1e-12 * total,
        "{sx} {sy} {total}"
    );
    assert!(m.abs() < 1e-12 * total * side, "{m}");
}

#[test]
fn check_point_reports_deep_penetration_and_invalid_triangles_without_nan() {
    // Deep: c's bottom edge at 0.6 H_t inside t (phi ~ 1 > 0.5).
    let (x, tris) = two(0.9, 0.0);
    let mut c = frictional();
    c.update_detection(&x, &tris);
    let v = vec![[0.0; 2]; 6];
    let s = c.compute_forces(&x, &v, &tris, &[], 1e-3);
    let err = s.check(0.5).unwrap_err();
    assert!(matches!(err, ContactError::TooDeep { .. }));
    assert!(
        err.to_string().contains("reduce dt or raise the penalty"),
        "{err}"
    );
    // A node becomes NaN: no force on anything, the couple is reported.
    let mut xn = x.clone();
    xn[4] = [f64::NAN, 0.0];
    let s = c.compute_forces(&xn, &v, &tris, &[], 1e-3);
    assert!(matches!(
        s.check(0.5),
        Err(ContactError::InvalidTriangles { count: 1, .. })
    ));
    let mut f = vec![[0.0; 2]; 6];
    c.add_forces(&tris, &mut f);
    assert!(f.iter().all(|g| g[0].is_finite() && g[1].is_finite()));
    // Shallow contact passes the check.
    let (x, _) = two(1e-3, 0.0);
    assert!(
        c.compute_forces(&x, &v, &tris, &[], 1e-3)
            .check(0.5)
            .is_ok()
    );
}

#[test]
fn plane_force_is_minus_energy_gradient_and_reaction_balances() {
    // Random triangles cut by a tilted plane: the force on the triangle equals -dW/dx for
    // rigid translation (central differences, 1e-6 of the force), and the plane's reaction is
    // the opposite of the sum.
    let mut rng = Rng(5);
    let law = ContactLaw::with_penalty(2.0);
    let plane = RigidPlane::new([0.1, -0.2], [0.3, 1.0], law);
    let mut tested = 0;
    for _ in 0..200 {
        let c0 = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
        let t = random_triangle(&mut rng, c0, 0.7);
        let f = plane.normal_force(&t);
        let fs = [f[0][0] + f[1][0] + f[2][0], f[0][1] + f[1][1] + f[2][1]];
        if fs[0].hypot(fs[1]) < 1e-3 {
            continue; // grazing contacts: W ~ d^3, central differences need h << d
        }
        tested += 1;
        let h = 1e-6;
        let w = |d: [f64; 2]| plane.energy(&t.map(|p| [p[0] + d[0], p[1] + d[1]]));
        let gx = -(w([h, 0.0]) - w([-h, 0.0])) / (2.0 * h);
        let gy = -(w([0.0, h]) - w([0.0, -h])) / (2.0 * h);
        let s = fs[0].hypot(fs[1]);
        assert!(
            (gx - fs[0]).abs() < 1e-6 * s.max(1e-4) && (gy - fs[1]).abs() < 1e-6 * s.max(1e-4),
            "{fs:?} vs {gx} {gy}"
        );
        // Along the normal.
        assert!(cross(fs, plane.normal).abs() < 1e-12 * s);
    }
    assert!(tested > 30);
    // Reaction through the model.
    let x = vec![[0.0, -0.1], [1.0, -0.1], [0.5, 1.0]];
    let tris = vec![[0, 1, 2]];
    let mut c = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
    c.walls.push(RigidPlane::new([0.0, 0.0], [0.0, 1.0], law));
    c.update_detection(&x, &tris);
    c.compute_forces(&x, &[[0.0; 2]; 3], &tris, &[], 1e-3);
    let mut f = vec![[0.0; 2]; 3];
    c.add_forces(&tris, &mut f);
    let mut r = [[0.0; 2]];
    c.wall_reactions(&mut r);
    assert!(f[0][1] + f[1][1] + f[2][1] > 0.0);
    assert_eq!(r[0][1], -(f[0][1] + f[1][1] + f[2][1]));
}

#[test]
fn moving_platen_triggers_redetection_after_half_the_buffer() {
    let x = vec![[0.0, 0.5], [1.0, 0.5], [0.5, 1.5]];
    let tris = vec![[0, 1, 2]];
    let law = ContactLaw::with_penalty(1.0);
    let mut c = Contact::new(
        ContactSettings {
            buffer: 0.2,
            ..Default::default()
        },
        ContactLaws::uniform(1, law),
    );
    c.walls.push(RigidPlane::new([0.0, 2.5], [0.0, -1.0], law)); // platen above, facing down
    assert!(c.update_detection(&x, &tris));
    assert!(c.wall_pairs().is_empty());
    c.walls[0].point[1] = 2.41; // moved 0.09 < b/2
    assert!(!c.update_detection(&x, &tris));
    c.walls[0].point[1] = 1.6; // moved 0.9 >= b/2; centroid 0.77 from the plane < r + b
    assert!(c.update_detection(&x, &tris));
    assert_eq!(c.wall_pairs(), &[[0, 0]]);
}

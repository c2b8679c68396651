//! `Contact::snapshot` / `Contact::restore`: a model driven N steps, snapshot, restored into a
//! model built afresh, then both driven M more steps at the same positions and velocities
//! give the same forces, friction histories, statistics, energies and plane reactions bit for
//! bit, through friction slip (couples and plane), re-detections, and releases of bonded pairs
//! after the restore (the couples they add without a detection rest on the restored detection
//! state). A snapshot that does not fit the model is an error that leaves it as it was.

use fdem_contact::{
    Contact, ContactLaw, ContactLaws, ContactSettings, ContactSnapshot, RigidPlane,
};

const DT: f64 = 1.0e-3;
const P: f64 = 1.0e3;

/// A fixed ground strip of 20 unit squares (two triangles each, sharing nodes) under a block
/// of 4 x 2 unit squares whose 16 triangles have their own nodes (a fractured body: triangles
/// bonded to their edge neighbours), its bottom 0.01 into the ground.
struct Scene {
    x0: Vec<[f64; 2]>,
    tris: Vec<[u32; 3]>,
    /// First node of the block.
    block: usize,
    /// Edge-neighbour pairs of the block's triangles.
    bonded: Vec<[u32; 2]>,
}

fn scene() -> Scene {
    let (mut x0, mut tris) = (Vec::new(), Vec::new());
    for i in 0..=20 {
        x0.push([i as f64, -1.0]);
        x0.push([i as f64, 0.0]);
    }
    for i in 0..20u32 {
        let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
        tris.push([a, b, c]);
        tris.push([a, c, d]);
    }
    let block = x0.len();
    let n_ground = tris.len() as u32;
    let mut bonded = Vec::new();
    for j in 0..2 {
        for i in 0..4 {
            let (x, y) = (2.0 + i as f64, -0.01 + j as f64);
            let q = [[x, y], [x + 1.0, y], [x + 1.0, y + 1.0], [x, y + 1.0]];
            for t in [[0, 1, 2], [0, 2, 3]] {
                let n = x0.len() as u32;
                x0.extend(t.map(|k| q[k]));
                tris.push([n, n + 1, n + 2]);
            }
            // the square's diagonal, its right and top neighbours
            let s = n_ground + 2 * (4 * j + i) as u32;
            bonded.push([s, s + 1]);
            if i < 3 {
                bonded.push([s, s + 3]);
            }
            if j < 1 {
                bonded.push([s + 1, s + 8]);
            }
        }
    }
    Scene {
        x0,
        tris,
        block,
        bonded,
    }
}

/// The model: one law with friction and damping between the triangles, a floor plane under
/// the ground (never reached) and a platen touching the block's top, sliding with friction.
fn model(sc: &Scene) -> Contact {
    let law = ContactLaw {
        mu: 0.3,
        damping: 5.0,
        ..ContactLaw::with_penalty(P)
    };
    let mut c = Contact::new(
        ContactSettings {
            buffer: 0.1,
            ..Default::default()
        },
        ContactLaws::uniform(1, law),
    );
    c.walls.push(RigidPlane::new(
        [0.0, -1.5],
        [0.0, 1.0],
        ContactLaw::with_penalty(P),
    ));
    c.walls.push(RigidPlane::new(
        [0.0, 1.985],
        [0.0, -1.0],
        ContactLaw {
            mu: 0.2,
            ..ContactLaw::with_penalty(P)
        },
    ));
    c.set_bonded(sc.tris.len(), &sc.bonded);
    c
}

/// Positions and velocities at step `n`: the block slides right at 1 m/s and sinks at
/// 0.01 m/s, each node wobbling (so bonded neighbours overlap a little); the platen slides
/// left at 0.5 m/s.
fn kinematics(sc: &Scene, c: &mut Contact, n: usize) -> (Vec<[f64; 2]>, Vec<[f64; 2]>) {
    let t = n as f64 * DT;
    let mut x = sc.x0.clone();
    let mut v = vec![[0.0; 2]; x.len()];
    for (k, (p, u)) in x.iter_mut().zip(&mut v).enumerate().skip(sc.block) {
        let w = 40.0 + k as f64;
        let a = 2e-3;
        p[0] += t + a * (w * t).sin();
        p[1] += -0.01 * t + a * (w * t + 1.0).cos();
        *u = [
            1.0 + a * w * (w * t).cos(),
            -0.01 - a * w * (w * t + 1.0).sin(),
        ];
    }
    c.walls[1].point = [-0.5 * t, 1.985];
    c.walls[1].velocity = [-0.5, 0.0];
    (x, v)
}

/// What one step gives, as bits: the scattered forces, the statistics, the energies and the
/// plane reactions.
fn step(sc: &Scene, c: &mut Contact, n: usize, release: &[[u32; 2]]) -> Vec<u64> {
    let (x, v) = kinematics(sc, c, n);
    c.release_pairs(release, &sc.tris);
    c.update_detection(&x, &sc.tris);
    let s = c.compute_forces(&x, &v, &sc.tris, &[], DT);
    let mut f = vec![[0.0; 2]; x.len()];
    c.add_forces(&sc.tris, &mut f);
    let mut r = vec![[0.0; 2]; c.walls.len()];
    c.wall_reactions(&mut r);
    c.commit();
    let e = c.energy(&x, &sc.tris, &[]);
    let mut out: Vec<u64> = f.iter().chain(&r).flatten().map(|v| v.to_bits()).collect();
    out.extend([
        s.n_couples as u64,
        s.n_active as u64,
        s.n_wall_active as u64,
        s.n_slipping as u64,
        s.max_phi.to_bits(),
        s.trial_dissipation.to_bits(),
        e.potential.to_bits(),
        e.friction_stored.to_bits(),
        e.friction_dissipated.to_bits(),
        c.damping_power(&sc.tris, &v).to_bits(),
        c.n_detections(),
        c.n_released_couples(),
    ]);
    out
}

/// The friction history of a snapshot as bits (couple index, six forces) and of the planes.
fn friction_bits(s: &ContactSnapshot) -> Vec<u64> {
    let mut out = Vec::new();
    for (k, f) in &s.friction {
        out.push(u64::from(*k));
        out.extend(f.map(f64::to_bits));
    }
    out.extend(s.wall_ft.iter().map(|f| f.to_bits()));
    out
}

#[test]
fn a_restored_model_continues_bit_for_bit() {
    let sc = scene();
    let (n, m) = (120, 160);
    let mut a = model(&sc);
    for k in 0..n {
        step(&sc, &mut a, k, &[]);
    }
    let snap = a.snapshot();
    let mut b = model(&sc);
    b.restore(snap.clone()).expect("restores");
    assert_eq!(
        format!("{:?}", b.snapshot()),
        format!("{snap:?}"),
        "a restored model's snapshot is the one restored (Debug prints every f64 exactly)"
    );
    let (det0, mut slips, mut wall_slips) = (a.n_detections(), 0, 0);
    for k in n..n + m {
        // the block's bonded pairs, released a few at a time after the restore
        let release: &[[u32; 2]] = match k - n {
            5 => &sc.bonded[..6],
            40 => &sc.bonded[6..14],
            90 => &sc.bonded[14..],
            _ => &[],
        };
        let (ra, rb) = (step(&sc, &mut a, k, release), step(&sc, &mut b, k, release));
        assert_eq!(ra, rb, "step {k}: forces, statistics, energies, reactions");
        assert_eq!(
            friction_bits(&a.snapshot()),
            friction_bits(&b.snapshot()),
            "step {k}: friction history"
        );
        slips += a.stats().n_slipping;
        wall_slips += a.wall_results().iter().filter(|r| r.slipping).count();
    }
    assert_eq!(format!("{:?}", a.snapshot()), format!("{:?}", b.snapshot()));
    // the case covers what it is meant to: slip on couples and on the platen, detections
    // after the restore, couples added by releases, loaded plane pairs
    let det = a.n_detections() - det0;
    let s = a.snapshot();
    eprintln!(
        "after restore: {det} detections, {slips} slipping couple edges, {wall_slips} slipping \
         plane pairs, {} released couples, {} couples, {} with friction",
        a.n_released_couples(),
        s.couples.len(),
        s.friction.len()
    );
    assert!(det >= 2, "{det} detections after the restore");
    assert!(slips > wall_slips && wall_slips > 0, "{slips} {wall_slips}");
    assert!(a.n_released_couples() > 0);
    assert!(s.wall_results.iter().any(|r| r.fn_total > 0.0));
    fdem_figures::record_part(
        83,
        1,
        format!(
            "model identical ({det} detections after the restore, slip of couples and platen, {} couples added by releases)",
            a.n_released_couples()
        ),
    );
}

#[test]
fn a_snapshot_that_does_not_fit_is_refused_and_changes_nothing() {
    let sc = scene();
    let mut a = model(&sc);
    for k in 0..30 {
        step(&sc, &mut a, k, &[]);
    }
    let good = a.snapshot();
    assert!(good.couples.len() > 2 && !good.flagged.is_empty());
    let fresh = model(&sc).snapshot();
    let bad: Vec<(&str, ContactSnapshot)> = vec![
        ("planes", {
            let mut s = good.clone();
            s.walls.pop();
            s
        }),
        ("couples order", {
            let mut s = good.clone();
            s.couples.swap(0, 1);
            s
        }),
        ("couple beyond the triangles", {
            let mut s = good.clone();
            s.n_tris_det = 10;
            s
        }),
        ("friction index", {
            let mut s = good.clone();
            s.friction.push((s.couples.len() as u32, [1.0; 6]));
            s
        }),
        ("results", {
            let mut s = good.clone();
            s.results.pop();
            s
        }),
        ("plane friction", {
            let mut s = good.clone();
            s.wall_ft.push(0.0);
            s
        }),
        ("bonded rows", {
            let mut s = good.clone();
            s.bonded.pop();
            s
        }),
        ("bonded pair in one row only", {
            let mut s = good.clone();
            let k = s.bonded.len() - 1;
            s.bonded[k] = (s.bonded[k] + 1) % s.bonded_lens.len() as u32;
            s
        }),
    ];
    for (what, s) in bad {
        let mut b = model(&sc);
        let err = b.restore(s).expect_err(what);
        assert_eq!(
            format!("{:?}", b.snapshot()),
            format!("{fresh:?}"),
            "{what}: {err}"
        );
    }
}

//! The per-step contact calls allocate nothing once warm (counted with a global counting
//! allocator), on 1 and 2 threads.

mod common;
use common::{Rng, random_triangle};
use fdem_contact::{Contact, ContactLaw, ContactLaws, ContactSettings, RigidPlane};
use stats_alloc::{INSTRUMENTED_SYSTEM, Region, StatsAlloc};
use std::alloc::System;

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

#[test]
fn step_calls_do_not_allocate_once_warm() {
    // update_detection (with and without a redetection), compute_forces, add_forces,
    // add_family, wall_reactions and commit: zero allocations and reallocations (exact count)
    // after a warm-up, with friction, damping and a plane.
    let mut rng = Rng(3);
    let (mut x, mut v, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..3000u32 {
        let c = [rng.range(0.0, 60.0), rng.range(0.0, 60.0)];
        x.extend_from_slice(&random_triangle(&mut rng, c, 0.8));
        for _ in 0..3 {
            v.push([rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)]);
        }
        tris.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let law = ContactLaw {
        mu: 0.4,
        damping: 2.0,
        ..ContactLaw::with_penalty(1.0e3)
    };
    let mut c = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
    c.walls.push(RigidPlane::new([0.0, 1.0], [0.0, 1.0], law));
    let mut f = vec![[0.0; 2]; x.len()];
    let mut r = [[0.0; 2]];
    let pools: Vec<_> = [1, 2]
        .map(|n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        })
        .into_iter()
        .collect();
    let mut run = |c: &mut Contact, x: &[[f64; 2]], f: &mut Vec<[f64; 2]>, redetect: bool| {
        if redetect {
            c.invalidate();
        }
        c.update_detection(x, &tris);
        c.compute_forces(x, &v, &tris, &[], 1e-3);
        c.add_forces(&tris, f);
        c.add_family(fdem_contact::Family::Friction, &tris, f);
        c.wall_reactions(&mut r);
        c.commit();
    };
    for pool in &pools {
        for k in 0..3 {
            pool.install(|| run(&mut c, &x, &mut f, k == 1));
        }
    }
    std::thread::sleep(std::time::Duration::from_millis(50));
    for (pool, threads) in pools.iter().zip([1, 2]) {
        let region = Region::new(GLOBAL);
        for k in 0..6 {
            // Small moves keep the same couples; every third step redetects.
            x.iter_mut().for_each(|p| p[0] += 1e-6);
            pool.install(|| run(&mut c, &x, &mut f, k % 3 == 2));
        }
        let s = region.change();
        assert_eq!(s.allocations, 0, "{threads} threads: {s:?}");
        assert_eq!(s.reallocations, 0, "{threads} threads: {s:?}");
    }
    assert!(c.stats().n_active > 100);
}

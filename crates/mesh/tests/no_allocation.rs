//! The force kernels allocate nothing per call (counted with a global counting allocator),
//! on 1 and 2 threads.

mod common;
use fdem_mesh::{ForceScratch, Material};
use stats_alloc::{INSTRUMENTED_SYSTEM, Region, StatsAlloc};
use std::alloc::System;

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

/// After a warm-up call, 10 calls of `internal_forces` and `force_derivative` make zero
/// allocations (the count is exact: any allocation fails the test).
#[test]
fn force_kernels_do_not_allocate() {
    let mesh = common::grid(200, 100, 2.0, 1.0, 0.4, 1);
    let el = common::elements(
        &mesh,
        Material {
            damping_ratio: 0.1,
            ..Material::new(1e9, 0.3, 2000.0)
        },
    );
    let x: Vec<[f64; 2]> = mesh.nodes.iter().map(|p| [1.01 * p[0], p[1]]).collect();
    let v = vec![[0.1, 0.0]; x.len()];
    let mut f = vec![[0.0; 2]; x.len()];
    let mut s = ForceScratch::new(&el);
    let pools: Vec<_> = [1, 2]
        .map(|n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        })
        .into_iter()
        .collect();
    // Warm-up: thread start-up allocates once per worker.
    for pool in &pools {
        for _ in 0..3 {
            pool.install(|| el.internal_forces(&x, &v, &mut f, &mut s));
            pool.install(|| el.force_derivative(&x, &v, &v, &mut f, &mut s));
        }
    }
    std::thread::sleep(std::time::Duration::from_millis(50));
    for (pool, threads) in pools.iter().zip([1, 2]) {
        let region = Region::new(GLOBAL);
        for _ in 0..10 {
            pool.install(|| el.internal_forces(&x, &v, &mut f, &mut s));
            pool.install(|| el.force_derivative(&x, &v, &v, &mut f, &mut s));
            pool.install(|| el.internal_forces_owner(&x, &v, &mut f));
        }
        let c = region.change();
        assert_eq!(c.allocations, 0, "{threads} threads: {c:?}");
        assert_eq!(c.reallocations, 0, "{threads} threads: {c:?}");
    }
}

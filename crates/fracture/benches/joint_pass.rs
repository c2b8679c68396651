//! Throughput of the joint-force pass (joints per second) on 1 and 2 threads, on an exploded
//! structured mesh of 100 000 triangles (about 150 000 joints) with random node perturbations:
//! `prepeak` (up to 0.2 o_p: every joint before its peak, the bulk of a loaded specimen) and
//! `softening` (up to 3 o_p: most joints softening, in mixed mode).
#![allow(missing_docs)]

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fdem_fracture::*;

fn bench(c: &mut Criterion) {
    let mesh = common::exploded_grid(250, 200, 0.005, 0.005);
    let mat = JointMaterialInput {
        tensile_strength: 5e6,
        cohesion: 10e6,
        friction_angle_deg: 30.0,
        fracture_energy_i: 50.0,
        fracture_energy_ii: 250.0,
        penalty_normal: 3e12,
        penalty_tangential: 3e12,
    };
    let set = JointSet::new(&mesh.joints, &[mat], mesh.x.len(), 1.0).unwrap();
    let o_p = 2.0 * 0.005 * 5e6 / 3e12;
    let mut g = c.benchmark_group("joint_force_pass");
    g.throughput(Throughput::Elements(set.len() as u64));
    g.sample_size(20);
    for (name, amp) in [("prepeak", 0.2 * o_p), ("softening", 3.0 * o_p)] {
        let mut rng = common::Lcg(7);
        let x: Vec<[f64; 2]> = mesh
            .x
            .iter()
            .map(|p| [p[0] + amp * rng.next(), p[1] + amp * rng.next()])
            .collect();
        let state = JointState::new(&set, &x);
        let mut scratch = JointScratch::new(set.len());
        let mut f = vec![[0.0; 2]; x.len()];
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            g.bench_function(
                format!("{name}_{}_joints_{threads}_threads", set.len()),
                |b| {
                    b.iter(|| {
                        pool.install(|| {
                            accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f)
                        })
                    })
                },
            );
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

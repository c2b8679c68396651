//! Triangle-steps per second of a fracturing Brazilian disc of about 10^5 triangles, whole
//! solver (`driver::run_outcome`: elements, joints, contact with the platens and between the
//! exploded triangles, central difference, energy books), output off, on 1 and 2 threads.
//!
//! The disc (R = 25 mm, t = 10 mm, E = 30 GPa, ring mesh h = R/129: 99 846 triangles, the whole
//! disc fracturing: 149 382 joints after the mesh crate's explode) is generated here with the
//! ring construction of `meshes/disc_rings.py`. The platens close at 2 x 10 m/s from the start
//! and the joints are brittle (ft = 3 MPa, G_I = G_II = 1 J/m^2), so joints under the platens
//! soften and break within the measured window (the first `STEPS` steps of each run: fracture
//! and contact are in every iteration; the summary of one run is printed with the per-stage
//! times and the number of broken joints).
//!
//! `cargo bench --bench fracture_disc`

use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fdem_solver::driver::{Problem, RunOptions, load, run_outcome};

const STEPS: u64 = 100;

#[path = "common/disc.rs"]
mod disc;
use disc::scene_dir;

fn loaded(dir: &Path) -> Problem {
    let mut l = load(&dir.join("disc.scene.json")).unwrap();
    l.n_steps = STEPS;
    l
}

fn bench(c: &mut Criterion) {
    let dir = scene_dir();
    let mut l = loaded(&dir);
    let n_tri = l.model.triangles.len();
    let opts = RunOptions {
        out_dir: dir.join("out"),
        raw: false,
        ..Default::default()
    };
    // one run with the stage timers, for the profile
    let o = run_outcome(&mut l, &opts, &mut |_| {}).unwrap();
    let s = &o.summary;
    eprintln!(
        "fracturing disc: {n_tri} triangles, dt = {:.3e} s, {STEPS} steps; wall {:.4} s (stepping {:.4e} triangle-steps/s); timers {}; stages {}",
        s.time_step,
        s.wall_time,
        s.triangle_steps_per_second,
        serde_json::to_string(&s.timers).unwrap(),
        s.stages
    );
    // Results identical bit for bit on 1 and 2 threads (final positions and velocities).
    let mut finals = Vec::new();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let o = pool.install(|| run_outcome(&mut l, &opts, &mut |_| {}).unwrap());
        let bits: Vec<u64> = (o.last_frame.points.iter())
            .chain(&o.last_frame.velocity)
            .flat_map(|p| [p[0].to_bits(), p[1].to_bits()])
            .collect();
        finals.push((bits, o.summary.stages["fracture"]["broken"].clone()));
    }
    assert!(
        finals[0] == finals[1],
        "1 and 2 threads give different final states"
    );
    // FNV-1a over the bits: compare runs of different builds
    let hash = finals[0].0.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b).wrapping_mul(0x0100_0000_01b3)
    });
    eprintln!(
        "1 and 2 threads: final positions and velocities bit-identical ({} values, {} broken, hash {hash:016x})",
        finals[0].0.len(),
        finals[0].1
    );
    let mut g = c.benchmark_group("fracture_disc");
    g.sample_size(10);
    g.throughput(Throughput::Elements(n_tri as u64 * STEPS));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        g.bench_function(
            format!("{n_tri}_triangles_{STEPS}_steps_{threads}_threads"),
            |b| b.iter(|| pool.install(|| run_outcome(&mut l, &opts, &mut |_| {}).unwrap())),
        );
    }
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! Each scheme's cost per DOF-step on 10^6 DOFs.
//!
//! - `overhead/<scheme>/<threads>`: 10^6 uncoupled unit oscillators, `a = -x` and the exact
//!   `G = -2 a`: the cheapest possible force (one streaming pass, 16 B per DOF), so the
//!   scheme's own update loops dominate. Throughput is in the bytes the whole step moves by
//!   the model in each scheme's docs (8 B per array read or written per DOF in the update
//!   loops) plus 16 B per DOF per force or gradient evaluation, to compare with the triad
//!   bandwidth of `benches/bandwidth.rs` at the same working-set size.
//! - `chain/<scheme>/<threads>`: a 10^6-DOF linear chain with its stencil force
//!   `a_i = k/m (x_{i-1} - 2 x_i + x_{i+1})` and exact gradient: DOF-steps per second.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fdem_time::systems::{LinearChain, Oscillator};
use fdem_time::{SchemeKind, State};

const N: usize = 1_000_000;

/// Bytes moved per DOF-step by the scheme's update loops (the model of each scheme's docs).
pub fn loop_bytes(kind: SchemeKind) -> u64 {
    8 * match kind {
        SchemeKind::CentralDifference => 8,
        SchemeKind::Omf30 => 13,
        SchemeKind::Chin => 14,
        SchemeKind::ForestRuth => 18,
        SchemeKind::Omf32 => 30,
        SchemeKind::Pc3 => 17,
        SchemeKind::Pc4 => 21,
        SchemeKind::Pc5 => 25,
    }
}

/// Bytes moved per DOF-step by a whole step with the oscillator force (16 B per force or
/// gradient evaluation: read one array, write one).
pub fn step_bytes(kind: SchemeKind) -> u64 {
    let c = kind.cost();
    loop_bytes(kind) + 16 * u64::from(c.forces + c.gradients)
}

fn bench(cr: &mut Criterion) {
    let x0: Vec<f64> = (0..N).map(|i| (i as f64 * 1e-3).sin()).collect();
    let v0: Vec<f64> = (0..N).map(|i| (i as f64 * 1e-3).cos()).collect();
    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for kind in SchemeKind::ALL {
            let mut g = cr.benchmark_group(format!("overhead/{kind}"));
            g.sample_size(10)
                .warm_up_time(std::time::Duration::from_secs(1))
                .measurement_time(std::time::Duration::from_secs(2));
            g.throughput(Throughput::Bytes(step_bytes(kind) * N as u64));
            let mut sys = Oscillator::new(N, 1.0);
            let mut st = State::new(0.0, x0.clone(), v0.clone());
            let mut s = kind.build(N);
            g.bench_function(format!("{threads}-thread"), |b| {
                b.iter(|| pool.install(|| s.step(&mut sys, &mut st, 0.1)))
            });
            g.finish();

            let mut g = cr.benchmark_group(format!("chain/{kind}"));
            g.sample_size(10)
                .warm_up_time(std::time::Duration::from_secs(1))
                .measurement_time(std::time::Duration::from_secs(2));
            g.throughput(Throughput::Elements(N as u64));
            let mut sys = LinearChain::new(N, 1.0);
            let mut st = State::new(0.0, x0.clone(), vec![0.0; N]);
            let mut s = kind.build(N);
            g.bench_function(format!("{threads}-thread"), |b| {
                b.iter(|| pool.install(|| s.step(&mut sys, &mut st, 0.1)))
            });
            g.finish();
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

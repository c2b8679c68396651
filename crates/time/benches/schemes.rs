//! Each scheme's own cost per DOF-step on a 10^6-DOF linear chain.
//!
//! - `overhead/<scheme>/<threads>`: the force evaluation is a no-op (and the gradient an
//!   exact no-op), so only the scheme's update loops run. Throughput is in the bytes those
//!   loops move per step by the model in each scheme's docs (8 B per array read or written
//!   per DOF), to compare with the triad bandwidth of `benches/bandwidth.rs`.
//! - `chain/<scheme>/<threads>`: the same with the chain's real stencil force
//!   `a_i = k/m (x_{i-1} - 2 x_i + x_{i+1})` and its exact gradient: throughput in
//!   DOF-steps per second.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fdem_time::systems::LinearChain;
use fdem_time::{GradientWork, SchemeKind, SecondOrderSystem, State};

const N: usize = 1_000_000;

/// A chain whose forces cost nothing: isolates the schemes' loops.
struct FreeChain {
    inv_mass: Vec<f64>,
}

impl SecondOrderSystem for FreeChain {
    fn n_dofs(&self) -> usize {
        self.inv_mass.len()
    }
    fn inv_mass(&self) -> &[f64] {
        &self.inv_mass
    }
    fn acceleration(&mut self, _t: f64, _x: &[f64], _v: &[f64], _a: &mut [f64]) {}
    fn has_exact_gradient(&self) -> bool {
        true
    }
    fn force_gradient(
        &mut self,
        _: f64,
        _: &[f64],
        _: &[f64],
        _: &[f64],
        _: &mut [f64],
        _: &mut GradientWork,
    ) {
    }
}

/// Bytes moved per DOF-step by the scheme's update loops (the model of each scheme's docs).
pub fn bytes_per_dof_step(kind: SchemeKind) -> u64 {
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

fn bench(cr: &mut Criterion) {
    let x0: Vec<f64> = (0..N).map(|i| 1e-3 * (i as f64 * 1e-3).sin()).collect();
    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for kind in SchemeKind::ALL {
            let mut g = cr.benchmark_group(format!("overhead/{kind}"));
            g.sample_size(10)
                .measurement_time(std::time::Duration::from_secs(2));
            g.throughput(Throughput::Bytes(bytes_per_dof_step(kind) * N as u64));
            let mut sys = FreeChain {
                inv_mass: vec![1.0; N],
            };
            let mut st = State::new(0.0, x0.clone(), vec![0.0; N]);
            let mut s = kind.build(N);
            g.bench_function(format!("{threads}-thread"), |b| {
                b.iter(|| pool.install(|| s.step(&mut sys, &mut st, 1e-3)))
            });
            g.finish();

            let mut g = cr.benchmark_group(format!("chain/{kind}"));
            g.sample_size(10)
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

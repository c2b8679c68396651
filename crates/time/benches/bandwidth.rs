//! Memory bandwidth of this machine: a STREAM-triad-like kernel `a = b + s c` on 1 and 2
//! threads, at the working-set size of the scheme benchmarks (10^6 elements per array,
//! 24 MB in all) and far beyond any cache (2^25 elements, 768 MiB in all). Throughput is
//! reported in bytes moved as STREAM counts them: 24 B per element (two reads, one write;
//! write-allocate traffic not counted).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rayon::prelude::*;
use std::hint::black_box;

fn triad(a: &mut [f64], b: &[f64], c: &[f64], s: f64) {
    for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
        *a = b + s * c;
    }
}

fn bench(cr: &mut Criterion) {
    for (label, n) in [("1e6", 1_000_000usize), ("2^25", 1usize << 25)] {
        let mut g = cr.benchmark_group(format!("triad/{label}"));
        g.sample_size(10);
        g.throughput(Throughput::Bytes(24 * n as u64));
        let mut a = vec![0.0; n];
        let b = vec![1.0; n];
        let c = vec![2.0; n];
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            g.bench_function(format!("{threads}-thread"), |bn| {
                bn.iter(|| {
                    pool.install(|| {
                        a.par_chunks_mut(1 << 14)
                            .zip(b.par_chunks(1 << 14))
                            .zip(c.par_chunks(1 << 14))
                            .for_each(|((a, b), c)| triad(a, b, c, 3.0));
                    });
                    black_box(&a);
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

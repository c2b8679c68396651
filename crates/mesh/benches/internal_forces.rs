//! Benchmark of the internal-force kernel on a 10^6-triangle mesh, on 1 and 2 threads.
//!
//! Mesh: a 708 x 708 grid of squares cut into 1 002 528 triangles, with the nodes numbered
//! row by row. Reports triangles per second (criterion throughput in elements). Also checks
//! that the 1- and 2-thread results agree bit for bit.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fdem_mesh::{Elements, ForceScratch, Material, Mesh};
use std::hint::black_box;

fn grid(n: usize) -> Mesh {
    let mut nodes = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            nodes.push([i as f64 / n as f64, j as f64 / n as f64]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut tris = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::from_nodes_triangles(nodes, tris).unwrap()
}

fn bench(c: &mut Criterion) {
    let mesh = grid(708);
    let x: Vec<[f64; 2]> = mesh
        .nodes
        .iter()
        .map(|p| [1.001 * p[0] + 1e-4 * p[1], 0.999 * p[1]])
        .collect();
    let v: Vec<[f64; 2]> = mesh.nodes.iter().map(|p| [p[1], -p[0]]).collect();
    let mut group = c.benchmark_group("internal_forces_1M");
    group.throughput(Throughput::Elements(mesh.n_triangles() as u64));
    group.sample_size(20);
    for xi in [0.0, 0.1] {
        let m = Material {
            damping_ratio: xi,
            ..Material::new(10e9, 0.25, 2700.0)
        };
        let el = Elements::new(&mesh, &[m]).unwrap();
        let mut results = Vec::new();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut s = ForceScratch::new(&el);
            let mut f = vec![[0.0; 2]; mesh.n_nodes()];
            let name = format!(
                "{}_threads{threads}",
                if xi > 0.0 { "viscous" } else { "elastic" }
            );
            group.bench_function(name, |b| {
                b.iter(|| {
                    pool.install(|| el.internal_forces(&x, &v, &mut f, &mut s));
                    black_box(&f);
                })
            });
            f.iter_mut().for_each(|p| *p = [0.0; 2]);
            pool.install(|| el.internal_forces(&x, &v, &mut f, &mut s));
            results.push(f);
        }
        assert!(
            results[0]
                .iter()
                .zip(&results[1])
                .all(|(a, b)| a[0].to_bits() == b[0].to_bits() && a[1].to_bits() == b[1].to_bits()),
            "1- and 2-thread forces differ"
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

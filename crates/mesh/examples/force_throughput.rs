//! Throughput of the internal-force kernels on a 10^6-triangle mesh and the machine's memory
//! bandwidth (a STREAM-like triad), on 1 and 2 threads, best of N runs (the best run is the
//! least disturbed by other processes on a shared machine):
//! `cargo run --release -p fdem-mesh --example force_throughput`.

use fdem_mesh::{Elements, ForceScratch, Material, Mesh};
use rayon::prelude::*;
use std::time::Instant;

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

fn best(runs: usize, mut f: impl FnMut()) -> (f64, f64) {
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    (t[0], t[runs / 2])
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(40);
    let mesh = grid(708);
    let nt = mesh.n_triangles() as f64;
    let x: Vec<[f64; 2]> = mesh
        .nodes
        .iter()
        .map(|p| [1.001 * p[0] + 1e-4 * p[1], 0.999 * p[1]])
        .collect();
    let v: Vec<[f64; 2]> = mesh.nodes.iter().map(|p| [p[1], -p[0]]).collect();
    println!(
        "mesh: {} triangles, {} nodes; best and median of {runs} runs",
        mesh.n_triangles(),
        mesh.n_nodes()
    );
    // STREAM-like triad a = b + s c over 3 x 32 MiB.
    let n = 4 << 20;
    let (b, c) = (vec![1.0f64; n], vec![2.0f64; n]);
    let mut a = vec![0.0f64; n];
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (tb, tm) = best(runs, || {
            pool.install(|| {
                a.par_chunks_mut(1 << 16)
                    .zip(b.par_chunks(1 << 16))
                    .zip(c.par_chunks(1 << 16))
                    .for_each(|((a, b), c)| {
                        for i in 0..a.len() {
                            a[i] = b[i] + 3.0 * c[i];
                        }
                    })
            })
        });
        // 24 bytes counted per element (read b, c, write a), as STREAM does
        println!(
            "triad {threads} thread(s): {:.1} GB/s best, {:.1} GB/s median",
            24.0 * n as f64 / tb / 1e9,
            24.0 * n as f64 / tm / 1e9
        );
    }
    for xi in [0.0, 0.1] {
        let m = Material {
            damping_ratio: xi,
            ..Material::new(10e9, 0.25, 2700.0)
        };
        let el = Elements::new(&mesh, &[m]).unwrap();
        let dup = el.block_tris.len() as f64 / nt - 1.0;
        let mut s = ForceScratch::new(&el);
        let mut f = vec![[0.0; 2]; mesh.n_nodes()];
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let kind = if xi > 0.0 { "viscous" } else { "elastic" };
            let (tb, tm) = best(runs, || {
                pool.install(|| el.internal_forces_owner(&x, &v, &mut f))
            });
            println!(
                "{kind} owner-computes {threads} thread(s): {:.1} M tri/s best, {:.1} median ({:.1} % triangles evaluated twice)",
                nt / tb / 1e6,
                nt / tm / 1e6,
                100.0 * dup
            );
            let (tb, tm) = best(runs, || {
                pool.install(|| el.internal_forces_buffered(&x, &v, &mut f, &mut s))
            });
            println!(
                "{kind} buffered      {threads} thread(s): {:.1} M tri/s best, {:.1} median",
                nt / tb / 1e6,
                nt / tm / 1e6
            );
        }
    }
}

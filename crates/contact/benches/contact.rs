//! Contact benchmarks: detection time per triangle (NBS and parry's BVH) for 10^4..10^6
//! triangles, and contact-force throughput (couples per second) on 1 and 2 threads.
//!
//! The configuration is a dense FDEM-like packing: a square grid of cells of size 1, each split
//! into two triangles that own their nodes (as with intrinsic joints), every node jittered by
//! up to ±0.05, so neighbouring triangles overlap slightly (about 12 couples per triangle).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fdem_contact::broad_parry::ParryBroadPhase;
use fdem_contact::nbs::Nbs;
use fdem_contact::{
    BoundingCircles, Contact, ContactLaw, ContactLaws, ContactSettings, Exclusions,
};
use std::hint::black_box;
use std::time::Duration;

#[path = "common/packing.rs"]
mod packing;
use packing::packing;

fn detection(c: &mut Criterion) {
    let mut g = c.benchmark_group("detection");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    for n in [10_000usize, 100_000, 1_000_000] {
        let p = packing(n);
        let mut circles = BoundingCircles::default();
        let excl = Exclusions::new();
        g.throughput(Throughput::Elements(n as u64));
        let mut out = Vec::new();
        let mut nbs = Nbs::new();
        g.bench_with_input(BenchmarkId::new("nbs", n), &n, |b, _| {
            b.iter(|| {
                circles.update(&p.x, &p.tris);
                nbs.find_couples(&circles, 0.05, &p.tris, &excl, &mut out);
                black_box(out.len())
            })
        });
        let mut parry = ParryBroadPhase::new();
        g.bench_with_input(BenchmarkId::new("parry_bvh", n), &n, |b, _| {
            b.iter(|| {
                circles.update(&p.x, &p.tris);
                parry.find_couples(&circles, 0.05, &p.tris, &excl, &mut out);
                black_box(out.len())
            })
        });
        eprintln!(
            "n = {n}: {} couples ({:.2} per triangle)",
            out.len(),
            out.len() as f64 / n as f64
        );
    }
    g.finish();
}

fn forces(c: &mut Criterion) {
    let mut g = c.benchmark_group("contact_forces");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    let n = 100_000;
    let p = packing(n);
    for mu in [0.0, 0.5] {
        let law = ContactLaw {
            mu,
            ..ContactLaw::with_penalty(1.0e9)
        };
        let mut contact = Contact::new(
            ContactSettings {
                buffer: 0.05,
                // Every circle candidate is a couple, as in the figures of docs/contact.md
                // section 10 (the narrow filter would drop the separated ones).
                narrow: false,
                ..Default::default()
            },
            ContactLaws::uniform(1, law),
        );
        contact.update_detection(&p.x, &p.tris);
        let stats = contact.compute_forces(&p.x, &p.v, &p.tris, &[], 1e-6);
        eprintln!(
            "mu = {mu}: {} couples, {} active ({:.0}%)",
            stats.n_couples,
            stats.n_active,
            100.0 * stats.n_active as f64 / stats.n_couples as f64
        );
        g.throughput(Throughput::Elements(stats.n_couples as u64));
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut f = vec![[0.0; 2]; p.x.len()];
            g.bench_function(BenchmarkId::new(format!("mu{mu}_threads"), threads), |b| {
                b.iter(|| {
                    pool.install(|| {
                        contact.compute_forces(&p.x, &p.v, &p.tris, &[], 1e-6);
                    });
                    f.iter_mut().for_each(|g| *g = [0.0; 2]);
                    contact.add_forces(&p.tris, &mut f);
                    black_box(f[0])
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, detection, forces);
criterion_main!(benches);

//! Times the contact force pass (`compute_forces` + `add_forces`) on the benchmark packing of
//! `benches/contact.rs` (10^5 triangles, about 7.9 couples per triangle, 30 % overlapping), on
//! 1 and 2 threads, and prints the fastest of `reps` passes, the process CPU time per pass
//! (from /proc/self/stat, 10 ms ticks over all passes: not inflated by time spent waiting for
//! a core on a shared machine) and a checksum of the forces:
//! `cargo run --release -p fdem-contact --example force_pass [reps]`.

use fdem_contact::{Contact, ContactLaw, ContactLaws, ContactSettings};
use std::time::Instant;

#[path = "../benches/common/packing.rs"]
mod packing;
use packing::packing;

fn main() {
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let packing::Packing { x, v, tris } = packing(100_000);
    for (mu, damping) in [(0.0, 0.0), (0.5, 0.0), (0.5, 1.0e5)] {
        let law = ContactLaw {
            mu,
            damping,
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
        contact.update_detection(&x, &tris);
        let mut f = vec![[0.0; 2]; x.len()];
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut best = f64::MAX;
            let mut n_couples = 0;
            let cpu0 = cpu_seconds();
            for _ in 0..reps {
                let t0 = Instant::now();
                let s = pool.install(|| contact.compute_forces(&x, &v, &tris, &[], 1e-6));
                f.iter_mut().for_each(|g| *g = [0.0; 2]);
                contact.add_forces(&tris, &mut f);
                best = best.min(t0.elapsed().as_secs_f64());
                n_couples = s.n_couples;
            }
            let cpu = (cpu_seconds() - cpu0) / reps as f64;
            let sum: f64 = f.iter().map(|g| g[0].abs() + g[1].abs()).sum();
            println!(
                "mu = {mu}, damping = {damping:e}, {threads} thread(s): best {:.1} ms ({:.2} M couples/s), CPU {:.1} ms per pass ({:.2} M couples per CPU-s); {n_couples} couples, checksum {sum:.17e}",
                best * 1e3,
                n_couples as f64 / best / 1e6,
                cpu * 1e3,
                n_couples as f64 / cpu / 1e6
            );
        }
    }
}

/// User + system CPU time of this process \[s\] (Linux; 0 elsewhere).
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the command name (which ends with ')'): utime and stime are the 12th and
    // 13th, in clock ticks of 1/100 s.
    let rest = stat.rsplit_once(')').map(|r| r.1).unwrap_or("");
    let f: Vec<&str> = rest.split_whitespace().collect();
    let tick = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    (tick(11) + tick(12)) / 100.0
}

//! Times the contact force pass (`compute_forces` + `add_forces`) on the benchmark packing of
//! `benches/contact.rs` (10^5 triangles, about 7.9 couples per triangle, 30 % overlapping), on
//! 1 and 2 threads, and prints the fastest of `reps` passes, the process CPU time per pass
//! (from /proc/self/stat, 10 ms ticks over all passes: not inflated by time spent waiting for
//! a core on a shared machine) and a checksum of the forces:
//! `cargo run --release -p fdem-contact --example force_pass [reps]`.

use fdem_contact::{Contact, ContactLaw, ContactLaws, ContactSettings};
use std::time::Instant;

/// Positions, velocities, triangles.
type Packing = (Vec<[f64; 2]>, Vec<[f64; 2]>, Vec<[u32; 3]>);

fn packing(n_tris: usize) -> Packing {
    let side = ((n_tris / 2) as f64).sqrt().ceil() as usize;
    let mut s = 0x1234_5678_9abc_def0u64;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let (mut x, mut v, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    'outer: for j in 0..side {
        for i in 0..side {
            let (a, b) = (i as f64, j as f64);
            let corners = [[a, b], [a + 1.0, b], [a + 1.0, b + 1.0], [a, b + 1.0]];
            for t in [[0, 1, 2], [0, 2, 3]] {
                if tris.len() == n_tris {
                    break 'outer;
                }
                let base = x.len() as u32;
                for k in t {
                    let c: [f64; 2] = corners[k];
                    x.push([c[0] + 0.1 * rnd(), c[1] + 0.1 * rnd()]);
                    v.push([rnd(), rnd()]);
                }
                tris.push([base, base + 1, base + 2]);
            }
        }
    }
    (x, v, tris)
}

fn main() {
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let (x, v, tris) = packing(100_000);
    for (mu, damping) in [(0.0, 0.0), (0.5, 0.0), (0.5, 1.0e5)] {
        let law = ContactLaw {
            mu,
            damping,
            ..ContactLaw::with_penalty(1.0e9)
        };
        let mut contact = Contact::new(
            ContactSettings {
                buffer: 0.05,
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

//! Checkpoints of the fracturing disc of about 10^5 triangles (`benches/common/disc.rs`): the
//! size of one checkpoint (bytes per triangle), the time a run waits to encode it and the time
//! of its write (on the writer's thread), and the cost on a run: 300 steps with a checkpoint
//! every 100 steps against the same run without, alternated (the machine is shared).
//!
//! `cargo bench --bench checkpoint`

use std::time::Instant;

use fdem_solver::checkpoint::Every;
use fdem_solver::driver::{RunOptions, load, run_outcome};

#[path = "common/disc.rs"]
mod disc;

const STEPS: u64 = 300;

fn main() {
    let dir = disc::scene_dir();
    let mut l = load(&dir.join("disc.scene.json")).unwrap();
    l.n_steps = STEPS;
    let n_tri = l.model.triangles.len();
    let out = dir.join("out");
    let with = |every: Every| RunOptions {
        out_dir: out.clone(),
        checkpoint_every: Some(every),
        ..Default::default()
    };
    // one run with checkpoints: their size and times
    let o = run_outcome(&mut l, &with(Every::Steps(100)), &mut |_| {}).unwrap();
    let c = &o.checkpoints;
    println!(
        "{n_tri} triangles: {} checkpoints of {:.2} MB ({:.0} bytes per triangle); the run waited {:.3} s per checkpoint (encoding), the writes took {:.3} s each (on their thread, with fsync)",
        c.written,
        c.bytes as f64 / 1e6,
        c.bytes as f64 / n_tri as f64,
        c.encode_time / c.written as f64,
        c.write_time / c.written as f64
    );
    let mut times = [Vec::new(), Vec::new()];
    for _ in 0..6 {
        for (k, every) in [Every::Off, Every::Steps(100)].into_iter().enumerate() {
            let s = Instant::now();
            run_outcome(&mut l, &with(every), &mut |_| {}).unwrap();
            times[k].push(s.elapsed().as_secs_f64());
        }
    }
    for t in &mut times {
        t.sort_by(f64::total_cmp);
    }
    let (off, on) = (times[0][3], times[1][3]);
    println!(
        "{STEPS} steps, median of 6 alternated runs: {off:.3} s without checkpoints, {on:.3} s with one every 100 steps ({:+.1} %); per checkpoint {:.3} s",
        100.0 * (on / off - 1.0),
        (on - off) / 4.0
    );
    let _ = std::fs::remove_dir_all(&dir);
}

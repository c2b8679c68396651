//! Serial-parallel parity of a whole run: the bar-pulse scene run in a 1-thread and a 2-thread
//! rayon pool gives identical positions, velocities, forces and stresses, bit for bit (the
//! mesh crate's kernel gathers element forces in a fixed order; the solver adds nothing that
//! depends on the thread count).

use crate::common;

#[test]
fn one_and_two_threads_give_bit_identical_results() {
    let mut frames = Vec::new();
    for threads in [1, 2] {
        let scene = common::edited_example("bar-pulse.json", &format!("parity{threads}"), |v| {
            v["output"]["frames"] = 0.into();
            v["duration"] = 1e-4.into();
            v["damping"] = serde_json::json!({"viscosity_ratio": 0.1, "mass_proportional": 10.0});
        });
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (o, _) = pool.install(|| common::run(&scene));
        assert_eq!(o.summary.threads, threads);
        frames.push(o.last_frame);
    }
    let (a, b) = (&frames[0], &frames[1]);
    assert!(a.points.iter().any(|p| p[0] != 0.0));
    assert_eq!(a.points, b.points);
    assert_eq!(a.velocity, b.velocity);
    assert_eq!(a.force, b.force);
    assert_eq!(a.stress, b.stress);
    fdem_figures::record(48, "equal");
}

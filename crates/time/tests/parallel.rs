//! Serial and parallel runs agree bit for bit for every scheme.

use fdem_time::kernels::PAR_MIN_DOFS;
use fdem_time::systems::LinearChain;
use fdem_time::{SchemeKind, State};

fn run(kind: SchemeKind, threads: usize) -> State {
    let n = PAR_MIN_DOFS + 1001;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut sys = LinearChain::new(n, 1.0).with_ends(0.0, 0.01);
        let x: Vec<f64> = (0..n).map(|i| 1e-3 * (i as f64 * 0.01).sin()).collect();
        let v: Vec<f64> = (0..n).map(|i| 1e-3 * (i as f64 * 0.003).cos()).collect();
        let mut st = State::new(0.0, x, v);
        let mut s = kind.build(n);
        for _ in 0..4 {
            s.step(&mut sys, &mut st, 0.3);
        }
        st
    })
}

#[test]
fn one_and_two_threads_give_identical_states_for_every_scheme() {
    for kind in SchemeKind::ALL {
        let a = run(kind, 1);
        let b = run(kind, 2);
        let same = |p: &[f64], q: &[f64]| p.iter().zip(q).all(|(p, q)| p.to_bits() == q.to_bits());
        assert!(
            same(&a.x, &b.x) && same(&a.v, &b.v),
            "{kind}: serial and parallel differ"
        );
        assert!(a.x.iter().all(|x| x.is_finite()));
    }
}

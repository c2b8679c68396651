//! What the accuracy indicators cost against a run: the indicators the problem decides at
//! load (`fdem_solver::problem::accuracy::predict`: process zone and joint compliance over
//! every joint, the mesh's angles and the frequency bound of every triangle, the units) on the
//! fracturing Brazilian disc (864 triangles, 1260 joints) and the wing-crack block, against
//! one step of the disc's run (the run's own indicators are a few sums over its summary).
//! Prints the share of the disc's whole run (50 996 steps) the indicators take.

use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use fdem_solver::driver;
use fdem_solver::problem::accuracy::predict;

fn bench(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for name in ["brazilian-disc-fracture", "wing-crack"] {
        let l = driver::load(&root.join(format!("examples/{name}.json"))).unwrap();
        let mut g = c.benchmark_group(format!("accuracy/{name}"));
        g.bench_function("predict", |b| {
            b.iter(|| predict(&l.scene, &l.model, &l.elements, &l.fracturing))
        });
        g.finish();
        let t = std::time::Instant::now();
        let n = 20;
        for _ in 0..n {
            std::hint::black_box(predict(&l.scene, &l.model, &l.elements, &l.fracturing));
        }
        let each = t.elapsed().as_secs_f64() / n as f64;
        eprintln!(
            "{name}: the indicators at load take {each:.3e} s, {} triangles, {} joints, {} steps",
            l.model.triangles.len(),
            l.fracturing.n_joints(),
            l.n_steps
        );
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);

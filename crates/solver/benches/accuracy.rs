//! What the accuracy indicators cost against a run: the indicators the problem decides at
//! load (`fdem_solver::problem::accuracy::predict`: process zone and joint compliance over
//! every joint, the mesh's angles and the frequency bound of every triangle, the units) on the
//! fracturing Brazilian disc (864 triangles, 1260 joints) and the wing-crack block, against
//! one step of the disc's run (the run's own indicators are a few sums over its summary).
//! Prints the share of the disc's whole run (50 996 steps) the indicators take. And the
//! result block's read-back at the end of a run (`fdem_solver::run::result::read`) on a run
//! folder the size of the disc's: `walls.csv` of 1020 rows, `fractures.csv` of 28.

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
        if name == "brazilian-disc-fracture" {
            result_read(c, &l.model);
        }
    }
}

/// The result block's read-back on a folder the size of the disc's run.
fn result_read(c: &mut Criterion, model: &fdem_solver::problem::model::Model) {
    let dir = std::env::temp_dir().join(format!("fdem-bench-result-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut walls = String::from(
        "time,u_x[top],u_y[top],force_x[top],force_y[top],u_x[bottom],u_y[bottom],force_x[bottom],force_y[bottom]\n",
    );
    for i in 0..1020 {
        let (u, f) = (
            1e-7 * i as f64,
            2.3e3 * (std::f64::consts::PI * i as f64 / 1020.0).sin(),
        );
        walls += &format!(
            "{:.9e},0,{:.9e},0,{:.9e},0,{:.9e},0,{:.9e}\n",
            1e-6 * i as f64,
            -u,
            -f,
            u,
            f
        );
    }
    std::fs::write(dir.join("walls.csv"), walls).unwrap();
    let mut fr = String::from("time,x,y,mode,mode_mix,energy_released,joint\n");
    for j in 0..28 {
        fr += &format!(
            "1.5e-3,{:.9e},{:.9e},I,0.0160,1.0e-3,{j}\n",
            1e-4 * j as f64,
            1e-3 * j as f64
        );
    }
    std::fs::write(dir.join("fractures.csv"), fr).unwrap();
    c.bench_function("accuracy/result-block-read", |b| {
        b.iter(|| fdem_solver::run::result::read(&dir, model).unwrap())
    });
    std::fs::remove_dir_all(&dir).unwrap();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);

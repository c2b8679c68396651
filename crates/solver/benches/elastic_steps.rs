//! Triangle-steps per second of a whole elastic scene with central difference, output off:
//! a 708 x 708 grid of squares cut into 1 002 528 triangles (plane strain, E = 10 GPa), bottom
//! fixed in y, left in x, a pressure on the top. Runs the solver's own dynamic loop
//! (`driver::run_outcome`: composition, integrator, load-work bookkeeping, stability checks)
//! for 20 steps per iteration, on 1 and 2 threads, and prints the per-stage timers of one run.

use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fdem_solver::Scene;
use fdem_solver::driver::{Problem, RunOptions, run_outcome, stable_step};
use fdem_solver::problem::model::MeshInput;
use fdem_solver::problem::{mesh_adapter, model};

const N: usize = 708;
const STEPS: u64 = 20;

fn scene_text() -> String {
    r#"{
      "bodies": [{"mesh": "grid", "materials": {"body": {"young": 10e9, "poisson": 0.25, "density": 2700, "plane": "strain"}}}],
      "boundary_conditions": [
        {"fixed": {"group": "bottom", "y": true}},
        {"fixed": {"group": "left", "x": true}},
        {"pressure": {"group": "top", "value": 1e6}}
      ],
      "duration": 1.0,
      "output": {"frames": 0}
    }"#
    .into()
}

fn grid() -> MeshInput {
    let mut m = MeshInput::default();
    for j in 0..=N {
        for i in 0..=N {
            m.nodes.push([i as f64 / N as f64, j as f64 / N as f64]);
        }
    }
    let id = |i: usize, j: usize| (j * (N + 1) + i) as u32;
    for j in 0..N {
        for i in 0..N {
            m.triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            m.triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    m.triangle_group = vec!["body".into(); m.triangles.len()];
    m.node_groups
        .insert("bottom".into(), (0..=N).map(|i| id(i, 0)).collect());
    m.node_groups
        .insert("left".into(), (0..=N).map(|j| id(0, j)).collect());
    m.edge_groups.insert(
        "top".into(),
        (0..N).map(|i| [id(i + 1, N), id(i, N)]).collect(),
    );
    m
}

fn loaded() -> Problem {
    let file = Path::new("bench.json");
    let scene = Scene::from_json(&scene_text(), file).unwrap();
    let mesh = grid();
    let names = fdem_solver::input::resolve::MeshNames::of_input(&mesh, "grid");
    let refs = fdem_solver::input::resolve::resolve(&scene, file, &[names]).unwrap();
    let model = model::build(&scene, file, &[mesh], &refs).unwrap();
    let elements = mesh_adapter::elements(&model, 0.0).unwrap();
    let scheme = fdem_time::SchemeKind::CentralDifference;
    let omega_max = elements.max_frequency_bound(&model.x0);
    let dt_limit = stable_step(scheme, omega_max, 0.0);
    Problem {
        file: file.into(),
        scene,
        meshes: Vec::new(),
        model,
        elements,
        scheme,
        z_high: 0.0,
        dt_limit,
        dt: 0.5 * dt_limit,
        n_steps: STEPS,
        load_s: 0.0,
        fracturing: Default::default(),
        initial_joint_state: None,
        frequency: fdem_solver::problem::stable_step::FrequencyTerms {
            elements: omega_max,
            ..Default::default()
        },
        warnings: Vec::new(),
        fluid: None,
        accuracy: Vec::new(),
    }
}

fn bench(c: &mut Criterion) {
    let mut l = loaded();
    let n_tri = l.elements.len();
    let out = std::env::temp_dir().join(format!("fdem-bench-{}", std::process::id()));
    let opts = RunOptions {
        out_dir: out.clone(),
        raw: false,
        ..Default::default()
    };
    let mut group = c.benchmark_group("elastic_scene_1M_central_difference");
    group.throughput(Throughput::Elements(n_tri as u64 * STEPS));
    group.sample_size(10);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let o = pool.install(|| run_outcome(&mut l, &opts, &mut |_| {}).unwrap());
        let t = o.summary.timers;
        eprintln!(
            "{threads} thread(s): {:.3e} triangle-steps/s; per step: internal forces {:.2} ms, loads {:.3} ms, integration {:.2} ms",
            o.summary.triangle_steps_per_second,
            1e3 * t.internal_forces / STEPS as f64,
            1e3 * t.external_loads / STEPS as f64,
            1e3 * t.integration / STEPS as f64
        );
        group.bench_function(format!("threads{threads}"), |b| {
            b.iter(|| pool.install(|| run_outcome(&mut l, &opts, &mut |_| {}).unwrap()))
        });
    }
    group.finish();
    let _ = std::fs::remove_dir_all(&out);
}

criterion_group!(benches, bench);
criterion_main!(benches);

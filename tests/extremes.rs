//! The solver at the extremes of what a user may ask of it (issue 7, elastic part): each scheme
//! just below and just above its predicted stable step, a stiffness contrast of 10^6, a body
//! spinning through many turns, near-degenerate triangles (aspect ratio 1000), the same scene
//! in mm-N-MPa and m-N-Pa, and a long run of a free elastic body. Every test asserts a number
//! with the tolerance stated beside it; none may see a NaN in any output.
//!
//! Predicted stable step: `h_limit = (h omega)_scheme / omega_max` (driver::stable_step), with
//! `omega_max` the mesh crate's element frequency bound (an upper bound of the highest mode,
//! so the prediction is conservative).

mod common;

use std::path::{Path, PathBuf};

use fdem_solver::RunError;
use fdem_solver::driver::{self, Loaded, Outcome, RunOptions};
use fdem_time::SchemeKind;
use serde_json::json;

/// A structured mesh of the rectangle [0, lx] x [0, ly], nx x ny cells, each split into two
/// CCW triangles. Surface groups: "a" (centroid x < split) and "b" (the rest; absent without a
/// split). Edge groups: left, right, bottom, top.
fn rect_mesh(
    dir: &Path,
    name: &str,
    lx: f64,
    ly: f64,
    nx: usize,
    ny: usize,
    split: f64,
) -> PathBuf {
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut nodes = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push([lx * i as f64 / nx as f64, ly * j as f64 / ny as f64]);
        }
    }
    let (mut tris, mut a, mut b) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..ny {
        for i in 0..nx {
            let (n00, n10, n11, n01) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            let xc = lx * (i as f64 + 0.5) / nx as f64;
            for t in [[n00, n10, n11], [n00, n11, n01]] {
                if xc < split {
                    a.push(tris.len())
                } else {
                    b.push(tris.len())
                }
                tris.push(t);
            }
        }
    }
    let edges = |pts: Vec<u32>| -> Vec<[u32; 2]> { pts.windows(2).map(|w| [w[0], w[1]]).collect() };
    let mut groups = vec![json!({"name": "a", "dim": 2, "triangles": a})];
    if !b.is_empty() {
        groups.push(json!({"name": "b", "dim": 2, "triangles": b}));
    }
    groups.push(
        json!({"name": "left", "dim": 1, "edges": edges((0..=ny).map(|j| id(0, j)).collect())}),
    );
    groups.push(
        json!({"name": "right", "dim": 1, "edges": edges((0..=ny).map(|j| id(nx, j)).collect())}),
    );
    groups.push(
        json!({"name": "bottom", "dim": 1, "edges": edges((0..=nx).map(|i| id(i, 0)).collect())}),
    );
    groups.push(
        json!({"name": "top", "dim": 1, "edges": edges((0..=nx).map(|i| id(i, ny)).collect())}),
    );
    let p = dir.join(name);
    let m = json!({"nodes": nodes, "triangles": tris, "groups": groups});
    std::fs::write(&p, serde_json::to_string(&m).unwrap()).unwrap();
    p
}

/// Writes a scene into `dir` and loads it.
fn load(dir: &Path, scene: serde_json::Value) -> Loaded {
    let p = dir.join("scene.json");
    std::fs::write(&p, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    driver::load(&p).unwrap_or_else(|e| panic!("{e}"))
}

fn run(l: &mut Loaded, dir: &Path) -> Result<Outcome, RunError> {
    driver::run_outcome(
        l,
        &RunOptions {
            out_dir: dir.join("out"),
            raw: false,
        },
        &mut |_| {},
    )
}

fn kinetic(l: &Loaded) -> f64 {
    l.model
        .mass
        .iter()
        .zip(&l.model.v0)
        .map(|(m, v)| 0.5 * m * (v[0] * v[0] + v[1] * v[1]))
        .sum()
}

/// A deterministic pseudo-random number in [-1, 1).
fn rnd(s: &mut u64) -> f64 {
    *s = s
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

fn no_nan(o: &Outcome) -> bool {
    let f = &o.last_frame;
    f.points
        .iter()
        .chain(&f.velocity)
        .chain(&f.displacement)
        .all(|p| p[0].is_finite() && p[1].is_finite())
        && f.stress.iter().all(|s| s.iter().all(|v| v.is_finite()))
}

/// The shipped bar mesh (1005 nodes, 1600 triangles), free, with a pseudo-random initial
/// velocity that excites every mode, the highest included. At 0.99 of the predicted limit every
/// scheme stays bounded: K + U after 2000 steps below 2 E0 (an unstable mode would grow by
/// orders of magnitude; near the limit K + U at the step differs from the conserved discrete
/// energy by O((h omega)^2), measured up to 1.19 for central difference), and above 0.5 E0
/// for the symplectic schemes (the Gear schemes may dissipate). At 1.01 each
/// scheme is either still bounded (the bound is conservative) or stopped by the solver's check
/// with an `Unstable` error naming the step and the fix; never a NaN in an output.
#[test]
fn each_scheme_at_099_and_101_of_its_predicted_stable_step() {
    let dir = common::temp_dir("extremes-limit");
    for k in SchemeKind::ALL {
        for f in [0.99, 1.01] {
            let mut l = load(
                &dir,
                json!({
                    "analysis": "dynamic",
                    "bodies": [{ "mesh": common::root().join("examples/meshes/bar.json"),
                        "materials": { "bar": { "young": 200e9, "poisson": 0.25, "density": 8000.0 } },
                        "thickness": 0.02 }],
                    "integrator": { "scheme": k.name() },
                    "duration": 1e-3, "output": { "frames": 0 }
                }),
            );
            let mut s = 7u64;
            for v in &mut l.model.v0 {
                *v = [rnd(&mut s), rnd(&mut s)];
            }
            let e0 = kinetic(&l);
            l.dt = f * l.dt_limit;
            l.n_steps = 2000;
            match run(&mut l, &dir) {
                Ok(o) => {
                    assert!(no_nan(&o), "{} at {f}: NaN in output", k.name());
                    let e = o.summary.energy.kinetic + o.summary.energy.strain;
                    eprintln!(
                        "{:<20} h/h_pred = {f}: bounded, E/E0 = {:.6}",
                        k.name(),
                        e / e0
                    );
                    assert!(
                        e / e0 < 2.0,
                        "{} at {f} of the limit: E/E0 = {}",
                        k.name(),
                        e / e0
                    );
                    if k.is_symplectic() && f < 1.0 {
                        // symplectic: no loss beyond the O((h omega)^2) offset
                        assert!(e / e0 > 0.5, "{} at {f}: E/E0 = {}", k.name(), e / e0);
                    }
                }
                Err(e) => {
                    let msg = e.to_string();
                    eprintln!("{:<20} h/h_pred = {f}: reported unstable: {msg}", k.name());
                    assert!(
                        f > 1.0,
                        "{} unstable at {f} of its predicted limit: {msg}",
                        k.name()
                    );
                    assert!(
                        matches!(e, RunError::Unstable { step, .. } if step > 0)
                            && msg.contains("fix: lower the time step"),
                        "{}: {msg}",
                        k.name()
                    );
                }
            }
        }
    }
}

/// Two materials in series (E_a = 10^6 E_b, nu = 0), clamped at x = 0, traction p at x = L:
/// end displacement `p (L_a/E_a + L_b/E_b)`, stress p in every triangle (CST is exact for
/// uniform stress). Asserted to 1e-8 relative. The stable step is set by the stiff material:
/// its ratio to the soft-only mesh is sqrt(E_b/E_a) = 1e-3 (same density and mesh), to 1e-12.
#[test]
fn stiffness_contrast_of_1e6_in_series() {
    let dir = common::temp_dir("extremes-contrast");
    let mesh = rect_mesh(&dir, "bar2.json", 2.0, 0.1, 40, 2, 1.0);
    let (ea, eb, p) = (1e12, 1e6, 1e3);
    let scene = |analysis: &str, ea: f64| {
        json!({
            "analysis": analysis,
            "bodies": [{ "mesh": mesh, "materials": {
                "a": { "young": ea, "poisson": 0.0, "density": 1000.0 },
                "b": { "young": eb, "poisson": 0.0, "density": 1000.0 } } }],
            "boundary_conditions": [
                { "fixed": { "group": "left", "x": true, "y": true } },
                { "traction": { "group": "right", "value": [p, 0.0] } } ],
            "duration": 1.0, "output": { "frames": 1 }
        })
    };
    let mut l = load(&dir, scene("static", ea));
    let o = run(&mut l, &dir).unwrap_or_else(|e| panic!("{e}"));
    let f = &o.last_frame;
    let u_end = f
        .displacement
        .iter()
        .zip(&f.points)
        .filter(|(u, x)| (x[0] - u[0] - 2.0).abs() < 1e-12)
        .map(|(u, _)| u[0])
        .sum::<f64>()
        / 3.0;
    let exact = p * (1.0 / ea + 1.0 / eb);
    let err = (u_end / exact - 1.0).abs();
    let s_err = f
        .stress
        .iter()
        .map(|s| (s[0] / p - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!("contrast 1e6: end displacement error {err:.2e}, max stress error {s_err:.2e}");
    assert!(err < 1e-8, "end displacement {u_end} vs {exact}");
    assert!(s_err < 1e-8, "stress error {s_err}");
    let stiff = load(&dir, scene("dynamic", ea)).dt_limit;
    let soft = load(&dir, scene("dynamic", eb)).dt_limit;
    let r = stiff / soft;
    eprintln!("contrast 1e6: h_limit ratio {r:.12e} (sqrt(E_b/E_a) = 1e-3)");
    assert!((r / 1e-3 - 1.0).abs() < 1e-12, "ratio {r}");
}

/// A free 1 x 1 square (E = 1e6 Pa, rho = 1000, c ~ 32 m/s) spinning rigidly at omega with
/// omega r_max = 0.01 c through 10 turns (central difference and Forest-Ruth, 0.5 of the limit).
/// The finite-strain CST gives no stress for a rigid rotation: only the physical centrifugal
/// stress, of scale rho omega^2 r^2 = E (omega r)^2 / c^2 (1e-4 E here), remains. Asserted: the
/// largest |stress| stays below 2 rho omega^2 r_max^2 (a small-strain element would give ~E,
/// 10^4 times more), and kinetic + strain energy within 1e-4 of the initial value.
#[test]
fn spinning_body_through_ten_turns_has_no_spurious_stress() {
    let dir = common::temp_dir("extremes-spin");
    let mesh = rect_mesh(&dir, "square.json", 1.0, 1.0, 8, 8, 2.0);
    let (e, rho): (f64, f64) = (1e6, 1000.0);
    let c = (e / rho).sqrt();
    let r_max = 0.5f64.sqrt();
    let omega = 0.01 * c / r_max;
    let turns = 10.0;
    for k in [SchemeKind::CentralDifference, SchemeKind::ForestRuth] {
        let mut l = load(
            &dir,
            json!({
                "analysis": "dynamic",
                "bodies": [{ "mesh": mesh, "materials": { "a": { "young": e, "poisson": 0.25, "density": rho } } }],
                "integrator": { "scheme": k.name(), "safety": 0.5 },
                "duration": turns * 2.0 * std::f64::consts::PI / omega, "output": { "frames": 1 }
            }),
        );
        for (v, x) in l.model.v0.iter_mut().zip(&l.model.x0) {
            *v = [-omega * (x[1] - 0.5), omega * (x[0] - 0.5)];
        }
        let e0 = kinetic(&l);
        let o = run(&mut l, &dir).unwrap_or_else(|e| panic!("{e}"));
        assert!(no_nan(&o));
        let smax = o
            .last_frame
            .stress
            .iter()
            .flat_map(|s| s.iter().map(|v| v.abs()))
            .fold(0.0, f64::max);
        let scale = rho * omega * omega * r_max * r_max;
        let en = o.summary.energy.kinetic + o.summary.energy.strain;
        eprintln!(
            "{:<20} spin {turns} turns, {} steps: max |stress| / (rho omega^2 r^2) = {:.3}, E/E0 - 1 = {:.2e}",
            k.name(),
            o.summary.steps,
            smax / scale,
            en / e0 - 1.0
        );
        assert!(smax < 2.0 * scale, "max stress {smax} vs scale {scale}");
        assert!((en / e0 - 1.0).abs() < 1e-4, "energy {en} vs {e0}");
    }
}

/// Triangles of aspect ratio 1000 (cells 1 x 0.001): a patch test (traction p on x = 4, rollers
/// on x = 0 and y = 0, nu = 0.3) gives sxx = p, syy = sxy = 0 in every triangle and
/// u_x(L) = p L / E, to 1e-8 relative. The predicted stable step is set by the thin direction:
/// between 0.1 and 1 times dy / c_p (c_p the plane-stress P-wave speed), and central difference
/// at 0.99 of it stays bounded for 2000 steps (K + U within a factor 2 of E0, as above;
/// measured 1.26).
#[test]
fn near_degenerate_triangles_aspect_1000() {
    let dir = common::temp_dir("extremes-thin");
    let (lx, ly) = (4.0, 0.004);
    let mesh = rect_mesh(&dir, "thin.json", lx, ly, 4, 4, 10.0);
    let (e, nu, rho, p) = (1e9, 0.3, 2000.0, 1e6);
    let scene = |analysis: &str| {
        json!({
            "analysis": analysis,
            "bodies": [{ "mesh": mesh, "materials": { "a": { "young": e, "poisson": nu, "density": rho } } }],
            "boundary_conditions": [
                { "fixed": { "group": "left", "x": true } },
                { "fixed": { "group": "bottom", "y": true } },
                { "traction": { "group": "right", "value": [p, 0.0] } } ],
            "duration": 1.0, "output": { "frames": 1 }
        })
    };
    let mut l = load(&dir, scene("static"));
    let o = run(&mut l, &dir).unwrap_or_else(|e| panic!("{e}"));
    let f = &o.last_frame;
    let s_err = f
        .stress
        .iter()
        .map(|s| {
            (s[0] / p - 1.0)
                .abs()
                .max(s[1].abs() / p)
                .max(s[2].abs() / p)
        })
        .fold(0.0, f64::max);
    let u_err = f
        .displacement
        .iter()
        .zip(&f.points)
        .filter(|(u, x)| (x[0] - u[0] - lx).abs() < 1e-12)
        .map(|(u, _)| (u[0] / (p * lx / e) - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!("aspect 1000 patch: stress error {s_err:.2e}, end displacement error {u_err:.2e}");
    assert!(s_err < 1e-8 && u_err < 1e-8, "{s_err} {u_err}");
    let mut l = load(&dir, scene("dynamic"));
    let cp = (e / (rho * (1.0 - nu * nu))).sqrt();
    let r = l.dt_limit / (ly / 4.0 / cp);
    eprintln!(
        "aspect 1000: h_limit = {:.4e} s = {r:.4} dy/c_p",
        l.dt_limit
    );
    assert!(
        l.dt_limit.is_finite() && (0.1..1.0).contains(&r),
        "h_limit / (dy/c_p) = {r}"
    );
    l.dt = 0.99 * l.dt_limit;
    l.n_steps = 2000;
    l.scene.boundary_conditions.truncate(2);
    l.model.loads.clear();
    let mut s = 3u64;
    for v in &mut l.model.v0 {
        *v = [rnd(&mut s), rnd(&mut s)];
    }
    for (i, c) in l.model.constrained.iter().enumerate() {
        if *c {
            l.model.v0[i / 2][i % 2] = 0.0;
        }
    }
    let e0 = kinetic(&l);
    let o = run(&mut l, &dir).unwrap_or_else(|e| panic!("{e}"));
    let en = o.summary.energy.kinetic + o.summary.energy.strain;
    eprintln!(
        "aspect 1000: central difference at 0.99 h_limit, E/E0 = {:.4}",
        en / e0
    );
    assert!(
        no_nan(&o) && en / e0 < 2.0 && en / e0 > 0.5,
        "E/E0 = {}",
        en / e0
    );
}

/// A steel cantilever 10 m x 1 m (tip traction) in m-N-Pa-kg and in mm-N-MPa-t: the
/// displacements in mm are 1000 times those in m, statically and after 200 dynamic steps,
/// to 1e-10 relative (max over nodes, relative to the largest displacement). The load
/// (100 MPa) makes the displacement large enough (~3e-3 of the positions) that the rounding
/// of positions `x = X + u` (eps |X| / |u| per step) stays far below 1e-10; with 1 MPa
/// (u ~ 3e-6 |X|) it gave 4.4e-10 dynamically.
#[test]
fn same_scene_in_mm_n_mpa_and_m_n_pa() {
    let dir = common::temp_dir("extremes-units");
    let m_mesh = rect_mesh(&dir, "m.json", 10.0, 1.0, 40, 4, 100.0);
    let mm_mesh = rect_mesh(&dir, "mm.json", 10_000.0, 1000.0, 40, 4, 100_000.0);
    let scene = |analysis: &str, mesh: &Path, e: f64, rho: f64, t: f64, p: f64| {
        json!({
            "analysis": analysis,
            "bodies": [{ "mesh": mesh, "materials": { "a": { "young": e, "poisson": 0.3, "density": rho } },
                "thickness": t }],
            "boundary_conditions": [
                { "fixed": { "group": "left", "x": true, "y": true } },
                { "traction": { "group": "right", "value": [0.0, p] } } ],
            "integrator": { "time_step": 2e-6 },
            "duration": 4e-4, "output": { "frames": 1 }
        })
    };
    for analysis in ["static", "dynamic"] {
        let mut lm = load(&dir, scene(analysis, &m_mesh, 200e9, 7850.0, 0.1, -1e8));
        let om = run(&mut lm, &dir).unwrap_or_else(|e| panic!("{e}"));
        let mut lmm = load(
            &dir,
            scene(analysis, &mm_mesh, 200e3, 7.85e-9, 100.0, -100.0),
        );
        let omm = run(&mut lmm, &dir).unwrap_or_else(|e| panic!("{e}"));
        let (um, umm) = (&om.last_frame.displacement, &omm.last_frame.displacement);
        let scale = um
            .iter()
            .map(|u| u[0].abs().max(u[1].abs()))
            .fold(0.0, f64::max);
        let err = um
            .iter()
            .zip(umm)
            .map(|(a, b)| {
                (b[0] / 1000.0 - a[0])
                    .abs()
                    .max((b[1] / 1000.0 - a[1]).abs())
            })
            .fold(0.0, f64::max)
            / scale;
        eprintln!(
            "units {analysis}: max |u_mm/1000 - u_m| / max|u_m| = {err:.2e} (max u = {scale:.3e} m)"
        );
        assert!(scale > 0.0 && err < 1e-10, "{analysis}: {err}");
    }
}

/// A free elastic body (2 m x 0.5 m, 20 x 5 cells: 126 nodes, 252 DOFs) with a smooth initial
/// velocity field, 40 000 steps at 0.5 of the limit: 1.0e7 DOF-steps. For each symplectic
/// scheme, `K + U` sampled every 400 steps oscillates by O((h omega)^2) about E0 but does not
/// drift: the largest |E/E0 - 1| over the whole run is at most 2 times the largest over its
/// first tenth (a secular drift would make it ~10 times larger), and below 1e-2.
#[test]
fn long_run_of_a_free_body_has_bounded_energy_drift_for_symplectic_schemes() {
    let dir = common::temp_dir("extremes-long");
    let mesh = rect_mesh(&dir, "free.json", 2.0, 0.5, 20, 5, 10.0);
    for k in SchemeKind::ALL.into_iter().filter(|k| k.is_symplectic()) {
        let mut l = load(
            &dir,
            json!({
                "analysis": "dynamic",
                "bodies": [{ "mesh": mesh, "materials": { "a": { "young": 1e6, "poisson": 0.3, "density": 1000.0 } } }],
                "integrator": { "scheme": k.name(), "safety": 0.5 },
                "duration": 1.0, "output": { "frames": 0 },
                "histories": { "every": 400, "probes": ["energy"] }
            }),
        );
        for (v, x) in l.model.v0.iter_mut().zip(&l.model.x0) {
            let s = (std::f64::consts::PI * x[0]).sin();
            *v = [0.3 * (2.0 * x[1] - 0.5), s];
        }
        let e0 = kinetic(&l);
        l.dt = 0.5 * l.dt_limit;
        l.n_steps = 40_000;
        let dof_steps = 2 * l.model.n_nodes() as u64 * l.n_steps;
        let o = run(&mut l, &dir).unwrap_or_else(|e| panic!("{e}"));
        let (h, rows) = common::histories(&dir.join("out"));
        let kin = common::column(&h, &rows, "kinetic");
        let strain = common::column(&h, &rows, "strain");
        let dev: Vec<f64> = kin
            .iter()
            .zip(&strain)
            .map(|(k, u)| ((k + u) / e0 - 1.0).abs())
            .collect();
        let first = dev[..dev.len() / 10]
            .iter()
            .fold(0.0, |a: f64, b| a.max(*b));
        let all = dev.iter().fold(0.0, |a: f64, b| a.max(*b));
        eprintln!(
            "{:<20} {dof_steps} DOF-steps in {:.2} s: max |E/E0 - 1| first tenth {first:.2e}, whole run {all:.2e}",
            k.name(),
            o.summary.wall_time,
        );
        assert!(dof_steps >= 10_000_000 && no_nan(&o));
        assert!(
            all <= 2.0 * first && all < 1e-2,
            "{}: {first} {all}",
            k.name()
        );
    }
}

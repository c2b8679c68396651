//! Fracturing specimens end to end (docs/howto-fracturing-specimen.md), each run from its example
//! scene, and the joint output series (`joints.pvd`, `joints_NNNN.vtu`) of both.
//!
//! - Notched beam in three-point bending (examples/notched-beam-fracture.json, mesh
//!   meshes/notched-beam-coarse.msh): pre-peak stiffness against the static solver on the same
//!   mesh; the crack starts at the notch tip and runs up towards the loading pad; the peak
//!   against the net-section flexural estimate `P = 2 ft t (H - a)^2 / (3 S)`.
//! - Square block between rigid platens (examples/block-compression-fracture.json, mesh
//!   meshes/block-coarse.msh), frictionless and with friction 0.5 at the platens: elastic slope
//!   against `E A / H`; the friction case is stronger; shear fractures appear.

use crate::common;

use std::collections::HashMap;
use std::path::Path;

use fdem_solver::driver::Outcome;
use serde_json::Value;

/// A CSV file as column names and text fields.
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (head, rows)
}

/// Numeric column `name` of a CSV table.
fn col(head: &[String], rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let i = head
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    rows.iter().map(|r| r[i].parse().unwrap()).collect()
}

/// The `(time, file)` entries of a `.pvd` collection.
fn pvd(path: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| l.contains("<DataSet "))
        .map(|l| {
            let attr = |k: &str| {
                let s = &l[l.find(&format!("{k}=\"")).unwrap() + k.len() + 2..];
                s[..s.find('"').unwrap()].to_string()
            };
            (attr("timestep").parse().unwrap(), attr("file"))
        })
        .collect()
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().expect("a number (no NaN/null)"))
        .collect()
}

/// Checks the joint series of a fracturing run against the solver's raw dump, the
/// `.vtu` files (read back by `fdem_solver::output::vtu::read`) and fractures.csv; returns (joints, broken at the end).
fn check_joint_series(out: &Path, o: &Outcome) -> (usize, usize) {
    let n_joints = o.summary.stages["fracture"]["joints"].as_u64().unwrap() as usize;
    let frames = pvd(&out.join("results.pvd"));
    let joints = pvd(&out.join("joints.pvd"));
    // One joint file per frame, at the same times.
    assert_eq!(joints.len(), frames.len(), "joint frames vs frames");
    let mut prev_damage: Option<Vec<f64>> = None;
    let mut last = None;
    for ((t, jf), (tf, ff)) in joints.iter().zip(&frames) {
        assert_eq!(t, tf, "joint frame time");
        assert_eq!(jf.replace("joints_", "frame_"), *ff, "joint file name");
        let raw: Value = serde_json::from_str(
            &std::fs::read_to_string(out.join(ff.replace(".vtu", ".json"))).unwrap(),
        )
        .unwrap();
        let j = &raw["joints"];
        let damage = f64s(&j["damage"]);
        let tof = f64s(&j["time_of_failure"]);
        let broken: Vec<i64> = j["broken"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| b.as_i64().unwrap())
            .collect();
        // Counts: one line (two points) per joint.
        assert_eq!(damage.len(), n_joints);
        assert_eq!(j["points"].as_array().unwrap().len(), 2 * n_joints);
        for k in 0..n_joints {
            assert!((0.0..=1.0).contains(&damage[k]), "damage {}", damage[k]);
            match broken[k] {
                1 => {
                    assert_eq!(damage[k], 1.0);
                    assert!(tof[k] >= 0.0 && tof[k] <= *t, "failure {} at {t}", tof[k]);
                }
                0 => assert_eq!(tof[k], -1.0),
                b => panic!("broken = {b}"),
            }
        }
        // Damage never heals.
        if let Some(p) = &prev_damage {
            assert!(damage.iter().zip(p).all(|(a, b)| a >= b), "damage healed");
        }
        prev_damage = Some(damage.clone());
        // The .vtu: line cells, the same damage (read back by the writer's reader).
        let arrays = fdem_solver::output::vtu::read(&std::fs::read(out.join(jf)).unwrap()).unwrap();
        let types = arrays.iter().find(|a| a.name == "types").unwrap();
        assert_eq!(types.bytes.len(), n_joints);
        assert!(
            types
                .bytes
                .iter()
                .all(|c| *c == fdem_solver::output::vtu::VTK_LINE)
        );
        assert_eq!(arrays[0].name, "damage");
        assert_eq!(arrays[0].to_f64(), damage);
        last = Some((broken, tof));
    }
    // The last frame (end of the run) against fractures.csv: the same joints, same times.
    let (broken, tof) = last.unwrap();
    let (h, rows) = csv(&out.join("fractures.csv"));
    let ids = col(&h, &rows, "joint");
    let times = col(&h, &rows, "time");
    let ev: HashMap<usize, f64> = ids.iter().map(|i| *i as usize).zip(times).collect();
    let n_broken = broken.iter().filter(|b| **b == 1).count();
    assert_eq!(n_broken, ev.len(), "broken joints vs fractures.csv rows");
    for (k, b) in broken.iter().enumerate() {
        if *b == 1 {
            let te = ev
                .get(&k)
                .unwrap_or_else(|| panic!("joint {k} not in fractures.csv"));
            // fractures.csv prints 10 significant digits.
            assert!((tof[k] - te).abs() <= 1e-9 * te, "{} vs {te}", tof[k]);
        }
    }
    (n_joints, n_broken)
}

/// The notched beam's load-point curve from `histories.csv` (load and displacement made
/// positive), the row of its peak and its pre-peak (secant) stiffness: the mean `P / u` over
/// the rows with 15-35 % of the peak load, after the loading ramp's first micrometre.
pub struct NotchedCurve {
    pub p: Vec<f64>,
    pub u: Vec<f64>,
    pub ip: usize,
    pub k: f64,
    pub rows: usize,
}

/// [`NotchedCurve`] of the run folder `out`.
pub fn notched_curve(out: &std::path::Path) -> NotchedCurve {
    let (hh, rows) = common::histories(out);
    let neg = |name: &str| -> Vec<f64> {
        common::column(&hh, &rows, name)
            .iter()
            .map(|v| -v)
            .collect()
    };
    let (p, u) = (neg("reaction_y[load]"), neg("u_y[load]"));
    let ip = (0..p.len()).max_by(|i, j| p[*i].total_cmp(&p[*j])).unwrap();
    let sec: Vec<f64> = (0..ip)
        .filter(|&i| p[i] > 0.15 * p[ip] && p[i] < 0.35 * p[ip] && u[i] > 1e-6)
        .map(|i| p[i] / u[i])
        .collect();
    let k = sec.iter().sum::<f64>() / sec.len() as f64;
    NotchedCurve {
        p,
        u,
        ip,
        k,
        rows: sec.len(),
    }
}

#[test]
fn notched_beam_cracks_from_the_notch_tip_towards_the_load_with_beam_stiffness_and_peak() {
    let (ft, t, h, a, s): (f64, f64, f64, f64, f64) = (3e6, 0.05, 0.05, 0.01, 0.18);
    // Static reference: the same mesh, not exploded, the loading pad pushed down 20 um.
    let stat = common::edited_example("notched-beam-fracture.json", "nb-static", |v| {
        let o = v.as_object_mut().unwrap();
        o.remove("fracture");
        o.insert("analysis".into(), "static".into());
        o.insert("duration".into(), 1e-3.into());
        v["boundary_conditions"][2]["velocity"]["ramp"] = 0.0.into();
    });
    let (_, sout) = common::run(&stat);
    let (sh, srows) = common::histories(&sout);
    let k_static = (common::column(&sh, &srows, "reaction_y[load]")[0]
        / common::column(&sh, &srows, "u_y[load]")[0])
        .abs();

    let scene = common::edited_example("notched-beam-fracture.json", "nb-fracture", |_| {});
    let (o, out) = common::run_raw(&scene);
    let NotchedCurve {
        p,
        u,
        ip,
        k: k_dyn,
        rows: sec_rows,
    } = notched_curve(&out);
    let peak = p[ip];
    let p_ns = 2.0 * ft * t * (h - a).powi(2) / (3.0 * s);
    // The crack.
    let (eh, ev) = csv(&out.join("fractures.csv"));
    let ex = col(&eh, &ev, "x");
    let ey = col(&eh, &ev, "y");
    let et = col(&eh, &ev, "time");
    let first = (0..et.len())
        .min_by(|i, j| et[*i].total_cmp(&et[*j]))
        .expect("no joint broke");
    let y_max = ey.iter().cloned().fold(f64::MIN, f64::max);
    let x_max = ex.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let e = &o.summary.energy;
    let work = e.supplied;
    eprintln!(
        "notched beam: K static {k_static:.4e} N/m, K dynamic (secant, 15-35 % of peak, {} rows) \
         {k_dyn:.4e} N/m ({:+.2} %); peak {peak:.1} N at u = {:.3e} m, net-section estimate \
         {p_ns:.1} N, ratio {:.3}; final load {:.1} N; {} joints broken, first at ({:.2}, {:.2}) mm \
         t = {:.4e} s, highest y {:.2} mm, max |x| {:.2} mm; energy residual {:.3e} of work {work:.4e} J",
        sec_rows,
        100.0 * (k_dyn / k_static - 1.0),
        u[ip],
        peak / p_ns,
        p.last().unwrap(),
        ev.len(),
        1e3 * ex[first],
        1e3 * ey[first],
        et[first],
        1e3 * y_max,
        1e3 * x_max,
        e.error / work,
    );
    // Stiffness within 5 % of the static solver on the same (unexploded) mesh: the joints'
    // initial compliance (p = 10 E) and the loading's inertia make the difference.
    assert!(
        (k_dyn / k_static - 1.0).abs() < 0.05,
        "stiffness {k_dyn} vs static {k_static}"
    );
    // Peak between 1.2 and 2.0 times the net-section estimate (docs: the cohesive zone at a
    // ligament of 0.6 l_ch carries more than the elastic net-section stress; the rigid-plastic
    // limit is 3 times it).
    assert!(
        (1.2..2.0).contains(&(peak / p_ns)),
        "peak {peak} N vs net-section {p_ns} N"
    );
    // Softening: the load has fallen below half the peak by the end.
    assert!(*p.last().unwrap() < 0.5 * peak, "no softening");
    // The crack starts at the notch tip: less than 4 mm above it, |x| < 3 mm (one or two
    // 2 mm elements) ...
    assert!(
        ey[first] > a && ey[first] < a + 0.004 && ex[first].abs() < 0.003,
        "first break at ({}, {})",
        ex[first],
        ey[first]
    );
    // ... and runs up towards the loading pad, through more than 1/3 of the ligament, inside
    // a band of +-5 % of the span around mid-span.
    assert!(y_max > a + (h - a) / 3.0, "crack reached y = {y_max}");
    assert!(x_max < 0.05 * s, "broken joint at |x| = {x_max}");
    // Energy balance (support work = strain + kinetic + joints) within 1 %.
    assert!((e.error / work).abs() < 0.01);
    let (nj, nb) = check_joint_series(&out, &o);
    assert_eq!(nb, ev.len());
    assert!(nj > 900, "{nj} joints");
    fdem_figures::record(45, format!("{:+.1} %", 100.0 * (k_dyn / k_static - 1.0)));
}

/// Runs the block example with friction `mu` at both platens: (peak load [N], elastic slope
/// [N/m], broken joints, mode II + mixed breaks, energy residual / work).
fn block(mu: f64, tag: &str) -> (f64, f64, usize, usize, f64, f64) {
    let scene = common::edited_example("block-compression-fracture.json", tag, |v| {
        for w in v["contact"]["walls"].as_array_mut().unwrap() {
            w["law"]["friction"] = mu.into();
        }
    });
    let (o, out) = common::run_raw(&scene);
    let (h, rows) = csv(&out.join("walls.csv"));
    let p: Vec<f64> = col(&h, &rows, "force_y[top]").iter().map(|v| -v).collect();
    let ut = col(&h, &rows, "u_y[top]");
    let ub = col(&h, &rows, "u_y[bottom]");
    let closure: Vec<f64> = ut.iter().zip(&ub).map(|(t, b)| b - t).collect();
    let ip = (0..p.len()).max_by(|i, j| p[*i].total_cmp(&p[*j])).unwrap();
    // Elastic slope: least squares over 20-60 % of the peak.
    let (mut sx, mut sy, mut sxx, mut sxy, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..ip {
        if p[i] > 0.2 * p[ip] && p[i] < 0.6 * p[ip] {
            let (x, y) = (closure[i], p[i]);
            sx += x;
            sy += y;
            sxx += x * x;
            sxy += x * y;
            n += 1.0;
        }
    }
    let slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let (eh, ev) = csv(&out.join("fractures.csv"));
    let mi = eh.iter().position(|c| c == "mode").unwrap();
    let shear = ev.iter().filter(|r| r[mi] != "I").count();
    let e = &o.summary.energy;
    let work = e.supplied;
    let (_, nb) = check_joint_series(&out, &o);
    // The run's result block, from its own files: this peak and these broken joints; a
    // rectangle whose loading-branch modulus is E with the joints' compliance in series:
    // about E / (1 + E/p) with one joint crossed per element row (an unstructured mesh
    // crosses somewhat more, and the platens' contact adds its own), so within 2 %.
    let res = o.summary.result.as_ref().expect("a result block");
    assert_eq!(res.failed, Some(true));
    assert_eq!(res.peak_load, Some(p[ip]));
    assert_eq!(res.broken_joints, nb);
    assert_eq!(res.broken_by_mode.ii + res.broken_by_mode.mixed, shear);
    let sp = res.specimen.as_ref().expect("a specimen between platens");
    assert_eq!(sp.shape, "rectangle");
    assert!((sp.peak_stress.unwrap() - p[ip] / (0.05 * 0.05)).abs() < 1e-6 * p[ip]);
    // the block's slope over 10-50 % of the peak, the test's over 20-60 %: one linear branch
    let stiffness = res.stiffness.unwrap();
    assert!(
        (stiffness / slope - 1.0).abs() < 0.01,
        "{stiffness} against {slope}"
    );
    let e_joints = 30e9 / (1.0 + 1.0 / 100.0);
    let modulus = sp.modulus.unwrap();
    eprintln!(
        "block mu = {mu}: result modulus {modulus:.4e} Pa = {:.4} E/(1+E/p)",
        modulus / e_joints
    );
    assert!((modulus / e_joints - 1.0).abs() < 0.02, "modulus {modulus}");
    if mu == 0.0 {
        fdem_figures::record_part(
            145,
            2,
            format!(
                "block (mu = 0): modulus {:.2} GPa, {:+.1} % of E/(1+E/p)",
                1e-9 * modulus,
                100.0 * (modulus / e_joints - 1.0)
            ),
        );
    }
    eprintln!(
        "block mu = {mu}: peak {:.1} N at closure {:.3e} m, slope {slope:.4e} N/m, {nb} broken \
         ({shear} mode II or mixed), energy residual {:.3e} of work {work:.4e} J, stages {}",
        p[ip],
        closure[ip],
        e.error / work,
        o.summary.stages
    );
    eprintln!(
        "block mu = {mu}: final load / peak {:.3}",
        p[p.len() - 1] / p[ip]
    );
    (
        p[ip],
        slope,
        nb,
        shear,
        e.error / work,
        p[p.len() - 1] / p[ip],
    )
}

#[test]
fn block_between_platens_has_the_elastic_slope_and_friction_raises_its_peak() {
    // Square block 50 x 50 mm, t = 50 mm, E = 30 GPa, plane stress: E A / H = E t.
    let k = 30e9 * 0.05 * 0.05 / 0.05;
    // The two runs side by side (each is serial in its own thread; rayon shares the cores).
    let ((p0, k0, b0, s0, r0, d0), (p5, k5, b5, s5, r5, d5)) = std::thread::scope(|sc| {
        let h0 = sc.spawn(|| block(0.0, "block-mu0"));
        let h5 = sc.spawn(|| block(0.5, "block-mu05"));
        (h0.join().unwrap(), h5.join().unwrap())
    });
    eprintln!(
        "block: E A / H = {k:.4e}; slope/EAH {:.4} (mu 0), {:.4} (mu 0.5); peak ratio {:.4}",
        k0 / k,
        k5 / k,
        p5 / p0
    );
    // Elastic slope within 3 % of E A / H (the joints' compliance at p = 100 E, about 2 E/p,
    // and the platens' loading inertia; friction stiffens slightly).
    assert!((k0 / k - 1.0).abs() < 0.03, "slope {k0}");
    assert!((k5 / k - 1.0).abs() < 0.03, "slope {k5}");
    // Friction at the platens confines the block ends: a higher peak.
    assert!(p5 > p0, "peak with friction {p5} <= frictionless {p0}");
    // It fails: the load has dropped below half the peak by the end of the run, with broken
    // joints in shear (mode II or mixed) as well as in tension. (A fully damaged joint breaks
    // only once open at both points or slid by h/10, so joints crushed shut in the shear bands
    // stay in the set with damage 1; the broken count is the lower bound 30.)
    for (b, s, d) in [(b0, s0, d0), (b5, s5, d5)] {
        assert!(d < 0.5, "final load / peak {d}: the block has not failed");
        assert!(b > 30 && s > 10, "{b} broken, {s} in shear");
    }
    // Energy balance within 2 % of the platens' work.
    assert!(r0.abs() < 0.02 && r5.abs() < 0.02, "residuals {r0} {r5}");
    fdem_figures::record(
        46,
        format!(
            "{:+.1} % (mu = 0), {:+.1} % (mu = 0.5); peak {:+.1} %",
            100.0 * (k0 / k - 1.0),
            100.0 * (k5 / k - 1.0),
            100.0 * (p5 / p0 - 1.0)
        ),
    );
}

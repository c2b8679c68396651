//! The fluid in the crack network (`"fluid"`): checks against answers known in closed form.
//!
//! - **Sneddon**: a straight crack of half-length a in a large plate, its faces under a
//!   uniform pressure p (plane strain, no far-field load): opening
//!   `w(x) = (4 p / E') sqrt(a^2 - x^2)`, so the mid-crack opening `4 p a / E'` and the
//!   volume `2 pi p a^2 / E'` (per unit thickness). Three meshes, a / h = 5, 10, 20.
//! - **Injection into a closed crack**: the volume injected into a crack whose tips hold
//!   fills it and compresses the fluid: `V_inj = 2 pi p a^2 / E' + p V / K` at the pressure
//!   p it reaches; the volume books close at every history row.
//! - **Unused physics costs nothing**, and bad input is refused at its JSON path.

use crate::common;

use std::path::PathBuf;

use serde_json::{Value, json};

const E: f64 = 10e9;
const NU: f64 = 0.25;
const A: f64 = 0.1;
const P: f64 = 1e6;

/// Plane-strain modulus `E / (1 - nu^2)`.
fn e_prime() -> f64 {
    E / (1.0 - NU * NU)
}

/// A square plate with a crack on y = 0, |x| <= a, meshed by squares of side `h = a / n_a`
/// in the box |x|, |y| <= 1.6 a, then rings of coarser squares out to at least `20 a`
/// ([`ringed_plate`]).
pub fn cracked_plate(n_a: i64) -> Value {
    let b0 = {
        let b = (1.6 * n_a as f64).round() as i64;
        b + b % 2
    };
    ringed_plate(A / n_a as f64, [b0, b0], n_a, 20 * n_a)
}

/// A plate meshed by squares of side `h` in the box |x| <= `box_[0]` h, |y| <= `box_[1]` h
/// (two triangles each; even counts), then rings of squares of sides 2h, 4h, ... four or
/// five squares wide (so that each ring's edges fall on the next ring's nodes) out to at
/// least `reach` h from the centre; each ring's squares along the finer box split in three
/// triangles at the finer nodes (no hanging node). Groups: `band` (the two rows of triangles
/// beside y = 0 in the inner box, the fracture region), `rest`, `crack` (the edges on y = 0
/// with |x| <= `crack` h), `outer` (the plate's edges).
pub fn ringed_plate(h: f64, box_: [i64; 2], crack: i64, reach: i64) -> Value {
    let mut ids = std::collections::HashMap::new();
    let mut pts: Vec<[i64; 2]> = Vec::new();
    let mut node = |p: [i64; 2]| -> u32 {
        *ids.entry(p).or_insert_with(|| {
            pts.push(p);
            (pts.len() - 1) as u32
        })
    };
    let (mut tris, mut band, mut rest) = (Vec::new(), Vec::new(), Vec::new());
    // hang: the side (0 bottom, 1 right, 2 top, 3 left) with a mid-side node
    let mut cell = |x0: i64, y0: i64, s: i64, hang: Option<usize>, in_band: bool| {
        let c = [[x0, y0], [x0 + s, y0], [x0 + s, y0 + s], [x0, y0 + s]];
        let out: Vec<[[i64; 2]; 3]> = match hang {
            None if (2 * x0 + s) * (2 * y0 + s) > 0 => vec![[c[0], c[1], c[2]], [c[0], c[2], c[3]]],
            None => vec![[c[0], c[1], c[3]], [c[1], c[2], c[3]]],
            Some(r) => {
                let q = [c[r], c[(r + 1) % 4], c[(r + 2) % 4], c[(r + 3) % 4]];
                let m = [(q[0][0] + q[1][0]) / 2, (q[0][1] + q[1][1]) / 2];
                vec![[q[0], m, q[3]], [m, q[1], q[2]], [m, q[2], q[3]]]
            }
        };
        for t in out {
            let g: &mut Vec<usize> = if in_band { &mut band } else { &mut rest };
            g.push(tris.len());
            tris.push(t.map(&mut node));
        }
    };
    let [bx, by] = box_;
    for j in -by..by {
        for i in -bx..bx {
            cell(i, j, 1, None, j == -1 || j == 0);
        }
    }
    let (mut inner, mut s) = ([bx, by], 1);
    while inner[0].min(inner[1]) < reach {
        s *= 2;
        let grow = |b: i64| b + if (b / s + 4) % 2 == 0 { 4 } else { 5 } * s;
        let outer = [grow(inner[0]), grow(inner[1])];
        let (ix, iy) = (inner[0], inner[1]);
        for j in (-outer[1]..outer[1]).step_by(s as usize) {
            for i in (-outer[0]..outer[0]).step_by(s as usize) {
                let in_x = -ix <= i && i < ix;
                let in_y = -iy <= j && j < iy;
                if in_x && in_y {
                    continue;
                }
                let hang = if j + s == -iy && in_x {
                    Some(2)
                } else if j == iy && in_x {
                    Some(0)
                } else if i + s == -ix && in_y {
                    Some(1)
                } else if i == ix && in_y {
                    Some(3)
                } else {
                    None
                };
                cell(i, j, s, hang, false);
            }
        }
        inner = outer;
    }
    let crack: Vec<[u32; 2]> = (-crack..crack)
        .map(|i| [node([i, 0]), node([i + 1, 0])])
        .collect();
    let mut outer_edges = Vec::new();
    let [ox, oy] = inner;
    for i in (-ox..ox).step_by(s as usize) {
        outer_edges.push([node([i, -oy]), node([i + s, -oy])]);
        outer_edges.push([node([i, oy]), node([i + s, oy])]);
    }
    for j in (-oy..oy).step_by(s as usize) {
        outer_edges.push([node([-ox, j]), node([-ox, j + s])]);
        outer_edges.push([node([ox, j]), node([ox, j + s])]);
    }
    let nodes: Vec<[f64; 2]> = pts
        .iter()
        .map(|p| [p[0] as f64 * h, p[1] as f64 * h])
        .collect();
    json!({
        "nodes": nodes, "triangles": tris,
        "groups": [
            {"name": "band", "dim": 2, "triangles": band},
            {"name": "rest", "dim": 2, "triangles": rest},
            {"name": "crack", "dim": 1, "edges": crack},
            {"name": "outer", "dim": 1, "edges": outer_edges}
        ]
    })
}

/// The scene of the cracked plate (`n_a` elements on the half-crack) with its outer edges
/// fixed and `fluid` as its `"fluid"` section, damped (`alpha` = 3000 /s) over `duration`.
fn plate_scene(tag: &str, n_a: i64, fluid: Value, duration: f64) -> PathBuf {
    let p = scene_on(tag, cracked_plate(n_a), fluid, duration);
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    v["fracture"]["material"] = json!({
        "tensile_strength": 50e6, "cohesion": 100e6, "friction_angle_deg": 30.0,
        "fracture_energy_i": 1e5, "fracture_energy_ii": 1e6,
        "penalty_normal": 10.0 * E, "penalty_tangential": 10.0 * E
    });
    v["damping"] = json!({ "mass_proportional": 3000.0 });
    v["output"]["frames"] = json!(1);
    v["histories"]["probes"] = json!(["energy", "fluid"]);
    std::fs::write(&p, v.to_string()).unwrap();
    p
}

/// The scene of a plate `mesh` (groups as [`ringed_plate`]'s) with its outer edges fixed, the
/// band's joints breakable (ft = 1 MPa, G_I = 6 J/m^2), the crack group a pre-existing crack,
/// `fluid` as its `"fluid"` section, over `duration`, no frames, the `fluid` probe every 20
/// steps.
fn scene_on(tag: &str, mesh: Value, fluid: Value, duration: f64) -> PathBuf {
    let dir = common::temp_dir(tag);
    std::fs::write(dir.join("plate.json"), mesh.to_string()).unwrap();
    let scene = json!({
        "title": "pressurised crack",
        "bodies": [{
            "name": "plate", "mesh": "plate.json",
            "materials": { "*": { "young": E, "poisson": NU, "density": 2500.0, "plane": "strain" } }
        }],
        "boundary_conditions": [ { "fixed": { "group": "outer", "x": true, "y": true } } ],
        "fracture": {
            "regions": [ { "body": "plate", "groups": ["band"] } ],
            "material": {
                "tensile_strength": 1e6, "cohesion": 3e6, "friction_angle_deg": 30.0,
                "fracture_energy_i": 6.0, "fracture_energy_ii": 60.0,
                "penalty_normal": 10.0 * E, "penalty_tangential": 10.0 * E
            },
            "cracks": [ { "group": "crack" } ]
        },
        "contact": {},
        "fluid": fluid,
        "integrator": { "scheme": "central-difference", "safety": 0.9 },
        "duration": duration,
        "output": { "frames": 0 },
        "histories": { "every": 20, "probes": [ "fluid" ] }
    });
    let p = dir.join("plate-scene.json");
    std::fs::write(&p, scene.to_string()).unwrap();
    p
}

/// The opening at the crack's centre (the spread of the current y of the copies of the node
/// at (0, 0)) and the crack's volume per unit thickness (the wetted joints' length times mean
/// opening) of a run's last frame.
fn opening_and_volume(o: &fdem_solver::driver::Outcome) -> (f64, f64) {
    let f = &o.last_frame;
    let x0 = common::reference_points(f);
    let ys: Vec<f64> = (0..x0.len())
        .filter(|&i| x0[i][0].abs() < 1e-12 && x0[i][1].abs() < 1e-12)
        .map(|i| f.points[i][1])
        .collect();
    assert!(ys.len() >= 2, "copies of the crack's centre: {}", ys.len());
    let w0 =
        ys.iter().fold(f64::MIN, |m, &y| m.max(y)) - ys.iter().fold(f64::MAX, |m, &y| m.min(y));
    let j = f.joints.as_ref().expect("joints");
    let fl = j.fluid.as_ref().expect("the fluid's joint arrays");
    let mut v = 0.0;
    for k in 0..j.len() {
        if fl.wetted[k] == 1 {
            let (p, q) = (j.points[2 * k], j.points[2 * k + 1]);
            v += ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt() * j.opening[k];
        }
    }
    (w0, v)
}

/// Sneddon's pressurised crack on three meshes: the mid-crack opening and the volume within
/// 3 % on the finest, the errors falling with the mesh.
#[test]
fn sneddon_pressurised_crack_opening_and_volume() {
    let w_exact = 4.0 * P * A / e_prime();
    let v_exact = 2.0 * std::f64::consts::PI * P * A * A / e_prime();
    let mut rows = Vec::new();
    for n_a in [5, 10, 20] {
        let fluid = json!({
            "viscosity": 1e-3, "bulk_modulus": 2.2e9,
            "pressures": [ { "group": "crack", "value": P, "ramp": 0.002 } ]
        });
        let p = plate_scene(&format!("sneddon-{n_a}"), n_a, fluid, 0.005);
        let (o, _) = common::run(&p);
        let (w0, v) = opening_and_volume(&o);
        let (ew, ev) = (w0 / w_exact - 1.0, v / v_exact - 1.0);
        eprintln!("a/h = {n_a}: w0 {w0:.5e} ({ew:+.4}), V {v:.5e} ({ev:+.4})");
        rows.push((n_a, ew, ev));
    }
    let (_, ew, ev) = rows[2];
    assert!(ew.abs() < 0.03 && ev.abs() < 0.03, "{rows:?}");
    assert!(
        rows[2].2.abs() < rows[0].2.abs(),
        "the volume converges: {rows:?}"
    );
    let text: Vec<String> = rows
        .iter()
        .map(|(n, ew, ev)| {
            format!(
                "a/h = {n}: opening {:+.1} %, volume {:+.1} %",
                100.0 * ew,
                100.0 * ev
            )
        })
        .collect();
    fdem_figures::record(148, text.join(", "));
}

/// The volume `V` injected into a crack whose tips hold (the joints beyond them are far
/// stronger than the pressure needs) spreads along it and opens it: at rest the pressure p
/// is uniform and the volume in the network is `c p + 2 a r` (`c` the crack's compliance,
/// volume per unit pressure: `2 pi a^2 / E'` by Sneddon, and the same mesh's under a
/// prescribed pressure; `r` the residual aperture of the touching faces), the rest of `V`
/// held by the fluid's compression. A thin fluid (1e-5 Pa s) evens the pressure out within
/// the run. The volume books close at every history row.
#[test]
fn injection_into_a_closed_crack_matches_sneddon() {
    let n_a = 10;
    let k_f = 2.2e9;
    let q = 3.84e-3;
    // ramped up over 0.5 ms, held 1 ms, ramped down over 0.5 ms: 1.5 ms at the full rate
    let injected = q * 0.0015;
    let fluid = json!({
        "viscosity": 1e-5, "bulk_modulus": k_f,
        "injections": [ {
            "at": [0.0, 0.0], "rate": q,
            "history": [[0.0, 0.0], [0.0005, 1.0], [0.0015, 1.0], [0.002, 0.0]]
        } ]
    });
    let p = plate_scene("inject", n_a, fluid, 0.006);
    let (o, out) = common::run(&p);
    let (head, rows) = common::histories(&out);
    let err = common::column(&head, &rows, "fluid_balance_error");
    let worst = err.iter().fold(0.0f64, |m, &e| m.max(e));
    assert!(worst < 1e-9, "the books' residual reaches {worst:e}");
    let inj = *common::column(&head, &rows, "fluid_injected")
        .last()
        .unwrap();
    assert!((inj / injected - 1.0).abs() < 1e-12, "{inj} vs {injected}");
    let pressure = *common::column(&head, &rows, "injection_pressure")
        .last()
        .unwrap();
    let stored = *common::column(&head, &rows, "fluid_stored").last().unwrap();
    let open = stored - 2.0 * A * 1e-6;
    // the same mesh's compliance under a prescribed pressure
    let fluid = json!({
        "viscosity": 1e-3, "bulk_modulus": k_f,
        "pressures": [ { "group": "crack", "value": P, "ramp": 0.002 } ]
    });
    let (o_p, _) = common::run(&plate_scene("inject-ref", n_a, fluid, 0.005));
    let c_mesh = opening_and_volume(&o_p).1 / P;
    let c_sneddon = 2.0 * std::f64::consts::PI * A * A / e_prime();
    let (p_mesh, p_sneddon) = (open / c_mesh, open / c_sneddon);
    let (e_mesh, e_sneddon) = (pressure / p_mesh - 1.0, pressure / p_sneddon - 1.0);
    eprintln!(
        "p {pressure:.5e}: against the mesh's compliance {e_mesh:+.4}, Sneddon's {e_sneddon:+.4}; books {worst:.1e}"
    );
    assert!(e_mesh.abs() < 0.01, "{e_mesh}");
    assert!(e_sneddon.abs() < 0.03, "{e_sneddon}");
    let energy = o.summary.energy;
    assert!(energy.fluid_work > 0.0);
    fdem_figures::record(
        149,
        format!(
            "pressure {:+.2} % against the mesh's own compliance, {:+.2} % against Sneddon (a/h = {n_a}), books closed to {} at every row",
            100.0 * e_mesh,
            100.0 * e_sneddon,
            fdem_figures::sci(worst.max(1e-16), 1)
        ),
    );
}

/// The error of loading the small cracked plate's scene with `edit` applied.
fn load_error(tag: &str, edit: impl FnOnce(&mut Value)) -> String {
    let fluid = json!({
        "viscosity": 1e-3, "bulk_modulus": 2.2e9,
        "injections": [ { "at": [0.0, 0.0], "rate": 1e-4 } ]
    });
    let p = plate_scene(tag, 2, fluid, 1e-4);
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    edit(&mut v);
    std::fs::write(&p, v.to_string()).unwrap();
    match fdem_solver::driver::load(&p) {
        Ok(_) => panic!("{tag}: the scene loaded"),
        Err(e) => e.to_string(),
    }
}

/// An edit of a scene's JSON.
type Edit = Box<dyn FnOnce(&mut Value)>;

/// Bad input is refused at its JSON path, with the fix; so is a distributed run of a scene
/// with a fluid.
#[test]
fn bad_fluid_input_is_refused_at_its_path() {
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "negative-viscosity",
            Box::new(|v| v["fluid"]["viscosity"] = json!(-1e-3)),
            "fluid.viscosity",
        ),
        (
            "point-off",
            Box::new(|v| v["fluid"]["injections"][0]["at"] = json!([0.9, 0.7])),
            "fluid.injections[0].at",
        ),
        (
            "no-fracture",
            Box::new(|v| {
                let o = v.as_object_mut().unwrap();
                o.remove("fracture");
                o.remove("contact");
            }),
            "fluid",
        ),
        (
            "unknown-group",
            Box::new(|v| {
                v["fluid"]["pressures"] = json!([{ "group": "crak", "value": 1e6 }]);
            }),
            "fluid.pressures[0].group",
        ),
        (
            "group-not-joints",
            Box::new(|v| {
                v["fluid"]["pressures"] = json!([{ "group": "outer", "value": 1e6 }]);
            }),
            "fluid.pressures[0].group",
        ),
        (
            "negative-rate",
            Box::new(|v| v["fluid"]["injections"][0]["rate"] = json!(-1.0)),
            "fluid.injections[0].rate",
        ),
        (
            "aperture-order",
            Box::new(|v| v["fluid"]["max_aperture"] = json!(1e-9)),
            "fluid.max_aperture",
        ),
        (
            "unknown-field",
            Box::new(|v| v["fluid"]["viscosty"] = json!(1e-3)),
            "fluid.viscosty",
        ),
        (
            "probe-without-fluid",
            Box::new(|v| {
                v.as_object_mut().unwrap().remove("fluid");
            }),
            "histories.probes[1]",
        ),
    ];
    let mut seen = Vec::new();
    for (tag, edit, path) in cases {
        let e = load_error(tag, edit);
        assert!(
            e.contains(path),
            "{tag}: the error does not name `{path}`: {e}"
        );
        seen.push(tag);
    }
    assert_eq!(seen.len(), 9);
    // a distributed run of a fluid scene, before anything is written
    let p = plate_scene(
        "fluid-ranks",
        2,
        json!({ "viscosity": 1e-3, "bulk_modulus": 2.2e9 }),
        1e-4,
    );
    let l = fdem_solver::driver::load(&p).unwrap();
    let e = fdem_solver::run::distributed::check(&l, 2)
        .unwrap_err()
        .to_string();
    assert!(e.contains("`fluid`") && e.contains("2 processes"), "{e}");
    fdem_figures::record(
        151,
        format!("{} of 10 refused at their paths", seen.len() + 1),
    );
}

/// A run with a fluid stopped twice during the injection and resumed writes the very same
/// files as the run that never stopped (frames with the fluid's joint arrays, the fluid's
/// histories, `summary.json` but for its timers).
#[test]
fn injection_resumes_bit_for_bit() {
    let fluid = json!({
        "viscosity": 1e-4, "bulk_modulus": 2.2e9, "leak_off": 1e-6,
        "injections": [ { "at": [0.0, 0.0], "rate": 3.0e-3, "ramp": 5e-4 } ]
    });
    let p = plate_scene("fluid-resume", 5, fluid, 0.002);
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    v["output"]["frames"] = json!(4);
    std::fs::write(&p, v.to_string()).unwrap();
    let (a, _) = crate::restart::straight_and_resumed(&p, &[700, 1900]);
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(a.join("summary.json")).unwrap()).unwrap();
    let fl = &summary["stages"]["fluid"];
    assert!(
        fl["injected_volume"].as_f64().unwrap() > 0.0
            && fl["leaked_volume"].as_f64().unwrap() > 0.0
    );
    fdem_figures::record_part(
        150,
        5,
        "a run stopped twice and resumed: the same files, bit for bit",
    );
}

/// A fracture driven by injection into a notch: with `wet_damaged` the fluid enters the
/// joints from their first softening (the process zone), without it only from their break;
/// the books close either way and the breaks follow the fluid.
#[test]
fn injection_grows_a_fracture_and_wet_damaged_wets_the_process_zone() {
    let h = 0.01;
    let run = |wet: bool| {
        let fluid = json!({
            "viscosity": 1e-6, "bulk_modulus": 2.2e9, "wet_damaged": wet,
            "injections": [ { "at": [0.0, 0.0], "rate": 4e-3 } ]
        });
        let tag = if wet { "grow-wet" } else { "grow-dry" };
        let p = scene_on(tag, ringed_plate(h, [32, 4], 5, 100), fluid, 0.0015);
        let (o, out) = common::run(&p);
        let (head, rows) = common::histories(&out);
        let worst = common::column(&head, &rows, "fluid_balance_error")
            .iter()
            .fold(0.0f64, |m, &e| m.max(e));
        assert!(worst < 1e-9, "books {worst:e}");
        let broken = o.summary.stages["fracture"]["broken"].as_u64().unwrap();
        let channels = o.summary.stages["fluid"]["channels"].as_u64().unwrap();
        (broken, channels)
    };
    let (broken_dry, channels_dry) = run(false);
    let (broken_wet, channels_wet) = run(true);
    eprintln!("broken {broken_dry} / {broken_wet}, channels {channels_dry} / {channels_wet}");
    // the notch's 10 joints start broken; the fracture grew
    assert!(broken_dry > 14 && broken_wet > 14);
    assert_eq!(
        channels_dry, broken_dry,
        "without wet_damaged only broken joints are wet"
    );
    assert!(channels_wet > broken_wet, "the process zone is wet");
}

/// A joint in a frame: its midpoint, wetted, broken.
type JointSeen = ([f64; 2], bool, bool);

/// The joint frames of a run: per frame, its time and the joints' midpoints with their
/// `wetted` and `broken` flags (read back from `joints_NNNN.vtu` and `joints.pvd`).
fn joint_frames(out: &std::path::Path) -> Vec<(f64, Vec<JointSeen>)> {
    let pvd = std::fs::read_to_string(out.join("joints.pvd")).unwrap();
    let mut frames = Vec::new();
    for line in pvd.lines().filter(|l| l.contains("<DataSet")) {
        let attr = |k: &str| {
            line.split(&format!("{k}=\""))
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
        };
        let t: f64 = attr("timestep").parse().unwrap();
        let bytes = std::fs::read(out.join(attr("file"))).unwrap();
        let arrays = fdem_solver::output::vtu::read(&bytes).unwrap();
        let get = |n: &str| arrays.iter().find(|a| a.name == n).unwrap();
        let flags = |n: &str| -> Vec<bool> {
            let a = get(n);
            assert_eq!(a.ty, "Int32", "{n}");
            a.bytes.chunks_exact(4).map(|b| b != [0, 0, 0, 0]).collect()
        };
        let (pts, wet, broken) = (get("Points").to_f64(), flags("wetted"), flags("broken"));
        let joints = (0..wet.len())
            .map(|j| {
                let mid = [
                    0.5 * (pts[6 * j] + pts[6 * j + 3]),
                    0.5 * (pts[6 * j + 1] + pts[6 * j + 4]),
                ];
                (mid, wet[j], broken[j])
            })
            .collect();
        frames.push((t, joints));
    }
    frames
}

/// KGD in the toughness-dominated regime: water-thin fluid (1e-9 Pa s, dimensionless
/// toughness `K' / (E'^3 mu' Q0)^(1/4)` = 6.7, above 4) injected at `Q0` into a 10 cm notch
/// on the line of a band of 5 mm joints (ft = 1 MPa, G_I = 3 J/m^2: `l_ch` = 6.4 joints), the
/// fluid entering the process zone (`wet_damaged`): the half-length of the fictitious crack
/// (the wetted, i.e. damaged or broken, joints on the line) against
/// `l(t) = [E' Q0 t / (2 sqrt(pi) K_Ic)]^(2/3)`, `K_Ic = sqrt(E' G_I)`, over a decade of time
/// (0.5 to 5 ms); the broken joints' front trails further behind (the process zone).
#[test]
fn kgd_toughness_dominated_half_length() {
    let (h, g_i, q0) = (0.005, 3.0, 3.71e-3);
    let fluid = json!({
        "viscosity": 1e-9, "bulk_modulus": 2.2e9, "wet_damaged": true,
        "injections": [ { "at": [0.0, 0.0], "rate": q0 } ]
    });
    let p = scene_on("kgd", ringed_plate(h, [128, 8], 10, 1000), fluid, 0.005);
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    v["fracture"]["material"]["fracture_energy_i"] = json!(g_i);
    v["fracture"]["material"]["fracture_energy_ii"] = json!(10.0 * g_i);
    v["damping"] = json!({ "mass_proportional": 1000.0 });
    v["output"] = json!({ "frames": 10, "arrays": ["damage", "broken", "wetted"] });
    v["histories"]["every"] = json!(100);
    std::fs::write(&p, v.to_string()).unwrap();
    let (_, out) = common::run(&p);
    let k_ic = (e_prime() * g_i).sqrt();
    let ell =
        |t: f64| (e_prime() * q0 * t / (2.0 * std::f64::consts::PI.sqrt() * k_ic)).powf(2.0 / 3.0);
    let mut rows = Vec::new();
    for (t, joints) in joint_frames(&out) {
        if t < 0.45e-3 {
            continue;
        }
        // the extent along the line y = 0 (half a joint beyond the last midpoint)
        let front = |keep: &dyn Fn(bool, bool) -> bool| {
            joints
                .iter()
                .filter(|(m, w, b)| m[1].abs() < 0.25 * h && keep(*w, *b))
                .fold(0.0f64, |e, (m, _, _)| e.max(m[0].abs() + 0.5 * h))
        };
        let (wet, broken) = (front(&|w, _| w), front(&|_, b| b));
        rows.push((t, wet / ell(t) - 1.0, broken / ell(t) - 1.0));
    }
    assert!(rows.len() >= 10, "{} frames from 0.5 ms", rows.len());
    let (head, hist) = common::histories(&out);
    let worst = common::column(&head, &hist, "fluid_balance_error")
        .iter()
        .fold(0.0f64, |m, &e| m.max(e));
    assert!(worst < 1e-9, "books {worst:e}");
    for &(t, ew, eb) in &rows {
        eprintln!("t {t:.2e}: fictitious crack {ew:+.3}, broken joints {eb:+.3}");
    }
    let max_wet = rows.iter().fold(0.0f64, |m, r| m.max(r.1.abs()));
    assert!(
        max_wet < 0.10,
        "the fictitious crack's half-length off by up to {max_wet:.3}"
    );
    assert!(
        rows.iter().all(|r| r.2 < r.1),
        "the broken joints trail the fictitious crack"
    );
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    fdem_figures::record(
        152,
        format!(
            "fictitious crack {:+.1} % at 0.5 ms, {:+.1} % at 5 ms, at most {:.1} % off, broken joints {:+.1} % and {:+.1} % (books {})",
            100.0 * first.1,
            100.0 * last.1,
            100.0 * max_wet,
            100.0 * first.2,
            100.0 * last.2,
            fdem_figures::sci(worst.max(1e-17), 1)
        ),
    );
}

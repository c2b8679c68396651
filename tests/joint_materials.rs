//! Joint materials per fracture region and per interface, and heterogeneous joint strengths
//! drawn from a distribution (`fracture.materials`, `fracture.interfaces`,
//! `heterogeneity`; docs/fracture.md, "Joint materials, interfaces and heterogeneity").
//!
//! - A bar of two bulk materials bonded by an interface weaker than both breaks at the
//!   interface, at `f_t(interface) x area`.
//! - Drawn strengths are the same bits on one and two threads, differ with the seed, and are
//!   those of `fdem_fracture::Heterogeneity::draw` for each joint's index.
//! - Weakest link: a chain of `N` joints in series with Weibull strengths fails, on average over
//!   seeds, at `lambda N^(-1/m) Gamma(1 + 1/m)`.
//! - Bad input is refused with the JSON path and the valid names.

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::common;
use fdem_fracture::heterogeneity::gamma;
use fdem_solver::driver::{self, Outcome, RunOptions};

/// A strip `[0, nx c] x [0, ny c]` of square cells of side `c`, each cut into two CCW
/// triangles; cell `(i, j)` is in the surface group `group(i)`. Edge groups `left`, `right`.
fn strip(dir: &Path, nx: usize, ny: usize, c: f64, group: impl Fn(usize) -> &'static str) {
    let (nodes, tris) = common::structured_rectangle(nx, ny, nx as f64 * c, ny as f64 * c);
    let mut names: Vec<&str> = Vec::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    for (t, _) in tris.iter().enumerate() {
        let g = group((t / 2) % nx);
        let k = names.iter().position(|n| *n == g).unwrap_or_else(|| {
            names.push(g);
            members.push(Vec::new());
            names.len() - 1
        });
        members[k].push(t);
    }
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let edges = |i: usize| -> Vec<[u32; 2]> { (0..ny).map(|j| [id(i, j), id(i, j + 1)]).collect() };
    let mut groups: Vec<Value> = names
        .iter()
        .zip(&members)
        .map(|(n, m)| json!({"name": n, "dim": 2, "triangles": m}))
        .collect();
    groups.push(json!({"name": "left", "dim": 1, "edges": edges(0)}));
    groups.push(json!({"name": "right", "dim": 1, "edges": edges(nx)}));
    let mesh = json!({"nodes": nodes, "triangles": tris, "groups": groups});
    std::fs::write(dir.join("strip.json"), mesh.to_string()).unwrap();
}

/// A joint material: strengths, energies and penalty.
fn joint(ft: f64, c: f64, g: f64) -> Value {
    json!({
        "tensile_strength": ft, "cohesion": c, "friction_angle_deg": 30.0,
        "fracture_energy_i": g, "fracture_energy_ii": 5.0 * g,
        "penalty_normal": 300e9, "penalty_tangential": 300e9
    })
}

fn bulk(young: f64) -> Value {
    json!({"young": young, "poisson": 0.2, "density": 2500.0, "plane": "stress"})
}

/// A strip pulled at `speed` (ramped over `ramp`) on its right end, its left end held in x.
fn pull_scene(
    bulk_materials: Value,
    fracture: Value,
    speed: f64,
    ramp: f64,
    duration: f64,
) -> Value {
    json!({
        "analysis": "dynamic",
        "bodies": [{"name": "bar", "mesh": "strip.json", "materials": bulk_materials, "thickness": 0.01}],
        "boundary_conditions": [
            {"fixed": {"group": "left", "x": true}},
            {"velocity": {"group": "right", "x": speed, "ramp": ramp}}
        ],
        "fracture": fracture,
        "integrator": {"scheme": "central-difference", "safety": 0.9},
        "damping": {"mass_proportional": 2e4},
        "duration": duration,
        "output": {"frames": 0},
        "histories": {"every": 1, "probes": [{"reaction": {"group": "left"}}]}
    })
}

fn write(dir: &Path, scene: &Value) -> PathBuf {
    let p = dir.join("scene.json");
    std::fs::write(&p, serde_json::to_string_pretty(scene).unwrap()).unwrap();
    p
}

fn run(p: &Path) -> Outcome {
    let mut l = driver::load(p).unwrap_or_else(|e| panic!("{e}"));
    driver::run_outcome(
        &mut l,
        &RunOptions {
            out_dir: p.parent().unwrap().join("out"),
            raw: false,
            ..Default::default()
        },
        &mut |_| {},
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The largest tensile reaction at the held end [N] (the left support pulls in -x).
fn peak_reaction(out: &Path) -> f64 {
    let (head, rows) = common::histories(out);
    common::column(&head, &rows, "reaction_x[left]")
        .iter()
        .map(|r| -r)
        .fold(0.0, f64::max)
}

/// A bar 40 x 10 mm (8 x 2 cells) of two bulk materials, E = 30 GPa (`soft`, x < 20 mm) and
/// 60 GPa (`stiff`), the whole bar fracturing with the strong joint material (f_t = 30 MPa)
/// and the joints between the two groups with the interface material (f_t = 3 MPa). Pulled at
/// 5 mm/s (ramped over 50 us): the rho c v of the pull is 43 kPa, 1.4 % of f_t, and the
/// damping takes the waves out. Known answer: the two interface joints (5 mm each, 10 mm
/// thick) break, and first, at f_t A = 3 MPa x 1e-4 m^2 = 300 N. Measured (release): peak
/// reaction 301.28 N, ratio 1.0043 (tolerance 2 %); every break at x = 20 mm.
#[test]
fn an_interface_weaker_than_both_materials_breaks_at_its_strength_times_its_area() {
    let dir = common::temp_dir("joint-interface");
    strip(&dir, 8, 2, 0.005, |i| if i < 4 { "soft" } else { "stiff" });
    let scene = pull_scene(
        json!({"soft": bulk(30e9), "stiff": bulk(60e9)}),
        json!({
            "regions": [{"groups": ["soft"], "material": "strong"}, {"groups": ["stiff"], "material": "strong"}],
            "materials": {"strong": joint(30e6, 60e6, 500.0), "weak": joint(3e6, 6e6, 2.0)},
            "interfaces": [{"groups": ["soft", "stiff"], "material": "weak"}]
        }),
        0.005,
        5e-5,
        1.5e-3,
    );
    let p = write(&dir, &scene);
    let o = run(&p);
    let peak = peak_reaction(&p.parent().unwrap().join("out"));
    let known = 3e6 * 0.01 * 0.01;
    let ratio = peak / known;
    println!("interface bar: peak reaction {peak:.2} N, f_t A = {known} N, ratio {ratio:.4}");
    assert!((ratio - 1.0).abs() < 0.02, "ratio {ratio}");
    let report = &o.summary.stages["fracture"];
    assert!(report["broken"].as_u64().unwrap() >= 2, "{report}");
    let text = std::fs::read_to_string(p.parent().unwrap().join("out/fractures.csv")).unwrap();
    for line in text.lines().skip(1) {
        let x: f64 = line.split(',').nth(1).unwrap().parse().unwrap();
        assert!(
            (x - 0.02).abs() < 1e-4,
            "a break away from the interface: {line}"
        );
    }
    // the joint series carries each joint's strength (two materials)
    let props = o.last_frame.joints.as_ref().unwrap().properties.as_ref();
    let ft = &props
        .expect("strengths in the joint frame")
        .tensile_strength;
    assert_eq!(ft.iter().filter(|&&f| f == 3e6).count(), 2, "{ft:?}");
    assert!(ft.iter().all(|&f| f == 3e6 || f == 30e6));
    fdem_figures::record(
        51,
        format!("{peak:.2} N (ratio {ratio:.4}); every break at the interface"),
    );
}

/// A 1-cell-thick strip of `n + 1` cells of 5 mm (groups alternating `even`, `odd`): its `n`
/// transverse joints are the interface `[even, odd]` with Weibull strengths (seed `seed`),
/// the diagonals are ten times stronger.
fn chain_scene(dir: &Path, n: usize, modulus: f64, scale: f64, seed: u64) -> PathBuf {
    strip(dir, n + 1, 1, 0.005, |i| {
        if i % 2 == 0 { "even" } else { "odd" }
    });
    let mut link = joint(0.0, 30e6, 50.0);
    link.as_object_mut().unwrap().remove("tensile_strength");
    link["heterogeneity"] = json!({
        "seed": seed,
        "tensile_strength": {"weibull": {"modulus": modulus, "scale": scale}}
    });
    let scene = pull_scene(
        json!({"*": bulk(30e9)}),
        json!({
            "regions": [{"material": "strong"}],
            "materials": {"strong": joint(10.0 * scale, 60e6, 500.0), "link": link},
            "interfaces": [{"groups": ["even", "odd"], "material": "link"}]
        }),
        0.0025,
        5e-5,
        2.5e-3,
    );
    write(dir, &scene)
}

/// Weakest link: N = 8 joints in series, Weibull modulus m = 12, scale lambda = 3 MPa, 96
/// seeds. The chain fails at the strength of its weakest joint, whose law is Weibull with scale
/// `lambda N^(-1/m)`: mean `lambda N^(-1/m) Gamma(1 + 1/m)` = 2.4175 MPa with a deviation of
/// 0.104 of it, so the mean of 96 seeds has a standard error of 1.03 %; tolerance 3 %. Each
/// run also checks that the failure stress is that of the weakest drawn joint within 1 % (the
/// pull at 2.5 mm/s has rho c v = 22 kPa, under 1 % of the strengths, and is damped). Measured
/// (release): mean failure stress 2.4555 MPa, ratio 1.0157 (the weakest drawn strengths
/// alone: 1.0137, the sampling error of 96 seeds); largest gap to the weakest joint 0.70 %.
#[test]
fn a_chain_of_weibull_joints_fails_at_the_weakest_link_mean() {
    let (n, m, lambda, seeds) = (8usize, 12.0f64, 3e6f64, 96u64);
    let area = 0.005 * 0.01;
    let (mut sum, mut sum_weakest) = (0.0, 0.0);
    let mut worst_gap = 0.0f64;
    for seed in 1..=seeds {
        let dir = common::temp_dir(&format!("joint-chain-{seed}"));
        let p = chain_scene(&dir, n, m, lambda, seed);
        let o = run(&p);
        let stress = peak_reaction(&p.parent().unwrap().join("out")) / area;
        let ft = &o
            .last_frame
            .joints
            .as_ref()
            .unwrap()
            .properties
            .as_ref()
            .unwrap()
            .tensile_strength;
        let weakest = ft.iter().copied().fold(f64::INFINITY, f64::min);
        assert_eq!(ft.iter().filter(|&&f| f != 10.0 * lambda).count(), n);
        let gap = (stress / weakest - 1.0).abs();
        worst_gap = worst_gap.max(gap);
        assert!(
            gap < 0.01,
            "seed {seed}: failure stress {stress} against weakest {weakest}"
        );
        sum += stress;
        sum_weakest += weakest;
        std::fs::remove_dir_all(&dir).ok();
    }
    let mean = sum / seeds as f64;
    let known = lambda * (n as f64).powf(-1.0 / m) * gamma(1.0 + 1.0 / m);
    let sd = lambda
        * (n as f64).powf(-1.0 / m)
        * (gamma(1.0 + 2.0 / m) - gamma(1.0 + 1.0 / m).powi(2)).sqrt();
    let se = sd / (seeds as f64).sqrt();
    println!(
        "weakest link: mean {mean:.5e} Pa against {known:.5e} Pa, ratio {:.4} (mean of the \
         weakest drawn joints: ratio {:.4}), standard error {:.2} %, largest gap to the weakest \
         joint {:.2} %",
        mean / known,
        sum_weakest / seeds as f64 / known,
        100.0 * se / known,
        100.0 * worst_gap
    );
    assert!(
        (mean / known - 1.0).abs() < 0.03,
        "mean {mean} against {known}"
    );
    fdem_figures::record(
        52,
        format!(
            "{:.4} MPa (ratio {:.4}); each run within {:.2} % of its weakest drawn joint",
            mean / 1e6,
            mean / known,
            100.0 * worst_gap
        ),
    );
}

/// The drawn strengths of a scene, as the solver's joint frame gives them, run in a pool of
/// `threads` threads.
fn drawn(dir: &Path, seed: u64, threads: usize) -> (Vec<f64>, Vec<f64>) {
    let p = chain_scene(dir, 8, 6.0, 3e6, seed);
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    v["duration"] = json!(1e-5);
    v["fracture"]["materials"]["link"]["heterogeneity"]["cohesion"] =
        json!({"lognormal": {"mean": 30e6, "cov": 0.2}});
    v["fracture"]["materials"]["link"]
        .as_object_mut()
        .unwrap()
        .remove("cohesion");
    let p = write(dir, &v);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let o = pool.install(|| run(&p));
    let props = o.last_frame.joints.unwrap().properties.unwrap();
    (props.tensile_strength, props.cohesion)
}

#[test]
fn drawn_strengths_are_the_same_bits_on_one_and_two_threads_and_change_with_the_seed() {
    let dir = common::temp_dir("joint-drawn");
    for d in ["a", "b", "c"] {
        std::fs::create_dir_all(dir.join(d)).unwrap();
    }
    let one = drawn(&dir.join("a"), 7, 1);
    let two = drawn(&dir.join("b"), 7, 2);
    let other = drawn(&dir.join("c"), 8, 2);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&one.0), bits(&two.0));
    assert_eq!(bits(&one.1), bits(&two.1));
    // the interface joints: the strength of the joint set's index j is the draw for j
    let h: fdem_fracture::Heterogeneity = serde_json::from_value(json!({
        "seed": 7,
        "tensile_strength": {"weibull": {"modulus": 6.0, "scale": 3e6}},
        "cohesion": {"lognormal": {"mean": 30e6, "cov": 0.2}}
    }))
    .unwrap();
    let base = serde_json::from_value(joint(1.0, 1.0, 50.0)).unwrap();
    let mut links = 0;
    for (j, (&ft, &c)) in one.0.iter().zip(&one.1).enumerate() {
        if ft == 30e6 {
            assert_eq!(c, 60e6, "joint {j}: a strong joint keeps its cohesion");
            continue;
        }
        let d = h.draw(&base, j as u64);
        assert_eq!(
            (ft.to_bits(), c.to_bits()),
            (d.tensile_strength.to_bits(), d.cohesion.to_bits())
        );
        assert_ne!(
            other.0[j], ft,
            "joint {j}: seed 8 draws the same strength as seed 7"
        );
        links += 1;
    }
    assert_eq!(links, 8);
    fdem_figures::record(53, format!("equal; all {links} drawn joints differ"));
}

/// A scene of one body with groups `soft`/`stiff` and an edit; returns the load error.
fn refused(tag: &str, edit: impl FnOnce(&mut Value)) -> String {
    let dir = common::temp_dir(tag);
    strip(&dir, 6, 1, 0.005, |i| match i {
        0..=1 => "soft",
        2..=3 => "stiff",
        _ => "far",
    });
    let mut v = pull_scene(
        json!({"*": bulk(30e9)}),
        json!({
            "regions": [{"groups": ["soft", "stiff"], "material": "strong"}],
            "materials": {"strong": joint(30e6, 60e6, 500.0), "weak": joint(3e6, 6e6, 50.0)},
            "interfaces": [{"groups": ["soft", "stiff"], "material": "weak"}]
        }),
        0.005,
        5e-5,
        1e-5,
    );
    let good = write(&dir, &v);
    driver::load(&good).unwrap_or_else(|e| panic!("{tag}: the base scene is refused: {e}"));
    edit(&mut v);
    let p = write(&dir, &v);
    match driver::load(&p) {
        Ok(_) => panic!("{tag}: accepted"),
        Err(e) => e.to_string(),
    }
}

fn says(e: &str, needles: &[&str]) {
    for n in needles {
        assert!(e.contains(n), "the error lacks {n:?}:\n{e}");
    }
}

#[test]
fn bad_joint_materials_are_refused_with_the_path_and_the_valid_names() {
    let e = refused("jm-modulus", |v| {
        v["fracture"]["materials"]["weak"]
            .as_object_mut()
            .unwrap()
            .remove("tensile_strength");
        v["fracture"]["materials"]["weak"]["heterogeneity"] =
            json!({"seed": 1, "tensile_strength": {"weibull": {"modulus": -2.0, "scale": 3e6}}});
    });
    says(
        &e,
        &[
            "fracture.materials.weak.heterogeneity.tensile_strength.weibull.modulus",
            "-2",
        ],
    );
    let e = refused("jm-both", |v| {
        v["fracture"]["materials"]["weak"]["heterogeneity"] =
            json!({"seed": 1, "cohesion": {"normal": {"mean": 6e6, "cov": 0.1}}});
    });
    says(&e, &["fracture.materials.weak.cohesion", "also drawn"]);
    let e = refused("jm-unknown", |v| {
        v["fracture"]["interfaces"][0]["material"] = json!("weakk");
    });
    says(
        &e,
        &["fracture.interfaces[0].material", "'weakk'", "strong, weak"],
    );
    let e = refused("jm-unknown-region", |v| {
        v["fracture"]["regions"][0]["material"] = json!("rock");
    });
    says(
        &e,
        &["fracture.regions[0].material", "'rock'", "strong, weak"],
    );
    let e = refused("jm-group", |v| {
        v["fracture"]["interfaces"][0]["groups"][1] = json!("right");
    });
    says(
        &e,
        &[
            "fracture.interfaces[0].groups[1]",
            "no surface group",
            "far, soft, stiff",
        ],
    );
    let e = refused("jm-apart", |v| {
        v["fracture"]["regions"][0]["groups"] = json!(["soft", "stiff", "far"]);
        v["fracture"]["interfaces"][0]["groups"] = json!(["soft", "far"]);
    });
    says(
        &e,
        &["fracture.interfaces[0]", "'soft' and 'far'", "do not touch"],
    );
    let e = refused("jm-no-region", |v| {
        v["fracture"]["regions"][0]["groups"] = json!(["far"]);
    });
    says(
        &e,
        &[
            "fracture.interfaces[0]",
            "no fracture region covers either side",
        ],
    );
    // a section without regions explodes nothing: refused as such, before its interfaces
    let e = refused("jm-no-region-at-all", |v| {
        v["fracture"]["regions"] = json!([]);
    });
    says(&e, &["fracture.regions", "has no region"]);
    let e = refused("jm-overlap", |v| {
        v["fracture"]["interfaces"]
            .as_array_mut()
            .unwrap()
            .push(json!({"groups": ["stiff", "soft"], "material": "strong"}));
    });
    says(
        &e,
        &[
            "fracture.interfaces[1]",
            "fracture.interfaces[0] claims too",
        ],
    );
    let e = refused("jm-regions-meet", |v| {
        v["fracture"]["regions"] = json!([
            {"groups": ["soft"], "material": "strong"},
            {"groups": ["stiff"], "material": "weak"}
        ]);
        v["fracture"]["interfaces"] = json!([]);
    });
    says(
        &e,
        &[
            "fracture.regions[1]",
            "no interface",
            "'strong'",
            "'weak'",
            "fracture.interfaces",
        ],
    );
    let e = refused("jm-regions-overlap", |v| {
        v["fracture"]["regions"]
            .as_array_mut()
            .unwrap()
            .push(json!({"groups": ["stiff", "far"], "material": "weak"}));
    });
    says(&e, &["fracture.regions[1]", "overlaps fracture.regions[0]"]);
    let e = refused("jm-no-material", |v| {
        v["fracture"]["regions"][0]
            .as_object_mut()
            .unwrap()
            .remove("material");
    });
    says(
        &e,
        &["fracture.regions[0]", "names no material", "strong, weak"],
    );
    // a drawn strength whose pre-peak work exceeds G_I: the material, the joint and the fix
    let e = refused("jm-drawn-energy", |v| {
        let w = &mut v["fracture"]["materials"]["weak"];
        w.as_object_mut().unwrap().remove("tensile_strength");
        w["fracture_energy_i"] = json!(0.002);
        w["heterogeneity"] =
            json!({"seed": 3, "tensile_strength": {"weibull": {"modulus": 2.0, "scale": 3e6}}});
    });
    says(
        &e,
        &[
            "fracture.materials.weak.heterogeneity",
            "seed 3",
            "fracture_energy_i",
            "penalty_normal",
        ],
    );
}

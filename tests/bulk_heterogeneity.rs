//! Young's modulus drawn per triangle (`bodies[i].materials.GROUP.heterogeneity`;
//! docs/scene-format.md, "Material"; docs/validation.md, "Heterogeneous bulk modulus").
//!
//! - The frame's `young` array is the same bits on one and two threads, is the draw of
//!   `BulkHeterogeneity::young` for each triangle's index, changes with the seed, and follows
//!   the Weibull law (mean, deviation, Kolmogorov-Smirnov distance) on 10 082 triangles.
//! - Uniaxial static tension of a block of drawn moduli: the effective modulus lies between
//!   the Reuss (harmonic) and Voigt (arithmetic) area means of the drawn moduli; with one
//!   modulus it is that modulus.
//! - The stable step of a block of drawn moduli is that of its stiffest triangle.
//! - Bad input is refused with the JSON path.

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::common;
use fdem_solver::input::scene::BulkHeterogeneity;
use fdem_solver::output::FrameData;

/// Cells per side of the square block (2 N^2 = 10 082 triangles).
const N: usize = 71;
/// Side of the block [m], thickness [m], prescribed stretch [m].
const SIDE: f64 = 1.0;
const THICK: f64 = 0.1;
const STRETCH: f64 = 1e-5;
/// Weibull modulus and scale [Pa] of the drawn moduli.
const M: f64 = 3.0;
const SCALE: f64 = 30e9;

/// Writes the block mesh (group `rock`; edge groups `left`, `right`; point group `corner`,
/// the node at the origin) into `dir`.
fn block_mesh(dir: &Path) {
    let (nodes, tris) = common::structured_rectangle(N, N, SIDE, SIDE);
    let id = |i: usize, j: usize| (j * (N + 1) + i) as u32;
    let edges = |i: usize| -> Vec<[u32; 2]> { (0..N).map(|j| [id(i, j), id(i, j + 1)]).collect() };
    let mesh = json!({
        "nodes": nodes,
        "triangles": tris,
        "groups": [
            {"name": "rock", "dim": 2, "triangles": (0..tris.len()).collect::<Vec<_>>()},
            {"name": "left", "dim": 1, "edges": edges(0)},
            {"name": "right", "dim": 1, "edges": edges(N)},
            {"name": "corner", "dim": 0, "nodes": [0]}
        ]
    });
    std::fs::write(dir.join("block.json"), mesh.to_string()).unwrap();
}

/// The rock material with Young's modulus drawn (Weibull `M`, `SCALE`) from `seed`, or the
/// given modulus when `seed` is `None`.
fn rock(seed: Option<u64>) -> Value {
    let mut m = json!({"poisson": 0.2, "density": 2500.0, "plane": "stress"});
    match seed {
        Some(s) => {
            m["heterogeneity"] =
                json!({"seed": s, "young": {"weibull": {"modulus": M, "scale": SCALE}}})
        }
        None => m["young"] = json!(SCALE),
    }
    m
}

/// The block stretched statically by `STRETCH` in x on its right edge (left edge held in x,
/// the corner in y).
fn tension_scene(dir: &Path, rock: Value) -> PathBuf {
    block_mesh(dir);
    let scene = json!({
        "analysis": "static",
        "bodies": [{"mesh": "block.json", "materials": {"rock": rock}, "thickness": THICK}],
        "boundary_conditions": [
            {"fixed": {"group": "left", "x": true}},
            {"fixed": {"group": "corner", "y": true}},
            {"displacement": {"group": "right", "x": STRETCH}}
        ],
        "output": {"frames": 1}
    });
    let p = dir.join("tension.json");
    std::fs::write(&p, scene.to_string()).unwrap();
    p
}

/// The static solve of the tension scene in a pool of `threads` threads: the last frame.
fn solve(tag: &str, rock: Value, threads: usize) -> FrameData {
    let dir = common::temp_dir(tag);
    let p = tension_scene(&dir, rock);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| common::run(&p)).0.last_frame
}

/// The frame's per-cell `young` array, if written.
fn young(f: &FrameData) -> Option<&[f64]> {
    f.extra_cell_scalars
        .iter()
        .find(|(n, _)| n == "young")
        .map(|(_, v)| v.as_slice())
}

/// The effective modulus `F L / (u W t)`: F the x reaction on the held left edge.
fn effective_modulus(f: &FrameData) -> f64 {
    let force: f64 = f
        .reaction
        .iter()
        .zip(&common::reference_points(f))
        .filter(|(_, p)| p[0] == 0.0)
        .map(|(r, _)| r[0])
        .sum();
    -force * SIDE / (STRETCH * SIDE * THICK)
}

#[test]
fn drawn_moduli_are_the_same_bits_on_any_thread_count_and_follow_the_law() {
    let one = solve("young-draw-1", rock(Some(11)), 1);
    let two = solve("young-draw-2", rock(Some(11)), 2);
    let other = solve("young-draw-other", rock(Some(12)), 2);
    let (e1, e2, e3) = (
        young(&one).expect("no young array"),
        young(&two).unwrap(),
        young(&other).unwrap(),
    );
    assert_eq!(e1.len(), 2 * N * N);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(e1), bits(e2), "1 and 2 threads draw different moduli");
    let h: BulkHeterogeneity = serde_json::from_value(
        json!({"seed": 11, "young": {"weibull": {"modulus": M, "scale": SCALE}}}),
    )
    .unwrap();
    for (t, e) in e1.iter().enumerate() {
        assert_eq!(e.to_bits(), h.young(t as u64).to_bits(), "triangle {t}");
    }
    // one material entry: one material id for all its triangles
    assert!(one.material.iter().all(|&m| m == 0), "material ids differ");
    let same = e1.iter().zip(e3).filter(|(a, b)| a == b).count();
    assert_eq!(same, 0, "seed 12 draws {same} moduli of seed 11");
    // Weibull m = 3: mean lambda Gamma(4/3), deviation lambda sqrt(Gamma(5/3) - Gamma(4/3)^2)
    let n = e1.len() as f64;
    let (g1, g2) = (0.892_979_511_569_249_2, 0.902_745_292_950_933_6);
    let (mean, sd) = (SCALE * g1, SCALE * (g2 - g1 * g1).sqrt());
    let m = e1.iter().sum::<f64>() / n;
    let s = (e1.iter().map(|e| (e - m) * (e - m)).sum::<f64>() / (n - 1.0)).sqrt();
    // 4 standard errors: of the mean sd / sqrt(n) (0.36 % of the mean), of the deviation
    // sd sqrt((kurtosis - 1) / (4 n)) with kurtosis 2.729 (0.65 %)
    let (tol_m, tol_s) = (4.0 * sd / n.sqrt(), 4.0 * 0.006_55 * sd);
    println!(
        "mean {m:.5e} (law {mean:.5e}, rel {:.3e}), deviation {s:.5e} (law {sd:.5e}, rel {:.3e})",
        (m - mean) / mean,
        (s - sd) / sd
    );
    assert!(
        (m - mean).abs() < tol_m,
        "mean {m:e} vs {mean:e} +- {tol_m:e}"
    );
    assert!(
        (s - sd).abs() < tol_s,
        "deviation {s:e} vs {sd:e} +- {tol_s:e}"
    );
    // Kolmogorov-Smirnov distance to the law's CDF: below 1.95 / sqrt(n) (level 0.001)
    let mut sorted = e1.to_vec();
    sorted.sort_by(f64::total_cmp);
    let law = fdem_fracture::Distribution::Weibull {
        modulus: M,
        scale: SCALE,
    };
    let d = sorted
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let c = law.cdf(x);
            (c - i as f64 / n).abs().max((c - (i + 1) as f64 / n).abs())
        })
        .fold(0.0, f64::max);
    println!("KS distance {d:.4e} (bound {:.4e})", 1.95 / n.sqrt());
    assert!(d < 1.95 / n.sqrt(), "KS distance {d}");
    fdem_figures::record(
        74,
        format!(
            "identical; mean {:+.2} %, deviation {:+.2} %; KS {d:.2e}",
            100.0 * (m - mean) / mean,
            100.0 * (s - sd) / sd
        ),
    );
}

#[test]
fn the_effective_modulus_of_drawn_moduli_lies_between_reuss_and_voigt() {
    // one modulus: the effective modulus is that modulus (uniform uniaxial stress is exact)
    let uniform = solve("young-uniform", rock(None), 2);
    assert!(young(&uniform).is_none(), "a uniform material writes young");
    let e_u = effective_modulus(&uniform);
    println!(
        "uniform: effective {e_u:.9e} Pa (E {SCALE:e}, rel {:.2e})",
        (e_u - SCALE) / SCALE
    );
    assert!((e_u - SCALE).abs() < 1e-9 * SCALE, "{e_u}");
    // drawn moduli: equal-area triangles, so the bounds are the plain means. The Voigt bound
    // (uniform strain is admissible) holds for the discrete solve exactly; the Reuss bound
    // (uniform stress is admissible) bounds the exact solution, which the displacement
    // solve over-stiffens, so it holds too.
    let f = solve("young-bounds", rock(Some(11)), 2);
    let e = young(&f).unwrap();
    let n = e.len() as f64;
    let voigt = e.iter().sum::<f64>() / n;
    let reuss = n / e.iter().map(|x| 1.0 / x).sum::<f64>();
    let eff = effective_modulus(&f);
    println!(
        "Reuss {reuss:.5e} < effective {eff:.5e} < Voigt {voigt:.5e} Pa \
         (position {:.3})",
        (eff - reuss) / (voigt - reuss)
    );
    assert!(reuss < eff && eff < voigt, "{reuss} {eff} {voigt}");
    // a bound that cannot hold by accident: the drawn field is far from uniform
    assert!(voigt > 1.1 * reuss, "Reuss {reuss} Voigt {voigt}");
    fdem_figures::record(
        75,
        format!(
            "Reuss {:.3} GPa < {:.3} GPa < Voigt {:.3} GPa ({:.2} of the way); uniform {}",
            reuss / 1e9,
            eff / 1e9,
            voigt / 1e9,
            (eff - reuss) / (voigt - reuss),
            fdem_figures::sci((e_u - SCALE) / SCALE, 1)
        ),
    );
}

#[test]
fn only_the_group_with_a_heterogeneity_draws_and_each_group_keeps_one_material_id() {
    // the block's triangles split into `a` (cells left of the middle, drawn) and `b`
    // (uniform): `a` draws for its global indices, `b` keeps its modulus
    let dir = common::temp_dir("young-groups");
    let p = tension_scene(&dir, rock(None));
    let mesh_path = dir.join("block.json");
    let mut mesh: Value =
        serde_json::from_str(&std::fs::read_to_string(&mesh_path).unwrap()).unwrap();
    let in_a = |t: usize| (t / 2) % N < N / 2;
    let (a, b): (Vec<usize>, Vec<usize>) = (0..2 * N * N).partition(|&t| in_a(t));
    mesh["groups"][0] = json!({"name": "b", "dim": 2, "triangles": b});
    mesh["groups"]
        .as_array_mut()
        .unwrap()
        .insert(0, json!({"name": "a", "dim": 2, "triangles": a}));
    std::fs::write(&mesh_path, mesh.to_string()).unwrap();
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    v["bodies"][0]["materials"] = json!({"a": rock(Some(5)), "b": rock(None)});
    std::fs::write(&p, v.to_string()).unwrap();
    let f = common::run(&p).0.last_frame;
    let h: BulkHeterogeneity = serde_json::from_value(
        json!({"seed": 5, "young": {"weibull": {"modulus": M, "scale": SCALE}}}),
    )
    .unwrap();
    let e = young(&f).unwrap();
    for t in 0..2 * N * N {
        let (want, id) = if in_a(t) {
            (h.young(t as u64), 0)
        } else {
            (SCALE, 1)
        };
        assert_eq!(e[t].to_bits(), want.to_bits(), "triangle {t}");
        assert_eq!(f.material[t], id, "triangle {t}");
    }
}

/// The stable step limit [s] of a short dynamic run of the block (left edge held in x).
fn step_limit(tag: &str, rock: Value) -> f64 {
    let dir = common::temp_dir(tag);
    block_mesh(&dir);
    let scene = json!({
        "analysis": "dynamic",
        "bodies": [{"mesh": "block.json", "materials": {"rock": rock}, "thickness": THICK}],
        "boundary_conditions": [{"fixed": {"group": "left", "x": true}}],
        "duration": 3e-6,
        "output": {"frames": 0}
    });
    let p = dir.join("dynamic.json");
    std::fs::write(&p, scene.to_string()).unwrap();
    common::run(&p).0.summary.time_step_limit
}

#[test]
fn the_stable_step_is_that_of_the_stiffest_drawn_triangle() {
    // every triangle of the structured mesh has the same shape, so the element frequency
    // bound scales with sqrt(E): the drawn field's limit is that of a uniform block of the
    // largest drawn modulus
    let e_max = (0..2 * N * N)
        .map(|t| {
            serde_json::from_value::<BulkHeterogeneity>(
                json!({"seed": 11, "young": {"weibull": {"modulus": M, "scale": SCALE}}}),
            )
            .unwrap()
            .young(t as u64)
        })
        .fold(0.0, f64::max);
    let drawn = step_limit("young-step-drawn", rock(Some(11)));
    let mut stiffest = rock(None);
    stiffest["young"] = json!(e_max);
    let uniform = step_limit("young-step-max", stiffest);
    let mean = step_limit("young-step-scale", rock(None));
    println!(
        "step limit: drawn {drawn:.6e} s, uniform E_max = {e_max:.4e} Pa {uniform:.6e} s, \
         uniform E = scale {mean:.6e} s; rel difference {:.2e}",
        (drawn - uniform) / uniform
    );
    assert!(
        (drawn - uniform).abs() <= 1e-12 * uniform,
        "{drawn} vs {uniform}"
    );
    assert!(drawn < 0.9 * mean, "{drawn} vs {mean}");
    fdem_figures::record(
        76,
        format!(
            "{}; {:.2} times shorter than at E = scale",
            fdem_figures::sci(((drawn - uniform) / uniform).abs(), 1),
            mean / drawn
        ),
    );
}

/// The tension scene with the rock material edited; returns the load error.
fn refused(tag: &str, edit: impl FnOnce(&mut Value)) -> String {
    let dir = common::temp_dir(tag);
    let mut r = rock(Some(3));
    edit(&mut r);
    let p = tension_scene(&dir, r);
    match fdem_solver::driver::load(&p) {
        Ok(_) => panic!("{tag}: the scene was accepted"),
        Err(e) => e.to_string(),
    }
}

fn says(e: &str, needles: &[&str]) {
    for n in needles {
        assert!(e.contains(n), "`{n}` not in: {e}");
    }
}

#[test]
fn bad_drawn_moduli_are_refused_with_the_path() {
    let e = refused("young-bad-modulus", |r| {
        r["heterogeneity"]["young"]["weibull"]["modulus"] = json!(0.0)
    });
    says(
        &e,
        &[
            "bodies[0].materials.rock.heterogeneity.young.weibull.modulus",
            "fix:",
        ],
    );
    let e = refused("young-bad-cov", |r| {
        r["heterogeneity"]["young"] = json!({"lognormal": {"mean": 30e9, "cov": -0.1}})
    });
    says(
        &e,
        &["bodies[0].materials.rock.heterogeneity.young.lognormal.cov"],
    );
    let e = refused("young-both", |r| r["young"] = json!(30e9));
    says(
        &e,
        &["bodies[0].materials.rock.young", "also drawn", "remove"],
    );
    let e = refused("young-none", |r| {
        r.as_object_mut().unwrap().remove("heterogeneity");
    });
    says(&e, &["bodies[0].materials.rock", "missing field `young`"]);
    let e = refused("young-unknown", |r| {
        r["heterogeneity"]["poisson"] = json!({"normal": {"mean": 0.2, "cov": 0.1}})
    });
    says(
        &e,
        &[
            "bodies[0].materials.rock.heterogeneity.poisson",
            "unknown field",
        ],
    );
    let e = refused("young-no-seed", |r| {
        r["heterogeneity"].as_object_mut().unwrap().remove("seed");
    });
    says(&e, &["bodies[0].materials.rock.heterogeneity", "seed"]);
}

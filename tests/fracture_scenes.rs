//! Fracture in whole scenes (examples/brazilian-disc-fracture.json): a Brazilian disc
//! (D = 50 mm, t = 10 mm, ring mesh h = R/12, 864 triangles, whole disc fracturing) between two
//! rigid frictionless platens closing at 2 x 0.02 m/s (ramped over 0.1 ms), central difference,
//! no damping, run to 1.65 ms (peak at 1.43 ms, split through at about 1.55 ms). Measured:
//! peak 2P/(pi D t) = 1.000 ft, 28 broken joints with mean |x| = 0.016 R, energy residual
//! -0.019 % of the platens' work. The coarse disc (h = R/8) run to 3 ms, well past the split:
//! residual -0.031 %. A diagonal pair failing in shear under compression: peak within 2.4 % of
//! 2c/(1 - tan(phi)), residual -1.1e-4, no energy jump at the hand-over to contact.

use crate::common;

use crate::plot;

fn csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (head, rows)
}

#[test]
fn brazilian_disc_splits_along_loaded_diameter_at_tensile_strength_with_closed_energy_balance() {
    let scene = common::edited_example("brazilian-disc-fracture.json", "bd-fracture", |_| {});
    let (o, out) = common::run(&scene);
    let (r, d, t, ft) = (0.025, 0.05, 0.01, 3e6);
    // Load: the top platen's force on the disc (negative y); the peak.
    let (h, rows) = csv(&out.join("walls.csv"));
    let col = h.iter().position(|c| c == "force_y[top]").unwrap();
    let ucol = h.iter().position(|c| c == "u_y[top]").unwrap();
    let mut peak = 0.0f64;
    let mut u_peak = 0.0;
    for row in &rows {
        let p = -row[col].parse::<f64>().unwrap();
        if p > peak {
            peak = p;
            u_peak = row[ucol].parse::<f64>().unwrap();
        }
    }
    let sigma = 2.0 * peak / (std::f64::consts::PI * d * t);
    // Broken joints: where.
    let (_, ev) = csv(&out.join("fractures.csv"));
    let xs: Vec<f64> = ev.iter().map(|r| r[1].parse::<f64>().unwrap()).collect();
    let ys: Vec<f64> = ev.iter().map(|r| r[2].parse::<f64>().unwrap()).collect();
    let span =
        ys.iter().fold(f64::MIN, |a, b| a.max(*b)) - ys.iter().fold(f64::MAX, |a, b| a.min(*b));
    let mean_abs_x = xs.iter().map(|x| x.abs()).sum::<f64>() / xs.len().max(1) as f64;
    let e = &o.summary.energy;
    let work = e.supplied;
    let residual = e.error;
    eprintln!(
        "brazilian disc: peak P = {peak:.1} N at platen displacement {u_peak:.3e} m; 2P/(pi D t) = {:.4e} Pa = {:.4} ft; broken joints {} , mean |x| = {:.4} R; energy: work {:.4e} J, kinetic {:.3e}, strain {:.3e}, contact+joints stored {:.3e}, fracture+friction dissipated {:.3e}, residual {:.3e} ({:.3e} of work); stages {}",
        sigma,
        sigma / ft,
        xs.len(),
        mean_abs_x / r,
        work,
        e.kinetic,
        e.strain,
        e.stored,
        e.friction + e.fracture + e.switch_loss,
        residual,
        residual / work,
        o.summary.stages
    );
    // FDEM_DOCS_IMG=1: draw the load-displacement curve into docs/img/.
    if std::env::var_os("FDEM_DOCS_IMG").is_some() {
        let points = rows
            .iter()
            .map(|row| {
                (
                    -2e3 * row[ucol].parse::<f64>().unwrap(),
                    -1e-3 * row[col].parse::<f64>().unwrap(),
                )
            })
            .collect();
        let p = plot::Plot {
            title: "Brazilian disc, D = 50 mm, t = 10 mm, ft = 3 MPa: platen load".into(),
            x_label: "platen closure [mm]".into(),
            y_label: "load P [kN]".into(),
            x_scale: plot::Scale::Linear,
            y_scale: plot::Scale::Linear,
            series: vec![plot::Series {
                name: "fdem (h = R/12, 2 x 0.02 m/s)".into(),
                points,
            }],
            y_range: None,
            lines: true,
        };
        p.write(&common::root().join("docs/img/brazilian-disc-fracture-load"))
            .unwrap();
    }
    // Splits along the loaded (vertical) diameter.
    assert!(xs.len() >= 10, "only {} joints broke", xs.len());
    assert!(
        mean_abs_x < 0.15 * r,
        "mean |x| of broken joints {mean_abs_x}"
    );
    // ... and the crack runs through: broken joints span at least 1.6 R of the diameter.
    assert!(span > 1.6 * r, "crack spans {span} m");
    // Peak load: 2P/(pi D t) within 15 % of ft.
    assert!((sigma / ft - 1.0).abs() < 0.15, "2P/(pi D t) = {sigma}");
    // The run's result block says the same, from its own files: failed, this peak, this
    // Brazilian stress (a disc), these broken joints and their extent.
    let res = o.summary.result.as_ref().expect("a result block");
    assert_eq!(res.failed, Some(true));
    assert_eq!(res.peak_load, Some(peak));
    let sp = res.specimen.as_ref().expect("a specimen between platens");
    assert_eq!(sp.shape, "disc");
    assert!((sp.width - d).abs() < 1e-9 && (sp.thickness - t).abs() < 1e-12);
    assert!((sp.peak_stress.unwrap() / sigma - 1.0).abs() < 1e-9);
    assert!((sp.strain_at_peak.unwrap() - 2.0 * u_peak.abs() / d).abs() < 1e-12);
    assert_eq!(sp.modulus, None);
    assert_eq!(res.broken_joints, xs.len());
    let by = res.broken_by_mode;
    assert_eq!(by.i + by.ii + by.mixed, xs.len());
    let ext = res.crack_extent.unwrap();
    assert!((ext.y[1] - ext.y[0] - span).abs() < 1e-12);
    fdem_figures::record_part(
        145,
        1,
        format!(
            "disc: failed, {:.4} MPa = the test's, {} joints (I {}, II {}, mixed {})",
            1e-6 * sp.peak_stress.unwrap(),
            res.broken_joints,
            by.i,
            by.ii,
            by.mixed
        ),
    );
    // Energy balance closes within 2 % of the work of the platens.
    assert!(
        (residual / work).abs() < 0.02,
        "residual {residual} of {work}"
    );
    fdem_figures::record(
        42,
        format!(
            "{peak:.0} N, {:.3} ft; split along the loaded diameter",
            sigma / ft
        ),
    );
    fdem_figures::record_part(43, 1, format!("{:.1e} (to 1.65 ms)", residual / work));
}

/// The same disc on the coarse ring mesh (h = R/8, 384 triangles, `meshes/disc-small.msh`) run
/// to 3 ms, well past the split (about 1.6 ms): the halves separate and keep being pressed by
/// the platens. Before the shear secant history (docs/fracture.md section 3) this run created
/// energy after the split (kinetic energy above the platens' work, negative joint
/// dissipation); now the balance closes.
#[test]
fn brazilian_disc_run_well_past_the_split_closes_the_energy_balance_within_2_percent() {
    let scene = common::edited_example("brazilian-disc-fracture.json", "bd-long", |v| {
        v["bodies"][0]["mesh"] = serde_json::Value::String(
            common::root()
                .join("meshes/disc-small.msh")
                .display()
                .to_string(),
        );
        v["duration"] = serde_json::json!(3e-3);
        v["output"]["frames"] = serde_json::json!(0);
    });
    let (o, out) = common::run(&scene);
    let r = 0.025;
    let (_, ev) = csv(&out.join("fractures.csv"));
    let xs: Vec<f64> = ev.iter().map(|r| r[1].parse::<f64>().unwrap()).collect();
    let t_last = ev
        .iter()
        .map(|r| r[0].parse::<f64>().unwrap())
        .fold(0.0, f64::max);
    let mean_abs_x = xs.iter().map(|x| x.abs()).sum::<f64>() / xs.len().max(1) as f64;
    let e = &o.summary.energy;
    let work = e.supplied;
    let fr = &o.summary.stages["fracture"];
    let diss = fr["dissipated"].as_f64().unwrap();
    let jump = o.summary.stages["contact"]["switch_jump"].as_f64().unwrap();
    eprintln!(
        "brazilian disc R/8 to 3 ms: {} broken joints (last at {t_last:.4e} s), mean |x| = {:.4} R; work {work:.4e} J, kinetic {:.4e}, strain {:.4e}, stored {:.4e}, dissipated {:.4e} (fracture {diss:.4e}), switch jump {jump:.3e}, residual {:.3e} ({:.3e} of work)",
        xs.len(),
        mean_abs_x / r,
        e.kinetic,
        e.strain,
        e.stored,
        e.friction + e.fracture + e.switch_loss,
        e.error,
        e.error / work
    );
    assert!(xs.len() >= 5, "only {} joints broke", xs.len());
    assert!(
        mean_abs_x < 0.15 * r,
        "mean |x| of broken joints {mean_abs_x}"
    );
    // fracture dissipates, never creates; the kinetic energy stays below the platens' work
    assert!(
        diss > 0.0 && e.kinetic < work,
        "dissipated {diss}, kinetic {}",
        e.kinetic
    );
    // the balance closes within 2 % of the platens' work
    assert!(
        (e.error / work).abs() < 0.02,
        "residual {} of {work}",
        e.error
    );
    fdem_figures::record_part(
        43,
        2,
        format!("{:.1e} (coarse disc to 3 ms)", e.error / work),
    );
}

#[test]
fn diagonal_pair_fails_in_shear_under_compression_and_hands_over_to_contact_with_closed_balance() {
    // The pair of `common::diagonal_pair_scene`: 10 mm square cut along its diagonal, joint
    // penalty 300 GPa, platen at 0.02 m/s.
    let scene = common::diagonal_pair_scene(
        "pair-handover",
        &common::PairScene {
            penalty: 300e9,
            speed: 0.02,
            ramp: 1e-4,
            safety: 0.9,
            duration: 1.5e-3,
            frames: 0,
            every: 20,
        },
    );
    let (o, out) = common::run(&scene);
    let (l, t, c, tan_phi) = (0.01, 0.01, 1e6, 30f64.to_radians().tan());
    let (h, rows) = csv(&out.join("walls.csv"));
    let col = h.iter().position(|c| c == "force_y[top]").unwrap();
    let peak = rows
        .iter()
        .map(|r| -r[col].parse::<f64>().unwrap())
        .fold(0.0, f64::max);
    let sigma_peak = peak / (l * t);
    let expected = 2.0 * c / (1.0 - tan_phi);
    let (_, ev) = csv(&out.join("fractures.csv"));
    let e = &o.summary.energy;
    let work = e.supplied;
    let st = &o.summary.stages;
    let jump = st["contact"]["switch_jump"].as_f64().unwrap();
    let released = st["fracture"]["released_at_break"].as_f64().unwrap();
    let diss = st["fracture"]["dissipated"].as_f64().unwrap();
    let g_area = 10.0 * 2f64.sqrt() * l * t;
    eprintln!(
        "pair: peak platen stress {sigma_peak:.4e} Pa (2c/(1 - tan phi) = {expected:.4e}); events {ev:?}; work {work:.4e} J, kinetic {:.3e}, strain {:.3e}, stored {:.3e}, dissipated {:.4e} (fracture {diss:.4e} = {:.4} G_II A), released at break {released:.3e}, switch jump {jump:.3e} J, residual {:.3e} ({:.2e} of work)",
        e.kinetic,
        e.strain,
        e.stored,
        e.friction + e.fracture + e.switch_loss,
        diss / g_area,
        e.error,
        e.error / work
    );
    assert_eq!(ev.len(), 1, "the joint breaks once");
    assert_eq!(ev[0][3], "II");
    // the shear failure of the diagonal at 2c/(1 - tan phi) = 4.73 MPa: within 10 % (the
    // loading is dynamic and the joint's pre-peak curve softens the response)
    assert!(
        (sigma_peak / expected - 1.0).abs() < 0.1,
        "peak {sigma_peak} vs {expected}"
    );
    // fracture dissipation: G_II times the diagonal's area when sigma stays constant; here fs
    // and with it s_p and the softening width change with the compression while the joint
    // softens: measured 1.24 G_II A; at least G_II A, at most 1.3 G_II A
    assert!(
        diss / g_area > 1.0 && diss / g_area < 1.3,
        "{diss} vs {g_area}"
    );
    // it broke open: the faces reach contact without overlap, no energy jump
    assert!(jump.abs() <= 1e-9 * work, "jump {jump}");
    // the balance closes: the ledger's error (the hand-over's energy jump is on its books,
    // in `switch_loss`) within 1e-3 of the work
    assert!(
        (e.error / work).abs() < 1e-3,
        "residual {} jump {jump} of work {work}",
        e.error
    );
    fdem_figures::record(
        44,
        format!(
            "mode II break, energy jump {} of the work, ledger {}",
            fdem_figures::sci(jump / work, 1),
            fdem_figures::sci(e.error / work, 1)
        ),
    );
}

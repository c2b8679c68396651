//! Dynamic relaxation of the elastic Brazilian disc (examples/brazilian-disc-relaxation.json:
//! central difference, mass-proportional damping near critical for the lowest mode) converges
//! to the static solve of the same scene: centre tensile stress and pole displacement within
//! 0.5 % (the relaxation uses the finite-strain law, the static solve small strain: they differ
//! at O(strain) = 3e-3 near the loaded arcs).

use crate::common;

use common::{centroids, recovered_stress};

#[test]
fn disc_relaxation_converges_to_the_static_solve() {
    let dr = common::edited_example("brazilian-disc-relaxation.json", "disc-dr", |v| {
        v["output"]["frames"] = 0.into();
    });
    let (o_dr, _) = common::run(&dr);
    assert_eq!(o_dr.summary.converged, Some(true));
    let st = common::edited_example("brazilian-disc-elastic.json", "disc-dr-static", |_| {});
    let (o_st, _) = common::run(&st);
    let centre =
        |f: &fdem_solver::output::FrameData| recovered_stress(f, &centroids(f), [0.0, 0.0], 30)[0];
    let (c_dr, c_st) = (centre(&o_dr.last_frame), centre(&o_st.last_frame));
    let top = |f: &fdem_solver::output::FrameData| {
        f.displacement
            .iter()
            .map(|d| d[1])
            .fold(f64::INFINITY, f64::min)
    };
    let (u_dr, u_st) = (top(&o_dr.last_frame), top(&o_st.last_frame));
    let (ec, eu) = ((c_dr / c_st - 1.0).abs(), (u_dr / u_st - 1.0).abs());
    eprintln!(
        "disc relaxation: {} steps; centre sxx {c_dr:.6e} vs static {c_st:.6e} ({ec:.2e}); largest downward displacement {u_dr:.6e} vs {u_st:.6e} ({eu:.2e})",
        o_dr.summary.steps
    );
    assert!(ec < 5e-3 && eu < 5e-3);
    fdem_figures::record(10, format!("{ec:.1e}, {eu:.1e}"));
}

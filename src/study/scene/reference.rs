//! The errors of the stable runs: against the scene's analytical answer, and against the
//! reference run (the highest-order scheme at the smallest fraction).
//!
//! - `error_vs_reference`: `max_i |u_i - u_ref,i| / max_i |u_ref,i|` over the nodes at the
//!   final time, against the reference run (OMF32 at the smallest fraction when run);
//! - `error_analytical`, when the side file declares an analytical answer (bar arrival, first
//!   frequency: [`super::side_file`]);
//! - `error_measure` (and `error_measure2`), when the side file declares a measure without an
//!   analytical value (collision, fracture), against the reference run's.
//!
//! The primary `error` is the analytical one when declared, else the measure's when declared,
//! else the displacements' against the reference.

use fdem_time::SchemeKind;

use super::runs::{Raw, Run};
use super::side_file::Analytical;

/// The reference scheme: the highest-order one run. (OMF32 when it is run: of the
/// fourth-order schemes its error constant is by far the smallest, 2e-8 against 2e-6 for CHIN
/// and Forest & Ruth on the oscillator, docs/time-integration.md.)
pub(super) fn reference_scheme(kinds: &[SchemeKind]) -> SchemeKind {
    if kinds.contains(&SchemeKind::Omf32) {
        SchemeKind::Omf32
    } else {
        kinds
            .iter()
            .copied()
            .max_by_key(|k| k.measured_order())
            .unwrap_or(SchemeKind::ForestRuth)
    }
}

/// The errors of the stable runs against the reference run (`ref_kind` at the smallest
/// fraction `f_min`, when it is stable) and each run's primary `error`.
pub(super) fn errors(
    mut raws: Vec<Raw>,
    ref_kind: SchemeKind,
    f_min: f64,
    analytical: Option<&Analytical>,
) -> Vec<Run> {
    let ref_raw = raws
        .iter()
        .find(|r| r.run.scheme == ref_kind.name() && r.run.fraction == f_min && r.run.stable);
    let reference = ref_raw.map(|r| r.displacement.clone());
    let (m_ref, m2_ref) = ref_raw
        .map(|r| (r.run.measured, r.run.measured2))
        .unwrap_or((None, None));
    let by_measure = analytical.is_some_and(|a| !a.is_analytical());
    if by_measure {
        for r in raws.iter_mut().filter(|r| r.run.stable) {
            if let (Some(m), Some(mr)) = (r.run.measured, m_ref) {
                r.run.error_measure = Some((m - mr).abs() / mr.abs().max(f64::MIN_POSITIVE));
            }
            if let Some(Analytical::Fracture { .. }) = analytical
                && let (Some(c), Some(cr)) = (r.run.measured2, m2_ref)
            {
                r.run.error_measure2 = Some((c - cr).abs());
            }
        }
    }
    if let Some(u_ref) = &reference {
        let scale = u_ref
            .iter()
            .map(|u| u[0].abs().max(u[1].abs()))
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        for r in raws.iter_mut().filter(|r| r.run.stable) {
            let d = r
                .displacement
                .iter()
                .zip(u_ref)
                .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
                .fold(0.0, f64::max);
            r.run.error_vs_reference = Some(d / scale);
        }
    }
    raws.into_iter()
        .map(|mut r| {
            r.run.error = if by_measure {
                r.run.error_measure
            } else if analytical.is_some() {
                r.run.error_analytical
            } else {
                r.run.error_vs_reference
            };
            r.run
        })
        .collect()
}

//! The ladder of steps: each scheme at the listed fractions of its predicted stable step,
//! then up a ladder of larger ones until one is unstable.
//!
//! When every listed fraction is stable, the study goes on at `r x` 0.5, 0.7, 0.9, 1, 1.1,
//! 1.2, 1.35, 1.5, 1.75, 2, 2.25, 2.5, 3, 3.5, 4, 5, 6, 8, 10, 12 and 16 (the first above the
//! last fraction run; `r = h_active / h_pred` the active prediction over the a-priori one,
//! [`super::active`], 1 without contact) until one is not: the observed limit lies between
//! the largest stable fraction and the first unstable one. The stability probes
//! ([`super::probes`]) run from 0.99 of the predicted step up, until one is unstable (after
//! that every fraction counts unstable).
//!
//! Schemes that are stable again in a window above their limit (PC-4, OMF30, OMF32) also get
//! **band probes**: at the steps that put the measured top frequency into their first
//! unstable band, `h omega_top = L (1 + j (W/L - 1)/2)`, `j = -1, 0, 1`, with `L` the limit
//! and `W` the start of the window ([`band_fractions`]); they join the list, or the ladder,
//! in order. The band above OMF32's limit is only 1.2 % wide (spectral radius up to 1.019
//! per step): on a scene whose top modes sit above a gap in the spectrum (the collision's
//! and the fracture disc's contact modes) a ladder of fractions steps over it and the scheme
//! reads stable up to its window's end, 1.8 times past its limit, although every step that
//! puts the top mode in the band is unstable. The observed limit is the first instability
//! as the step grows, so the band is looked for.

use std::path::Path;

use anyhow::Result;
use fdem_time::SchemeKind;
use indicatif::ProgressBar;
use serde::Serialize;

use super::Study;
use super::probes::{Probe, stability_probe};
use super::runs::{Raw, one_run};

/// Fractions tried after the list when all of it was stable, to find the observed limit: these
/// times `r = h_active / h_pred` (the active prediction over the a-priori one; 1 without
/// contact), the first one above the last fraction run, and on until one is unstable. (Beyond
/// 3: the weakly unstable schemes, whose growth a short contact does not show.)
const PROBES: [f64; 21] = [
    0.5, 0.7, 0.9, 1.0, 1.1, 1.2, 1.35, 1.5, 1.75, 2.0, 2.25, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 8.0,
    10.0, 12.0, 16.0,
];

/// Per scheme: predicted and observed stable steps.
#[derive(Clone, Debug, Serialize)]
pub(super) struct Limit {
    pub(super) scheme: String,
    pub(super) dt_predicted: f64,
    /// Largest stable fraction tried.
    pub(super) observed_at_least: f64,
    /// Smallest unstable fraction tried (None: none found up to the last probe).
    pub(super) observed_below: Option<f64>,
    /// Stability probes ([`stability_probe`]).
    pub(super) probes: Vec<Probe>,
    /// The active predicted step `h_pred r` [s] (`r` = [`Active::ratio`](super::active::Active::ratio), 1 without contact).
    pub(super) dt_active: f64,
    /// The observed limit over the active prediction: `observed_at_least / r`.
    pub(super) observed_over_active_at_least: f64,
    /// `observed_below / r`.
    pub(super) observed_over_active_below: Option<f64>,
}

/// Runs scheme `k` up its ladder of steps from the listed `fractions` (sorted), pushing each
/// run onto `raws`; returns its observed limit.
pub(super) fn scheme_ladder(
    study: &Study,
    k: SchemeKind,
    fractions: &[f64],
    bar: &ProgressBar,
    raws: &mut Vec<Raw>,
) -> Result<Limit> {
    let run_dir = |f: f64| study.out.join("runs").join(format!("{}-{f}", k.name()));
    let mut lad = Ladder::new(k, fractions);
    let mut i = 0;
    while i < lad.list.len() {
        let f = lad.list[i];
        bar.set_message(format!("{} at {f} h_pred", k.name()));
        let r = one_run(&study.scene, k, f, &run_dir(f), study.analytical.as_ref())?;
        // The measured-stability probe from 0.99 up, until one is unstable.
        let probe_stable = if f >= 0.99 && lad.probes_stable() {
            let probe = probe_at(study, k, f, &run_dir(f), lad.band.is_some(), bar)?;
            let added = lad.add_band(i, f, probe.omega_probe, r.run.dt_predicted);
            bar.inc_length(added as u64);
            let ok = probe.stable;
            lad.probes.push(probe);
            ok
        } else {
            lad.probes_stable()
        };
        lad.record(f, r.run.stable && probe_stable);
        raws.push(r);
        bar.inc(1);
        i += 1;
        if i == lad.list.len()
            && lad.first_unstable.is_none()
            && let Some(p) = lad.next_rung(f, study.r_active)
        {
            lad.list.push(p);
            bar.inc_length(1);
        }
        // past the first instability only the listed fractions still run (their errors)
        if lad.first_unstable.is_some() && lad.list[i..].iter().all(|x| !fractions.contains(x)) {
            break;
        }
    }
    let dt_predicted = raws.last().map(|r| r.run.dt_predicted).unwrap_or(0.0);
    let r_active = study.r_active;
    Ok(Limit {
        scheme: k.name().into(),
        dt_predicted,
        observed_at_least: lad.last_stable,
        observed_below: lad.first_unstable,
        probes: lad.probes,
        dt_active: dt_predicted * r_active,
        observed_over_active_at_least: lad.last_stable / r_active,
        observed_over_active_below: lad.first_unstable.map(|b| b / r_active),
    })
}

/// The stability probes of scheme `k` at fraction `f` into `dir`: the top-mode probe and,
/// for a scheme with stable `windows` above its limit whose top-mode probe is stable, the
/// broadband one; stable when both are.
fn probe_at(
    study: &Study,
    k: SchemeKind,
    f: f64,
    dir: &Path,
    windows: bool,
    bar: &ProgressBar,
) -> Result<Probe> {
    bar.set_message(format!("{} at {f} h_pred (stability probe)", k.name()));
    let start = study.start.as_ref();
    let top = stability_probe(
        &study.scene,
        k,
        f,
        &dir.join("probe"),
        start,
        study.amplitude,
        false,
    )?;
    let broad = if top.stable && windows {
        bar.set_message(format!("{} at {f} h_pred (broadband probe)", k.name()));
        Some(stability_probe(
            &study.scene,
            k,
            f,
            &dir.join("probe-broad"),
            start,
            study.amplitude,
            true,
        )?)
    } else {
        None
    };
    let ok = top.stable && broad.as_ref().is_none_or(|b| b.stable);
    Ok(Probe {
        fraction: f,
        stable: ok,
        ratio: top.ratio,
        broad_ratio: broad.and_then(|b| b.ratio),
        omega_probe: top.omega,
    })
}

/// One scheme's way up: the fractions to run, the probes so far and the verdicts.
struct Ladder<'a> {
    /// The listed fractions (sorted).
    listed: &'a [f64],
    /// The fractions to run: the listed ones, then the band and ladder fractions added.
    list: Vec<f64>,
    /// The scheme's first unstable band `[L, W]` (schemes stable again above their limit).
    band: Option<[f64; 2]>,
    /// Whether the band fractions were placed (once, at the first probe).
    band_added: bool,
    /// Band fractions above the listed ones, tried in order with the ladder.
    pending: Vec<f64>,
    probes: Vec<Probe>,
    /// The largest fraction below which every fraction tried is stable.
    last_stable: f64,
    first_unstable: Option<f64>,
}

impl<'a> Ladder<'a> {
    fn new(k: SchemeKind, listed: &'a [f64]) -> Self {
        // a scheme stable again above its limit also gets a broadband probe, and probes at
        // the steps that put the measured top mode into its unstable band
        let band = fdem_time::stability::stable_windows(k, 8.0)
            .first()
            .map(|w| [k.stability_limit(), w[0]]);
        Self {
            listed,
            list: listed.to_vec(),
            band,
            band_added: false,
            pending: Vec::new(),
            probes: Vec::new(),
            last_stable: 0.0,
            first_unstable: None,
        }
    }

    /// Whether every probe so far is stable.
    fn probes_stable(&self) -> bool {
        self.probes.iter().all(|p| p.stable)
    }

    /// At the first probe (run `i`, fraction `f`, measured top frequency `omega_top`,
    /// predicted step `h_pred`): the band fractions among the listed ones join the list after
    /// `i`, the others wait for the ladder. Returns how many joined the list.
    fn add_band(&mut self, i: usize, f: f64, omega_top: f64, h_pred: f64) -> usize {
        let Some(b) = self.band.filter(|_| !self.band_added) else {
            return 0;
        };
        self.band_added = true;
        let last = self.listed.last().copied().unwrap_or(f);
        let (now, later): (Vec<f64>, Vec<f64>) = band_fractions(b, omega_top, h_pred)
            .into_iter()
            .partition(|x| *x < last);
        let added = insert_fractions(&mut self.list, i + 1, &now, f);
        self.pending = later;
        added
    }

    /// The verdict at `f`: the observed limit is the largest fraction below which every
    /// fraction tried is stable (a stable run above an unstable one does not count: on the
    /// fracture disc the scene runs' verdicts past the first unstable step are erratic).
    fn record(&mut self, f: f64, stable: bool) {
        if stable {
            if self.first_unstable.is_none() {
                self.last_stable = self.last_stable.max(f);
            }
        } else if self.first_unstable.is_none() {
            self.first_unstable = Some(f);
        }
    }

    /// The next fraction above `f` when the list is done and all of it stable: the next rung
    /// of [`PROBES`] (times `r_active`, rounded to 4 digits: a readable fraction in the tables
    /// and file names) or the next pending band fraction, whichever is smaller.
    fn next_rung(&self, f: f64, r_active: f64) -> Option<f64> {
        let ladder = PROBES
            .iter()
            .map(|p| (p * r_active * 1e4).round() / 1e4)
            .find(|p| *p > f * 1.0001);
        let band_next = self.pending.iter().copied().find(|p| *p > f * 1.0001);
        match (ladder, band_next) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }
}

/// The fractions of the predicted step `h_pred` that put the probed state's measured top
/// frequency `omega_top` into a scheme's first unstable band `(L, W)` (from its limit `L` to
/// the start `W` of its first stable window): `h omega_top = L (1 + j (W/L - 1) / 2)` for
/// `j = -1, 0, 1`, rounded to 4 digits. The Rayleigh estimate is at most the true top
/// frequency `omega_true = omega_top (1 + delta)`, and within about 1 % of it after 40 power
/// iterations; the three points put the true top mode in the band for every `delta` in
/// `[0, 1.5 (W/L - 1)]` (OMF32's band is 1.2 % wide, its spectral radius there up to 1.019 per
/// step). Without them the ladder of fractions steps over so narrow a band, and on a scene
/// whose top modes sit above a gap in the spectrum such a scheme is then seen stable up to
/// its window's end.
pub(super) fn band_fractions(band: [f64; 2], omega_top: f64, h_pred: f64) -> Vec<f64> {
    let [l, w] = band;
    if !(omega_top > 0.0 && h_pred > 0.0 && w > l) {
        return Vec::new();
    }
    [-1.0, 0.0, 1.0]
        .iter()
        .map(|j| {
            let hw = l * (1.0 + j * (w / l - 1.0) / 2.0);
            (hw / (omega_top * h_pred) * 1e4).round() / 1e4
        })
        .collect()
}

/// Inserts the fractions of `extra` above `after` into the sorted tail `list[from..]`, leaving
/// out those within 1e-4 of one already listed; returns how many it inserted.
pub(super) fn insert_fractions(
    list: &mut Vec<f64>,
    from: usize,
    extra: &[f64],
    after: f64,
) -> usize {
    let mut added = 0;
    for &x in extra {
        if x <= after * 1.0001 || list.iter().any(|y| (x - y).abs() <= 1e-4 * y.abs()) {
            continue;
        }
        let at = from + list[from..].partition_point(|y| *y < x);
        list.insert(at, x);
        added += 1;
    }
    added
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OMF32's band: the middle point and the upper one put `h omega_top` inside `(L, W)`,
    /// the lower one half a band below `L` (to 4-digit rounding of the fraction, 1e-4
    /// relative).
    #[test]
    fn band_fractions_put_the_top_mode_in_the_unstable_band() {
        let k = SchemeKind::Omf32;
        let w = fdem_time::stability::stable_windows(k, 8.0)[0][0];
        let l = k.stability_limit();
        let (omega_top, h_pred) = (1.819e6, l / 3.135e6);
        let f = band_fractions([l, w], omega_top, h_pred);
        let hw: Vec<f64> = f.iter().map(|f| f * h_pred * omega_top).collect();
        assert_eq!(hw.len(), 3);
        assert!((hw[0] / (l - 0.5 * (w - l)) - 1.0).abs() < 1e-4, "{hw:?}");
        assert!(hw[1] > l && hw[1] < w && hw[2] > l && hw[2] < w, "{hw:?}");
        // the collision's figures: the band lies 1.72 times above the predicted step
        assert!((f[1] - 3.135 / 1.819).abs() < 1e-3, "{f:?}");
    }

    #[test]
    fn inserted_fractions_keep_the_list_sorted_and_skip_duplicates() {
        let mut list = vec![0.1, 0.99, 1.01, 1.05];
        let n = insert_fractions(&mut list, 2, &[1.3, 1.02, 1.01, 0.5], 0.99);
        assert_eq!(n, 2);
        assert_eq!(list, vec![0.1, 0.99, 1.01, 1.02, 1.05, 1.3]);
        assert!(band_fractions([3.0, 2.0], 1.0, 1.0).is_empty());
    }
}

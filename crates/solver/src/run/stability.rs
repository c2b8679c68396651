//! The run's stability checks ([`StabilityGuard`]): every [`CHECK_EVERY`] steps and at the
//! last step, a stage's error, non-finite values and energy growth stop the run with an
//! `Unstable` error that names the cause and the fix ([`crate::diagnosis`]).
//!
//! Energy growth: the mechanical energy `E = K + U + stored (contact, joints)` may not exceed
//! the energy supplied `S = E_0 + |W_loads + W_gravity| + |W_supports| + |W_walls| +
//! K_prescribed` (damping, friction and fracture only remove energy) by more than the
//! step-synchronisation factor: `E > 2 S / (1 - (h / h_limit)^2)` while `E` grew since the
//! last check stops the run, long before an unstable mode overflows, with a message naming
//! the scheme, the step, the predicted limit and the fix ([`energy_growth`]).

use fdem_time::SchemeKind;

use super::observer::{Flow, Halt, Observer, RunView};
use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::diagnosis::Found;
use crate::error::RunError;
use crate::ledger::kinetic_energy;
use crate::stages::summed_report;
use crate::summary::{QuasiStatic, Summary};

/// Steps between two stability checks (and two residual checks of a relaxation).
pub const CHECK_EVERY: u64 = 100;

/// The stability checks: a stage's error, non-finite positions or velocities, energy growth;
/// and a scan for triangles turned inside out (the likely cause of what follows).
pub struct StabilityGuard {
    /// The mechanical energy at the last check [J].
    e_prev: f64,
    /// Energy below which a prestressed scene's growth is round-off [J]: 1e-12 of the
    /// initial stresses' energy scale (0 without initial stress).
    floor: f64,
    /// The quasi-static indicator so far (dynamic analyses).
    indicator: Option<Indicator>,
}

/// The quasi-static indicator's samples: `[t, K, U + S]` at each check (dynamic analyses),
/// reduced at the end by [`indicator`].
#[derive(Debug, Clone, Default)]
struct Indicator {
    samples: Vec<[f64; 3]>,
}

impl StabilityGuard {
    /// A guard; its first check compares against the initial energy.
    pub fn new() -> Self {
        Self {
            e_prev: 0.0,
            floor: 0.0,
            indicator: None,
        }
    }
}

impl Default for StabilityGuard {
    fn default() -> Self {
        Self::new()
    }
}

impl Observer for StabilityGuard {
    fn start(&mut self, run: &mut RunView) -> Result<(), Halt> {
        self.e_prev = run.ledger.initial();
        self.floor = 1e-12 * run.sys.elements.initial_stress_energy_scale();
        let scene = &run.loaded.scene;
        if scene.analysis == crate::scene::Analysis::Dynamic {
            // one sample per check: allocated once
            let checks = run.loaded.n_steps / CHECK_EVERY + 2;
            self.indicator = Some(Indicator {
                samples: Vec::with_capacity(checks.min(1 << 20) as usize),
            });
        }
        Ok(())
    }

    fn after_step(&mut self, run: &mut RunView) -> Result<Flow, Halt> {
        if !(run.step.is_multiple_of(CHECK_EVERY) || run.last) {
            return Ok(Flow::Continue);
        }
        let (sys, state) = (&*run.sys, run.state);
        run.inversions
            .scan(&sys.model, state.x_nodes(), run.step, state.t);
        if let Some(message) = crate::stages::first_error(sys) {
            return Err(Halt::Unstable(Found::Stage(message)));
        }
        if !state.x.iter().all(|v| v.is_finite()) || !state.v.iter().all(|v| v.is_finite()) {
            return Err(Halt::Unstable(Found::NonFinite));
        }
        let (stored, walls) =
            summed_report(sys, state.x_nodes()).map_or((0.0, 0.0), |r| (r.stored, r.wall_work));
        let kinetic = kinetic_energy(&run.ledger.mass_dof, &state.v);
        let strain = sys.elements.strain_energy(state.x_nodes());
        let mut e_now = kinetic + strain + stored;
        let mut supplied = run.ledger.supplied_bound(&sys.model, state, walls);
        if sys.elements.prestressed() {
            // the initial stresses' energy S0 : E is first order in the displacement and
            // of either sign: the growth check takes the elastic part and counts its
            // magnitude as supplied (an excavation draws on it); a body at rest in its
            // initial stress moves by round-off only, below the floor
            let w0 = sys.elements.initial_stress_energy(state.x_nodes());
            e_now -= w0;
            supplied += w0.abs() + self.floor;
        }
        if let Some(ind) = &mut self.indicator {
            let k_free = kinetic - run.ledger.k_prescribed(&state.v);
            ind.samples.push([state.t, k_free, strain + stored]);
        }
        if let Some(message) = energy_growth(
            e_now,
            self.e_prev,
            supplied,
            run.loaded.scheme,
            run.control.h_step(),
            run.control.h_limit(),
            run.step.saturating_sub(CHECK_EVERY),
        ) {
            return Err(Halt::Unstable(Found::EnergyGrowth(message)));
        }
        self.e_prev = e_now;
        Ok(Flow::Continue)
    }

    fn finish(&mut self, run: &mut RunView, summary: &mut Summary) -> Result<(), RunError> {
        let scene = &run.loaded.scene;
        summary.quasi_static = self.indicator.as_ref().map(|i| {
            let mut q = indicator(&i.samples);
            warn(scene, &mut q);
            q
        });
        Ok(())
    }

    fn stopped(&mut self, summary: &mut Summary) {
        summary.quasi_static = self.indicator.as_ref().map(|i| indicator(&i.samples));
    }

    fn save(&mut self, e: &mut Enc) -> Result<(), RunError> {
        e.put(&[self.e_prev, self.floor]);
        if let Some(i) = &self.indicator {
            e.put(&i.samples);
        }
        Ok(())
    }

    fn restore(&mut self, run: &mut RunView, d: &mut Dec) -> Result<(), DecodeError> {
        [self.e_prev, self.floor] = d.get()?;
        if run.loaded.scene.analysis == crate::scene::Analysis::Dynamic {
            let mut samples: Vec<[f64; 3]> = d.get()?;
            samples.reserve((run.loaded.n_steps / CHECK_EVERY + 2).min(1 << 20) as usize);
            self.indicator = Some(Indicator { samples });
        }
        Ok(())
    }
}

/// The quasi-static indicator of the samples `[t, K, U + S]` of a run (kinetic energy of the
/// free DOFs, stored energy): with `S*` the largest stored energy and `t*` its time (about
/// the peak load), the largest `K / (U + S)` before `t*` while the stored energy lies between
/// 10 % and 90 % of `S*` (the loading: not the start, where nothing is stored yet, nor the
/// cracking that announces the peak), and the largest after the stored energy first reached
/// 10 % of `S*` over the whole run. No stored energy: all zeros.
pub fn indicator(samples: &[[f64; 3]]) -> QuasiStatic {
    let (mut peak, mut s_max) = (0.0, 0.0);
    for &[t, _, s] in samples {
        if s > s_max {
            (peak, s_max) = (t, s);
        }
    }
    let start = samples
        .iter()
        .position(|p| s_max > 0.0 && p[2] >= 0.1 * s_max);
    let (mut loading, mut all) = (0.0f64, 0.0f64);
    for &[t, k, s] in start.map_or(&[][..], |i| &samples[i..]) {
        let r = k / s;
        all = all.max(r);
        if t <= peak && s <= 0.9 * s_max {
            loading = loading.max(r);
        }
    }
    QuasiStatic {
        transient_end: start.map_or(0.0, |i| samples[i][0]),
        peak_time: peak,
        kinetic_ratio_max: loading,
        kinetic_ratio_max_all: all,
        limit: None,
        warning: None,
    }
}

/// The limit and the warning of a scene that declares a slow run (a `loading` or
/// `mass_scaling` section): the warning when the indicator exceeds the limit.
fn warn(scene: &crate::scene::Scene, q: &mut QuasiStatic) {
    if scene.loading.is_none() && scene.mass_scaling.is_none() {
        return;
    }
    let l = scene
        .loading
        .as_ref()
        .map_or(crate::scene::mass_scaling::KINETIC_RATIO_LIMIT, |l| {
            l.kinetic_ratio_limit
        });
    q.limit = Some(l);
    if q.kinetic_ratio_max > l {
        q.warning = Some(format!(
            "the run is not quasi-static: the kinetic energy reached {:.3} of the stored energy while loading (limit {l}, before the peak of the stored energy at t = {:.4e} s); lower loading.rate or the mass_scaling factor",
            q.kinetic_ratio_max, q.peak_time
        ));
    }
}

/// Margin of the energy-growth check: the mechanical energy may exceed the energy supplied by
/// this factor over the step-synchronisation factor `1 / (1 - (h / h_limit)^2)` (see
/// [`energy_growth`]) before a run is called unstable.
pub const ENERGY_GROWTH_BOUND: f64 = 2.0;

/// The energy-growth check: `Some(message)` when the mechanical energy `e_now`
/// exceeds `ENERGY_GROWTH_BOUND / (1 - min(h / h_limit, 0.995)^2)` times the energy
/// `supplied` and has grown since the last check (`e_prev`, at step `prev_step`), or is not
/// finite. The message names the scheme, the step used and the predicted stable limit.
///
/// Why the factor `1 / (1 - (h / h_limit)^2)`: `K + U` taken at the steps is not what a
/// scheme conserves. For central difference on a mode of frequency `omega` the conserved
/// quantity is `K + U (1 - (h omega / 2)^2)`, so a legitimate `K + U` reaches up to
/// `1 / (1 - (h omega / 2)^2)` times the energy, 50 at `h omega = 1.98`; with
/// `h / h_limit = h omega_max / 2` (`omega_max` an upper bound of every mode's frequency) the
/// factor bounds every mode. The same form is used for every scheme (their step-synchronised
/// energies degenerate the same way at their limits); at 0.9 of the limit it is 5.3, at 0.5
/// it is 1.33.
pub fn energy_growth(
    e_now: f64,
    e_prev: f64,
    supplied: f64,
    scheme: SchemeKind,
    h: f64,
    h_limit: f64,
    prev_step: u64,
) -> Option<String> {
    let r = (h / h_limit).min(0.995);
    let bound = ENERGY_GROWTH_BOUND / (1.0 - r * r);
    let bad = !e_now.is_finite() || (e_now > bound * supplied && e_now > e_prev);
    bad.then(|| {
        format!(
            "energy growth: kinetic + strain (+ contact/joint) energy {e_now:.3e} J is {:.3e} times the energy supplied (more than the allowed {bound:.3}; {supplied:.3e} J: initial energy and work of loads, gravity, supports and walls) and grew {:.3e}-fold since step {prev_step}; {scheme} with h = {h:.4e} s is past its stable step on this scene (predicted limit {h_limit:.4e} s, h / limit = {:.3})",
            e_now / supplied.max(f64::MIN_POSITIVE),
            e_now / e_prev.max(f64::MIN_POSITIVE),
            h / h_limit
        )
    })
}

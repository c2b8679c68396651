//! The run's stability checks ([`StabilityGuard`]): every [`CHECK_EVERY`] steps and at the
//! last step, a stage's error, non-finite values and energy growth stop the run with an
//! `Unstable` error that names the cause and the fix ([`crate::run::diagnosis`]).
//!
//! Energy growth: the mechanical energy `E = K + U + stored (contact, joints)` may not exceed
//! the energy supplied `S = E_0 + |W_loads + W_gravity| + |W_supports| + |W_walls| +
//! K_prescribed` (damping, friction and fracture only remove energy) by more than the
//! step-synchronisation factor: `E > 2 S / (1 - (h / h_limit)^2)` while `E` grew since the
//! last check stops the run, long before an unstable mode overflows, with a message naming
//! the scheme, the step, the predicted limit and the fix ([`energy_growth`]).
//!
//! Round-off: `S` also carries the round-off floor of the scene ([`round_off_floor`]), so
//! that a scene in which nothing happens yet (a body at rest, platens still closing the gap
//! to the specimen) is not stopped for energies of the order of its round-off.

use fdem_time::SchemeKind;

use super::observer::{Flow, Halt, Observer, RunView};
use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::error::RunError;
use crate::run::diagnosis::Found;
use crate::run::ledger::kinetic_energy;
use crate::run::summary::{QuasiStatic, Summary};
use crate::stages::summed_report;

/// Steps between two stability checks (and two residual checks of a relaxation).
pub const CHECK_EVERY: u64 = 100;

/// The stability checks: a stage's error, non-finite positions or velocities, energy growth;
/// and a scan for triangles turned inside out (the likely cause of what follows).
pub struct StabilityGuard {
    /// The mechanical energy at the last check [J].
    e_prev: f64,
    /// Energy below which growth is round-off at the first check [J] ([`round_off_floor`]);
    /// at step `n` it is `floor (1 + n / CHECK_EVERY)`.
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
        self.floor = round_off_floor(run.loaded, run.sys, run.ledger.initial());
        let scene = &run.loaded.scene;
        if scene.analysis == crate::input::scene::Analysis::Dynamic {
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
        let (stored, walls) = summed_report(sys, state.x_nodes())
            .map_or((0.0, 0.0), |r| (r.stored, r.wall_work + r.fluid_work));
        let kinetic = kinetic_energy(&run.ledger.mass_dof, &state.v);
        let strain = sys.elements.strain_energy(state.x_nodes());
        let mut e_now = kinetic + strain + stored;
        // the floor grows with the steps taken: round-off accumulates over them
        let floor = self.floor * (1.0 + run.step as f64 / CHECK_EVERY as f64);
        let mut supplied = run.ledger.supplied_bound(&sys.model, state, walls) + floor;
        if sys.elements.prestressed() {
            // the initial stresses' energy S0 : E is first order in the displacement and
            // of either sign: the growth check takes the elastic part and counts its
            // magnitude as supplied (an excavation draws on it); a body at rest in its
            // initial stress moves by round-off only, below the floor
            let w0 = sys.elements.initial_stress_energy(state.x_nodes());
            e_now -= w0;
            supplied += w0.abs();
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
        if run.loaded.scene.analysis == crate::input::scene::Analysis::Dynamic {
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
fn warn(scene: &crate::input::scene::Scene, q: &mut QuasiStatic) {
    if scene.loading.is_none() && scene.mass_scaling.is_none() {
        return;
    }
    let l = scene.loading.as_ref().map_or(
        crate::input::scene::mass_scaling::KINETIC_RATIO_LIMIT,
        |l| l.kinetic_ratio_limit,
    );
    q.limit = Some(l);
    if q.kinetic_ratio_max > l {
        q.warning = Some(format!(
            "the run is not quasi-static: the kinetic energy reached {:.3} of the stored energy while loading (limit {l}, before the peak of the stored energy at t = {:.4e} s); lower loading.rate or the mass_scaling factor",
            q.kinetic_ratio_max, q.peak_time
        ));
    }
}

/// The margin of the round-off floor over its estimate ([`round_off_floor`]).
pub const ROUND_OFF_MARGIN: f64 = 1e4;

/// The energy below which the energy-growth check takes growth for round-off [J]:
/// `ROUND_OFF_MARGIN (eps S + E_x)`, `eps` the machine epsilon, with
///
/// - `S` the scene's energy scale, the largest of: the initial energy `|E_0|` (`e0`: kinetic,
///   strain, stored); the initial stresses' energy scale
///   `sum A t (sxx^2 + syy^2 + 2 sxy^2) / (2 (lambda + 2 mu))`; `1/2 M v^2` and
///   `1/2 k_max (v T)^2` for the fastest prescribed velocity or wall velocity `v` (times the
///   largest factor of its history) over the duration `T`; `1/2 k_max d^2` for the largest
///   prescribed displacement `d`; `F^2 / k_min` for the loads' total force `F` (times the
///   largest factor of their histories); `M |g| L` for gravity. `M` is the scene's mass (the
///   masses of the run), `k_min` and `k_max` the smallest and the largest `E t` of the
///   materials (a body's stiffness in the plane), `L` the scene's size: a sum of energies of
///   size `S` carries a round-off of `eps S`;
/// - `E_x = 1/2 M (omega_max eps L)^2`, `L` here the largest coordinate magnitude or the
///   size of the scene, whichever is larger, and `omega_max` the scene's frequency bound
///   (elements, contact and joints): the energy of positions each rounded to `eps L` at the
///   stiffest mode, what a body at rest holds when nothing loads it yet.
///
/// The margin allows for the accumulation of both over the sums of a run, and the check
/// multiplies the floor by `1 + n / CHECK_EVERY` at step `n` for their accumulation over the
/// steps (a random walk of the positions' round-off: an energy growing as `n`, as measured).
/// Measured (central difference at 0.9 of the limit): the fracturing block of
/// `block-compression-fracture.json` at rest without its platens holds at most 4.2e-5 of
/// the floor over 60 000 steps (its round-off energy grows as `n` after the first 10 000);
/// the two discs of `disc-collision.json` at rest at most 5e-8 over 223 000 steps; the
/// fracturing specimens of `block-compression-fracture.json`, `brazilian-disc-fracture.json`
/// and `wing-crack.json` with their platens 1 mm away, over their durations, at most 3e-8.
/// The floor is a negligible energy of any scene (`1e4 eps = 2.2e-12` of its energy scale at
/// the start), so an unstable mode, which grows exponentially, passes it within a few checks.
pub fn round_off_floor(
    l: &crate::problem::load::Problem,
    sys: &crate::stages::system::SceneSystem,
    e0: f64,
) -> f64 {
    let model = &sys.model;
    let mass: f64 = model.mass.iter().sum();
    let (mut lo, mut hi, mut coord) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2], 0.0f64);
    for p in &model.x0 {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
            coord = coord.max(p[k].abs());
        }
    }
    let size = if model.x0.is_empty() {
        0.0
    } else {
        (hi[0] - lo[0]).hypot(hi[1] - lo[1])
    };
    let (mut k_min, mut k_max) = (f64::INFINITY, 0.0f64);
    for (m, t) in &model.materials {
        if m.young.is_finite() {
            k_min = k_min.min(m.young * t);
            k_max = k_max.max(m.young * t);
        }
    }
    let duration = l.scene.duration.unwrap_or(0.0);
    // the fastest prescribed speed (supports and walls) and the largest displacement
    let (v, d) = crate::problem::strains::fastest_loading(&l.scene, model);
    let d = d.max(v * duration);
    let force: f64 = model
        .loads
        .iter()
        .map(|ld| {
            let f = ld.history.as_ref().map_or(1.0, |h| h.max_abs());
            ld.forces.iter().map(|(_, x)| x.abs()).sum::<f64>() * f
        })
        .sum();
    let gravity = model.gravity.map_or(0.0, |g| g[0].hypot(g[1]));
    let weight: f64 = model.weight_mass().iter().sum();
    let scale = [
        e0.abs(),
        sys.elements.initial_stress_energy_scale(),
        0.5 * mass * v * v,
        0.5 * k_max * d * d,
        if k_min.is_finite() && k_min > 0.0 {
            force * force / k_min
        } else {
            0.0
        },
        weight * gravity * size,
    ]
    .into_iter()
    .filter(|e| e.is_finite())
    .fold(0.0, f64::max);
    // (as the square of sqrt(M / 2) omega eps L: no underflow of a scaled mass's tiny omega)
    let e_x = ((0.5 * mass).sqrt() * l.omega_max() * f64::EPSILON * coord.max(size)).powi(2);
    let floor = ROUND_OFF_MARGIN * (f64::EPSILON * scale + e_x);
    if floor.is_finite() { floor } else { 0.0 }
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
            "energy growth: kinetic + strain (+ contact/joint) energy {e_now:.3e} J is {:.3e} times the energy supplied (more than the allowed {bound:.3}; {supplied:.3e} J: initial energy, work of loads, gravity, supports and walls, and the round-off floor) and grew {:.3e}-fold since step {prev_step}; {scheme} with h = {h:.4e} s is past its stable step on this scene (predicted limit {h_limit:.4e} s, h / limit = {:.3})",
            e_now / supplied.max(f64::MIN_POSITIVE),
            e_now / e_prev.max(f64::MIN_POSITIVE),
            h / h_limit
        )
    })
}

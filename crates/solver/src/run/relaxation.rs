//! The convergence of a dynamic relaxation ([`Relaxation`]): at the stability checks, the
//! relative residual `|f|_free / max(|f_ext|, |reaction|)`; the run ends when it reaches
//! `integrator.relaxation_tolerance`. `|f_ext|` is the full load: ramped loads at full
//! strength, a load with a time history at its value at the check's time. With histories
//! (on loads, prescribed motions or walls) the run cannot converge before the last of them
//! stops changing: a load held at zero for a while would otherwise meet any tolerance.
//!
//! A relative tolerance cannot go below what the force sums resolve: the run also converges
//! when the residual is at most the round-off floor `c eps |S| / scale` (`c` =
//! [`ROUND_OFF_FACTOR`])
//! ([`SceneSystem::force_round_off`](crate::stages::system::SceneSystem::force_round_off)), i.e. at
//! `max(tolerance, floor)`. The summary gives the floor at the last check and the kinetic
//! energy over the strain and stored energy at the end.

use super::observer::{Flow, Halt, Observer, RunView};
use super::stability::CHECK_EVERY;
use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::error::RunError;
use crate::run::summary::Summary;

/// The floor of the relative residual is this many times `eps |S| / scale`: the force of a
/// DOF goes through more roundings than the sum of its terms (the deformation gradient, the
/// stress, the rotation back), and a relaxation stalls above `eps |S|`: the 120 x 12-cell
/// cantilever of `tests/relaxation_methods.rs` under a tip load of 1 mN stalls at a relative
/// residual of 1.9e-5 with `eps |S| / scale` = 7.2e-6 (2.6 times).
pub const ROUND_OFF_FACTOR: f64 = 4.0;

/// The residual of a relaxation, checked with the stability checks.
pub struct Relaxation {
    tolerance: f64,
    /// `|f_ext|` at full load.
    load_norm: f64,
    /// The load vector at a check, when some load has a history (else empty).
    loads: Vec<f64>,
    /// The time after which every history of the scene is constant [s] (0 without).
    settle: f64,
    /// The relative residual at the last check.
    residual: Option<f64>,
    /// The round-off floor of the relative residual at the last check.
    floor: Option<f64>,
    converged: bool,
    /// The method's name for the summary.
    method: &'static str,
    /// A DOF array for the floor.
    buf: Vec<f64>,
}

impl Relaxation {
    /// A relaxation to `tolerance` by the method named `method`.
    pub fn new(tolerance: f64, method: &'static str) -> Self {
        Self {
            tolerance,
            load_norm: 0.0,
            loads: Vec::new(),
            settle: 0.0,
            residual: None,
            floor: None,
            converged: false,
            method,
            buf: Vec::new(),
        }
    }
}

impl Observer for Relaxation {
    fn start(&mut self, run: &mut RunView) -> Result<(), Halt> {
        let mut f = vec![0.0; 2 * run.sys.model.n_nodes()];
        run.sys.model.add_external(f64::INFINITY, &mut f);
        self.load_norm = f.iter().map(|v| v * v).sum::<f64>().sqrt();
        if run.sys.model.loads_have_histories() {
            self.loads = f;
        }
        let scene = &run.loaded.scene;
        let walls = scene.contact.iter().flat_map(|c| &c.walls);
        self.settle = scene
            .boundary_conditions
            .iter()
            .filter_map(|bc| bc.history())
            .chain(walls.filter_map(|w| w.history.as_ref()))
            .map(|h| h.settle_time())
            .fold(0.0, f64::max);
        Ok(())
    }

    fn after_step(&mut self, run: &mut RunView) -> Result<Flow, Halt> {
        if !(run.step.is_multiple_of(CHECK_EVERY) || run.last) {
            return Ok(Flow::Continue);
        }
        let sys = &*run.sys;
        if !self.loads.is_empty() {
            self.loads.fill(0.0);
            sys.model.add_external_static(run.state.t, &mut self.loads);
            self.load_norm = self.loads.iter().map(|v| v * v).sum::<f64>().sqrt();
        }
        let f = sys.force.as_flattened();
        let mut r2 = 0.0;
        for d in 0..f.len() {
            if !sys.model.constrained[d] {
                r2 += f[d] * f[d];
            }
        }
        // Scale: applied loads, or the reactions when the loading is by supports.
        let reac: f64 = sys
            .constrained()
            .iter()
            .map(|&d| f[d] * f[d])
            .sum::<f64>()
            .sqrt();
        let scale = self.load_norm.max(reac).max(f64::MIN_POSITIVE);
        let r = r2.sqrt() / scale;
        self.residual = Some(r);
        let (t, x, v) = (run.state.t, &run.state.x, &run.state.v);
        let floor = ROUND_OFF_FACTOR * sys.force_round_off(t, x, v, &mut self.buf) / scale;
        self.floor = Some(floor);
        if r <= self.tolerance.max(floor) && run.state.t >= self.settle {
            self.converged = true;
            return Ok(Flow::Stop);
        }
        Ok(Flow::Continue)
    }

    fn finish(&mut self, run: &mut RunView, summary: &mut Summary) -> Result<(), RunError> {
        let scene = &run.loaded.scene;
        let equal = scene
            .integrator
            .equal_step_masses(scene.analysis, scene.relaxation_choice().0);
        summary.relaxation_masses = Some(if equal { "equal-step" } else { "true" }.into());
        summary.converged = Some(self.converged);
        summary.relative_residual = self.residual;
        summary.relaxation = Some(self.method.into());
        summary.relaxation_reason = Some(scene.relaxation_choice().1);
        summary.residual_floor = self.floor;
        let e = &summary.energy;
        let elastic = e.strain + e.stored;
        summary.kinetic_to_strain = (elastic > 0.0).then(|| e.kinetic / elastic);
        Ok(())
    }

    fn save(&mut self, e: &mut Enc) -> Result<(), RunError> {
        e.put(&[self.load_norm, self.settle]);
        e.put(&self.loads);
        e.put(&self.residual);
        e.put(&self.floor);
        e.put(&self.converged);
        Ok(())
    }

    fn restore(&mut self, run: &mut RunView, d: &mut Dec) -> Result<(), DecodeError> {
        [self.load_norm, self.settle] = d.get()?;
        self.loads = d.get()?;
        if !self.loads.is_empty() && self.loads.len() != 2 * run.sys.model.n_nodes() {
            return Err(d.error("the loads do not fit the scene's nodes"));
        }
        self.residual = d.get()?;
        self.floor = d.get()?;
        self.converged = d.get()?;
        Ok(())
    }
}

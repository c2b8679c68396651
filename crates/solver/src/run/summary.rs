//! The run summary (`summary.json`, and a few lines for the terminal) and the outcome of a
//! finished run.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::error::RunError;
use crate::output::{FrameData, write_atomic};
use crate::problem::indicator::Accuracy;
use crate::run::ledger::Energies;
use crate::stages::system::StageTimers;

/// The run summary (also written as `summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// The scene file.
    pub scene: String,
    /// Analysis kind.
    pub analysis: String,
    /// Scheme name.
    pub scheme: String,
    /// Nodes.
    pub nodes: usize,
    /// Triangles.
    pub triangles: usize,
    /// Time step [s].
    pub time_step: f64,
    /// Stable limit [s].
    pub time_step_limit: f64,
    /// Steps done.
    pub steps: u64,
    /// Force evaluations.
    pub force_evaluations: u64,
    /// Simulated time [s].
    pub simulated_time: f64,
    /// Wall time of the whole run [s].
    pub wall_time: f64,
    /// Triangles times steps per second of stepping wall time.
    pub triangle_steps_per_second: f64,
    /// Per-stage wall times [s].
    pub timers: StageTimers,
    /// The energy ledger at the end (`crate::run::ledger`).
    pub energy: Energies,
    /// Frames written.
    pub frames: usize,
    /// Relaxation: whether the residual tolerance was reached.
    pub converged: Option<bool>,
    /// Relaxation: final |residual| / |load|.
    pub relative_residual: Option<f64>,
    /// Relaxation: its method (`"kinetic"`, `"adaptive"`, `"viscous"` or
    /// `"conjugate-gradient"`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relaxation: Option<String>,
    /// Relaxation: why that method (named in the scene, or the default and what decided it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relaxation_reason: Option<String>,
    /// Relaxation: the masses of its pseudo-dynamics (`"equal-step"` or `"true"`,
    /// `integrator.relaxation_masses`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relaxation_masses: Option<String>,
    /// Relaxation: the round-off floor of the relative residual at the last check,
    /// `4 eps sqrt(sum_i S_i^2) / scale` with `S_i` the sum of the magnitudes of the terms of
    /// DOF `i`'s force (element contributions, stiffness times the absolute positions, loads);
    /// the run converges at `max(tolerance, floor)`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub residual_floor: Option<f64>,
    /// Relaxation: kinetic energy over strain plus stored energy at the end.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kinetic_to_strain: Option<f64>,
    /// Kinetic relaxation: the resets (velocities zeroed at a peak of the kinetic energy).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kinetic_resets: Option<u64>,
    /// Conjugate-gradient relaxation: the restarts (the search direction reset to the
    /// preconditioned force).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cg_restarts: Option<u64>,
    /// Conjugate-gradient relaxation: the largest rise of the total potential energy in one
    /// iteration [J] (0 when none rose; a minimiser's iteration lowers it, so a rise is the
    /// round-off of the energy sums, or a scene whose energy is not conservative).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cg_largest_rise: Option<f64>,
    /// Largest displacement magnitude at the end [m].
    pub max_displacement: f64,
    /// Threads used.
    pub threads: usize,
    /// Details of the optional stages (contact, joints), by name.
    pub stages: serde_json::Value,
    /// An `"adaptive"` step: the smallest and the largest step taken [s].
    pub time_step_range: Option<[f64; 2]>,
    /// Mass scaling: the factor on every mass (absent without mass scaling).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass_scaling_factor: Option<f64>,
    /// The loading rate of the scene's `loading` section (absent without one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub loading_rate: Option<f64>,
    /// The quasi-static indicator of a dynamic run (kinetic over stored energy).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quasi_static: Option<QuasiStatic>,
    /// The accuracy indicators: what the run found and how far to trust it
    /// ([`crate::run::accuracy`]).
    pub accuracy: Accuracy,
    /// What the run found: failure, peak load and stress, stiffness, broken joints
    /// ([`crate::run::result`]); absent for a run without a load-displacement curve or broken
    /// joints, a static solve and an interrupted run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub result: Option<crate::run::result::RunResult>,
    /// Present when the run was resumed from a checkpoint (`fdem run --resume`): where it
    /// resumed. The summary is of the whole run; its wall time adds the earlier parts'.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resumed: Option<Resumed>,
    /// Present when the run was interrupted (a signal, or `--stop-after`): where it stopped
    /// and the checkpoint to resume from.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interrupted: Option<Interrupted>,
    /// Present for a distributed run: the ranks, this rank's share of the work and how often
    /// the ranks exchanged (`crate::distributed`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distributed: Option<serde_json::Value>,
}

/// The quasi-static indicator: the ratio `K / (U + S)` of the kinetic energy of the free
/// degrees of freedom to the stored energy (strain `U`, contact and joints `S`), taken at the
/// stability checks (every 100 steps and the last): see [`crate::run::indicator`].
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct QuasiStatic {
    /// The end of the initial transient [s]: when the stored energy first reached 10 % of
    /// its largest value.
    pub transient_end: f64,
    /// The time of the largest stored energy (about the peak load) [s].
    pub peak_time: f64,
    /// The indicator: the largest ratio before `peak_time` while the stored energy lies
    /// between 10 % and 90 % of its largest value.
    pub kinetic_ratio_max: f64,
    /// The largest ratio after `transient_end` over the whole run (a brittle failure after
    /// the peak is dynamic at any rate).
    pub kinetic_ratio_max_all: f64,
    /// The warning threshold (`loading.kinetic_ratio_limit`) of a scene with a `loading` or
    /// `mass_scaling` section.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit: Option<f64>,
    /// The warning, when `kinetic_ratio_max` exceeds `limit`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
}

/// Where a resumed run took up from its checkpoint.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Resumed {
    /// The step of the checkpoint.
    pub step: u64,
    /// The time of the checkpoint [s].
    pub time: f64,
}

/// How an interrupted run stopped.
#[derive(Debug, Clone, Serialize)]
pub struct Interrupted {
    /// What stopped it: `SIGINT`, `SIGTERM` or `stop_after`.
    pub reason: String,
    /// The checkpoint written at the stop (`fdem run --resume DIR` continues from it).
    pub checkpoint: String,
}

impl Summary {
    /// A few lines for the terminal.
    pub fn describe(&self) -> String {
        let mut s = if self.analysis == "static" {
            format!(
                "static solve (sparse Cholesky, {} DOFs) in {:.3} s, {:.2} s wall\n",
                2 * self.nodes,
                self.timers.internal_forces,
                self.wall_time
            )
        } else {
            format!(
                "{} steps of {:.4e} s ({}), {} force evaluations, {:.2} s wall, {:.3e} triangle-steps/s\n",
                self.steps,
                self.time_step,
                self.scheme,
                self.force_evaluations,
                self.wall_time,
                self.triangle_steps_per_second
            )
        };
        let t = &self.timers;
        let _ = writeln!(
            s,
            "time: internal forces {:.3} s, loads {:.3} s, damping {:.3} s, contributions {:.3} s, integration {:.3} s, histories {:.3} s, output {:.3} s",
            t.internal_forces,
            t.external_loads,
            t.mass_damping,
            t.contributions,
            t.integration,
            t.histories,
            t.output
        );
        let _ = write!(
            s,
            "{}\nmax |u| {:.4e} m",
            self.energy
                .line((self.analysis == "static").then_some("round-off of the solve")),
            self.max_displacement
        );
        if let (Some(c), Some(r)) = (self.converged, self.relative_residual) {
            let _ = write!(s, "\nrelaxation converged: {c} (relative residual {r:.3e})");
            if let (Some(m), Some(why)) = (&self.relaxation, &self.relaxation_reason) {
                let _ = write!(s, "; {m}: {why}");
            }
        }
        if let Some(r) = &self.resumed {
            let _ = write!(
                s,
                "\nresumed from the checkpoint at step {} (t = {:.4e} s); every figure is of the whole run",
                r.step, r.time
            );
        }
        if let Some(r) = &self.result {
            let _ = write!(s, "\n{}", crate::run::result::describe(r));
        }
        let a = &self.accuracy;
        if !a.indicators.is_empty() {
            let _ = write!(
                s,
                "\naccuracy: {} warning{} (value, threshold; every figure: summary.json \"accuracy\"){}",
                a.warnings,
                if a.warnings == 1 { "" } else { "s" },
                crate::problem::indicator::describe(&a.indicators)
            );
        }
        s
    }
}

/// The state of a finished run, for tests and callers that want the numbers.
pub struct Outcome {
    /// The summary.
    pub summary: Summary,
    /// The last frame's data.
    pub last_frame: FrameData,
    /// The joints' committed history at the end (scenes with joints): a later run starts
    /// from it through `scene.fracture.initial_state`.
    pub joint_state: Option<fdem_fracture::JointState>,
    /// What the run's checkpoints cost (none written: zeros).
    pub checkpoints: crate::checkpoint::Stats,
}

/// Writes `summary` as `summary.json` in the output folder `dir`.
pub fn write_summary(dir: &Path, summary: &Summary) -> Result<(), RunError> {
    let p = dir.join("summary.json");
    let text = serde_json::to_vec_pretty(summary).map_err(|e| RunError::Output {
        file: p.clone(),
        message: e.to_string(),
    })?;
    write_atomic(&p, &text).map_err(|e| RunError::Output {
        file: p,
        message: e.to_string(),
    })
}

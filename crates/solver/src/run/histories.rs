//! The histories of a run (`histories.csv`): the scene's probes (displacement, velocity and
//! reaction of a group, the energy ledger, the fluid's books), one row every
//! `histories.every` steps.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::observer::{Flow, Halt, Observer, RunView};
use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::error::RunError;
use crate::input::scene::Probe;
use crate::output::HistoryWriter;
use crate::problem::load::Problem;
use crate::problem::model::Model;
use crate::run::ledger::Energies;
use crate::run::summary::Summary;
use crate::stages::summed_report;

/// History columns and their evaluation.
pub struct Histories {
    writer: HistoryWriter,
    /// `histories.csv`.
    file: PathBuf,
    every: u64,
    groups: Vec<Vec<u32>>,
    /// Whether an energy probe is recorded (then the ledger is computed at each record).
    energy: bool,
    /// Whether the energy probe adds the quasi-static indicator `kinetic_ratio` (a scene
    /// with a `loading` or `mass_scaling` section).
    ratio: bool,
}

impl Histories {
    /// The histories of `l` on `model` (`None`: the scene has no probes).
    pub fn new(l: &Problem, model: &Model, dir: &Path) -> Option<Self> {
        let probes = &l.scene.histories.probes;
        if probes.is_empty() {
            return None;
        }
        let mut cols = vec!["time".to_string()];
        let mut groups = Vec::new();
        for (i, p) in probes.iter().enumerate() {
            match p {
                Probe::Displacement(g) | Probe::Velocity(g) | Probe::Reaction(g) => {
                    let kind = match p {
                        Probe::Displacement(_) => "u",
                        Probe::Velocity(_) => "v",
                        _ => "reaction",
                    };
                    // the body the resolver found (`v_x[body/group]` when another body has a
                    // group of that name)
                    let body = model.probe_body.get(i).copied().flatten().unwrap_or(0);
                    let label = model.group_label(&l.scene, body, &g.group);
                    cols.push(format!("{kind}_x[{label}]"));
                    cols.push(format!("{kind}_y[{label}]"));
                    let nodes = model
                        .group_nodes(body, &g.group)
                        .map(<[u32]>::to_vec)
                        .unwrap_or_default();
                    groups.push(nodes);
                }
                Probe::Fluid => {
                    cols.extend(crate::stages::fluid::COLUMNS.map(String::from));
                    groups.push(Vec::new());
                }
                Probe::Energy => {
                    // the ledger's terms, named as in summary.json and the console
                    cols.extend(Energies::column_names().map(String::from));
                    if declares_slow_run(l) {
                        cols.push("kinetic_ratio".into());
                    }
                    groups.push(Vec::new());
                }
            }
        }
        let every = l
            .scene
            .histories
            .every
            .map(|e| e as u64)
            .unwrap_or((l.n_steps / 1000).max(1));
        Some(Self {
            writer: HistoryWriter::new(&dir.join("histories.csv"), &cols),
            file: dir.join("histories.csv"),
            every,
            groups,
            energy: probes.iter().any(|p| matches!(p, Probe::Energy)),
            ratio: declares_slow_run(l),
        })
    }

    /// Records one row; `k_free` is the kinetic energy of the free DOFs (the indicator's).
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &mut self,
        l: &Problem,
        x0: &[[f64; 2]],
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        reaction: &[[f64; 2]],
        energy: &Energies,
        k_free: f64,
        fluid: Option<&crate::stages::fluid::FluidBooks>,
    ) {
        let mut row = vec![t];
        for (p, nodes) in l.scene.histories.probes.iter().zip(&self.groups) {
            match p {
                Probe::Displacement(_) => {
                    let k = nodes.len().max(1) as f64;
                    let (mut ux, mut uy) = (0.0, 0.0);
                    for &n in nodes {
                        ux += x[n as usize][0] - x0[n as usize][0];
                        uy += x[n as usize][1] - x0[n as usize][1];
                    }
                    row.extend([ux / k, uy / k]);
                }
                Probe::Velocity(_) => {
                    let k = nodes.len().max(1) as f64;
                    let (mut vx, mut vy) = (0.0, 0.0);
                    for &n in nodes {
                        vx += v[n as usize][0];
                        vy += v[n as usize][1];
                    }
                    row.extend([vx / k, vy / k]);
                }
                Probe::Reaction(_) => {
                    let (mut rx, mut ry) = (0.0, 0.0);
                    for &n in nodes {
                        rx += reaction[n as usize][0];
                        ry += reaction[n as usize][1];
                    }
                    row.extend([rx, ry]);
                }
                Probe::Fluid => {
                    let b = fluid.copied().unwrap_or_default();
                    row.extend(b.columns());
                }
                Probe::Energy => {
                    row.extend(energy.columns().map(|(_, v)| v));
                    if self.ratio {
                        row.push(kinetic_ratio(k_free, energy.strain + energy.stored));
                    }
                }
            }
        }
        self.writer.push(&row);
    }
}

/// Whether a scene declares a slow run (a `loading` or `mass_scaling` section): its energy
/// probe then adds the quasi-static indicator.
pub fn declares_slow_run(l: &Problem) -> bool {
    l.scene.loading.is_some() || l.scene.mass_scaling.is_some()
}

/// The quasi-static indicator `k / stored` (0 while nothing is stored).
pub fn kinetic_ratio(k: f64, stored: f64) -> f64 {
    if stored > 0.0 { k / stored } else { 0.0 }
}

impl Histories {
    /// Writes `histories.csv` whole.
    pub fn flush(&self) -> Result<(), RunError> {
        self.writer.flush().map_err(|e| RunError::Output {
            file: self.file.clone(),
            message: e.to_string(),
        })
    }
}

impl Observer for Histories {
    /// A row every `every` steps and at the last step.
    fn after_step(&mut self, run: &mut RunView) -> Result<Flow, Halt> {
        if run.step.is_multiple_of(self.every) || run.end {
            let s = Instant::now();
            let (sys, state) = (&*run.sys, run.state);
            let reaction = sys.reactions();
            let e = if self.energy {
                let r = summed_report(sys, state.x_nodes());
                run.ledger.ledger(sys, state, r.as_ref())
            } else {
                Energies::default()
            };
            let k_free = if self.ratio {
                e.kinetic - run.ledger.k_prescribed(&state.v)
            } else {
                0.0
            };
            self.record(
                run.loaded,
                &sys.model.x0,
                state.t,
                state.x_nodes(),
                state.v_nodes(),
                &reaction,
                &e,
                k_free,
                crate::stages::fluid::books_of(sys).as_ref(),
            );
            run.sys.timers.histories += s.elapsed().as_secs_f64();
        }
        Ok(Flow::Continue)
    }

    /// The file written at each frame (an error here is not fatal: it is written again).
    fn at_frame(&mut self, _run: &mut RunView) -> Result<(), Halt> {
        let _ = self.writer.flush();
        Ok(())
    }

    fn finish(&mut self, _run: &mut RunView, _summary: &mut Summary) -> Result<(), RunError> {
        self.flush()
    }

    /// The rows up to the stop written (a failure to write them is not reported over the
    /// run's error).
    fn stopped(&mut self, _summary: &mut Summary) {
        let _ = self.flush();
    }

    /// The rows so far travel in the checkpoint (the file on disk may hold rows of steps
    /// after it, or fewer), and are written whole at the next flush.
    fn save(&mut self, e: &mut Enc) -> Result<(), RunError> {
        e.put(&self.writer.text().to_string());
        Ok(())
    }

    fn restore(&mut self, _run: &mut RunView, d: &mut Dec) -> Result<(), DecodeError> {
        let text: String = d.get()?;
        self.writer.restore_text(text).map_err(|e| d.error(e))?;
        self.flush().map_err(|e| d.error(e))
    }
}

//! The run's output folder and its frames: [`FrameWriter`] writes the `.vtu` frames (and the
//! joints' series, the raw JSON frames) collected in `results.pvd`; [`FrameClock`] says when a
//! frame is due.

use std::path::PathBuf;
use std::time::Instant;

use fdem_time::State;

use super::observer::{Halt, Observer, RunView};
use super::options::RunOptions;
use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::diagnosis::Found;
use crate::error::RunError;
use crate::load::Loaded;
use crate::output::{Collection, FrameData, JointSeries, make_frame, vtu, write_atomic};
use crate::summary::Summary;
use crate::system::SceneSystem;

/// The output files of a run.
pub struct FrameWriter {
    dir: PathBuf,
    pvd: Collection,
    raw: bool,
    level: u32,
    frames: usize,
    joints: JointSeries,
}

impl FrameWriter {
    /// Claims the output folder: creates it, and removes the files of an earlier run
    /// (`output::folder`) so that none is mistaken for this run's.
    pub fn new(options: &RunOptions, level: u32) -> Result<Self, RunError> {
        crate::output::folder::claim(&options.out_dir).map_err(|e| RunError::Output {
            file: options.out_dir.clone(),
            message: format!("cannot prepare the output folder: {e}"),
        })?;
        Ok(Self {
            dir: options.out_dir.clone(),
            pvd: Collection::new(&options.out_dir.join("results.pvd")),
            raw: options.raw,
            level,
            frames: 0,
            joints: JointSeries::default(),
        })
    }

    /// The writer of a run resumed in its folder (which it does not claim: the frames written
    /// before the checkpoint stay; [`Observer::restore`] removes those after it).
    pub fn resume(options: &RunOptions, level: u32) -> Self {
        Self {
            dir: options.out_dir.clone(),
            pvd: Collection::new(&options.out_dir.join("results.pvd")),
            raw: options.raw,
            level,
            frames: 0,
            joints: JointSeries::default(),
        }
    }

    /// Removes the frame files numbered `from` and above (written after a checkpoint by the
    /// run that is being resumed).
    fn remove_frames_from(&self, from: usize) -> std::io::Result<()> {
        for entry in std::fs::read_dir(&self.dir)? {
            let name = entry?.file_name().to_string_lossy().into_owned();
            let number = ["frame_", "joints_"]
                .iter()
                .find_map(|p| name.strip_prefix(p))
                .and_then(|r| r.strip_suffix(".vtu").or_else(|| r.strip_suffix(".json")))
                .filter(|d| !d.is_empty() && d.bytes().all(|c| c.is_ascii_digit()))
                .and_then(|d| d.parse::<usize>().ok());
            if number.is_some_and(|k| k >= from) {
                std::fs::remove_file(self.dir.join(&name))?;
            }
        }
        Ok(())
    }

    /// Frames written.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Writes one frame (refused, with an `Unstable` error, when a value is not finite).
    pub fn write(&mut self, data: &FrameData) -> Result<(), RunError> {
        let check_finite = data
            .points
            .iter()
            .chain(&data.velocity)
            .chain(&data.force)
            .all(|p| p[0].is_finite() && p[1].is_finite())
            && data.stress.iter().flatten().all(|s| s.is_finite())
            && data.energy_density.iter().all(|e| e.is_finite());
        if !check_finite {
            return Err(RunError::Unstable {
                step: 0,
                time: data.time,
                message: "non-finite positions, velocities, forces or stresses in an output frame (not written)\n  fix: lower the time step (`integrator.safety`), and check the materials (young, density) and the loads".into(),
            });
        }
        let name = format!("frame_{:04}.vtu", self.frames);
        let out = |file: PathBuf, e: String| RunError::Output { file, message: e };
        let bytes = vtu::encode(data, self.level).map_err(|e| out(self.dir.join(&name), e))?;
        write_atomic(&self.dir.join(&name), &bytes)
            .map_err(|e| out(self.dir.join(&name), e.to_string()))?;
        self.joints
            .write(&self.dir, self.frames, data, self.level)
            .map_err(|(file, e)| out(file, e))?;
        if self.raw {
            let raw = format!("frame_{:04}.json", self.frames);
            let text =
                serde_json::to_vec(data).map_err(|e| out(self.dir.join(&raw), e.to_string()))?;
            write_atomic(&self.dir.join(&raw), &text)
                .map_err(|e| out(self.dir.join(&raw), e.to_string()))?;
        }
        self.pvd
            .push(data.time, &name)
            .map_err(|e| out(self.dir.join("results.pvd"), e.to_string()))?;
        self.frames += 1;
        Ok(())
    }

    /// Writes the frame of the system at `state`: the force evaluated there (not counted in
    /// the stage timers), the stresses, the stages' fields; its time counted as output.
    fn write_state(&mut self, sys: &mut SceneSystem, state: &State) -> Result<(), RunError> {
        let s = Instant::now();
        let saved = sys.timers;
        let mut a = vec![0.0; state.x.len()];
        fdem_time::SecondOrderSystem::acceleration(sys, state.t, &state.x, &state.v, &mut a);
        sys.timers = saved;
        let mut fr = state_frame(sys, state);
        for c in &sys.contributions {
            c.frame_fields(state.x_nodes(), &mut fr);
        }
        self.write(&fr)?;
        sys.timers.output += s.elapsed().as_secs_f64();
        Ok(())
    }
}

/// The frame of the system at `state`, with the forces and reactions of its last evaluation
/// (without the stages' fields).
pub fn state_frame(sys: &SceneSystem, state: &State) -> FrameData {
    let reaction = sys.reactions();
    make_frame(
        &sys.model,
        &sys.elements,
        state.t,
        state.x_nodes(),
        state.v_nodes(),
        &sys.force,
        &reaction,
    )
}

impl Observer for FrameWriter {
    /// The initial frame (an error here is returned as it is).
    fn start(&mut self, run: &mut RunView) -> Result<(), Halt> {
        if run.loaded.scene.output.frames > 0 {
            self.write_state(run.sys, run.state).map_err(Halt::Failed)?;
        }
        Ok(())
    }

    /// A frame with non-finite values: diagnosed as at the stability checks.
    fn at_frame(&mut self, run: &mut RunView) -> Result<(), Halt> {
        self.write_state(run.sys, run.state).map_err(|e| match e {
            RunError::Unstable { .. } => Halt::Unstable(Found::Frame),
            e => Halt::Failed(e),
        })
    }

    fn finish(&mut self, _run: &mut RunView, summary: &mut Summary) -> Result<(), RunError> {
        summary.frames = self.frames;
        Ok(())
    }

    fn stopped(&mut self, summary: &mut Summary) {
        summary.frames = self.frames;
    }

    fn save(&mut self, e: &mut Enc) -> Result<(), RunError> {
        e.put(&self.frames);
        e.put(&self.pvd.entries().to_vec());
        e.put(&self.joints.entries().to_vec());
        Ok(())
    }

    /// The collections as they were at the checkpoint, rewritten; later frames removed.
    fn restore(&mut self, _run: &mut RunView, d: &mut Dec) -> Result<(), DecodeError> {
        self.frames = d.get()?;
        let entries: Vec<(f64, String)> = d.get()?;
        let joints: Vec<(f64, String)> = d.get()?;
        if entries.len() != self.frames {
            return Err(d.error("the frame count and the collection differ"));
        }
        let io = |e: std::io::Error| {
            d.error(format!(
                "cannot restore the frames in {}: {e}",
                self.dir.display()
            ))
        };
        self.remove_frames_from(self.frames).map_err(io)?;
        self.pvd = Collection::with_entries(&self.dir.join("results.pvd"), entries).map_err(io)?;
        self.joints = JointSeries::with_entries(&self.dir, joints).map_err(io)?;
        Ok(())
    }
}

/// When the frames of a run are due: `output.frames` frames after the initial one, evenly
/// spaced in steps (fixed step) or in time (adaptive step), and one at the end of a run that
/// ends early (a relaxation that converged).
pub struct FrameClock {
    frames: usize,
    /// The next frame's number.
    next: usize,
    /// `Some(end time)`: spaced in time.
    t_end: Option<f64>,
    n_steps: u64,
}

impl FrameClock {
    /// The clock of `l`, the initial frame written.
    pub fn new(l: &Loaded) -> Self {
        let adaptive = l.scene.integrator.time_step == crate::scene::TimeStep::Adaptive;
        let t_end = adaptive.then(|| l.scene.duration.unwrap_or(0.0));
        Self::with(l.scene.output.frames, t_end, l.n_steps)
    }

    /// `frames` frames over `n_steps` steps, or up to `t_end` (an adaptive step).
    fn with(frames: usize, t_end: Option<f64>, n_steps: u64) -> Self {
        Self {
            frames,
            next: usize::from(frames > 0),
            t_end,
            n_steps,
        }
    }

    /// A frame is due after step `step` at time `t` (`end`: the run ends after this step).
    pub fn due(&self, step: u64, t: f64, end: bool) -> bool {
        if self.frames == 0 {
            return false;
        }
        let scheduled = match self.t_end {
            Some(t_end) => t >= (self.next as f64) * t_end / (self.frames as f64) * (1.0 - 1e-12),
            None => {
                let tf = (self.next as f64) * (self.n_steps as f64) / (self.frames as f64);
                (step as f64) >= tf.round()
            }
        };
        scheduled || (end && self.next <= self.frames)
    }

    /// The due frame was written.
    pub fn advance(&mut self) {
        self.next += 1;
    }

    /// The next frame's number (a checkpoint saves it).
    pub fn next(&self) -> usize {
        self.next
    }

    /// Goes on from frame number `next` (a resumed run).
    pub fn resume_at(&mut self, next: usize) {
        self.next = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steps (or the times) at which a clock writes its frames, the run ending after
    /// `end_at` steps.
    fn frame_steps(mut clock: FrameClock, dt: f64, end_at: u64) -> Vec<u64> {
        let mut out = Vec::new();
        for step in 1..=end_at {
            if clock.due(step, step as f64 * dt, step == end_at) {
                out.push(step);
                clock.advance();
            }
        }
        out
    }

    #[test]
    fn frames_are_spread_evenly_over_the_steps_and_the_last_falls_on_the_last_step() {
        assert_eq!(
            frame_steps(FrameClock::with(4, None, 10), 1.0, 10),
            [3, 5, 8, 10]
        );
        assert_eq!(frame_steps(FrameClock::with(3, None, 3), 1.0, 3), [1, 2, 3]);
        assert!(frame_steps(FrameClock::with(0, None, 10), 1.0, 10).is_empty());
    }

    #[test]
    fn a_run_that_ends_early_writes_one_frame_at_its_end() {
        // a relaxation converged after 7 of 100 steps: one frame at step 7
        assert_eq!(frame_steps(FrameClock::with(4, None, 100), 1.0, 7), [7]);
    }

    #[test]
    fn an_adaptive_step_spreads_the_frames_in_time() {
        // steps of 0.3 s up to t = 3 s, two frames: at t >= 1.5 s and at the end
        assert_eq!(
            frame_steps(FrameClock::with(2, Some(3.0), 0), 0.3, 10),
            [5, 10]
        );
    }
}

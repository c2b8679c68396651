//! The run's output folder and its frames: [`FrameWriter`] writes the `.vtu` frames (and the
//! joints' series, the raw JSON frames) collected in `results.pvd`; [`FrameClock`] says when a
//! frame is due.
//!
//! With `output.writer_thread` (the default) a frame is copied out of the state and then
//! compressed and written on a background thread (with its own rayon pool of as many threads
//! as the run's) while the run steps on. At most one frame is in flight: the next frame, a
//! checkpoint, the end of the run and any stop wait for it first, and a failure of the
//! background write ends the run there with the same error as a write in the loop. A frame
//! enters `results.pvd` (and `joints.pvd`) once its files are whole.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Instant;

use fdem_time::State;

use super::observer::{Halt, Observer, RunView};
use super::options::RunOptions;
use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::error::RunError;
use crate::input::scene::Output;
use crate::output::{
    ArraySet, Collection, FrameData, JointSeries, joints, make_frame_of, vtu, write_atomic,
};
use crate::problem::load::Problem;
use crate::run::diagnosis::Found;
use crate::run::summary::Summary;
use crate::stages::system::SceneSystem;

/// The output files of a run.
pub struct FrameWriter {
    dir: PathBuf,
    pvd: Collection,
    raw: bool,
    level: u32,
    frames: usize,
    joints: JointSeries,
    arrays: ArraySet,
    /// Frames written in the background.
    background: bool,
    /// The pool of the background writes, once made.
    pool: Option<Arc<rayon::ThreadPool>>,
    /// The frame being written in the background.
    pending: Option<JoinHandle<Result<Written, RunError>>>,
}

/// A frame's files, written: its time and the names to add to the collections.
struct Written {
    time: f64,
    frame: String,
    joints: Option<String>,
}

/// The files of frame `index` (frame, joints, raw JSON) in `dir`.
fn write_files(
    dir: &Path,
    index: usize,
    data: &FrameData,
    level: u32,
    raw: bool,
    arrays: &ArraySet,
) -> Result<Written, RunError> {
    let out = |file: PathBuf, e: String| RunError::Output { file, message: e };
    let name = format!("frame_{index:04}.vtu");
    let joints = match &data.joints {
        Some(j) => Some((
            JointSeries::file_name(dir, index, j).map_err(|(file, e)| out(file, e))?,
            joints::grid(j, arrays),
        )),
        None => None,
    };
    let frame = (vtu::frame_grid(data, arrays), dir.join(&name));
    let joint_path = joints.as_ref().map(|(n, g)| (g, dir.join(n)));
    let mut files: Vec<(&vtu::Grid, &Path)> = vec![(&frame.0, &frame.1)];
    if let Some((g, p)) = &joint_path {
        files.push((g, p));
    }
    vtu::write_files(&files, level).map_err(|(file, e)| out(file, e))?;
    let joints = joints.map(|(n, _)| n);
    if raw {
        let path = dir.join(format!("frame_{index:04}.json"));
        let text = serde_json::to_vec(data).map_err(|e| out(path.clone(), e.to_string()))?;
        write_atomic(&path, &text).map_err(|e| out(path, e.to_string()))?;
    }
    Ok(Written {
        time: data.time,
        frame: name,
        joints,
    })
}

impl FrameWriter {
    /// Claims the output folder: creates it, and removes the files of an earlier run
    /// (`output::folder`) so that none is mistaken for this run's.
    pub fn new(options: &RunOptions, output: &Output) -> Result<Self, RunError> {
        crate::output::folder::claim(&options.out_dir).map_err(|e| RunError::Output {
            file: options.out_dir.clone(),
            message: format!("cannot prepare the output folder: {e}"),
        })?;
        Ok(Self::resume(options, output))
    }

    /// The writer of a run resumed in its folder (which it does not claim: the frames written
    /// before the checkpoint stay; [`Observer::restore`] removes those after it).
    pub fn resume(options: &RunOptions, output: &Output) -> Self {
        Self {
            dir: options.out_dir.clone(),
            pvd: Collection::new(&options.out_dir.join("results.pvd")),
            raw: options.raw,
            level: output.compression,
            frames: 0,
            joints: JointSeries::default(),
            arrays: output.arrays.set(),
            background: output.writer_thread,
            pool: None,
            pending: None,
        }
    }

    /// The pool of the background writes (made at the first frame, of as many threads as
    /// the run's pool), or `None` for writes in the loop (also when no pool can be made).
    fn pool(&mut self) -> Option<Arc<rayon::ThreadPool>> {
        if self.background && self.pool.is_none() {
            self.pool = rayon::ThreadPoolBuilder::new()
                .num_threads(rayon::current_num_threads())
                .thread_name(|i| format!("fdem-frames-{i}"))
                .build()
                .ok()
                .map(Arc::new);
        }
        self.pool.clone()
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

    /// Frames written or in flight.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// The arrays the frames carry.
    pub fn arrays(&self) -> &ArraySet {
        &self.arrays
    }

    /// Writes one frame (refused, with an `Unstable` error, when a value is not finite), in
    /// the background when the writer has a pool (after the frame in flight is written).
    pub fn write(&mut self, data: FrameData) -> Result<(), RunError> {
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
        self.flush()?;
        let (dir, index, level, raw) = (self.dir.clone(), self.frames, self.level, self.raw);
        match self.pool() {
            Some(pool) => {
                let arrays = self.arrays.clone();
                self.pending = Some(std::thread::spawn(move || {
                    pool.install(|| write_files(&dir, index, &data, level, raw, &arrays))
                }));
            }
            None => {
                let written = write_files(&dir, index, &data, level, raw, &self.arrays)?;
                self.enter(written)?;
            }
        }
        self.frames += 1;
        Ok(())
    }

    /// Waits for the frame in flight, if any, and enters it in the collections.
    pub fn flush(&mut self) -> Result<(), RunError> {
        let Some(h) = self.pending.take() else {
            return Ok(());
        };
        let written = h.join().map_err(|_| RunError::Output {
            file: self.dir.clone(),
            message: "the frame writer thread panicked".into(),
        })??;
        self.enter(written)
    }

    /// Adds a written frame to `results.pvd` (and `joints.pvd`).
    fn enter(&mut self, w: Written) -> Result<(), RunError> {
        let out = |file: PathBuf, e: String| RunError::Output { file, message: e };
        if let Some(name) = &w.joints {
            self.joints
                .push(&self.dir, w.time, name)
                .map_err(|(file, e)| out(file, e))?;
        }
        self.pvd
            .push(w.time, &w.frame)
            .map_err(|e| out(self.dir.join("results.pvd"), e.to_string()))
    }

    /// Writes the frame of the system at `state`: the force evaluated there (not counted in
    /// the stage timers), the stresses, the stages' fields (when the frames carry some of
    /// theirs); the time until the frame is handed over (or written) counted as output.
    fn write_state(&mut self, sys: &mut SceneSystem, state: &State) -> Result<(), RunError> {
        let s = Instant::now();
        let saved = sys.timers;
        let mut a = vec![0.0; state.x.len()];
        sys.look(state.t, &state.x, &state.v, &mut a);
        sys.timers = saved;
        let mut fr = state_frame_of(sys, state, &self.arrays);
        if self.arrays.has_stage_arrays() {
            for c in &sys.contributions {
                c.frame_fields(state.x_nodes(), &mut fr);
            }
        }
        if !self.arrays.has_joints() {
            fr.joints = None;
        }
        let result = self.write(fr);
        sys.timers.output += s.elapsed().as_secs_f64();
        result
    }
}

impl Drop for FrameWriter {
    /// A frame in flight is finished before the writer goes (its error is the run's only
    /// when the run waits for it: [`FrameWriter::flush`]).
    fn drop(&mut self) {
        if let Some(h) = self.pending.take() {
            let _ = h.join();
        }
    }
}

/// The frame of the system at `state`, with the forces and reactions of its last evaluation
/// and the recovered nodal stresses (without the stages' fields).
pub fn state_frame(sys: &SceneSystem, state: &State) -> FrameData {
    state_frame_of(sys, state, &ArraySet::all())
}

/// [`state_frame`] with the arrays of `arrays` only.
fn state_frame_of(sys: &SceneSystem, state: &State, arrays: &ArraySet) -> FrameData {
    let reaction = sys.reactions();
    let (x, v) = (state.x_nodes(), state.v_nodes());
    let (m, e) = (&sys.model, &sys.elements);
    let mut frame = make_frame_of(m, e, state.t, x, v, &sys.force, &reaction, arrays);
    let links = sys.contributions.iter().find_map(|c| c.joint_links());
    frame.recover_nodal(m, links, arrays);
    frame
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

    /// The last frame written (and its wait counted as output) before the summary.
    fn finish(&mut self, _run: &mut RunView, summary: &mut Summary) -> Result<(), RunError> {
        let s = Instant::now();
        self.flush()?;
        summary.timers.output += s.elapsed().as_secs_f64();
        summary.frames = self.frames;
        Ok(())
    }

    /// The run stops on an error of its own: the frame in flight finished (a failure of it
    /// is not reported over the run's error).
    fn stopped(&mut self, summary: &mut Summary) {
        let _ = self.flush();
        summary.frames = self.pvd.len();
    }

    /// The frame in flight written first, so that the checkpoint's count is of whole files.
    fn save(&mut self, e: &mut Enc) -> Result<(), RunError> {
        self.flush()?;
        e.put(&self.frames);
        e.put(&self.pvd.entries().to_vec());
        e.put(&self.joints.entries().to_vec());
        Ok(())
    }

    /// The frames of the collections (written whole by [`Observer::save`]).
    fn files(&self, files: &mut Vec<String>) {
        let frames = self.pvd.entries().iter().chain(self.joints.entries());
        files.extend(frames.map(|(_, name)| name.clone()));
    }

    /// The collections as they were at the checkpoint, rewritten; later frames removed.
    fn restore(&mut self, _run: &mut RunView, d: &mut Dec) -> Result<(), DecodeError> {
        if let Some(h) = self.pending.take() {
            let _ = h.join();
        }
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
    pub fn new(l: &Problem) -> Self {
        let adaptive = l.scene.integrator.time_step == crate::input::scene::TimeStep::Adaptive;
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

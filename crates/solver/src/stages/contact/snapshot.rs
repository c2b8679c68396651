//! The contact stage in a checkpoint: the contact model's state
//! ([`fdem_contact::ContactSnapshot`]) and the stage's own books, in one section `contact`.
//!
//! Saved besides the model: the step in use, the walls' last force and displacement (the
//! trapezoid of the wall work), whether the bonded list was handed over, the release timer and
//! the switch-jump energy, the report (maxima, counters, wall work, wall forces and
//! displacements, first error, largest active bound), the step count (walls.csv rows), the
//! damping books, the nodal work books (work, positions and contact forces of the last booked
//! state, the energy stored at t = 0) and the length of walls.csv. The booked forces are saved,
//! not rebuilt from the model's last force pass, which need not be the booked one: the frame
//! writer evaluates the force at a frame's state after the step's commit, and with friction
//! that pass differs from the step's own (rebuilding the booked forces from it moved
//! `node_work` after a stop at a frame step during contact).
//!
//! Not saved, rebuilt identically by the attach: the mesh arrays, body labels, laws, wall
//! motions, masses, sampling intervals. Scratch that is written before it is read: the wall
//! reactions (`Contact::wall_reactions` fills them), the released pairs being handed over
//! (emptied after each hand-over), the active bound's rows, the current nodal forces
//! (`node_force_now`, zeroed and refilled at each end of step). `damped` and `book_work`
//! come from the scene: they are saved as a check that the checkpoint is this scene's.

use fdem_contact::{ContactSnapshot, ContactStats, CoupleForce, WallForce};

use super::{ContactReport, ContactStage};
use crate::checkpoint::pack::{Dec, DecodeError, Enc, Pack};
use crate::stages::system::{StageCheckpoint, StepEvents};

impl Pack for CoupleForce {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.active);
        e.put(&self.normal);
        e.put(&self.friction);
        e.put(&self.damping);
        e.put(&self.total);
        e.put(&self.ft);
        e.put(&self.dissipation);
        e.put(&self.fn_total);
        e.put(&self.phi_max);
        e.put(&self.slipping);
        e.put(&self.invalid);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok(Self {
            active: d.get()?,
            normal: d.get()?,
            friction: d.get()?,
            damping: d.get()?,
            total: d.get()?,
            ft: d.get()?,
            dissipation: d.get()?,
            fn_total: d.get()?,
            phi_max: d.get()?,
            slipping: d.get()?,
            invalid: d.get()?,
        })
    }
}

impl Pack for WallForce {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.normal);
        e.put(&self.friction);
        e.put(&self.damping);
        e.put(&self.ft);
        e.put(&self.dissipation);
        e.put(&self.fn_total);
        e.put(&self.phi_max);
        e.put(&self.slipping);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok(Self {
            normal: d.get()?,
            friction: d.get()?,
            damping: d.get()?,
            ft: d.get()?,
            dissipation: d.get()?,
            fn_total: d.get()?,
            phi_max: d.get()?,
            slipping: d.get()?,
        })
    }
}

impl Pack for ContactStats {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.n_couples);
        e.put(&self.n_active);
        e.put(&self.n_wall_active);
        e.put(&self.n_slipping);
        e.put(&self.max_phi);
        e.put(&self.max_phi_couple);
        e.put(&self.n_invalid);
        e.put(&self.first_invalid);
        e.put(&self.trial_dissipation);
        e.put(&self.sum_phi_loaded);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok(Self {
            n_couples: d.get()?,
            n_active: d.get()?,
            n_wall_active: d.get()?,
            n_slipping: d.get()?,
            max_phi: d.get()?,
            max_phi_couple: d.get()?,
            n_invalid: d.get()?,
            first_invalid: d.get()?,
            trial_dissipation: d.get()?,
            sum_phi_loaded: d.get()?,
        })
    }
}

impl Pack for ContactSnapshot {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.walls);
        e.put(&self.bonded_lens);
        e.put(&self.bonded);
        e.put(&self.x_det);
        e.put(&self.wall_det);
        e.put(&self.n_tris_det);
        e.put(&self.buffer);
        e.put(&self.stale);
        e.put(&self.n_detections);
        e.put(&self.couples);
        e.put(&self.friction);
        e.put(&self.flagged);
        e.put(&self.results);
        e.put(&self.wall_pairs);
        e.put(&self.wall_ft);
        e.put(&self.wall_results);
        e.put(&self.n_released_couples);
        e.put(&self.friction_dissipated);
        e.put(&self.stats);
    }
    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok(Self {
            walls: d.get()?,
            bonded_lens: d.get()?,
            bonded: d.get()?,
            x_det: d.get()?,
            wall_det: d.get()?,
            n_tris_det: d.get()?,
            buffer: d.get()?,
            stale: d.get()?,
            n_detections: d.get()?,
            couples: d.get()?,
            friction: d.get()?,
            flagged: d.get()?,
            results: d.get()?,
            wall_pairs: d.get()?,
            wall_ft: d.get()?,
            wall_results: d.get()?,
            n_released_couples: d.get()?,
            friction_dissipated: d.get()?,
            stats: d.get()?,
        })
    }
}

fn put_report(e: &mut Enc, r: &ContactReport) {
    e.put(&r.max_phi);
    e.put(&r.max_depth_over_altitude);
    e.put(&r.phi_sum);
    e.put(&r.phi_count);
    e.put(&r.detections);
    e.put(&r.active_couples);
    e.put(&r.wall_work);
    e.put(&r.wall_force);
    e.put(&r.wall_displacement);
    e.put(&r.error);
    e.put(&r.omega_active_max);
    e.put(&r.omega_active_max_time);
}

/// The report of a stage with `nw` walls.
fn get_report(d: &mut Dec, nw: usize) -> Result<ContactReport, DecodeError> {
    Ok(ContactReport {
        max_phi: d.get()?,
        max_depth_over_altitude: d.get()?,
        phi_sum: d.get()?,
        phi_count: d.get()?,
        detections: d.get()?,
        active_couples: d.get()?,
        wall_work: d.get()?,
        wall_force: d.vec_of_len(nw, "wall forces")?,
        wall_displacement: d.vec_of_len(nw, "wall displacements")?,
        error: d.get()?,
        omega_active_max: d.get()?,
        omega_active_max_time: d.get()?,
    })
}

/// What the section holds besides the model, read before anything is changed.
struct Books {
    dt: f64,
    prev_force: Vec<[f64; 2]>,
    prev_disp: Vec<[f64; 2]>,
    bonded_set: bool,
    release_s: f64,
    switch_jump: f64,
    report: ContactReport,
    steps: u64,
    damping_dissipated: f64,
    damping_power: Option<(f64, f64)>,
    node_work: f64,
    node_x: Vec<[f64; 2]>,
    node_force: Vec<[f64; 2]>,
    stored0: f64,
    csv_len: Option<u64>,
}

impl ContactStage {
    /// [`StageCheckpoint::save`] of the stage (module docs).
    fn save_state(&mut self, e: &mut Enc) -> std::io::Result<()> {
        let csv_len = match &mut self.csv {
            Some(w) => Some(crate::output::csv_length(w)?),
            None => None,
        };
        let snap = self.contact.snapshot();
        let report = &self.report;
        e.section("contact", |e| {
            e.put(&snap);
            e.put(&self.dt);
            e.put(&self.prev_force);
            e.put(&self.prev_disp);
            e.put(&self.bonded_set);
            e.put(&self.release_s);
            e.put(&self.switch_jump);
            put_report(e, report);
            e.put(&self.steps);
            e.put(&self.damped);
            e.put(&self.damping_dissipated);
            e.put(&self.damping_power);
            e.put(&self.node_work);
            e.put(&self.node_x);
            e.put(&self.node_force);
            e.put(&self.stored0);
            e.put(&self.book_work);
            e.put(&csv_len);
        });
        Ok(())
    }

    /// The model's snapshot, checked against this stage's mesh and walls.
    fn read_snapshot(&self, d: &mut Dec) -> Result<ContactSnapshot, DecodeError> {
        let s: ContactSnapshot = d.get()?;
        let (nn, nt) = (self.inv_sqrt_mass.len(), self.tris.len());
        if !(s.x_det.is_empty() || s.x_det.len() == nn) {
            return Err(d.error(format!(
                "positions at the last detection: {} where the scene has {nn} nodes",
                s.x_det.len()
            )));
        }
        if !(s.n_tris_det == 0 || s.n_tris_det == nt) {
            return Err(d.error(format!(
                "{} triangles at the last detection where the scene has {nt}",
                s.n_tris_det
            )));
        }
        if s.n_tris_det > 0 && s.x_det.is_empty() {
            return Err(d.error("a detection without its positions"));
        }
        if !(s.bonded_lens.is_empty() || s.bonded_lens.len() == nt) {
            return Err(d.error(format!(
                "bonded pairs of {} triangles where the scene has {nt}",
                s.bonded_lens.len()
            )));
        }
        Ok(s)
    }

    /// The stage's books, checked against this stage's scene.
    fn read_books(&self, d: &mut Dec) -> Result<Books, DecodeError> {
        let (nn, nw) = (self.inv_sqrt_mass.len(), self.motion.len());
        let dt = d.get()?;
        let prev_force = d.vec_of_len(nw, "wall forces")?;
        let prev_disp = d.vec_of_len(nw, "wall displacements")?;
        let bonded_set = d.get()?;
        let release_s = d.get()?;
        let switch_jump = d.get()?;
        let report = get_report(d, nw)?;
        let steps = d.get()?;
        let damped: bool = d.get()?;
        if damped != self.damped {
            return Err(d.error(format!(
                "written for a scene {} contact damping",
                if damped { "with" } else { "without" }
            )));
        }
        let damping_dissipated = d.get()?;
        let damping_power = d.get()?;
        let node_work = d.get()?;
        let node_x: Vec<[f64; 2]> = d.get()?;
        if !(node_x.is_empty() || node_x.len() == nn) {
            return Err(d.error(format!(
                "nodal work books of {} positions where the scene has {nn} nodes",
                node_x.len()
            )));
        }
        let node_force: Vec<[f64; 2]> = d.get()?;
        if node_force.len() != node_x.len() {
            return Err(d.error(format!(
                "nodal work books of {} forces for {} positions",
                node_force.len(),
                node_x.len()
            )));
        }
        let stored0 = d.get()?;
        let book_work: bool = d.get()?;
        if book_work != self.book_work {
            return Err(d.error(format!(
                "written for a run {} the energy probe",
                if book_work { "with" } else { "without" }
            )));
        }
        let csv_len = d.get()?;
        Ok(Books {
            dt,
            prev_force,
            prev_disp,
            bonded_set,
            release_s,
            switch_jump,
            report,
            steps,
            damping_dissipated,
            damping_power,
            node_work,
            node_x,
            node_force,
            stored0,
            csv_len,
        })
    }

    /// [`StageCheckpoint::restore`] of the stage (module docs): everything is read and
    /// checked first, then set.
    fn restore_state(&mut self, d: &mut Dec) -> Result<(), DecodeError> {
        d.section("contact", |d| {
            let snap = self.read_snapshot(d)?;
            let b = self.read_books(d)?;
            match (&self.csv, b.csv_len) {
                (None, Some(_)) if !self.csv_wanted => {}
                (None, Some(_)) => {
                    return Err(d.error("walls.csv of the run being resumed cannot be opened"));
                }
                (Some(_), None) => return Err(d.error("written by a run without walls.csv")),
                _ => {}
            }
            self.contact
                .restore(snap)
                .map_err(|m| d.error(format!("contact model: {m}")))?;
            if let (Some(w), Some(len)) = (&mut self.csv, b.csv_len) {
                crate::output::truncate_csv(w, len)
                    .map_err(|m| d.error(format!("walls.csv {m}")))?;
            }
            self.dt = b.dt;
            self.prev_force = b.prev_force;
            self.prev_disp = b.prev_disp;
            self.bonded_set = b.bonded_set;
            self.release_s = b.release_s;
            self.switch_jump = b.switch_jump;
            self.report = b.report;
            self.steps = b.steps;
            self.damping_dissipated = b.damping_dissipated;
            self.damping_power = b.damping_power;
            self.node_work = b.node_work;
            self.node_force_now = vec![[0.0; 2]; b.node_x.len()];
            self.node_force = b.node_force;
            self.node_x = b.node_x;
            self.stored0 = b.stored0;
            Ok(())
        })
    }
}

/// The contact stage hands nothing over to later stages: `events` is not its part.
impl StageCheckpoint for ContactStage {
    /// The contact model's state and the stage's books (module docs).
    fn save(&mut self, e: &mut Enc, _events: &StepEvents) -> std::io::Result<()> {
        self.save_state(e)
    }

    fn restore(&mut self, d: &mut Dec, _events: &mut StepEvents) -> Result<(), DecodeError> {
        self.restore_state(d)
    }
}

#[cfg(test)]
mod tests;

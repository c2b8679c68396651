//! The contact stage's reports and output ([`StageOutput`]): its energy books and details for
//! the run summary, the first error (too deep a penetration), the frame arrays
//! (`contact_force`, `contact_active`) and `walls.csv`.

use std::io::Write;

use super::ContactStage;
use crate::output::FrameData;
use crate::stages::system::{StageOutput, StageReport};

impl ContactStage {
    /// A row of `walls.csv` at time `t` (every `csv_every` steps): each wall's displacement
    /// and force, as booked.
    pub(super) fn write_walls_row(&mut self, t: f64) {
        let r = &self.report;
        if let Some(w) = &mut self.csv
            && self.steps.is_multiple_of(self.csv_every)
        {
            let mut line = format!("{t:.9e}");
            for k in 0..self.motion.len() {
                let (u, f) = (r.wall_displacement[k], r.wall_force[k]);
                line.push_str(&format!(
                    ",{:.9e},{:.9e},{:.9e},{:.9e}",
                    u[0], u[1], f[0], f[1]
                ));
            }
            let _ = writeln!(w, "{line}");
        }
    }
}

impl StageOutput for ContactStage {
    fn report(&self, x: &[[f64; 2]]) -> StageReport {
        let e = self.contact.energy(x, &self.tris, &self.labels);
        let r = &self.report;
        let stored = e.potential + e.friction_stored;
        // What the contact's books do not explain of the work its forces did on the nodes:
        // the pair potential is exact for rigid relative motion only (docs/contact.md
        // section 2), and the friction and damping books are their own quadratures.
        let residual = if self.book_work {
            r.wall_work
                - (stored - self.stored0 - self.switch_jump)
                - e.friction_dissipated
                - self.damping_dissipated
                - self.node_work
        } else {
            0.0
        };
        StageReport {
            stored,
            contact_residual: residual,
            friction: e.friction_dissipated,
            contact_damping: self.damping_dissipated,
            switch_loss: -self.switch_jump,
            wall_work: r.wall_work,
            fluid_work: 0.0,
            fracture: 0.0,
            error: r.error.clone(),
            details: serde_json::json!({
                "contact_potential": e.potential,
                "friction_stored": e.friction_stored,
                "friction_dissipated": e.friction_dissipated,
                "wall_work": r.wall_work,
                "damping_dissipated": self.damping_dissipated,
                "node_work": self.node_work,
                "contact_residual": residual,
                "switch_jump": self.switch_jump,
                "max_phi": r.max_phi,
                "max_depth_over_altitude": r.max_depth_over_altitude,
                "mean_depth_over_altitude": r.mean_depth_over_altitude(),
                "detections": r.detections,
                "released_couples": self.contact.n_released_couples(),
                "release_s": self.release_s,
                "active_couples": r.active_couples,
                "omega_active_max": r.omega_active_max,
                "omega_active_max_time": r.omega_active_max_time,
                "wall_force": r.wall_force,
                "couples": self.contact.couples().len(),
                // in a distributed run: the couples this rank evaluates
                "rank_couples": self.part.as_ref().map(|_| {
                    let c = &self.contact;
                    c.couples().iter().filter(|p| c.couple_local(p)).count()
                }),
            }),
        }
    }

    fn error(&self) -> Option<String> {
        self.report.error.clone()
    }

    /// `contact_force` on the points: the total contact force (normal + friction + damping,
    /// couples and walls) of the last force pass [N]; `contact_active` on the cells: 1 where
    /// the triangle is in at least one couple or wall contact with a positive normal load.
    fn frame_fields(&self, x: &[[f64; 2]], frame: &mut FrameData) {
        let mut f = vec![[0.0; 2]; x.len()];
        self.contact.add_forces(&self.tris, &mut f);
        let mut active = vec![0.0; self.tris.len()];
        for (r, c) in self
            .contact
            .couple_results()
            .iter()
            .zip(self.contact.couples())
        {
            if r.active && r.fn_total > 0.0 {
                active[c[0] as usize] = 1.0;
                active[c[1] as usize] = 1.0;
            }
        }
        for (r, c) in self
            .contact
            .wall_results()
            .iter()
            .zip(self.contact.wall_pairs())
        {
            if r.fn_total > 0.0 {
                active[c[1] as usize] = 1.0;
            }
        }
        frame.extra_point_vectors.push(("contact_force".into(), f));
        frame
            .extra_cell_scalars
            .push(("contact_active".into(), active));
    }

    fn files(&self, files: &mut Vec<String>) {
        if self.csv.is_some() {
            files.push("walls.csv".into());
        }
    }

    fn finish(&mut self) {
        if let Some(w) = &mut self.csv {
            let _ = w.flush();
        }
    }
}

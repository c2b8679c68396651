//! The fracture stage's reports and output ([`StageOutput`]): its energy books and details for
//! the run summary, the joints of the output frames (the `joints_NNNN.vtu` series) and of the
//! nodal stress recovery, and `fractures.csv`.

use std::io::Write;

use fdem_fracture::FractureEvent;

use super::{FractureReport, FractureStage};
use crate::stages::system::{StageOutput, StageReport};

impl FractureStage {
    /// The count of joints and broken joints, and every fracture event so far.
    pub fn fracture_report(&self) -> &FractureReport {
        &self.report
    }

    /// Books the breaks of a commit (in joint order): the report's count and events, and a
    /// row of `fractures.csv` each.
    pub(super) fn record_breaks(&mut self, breaks: &[FractureEvent]) {
        if breaks.is_empty() {
            return;
        }
        let r = &mut self.report;
        r.broken = self.state.n_broken;
        for e in breaks {
            r.events.push((
                e.time,
                e.position[0],
                e.position[1],
                e.mode.as_str().to_string(),
                e.energy_released,
            ));
            if let Some(w) = &mut self.csv {
                let _ = writeln!(
                    w,
                    "{:.9e},{:.9e},{:.9e},{},{:.4},{:.9e},{}",
                    e.time,
                    e.position[0],
                    e.position[1],
                    e.mode.as_str(),
                    e.mode_mix,
                    e.energy_released,
                    e.joint.0
                );
            }
        }
    }
}

impl StageOutput for FractureStage {
    fn report(&self, _x: &[[f64; 2]]) -> StageReport {
        let e = self.state.energy();
        StageReport {
            stored: e.stored - e.stored_initial,
            fracture: e.dissipated,
            switch_loss: e.released_at_break,
            details: serde_json::json!({
                "joints": self.set.len(),
                "broken": self.state.n_broken,
                "bonded_pairs": self.stars.n_bonded(),
                "bonded_releases": self.releases,
                "released_pairs": self.released_pairs,
                "bonded_release_s": self.release_s,
                "stored": e.stored,
                "dissipated": e.dissipated,
                "released_at_break": e.released_at_break,
                "work": e.work,
                // in a distributed run: the joints this rank evaluates
                "rank_joints": self.local.as_ref().map(|l| l.ids.len()),
            }),
            ..StageReport::default()
        }
    }

    /// Hands the joints to the writer (the `joints_NNNN.vtu` series, `crate::output::joints`).
    fn frame_fields(&self, x: &[[f64; 2]], frame: &mut crate::output::FrameData) {
        let mut joints = crate::output::JointFrame::new(&self.set, &self.state, x);
        if self.write_properties {
            joints.properties = Some(crate::output::JointProperties::new(&self.set));
        }
        frame.joints = Some(joints);
    }

    fn files(&self, files: &mut Vec<String>) {
        if self.csv.is_some() {
            files.push("fractures.csv".into());
        }
    }

    fn finish(&mut self) {
        if let Some(w) = &mut self.csv {
            let _ = w.flush();
        }
    }

    fn joint_links(&self) -> Option<crate::output::recovery::Links<'_>> {
        Some(crate::output::recovery::Links {
            nodes: &self.set.nodes,
            intact: &self.state.intact,
        })
    }
}

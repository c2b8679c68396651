//! The contact stage: the contact crate as a force term ([`ForceTerm`]) of the composition,
//! set up from the scene's `"contact"` section ([`crate::input::scene::contact`]). Its other layers,
//! each in its own file of `stages/contact/`: the reports and `walls.csv` (`output.rs`), the
//! checkpoint (`snapshot.rs`), a distributed run's part (`distributed.rs`).
//!
//! Each step (every force evaluation) it moves the rigid walls to `x_w(t) = x_w0 + v_w r(t)`
//! (`r` the integral of the ramp or history, [`crate::problem::time_function`]), refreshes detection when the buffer may be used up
//! (`Contact::update_detection`), computes the potential contact forces with friction
//! (`f = p ∫ (grad phi_c - grad phi_t) dA`, Coulomb with tangential penalty, see
//! docs/contact.md) and adds them. The friction history is committed in the end-of-step hook
//! only, so multi-stage integrators can evaluate forces any number of times per step.
//!
//! Laws are per pair of **bodies** (each body is usually one material): the per-triangle label
//! handed to the contact crate is the triangle's body index. Forces from the contact crate are
//! per unit thickness, so every penalty is multiplied by the bodies' thickness (the larger of
//! the two; walls use the largest thickness of the scene).
//!
//! Stable time step (docs/time-integration.md, "The stable step of a scene"): contact adds to the element bound
//! `omega_c^2 = max_e 3 p (2 / H_e) l_e (2 / A_e) / rho_e` (a triangle pair of two equal
//! triangles: `3 p (1/H_1 + 1/H_2)` in place of the joint's `p/h`, `H_e` the smallest altitude,
//! `l_e` the longest edge), and `omega_max^2 = omega_el^2 + omega_c^2`. That term covers every
//! edge pressed flat along its whole length; the **active** term
//! (`fdem_contact::active_bound`) covers only the contact engaged in a state: the stage
//! records its largest value over the run at the end of every `active_bound_every`-th step
//! (default 10; `omega_active_max` in
//! the summary) and gives it on demand for the adaptive step (docs/contact.md section 12.1).

use std::path::Path;

use fdem_contact::{ActiveBound, Contact, ContactLaw, ContactSettings, RigidPlane};

use crate::problem::contact_laws::{body_props, contact_law, laws};
use serde::Serialize;

use crate::input::scene::Scene;
pub use crate::input::scene::contact::{ContactSection, LawSpec, PairSpec, WallSpec};
use crate::problem::model::Model;
use crate::problem::time_function::{self, History};
use crate::stages::system::{Engaged, ForceTerm, StepEvents};

mod distributed;
mod output;
mod snapshot;

/// The contact stage's books for its report ([`crate::stages::system::StageOutput::report`]).
#[derive(Debug, Clone, Default, Serialize)]
pub struct ContactReport {
    /// Largest `phi = 3 d / H` seen over the run (d/H = phi/3).
    pub max_phi: f64,
    /// Largest overlap depth over the run relative to the altitude of the triangle, `phi/3`.
    pub max_depth_over_altitude: f64,
    /// The sum behind [`ContactReport::mean_depth_over_altitude`]: each loaded couple's
    /// largest `phi`, over the passes of steps.
    #[serde(skip)]
    pub phi_sum: f64,
    /// The loaded couples behind the mean, over the passes.
    #[serde(skip)]
    pub phi_count: u64,
    /// Detections done.
    pub detections: u64,
    /// Active couples (normal force > 0) at the last evaluation.
    pub active_couples: usize,
    /// Work done on the bodies by the moving walls [J].
    pub wall_work: f64,
    /// Current force of each wall on the bodies [N].
    pub wall_force: Vec<[f64; 2]>,
    /// Current displacement of each wall [m].
    pub wall_displacement: Vec<[f64; 2]>,
    /// First error (penetration too deep), if any.
    pub error: Option<String>,
    /// Largest active contact frequency bound over the run's end-of-step states, sampled
    /// every [`ContactSection::active_bound_every`] steps [rad/s]
    /// (`fdem_contact::active_bound`: the couples and walls engaged in each state).
    pub omega_active_max: f64,
    /// Time of that largest bound [s].
    pub omega_active_max_time: f64,
}

impl ContactReport {
    /// The mean overlap depth relative to the altitude of the triangle over the run: the mean
    /// of each loaded couple's largest `phi / 3` over every loaded couple of every force pass
    /// of a step (looks at the state for output are not counted); 0 before any contact.
    pub fn mean_depth_over_altitude(&self) -> f64 {
        if self.phi_count > 0 {
            self.phi_sum / (3.0 * self.phi_count as f64)
        } else {
            0.0
        }
    }
}

struct WallMotion {
    point0: [f64; 2],
    velocity: [f64; 2],
    ramp: f64,
    history: Option<History>,
}

/// The contact stage (a [`crate::stages::system::Stage`]).
pub struct ContactStage {
    contact: Contact,
    tris: Vec<[u32; 3]>,
    labels: Vec<u32>,
    dt: f64,
    motion: Vec<WallMotion>,
    reactions: Vec<[f64; 2]>,
    prev_force: Vec<[f64; 2]>,
    prev_disp: Vec<[f64; 2]>,
    /// The bonded triangle pairs at set-up (intact joints and intact stars), given by the
    /// fracture stage at attach (`crate::stages::fracture::FractureStage::new`) and handed to
    /// the contact model (as its exclusions) at the first force evaluation; the pairs released
    /// since come as [`StepEvents::released`]. `None`: no stage bonds pairs.
    pub bonded: Option<Vec<[u32; 2]>>,
    /// The initial bonded list was handed to the contact model.
    bonded_set: bool,
    /// The released pairs being handed over (swapped with [`StepEvents::released`]).
    released: Vec<[u32; 2]>,
    /// Wall time of the hand-overs of released pairs (release and switch-jump energy) [s].
    release_s: f64,
    /// Sum over the joint -> contact hand-overs of the contact potential they brought in [J].
    switch_jump: f64,
    report: ContactReport,
    /// Scratch of the active frequency bound.
    active: ActiveBound,
    /// Steps between the recorded samples of the active bound (0: none).
    active_every: u64,
    /// `1/sqrt(m_i)` per node (0 without mass).
    inv_sqrt_mass: Vec<f64>,
    csv: Option<std::io::BufWriter<std::fs::File>>,
    /// An output folder was given (`walls.csv` is written where there are walls): a stage
    /// without one (`fdem check`'s sample, the ranks other than 0 of a distributed run)
    /// resumes a checkpoint whose run wrote the file.
    csv_wanted: bool,
    csv_every: u64,
    steps: u64,
    /// Some law (pair or wall) has contact damping: its dissipation is booked.
    damped: bool,
    /// Energy dissipated by contact damping (trapezoidal rule in time on the power of the
    /// end-of-step states) [J], the power at the last booked state [W] and its time [s]
    /// (`None` before the first force evaluation).
    damping_dissipated: f64,
    damping_power: Option<(f64, f64)>,
    /// Work of all contact forces (couples and walls, every family) on the nodes since t = 0
    /// (trapezoidal rule on each step's displacement) [J].
    node_work: f64,
    /// The contact forces on the nodes at the last booked state [N], scratch for the current
    /// ones, and the positions of the last booked state (empty before the first force
    /// evaluation; allocated once).
    node_force: Vec<[f64; 2]>,
    node_force_now: Vec<[f64; 2]>,
    node_x: Vec<[f64; 2]>,
    /// Contact energy stored at t = 0 (potential and friction springs) [J].
    stored0: f64,
    /// Book the work of the contact forces on the nodes (`node_work`) and report the
    /// `contact_residual` (set when the run records the `energy` probe; off, it costs nothing).
    pub book_work: bool,
    /// This rank's part of a distributed run ([`distributed`]); `None`: the whole contact.
    part: Option<Box<distributed::ContactPart>>,
    /// The passes evaluate this rank's part (a distributed run's steps).
    partial: bool,
    /// The passes only look at the state
    /// ([`crate::stages::system::StageDistribution::set_looking`]).
    looking: bool,
}

impl ContactStage {
    /// Builds the stage for a scene with an enabled contact section; `dt` is the step,
    /// `out_dir` receives `walls.csv` (every `csv_every` steps) when there are walls: a new
    /// file, or (`resume`) the file of the run being resumed, cut back by
    /// [`crate::stages::system::StageCheckpoint::restore`].
    pub fn new(
        scene: &Scene,
        model: &Model,
        dt: f64,
        out_dir: Option<&Path>,
        csv_every: u64,
        resume: bool,
    ) -> Option<Self> {
        let section = scene.contact.as_ref().filter(|c| c.enabled)?;
        let laws = laws(section, scene, model);
        let settings = ContactSettings {
            buffer: section.buffer,
            max_phi: section.max_phi,
            ..ContactSettings::default()
        };
        let mut contact = Contact::new(settings, laws);
        let props = body_props(model, scene.bodies.len());
        let e_max = props.iter().map(|p| p.0).fold(0.0, f64::max);
        let th_max = props.iter().map(|p| p.1).fold(0.0, f64::max);
        let mut motion = Vec::new();
        for w in &section.walls {
            contact.walls.push(RigidPlane::new(
                w.point,
                w.normal,
                contact_law(&w.law, e_max, th_max),
            ));
            motion.push(WallMotion {
                point0: w.point,
                velocity: w.velocity,
                ramp: w.ramp,
                history: w.history.as_ref().map(History::new),
            });
        }
        let nw = section.walls.len();
        let report = ContactReport {
            wall_force: vec![[0.0; 2]; nw],
            wall_displacement: vec![[0.0; 2]; nw],
            ..Default::default()
        };
        let csv = if nw > 0 {
            out_dir.and_then(|d| {
                let mut head = String::from("time");
                for (i, s) in section.walls.iter().enumerate() {
                    let n = s.name.clone().unwrap_or_else(|| format!("wall{i}"));
                    head.push_str(&format!(",u_x[{n}],u_y[{n}],force_x[{n}],force_y[{n}]"));
                }
                crate::output::open_csv(d, "walls.csv", &head, resume)
            })
        } else {
            None
        };
        let mut stage = Self {
            contact,
            tris: model.triangles.clone(),
            labels: model.tri_body.clone(),
            dt,
            motion,
            reactions: vec![[0.0; 2]; nw],
            prev_force: vec![[0.0; 2]; nw],
            prev_disp: vec![[0.0; 2]; nw],
            bonded: None,
            bonded_set: false,
            released: Vec::new(),
            release_s: 0.0,
            switch_jump: 0.0,
            report,
            active: ActiveBound::new(),
            active_every: section.active_bound_every,
            inv_sqrt_mass: model
                .mass
                .iter()
                .map(|m| if *m > 0.0 { 1.0 / m.sqrt() } else { 0.0 })
                .collect(),
            csv,
            csv_wanted: out_dir.is_some(),
            csv_every: csv_every.max(1),
            steps: 0,
            damped: false,
            damping_dissipated: 0.0,
            damping_power: None,
            node_work: 0.0,
            node_force: Vec::new(),
            node_force_now: Vec::new(),
            node_x: Vec::new(),
            stored0: 0.0,
            book_work: false,
            part: None,
            partial: false,
            looking: false,
        };
        let c = &stage.contact;
        let n = c.laws.n_materials() as u32;
        stage.damped = (0..n).any(|i| (0..n).any(|j| c.laws.get(i, j).damping > 0.0))
            || c.walls.iter().any(|w| w.law.damping > 0.0);
        Some(stage)
    }

    /// Triangle couples of the last detection (pairs within the buffer, bonded pairs excluded).
    pub fn n_couples(&self) -> usize {
        self.contact.couples().len()
    }

    fn place_walls(&mut self, t: f64) {
        for (w, m) in self.contact.walls.iter_mut().zip(&self.motion) {
            let r = time_function::integral(t, m.ramp, m.history.as_ref());
            let s = time_function::factor(t, m.ramp, m.history.as_ref());
            w.point = [
                m.point0[0] + m.velocity[0] * r,
                m.point0[1] + m.velocity[1] * r,
            ];
            w.velocity = [m.velocity[0] * s, m.velocity[1] * s];
        }
    }
}

impl ContactStage {
    /// Hands the model the bonded list at set-up and the pairs released since the last
    /// evaluation (joints softened or broke): the released pairs that the last detection
    /// would have listed become couples now, without a re-detection (the others are more
    /// than the buffer apart and the next regular detection finds them when they come
    /// close). Returns whether couples were added ([`Contact::added_couples`]).
    fn take_releases(&mut self, events: &mut StepEvents) -> bool {
        let Some(initial) = &mut self.bonded else {
            return false;
        };
        if !self.bonded_set {
            // The list at set-up; releases already queued are applied below (the detection
            // is stale then, so they only leave the exclusions).
            self.contact
                .set_bonded(self.tris.len(), &std::mem::take(initial));
            self.bonded_set = true;
        }
        if events.released.is_empty() {
            return false;
        }
        let t0 = std::time::Instant::now();
        std::mem::swap(&mut self.released, &mut events.released);
        self.contact.release_pairs(&self.released, &self.tris);
        self.released.clear();
        self.release_s += t0.elapsed().as_secs_f64();
        !self.contact.added_couples().is_empty()
    }

    /// At the first evaluation, at the initial state, with the work probe on: the forces
    /// and positions the nodal work starts from, and the energy stored then.
    fn start_books(&mut self, t: f64, x: &[[f64; 2]], v: &[[f64; 2]]) {
        let _ = (t, v);
        if self.book_work && self.node_x.is_empty() {
            self.node_force = vec![[0.0; 2]; x.len()];
            self.node_force_now = vec![[0.0; 2]; x.len()];
            self.contact.add_forces(&self.tris, &mut self.node_force);
            self.node_x = x.to_vec();
            let e = self.contact.energy(x, &self.tris, &self.labels);
            self.stored0 = e.potential + e.friction_stored;
        }
    }

    /// Books a force pass's statistics at time `t`: the deepest overlap, the first error,
    /// the active couples; with `step`, the pass of a step (not a look at the state, nor a
    /// distributed run's whole evaluation), the mean overlap too.
    fn book_pass(&mut self, t: f64, stats: &fdem_contact::ContactStats, step: bool) {
        let r = &mut self.report;
        if stats.max_phi > r.max_phi {
            r.max_phi = stats.max_phi;
            r.max_depth_over_altitude = stats.max_phi / 3.0;
        }
        let loaded = (stats.n_active + stats.n_wall_active) as u64;
        if step && loaded > 0 {
            r.phi_sum += stats.sum_phi_loaded;
            r.phi_count += loaded;
        }
        if r.error.is_none()
            && let Err(e) = stats.check(self.contact.settings.max_phi)
        {
            r.error = Some(format!("at t = {t:e} s: {e}"));
        }
        r.active_couples = stats.n_active + stats.n_wall_active;
    }

    /// Whether this step records a sample of the active bound: every `active_every` steps
    /// while some contact carries load (every step it took ~20 % of a fragmenting run's
    /// time).
    fn active_due(&self) -> bool {
        let stats = self.contact.stats();
        self.active_every > 0
            && self.steps.is_multiple_of(self.active_every)
            && stats.n_active + stats.n_wall_active > 0
    }

    /// The end of a step once the model has committed and the step's books are known: `p`
    /// the damping power at the end-of-step velocities (when damped), `w2` the active bound's
    /// sample (0: none), the walls' reactions in `reactions`. Books the dashpots'
    /// dissipation, the walls' work and forces, and writes `walls.csv` (`output.rs`).
    fn book_step(&mut self, t: f64, p: Option<f64>, w2: f64) {
        if let Some(p) = p {
            // trapezoidal rule in time on the power of the end-of-step states
            let (t0, p0) = self.damping_power.unwrap_or((t, p));
            self.damping_dissipated += 0.5 * (p0 + p) * (t - t0);
            self.damping_power = Some((t, p));
        }
        let r = &mut self.report;
        if w2.sqrt() > r.omega_active_max {
            r.omega_active_max = w2.sqrt();
            r.omega_active_max_time = t;
        }
        // Work of the moving walls on the bodies (trapezoid rule on the walls' displacement).
        for (k, m) in self.motion.iter().enumerate() {
            // Force of the wall on the bodies: minus the reaction on the wall; per unit
            // thickness already scaled by the thickness in the laws.
            let f = [-self.reactions[k][0], -self.reactions[k][1]];
            let s = time_function::integral(t, m.ramp, m.history.as_ref());
            let u = [m.velocity[0] * s, m.velocity[1] * s];
            for c in 0..2 {
                r.wall_work += 0.5 * (self.prev_force[k][c] + f[c]) * (u[c] - self.prev_disp[k][c]);
            }
            self.prev_force[k] = f;
            self.prev_disp[k] = u;
            r.wall_force[k] = f;
            r.wall_displacement[k] = u;
        }
        r.detections = self.contact.n_detections();
        self.write_walls_row(t);
    }
}

impl crate::stages::system::Stage for ContactStage {
    fn name(&self) -> &str {
        "contact"
    }
}

impl ForceTerm for ContactStage {
    /// Only friction and contact damping (of a pair of materials or of a wall) read the
    /// velocities (`fdem_contact`'s `compute_forces` and `wall_force`).
    fn reads_velocities(&self) -> bool {
        let c = &self.contact;
        let n = c.laws.n_materials() as u32;
        let moving = |l: &ContactLaw| l.mu > 0.0 || l.damping > 0.0;
        (0..n).any(|i| (0..n).any(|j| moving(c.laws.get(i, j))))
            || c.walls.iter().any(|w| moving(&w.law))
    }

    fn forces(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        events: &mut StepEvents,
    ) {
        if self.part.is_some() && self.partial {
            return self.add_forces_part(t, x, v, f);
        }
        // A look at the state (an output frame) leaves the released pairs for the next step's
        // pass; in a distributed run (the whole state, on one rank) it evaluates every couple
        // and does not detect (the last pass was at these positions and detected if needed).
        let whole = self.part.is_some();
        if !(self.looking || whole) && self.take_releases(events) {
            // Book the contact potential the new couples bring in at these positions (the
            // energy jump of the joint -> contact hand-over; 0 when the faces do not overlap).
            let c = &self.contact;
            self.switch_jump += c.potential_of(c.added_couples(), x, &self.tris, &self.labels);
        }
        self.place_walls(t);
        if whole {
            self.contact.set_whole(true);
        } else {
            self.contact.update_detection(x, &self.tris);
        }
        let stats = self
            .contact
            .compute_forces(x, v, &self.tris, &self.labels, self.dt);
        self.contact.set_whole(false);
        self.contact.add_forces(&self.tris, f);
        self.start_books(t, x, v);
        if self.damped && self.damping_power.is_none() {
            // the first evaluation, at the initial state: the power the dissipation starts from
            self.damping_power = Some((t, self.contact.damping_power(&self.tris, v)));
        }
        self.book_pass(t, &stats, !(self.looking || whole));
    }

    /// The commit and the step's books (the same whether or not the last evaluation was at `x`).
    fn end_of_step(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        _at_last: bool,
        _events: &mut StepEvents,
    ) {
        self.contact.commit();
        self.steps += 1;
        // Work of the contact forces on the nodes over this step (trapezoidal rule on the
        // displacement; the last pass was at the end-of-step positions).
        if !self.node_x.is_empty() {
            self.node_force_now.fill([0.0; 2]);
            self.contact
                .add_forces(&self.tris, &mut self.node_force_now);
            let mut w = 0.0;
            for ((f0, f1), (x0, x1)) in self
                .node_force
                .iter()
                .zip(&self.node_force_now)
                .zip(self.node_x.iter_mut().zip(x))
            {
                w += 0.5 * ((f0[0] + f1[0]) * (x1[0] - x0[0]) + (f0[1] + f1[1]) * (x1[1] - x0[1]));
                *x0 = *x1;
            }
            self.node_work += w;
            std::mem::swap(&mut self.node_force, &mut self.node_force_now);
        }
        // Dissipation of the dashpots: the power of the last pass's damping forces at the
        // end-of-step velocities.
        let p = self
            .damped
            .then(|| self.contact.damping_power(&self.tris, v));
        let w2 = if self.active_due() {
            self.active.omega_sq(
                &self.contact,
                x,
                &self.tris,
                &self.labels,
                &self.inv_sqrt_mass,
            )
        } else {
            0.0
        };
        self.contact.wall_reactions(&mut self.reactions);
        self.book_step(t, p, w2);
    }

    /// [`Engaged::LastEvaluation`]: the contact engaged at the last force evaluation, its
    /// geometry at `x` (`fdem_contact::active_bound`; docs/contact.md section 12);
    /// [`Engaged::Elsewhere`]: every detected couple and wall candidate, its geometry at `x`.
    fn active_frequency_bound(&mut self, x: &[[f64; 2]], at: Engaged) -> Option<f64> {
        let bound = match at {
            Engaged::LastEvaluation => ActiveBound::omega_sq,
            Engaged::Elsewhere => ActiveBound::omega_sq_at,
        };
        let w2 = bound(
            &mut self.active,
            &self.contact,
            x,
            &self.tris,
            &self.labels,
            &self.inv_sqrt_mass,
        );
        Some(w2.sqrt())
    }

    /// The friction increment uses the step.
    fn set_time_step(&mut self, h: f64) {
        self.dt = h;
    }
}

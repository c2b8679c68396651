//! The fluid stage: the fluid in the crack network (`fdem_flow::Network`) as a force term
//! (the pressure on the wetted faces), stepped at the end of each mechanical step.
//!
//! - **Forces**: each force evaluation takes the cavities' volumes at its positions, their
//!   pressures from the fluid they store (moved by the flow at the last end of step) and adds
//!   the pressure's forces on the faces of every channel: within a step the stored fluid is
//!   a spring of the positions (a pressure lagged by a step pumps energy into the solid), and
//!   the flow is staggered, one update per step.
//! - **End of step** at `t`: the joints the fracture stage broke in this step
//!   ([`StepEvents::fractures`]) become channels (with `fluid.wet_damaged`, those that
//!   softened, [`StepEvents::softened`]); the channels' apertures and the cavities'
//!   volumes are taken at the step's end positions; the prescribed pressures take their
//!   values at `t`, the injections put in their volume over the step; the pressures are then
//!   stepped over the mechanical step (backward Euler, or explicit sub-steps: `fluid.stepping`).
//! - **Books**: the fluid's work on the solid is the trapezoidal rule on each step's
//!   displacement of the faces' nodes, with the forces at the step's start and end positions
//!   under the step's pressures ([`StageReport::fluid_work`], a supplied energy of the ledger);
//!   the volume books are the network's ([`fdem_flow::Books`]).
//! - **Time step**: a filled cavity is a spring between its faces; its frequency
//!   ([`fdem_flow::Network::frequency_bound`]) is the stage's active bound.
//! - **Checkpoint** (section `fluid`): the wetted joints and when, the stored volumes, the
//!   books, the work and the faces' forces at the step's start.

use fdem_flow::Network;
use serde::Serialize;

use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::problem::fluid::FluidSetup;
use crate::problem::model::Model;
use crate::stages::system::{
    Engaged, ForceTerm, Stage, StageCheckpoint, StageDistribution, StageOutput, StageReport,
    StepEvents,
};

/// The fluid's books for the summary and the histories.
#[derive(Debug, Clone, Copy, Default, Serialize, PartialEq)]
pub struct FluidBooks {
    /// Volume in the network at the start [m^3].
    pub initial_volume: f64,
    /// Volume injected [m^3].
    pub injected_volume: f64,
    /// Net volume in through the prescribed pressures [m^3].
    pub boundary_volume: f64,
    /// Volume leaked off [m^3].
    pub leaked_volume: f64,
    /// Volume in the network (cavities, up to their volume) [m^3].
    pub stored_volume: f64,
    /// Volume the fluid's compression holds beyond the cavities' volume [m^3].
    pub compressed_volume: f64,
    /// `initial + injected + boundary - stored - compressed - leaked`, relative to the
    /// largest of them.
    pub balance_error: f64,
    /// Pressure at the first injection [Pa] (0 without one).
    pub injection_pressure: f64,
    /// Channels (wetted joints).
    pub channels: usize,
    /// Work of the fluid on the solid [J].
    pub work_on_solid: f64,
    /// Energy the injections put in, `int p Q dt` [J].
    pub injected_energy: f64,
    /// Viscous dissipation in the channels [J].
    pub viscous_dissipation: f64,
}

pub use crate::problem::fluid::COLUMNS;

impl FluidBooks {
    /// The values of [`COLUMNS`]: volumes [m^3] in the network at the start, injected, in through the prescribed
    /// pressures, stored in the network, held by the compression, leaked off; the books'
    /// relative residual; the pressure at the first injection [Pa]; the number of channels.
    pub fn columns(&self) -> [f64; 9] {
        [
            self.initial_volume,
            self.injected_volume,
            self.boundary_volume,
            self.stored_volume,
            self.compressed_volume,
            self.leaked_volume,
            self.balance_error,
            self.injection_pressure,
            self.channels as f64,
        ]
    }
}

/// `fdem check`'s line on the fluid of `l` (`None` without one): the channels at the start,
/// the stepping, the flow's explicit stable step at the start (the cavities' residual or
/// initial volumes) and what it means per mechanical step, and the stiffness cap.
pub fn check_line(l: &crate::problem::load::Problem) -> Option<String> {
    let (setup, set) = (l.fluid.as_ref()?, l.fracturing.set.as_ref()?);
    let state = l
        .initial_joint_state
        .clone()
        .or_else(|| crate::problem::cracks::initial_state(&l.fracturing, &l.model));
    let broken: Vec<bool> = match &state {
        Some(s) => s.intact.iter().map(|i| !i).collect(),
        None => vec![false; set.len()],
    };
    let limit = l.scheme.stability_limit();
    let omega = if l.dt > 0.0 {
        limit / l.dt
    } else {
        f64::INFINITY
    };
    let stage = FluidStage::new(setup, set, &broken, &l.model, omega);
    let net = stage.network();
    let h = net.stable_step();
    let per_step = if h.is_finite() && h > 0.0 {
        format!(
            "{h:.3e} s (explicit: {} sub-steps per step; it falls as the cracks open, as mu / a^2)",
            (l.dt / (EXPLICIT_SAFETY * h)).ceil().max(1.0)
        )
    } else {
        "none (no free cavity with a channel)".into()
    };
    Some(format!(
        "fluid: {} channels at the start, {} stepping ({}); the flow's stable step at the start \
         {per_step}; a filled cavity adds at most {:.3e} rad/s (its bulk modulus is lowered \
         where it would add more)",
        net.channels.len(),
        match setup.stepping {
            crate::input::scene::fluid::FlowStepping::Implicit => "implicit",
            crate::input::scene::fluid::FlowStepping::Explicit => "explicit",
        },
        match setup.stepping {
            crate::input::scene::fluid::FlowStepping::Implicit =>
                "one backward-Euler solve per step",
            crate::input::scene::fluid::FlowStepping::Explicit =>
                "sub-steps below the flow's stable step",
        },
        CAP_FRACTION * omega
    ))
}

/// The books of the fluid stage of `sys`, if it has one.
pub fn books_of(sys: &crate::stages::system::SceneSystem) -> Option<FluidBooks> {
    sys.contributions.iter().find_map(|c| {
        let any: &dyn std::any::Any = c.as_ref();
        any.downcast_ref::<FluidStage>().map(FluidStage::books)
    })
}

/// The fluid stage (a [`Stage`]).
pub struct FluidStage {
    net: Network,
    setup: FluidSetup,
    /// The cavity of each injection.
    source_cavity: Vec<usize>,
    /// Inverse lumped mass per node (the frequency bound).
    inv_mass: Vec<f64>,
    /// The nodes of the channels (increasing) and, per node, the faces' force at the step's
    /// start positions under the step's pressures and those positions.
    work_nodes: Vec<u32>,
    f_start: Vec<[f64; 2]>,
    x_start: Vec<[f64; 2]>,
    /// Scratch: a force per node of the model (zero outside `work_nodes`).
    scratch: Vec<[f64; 2]>,
    /// The fluid's work on the solid [J].
    work: f64,
    /// Time of the last end of step [s].
    t_last: f64,
    /// `(h omega)_scheme` of the run's scheme (the stiffness cap follows the step).
    scheme_limit: f64,
    /// The largest flow sub-steps per mechanical step, and the smallest flow stable step [s].
    max_substeps: u64,
    min_flow_step: f64,
    /// Conjugate-gradient iterations in all.
    iterations: u64,
}

impl FluidStage {
    /// The stage for `setup` on the joints of `set`, with the joints `broken` (the run's
    /// starting state) wet, at the reference positions of `model`.
    ///
    /// `omega_limit`: the largest frequency the time step carries, `(h omega)_scheme / h`;
    /// a cavity adds at most [`CAP_FRACTION`] of it ([`fdem_flow::Network::set_stiffness_cap`]).
    pub fn new(
        setup: &FluidSetup,
        set: &fdem_fracture::JointSet,
        broken: &[bool],
        model: &Model,
        omega_limit: f64,
    ) -> Self {
        let n = model.n_nodes();
        let mut net = Network::new(set.nodes.clone(), n, set.thickness, setup.fluid)
            .expect("the fluid was checked at load");
        let wet =
            (setup.wet.iter().map(|&j| j as usize)).chain((0..broken.len()).filter(|&j| broken[j]));
        net.wet_joints(wet, 0.0);
        let source_cavity = (setup.sources.iter())
            .map(|s| net.vertex_of[s.node as usize] as usize)
            .collect();
        let inv_mass: Vec<f64> = (model.mass.iter())
            .map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 })
            .collect();
        net.set_stiffness_cap(inv_mass.clone(), CAP_FRACTION * omega_limit);
        let mut s = Self {
            net,
            setup: setup.clone(),
            source_cavity,
            inv_mass,
            work_nodes: Vec::new(),
            f_start: Vec::new(),
            x_start: Vec::new(),
            scratch: vec![[0.0; 2]; n],
            work: 0.0,
            t_last: 0.0,
            scheme_limit: 0.0,
            max_substeps: 0,
            min_flow_step: f64::INFINITY,
            iterations: 0,
        };
        s.hold(0.0);
        s.faces_at(&model.x0);
        s.collect_start(&model.x0);
        s
    }

    /// The network (read by the tests).
    pub fn network(&self) -> &Network {
        &self.net
    }

    /// The fluid's books now.
    pub fn books(&self) -> FluidBooks {
        let b = &self.net.books;
        let (stored, compressed) = self.net.network_and_compression();
        FluidBooks {
            initial_volume: b.initial,
            injected_volume: b.injected,
            boundary_volume: b.boundary,
            leaked_volume: b.leaked,
            stored_volume: stored,
            compressed_volume: compressed,
            balance_error: self.net.balance_error(),
            injection_pressure: (self.source_cavity.first()).map_or(0.0, |&v| self.net.pressure[v]),
            channels: self.net.channels.len(),
            work_on_solid: self.work,
            injected_energy: b.injected_energy,
            viscous_dissipation: b.viscous,
        }
    }

    /// The prescribed pressures at `t` into the network's cavities.
    fn hold(&mut self, t: f64) {
        for p in &self.setup.pressures {
            let value = p.at(t);
            for &j in &p.joints {
                for v in self.net.ends(j as usize) {
                    self.net.fixed[v] = value;
                }
            }
        }
    }

    /// The channels' nodes, and the faces' forces at `x` as the last force evaluation there
    /// gave them (in `scratch`, which this zeroes): the start of the next step's work. (The
    /// integrator's first kick of a step reuses that evaluation, before the flow moved.)
    fn collect_start(&mut self, x: &[[f64; 2]]) {
        self.work_nodes.clear();
        for &j in &self.net.channels {
            self.work_nodes.extend(self.net.joints[j as usize]);
        }
        self.work_nodes.sort_unstable();
        self.work_nodes.dedup();
        self.f_start.clear();
        self.x_start.clear();
        for &k in &self.work_nodes {
            self.f_start.push(self.scratch[k as usize]);
            self.x_start.push(x[k as usize]);
            self.scratch[k as usize] = [0.0; 2];
        }
    }

    /// The faces' forces at `x` under the stored fluid into `scratch` (zero there before),
    /// as a force evaluation at `x` gives them.
    fn faces_at(&mut self, x: &[[f64; 2]]) {
        self.net.geometry(x);
        self.net.add_face_forces(x, &mut self.scratch);
    }

    /// The work of the faces' forces over the step that ends at `x` (trapezoidal rule on the
    /// forces the integrator used at the step's two ends), added to the books; the forces at
    /// `x` stay in `scratch` for [`FluidStage::collect_start`].
    fn book_work(&mut self, x: &[[f64; 2]]) {
        self.faces_at(x);
        let mut w = 0.0;
        for (i, &k) in self.work_nodes.iter().enumerate() {
            let (f0, x0) = (self.f_start[i], self.x_start[i]);
            let f1 = self.scratch[k as usize];
            let x1 = x[k as usize];
            w += 0.5 * ((f0[0] + f1[0]) * (x1[0] - x0[0]) + (f0[1] + f1[1]) * (x1[1] - x0[1]));
        }
        self.work += w;
    }
}

impl ForceTerm for FluidStage {
    fn forces(
        &mut self,
        _t: f64,
        x: &[[f64; 2]],
        _v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        _events: &mut StepEvents,
    ) {
        // the cavities' pressures at these positions: the stored fluid is a spring
        self.net.geometry(x);
        self.net.add_face_forces(x, f);
    }

    fn end_of_step(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        _v: &[[f64; 2]],
        _at_last: bool,
        events: &mut StepEvents,
    ) {
        // the stored fluid did its work up to these positions
        self.book_work(x);
        let t0 = self.t_last;
        let dt = t - t0;
        self.t_last = t;
        let broke = events.fractures.iter().map(|e| e.joint.0 as usize);
        self.net.wet_joints(broke, t);
        if self.setup.wet_damaged {
            let softened = events.softened.iter().map(|&j| j as usize);
            self.net.wet_joints(softened, t);
        }
        self.collect_start(x);
        self.hold(t);
        self.net.geometry(x);
        for v in self.net.rate.iter_mut() {
            *v = 0.0;
        }
        if dt > 0.0 {
            for (s, &v) in self.setup.sources.iter().zip(&self.source_cavity) {
                self.net.rate[v] += s.volume(t0, t) / dt;
            }
        }
        match self.setup.stepping {
            crate::input::scene::fluid::FlowStepping::Implicit => {
                self.iterations += self.net.advance_implicit(t0, dt);
            }
            crate::input::scene::fluid::FlowStepping::Explicit => {
                self.min_flow_step = self.min_flow_step.min(self.net.stable_step());
                let n = self.net.advance(t0, dt, EXPLICIT_SAFETY);
                self.max_substeps = self.max_substeps.max(n);
            }
        }
    }

    fn reads_velocities(&self) -> bool {
        false
    }

    fn active_frequency_bound(&mut self, _x: &[[f64; 2]], _at: Engaged) -> Option<f64> {
        Some(self.net.frequency_bound(&self.inv_mass))
    }

    fn set_time_step(&mut self, h: f64) {
        if self.scheme_limit > 0.0 && h > 0.0 {
            let inv = std::mem::take(&mut self.inv_mass);
            self.net
                .set_stiffness_cap(inv.clone(), CAP_FRACTION * self.scheme_limit / h);
            self.inv_mass = inv;
        }
    }
}

/// The fraction of the largest frequency the step carries that a filled cavity may add
/// (with the mechanical bound at 0.9 of it, the sum of squares stays below 1).
pub const CAP_FRACTION: f64 = 0.3;

impl FluidStage {
    /// Sets the scheme's `(h omega)` limit, so that a change of step moves the stiffness cap.
    pub fn set_scheme_limit(&mut self, limit: f64) {
        self.scheme_limit = limit;
    }

    /// The cavities whose bulk modulus the cap lowers, and the smallest ratio `K_v / K`.
    pub fn capped(&self) -> (usize, f64) {
        let k = self.net.fluid.bulk_modulus;
        let mut n = 0;
        let mut r: f64 = 1.0;
        for v in 0..self.net.n_vertices {
            if self.net.is_wetted(v) && self.net.bulk[v] < k {
                n += 1;
                r = r.min(self.net.bulk[v] / k);
            }
        }
        (n, r)
    }
}

/// The explicit sub-steps' fraction of the flow's stable step.
pub const EXPLICIT_SAFETY: f64 = 0.9;

impl StageOutput for FluidStage {
    fn report(&self, _x: &[[f64; 2]]) -> StageReport {
        let b = self.books();
        let mut details = serde_json::to_value(b).unwrap_or_default();
        if let Some(o) = details.as_object_mut() {
            o.insert("stepping".into(), serde_json::json!(self.setup.stepping));
            o.insert("flow_steps".into(), serde_json::json!(self.net.substeps));
            o.insert("max_substeps".into(), serde_json::json!(self.max_substeps));
            o.insert("cg_iterations".into(), serde_json::json!(self.iterations));
            let (n, r) = self.capped();
            o.insert("capped_cavities".into(), serde_json::json!(n));
            o.insert("capped_bulk_ratio_min".into(), serde_json::json!(r));
            o.insert(
                "stiffness_cap".into(),
                serde_json::json!(self.net.stiffness_cap()),
            );
            let fs = self.min_flow_step;
            o.insert(
                "min_flow_step".into(),
                serde_json::json!(fs.is_finite().then_some(fs)),
            );
        }
        StageReport {
            fluid_work: self.work,
            details,
            ..StageReport::default()
        }
    }

    fn error(&self) -> Option<String> {
        let b = self.books();
        if b.balance_error > BALANCE_LIMIT {
            return Some(format!(
                "the fluid's volume books do not close: a relative residual of {:.2e} (the \
                 limit is {BALANCE_LIMIT:.0e})",
                b.balance_error
            ));
        }
        // the fluid can give the solid no more than it was given: a coupling that pumps
        // energy into the solid is unstable (its stiffness beyond the step)
        let given = b.injected_energy + self.net.books.boundary_energy;
        (self.work > WORK_LIMIT * given && self.work > 0.0).then(|| {
            format!(
                "the fluid did {:.3e} J of work on the solid but was given {:.3e} J: the \
                 coupling of the fluid and the solid is unstable (a filled cavity is a spring \
                 of stiffness K / V, beyond the time step): lower fluid.bulk_modulus, use \
                 \"integrator\": {{\"time_step\": \"adaptive\"}} (the step then follows the \
                 fluid's frequency bound), or a smaller integrator.safety",
                self.work, given
            )
        })
    }

    fn frame_fields(&self, _x: &[[f64; 2]], frame: &mut crate::output::FrameData) {
        let Some(joints) = frame.joints.as_mut() else {
            return;
        };
        let n = self.net.joints.len();
        let mut fl = crate::output::JointFluid {
            pressure: vec![0.0; n],
            aperture: vec![0.0; n],
            flow_rate: vec![0.0; n],
            wetted: vec![0; n],
        };
        for (c, &j) in self.net.channels.iter().enumerate() {
            let (j, g) = (j as usize, &self.net.geometry[c]);
            let [a, b] = self.net.ends(j);
            fl.pressure[j] = 0.5 * (self.net.pressure[a] + self.net.pressure[b]);
            fl.aperture[j] = 0.5 * (g.aperture[0] + g.aperture[1]);
            fl.flow_rate[j] = g.flow;
            fl.wetted[j] = 1;
        }
        joints.fluid = Some(fl);
    }
}

/// The fluid's work on the solid, over the energy it was given, that stops a run.
pub const WORK_LIMIT: f64 = 2.0;

/// The relative residual of the volume books that stops a run.
pub const BALANCE_LIMIT: f64 = 1e-9;

impl StageCheckpoint for FluidStage {
    fn save(&mut self, e: &mut Enc, _events: &StepEvents) -> std::io::Result<()> {
        e.section("fluid", |e| {
            let b = &self.net.books;
            e.put(&self.net.joints.len());
            e.put(&self.net.wet);
            e.put(&self.net.wet_since);
            e.put(&self.net.stored);
            e.put(&b.to_array());
            e.put(&self.net.substeps);
            e.put(&self.work);
            e.put(&self.t_last);
            e.put(&self.max_substeps);
            e.put(&self.min_flow_step);
            e.put(&self.iterations);
            e.put(&self.f_start);
            e.put(&self.x_start);
            e.put(
                &self
                    .net
                    .geometry
                    .iter()
                    .map(|g| g.flow)
                    .collect::<Vec<f64>>(),
            );
        });
        Ok(())
    }

    fn restore(&mut self, d: &mut Dec, _events: &mut StepEvents) -> Result<(), DecodeError> {
        let n = self.net.joints.len();
        let nv = self.net.n_vertices;
        let saved = d.section("fluid", |d| {
            let nj: usize = d.get()?;
            if nj != n {
                return Err(d.error(format!("{nj} joints where the scene has {n}")));
            }
            let wet: Vec<bool> = d.vec_of_len(n, "wetted flags")?;
            let since: Vec<f64> = d.vec_of_len(n, "wetting times")?;
            let stored: Vec<f64> = d.vec_of_len(nv, "stored volumes")?;
            let books: [f64; 7] = d.get()?;
            let rest: (u64, f64, f64, u64, f64, u64) =
                (d.get()?, d.get()?, d.get()?, d.get()?, d.get()?, d.get()?);
            let f_start: Vec<[f64; 2]> = d.get()?;
            let x_start: Vec<[f64; 2]> = d.get()?;
            let flows: Vec<f64> = d.get()?;
            Ok((wet, since, stored, books, rest, (f_start, x_start, flows)))
        })?;
        let (wet, since, stored, books, rest, (f_start, x_start, flows)) = saved;
        let js: Vec<usize> = (0..n).filter(|&j| wet[j]).collect();
        self.net.wet_joints(js, 0.0);
        self.net.wet_since = since;
        self.net.stored = stored;
        self.net.books = fdem_flow::Books::from_array(books);
        (self.net.substeps, self.work, self.t_last) = (rest.0, rest.1, rest.2);
        (self.max_substeps, self.min_flow_step, self.iterations) = (rest.3, rest.4, rest.5);
        // the channels' nodes of the restored network, and their saved start
        self.work_nodes.clear();
        for &j in &self.net.channels {
            self.work_nodes.extend(self.net.joints[j as usize]);
        }
        self.work_nodes.sort_unstable();
        self.work_nodes.dedup();
        if f_start.len() != self.work_nodes.len() || x_start.len() != f_start.len() {
            return Err(DecodeError(format!(
                "section `fluid`: {} start forces for {} channel nodes",
                f_start.len(),
                self.work_nodes.len()
            )));
        }
        self.f_start = f_start;
        self.x_start = x_start;
        // the pressures and apertures at the checkpoint's positions
        let mut x = vec![[0.0; 2]; self.scratch.len()];
        for (i, &k) in self.work_nodes.iter().enumerate() {
            x[k as usize] = self.x_start[i];
        }
        self.hold(self.t_last);
        self.net.geometry(&x);
        if flows.len() != self.net.geometry.len() {
            return Err(DecodeError(format!(
                "section `fluid`: {} flows for {} channels",
                flows.len(),
                self.net.geometry.len()
            )));
        }
        for (g, q) in self.net.geometry.iter_mut().zip(flows) {
            g.flow = q;
        }
        Ok(())
    }
}

impl StageDistribution for FluidStage {}

impl Stage for FluidStage {
    fn name(&self) -> &str {
        "fluid"
    }
}

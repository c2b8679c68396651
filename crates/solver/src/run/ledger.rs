//! The energy ledger of a run: one set of named terms that the console summary,
//! `summary.json` (`energy`) and the `energy` probe of `histories.csv` all report, with the
//! same names and, at the same time, the same numbers.
//!
//! ```text
//! error = initial + supplied - present - dissipated
//! initial    = initial_kinetic + initial_strain + initial_stored            (t = 0)
//! supplied   = external_work + gravity_work + support_work + wall_work + fluid_work (since t = 0)
//! present    = kinetic + strain + stored                                    (now)
//! dissipated = mass_damping + viscosity + contact_damping + friction + fracture + switch_loss
//!              + contact_residual + elastic_residual
//! ```
//!
//! How each term is computed (docs/solver.md, "Energy ledger"):
//! - kinetic `1/2 sum m v^2` over every DOF (prescribed ones included); strain: the mesh
//!   crate's strain energy of the triangles; stored: the stages' stored energy (contact
//!   potential and tangential springs, joints);
//! - external_work (pressure, traction, point loads) and the reaction part of support_work:
//!   trapezoidal rule on each step's displacement of the loaded / prescribed DOFs; the
//!   supports also supply the kinetic energy of the prescribed DOFs' change of velocity
//!   (`1/2 m v^2` there, now less at t = 0); gravity_work `sum m g . (x - x_0)` (exact, dead
//!   load); wall_work: the contact stage's trapezoidal work of the moving walls; fluid_work:
//!   the fluid stage's trapezoidal work of the pressure on the crack faces;
//! - mass_damping `int alpha sum m v^2 dt`, viscosity `int P_visc dt` (the mesh crate's
//!   viscous stress power), contact_damping `int P_dashpots dt`: trapezoidal rule in time on
//!   the end-of-step states; friction and fracture: the contact and joint books; switch_loss:
//!   energy stored in joints at their breaks less the contact potential that released pairs
//!   brought in; contact_residual: what the contact's books (walls' work, stored energy,
//!   friction, damping) leave unexplained of the trapezoidal work of the contact forces on
//!   the nodes (the pair potential is exact for rigid relative motion only);
//!   elastic_residual: the same for the element forces (Munjiza's law has no potential).
//!
//! Each quadrature is second order, so for a second-order scheme `error` is the integration
//! error, `O(h^2)`: it converges at second order as the step is refined (a term left out of
//! the books would show as an error that does not). A term the scene lacks is not computed
//! per step (no loads, no supports, `alpha = 0`, no viscosity, no contact damping), and
//! nothing is allocated per step.

use serde::Serialize;

use fdem_time::State;

use crate::checkpoint::pack::{Dec, DecodeError, Enc, Pack};
use crate::problem::model::Model;
use crate::stages::system::{SceneSystem, StageReport};

/// The energy ledger [J] (see the module docs): the terms at t = 0, supplied since, present
/// now, dissipated since, their totals and the error that closes the books.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Energies {
    /// Kinetic energy at t = 0.
    pub initial_kinetic: f64,
    /// Strain energy at t = 0.
    pub initial_strain: f64,
    /// Energy stored by contact and joints at t = 0.
    pub initial_stored: f64,
    /// `initial_kinetic + initial_strain + initial_stored`.
    pub initial: f64,
    /// Work of the loads: pressure, traction and point loads (trapezoidal rule on each
    /// step's displacement).
    pub external_work: f64,
    /// Work of gravity, `sum m g . (x - x_0)`.
    pub gravity_work: f64,
    /// Work of the supports at prescribed-velocity DOFs: their reaction's work plus the
    /// kinetic energy they gave those DOFs.
    pub support_work: f64,
    /// Work of the moving rigid walls (platens) on the bodies.
    pub wall_work: f64,
    /// Work of the fluid's pressure on the crack faces (scenes with a `"fluid"` section;
    /// not written without one, and part of `supplied`, with no column of its own in
    /// `histories.csv`).
    #[serde(skip_serializing_if = "is_zero")]
    pub fluid_work: f64,
    /// `external_work + gravity_work + support_work + wall_work + fluid_work`.
    pub supplied: f64,
    /// Kinetic energy now.
    pub kinetic: f64,
    /// Strain energy now.
    pub strain: f64,
    /// Energy stored by contact (potential, friction springs) and joints now.
    pub stored: f64,
    /// `kinetic + strain + stored`.
    pub present: f64,
    /// Dissipated by mass-proportional damping, `int alpha sum m v^2 dt`.
    pub mass_damping: f64,
    /// Dissipated by the element viscosity (`damping.viscosity_ratio`), the viscous stress
    /// power integrated over time.
    pub viscosity: f64,
    /// Dissipated by contact damping (normal dashpots of the contact laws and walls).
    pub contact_damping: f64,
    /// Dissipated by friction slip.
    pub friction: f64,
    /// Dissipated by the softening of joints (fracture).
    pub fracture: f64,
    /// Lost at the switches between joints and contact: energy stored in joints at their
    /// breaks less the contact potential brought in by the pairs the joints released.
    pub switch_loss: f64,
    /// Removed by the contact forces beyond the contact's books: the work of the walls less
    /// the change of the contact's stored energy, its friction and damping dissipation and
    /// the work its forces did on the nodes. The pair potential is an exact potential of the
    /// contact force for rigid relative motion only, so deforming triangles in contact leave a
    /// residual while they touch (it returns as they separate).
    pub contact_residual: f64,
    /// Removed by the element forces beyond the change of `strain` and the `viscosity`
    /// dissipation: minus their work on the nodes (trapezoidal rule on each step's
    /// displacement) less those two. Munjiza's law (`"linear-elastic"`) has no strain-energy
    /// potential and `strain` is its small-strain value, so finite strains (e.g. under a
    /// contact) leave a residual; 0 with `"neo-hookean"` (an exact potential; not computed).
    pub elastic_residual: f64,
    /// `mass_damping + viscosity + contact_damping + friction + fracture + switch_loss +
    /// contact_residual + elastic_residual`.
    pub dissipated: f64,
    /// `initial + supplied - present - dissipated`: the integration error (`O(h^2)`).
    pub error: f64,
    /// The energy in play, `initial + |external_work| + |gravity_work| + |support_work| +
    /// |wall_work|`: the scale of `error`.
    pub in_play: f64,
    /// The static solve's closure `external_work + support_work - strain` as it builds its
    /// summary; [`Energies::close`] turns the static terms into the ledger (not written).
    #[serde(skip)]
    pub dissipated_or_error: f64,
    /// Whether `contact_residual` and `elastic_residual` were booked (a run that records the
    /// `energy` probe). Without it both are 0 and `error` holds them besides the integration
    /// error: booking them costs about a tenth of the step on a fracturing disc.
    pub residuals_booked: bool,
}

/// True for 0 (a term a scene without it does not write).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Number of ledger terms ([`Energies::columns`]), as the history rows are sized at load.
pub const N_COLUMNS: usize = crate::problem::limits::ENERGY_COLUMNS;

impl Energies {
    /// Sets the totals (`initial`, `supplied`, `present`, `dissipated`, `in_play`) and the
    /// `error` from the terms.
    pub fn close(&mut self) {
        self.initial = self.initial_kinetic + self.initial_strain + self.initial_stored;
        self.supplied = self.external_work
            + self.gravity_work
            + self.support_work
            + self.wall_work
            + self.fluid_work;
        self.present = self.kinetic + self.strain + self.stored;
        self.dissipated = self.mass_damping
            + self.viscosity
            + self.contact_damping
            + self.friction
            + self.fracture
            + self.switch_loss
            + self.contact_residual
            + self.elastic_residual;
        self.error = self.initial + self.supplied - self.present - self.dissipated;
        self.in_play = self.initial
            + self.external_work.abs()
            + self.gravity_work.abs()
            + self.support_work.abs()
            + self.wall_work.abs()
            + self.fluid_work.abs();
        self.dissipated_or_error = 0.0;
    }

    /// `error / in_play` (0 when nothing is in play).
    pub fn relative_error(&self) -> f64 {
        if self.in_play > 0.0 {
            self.error / self.in_play
        } else {
            0.0
        }
    }

    /// Every term by name, in the order of `summary.json` and of the `energy` columns of
    /// `histories.csv`.
    pub fn columns(&self) -> [(&'static str, f64); N_COLUMNS] {
        [
            ("initial_kinetic", self.initial_kinetic),
            ("initial_strain", self.initial_strain),
            ("initial_stored", self.initial_stored),
            ("initial", self.initial),
            ("external_work", self.external_work),
            ("gravity_work", self.gravity_work),
            ("support_work", self.support_work),
            ("wall_work", self.wall_work),
            ("supplied", self.supplied),
            ("kinetic", self.kinetic),
            ("strain", self.strain),
            ("stored", self.stored),
            ("present", self.present),
            ("mass_damping", self.mass_damping),
            ("viscosity", self.viscosity),
            ("contact_damping", self.contact_damping),
            ("friction", self.friction),
            ("fracture", self.fracture),
            ("switch_loss", self.switch_loss),
            ("contact_residual", self.contact_residual),
            ("elastic_residual", self.elastic_residual),
            ("dissipated", self.dissipated),
            ("error", self.error),
            ("in_play", self.in_play),
        ]
    }

    /// One line for the terminal: the closure error against the energy in play (`what`
    /// it is, when given: the round-off of a static solve) and the largest book (the term of
    /// largest magnitude, sums left out); every term is in `summary.json`.
    pub fn line(&self, what: Option<&str>) -> String {
        const SUMS: [&str; 6] = [
            "initial",
            "supplied",
            "present",
            "dissipated",
            "error",
            "in_play",
        ];
        let largest = self
            .columns()
            .into_iter()
            .filter(|(n, _)| !SUMS.contains(n))
            .fold(
                ("none", 0.0f64),
                |a, b| if b.1.abs() > a.1.abs() { b } else { a },
            );
        format!(
            "energy: closure error {:.2e} J = {:.1e} of the {:.3e} J in play ({}); largest book {} {:.3e} J (every book: summary.json \"energy\")",
            self.error,
            self.relative_error(),
            self.in_play,
            what.unwrap_or(if self.residuals_booked {
                "integration error"
            } else {
                "integration error and the laws' residuals"
            }),
            largest.0,
            largest.1
        )
    }

    /// The names of [`Energies::columns`].
    pub fn column_names() -> [&'static str; N_COLUMNS] {
        Energies::default().columns().map(|(n, _)| n)
    }

    /// The ledger of a static solve from the terms it builds (`external_work`: loads and
    /// gravity at full strength, `support_work`, `strain`, each `1/2 f . u`), with the work of
    /// gravity `1/2 sum m g . u` taken apart.
    pub fn from_static(e: &Energies, gravity_work: f64) -> Energies {
        let mut l = Energies {
            strain: e.strain,
            kinetic: e.kinetic,
            external_work: e.external_work - gravity_work,
            gravity_work,
            support_work: e.support_work,
            ..Energies::default()
        };
        l.close();
        l
    }
}

/// The running books of a dynamic or relaxation run: the time integrals of the ledger
/// (works and dissipations), updated after each accepted step, and the state at t = 0.
pub struct Books {
    /// Initial terms and the time integrals so far (`external_work`, the reaction part of
    /// `support_work`, `mass_damping`, `viscosity`).
    sums: Energies,
    loaded_dofs: Vec<usize>,
    fext_full: Vec<f64>,
    prev_fext: Vec<f64>,
    prev_x_loaded: Vec<f64>,
    prescribed: Vec<usize>,
    prev_r_pres: Vec<f64>,
    prev_x_pres: Vec<f64>,
    /// Kinetic energy of the prescribed DOFs at t = 0.
    k_prescribed0: f64,
    /// Mass per DOF.
    pub mass_dof: Vec<f64>,
    alpha: f64,
    /// Mass-damping power at the last booked state [W].
    p_mass: f64,
    /// Viscous power at the last booked state [W].
    p_visc: f64,
    visc_sums: Vec<f64>,
    /// Positions at t = 0 (only with gravity).
    grav0: Vec<f64>,
    t_prev: f64,
    /// Work of the element forces on the nodes so far [J], their value and the positions
    /// at the last booked state (empty: not booked, the elements have a potential).
    internal_work: f64,
    prev_f_int: Vec<[f64; 2]>,
    prev_x: Vec<[f64; 2]>,
    /// Whether the element and contact forces' work is booked ([`Books::prepare`]).
    book_residuals: bool,
}

impl Books {
    /// Prepares `sys` before its first force evaluation: with `book_residuals` (the scene
    /// records the `energy` probe), the work of the element forces is booked when some
    /// material has no strain-energy potential (Munjiza's law), and then the system keeps its
    /// internal forces apart. Without it the residuals cost nothing and stay in `error`.
    pub fn prepare(sys: &mut SceneSystem, book_residuals: bool) {
        if book_residuals
            && sys
                .elements
                .materials
                .iter()
                .any(|m| m.law == fdem_mesh::ElasticLaw::Munjiza)
        {
            sys.keep_internal_forces();
        }
    }

    /// The books at t = 0 of a system whose force at the initial state `state` was just
    /// evaluated (the reactions at the supports are read from it) and whose stages are
    /// attached; `alpha` is the mass-proportional damping.
    pub fn new(sys: &mut SceneSystem, state: &State, alpha: f64, book_residuals: bool) -> Self {
        let n = sys.model.n_nodes();
        let mut loaded_dofs: Vec<usize> = sys
            .model
            .loads
            .iter()
            .flat_map(|ld| ld.forces.iter().map(|(d, _)| *d as usize))
            .collect();
        loaded_dofs.sort_unstable();
        loaded_dofs.dedup();
        let prescribed: Vec<usize> = sys
            .model
            .prescribed
            .iter()
            .map(|p| p.dof as usize)
            .collect();
        let mut fext_full = if loaded_dofs.is_empty() {
            Vec::new()
        } else {
            vec![0.0; 2 * n]
        };
        external_loads(&sys.model, &loaded_dofs, state.t, &mut fext_full);
        let prev_fext = loaded_dofs.iter().map(|&d| fext_full[d]).collect();
        let prev_x_loaded = loaded_dofs.iter().map(|&d| state.x[d]).collect();
        let f = sys.force.as_flattened();
        let prev_r_pres = prescribed.iter().map(|&d| -f[d]).collect();
        let prev_x_pres = prescribed.iter().map(|&d| state.x[d]).collect();
        let mass_dof: Vec<f64> = sys.model.mass.iter().flat_map(|m| [*m, *m]).collect();
        let grav0 = if sys.model.gravity.is_some() {
            state.x.clone()
        } else {
            Vec::new()
        };
        let stored = if sys.contributions.is_empty() {
            0.0
        } else {
            crate::stages::reports(sys, state.x_nodes()).0.stored
        };
        let mut books = Books {
            sums: Energies {
                initial_kinetic: kinetic_energy(&mass_dof, &state.v),
                initial_strain: sys.elements.strain_energy(state.x_nodes()),
                initial_stored: stored,
                ..Energies::default()
            },
            loaded_dofs,
            fext_full,
            prev_fext,
            prev_x_loaded,
            k_prescribed0: 0.0,
            prescribed,
            prev_r_pres,
            prev_x_pres,
            mass_dof,
            alpha,
            p_mass: 0.0,
            p_visc: 0.0,
            visc_sums: Vec::new(),
            grav0,
            t_prev: state.t,
            internal_work: 0.0,
            book_residuals,
            prev_f_int: sys.internal_force.clone(),
            prev_x: if sys.internal_force.is_empty() {
                Vec::new()
            } else {
                state.x_nodes().to_vec()
            },
        };
        books.k_prescribed0 = books.k_prescribed(&state.v);
        books.p_mass = books.mass_damping_power(&state.v);
        books.p_visc =
            sys.elements
                .viscous_power(state.x_nodes(), state.v_nodes(), &mut books.visc_sums);
        books
    }

    /// The mass-proportional damping is `alpha` from the state of velocities `v` on (the
    /// last booked one): an adaptive relaxation.
    pub fn set_alpha(&mut self, alpha: f64, v: &[f64]) {
        self.alpha = alpha;
        self.p_mass = self.mass_damping_power(v);
    }

    /// Books `e` [J] as removed by a relaxation's kinetic damping (in `mass_damping`).
    pub fn book_removed(&mut self, e: f64) {
        self.sums.mass_damping += e;
    }

    /// The initial energy (kinetic, strain, stored at t = 0).
    pub fn initial(&self) -> f64 {
        self.sums.initial_kinetic + self.sums.initial_strain + self.sums.initial_stored
    }

    /// Books the accepted step that just ended at `state` (from the time of the last call):
    /// the works of the loads and supports on its displacement, and the damping and viscous
    /// dissipation over its duration. Terms the scene lacks cost nothing.
    pub fn step(&mut self, sys: &mut SceneSystem, state: &State) {
        let h = state.t - self.t_prev;
        self.t_prev = state.t;
        if !self.loaded_dofs.is_empty() {
            external_loads(&sys.model, &self.loaded_dofs, state.t, &mut self.fext_full);
            for (k, &d) in self.loaded_dofs.iter().enumerate() {
                let f1 = self.fext_full[d];
                self.sums.external_work +=
                    0.5 * (self.prev_fext[k] + f1) * (state.x[d] - self.prev_x_loaded[k]);
                self.prev_fext[k] = f1;
                self.prev_x_loaded[k] = state.x[d];
            }
        }
        if !self.prescribed.is_empty() {
            let f = sys.force.as_flattened();
            for (k, &d) in self.prescribed.iter().enumerate() {
                let r1 = -f[d];
                self.sums.support_work +=
                    0.5 * (self.prev_r_pres[k] + r1) * (state.x[d] - self.prev_x_pres[k]);
                self.prev_r_pres[k] = r1;
                self.prev_x_pres[k] = state.x[d];
            }
        }
        if self.alpha > 0.0 {
            let p = self.mass_damping_power(&state.v);
            self.sums.mass_damping += 0.5 * (self.p_mass + p) * h;
            self.p_mass = p;
        }
        if !self.prev_f_int.is_empty() {
            if !sys.evaluated_at_end {
                // the scheme's last evaluation was not at the step's end (PC, OMF32, or a
                // gradient by finite differences): the element forces there
                sys.refresh_internal_forces(state.x_nodes(), state.v_nodes());
            }
            let mut w = 0.0;
            for ((f0, f1), (x0, x1)) in self
                .prev_f_int
                .iter_mut()
                .zip(&sys.internal_force)
                .zip(self.prev_x.iter_mut().zip(state.x_nodes()))
            {
                w += 0.5 * ((f0[0] + f1[0]) * (x1[0] - x0[0]) + (f0[1] + f1[1]) * (x1[1] - x0[1]));
                *f0 = *f1;
                *x0 = *x1;
            }
            self.internal_work += w;
        }
        if sys.elements.viscous {
            let p =
                sys.elements
                    .viscous_power(state.x_nodes(), state.v_nodes(), &mut self.visc_sums);
            self.sums.viscosity += 0.5 * (self.p_visc + p) * h;
            self.p_visc = p;
        }
    }

    /// The ledger at `state`, with the stages' report at its positions (`None`: the
    /// scene has no stages).
    pub fn ledger(
        &self,
        sys: &SceneSystem,
        state: &State,
        stages: Option<&StageReport>,
    ) -> Energies {
        let mut e = self.sums;
        e.residuals_booked = self.book_residuals;
        e.gravity_work = self.gravity_work(&sys.model, &state.x);
        e.support_work += self.k_prescribed(&state.v) - self.k_prescribed0;
        e.kinetic = kinetic_energy(&self.mass_dof, &state.v);
        e.strain = sys.elements.strain_energy(state.x_nodes());
        if !self.prev_f_int.is_empty() {
            e.elastic_residual = -self.internal_work - e.viscosity - (e.strain - e.initial_strain);
        }
        if let Some(r) = stages {
            e.stored = r.stored;
            e.wall_work = r.wall_work;
            e.fluid_work = r.fluid_work;
            e.friction = r.friction;
            e.contact_damping = r.contact_damping;
            e.fracture = r.fracture;
            e.switch_loss = r.switch_loss;
            e.contact_residual = r.contact_residual;
        }
        e.close();
        e
    }

    /// The energy supplied so far for the run's energy-growth check: the initial energy,
    /// `|W_loads + W_gravity| + |W_supports| + |wall_work|` and the kinetic energy of the
    /// prescribed DOFs now.
    pub fn supplied_bound(&self, model: &Model, state: &State, wall_work: f64) -> f64 {
        let kp = self.k_prescribed(&state.v);
        self.initial()
            + (self.sums.external_work + self.gravity_work(model, &state.x)).abs()
            + (self.sums.support_work + kp - self.k_prescribed0).abs()
            + wall_work.abs()
            + kp
    }

    /// The kinetic energy of the DOFs with a prescribed velocity or displacement.
    pub fn k_prescribed(&self, v: &[f64]) -> f64 {
        self.prescribed
            .iter()
            .map(|&d| 0.5 * self.mass_dof[d] * v[d] * v[d])
            .sum()
    }

    fn mass_damping_power(&self, v: &[f64]) -> f64 {
        if self.alpha > 0.0 {
            2.0 * self.alpha * kinetic_energy(&self.mass_dof, v)
        } else {
            0.0
        }
    }

    fn gravity_work(&self, model: &Model, x: &[f64]) -> f64 {
        match model.gravity {
            None => 0.0,
            Some(g) => model
                .weight_mass()
                .iter()
                .enumerate()
                .map(|(i, m)| {
                    m * (g[0] * (x[2 * i] - self.grav0[2 * i])
                        + g[1] * (x[2 * i + 1] - self.grav0[2 * i + 1]))
                })
                .sum(),
        }
    }
}

/// `1/2 sum m v^2` over the DOFs.
pub fn kinetic_energy(m: &[f64], v: &[f64]) -> f64 {
    0.5 * m.iter().zip(v).map(|(m, v)| m * v * v).sum::<f64>()
}

/// The loads (not gravity) at time `t` on the loaded DOFs of `buf` (the others untouched).
fn external_loads(m: &Model, loaded_dofs: &[usize], t: f64, buf: &mut [f64]) {
    if loaded_dofs.is_empty() {
        return;
    }
    for &d in loaded_dofs {
        buf[d] = 0.0;
    }
    for ld in &m.loads {
        let s = ld.factor(t);
        for &(d, v) in &ld.forces {
            buf[d as usize] += s * v;
        }
    }
}

impl Pack for Energies {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.initial_kinetic);
        e.put(&self.initial_strain);
        e.put(&self.initial_stored);
        e.put(&self.initial);
        e.put(&self.external_work);
        e.put(&self.gravity_work);
        e.put(&self.support_work);
        e.put(&self.wall_work);
        e.put(&self.supplied);
        e.put(&self.kinetic);
        e.put(&self.strain);
        e.put(&self.stored);
        e.put(&self.present);
        e.put(&self.mass_damping);
        e.put(&self.viscosity);
        e.put(&self.contact_damping);
        e.put(&self.friction);
        e.put(&self.fracture);
        e.put(&self.switch_loss);
        e.put(&self.contact_residual);
        e.put(&self.elastic_residual);
        e.put(&self.dissipated);
        e.put(&self.error);
        e.put(&self.in_play);
        e.put(&self.dissipated_or_error);
        e.put(&self.residuals_booked);
        e.put(&self.fluid_work);
    }

    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok(Self {
            initial_kinetic: d.get()?,
            initial_strain: d.get()?,
            initial_stored: d.get()?,
            initial: d.get()?,
            external_work: d.get()?,
            gravity_work: d.get()?,
            support_work: d.get()?,
            wall_work: d.get()?,
            supplied: d.get()?,
            kinetic: d.get()?,
            strain: d.get()?,
            stored: d.get()?,
            present: d.get()?,
            mass_damping: d.get()?,
            viscosity: d.get()?,
            contact_damping: d.get()?,
            friction: d.get()?,
            fracture: d.get()?,
            switch_loss: d.get()?,
            contact_residual: d.get()?,
            elastic_residual: d.get()?,
            dissipated: d.get()?,
            error: d.get()?,
            in_play: d.get()?,
            dissipated_or_error: d.get()?,
            residuals_booked: d.get()?,
            fluid_work: d.get()?,
        })
    }
}

impl Books {
    /// Appends the books to a checkpoint: the sums and the last booked state (the masses
    /// per DOF are the model's).
    pub fn save(&self, e: &mut Enc) {
        e.put(&self.sums);
        e.put(&self.loaded_dofs);
        e.put(&self.fext_full);
        e.put(&self.prev_fext);
        e.put(&self.prev_x_loaded);
        e.put(&self.prescribed);
        e.put(&self.prev_r_pres);
        e.put(&self.prev_x_pres);
        e.put(&self.k_prescribed0);
        e.put(&self.alpha);
        e.put(&self.p_mass);
        e.put(&self.p_visc);
        e.put(&self.visc_sums);
        e.put(&self.grav0);
        e.put(&self.t_prev);
        e.put(&self.internal_work);
        e.put(&self.prev_f_int);
        e.put(&self.prev_x);
        e.put(&self.book_residuals);
    }

    /// The books [`Books::save`] wrote, for the system of `model`.
    pub fn restore(d: &mut Dec, model: &Model) -> Result<Self, DecodeError> {
        let n = model.n_nodes();
        let b = Books {
            sums: d.get()?,
            loaded_dofs: d.get()?,
            fext_full: d.get()?,
            prev_fext: d.get()?,
            prev_x_loaded: d.get()?,
            prescribed: d.get()?,
            prev_r_pres: d.get()?,
            prev_x_pres: d.get()?,
            k_prescribed0: d.get()?,
            mass_dof: model.mass.iter().flat_map(|m| [*m, *m]).collect(),
            alpha: d.get()?,
            p_mass: d.get()?,
            p_visc: d.get()?,
            visc_sums: d.get()?,
            grav0: d.get()?,
            t_prev: d.get()?,
            internal_work: d.get()?,
            prev_f_int: d.get()?,
            prev_x: d.get()?,
            book_residuals: d.get()?,
        };
        let dofs_ok = b
            .loaded_dofs
            .iter()
            .chain(&b.prescribed)
            .all(|&k| k < 2 * n);
        let sizes_ok = b.prev_fext.len() == b.loaded_dofs.len()
            && b.prev_x_loaded.len() == b.loaded_dofs.len()
            && b.prev_r_pres.len() == b.prescribed.len()
            && b.prev_x_pres.len() == b.prescribed.len()
            && (b.fext_full.is_empty() || b.fext_full.len() == 2 * n)
            && (b.grav0.is_empty() || b.grav0.len() == 2 * n)
            && (b.prev_f_int.is_empty() || b.prev_f_int.len() == n)
            && (b.prev_x.is_empty() || b.prev_x.len() == n);
        if !(dofs_ok && sizes_ok) {
            return Err(d.error("the energy books do not fit the scene's nodes"));
        }
        Ok(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names of the numbers of `summary.json`'s `energy` object are the ledger's column
    /// names (those of the console and of `histories.csv`), one for one; the one other field
    /// is the flag `residuals_booked`.
    #[test]
    fn summary_names_are_the_column_names() {
        let v = serde_json::to_value(Energies::default()).unwrap();
        let o = v.as_object().unwrap();
        assert_eq!(o["residuals_booked"], serde_json::json!(false));
        let mut keys: Vec<&str> = o
            .iter()
            .filter(|(_, v)| v.is_number())
            .map(|(k, _)| k.as_str())
            .collect();
        assert_eq!(keys.len() + 1, o.len());
        let mut names = Energies::column_names().to_vec();
        keys.sort_unstable();
        names.sort_unstable();
        assert_eq!(keys, names);
    }

    /// `close` sets the totals and the error: initial + supplied - present - dissipated.
    #[test]
    fn close_balances_the_books() {
        let mut e = Energies {
            initial_kinetic: 10.0,
            initial_stored: 1.0,
            external_work: 3.0,
            support_work: -2.0,
            wall_work: 4.0,
            kinetic: 5.0,
            strain: 2.0,
            stored: 1.5,
            mass_damping: 1.0,
            viscosity: 0.5,
            friction: 2.0,
            fracture: 3.0,
            switch_loss: -0.25,
            ..Energies::default()
        };
        e.close();
        assert_eq!(e.initial, 11.0);
        assert_eq!(e.supplied, 5.0);
        assert_eq!(e.present, 8.5);
        assert_eq!(e.dissipated, 6.25);
        assert_eq!(e.error, 11.0 + 5.0 - 8.5 - 6.25);
        assert_eq!(e.in_play, 11.0 + 3.0 + 2.0 + 4.0);
    }
}

//! # fdem-fracture: joint elements for fracture in FDEM
//!
//! Munjiza's combined single and smeared crack model on four-node joint elements bonding the
//! edges of the triangles of a fracturing region (each triangle owns its nodes there). Theory
//! and validation: `docs/fracture.md`; equations of each part in its module:
//!
//! - [`softening`]: pre-peak curve `ft (2x - x^2)` and the Evans-Marathe curve `z(D)`
//!   (a = 0.63, b = 1.8, c = 6), `I_z = 0.386307`.
//! - [`material`]: inputs (`ft`, `c`, `phi`, `G_I`, `G_II`, `p`, `p_t`), stiffness `p/h` with `h`
//!   the reference edge length, `o_p = 2 h ft/p`, `o_c = o_p + (G_I - (2/3) ft o_p)/(I_z ft)`
//!   so that a joint dissipates exactly `G` times its area in a pure mode.
//! - [`joint`]: kinematics at the two nodal integration points, the mixed-mode law with damage
//!   `D = max(D_old, sqrt(<o-o_p>^2/(o_c-o_p)^2 + <|s|-s_p>^2/(s_c-s_p)^2))`, secant unloading,
//!   compression `(p/h) o`, Mohr-Coulomb shear strength `c + sigma_c tan(phi)` with a shear
//!   secant history `k_t = min(k_t_old, tau_law/|s|)` (the law's shear depends on sigma and
//!   has no potential: without the history a joint can create energy), nodal forces on the
//!   reference area `h t/2` that conserve linear and angular momentum exactly.
//! - [`pass`]: the parallel force pass ([`accumulate_joint_forces`], read-only on the
//!   committed history; it writes the forces and the trial history, with the dissipation of
//!   a step whose history changes, into the caller's scratch) and the end-of-step
//!   [`commit_joints`] (damage, energy books, breaking when fully damaged and open (or slid by
//!   `h/10`), events); at the positions of the last pass the commit swaps the trial arrays
//!   in (structure of arrays, [`state`]) instead of evaluating again.
//! - [`state`]: the committed history of every joint and the energy books;
//!   [`JointStateSnapshot`] is a state as plain data (a checkpoint's), checked against the
//!   joint set by [`JointState::from_snapshot`].
//! - [`set`]: the joints as plain arrays; [`JointSet::set_initial_tractions`] prestresses them
//!   (an in-situ stress): constant offsets of the opening and sliding at which the undamaged
//!   law gives the initial traction, so the joint carries it at zero deformation.
//! - [`timestep`]: the joints' bound on `omega^2` for the stable time step.
//! - [`events`]: a broken joint reported as data ([`FractureEvent`]): the solver hands the
//!   two triangles to contact; this crate does not depend on contact.
//!
//! Use (the solver's loop):
//!
//! ```
//! use fdem_fracture::*;
//! let mat = JointMaterialInput {
//!     tensile_strength: 5e6, cohesion: 10e6, friction_angle_deg: 30.0,
//!     fracture_energy_i: 50.0, fracture_energy_ii: 250.0,
//!     penalty_normal: 3e12, penalty_tangential: 3e12,
//! };
//! // two triangles' edges, P = 0, Q = 1 (T1) and R = 2, S = 3 (T2), length 1 cm
//! let joints = [Joint { nodes: [0, 1, 2, 3], triangles: [0, 1], ref_length: 0.01, material: 0 }];
//! let mut x = vec![[0.0, 0.0], [0.01, 0.0], [0.01, 0.0], [0.0, 0.0]];
//! let set = JointSet::new(&joints, &[mat], x.len(), 1.0).unwrap();
//! let mut state = JointState::new(&set, &x);
//! let mut scratch = JointScratch::new(set.len());
//! let (mut f, mut events) = (vec![[0.0; 2]; 4], Vec::new());
//! x[2][1] -= 1e-6; x[3][1] -= 1e-6;                     // open by 1 um (nn points to -y)
//! accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f);   // each force stage
//! commit_joints(&set, &mut state, &x, 1e-6, &mut scratch, &mut events); // end of step
//! assert!(f[3][1] > 0.0 && events.is_empty());           // S pulled back towards P
//! ```
#![forbid(unsafe_code)]

pub mod error;
pub mod events;
pub mod heterogeneity;
pub mod joint;
mod lanes;
pub mod material;
pub mod pass;
pub mod set;
pub mod softening;
pub mod state;
pub mod timestep;

pub use error::FractureError;
pub use events::{FractureEvent, FractureMode};
pub use heterogeneity::{Distribution, Heterogeneity};
pub use joint::{
    JointEval, JointKinematics, PointHistory, PointTraction, evaluate, evaluate_forces,
    evaluate_offset, kinematics, point_traction,
};
pub use material::{JointConsts, JointMaterial, JointMaterialInput, SofteningConsts};
pub use pass::{
    JointScratch, accumulate_joint_forces, accumulate_joint_forces_committing, add_joint_forces,
    commit_joints, commit_joints_at_last_pass, joint_forces_ahead, joint_forces_ahead_committing,
};
pub use set::{Joint, JointId, JointSet};
pub use softening::{Z_INTEGRAL, z};
pub use state::{Histories, JointBooks, JointEnergy, JointState, JointStateSnapshot};
pub use timestep::{joint_omega_sq_bound, joint_omega_sq_bound_intact};

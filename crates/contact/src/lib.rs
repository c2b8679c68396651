//! Contact for fdem: Munjiza's distributed potential contact force between triangles, Coulomb
//! friction with a tangential penalty, rigid planes and platens, and NBS contact detection.
//!
//! All kernels take plain data: node positions and velocities `&[[f64; 2]]`, triangles
//! `&[[u32; 3]]` (CCW), and accumulate node forces into `&mut [[f64; 2]]`. Forces and
//! energies are per unit thickness (multiply by the thickness `t`).
//!
//! # Equations
//!
//! * Potential of a triangle: `phi(x) = 3 min(lam_0, lam_1, lam_2)` (barycentric `lam_k`).
//! * Force on contactor c from target t, penalty p:
//!   `f_c = p int_{c∩t} (grad phi_c - grad phi_t) dA
//!        = -p int_{edges of c in t} phi_t n_c ds + p int_{edges of t in c} phi_c n_t ds`,
//!   evaluated in closed form per edge piece and lumped consistently
//!   ([`potential_tri_tri`]).
//! * Energy `W = p int_{c∩t} (phi_c + phi_t) dA` (exact potential for rigid relative motion);
//!   flat overlap of depth d: traction `3 p d (1/H_c + 1/H_t)`.
//! * Friction per (couple, edge): `Ft* = Ft_old - k_t v_t dt`, capped at `mu (Fn + f_d)`
//!   (potential plus damping normal force)
//!   ([`friction`]); history committed at the end of the step ([`Contact::commit`]).
//! * Rigid plane: a target of infinite altitude, `f_T = p int_{plane∩T} phi_T ds n` ([`walls`]).
//! * Highest frequency of the engaged contact ([`active_bound`]): per engaged edge part
//!   `k_e = p ∫ |grad phi_T| ds` with weights `c = max(a, b_g)`, and Gershgorin
//!   `omega_c^2 <= max_i sum_e k_e c_i/sqrt(m_i) sum_j c_j/sqrt(m_j)`.
//! * Detection: NBS binning with bounding circles and buffer b, refreshed when a node has
//!   moved `b/2` since the last detection ([`nbs`]); parry2d's BVH as the alternative
//!   ([`broad_parry`]); candidates whose triangles an edge line separates by more than `b`
//!   are dropped ([`narrow`]).
//!
//! See docs/contact.md for the derivations, validation figures and performance.

pub mod active_bound;
pub mod bounding;
pub mod broad_parry;
pub mod couple;
pub mod exclusions;
pub mod friction;
mod geom;
pub mod laws;
pub mod model;
pub mod narrow;
pub mod nbs;
pub mod potential_tri_tri;
pub mod walls;

pub use active_bound::ActiveBound;
pub use bounding::{BoundingCircles, brute_force_couples};
pub use couple::{CoupleForce, WallForce, couple_force, couple_force_into, wall_force};
pub use exclusions::Exclusions;
pub use geom::V2;
pub use laws::{BroadPhase, ContactLaw, ContactLaws, ContactSettings};
pub use model::{
    COUPLE_SHARE, Contact, ContactEnergy, ContactError, ContactSnapshot, ContactStats, Family,
    LEAD, LOCAL, TALLY, Tally, WALL_SHARE, react,
};
pub use walls::RigidPlane;

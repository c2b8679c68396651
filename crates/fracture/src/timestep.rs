//! The joints' contribution to the stable time step.
//!
//! Linearised about the reference state, a joint couples P with S and Q with R through
//! springs of stiffness `k = max(p, p_t)/h * (h t/2) = max(p, p_t) t/2` (N/m; the tangent of
//! the pre-peak curve is largest at zero opening, `2 ft/o_p = p/h`, and softening only lowers
//! it). With lumped masses, Gershgorin's theorem on `M^-1/2 K_j M^-1/2` bounds the joints'
//! largest squared frequency by
//!
//! ```text
//! omega_j^2 <= max_i sum over springs (i, k) of k (1/m_i + 1/sqrt(m_i m_k))
//! ```
//!
//! For a node of an exploded triangle (two joint edges meet at each corner) and
//! `m = rho A t/3` this is about `3 (p/h) l (1/A1 + 1/A2)/rho` (docs/fracture.md, section 8). Because
//! `lambda_max(K_e + K_j) <= lambda_max(K_e) + lambda_max(K_j)` for the same mass matrix, the
//! solver takes `omega_max^2 <= max_e omega_e^2 + omega_j^2` and `dt <= 2/omega_max`.

use crate::set::JointSet;
use crate::state::JointState;

/// Upper bound of the joints' squared angular frequency (rad^2/s^2) over the intact joints,
/// for lumped nodal masses `masses` (kg). Allocates one array per node: call it when the time
/// step is chosen, not in the step loop.
pub fn joint_omega_sq_bound(set: &JointSet, state: &JointState, masses: &[f64]) -> f64 {
    bound_over(set, masses, |j| state.intact[j])
}

/// [`joint_omega_sq_bound`] of a fresh state (every joint intact, as
/// [`JointState::new`](crate::JointState::new) starts), without building the state: the same
/// value bit for bit.
pub fn joint_omega_sq_bound_intact(set: &JointSet, masses: &[f64]) -> f64 {
    bound_over(set, masses, |_| true)
}

/// The bound over the joints `intact(j)` says are intact.
fn bound_over(set: &JointSet, masses: &[f64], intact: impl Fn(usize) -> bool) -> f64 {
    assert_eq!(
        masses.len(),
        set.n_nodes,
        "masses must have one entry per node"
    );
    let mut row = vec![0.0; set.n_nodes];
    for (j, nodes) in set.nodes.iter().enumerate() {
        if !intact(j) {
            continue;
        }
        let m = &set.materials[set.material[j] as usize];
        let k = 0.5 * m.p.max(m.p_t) * set.thickness;
        let [p, q, r, s] = nodes.map(|n| n as usize);
        for (a, b) in [(p, s), (q, r)] {
            let (ma, mb) = (masses[a], masses[b]);
            let cross = 1.0 / (ma * mb).sqrt();
            row[a] += k * (1.0 / ma + cross);
            row[b] += k * (1.0 / mb + cross);
        }
    }
    row.into_iter().fold(0.0, f64::max)
}

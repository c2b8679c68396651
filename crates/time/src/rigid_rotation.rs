//! Munjiza's scheme for the rotation of a rigid discrete element in 3D (seed eqs 5.79-5.82).
//!
//! A rigid body has principal moments `I = diag(Ix, Iy, Iz)` about its body axes `i, j, k`,
//! the columns of its orientation `A` (global frame), an angular velocity `w` and a torque
//! `M` (global frame, held constant over the step). With `L_t = A_t I A_t^T w_t`:
//!
//! ```text
//! w1 = w_t
//! A1 = R(h/2 w1) A_t,   w2 = A1 I^-1 A1^T (L_t + M h/2)
//! A2 = R(h/2 w2) A_t,   w3 = A2 I^-1 A2^T (L_t + M h/2)
//! A3 = R(h w3)   A_t,   w4 = A3 I^-1 A3^T (L_t + M h)
//! A_{t+h} = R(h (w1 + 2 w2 + 2 w3 + w4) / 6) A_t
//! w_{t+h} = A_{t+h} I^-1 A_{t+h}^T (L_t + M h)
//! ```
//!
//! `R(psi)` rotates each axis `t` by the angle `|psi|` about `n = psi / |psi|` (Rodrigues,
//! eq 5.81): `t' = (n.t) n + (t - (n.t) n) cos|psi| + (n x t) sin|psi|`.
//! Angular momentum is updated exactly (`L_{t+h} = L_t + M h`), so a torque-free body keeps
//! it to round-off; the new axes are re-orthonormalised (one Newton step of the polar
//! decomposition) so that round-off in `A` does not accumulate into `L = A I A^T w`. The energy error order is measured in `tests/rigid_rotation.rs` (the
//! averaged angular velocity is a Runge-Kutta average of vectors from different frames,
//! which need not keep fourth order; see `docs/time-integration.md`).

use nalgebra::{Matrix3, Vector3};

/// Orientation, angular velocity and principal inertia of a rigid body.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidBody {
    /// Orientation `A`: its columns are the body axes `i, j, k` in the global frame.
    pub axes: Matrix3<f64>,
    /// Angular velocity `w` in the global frame (rad/s).
    pub omega: Vector3<f64>,
    /// Principal moments of inertia `(Ix, Iy, Iz)` about the body axes (kg m^2).
    pub inertia: Vector3<f64>,
}

impl RigidBody {
    /// Angular momentum `L = A I A^T w` (global frame).
    pub fn angular_momentum(&self) -> Vector3<f64> {
        let body = self.axes.transpose() * self.omega;
        self.axes * body.component_mul(&self.inertia)
    }

    /// Kinetic energy `1/2 w . L`.
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.omega.dot(&self.angular_momentum())
    }

    /// The angular velocity `A I^-1 A^T L` that momentum `l` gives at orientation `axes`.
    pub fn omega_for(
        axes: &Matrix3<f64>,
        inertia: &Vector3<f64>,
        l: &Vector3<f64>,
    ) -> Vector3<f64> {
        let body = axes.transpose() * l;
        axes * body.component_div(inertia)
    }
}

/// Rotates each column of `axes` by the rotation vector `psi` (Rodrigues' formula, eq 5.81).
pub fn rotate(axes: &Matrix3<f64>, psi: &Vector3<f64>) -> Matrix3<f64> {
    let angle = psi.norm();
    if angle == 0.0 {
        return *axes;
    }
    let n = psi / angle;
    let (s, c) = angle.sin_cos();
    let mut out = *axes;
    for col in 0..3 {
        let t: Vector3<f64> = axes.column(col).into();
        let along = n.dot(&t) * n;
        let r = along + (t - along) * c + n.cross(&t) * s;
        out.set_column(col, &r);
    }
    out
}

/// One Newton step towards the nearest orthonormal matrix (polar factor),
/// `A (3 I - A^T A) / 2`: squares the orthonormality error, so that round-off in the
/// axes does not accumulate (otherwise `L = A I A^T w` drifts by the accumulated
/// orthonormality error, about 1e-9 after 1e5 steps).
pub fn reorthonormalise(a: &Matrix3<f64>) -> Matrix3<f64> {
    a * (Matrix3::identity() * 3.0 - a.transpose() * a) * 0.5
}

/// Munjiza's rigid-rotation scheme (stateless: the body carries its state).
#[derive(Clone, Copy, Debug, Default)]
pub struct RigidRotation;

impl RigidRotation {
    /// Advances `body` by `h` under the torque `torque` (global frame, constant over the
    /// step). Four orientation updates and one angular-velocity solve per stage; no
    /// allocation.
    pub fn step(&self, body: &mut RigidBody, torque: &Vector3<f64>, h: f64) {
        let a0 = body.axes;
        let inertia = body.inertia;
        let l0 = body.angular_momentum();
        let l_half = l0 + torque * (0.5 * h);
        let l_end = l0 + torque * h;
        let w1 = body.omega;
        let a1 = rotate(&a0, &(w1 * (0.5 * h)));
        let w2 = RigidBody::omega_for(&a1, &inertia, &l_half);
        let a2 = rotate(&a0, &(w2 * (0.5 * h)));
        let w3 = RigidBody::omega_for(&a2, &inertia, &l_half);
        let a3 = rotate(&a0, &(w3 * h));
        let w4 = RigidBody::omega_for(&a3, &inertia, &l_end);
        let w_avg = (w1 + 2.0 * w2 + 2.0 * w3 + w4) / 6.0;
        body.axes = reorthonormalise(&rotate(&a0, &(w_avg * h)));
        body.omega = RigidBody::omega_for(&body.axes, &inertia, &l_end);
    }
}

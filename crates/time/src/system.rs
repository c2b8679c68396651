//! The second-order system every scheme advances: `M x'' = f(t, x, v)` with a lumped mass.

/// A mechanical system `M x'' = f(t, x, v)` with a diagonal (lumped) mass `M`, seen through
/// flat DOF slices.
///
/// # Contract
/// - [`acceleration`](Self::acceleration) writes `a = M^-1 f(t, x, v)`. It may be called
///   at trial (intermediate) stages that are later discarded: it must **not** commit any
///   history (joint damage, friction slip, plastic strain). History is committed only in
///   [`end_of_step`](Self::end_of_step), called once per accepted step.
/// - `v` enters only through velocity-dependent forces (viscous damping). Which velocity
///   estimate each scheme passes at each stage is stated in each scheme's file: for the
///   splitting schemes (central difference, CHIN, OMF30, OMF32, Forest & Ruth) the
///   velocity variable extrapolated to the stage's position time with the latest
///   acceleration, `v + (tau_x - tau_v) h a_last` (an `O(h^2)` estimate; see
///   [`velocity_dependent`](Self::velocity_dependent)); for Gear PC the predicted
///   velocity `r_1^p / h`.
/// - Prescribed DOFs ([`prescribed_dofs`](Self::prescribed_dofs)) are never moved by a
///   scheme: after every update loop a scheme puts them back to their values at the start
///   of the step, then calls [`prescribe`](Self::prescribe) with the stage time so that
///   the system can set them to a prescribed motion (a platen at constant velocity, ...).
///   With the default `prescribe` (which does nothing) they stay exactly where they are.
pub trait SecondOrderSystem {
    /// Number of degrees of freedom.
    fn n_dofs(&self) -> usize;

    /// Inverse lumped mass `M^-1` per DOF (1/kg). Used by diagnostics such as
    /// [`kinetic_energy`](Self::kinetic_energy); the schemes themselves only need `a`.
    fn inv_mass(&self) -> &[f64];

    /// Writes the acceleration `a = M^-1 f(t, x, v)` (m/s^2) for every DOF. Entries at
    /// prescribed DOFs are ignored. Must not commit history (see the trait docs).
    fn acceleration(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]);

    /// Whether the forces depend on the velocities (viscous damping). When true (the
    /// default), the splitting schemes pass `a` a velocity extrapolated to the stage time,
    /// `v + (tau_x - tau_v) h a_last` (one extra pass over the DOFs per force), which keeps
    /// them second order with damping; when false they pass their velocity variable as it
    /// is and save that pass. Return false when no force depends on `v`.
    fn velocity_dependent(&self) -> bool {
        true
    }

    /// Whether [`force_gradient`](Self::force_gradient) is overridden with an exact
    /// product. With `false` (the default), each gradient costs two extra force
    /// evaluations (the central finite difference), and the schemes count them so.
    fn has_exact_gradient(&self) -> bool {
        false
    }

    /// Writes the force-gradient term of CHIN and OMF32,
    /// `G(x) = 2 M^-1 J(x) M^-1 f(x)` with `J = df/dx` (the negative tangent stiffness),
    /// given `a = M^-1 f(x)` already evaluated at `(t, x, v)`.
    /// For one linear spring `f = -k x`: `G = 2 k^2 x / m^2`.
    ///
    /// The default is the central finite difference along `a`,
    /// `G = (a(x + e a) - a(x - e a)) / e`, with `e = sqrt(eps) |x|_inf / |a|_inf` (`|x|_inf`
    /// taken as 1 when all positions are 0),
    /// using the scheme-owned buffers in `work`. Override it with an exact product (and
    /// return `true` from [`has_exact_gradient`](Self::has_exact_gradient)) where one is
    /// available: it is cheaper and exact.
    fn force_gradient(
        &mut self,
        t: f64,
        x: &[f64],
        v: &[f64],
        a: &[f64],
        g: &mut [f64],
        work: &mut GradientWork,
    ) {
        finite_difference_gradient(self, t, x, v, a, g, work);
    }

    /// Indices of the DOFs whose motion is prescribed (sorted or not; each once).
    /// A scheme never moves them. Default: none.
    fn prescribed_dofs(&self) -> &[usize] {
        &[]
    }

    /// The DOFs the central-difference scheme moves when not all of them: sorted, disjoint
    /// ranges (one process's part of a distributed system). The scheme then updates only
    /// these DOFs and leaves the others as they are, the system's
    /// [`acceleration`](Self::acceleration) need fill only these, and
    /// [`prescribed_dofs`](Self::prescribed_dofs) need name only the prescribed DOFs among
    /// them. The other schemes move every DOF: such a system is stepped by central difference
    /// only. Default: `None` (every DOF).
    fn active_dofs(&self) -> Option<&[std::ops::Range<usize>]> {
        None
    }

    /// Sets the positions and velocities of the prescribed DOFs at time `t` (for example
    /// `x[i] = x0 + u t`, `v[i] = u` for a platen moving at speed `u`). Called at the
    /// start of a run and after every update loop with that stage's time, which may lie
    /// outside `[t, t + h]` for schemes with negative coefficients (Forest & Ruth).
    /// Must touch only prescribed DOFs. Default: nothing, so prescribed DOFs stay fixed.
    fn prescribe(&mut self, t: f64, x: &mut [f64], v: &mut [f64]) {
        let _ = (t, x, v);
    }

    /// Called once per accepted step with the final state at `t + h`: the place to commit
    /// history-dependent quantities. Default: nothing.
    fn end_of_step(&mut self, t: f64, x: &[f64], v: &[f64]) {
        let _ = (t, x, v);
    }

    /// Says that the next [`acceleration`](Self::acceleration) call is the last of the step:
    /// the step then ends with [`end_of_step_at_last_evaluation`](Self::end_of_step_at_last_evaluation)
    /// at that call's positions and time, with no other call in between (central difference
    /// says so before its one evaluation per step). A system may then advance its history in
    /// that evaluation instead of keeping a trial copy for the commit. Default: nothing.
    fn next_evaluation_ends_step(&mut self) {}

    /// Called instead of [`end_of_step`](Self::end_of_step) when the step's last
    /// [`acceleration`](Self::acceleration) call was at these positions `x` and time `t`,
    /// bit for bit (the velocities may have changed since): central difference, CHIN, OMF30
    /// and Forest & Ruth. A system may then reuse what that evaluation computed (trial
    /// history) without checking the positions. Default: [`end_of_step`](Self::end_of_step).
    fn end_of_step_at_last_evaluation(&mut self, t: f64, x: &[f64], v: &[f64]) {
        self.end_of_step(t, x, v);
    }

    /// Kinetic energy `1/2 sum v_i^2 / invm_i` over DOFs of finite mass (J).
    fn kinetic_energy(&self, v: &[f64]) -> f64 {
        v.iter()
            .zip(self.inv_mass())
            .filter(|(_, im)| **im > 0.0)
            .map(|(vi, im)| 0.5 * vi * vi / im)
            .sum()
    }
}

/// Buffers owned by a scheme and lent to [`SecondOrderSystem::force_gradient`], so that
/// the finite-difference default allocates nothing per step.
#[derive(Clone, Debug, Default)]
pub struct GradientWork {
    /// Perturbed positions.
    pub x: Vec<f64>,
    /// A second acceleration buffer.
    pub a: Vec<f64>,
}

impl GradientWork {
    /// Buffers for `n` DOFs.
    pub fn new(n: usize) -> Self {
        Self {
            x: vec![0.0; n],
            a: vec![0.0; n],
        }
    }
}

/// The central finite-difference force-gradient product (the default of
/// [`SecondOrderSystem::force_gradient`]): `G = (a(x + e a) - a(x - e a)) / e`, which is
/// `2 M^-1 J M^-1 f` to `O(e^2)`. Costs two acceleration evaluations. Writes `g`.
pub fn finite_difference_gradient<S: SecondOrderSystem + ?Sized>(
    system: &mut S,
    t: f64,
    x: &[f64],
    v: &[f64],
    a: &[f64],
    g: &mut [f64],
    work: &mut GradientWork,
) {
    let n = x.len();
    if work.x.len() != n {
        work.x.resize(n, 0.0);
        work.a.resize(n, 0.0);
    }
    let amax = crate::kernels::max_abs(a);
    if amax == 0.0 || !amax.is_finite() {
        g.fill(if amax == 0.0 { 0.0 } else { f64::NAN });
        return;
    }
    // The step moves the nodes by `sqrt(eps) |x|_inf` at most: well inside the range where
    // penalty laws are smooth (a joint's peak opening is ~1e-5 of the model size), and
    // `sqrt(eps)` above the rounding of the positions themselves (relative error of `G`
    // ~1e-8). The former `eps^(1/3) max(|x|, 1)` moved them by 6 um in SI units, ~100 peak
    // openings of the Brazilian disc's joints: the difference then spanned the joint law's
    // nonlinear range and CHIN's probe went unstable below its predicted step
    // (docs/speed-vs-accuracy.md).
    let xmax = crate::kernels::max_abs(x);
    let xmax = if xmax > 0.0 { xmax } else { 1.0 };
    let e = f64::EPSILON.sqrt() * xmax / amax;
    crate::kernels::axpy_into(&mut work.x, x, e, a);
    system.acceleration(t, &work.x, v, g);
    crate::kernels::axpy_into(&mut work.x, x, -e, a);
    system.acceleration(t, &work.x, v, &mut work.a);
    crate::kernels::sub_scale(g, &work.a, 1.0 / e);
}

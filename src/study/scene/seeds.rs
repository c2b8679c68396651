//! The initial fields of the stability probes: velocity fields concentrated in the highest
//! modes of the scene's whole system (elements, contact, joints), by power iteration.

use std::path::Path;

use anyhow::Result;
use fdem_solver::driver;

/// Power iterations that concentrate a probe's initial velocity in the highest modes.
const PROBE_POWER_ITERATIONS: usize = 40;
/// Power iterations of the broadband probe's field: the modes weighted by `(omega/omega_top)^4`
/// (the upper part of the spectrum, where a scheme with a stable window above its limit,
/// OMF32, has its unstable band when the top modes sit in the window).
const PROBE_BROAD_ITERATIONS: usize = 2;

/// An initial velocity field concentrated in the highest modes of the scene: power iteration
/// `v <- M^-1 K v` (with `M^-1 K v = -(a(x_0 + eps v) - a(x_0)) / eps`, `a` the whole
/// system's acceleration at rest: elements and the stages, contact and joints, so that the
/// field reaches the contact and joint modes; constrained DOFs zero), scaled to a largest
/// nodal speed of `amplitude omega_max` times the model size (small strain). `dir` receives
/// the stages' files. Also returns `a(x_0)` at rest (flat DOFs, loads and gravity left out),
/// the field after [`PROBE_BROAD_ITERATIONS`] iterations (the upper part of the spectrum,
/// same scaling), and the highest frequency measured by the last iteration's Rayleigh
/// quotient `omega^2 = (v . K v)/(v . M v)` (at most the true highest frequency of the
/// state, for any `v`).
pub(super) fn top_mode_velocity(
    l: &driver::Problem,
    amplitude: f64,
    dir: &Path,
) -> Result<ProbeSeeds> {
    use fdem_time::SecondOrderSystem;
    let n = l.model.n_nodes();
    let mut sys =
        fdem_solver::stages::system::SceneSystem::new(l.model.clone(), l.elements.clone(), 0.0);
    sys.set_timing(false);
    sys.model.loads.clear();
    sys.model.gravity = None;
    std::fs::create_dir_all(dir)?;
    fdem_solver::stages::attach(l, &mut sys, l.dt, dir, u64::MAX)?;
    let x0: Vec<f64> = l.model.x0.as_flattened().to_vec();
    let zero = vec![0.0; 2 * n];
    let mut a0 = vec![0.0; 2 * n];
    sys.acceleration(0.0, &x0, &zero, &mut a0);
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let free = |d: usize| !l.model.constrained[d] && l.model.mass[d / 2] > 0.0;
    let mut v: Vec<f64> = (0..2 * n)
        .map(|d| if free(d) { rnd() } else { 0.0 })
        .collect();
    let scale_of = |v: &[f64]| {
        v.iter()
            .map(|a| a.abs())
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE)
    };
    let size = l
        .model
        .x0
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut x = x0.clone();
    let mut a = vec![0.0; 2 * n];
    let mut w = vec![0.0; 2 * n];
    let mut broad = Vec::new();
    let mut omega_sq = 0.0;
    for it in 0..PROBE_POWER_ITERATIONS {
        if it == PROBE_BROAD_ITERATIONS {
            broad.clone_from(&v);
        }
        let s = scale_of(&v);
        let eps = amplitude * size / s;
        for d in 0..2 * n {
            x[d] = x0[d] + eps * v[d];
        }
        sys.acceleration(0.0, &x, &zero, &mut a);
        for d in 0..2 * n {
            w[d] = if free(d) { -(a[d] - a0[d]) / eps } else { 0.0 };
        }
        // Rayleigh quotient (v . M w)/(v . M v) with w = M^-1 K v
        let (mut num, mut den) = (0.0, 0.0);
        for d in 0..2 * n {
            let m = l.model.mass[d / 2];
            num += m * v[d] * w[d];
            den += m * v[d] * v[d];
        }
        omega_sq = num / den.max(f64::MIN_POSITIVE);
        std::mem::swap(&mut v, &mut w);
        let s = scale_of(&v);
        v.iter_mut().for_each(|vi| *vi /= s);
    }
    // a largest speed of amplitude x omega_max x the largest coordinate: displacements
    // ~amplitude of it
    let amp = amplitude * l.omega_max() * size;
    let scaled = |v: &[f64]| -> Vec<[f64; 2]> {
        let s = scale_of(v);
        v.chunks_exact(2)
            .map(|a| [amp * a[0] / s, amp * a[1] / s])
            .collect()
    };
    Ok(ProbeSeeds {
        top: scaled(&v),
        broad: scaled(&broad),
        a0,
        omega_top: omega_sq.max(0.0).sqrt(),
    })
}

/// The initial fields of a stability probe ([`top_mode_velocity`]).
pub(super) struct ProbeSeeds {
    /// Concentrated in the highest modes ([`PROBE_POWER_ITERATIONS`] power iterations).
    pub(super) top: Vec<[f64; 2]>,
    /// The upper part of the spectrum ([`PROBE_BROAD_ITERATIONS`] power iterations).
    pub(super) broad: Vec<[f64; 2]>,
    /// The acceleration at rest at the probe's start (flat DOFs).
    pub(super) a0: Vec<f64>,
    /// The state's highest frequency measured by the Rayleigh quotient [rad/s].
    pub(super) omega_top: f64,
}

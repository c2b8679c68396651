//! The stability probes: measured stability of a scheme at one step.
//!
//! A fraction is stable when the scene run is ([`super::runs`]) *and* its *stability probe*
//! is: the scene's mesh, supports and stages (contact, joints) with no loads, no gravity and
//! the walls at rest, started from a velocity field concentrated in the highest modes (40
//! power iterations `v <- M^-1 K v` through the whole system's forces: elements, contact and
//! joints, [`super::seeds`]), run for `omega_top t` = 5000 (796 periods of the state's highest
//! mode: `omega_top` is the Rayleigh quotient of the last power iteration, at most the true
//! highest frequency, so the probe spans at least that many of its periods; it is kept within
//! [1/4, 1] of the frequency bound); it is unstable when the solver stops it or the mean
//! `K + U + stored` (contact, joints) over its last fifth exceeds that over its first fifth by
//! more than 1 %. The centres of the fifths are 4000 apart in `omega_top t`, so 1 % is an
//! amplitude growth rate of 1.24e-6 per unit `omega_top t`: the time crate's own definition of
//! a stable step (`rho(T(h)) <= 1 + 1e-6 h`, docs/time-integration.md), applied to the mesh's
//! highest modes. (Measured in units of the bound instead, which overestimates the top
//! frequency 1.3-1.8 times, the probe was that much shorter, and PC-4's slow growth passed on
//! the collision at 2.05 times its limit.)
//!
//! Schemes that are stable again in a window above their limit (PC-4, OMF30, OMF32:
//! `fdem_time::stability::stable_windows`) also get a **broadband probe** at each fraction
//! whose top-mode probe is stable: the same run from the field after 2 power iterations (the
//! upper part of the spectrum), since with the top modes inside a window the unstable band
//! lies among lower modes that the top-mode field barely excites; the fraction is stable when
//! both are. Unlike the scene run alone, the probe also finds the weak growth of PC-4, PC-5
//! and OMF32 past their limits.
//!
//! The probes start from rest in the reference state, or from a state of the scene
//! ([`ProbeStart`], side file `"probe_from"`).

use std::path::Path;

use anyhow::{Context, Result};
use fdem_solver::RunError;
use fdem_solver::driver::{self, RunOptions};
use fdem_time::SchemeKind;
use serde::Serialize;

use super::measures::read_history;
use super::seeds::top_mode_velocity;

/// Length of a stability probe run, in units of `omega_top t` (796 periods of the probed
/// state's highest mode, as measured by the power iteration's Rayleigh quotient).
pub(super) const PROBE_OMEGA_T: f64 = 5000.0;
/// A probe is unstable when the mean energy over its last fifth exceeds that over its first
/// fifth by this factor: the centres are `0.8 x 5000 = 4000` apart in `omega_top t`, so 1 %
/// is an amplitude growth rate of `ln(1.01) / 2 / 4000 = 1.24e-6` per unit `omega_top t`, the
/// time crate's definition of stability (`rho(T(h)) <= 1 + 1e-6 h`).
pub(super) const PROBE_GROWTH: f64 = 1.01;
/// Default largest displacement of a probe's field (its largest speed over `omega_max`),
/// relative to the model size.
pub(super) const PROBE_AMPLITUDE: f64 = 1e-7;

/// The state a stability probe starts from when the side file sets `probe_from` = T: the
/// scene run to T with central difference at half its predicted step (loads, walls and
/// initial velocities as in the scene), giving node positions and velocities and the walls'
/// positions at T. The probe then runs from there with the walls held at those positions and
/// no loads: bodies pressed together stay pressed, so the contact is active during the probe.
/// With joints, the probe also starts from the joints' state at T (which are broken, their
/// damage, shear secant and mode histories): the joints hold the damaged state, and the
/// contact pairs released by the breaks and softenings up to T are contact couples from the
/// start, so re-closed crack faces stay in contact through the probe.
///
/// `"probe_from": "active"` takes T where the bound run's engaged contact bound peaks (the
/// state the active prediction comes from) and *freezes* it: velocities zeroed and constant
/// nodal loads `F = -M a(x_T, 0)` added, so that the state is an equilibrium (a collision's
/// discs at peak compression would otherwise separate within a fraction of the probe). The
/// probe then oscillates about that state, its contact engaged as at the peak, for the whole
/// `omega_top t` = [`PROBE_OMEGA_T`], and its growth is measured on the kinetic energy alone
/// (the loads' work makes `K + U` exchange first-order terms with them): mean `K` over the
/// last fifth over that over the first.
pub(super) struct ProbeStart {
    displacement: Vec<[f64; 2]>,
    velocity: Vec<[f64; 2]>,
    /// Each wall's displacement at T [m].
    walls: Vec<[f64; 2]>,
    /// The joints' history at T (scenes with joints): the probe's fracture stage adopts it
    /// (`Problem::initial_joint_state`), so the joints broken by T stay broken, the
    /// damaged ones keep their damage, and crack faces in contact at T are contact couples
    /// from the probe's first force evaluation.
    pub(super) joints: Option<fdem_fracture::JointState>,
    /// Frozen (`"active"`): velocities zeroed, the state held by balancing loads.
    pub(super) frozen: bool,
    /// The time of the state [s].
    pub(super) time: f64,
    /// The frequency bound of a frozen state [rad/s] (its active bound; else the probe takes
    /// `omega_max`): the measured top frequency that sets a probe's length is kept within
    /// [1/4, 1] of it.
    omega: Option<f64>,
}

/// Runs `scene` to `t` ([`ProbeStart`]); `omega`: the frequency bound of a frozen state
/// (`Some` freezes it).
pub(super) fn probe_start(
    scene: &Path,
    t: f64,
    omega: Option<f64>,
    out: &Path,
) -> Result<ProbeStart> {
    let frozen = omega.is_some();
    let mut l = driver::load(scene)?;
    let k = SchemeKind::CentralDifference;
    l.scheme = k;
    l.dt_limit = driver::stable_step(k, l.omega_max(), l.z_high);
    l.scene.integrator.scheme = k.name().into();
    l.scene.output.frames = 0;
    l.scene.duration = Some(t);
    (l.n_steps, l.dt) = driver::step_count(t, 0.5 * l.dt_limit);
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        raw: false,
        ..Default::default()
    };
    std::fs::create_dir_all(out)?;
    let o = driver::run_outcome(&mut l, &options, &mut |_| {})
        .with_context(|| format!("running {} to the probe's start {t} s", scene.display()))?;
    let walls = l
        .scene
        .contact
        .as_ref()
        .map(|c| {
            c.walls
                .iter()
                .map(|w| {
                    let h = w
                        .history
                        .as_ref()
                        .map(fdem_solver::problem::time_function::History::new);
                    let r = fdem_solver::problem::time_function::integral(t, w.ramp, h.as_ref());
                    [w.velocity[0] * r, w.velocity[1] * r]
                })
                .collect()
        })
        .unwrap_or_default();
    Ok(ProbeStart {
        displacement: o.last_frame.displacement,
        velocity: o.last_frame.velocity,
        walls,
        joints: o.joint_state,
        frozen,
        time: t,
        omega,
    })
}

/// One stability probe's outcome, as `study.json` records it.
#[derive(Clone, Debug, Serialize)]
pub(super) struct Probe {
    /// The fraction of the predicted step.
    pub(super) fraction: f64,
    /// Stable: the top-mode probe and, where run, the broadband one.
    pub(super) stable: bool,
    /// Energy ratio (last fifth over first) of the top-mode probe (`None`: stopped).
    pub(super) ratio: Option<f64>,
    /// The same for the broadband probe, run for the schemes with stable windows above their
    /// limit (PC-4, OMF30, OMF32) when the top-mode probe is stable.
    pub(super) broad_ratio: Option<f64>,
    /// The frequency the probe's length is measured in [rad/s]: the Rayleigh estimate of the
    /// state's highest frequency.
    pub(super) omega_probe: f64,
}

/// What [`stability_probe`] finds.
pub(super) struct ProbeVerdict {
    pub(super) stable: bool,
    /// Energy ratio, last fifth over first (`None`: stopped by the solver, or too short).
    pub(super) ratio: Option<f64>,
    /// The frequency the probe's length was measured in [rad/s].
    pub(super) omega: f64,
}

/// The measured-stability probe of one scheme at one fraction of its predicted step: the
/// scene's mesh, supports and optional stages (contact, joints), with no loads, no gravity and
/// the walls at rest, started from [`top_mode_velocity`] (its top-mode field, or with `broad`
/// its broadband field) and run for `omega_top t` = [`PROBE_OMEGA_T`]. Returns whether it is
/// stable (solver did not stop it and the mean of `K + U` over the last fifth is at most
/// [`PROBE_GROWTH`] times that over the first fifth), that ratio, and `omega_top`.
pub(super) fn stability_probe(
    scene: &Path,
    scheme: SchemeKind,
    fraction: f64,
    out: &Path,
    start: Option<&ProbeStart>,
    amplitude: f64,
    broad: bool,
) -> Result<ProbeVerdict> {
    let mut l = driver::load(scene)?;
    let v_start = probe_scene(&mut l, scheme, start);
    let seeds = top_mode_velocity(&l, amplitude, &out.join("seed"))?;
    let a0 = &seeds.a0;
    let seed = if broad { &seeds.broad } else { &seeds.top };
    let frozen = start.is_some_and(|s| s.frozen);
    if frozen {
        // the state held by constant loads that balance its forces: `F = -M a(x_T, 0)`
        let forces = a0
            .iter()
            .enumerate()
            .filter(|&(d, a)| !l.model.constrained[d] && *a != 0.0)
            .map(|(d, a)| (d as u32, -l.model.mass[d / 2] * a))
            .collect();
        l.model.loads = vec![fdem_solver::problem::model::RampedLoad {
            ramp: 0.0,
            forces,
            history: None,
        }];
    }
    let e_seed = l.model.kinetic_energy(seed);
    l.model.v0 = seed
        .iter()
        .zip(&v_start)
        .map(|(a, b)| [a[0] + b[0], a[1] + b[1]])
        .collect();
    // `omega t` = PROBE_OMEGA_T of the probed state's highest frequency as measured (the
    // Rayleigh estimate, at most the true one, so the probe spans at least that many
    // radians of the top mode): the growth tolerance is per unit `omega t` of that mode. The
    // bound (`omega_max`, or the active bound from a frozen active state) overestimates it,
    // 1.8 times on the collision's state, where a probe measured in the bound's radians let
    // PC-4's slow growth pass 1.8 times too long a step. Kept within [1/4, 1] of the bound.
    let bound = start.and_then(|s| s.omega).unwrap_or(l.omega_max());
    let omega_t = if seeds.omega_top.is_finite() {
        seeds.omega_top.clamp(0.25 * bound, bound)
    } else {
        bound
    };
    let duration = PROBE_OMEGA_T / omega_t;
    l.scene.duration = Some(duration);
    (l.n_steps, l.dt) = driver::step_count(duration, fraction * l.dt_limit);
    // every step: sampled more sparsely, the fast oscillation of `K + U` near a scheme's
    // limit aliases into slow beats that bias the means of the fifths by ~1 %
    l.scene.histories.every = Some(1);
    l.scene.histories.probes = vec![fdem_solver::input::scene::Probe::Energy];
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        raw: false,
        ..Default::default()
    };
    match driver::run_outcome(&mut l, &options, &mut |_| {}) {
        Ok(_) => {}
        Err(RunError::Unstable { .. }) => {
            return Ok(ProbeVerdict {
                stable: false,
                ratio: None,
                omega: omega_t,
            });
        }
        Err(e) => return Err(e.into()),
    }
    let e = probe_energy(out, frozen)?;
    // From a pressed state the static strain and contact energy (0.147 J on the tests' two
    // blocks) and the vibration left by the loading (~2e-4 J) dwarf the energy of the
    // high-mode field (~1e-5 J): the growth is measured against the field's own energy, its
    // initial kinetic energy (from rest that is the whole energy, as before).
    let field_energy = (start.is_some() && !frozen).then_some(e_seed);
    Ok(growth_verdict(&e, field_energy, omega_t))
}

/// The loaded scene made a probe's: `scheme` at its predicted step, no frames, no loads, no
/// gravity, supports and walls at rest (walls moved to their places at the start), and from
/// a [`ProbeStart`] its joints' history and positions. Returns the start's velocities (zero
/// from rest or from a frozen state).
fn probe_scene(
    l: &mut driver::Problem,
    scheme: SchemeKind,
    start: Option<&ProbeStart>,
) -> Vec<[f64; 2]> {
    l.scheme = scheme;
    l.dt_limit = driver::stable_step(scheme, l.omega_max(), l.z_high);
    l.scene.integrator.scheme = scheme.name().into();
    l.scene.output.frames = 0;
    l.model.loads.clear();
    l.model.gravity = None;
    for p in &mut l.model.prescribed {
        p.velocity = 0.0;
    }
    if let Some(c) = &mut l.scene.contact {
        for (i, w) in c.walls.iter_mut().enumerate() {
            if let Some(d) = start.and_then(|s| s.walls.get(i)) {
                w.point = [w.point[0] + d[0], w.point[1] + d[1]];
            }
            w.velocity = [0.0, 0.0];
        }
    }
    // The joints' history at T (scenes with joints): adopted by the fracture stage of the
    // seed's system and of the probe run.
    if l.scene.fracture.is_some()
        && let Some(js) = start.and_then(|s| s.joints.as_ref())
    {
        l.initial_joint_state = Some(js.clone());
    }
    // From a contact state: the positions become the start (the elements keep their own
    // reference shape, built at load), and the velocities are the state's.
    let mut v_start = vec![[0.0; 2]; l.model.n_nodes()];
    if let Some(s) = start {
        for (x, u) in l.model.x0.iter_mut().zip(&s.displacement) {
            *x = [x[0] + u[0], x[1] + u[1]];
        }
        if !s.frozen {
            v_start.clone_from(&s.velocity);
        }
    }
    v_start
}

/// The energy history a probe's growth is measured on: `K + U + stored`, or about an
/// equilibrium held by loads (`frozen`) the kinetic energy alone (its mean over a fifth is
/// half the oscillation's energy; `K + U` trades first-order terms with the loads' work).
fn probe_energy(out: &Path, frozen: bool) -> Result<Vec<f64>> {
    let (_, k) = read_history(out, "kinetic")?;
    if frozen {
        return Ok(k);
    }
    let (_, u) = read_history(out, "strain")?;
    let (_, st) = read_history(out, "stored")?;
    Ok(k.iter()
        .zip(&u)
        .zip(&st)
        .map(|((a, b), c)| a + b + c)
        .collect())
}

/// The growth of a probe's energy history `e`: mean over the last fifth over that over the
/// first, or with `field_energy` (a probe from a moving state) `1 + (last - first) /
/// field_energy`; stable at most [`PROBE_GROWTH`].
fn growth_verdict(e: &[f64], field_energy: Option<f64>, omega: f64) -> ProbeVerdict {
    let m = e.len() / 5;
    if m == 0 {
        return ProbeVerdict {
            stable: true,
            ratio: None,
            omega,
        };
    }
    let first = e[..m].iter().sum::<f64>() / m as f64;
    let last = e[e.len() - m..].iter().sum::<f64>() / m as f64;
    let ratio = match field_energy {
        Some(e_seed) => 1.0 + (last - first) / e_seed.max(f64::MIN_POSITIVE),
        None => last / first.max(f64::MIN_POSITIVE),
    };
    ProbeVerdict {
        stable: ratio.is_finite() && ratio <= PROBE_GROWTH,
        ratio: Some(ratio),
        omega,
    }
}

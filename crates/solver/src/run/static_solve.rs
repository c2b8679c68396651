//! The static analysis: the small-strain linear-elastic solve `K u = f` of the same
//! constant-strain triangles (the mesh crate's sparse stiffness and faer's sparse Cholesky),
//! with the scene's Dirichlet conditions (fixed DOFs: `u = 0`; prescribed velocity `v` with
//! ramp `r`: `u = v (T - r/2)` at the end of the duration `T`, with a history `v F(T)`;
//! prescribed displacement `d`: `d`, with a history `d f(T)`) and Neumann loads at full
//! strength (pressure, traction, point loads, gravity), a load with a history at `f(T)`.
//!
//! Stresses are the linear ones, `sigma = D eps(u)`, `eps = sym grad u` with the reference
//! shape-function gradients; `sigma_zz = lam* (eps_xx + eps_yy)` in plane strain (where
//! `lam*` is the 3D Lame constant), 0 in plane stress. Strain energy density `sigma:eps / 2`.
//! Nodal force `f_ext - K u` (zero at free DOFs up to round-off); reaction `K u - f_ext` at
//! constrained DOFs.
//!
//! An initial stress `sigma_0` (`"initial_stress"`) adds `-int B^T sigma_0` to the loads:
//! `K u = f_ext - int B^T sigma_0`; the stress is the total `sigma_0 + D eps(u)` (the
//! geometric stiffness of `sigma_0` is left out, as all finite-strain terms are), the energy
//! density `sigma_0 : eps + eps : D eps / 2`.

use std::time::Instant;

use fdem_mesh::{PlaneKind, reference_gradients};

use crate::error::{RunError, SceneError};
use crate::output::{FrameData, frame_from_parts};
use crate::problem::load::Problem;
use crate::run::ledger::Energies;
use crate::run::summary::Summary;
use crate::stages::system::StageTimers;

/// The static displacement (flat DOFs) of a loaded scene.
pub fn displacement(l: &Problem) -> Result<Vec<f64>, RunError> {
    let n = 2 * l.model.n_nodes();
    let k = l.elements.stiffness();
    let mut f = vec![0.0; n];
    let t_load = l.scene.duration.unwrap_or(f64::INFINITY);
    l.model.add_external_static(t_load, &mut f);
    add_initial_stress(l, &mut f);
    let mut prescribed: Vec<(usize, f64)> = Vec::new();
    let mut value = vec![0.0; n];
    for p in &l.model.prescribed {
        if p.displacement {
            value[p.dof as usize] = p.static_displacement(t_load);
            continue;
        }
        let Some(t) = l.scene.duration else {
            return Err(SceneError::Invalid {
                file: l.file.clone(),
                path: "duration".into(),
                message: "a prescribed velocity needs a duration to give a displacement in a static analysis".into(),
                fix: "add \"duration\": the static displacement is v (duration - ramp/2)".into(),
            }
            .into());
        };
        value[p.dof as usize] = p.static_displacement(t);
    }
    for d in 0..n {
        if l.model.constrained[d] {
            prescribed.push((d, value[d]));
        }
    }
    let u = fdem_mesh::solve_static(&k, &f, &prescribed).map_err(|_| RunError::Static {
        message: "the stiffness matrix is singular: a body, or a part of one, is not held by the supports".into(),
        fix: "hold every body (and every part joined to the rest at a single node) against translation in x and y and against rotation: fix x and y at one group and x or y at another group away from it".into(),
    })?;
    check_solution(l, &k, &f, &u)?;
    Ok(u)
}

/// Adds the element forces of the initial stresses at the reference positions,
/// `-int B^T sigma_0`, to the flat load vector `f` (nothing without initial stress): the
/// static solve is then `K u = f_ext - int B^T sigma_0`, the total stress
/// `sigma_0 + D eps(u)`.
fn add_initial_stress(l: &Problem, f: &mut [f64]) {
    if l.elements.prestressed() {
        l.elements
            .add_initial_stress_forces(&l.model.x0, f.as_chunks_mut::<2>().0);
    }
}

/// Relative residual above which a static solution is rejected as that of a nearly singular
/// stiffness (`check_solution`).
pub const MAX_RELATIVE_RESIDUAL: f64 = 1e-6;

/// The solution `u` against the loads: the out-of-balance force at the free DOFs,
/// `|f - K u|_free / max(|f|_free, |K u|_constrained)`, must be below
/// [`MAX_RELATIVE_RESIDUAL`]. A backward-stable Cholesky solve leaves a residual of about
/// `eps |K| |u|`: far above the loads only when `u` is huge for them, that is when the
/// stiffness is nearly singular (a part held only through a very soft region, or supports
/// very close together), which the rigid-motion check of
/// [`crate::problem::static_checks::check_supports`] cannot see.
fn check_solution(
    l: &Problem,
    k: &faer::sparse::SparseColMat<usize, f64>,
    f: &[f64],
    u: &[f64],
) -> Result<(), RunError> {
    let n = u.len();
    let mut ku = vec![0.0; n];
    let (cp, ri, vals) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for col in 0..n {
        for p in cp[col]..cp[col + 1] {
            ku[ri[p]] += vals[p] * u[col];
        }
    }
    // the norms of forces scaled by the largest one first: loads near the top of the
    // floating-point range (a huge thickness) would overflow their squares
    let big = (f.iter().chain(&ku))
        .map(|v| v.abs())
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    let unit = Some(1.0 / big).filter(|u| u.is_finite()).unwrap_or(1.0);
    let (mut r2, mut f2, mut react2) = (0.0, 0.0, 0.0);
    for d in 0..n {
        let (fd, kud) = (f[d] * unit, ku[d] * unit);
        if l.model.constrained[d] {
            react2 += kud * kud;
        } else {
            r2 += (fd - kud).powi(2);
            f2 += fd * fd;
        }
    }
    let scale = f2.max(react2).sqrt();
    let rel = r2.sqrt() / scale.max(f64::MIN_POSITIVE);
    let finite = u.iter().all(|v| v.is_finite());
    if finite && (scale == 0.0 || rel <= MAX_RELATIVE_RESIDUAL) {
        return Ok(());
    }
    Err(RunError::Static {
        message: format!(
            "the stiffness is nearly singular: the solution does not balance the loads (out-of-balance force {}, allowed {MAX_RELATIVE_RESIDUAL:e}; largest displacement {:.3e} m)",
            if finite { format!("{rel:.3e} of the load") } else { "not finite".into() },
            u.iter().map(|v| v.abs()).fold(0.0, f64::max)
        ),
        fix: "hold each body firmly: supports far apart rather than at nearby nodes, no part held only through a material many orders of magnitude softer than the rest".into(),
    })
}

/// Solves the static scene and returns its frame and summary.
pub fn solve(l: &Problem) -> Result<(FrameData, Summary), RunError> {
    let start = Instant::now();
    let u = displacement(l)?;
    let solve_time = start.elapsed().as_secs_f64();
    let n = u.len();
    let k = l.elements.stiffness();
    // f_int = -K u.
    let mut ku = vec![0.0; n];
    {
        let (cp, ri, vals) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
        for col in 0..n {
            for p in cp[col]..cp[col + 1] {
                ku[ri[p]] += vals[p] * u[col];
            }
        }
    }
    let mut fext = vec![0.0; n];
    l.model
        .add_external_static(l.scene.duration.unwrap_or(f64::INFINITY), &mut fext);
    // with initial stress, f0 = -int B^T sigma_0 joins the loads in the nodal force
    let mut f0 = Vec::new();
    if l.elements.prestressed() {
        f0 = vec![0.0; n];
        add_initial_stress(l, &mut f0);
    }
    let force: Vec<f64> = if f0.is_empty() {
        (0..n).map(|d| fext[d] - ku[d]).collect()
    } else {
        (0..n).map(|d| fext[d] + f0[d] - ku[d]).collect()
    };
    let mut reaction = vec![0.0; n];
    for d in 0..n {
        if l.model.constrained[d] {
            reaction[d] = -force[d];
        }
    }
    let (stress, energy_density) = linear_stresses(l, &u);
    let x: Vec<[f64; 2]> = l
        .model
        .x0
        .iter()
        .enumerate()
        .map(|(i, p)| [p[0] + u[2 * i], p[1] + u[2 * i + 1]])
        .collect();
    let zeros = vec![[0.0; 2]; l.model.n_nodes()];
    let mut frame = frame_from_parts(
        &l.model,
        0.0,
        &x,
        &zeros,
        force.as_chunks::<2>().0,
        reaction.as_chunks::<2>().0,
        stress,
        energy_density,
    );
    frame.recover_nodal(&l.model, None, &l.scene.output.arrays.set());
    let mut strain = 0.5 * u.iter().zip(&ku).map(|(a, b)| a * b).sum::<f64>();
    let mut ext = 0.5 * u.iter().zip(&fext).map(|(a, b)| a * b).sum::<f64>();
    if !f0.is_empty() {
        // stored: int sigma_0 : eps = -u . f0 more; supplied: the loads at full strength
        // from the start (u . f_ext) and the out-of-balance force at u = 0, f_ext + f0,
        // released linearly (-u . (f_ext + f0) / 2)
        let uf0 = u.iter().zip(&f0).map(|(a, b)| a * b).sum::<f64>();
        strain -= uf0;
        ext -= 0.5 * uf0;
    }
    let sup = 0.5 * u.iter().zip(&reaction).map(|(a, b)| a * b).sum::<f64>();
    let max_u = frame
        .displacement
        .iter()
        .map(|d| (d[0] * d[0] + d[1] * d[1]).sqrt())
        .fold(0.0, f64::max);
    let energy = Energies {
        kinetic: 0.0,
        strain,
        external_work: ext,
        support_work: sup,
        dissipated_or_error: ext + sup - strain,
        ..Default::default()
    };
    let summary = static_summary(l, solve_time, energy, max_u);
    Ok((frame, summary))
}

/// The summary of the static solve of `l`: the solve's time, its ledger `energy` and the
/// largest displacement `max_u`.
fn static_summary(l: &Problem, solve_time: f64, energy: Energies, max_u: f64) -> Summary {
    Summary {
        scene: l.file.display().to_string(),
        analysis: "static".into(),
        scheme: "sparse-cholesky".into(),
        nodes: l.model.n_nodes(),
        triangles: l.elements.len(),
        time_step: 0.0,
        time_step_limit: l.dt_limit,
        steps: 0,
        force_evaluations: 0,
        simulated_time: 0.0,
        wall_time: 0.0,
        triangle_steps_per_second: 0.0,
        timers: StageTimers {
            internal_forces: solve_time,
            ..Default::default()
        },
        energy,
        frames: 0,
        converged: None,
        relative_residual: None,
        relaxation: None,
        relaxation_reason: None,
        relaxation_masses: None,
        residual_floor: None,
        kinetic_to_strain: None,
        kinetic_resets: None,
        cg_restarts: None,
        cg_largest_rise: None,
        max_displacement: max_u,
        threads: rayon::current_num_threads(),
        stages: serde_json::Value::Null,
        time_step_range: None,
        mass_scaling_factor: None,
        loading_rate: None,
        quasi_static: None,
        accuracy: Default::default(),
        result: None,
        resumed: None,
        interrupted: None,
        distributed: None,
    }
}

/// Linear stresses `(sxx, syy, sxy, szz)` and strain energy densities of every triangle for
/// the displacement `u` (flat DOFs).
pub fn linear_stresses(l: &Problem, u: &[f64]) -> (Vec<[f64; 4]>, Vec<f64>) {
    let e = &l.elements;
    let mut stress = Vec::with_capacity(e.len());
    let mut density = Vec::with_capacity(e.len());
    for td in &e.tris {
        let c = &e.materials[td.material as usize];
        let [exx, eyy, gxy] = small_strain(td, u);
        let sxx = (c.lam + 2.0 * c.mu) * exx + c.lam * eyy;
        let syy = c.lam * exx + (c.lam + 2.0 * c.mu) * eyy;
        let sxy = c.mu * gxy;
        let szz = match c.material.plane {
            PlaneKind::Strain => c.lam * (exx + eyy),
            PlaneKind::Stress => 0.0,
        };
        stress.push([sxx, syy, sxy, szz]);
        density.push(0.5 * (sxx * exx + syy * eyy + sxy * gxy));
    }
    // the total stress sigma_0 + D eps, the energy density sigma_0 : eps + eps : D eps / 2
    for (t, s0) in e.initial_stress.iter().enumerate() {
        let s = &mut stress[t];
        let d = &mut density[t];
        let [exx, eyy, gxy] = small_strain(&e.tris[t], u);
        s[0] += s0[0];
        s[1] += s0[1];
        s[2] += s0[2];
        *d += s0[0] * exx + s0[1] * eyy + s0[2] * gxy;
    }
    (stress, density)
}

/// The small strain `[exx, eyy, gamma_xy]` of triangle `td` under the nodal displacements `u`
/// (two per node).
pub fn small_strain(td: &fdem_mesh::TriData, u: &[f64]) -> [f64; 3] {
    let g = reference_gradients(td.ginv);
    let (mut exx, mut eyy, mut gxy) = (0.0, 0.0, 0.0);
    for a in 0..3 {
        let n = td.nodes[a] as usize;
        let (ux, uy) = (u[2 * n], u[2 * n + 1]);
        exx += ux * g[a][0];
        eyy += uy * g[a][1];
        gxy += ux * g[a][1] + uy * g[a][0];
    }
    [exx, eyy, gxy]
}

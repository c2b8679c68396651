//! The static analysis: the small-strain linear-elastic solve `K u = f` of the same
//! constant-strain triangles (the mesh crate's sparse stiffness and faer's sparse Cholesky),
//! with the scene's Dirichlet conditions (fixed DOFs: `u = 0`; prescribed velocity `v` with
//! ramp `r`: `u = v (T - r/2)` at the end of the duration `T`) and Neumann loads at full
//! strength (pressure, traction, point loads, gravity).
//!
//! Stresses are the linear ones, `sigma = D eps(u)`, `eps = sym grad u` with the reference
//! shape-function gradients; `sigma_zz = lam* (eps_xx + eps_yy)` in plane strain (where
//! `lam*` is the 3D Lame constant), 0 in plane stress. Strain energy density `sigma:eps / 2`.
//! Nodal force `f_ext - K u` (zero at free DOFs up to round-off); reaction `K u - f_ext` at
//! constrained DOFs.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use fdem_mesh::{PlaneKind, reference_gradients};

use crate::driver::{Energies, Loaded, Summary, frame_from_parts};
use crate::error::{RunError, SceneError};
use crate::model::{Model, ramp_integral};
use crate::output::FrameData;
use crate::scene::Scene;
use crate::system::StageTimers;

/// The static displacement (flat DOFs) of a loaded scene.
pub fn displacement(l: &Loaded) -> Result<Vec<f64>, RunError> {
    let n = 2 * l.model.n_nodes();
    let k = l.elements.stiffness();
    let mut f = vec![0.0; n];
    l.model.add_external(f64::INFINITY, &mut f);
    let mut prescribed: Vec<(usize, f64)> = Vec::new();
    let mut value = vec![0.0; n];
    for p in &l.model.prescribed {
        let Some(t) = l.scene.duration else {
            return Err(SceneError::Invalid {
                file: l.file.clone(),
                path: "duration".into(),
                message: "a prescribed velocity needs a duration to give a displacement in a static analysis".into(),
                fix: "add \"duration\": the static displacement is v (duration - ramp/2)".into(),
            }
            .into());
        };
        value[p.dof as usize] = p.velocity * ramp_integral(t, p.ramp);
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

/// Relative residual above which a static solution is rejected as that of a nearly singular
/// stiffness (module docs of [`check_supports`]).
pub const MAX_RELATIVE_RESIDUAL: f64 = 1e-6;

/// The solution `u` against the loads: the out-of-balance force at the free DOFs,
/// `|f - K u|_free / max(|f|_free, |K u|_constrained)`, must be below
/// [`MAX_RELATIVE_RESIDUAL`]. A backward-stable Cholesky solve leaves a residual of about
/// `eps |K| |u|`: far above the loads only when `u` is huge for them, that is when the
/// stiffness is nearly singular (a part held only through a very soft region, or supports
/// very close together), which the rigid-motion check of [`check_supports`] cannot see.
fn check_solution(
    l: &Loaded,
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
    let (mut r2, mut f2, mut react2) = (0.0, 0.0, 0.0);
    for d in 0..n {
        if l.model.constrained[d] {
            react2 += ku[d] * ku[d];
        } else {
            r2 += (f[d] - ku[d]).powi(2);
            f2 += f[d] * f[d];
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

/// Rejects the scene sections a static analysis cannot honour: `contact` (the solve is one
/// linear system of the bodies' stiffness, without contact) and `fracture` (its bodies are
/// split into separate triangles joined only by the joints, which have no stiffness in the
/// solve). The alternative is a relaxation, which runs them.
pub fn check_sections(scene: &Scene, file: &Path) -> Result<(), SceneError> {
    if scene.analysis != crate::scene::Analysis::Static {
        return Ok(());
    }
    let what = if scene.contact.is_some() {
        Some((
            "contact",
            "the static analysis solves the bodies' linear stiffness alone and cannot honour contact",
        ))
    } else if scene.fracture.is_some() {
        Some((
            "fracture",
            "the static analysis cannot honour fracture: the fracturing bodies are split into triangles joined only by the joints, which have no stiffness in the linear solve",
        ))
    } else {
        None
    };
    match what {
        None => Ok(()),
        Some((path, message)) => Err(SceneError::Invalid {
            file: file.to_path_buf(),
            path: path.into(),
            message: message.into(),
            fix: format!(
                "use \"analysis\": \"relaxation\" (dynamic relaxation to the static state, with {path}) and a duration, or remove the \"{path}\" section"
            ),
        }),
    }
}

/// At most this many edge-connected parts are analysed together (their joints at single
/// nodes included); a model with more is checked part by part, each shared node counted as
/// held (then mechanisms through shared nodes are left to [`check_solution`]).
const MAX_JOINED_PARTS: usize = 300;

/// An eigenvalue of the constraint matrix below this (times the largest, at least 1) is a
/// rigid motion the supports leave free (the columns are scaled to O(1) entries).
const FREE_MOTION_TOL: f64 = 1e-10;

/// One edge-connected part of the mesh.
struct Part {
    body: usize,
    centroid: [f64; 2],
    /// Length scale of the rotation column [m].
    size: f64,
    constrained_dofs: usize,
    /// Whether the part shares a node (and no edge) with another part.
    joined: bool,
}

/// Checks that the supports hold every body of a static analysis: the rigid motions
/// (translation in x and y, rotation) of every edge-connected part of the mesh, joined to the
/// parts it shares nodes with, restricted to the constrained DOFs. The motions the
/// constraints leave free are the null space of `A^T A`, where a row of `A` is a constrained
/// DOF of a part (`u_x = a - w (y - yc)`, `u_y = b + w (x - xc)` of its rigid motion
/// `(a, b, w)` about its centroid `(xc, yc)`) or the equality of two parts' motions at a node
/// they share. An empty null space means the stiffness of the free DOFs is positive definite
/// (for non-degenerate triangles); otherwise the error names each free part, its body and
/// its free motions (translation in x, in y, rotation about a point) and the supports to add.
pub fn check_supports(scene: &Scene, file: &Path, model: &Model) -> Result<(), SceneError> {
    let nt = model.triangles.len();
    if nt == 0 {
        return Ok(());
    }
    // Edge-connected parts (union-find over the triangles).
    let mut parent: Vec<usize> = (0..nt).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let mut owner: HashMap<(u32, u32), usize> = HashMap::with_capacity(2 * nt);
    for (t, tri) in model.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            match owner.entry((a.min(b), a.max(b))) {
                std::collections::hash_map::Entry::Occupied(o) => {
                    let (ra, rb) = (root(&mut parent, t), root(&mut parent, *o.get()));
                    parent[ra.max(rb)] = ra.min(rb);
                }
                std::collections::hash_map::Entry::Vacant(v) => {
                    v.insert(t);
                }
            }
        }
    }
    drop(owner);
    let mut part_of_root = HashMap::new();
    let mut part_of_tri = vec![0usize; nt];
    for t in 0..nt {
        let r = root(&mut parent, t);
        let next = part_of_root.len();
        part_of_tri[t] = *part_of_root.entry(r).or_insert(next);
    }
    let m = part_of_root.len();
    // (node, part) pairs.
    let mut pairs: Vec<(u32, usize)> = model
        .triangles
        .iter()
        .enumerate()
        .flat_map(|(t, tri)| tri.iter().map(move |&n| (n, t)))
        .map(|(n, t)| (n, part_of_tri[t]))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    let mut parts: Vec<Part> = (0..m)
        .map(|_| Part {
            body: 0,
            centroid: [0.0; 2],
            size: 0.0,
            constrained_dofs: 0,
            joined: false,
        })
        .collect();
    for (t, &p) in part_of_tri.iter().enumerate() {
        parts[p].body = model.tri_body.get(t).copied().unwrap_or(0) as usize;
    }
    let mut count = vec![0usize; m];
    for &(n, p) in &pairs {
        let x = model.x0[n as usize];
        parts[p].centroid[0] += x[0];
        parts[p].centroid[1] += x[1];
        count[p] += 1;
    }
    for (p, c) in parts.iter_mut().zip(&count) {
        p.centroid = [p.centroid[0] / *c as f64, p.centroid[1] / *c as f64];
    }
    for &(n, p) in &pairs {
        let x = model.x0[n as usize];
        let c = parts[p].centroid;
        parts[p].size = parts[p].size.max((x[0] - c[0]).hypot(x[1] - c[1]));
        for k in 0..2 {
            if model.constrained[2 * n as usize + k] {
                parts[p].constrained_dofs += 1;
            }
        }
    }
    for p in &mut parts {
        if p.size.is_nan() || p.size <= 0.0 {
            p.size = 1.0;
        }
    }
    for w in pairs.windows(2) {
        if w[0].0 == w[1].0 {
            parts[w[0].1].joined = true;
            parts[w[1].1].joined = true;
        }
    }
    // Row of a part's rigid motion at node n, DOF k: (column offsets within the part, values).
    let row = |p: usize, n: u32, k: usize| -> [(usize, f64); 2] {
        let x = model.x0[n as usize];
        let (c, l) = (parts[p].centroid, parts[p].size);
        if k == 0 {
            [(0, 1.0), (2, -(x[1] - c[1]) / l)]
        } else {
            [(1, 1.0), (2, (x[0] - c[0]) / l)]
        }
    };
    let joined_analysis = m <= MAX_JOINED_PARTS;
    // Blocks of parts analysed together: all parts, or each part alone.
    let blocks: Vec<Vec<usize>> = if joined_analysis {
        vec![(0..m).collect()]
    } else {
        (0..m).map(|p| vec![p]).collect()
    };
    let mut index_in_block = vec![0usize; m];
    let mut free: Vec<(usize, Vec<String>)> = Vec::new();
    for block in &blocks {
        for (i, &p) in block.iter().enumerate() {
            index_in_block[p] = i;
        }
        let dim = 3 * block.len();
        let mut a = faer::Mat::<f64>::zeros(dim, dim);
        let mut add = |entries: &[(usize, f64)]| {
            for &(i, vi) in entries {
                for &(j, vj) in entries {
                    a[(i, j)] += vi * vj;
                }
            }
        };
        let in_block = |p: usize| block.len() == m || block[0] == p;
        // group the pairs by node
        let mut i = 0;
        while i < pairs.len() {
            let n = pairs[i].0;
            let mut j = i;
            while j < pairs.len() && pairs[j].0 == n {
                j += 1;
            }
            let node_parts: Vec<usize> = pairs[i..j].iter().map(|x| x.1).collect();
            let shared = node_parts.len() > 1;
            for &p in &node_parts {
                if !in_block(p) {
                    continue;
                }
                let o = 3 * index_in_block[p];
                for k in 0..2 {
                    let held =
                        model.constrained[2 * n as usize + k] || (shared && !joined_analysis);
                    if held {
                        let r = row(p, n, k);
                        add(&[(o + r[0].0, r[0].1), (o + r[1].0, r[1].1)]);
                    }
                }
            }
            if shared && joined_analysis {
                let p0 = node_parts[0];
                for &p in &node_parts[1..] {
                    for k in 0..2 {
                        let (r0, r1) = (row(p0, n, k), row(p, n, k));
                        let (o0, o1) = (3 * index_in_block[p0], 3 * index_in_block[p]);
                        add(&[
                            (o0 + r0[0].0, r0[0].1),
                            (o0 + r0[1].0, r0[1].1),
                            (o1 + r1[0].0, -r1[0].1),
                            (o1 + r1[1].0, -r1[1].1),
                        ]);
                    }
                }
            }
            i = j;
        }
        let Ok(eig) = a.self_adjoint_eigen(faer::Side::Lower) else {
            continue;
        };
        let s = eig.S().column_vector();
        let lmax = (0..dim).map(|i| s[i]).fold(1.0, f64::max);
        let null: Vec<usize> = (0..dim)
            .filter(|&i| s[i] <= FREE_MOTION_TOL * lmax)
            .collect();
        if null.is_empty() {
            continue;
        }
        let v = eig.U();
        // projection of a unit vector e_c onto the null space
        let project = |c: usize| -> Vec<f64> {
            let mut out = vec![0.0; dim];
            for &q in &null {
                let w = v[(c, q)];
                for (r, o) in out.iter_mut().enumerate() {
                    *o += w * v[(r, q)];
                }
            }
            out
        };
        for &p in block {
            let o = 3 * index_in_block[p];
            let moves = null
                .iter()
                .any(|&q| (0..3).any(|c| v[(o + c, q)].abs() > 1e-6));
            if !moves {
                continue;
            }
            let mut motions = Vec::new();
            let tx = project(o)[o];
            let ty = project(o + 1)[o + 1];
            if tx > 0.99 {
                motions.push("translation in x".to_string());
            }
            if ty > 0.99 {
                motions.push("translation in y".to_string());
            }
            let pr = project(o + 2);
            if pr[o + 2] > 1e-6 {
                if tx > 0.99 && ty > 0.99 {
                    motions.push("rotation".to_string());
                } else {
                    let w = pr[o + 2] / parts[p].size;
                    let c = parts[p].centroid;
                    // round-off below 1e-9 of the part's size shown as 0
                    let tidy = |v: f64| {
                        if v.abs() < 1e-9 * parts[p].size {
                            0.0
                        } else {
                            v
                        }
                    };
                    motions.push(format!(
                        "rotation about ({:.4e}, {:.4e}) m",
                        tidy(c[0] - pr[o + 1] / w),
                        tidy(c[1] + pr[o] / w)
                    ));
                }
            }
            if motions.is_empty() {
                motions.push("a rigid motion together with the parts it is joined to".into());
            }
            free.push((p, motions));
        }
    }
    if free.is_empty() {
        return Ok(());
    }
    let body_name = |b: usize| match scene.bodies.get(b).and_then(|x| x.name.as_deref()) {
        Some(n) => format!("body '{}'", fdem_mesh::excerpt(n)),
        None => format!("bodies[{b}]"),
    };
    let groups_of = |b: usize| {
        let mut g: Vec<String> = model
            .groups
            .iter()
            .filter(|x| x.0 as usize == b)
            .map(|x| format!("'{}'", fdem_mesh::excerpt(&x.1)))
            .collect();
        g.dedup();
        let more = g.len().saturating_sub(8);
        g.truncate(8);
        let mut s = g.join(", ");
        if more > 0 {
            let _ = write!(s, " and {more} more");
        }
        s
    };
    let mut message = String::from(
        "the supports do not hold the model: the static solve would be singular (an arbitrary rigid motion added to any answer)",
    );
    let mut fixes = Vec::new();
    for (p, motions) in free.iter().take(4) {
        let part = &parts[*p];
        let n_parts = parts.iter().filter(|q| q.body == part.body).count();
        let name = if n_parts > 1 {
            format!(
                "the part of {} around ({:.4e}, {:.4e}) m",
                body_name(part.body),
                part.centroid[0],
                part.centroid[1]
            )
        } else {
            body_name(part.body)
        };
        let _ = write!(message, "\n  {name} is free: {}", motions.join(", "));
        if part.constrained_dofs == 0 && !part.joined {
            let _ = write!(message, " (no node of it is supported)");
        } else if part.joined {
            let _ = write!(
                message,
                " (it is joined to the rest at single nodes, which act as hinges)"
            );
        }
        let groups = groups_of(part.body);
        let fix = if motions.iter().any(|m| m.starts_with("rotation about"))
            && part.constrained_dofs > 0
        {
            format!(
                "hold a second point of {} away from the first (e.g. a `fixed` condition on another of its groups: {groups})",
                body_name(part.body)
            )
        } else if part.constrained_dofs > 0
            && motions.iter().all(|m| m.starts_with("translation in"))
        {
            let axes: Vec<&str> = motions
                .iter()
                .map(|m| m.trim_start_matches("translation in "))
                .collect();
            format!(
                "fix {} at a node of {} too (e.g. add {} to one of its `fixed` conditions)",
                axes.join(" and "),
                body_name(part.body),
                axes.iter()
                    .map(|a| format!("\"{a}\": true"))
                    .collect::<Vec<_>>()
                    .join(" and ")
            )
        } else if part.joined && part.constrained_dofs == 0 {
            format!(
                "support the part of {} around ({:.4e}, {:.4e}) m, or mesh it joined to the rest along an edge",
                body_name(part.body),
                part.centroid[0],
                part.centroid[1]
            )
        } else {
            format!(
                "add supports to {}: a `fixed` condition with \"x\": true and \"y\": true on one of its groups and \"x\" or \"y\" on another away from it (its groups: {groups})",
                body_name(part.body)
            )
        };
        if !fixes.contains(&fix) {
            fixes.push(fix);
        }
    }
    if free.len() > 4 {
        let _ = write!(message, "\n  and {} more free parts", free.len() - 4);
    }
    Err(SceneError::Invalid {
        file: file.to_path_buf(),
        path: "boundary_conditions".into(),
        message,
        fix: fixes.join("; "),
    })
}

/// Solves the static scene and returns its frame and summary.
pub fn solve(l: &Loaded) -> Result<(FrameData, Summary), RunError> {
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
    l.model.add_external(f64::INFINITY, &mut fext);
    let force: Vec<f64> = (0..n).map(|d| fext[d] - ku[d]).collect();
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
    let frame = frame_from_parts(
        &l.model,
        0.0,
        &x,
        &zeros,
        force.as_chunks::<2>().0,
        reaction.as_chunks::<2>().0,
        stress,
        energy_density,
    );
    let strain = 0.5 * u.iter().zip(&ku).map(|(a, b)| a * b).sum::<f64>();
    let ext = 0.5 * u.iter().zip(&fext).map(|(a, b)| a * b).sum::<f64>();
    let sup = 0.5 * u.iter().zip(&reaction).map(|(a, b)| a * b).sum::<f64>();
    let max_u = frame
        .displacement
        .iter()
        .map(|d| (d[0] * d[0] + d[1] * d[1]).sqrt())
        .fold(0.0, f64::max);
    let summary = Summary {
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
        element_steps_per_second: 0.0,
        timers: StageTimers {
            internal_forces: solve_time,
            ..Default::default()
        },
        energy: Energies {
            kinetic: 0.0,
            strain,
            external_work: ext,
            support_work: sup,
            dissipated_or_error: ext + sup - strain,
            ..Default::default()
        },
        frames: 0,
        converged: None,
        relative_residual: None,
        max_displacement: max_u,
        threads: rayon::current_num_threads(),
        stages: serde_json::Value::Null,
        time_step_range: None,
    };
    Ok((frame, summary))
}

/// Linear stresses `(sxx, syy, sxy, szz)` and strain energy densities of every triangle for
/// the displacement `u` (flat DOFs).
pub fn linear_stresses(l: &Loaded, u: &[f64]) -> (Vec<[f64; 4]>, Vec<f64>) {
    let e = &l.elements;
    let mut stress = Vec::with_capacity(e.len());
    let mut density = Vec::with_capacity(e.len());
    for td in &e.tris {
        let c = &e.materials[td.material as usize];
        let g = reference_gradients(td.ginv);
        let (mut exx, mut eyy, mut gxy) = (0.0, 0.0, 0.0);
        for a in 0..3 {
            let n = td.nodes[a] as usize;
            let (ux, uy) = (u[2 * n], u[2 * n + 1]);
            exx += ux * g[a][0];
            eyy += uy * g[a][1];
            gxy += ux * g[a][1] + uy * g[a][0];
        }
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
    (stress, density)
}

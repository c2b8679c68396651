//! What a static analysis needs of the scene, checked when the scene is loaded: only the
//! sections the linear solve can honour ([`check_sections`]), and supports that hold every
//! body against rigid motion ([`check_supports`]).

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::error::SceneError;
use crate::input::scene::Scene;
use crate::problem::model::Model;

/// Rejects the scene sections a static analysis cannot honour: `contact` (the solve is one
/// linear system of the bodies' stiffness, without contact) and `fracture` (its bodies are
/// split into separate triangles joined only by the joints, which have no stiffness in the
/// solve). The alternative is a relaxation, which runs them.
pub fn check_sections(scene: &Scene, file: &Path) -> Result<(), SceneError> {
    if scene.analysis != crate::input::scene::Analysis::Static {
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
/// held (then mechanisms through shared nodes are left to the
/// static solve's residual check).
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
    if model.triangles.is_empty() {
        return Ok(());
    }
    let (parts, pairs) = parts_of(model);
    let m = parts.len();
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
        let a = constraint_matrix(model, &parts, &pairs, block, &index_in_block);
        free_motions(&a, &parts, block, &index_in_block, &mut free);
    }
    if free.is_empty() {
        return Ok(());
    }
    Err(unsupported(scene, file, model, &parts, &free))
}

/// The edge-connected parts of the mesh (union-find over the triangles) and the sorted
/// `(node, part)` pairs.
fn parts_of(model: &Model) -> (Vec<Part>, Vec<(u32, usize)>) {
    let nt = model.triangles.len();
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
    measure_parts(model, &pairs, &mut parts);
    (parts, pairs)
}

/// Each part's centroid, size, constrained DOFs and whether it shares a node with another.
fn measure_parts(model: &Model, pairs: &[(u32, usize)], parts: &mut [Part]) {
    let mut count = vec![0usize; parts.len()];
    for &(n, p) in pairs {
        let x = model.x0[n as usize];
        parts[p].centroid[0] += x[0];
        parts[p].centroid[1] += x[1];
        count[p] += 1;
    }
    for (p, c) in parts.iter_mut().zip(&count) {
        p.centroid = [p.centroid[0] / *c as f64, p.centroid[1] / *c as f64];
    }
    for &(n, p) in pairs {
        let x = model.x0[n as usize];
        let c = parts[p].centroid;
        parts[p].size = parts[p].size.max((x[0] - c[0]).hypot(x[1] - c[1]));
        for k in 0..2 {
            if model.constrained[2 * n as usize + k] {
                parts[p].constrained_dofs += 1;
            }
        }
    }
    for p in parts.iter_mut() {
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
}

/// `A^T A` of a block of parts (module docs of [`check_supports`]): the constrained DOFs of
/// its parts, and (when all parts are analysed together) the equality of the motions of the
/// parts that share a node; else a shared node counts as held.
fn constraint_matrix(
    model: &Model,
    parts: &[Part],
    pairs: &[(u32, usize)],
    block: &[usize],
    index_in_block: &[usize],
) -> faer::Mat<f64> {
    let m = parts.len();
    let joined_analysis = m <= MAX_JOINED_PARTS;
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
                let held = model.constrained[2 * n as usize + k] || (shared && !joined_analysis);
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
    a
}

/// The parts of `block` that the constraint matrix `a` leaves a rigid motion (its null
/// space), each with its free motions in words, pushed onto `free`.
fn free_motions(
    a: &faer::Mat<f64>,
    parts: &[Part],
    block: &[usize],
    index_in_block: &[usize],
    free: &mut Vec<(usize, Vec<String>)>,
) {
    let dim = a.nrows();
    let Ok(eig) = a.self_adjoint_eigen(faer::Side::Lower) else {
        return;
    };
    let s = eig.S().column_vector();
    let lmax = (0..dim).map(|i| s[i]).fold(1.0, f64::max);
    let null: Vec<usize> = (0..dim)
        .filter(|&i| s[i] <= FREE_MOTION_TOL * lmax)
        .collect();
    if null.is_empty() {
        return;
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

/// The error for the `free` parts (at most four named): each part, its free motions, and the
/// supports to add.
fn unsupported(
    scene: &Scene,
    file: &Path,
    model: &Model,
    parts: &[Part],
    free: &[(usize, Vec<String>)],
) -> SceneError {
    let body_name = |b: usize| body_name(scene, b);
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
        let fix = support_fix(scene, model, part, motions);
        if !fixes.contains(&fix) {
            fixes.push(fix);
        }
    }
    if free.len() > 4 {
        let _ = write!(message, "\n  and {} more free parts", free.len() - 4);
    }
    SceneError::Invalid {
        file: file.to_path_buf(),
        path: "boundary_conditions".into(),
        message,
        fix: fixes.join("; "),
    }
}

/// `body 'name'` or `bodies[b]`.
fn body_name(scene: &Scene, b: usize) -> String {
    match scene.bodies.get(b).and_then(|x| x.name.as_deref()) {
        Some(n) => format!("body '{}'", fdem_mesh::excerpt(n)),
        None => format!("bodies[{b}]"),
    }
}

/// The supports that hold a free part.
fn support_fix(scene: &Scene, model: &Model, part: &Part, motions: &[String]) -> String {
    let body_name = |b: usize| body_name(scene, b);
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
    let groups = groups_of(part.body);
    if motions.iter().any(|m| m.starts_with("rotation about")) && part.constrained_dofs > 0 {
        format!(
            "hold a second point of {} away from the first (e.g. a `fixed` condition on another of its groups: {groups})",
            body_name(part.body)
        )
    } else if part.constrained_dofs > 0 && motions.iter().all(|m| m.starts_with("translation in")) {
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
    }
}

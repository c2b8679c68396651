//! The explode operation: own nodes per triangle, internal edges in the joint convention of
//! docs/mesh.md, "Exploding a mesh for fracture", the map back to original nodes, and partial explosion of a group.

use crate::common;
use common::*;
use fdem_mesh::{Material, explode, read_mesh};

fn check_joints(ex: &fdem_mesh::Exploded) {
    let m = &ex.mesh;
    for j in &ex.internal_edges {
        let [p, q, r, s] = j.nodes.map(|n| m.nodes[n.idx()]);
        assert_eq!(p, s);
        assert_eq!(q, r);
        let [t1, t2] = j.tris;
        let (k1, k2) = (j.local_edge[0] as usize, j.local_edge[1] as usize);
        let tri1 = m.triangles[t1.idx()];
        let tri2 = m.triangles[t2.idx()];
        // P -> Q is CCW local edge k1 of T1; R -> S is CCW local edge k2 of T2.
        assert_eq!([tri1[k1], tri1[(k1 + 1) % 3]], [j.nodes[0].0, j.nodes[1].0]);
        assert_eq!([tri2[k2], tri2[(k2 + 1) % 3]], [j.nodes[2].0, j.nodes[3].0]);
        // nn = (tt_y, -tt_x) points from T1 to T2.
        let tt = [q[0] - p[0], q[1] - p[1]];
        let nn = [tt[1], -tt[0]];
        let c = |t: [u32; 3]| {
            let x = t.map(|n| m.nodes[n as usize]);
            [
                (x[0][0] + x[1][0] + x[2][0]) / 3.0,
                (x[0][1] + x[1][1] + x[2][1]) / 3.0,
            ]
        };
        let (c1, c2) = (c(tri1), c(tri2));
        assert!((c2[0] - c1[0]) * nn[0] + (c2[1] - c1[1]) * nn[1] > 0.0);
    }
}

/// Full explosion: 3 nodes per triangle, one joint per internal edge, map back to the
/// original nodes, same mass, and under a homogeneous deformation the forces of the copies of
/// each node add up to the original mesh's force (1e-12 relative).
#[test]
fn full_explode_gives_joints_and_keeps_mechanics() {
    let mesh = common::grid(6, 4, 1.5, 1.0, 0.5, 9);
    let ex = explode(&mesh, None).unwrap();
    let nt = mesh.n_triangles();
    assert_eq!(ex.mesh.n_nodes(), 3 * nt);
    assert_eq!(
        ex.internal_edges.len(),
        mesh.edges.len() - mesh.boundary_edges.len()
    );
    assert_eq!(ex.mesh.boundary_edges.len(), 3 * nt);
    for (i, o) in ex.original_node.iter().enumerate() {
        assert_eq!(ex.mesh.nodes[i], mesh.nodes[o.idx()]);
    }
    check_joints(&ex);
    let mat = Material::new(1e10, 0.25, 2500.0);
    let (el0, el1) = (elements(&mesh, mat), elements(&ex.mesh, mat));
    let m0: f64 = el0.lumped_masses().iter().sum();
    let m1: f64 = el1.lumped_masses().iter().sum();
    assert!((m0 - m1).abs() < 1e-12 * m0);
    let fgrad = [1.02, 0.01, -0.02, 0.97];
    let (x0, x1) = (
        affine(&mesh.nodes, fgrad, [0.0; 2]),
        affine(&ex.mesh.nodes, fgrad, [0.0; 2]),
    );
    let mut f0 = vec![[0.0; 2]; x0.len()];
    let mut f1 = vec![[0.0; 2]; x1.len()];
    el0.internal_forces(&x0, &x0, &mut f0, &mut fdem_mesh::ForceScratch::new(&el0));
    el1.internal_forces(&x1, &x1, &mut f1, &mut fdem_mesh::ForceScratch::new(&el1));
    let mut back = vec![[0.0; 2]; x0.len()];
    for (i, o) in ex.original_node.iter().enumerate() {
        back[o.idx()][0] += f1[i][0];
        back[o.idx()][1] += f1[i][1];
    }
    let scale = f0
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max);
    for (a, b) in f0.iter().zip(&back) {
        assert!((a[0] - b[0]).abs() < 1e-12 * scale && (a[1] - b[1]).abs() < 1e-12 * scale);
    }
}

/// Partial explosion of the notched beam's fracture zone: zone triangles own their nodes,
/// bulk triangles still share theirs, joints on every edge touching the zone, groups kept.
#[test]
fn partial_explode_of_fracture_zone() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes");
    let mesh = read_mesh(root.join("notched-beam.msh")).unwrap();
    let zone = mesh.group("fracture_zone").unwrap();
    let mut in_zone = vec![false; mesh.n_triangles()];
    for t in &zone.triangles {
        in_zone[t.idx()] = true;
    }
    let ex = explode(&mesh, Some(&["fracture_zone"])).unwrap();
    let mut bulk_nodes: Vec<u32> = mesh
        .triangles
        .iter()
        .zip(&in_zone)
        .filter(|(_, z)| !**z)
        .flat_map(|(t, _)| *t)
        .collect();
    bulk_nodes.sort_unstable();
    bulk_nodes.dedup();
    assert_eq!(
        ex.mesh.n_nodes(),
        bulk_nodes.len() + 3 * zone.triangles.len()
    );
    let expect = mesh
        .edges
        .iter()
        .filter(|e| {
            e.right
                .is_some_and(|r| in_zone[r.idx()] || in_zone[e.left.idx()])
        })
        .count();
    assert_eq!(ex.internal_edges.len(), expect);
    check_joints(&ex);
    assert_eq!(ex.mesh.regions, mesh.regions);
    assert_eq!(ex.mesh.tri_region, mesh.tri_region);
    // A point group gets every copy of its node (the load point lies on zone triangles).
    let lt = mesh.group("load_top").unwrap().nodes[0];
    let copies = ex.original_node.iter().filter(|o| **o == lt).count();
    assert!(copies > 1);
    assert_eq!(ex.mesh.group("load_top").unwrap().nodes.len(), copies);
    assert_eq!(
        ex.mesh.group("bottom").unwrap().edges.len(),
        mesh.group("bottom").unwrap().edges.len()
    );
    assert!(explode(&mesh, Some(&["nope"])).is_err());
    assert!(explode(&mesh, Some(&["top"])).is_err());
}

/// On a wholly exploded mesh the kernel adds each triangle's forces to its own nodes
/// directly (`Elements::owned_nodes`): the result is the two-pass kernel's bit for bit (elastic
/// and viscous, with and without initial stresses, 1 and 2 threads, onto zero and onto a
/// non-zero array), and
/// `set_internal_forces` equals zeroing then `internal_forces`. 2 x 70 x 60 = 8 400 triangles:
/// two chunks of the kernel.
#[test]
fn exploded_kernel_matches_the_two_pass_kernel_bit_for_bit() {
    let mesh = common::grid(70, 60, 1.4, 1.2, 0.3, 5);
    let ex = explode(&mesh, None).unwrap();
    let mut rng = Rng(3);
    let x: Vec<[f64; 2]> = affine(&ex.mesh.nodes, [1.01, 0.02, -0.01, 0.98], [0.1, 0.0])
        .iter()
        .map(|p| [p[0] + 1e-4 * rng.next(), p[1] + 1e-4 * rng.next()])
        .collect();
    let v: Vec<[f64; 2]> = x.iter().map(|_| [rng.next(), rng.next()]).collect();
    let start: Vec<[f64; 2]> = x.iter().map(|_| [rng.next(), -rng.next()]).collect();
    let bits = |f: &[[f64; 2]]| {
        f.iter()
            .flat_map(|p| p.map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    for (damping, pre) in [(0.0, false), (0.1, false), (0.0, true), (0.1, true)] {
        let mut mat = Material::new(1e10, 0.25, 2500.0);
        mat.damping_ratio = damping;
        let mut el = elements(&ex.mesh, mat);
        if pre {
            let s0 = (0..el.len())
                .map(|t| [-1e7 * (1.0 + (t % 5) as f64), -4e6, 1e6 * (t % 3) as f64])
                .collect();
            el.set_initial_stress(s0);
        }
        assert!(el.owned_nodes);
        let mut s = fdem_mesh::ForceScratch::new(&el);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                for f0 in [vec![[0.0; 2]; x.len()], start.clone()] {
                    let (mut a, mut b) = (f0.clone(), f0.clone());
                    el.internal_forces(&x, &v, &mut a, &mut s);
                    el.internal_forces_buffered(&x, &v, &mut b, &mut s);
                    assert_eq!(bits(&a), bits(&b), "damping {damping}, {threads} threads");
                }
                let mut c = start.clone();
                el.set_internal_forces(&x, &v, &mut c, &mut s);
                let mut d = vec![[0.0; 2]; x.len()];
                el.internal_forces_buffered(&x, &v, &mut d, &mut s);
                assert_eq!(bits(&c), bits(&d), "set, damping {damping}");
            });
        }
    }
    // a connected mesh is not owned-node
    assert!(!elements(&mesh, Material::new(1e10, 0.25, 2500.0)).owned_nodes);
    fdem_figures::record_part(62, 2, "exploded kernel equal bit for bit");
}

/// `set_internal_forces_then` hands every node to `then` exactly once, after the node's own
/// triangles wrote its forces: the result is `set_internal_forces` followed by `then` over the
/// whole array, bit for bit, on a wholly exploded mesh (ranges of one chunk of triangles, in
/// the kernel) and on a connected one (ranges after the pass), on 1 and 2 threads.
#[test]
fn forces_then_visits_each_node_once_after_its_forces() {
    use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
    let mesh = common::grid(70, 60, 1.4, 1.2, 0.3, 5);
    let ex = explode(&mesh, None).unwrap();
    for m in [&ex.mesh, &mesh] {
        let el = elements(m, Material::new(1e10, 0.25, 2500.0));
        let mut rng = Rng(7);
        let x: Vec<[f64; 2]> = m
            .nodes
            .iter()
            .map(|p| [p[0] + 1e-4 * rng.next(), p[1] + 1e-4 * rng.next()])
            .collect();
        let v = vec![[0.0; 2]; x.len()];
        // the added term: a per-node value whose sum with the element force rounds
        let add = |i: usize| [1e3 * (i % 7) as f64 + 0.1, -2e3 * (i % 5) as f64 - 0.3];
        let mut s = fdem_mesh::ForceScratch::new(&el);
        let mut whole = vec![[0.0; 2]; x.len()];
        el.set_internal_forces(&x, &v, &mut whole, &mut s);
        for (i, w) in whole.iter_mut().enumerate() {
            let a = add(i);
            w[0] += a[0];
            w[1] += a[1];
        }
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let visits: Vec<AtomicU32> = (0..x.len()).map(|_| AtomicU32::new(0)).collect();
            let mut f = vec![[7.0; 2]; x.len()];
            pool.install(|| {
                el.set_internal_forces_then(&x, &v, &mut f, &mut s, |i0, fc| {
                    for (i, fi) in (i0..).zip(fc) {
                        visits[i].fetch_add(1, Relaxed);
                        let a = add(i);
                        fi[0] += a[0];
                        fi[1] += a[1];
                    }
                })
            });
            let owned = el.owned_nodes;
            assert!(
                visits.iter().all(|c| c.load(Relaxed) == 1),
                "owned {owned}, {threads} threads: a node not visited exactly once"
            );
            let same = f
                .iter()
                .zip(&whole)
                .all(|(a, b)| a.map(f64::to_bits) == b.map(f64::to_bits));
            assert!(same, "owned {owned}, {threads} threads: forces differ");
        }
    }
    fdem_figures::record_part(
        147,
        2,
        format!(
            "each of {} and {} nodes once, identical",
            ex.mesh.nodes.len(),
            mesh.nodes.len()
        ),
    );
}

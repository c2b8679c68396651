//! Test support: a structured mesh of exploded triangles (each triangle owns its three
//! nodes) with a joint on every internal edge, built from plain arrays.
#![allow(dead_code)]

use fdem_fracture::Joint;

/// An exploded structured mesh of `nx` x `ny` cells of size `dx` x `dy`, each cut by its
/// diagonal into a lower triangle (a, b, c) and an upper one (a, c, d), CCW.
pub struct Exploded {
    /// Reference node positions; triangle `t` owns nodes `3t, 3t+1, 3t+2`.
    pub x: Vec<[f64; 2]>,
    /// Triangles (CCW node ids).
    pub tris: Vec<[u32; 3]>,
    /// Joints on every internal edge (material 0).
    pub joints: Vec<Joint>,
}

/// Builds the mesh with its lower-left corner at the origin.
pub fn exploded_grid(nx: usize, ny: usize, dx: f64, dy: f64) -> Exploded {
    let lo = |i: usize, j: usize| 2 * (j * nx + i);
    let up = |i: usize, j: usize| 2 * (j * nx + i) + 1;
    let mut x = Vec::with_capacity(6 * nx * ny);
    let mut tris = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (x0, y0) = (i as f64 * dx, j as f64 * dy);
            let a = [x0, y0];
            let b = [x0 + dx, y0];
            let c = [x0 + dx, y0 + dy];
            let d = [x0, y0 + dy];
            for corners in [[a, b, c], [a, c, d]] {
                let t = tris.len() as u32;
                tris.push([3 * t, 3 * t + 1, 3 * t + 2]);
                x.extend_from_slice(&corners);
            }
        }
    }
    let node = |t: usize, k: usize| (3 * t + k) as u32;
    let mut joints = Vec::new();
    let diag = dx.hypot(dy);
    for j in 0..ny {
        for i in 0..nx {
            // diagonal: T_lo edge c->a against T_up edge a->c
            let (t1, t2) = (lo(i, j), up(i, j));
            joints.push(Joint {
                nodes: [node(t1, 2), node(t1, 0), node(t2, 0), node(t2, 1)],
                triangles: [t1 as u32, t2 as u32],
                ref_length: diag,
                material: 0,
            });
            if i + 1 < nx {
                // vertical: T_lo(i) edge b->c against T_up(i+1) edge d->a
                let (t1, t2) = (lo(i, j), up(i + 1, j));
                joints.push(Joint {
                    nodes: [node(t1, 1), node(t1, 2), node(t2, 2), node(t2, 0)],
                    triangles: [t1 as u32, t2 as u32],
                    ref_length: dy,
                    material: 0,
                });
            }
            if j + 1 < ny {
                // horizontal: T_up(i, j) edge c->d against T_lo(i, j+1) edge a->b
                let (t1, t2) = (up(i, j), lo(i, j + 1));
                joints.push(Joint {
                    nodes: [node(t1, 1), node(t1, 2), node(t2, 0), node(t2, 1)],
                    triangles: [t1 as u32, t2 as u32],
                    ref_length: dx,
                    material: 0,
                });
            }
        }
    }
    Exploded { x, tris, joints }
}

/// A small deterministic generator (64-bit LCG), uniform in [-1, 1).
pub struct Lcg(pub u64);

impl Lcg {
    /// Next value in [-1, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

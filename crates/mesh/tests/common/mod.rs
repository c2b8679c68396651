//! Shared helpers of the integration tests: small deterministic meshes.
#![allow(dead_code)]

use fdem_mesh::{Elements, Material, Mesh};

/// A tiny deterministic pseudo-random generator (xorshift), values in [0, 1).
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// An `nx` x `ny` grid on [0, lx] x [0, ly], each square cut along alternating diagonals,
/// interior nodes moved randomly by up to `jitter` of the cell size (an irregular mesh).
pub fn grid(nx: usize, ny: usize, lx: f64, ly: f64, jitter: f64, seed: u64) -> Mesh {
    let mut rng = Rng(seed.max(1));
    let (dx, dy) = (lx / nx as f64, ly / ny as f64);
    let mut nodes = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let mut p = [i as f64 * dx, j as f64 * dy];
            if i > 0 && i < nx && j > 0 && j < ny {
                p[0] += jitter * dx * (rng.next() - 0.5);
                p[1] += jitter * dy * (rng.next() - 0.5);
            }
            nodes.push(p);
        }
    }
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut tris = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                tris.push([a, b, c]);
                tris.push([a, c, d]);
            } else {
                tris.push([a, b, d]);
                tris.push([b, c, d]);
            }
        }
    }
    Mesh::from_nodes_triangles(nodes, tris).unwrap()
}

/// Elements of `mesh` with one material.
pub fn elements(mesh: &Mesh, m: Material) -> Elements {
    Elements::new(mesh, &vec![m; mesh.regions.len()]).unwrap()
}

/// Applies the affine map `x -> F x + c` to all nodes.
pub fn affine(x: &[[f64; 2]], f: [f64; 4], c: [f64; 2]) -> Vec<[f64; 2]> {
    x.iter()
        .map(|p| {
            [
                f[0] * p[0] + f[1] * p[1] + c[0],
                f[2] * p[0] + f[3] * p[1] + c[1],
            ]
        })
        .collect()
}

/// Rotation matrix (row-major).
pub fn rot(theta: f64) -> [f64; 4] {
    let (s, c) = theta.sin_cos();
    [c, -s, s, c]
}

/// Product of 2x2 row-major matrices.
pub fn mm(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] + a[1] * b[2],
        a[0] * b[1] + a[1] * b[3],
        a[2] * b[0] + a[3] * b[2],
        a[2] * b[1] + a[3] * b[3],
    ]
}

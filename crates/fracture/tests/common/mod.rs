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

/// Perturbs every node by up to `amp` in each direction.
pub fn perturbed(mesh: &Exploded, amp: f64, seed: u64) -> Vec<[f64; 2]> {
    let mut rng = Lcg(seed);
    mesh.x
        .iter()
        .map(|p| [p[0] + amp * rng.next(), p[1] + amp * rng.next()])
        .collect()
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

/// A small-strain linear-elastic constant-strain triangle in plane stress (test support only;
/// the solver has its own finite-strain elements).
pub struct Cst {
    /// Node ids.
    pub nodes: [usize; 3],
    /// `b_a = y_b - y_c` (reference).
    pub b: [f64; 3],
    /// `c_a = x_c - x_b` (reference).
    pub c: [f64; 3],
    /// Reference area.
    pub area: f64,
}

/// Linear elastic plane-stress triangles of a mesh: modulus, Poisson ratio, thickness.
pub struct Elastic {
    /// The triangles.
    pub tris: Vec<Cst>,
    /// Young's modulus (Pa).
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Thickness (m).
    pub t: f64,
}

impl Elastic {
    /// Builds the triangles from reference positions.
    pub fn new(tris: &[[u32; 3]], x0: &[[f64; 2]], e: f64, nu: f64, t: f64) -> Self {
        let tris = tris
            .iter()
            .map(|tri| {
                let p = tri.map(|i| x0[i as usize]);
                let area = 0.5
                    * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                        - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
                let b = [p[1][1] - p[2][1], p[2][1] - p[0][1], p[0][1] - p[1][1]];
                let c = [p[2][0] - p[1][0], p[0][0] - p[2][0], p[1][0] - p[0][0]];
                Cst {
                    nodes: tri.map(|i| i as usize),
                    b,
                    c,
                    area,
                }
            })
            .collect();
        Elastic { tris, e, nu, t }
    }

    fn stress(&self, tri: &Cst, x0: &[[f64; 2]], x: &[[f64; 2]]) -> ([f64; 3], [f64; 3]) {
        let (mut exx, mut eyy, mut gxy) = (0.0, 0.0, 0.0);
        for a in 0..3 {
            let n = tri.nodes[a];
            let u = [x[n][0] - x0[n][0], x[n][1] - x0[n][1]];
            exx += tri.b[a] * u[0];
            eyy += tri.c[a] * u[1];
            gxy += tri.c[a] * u[0] + tri.b[a] * u[1];
        }
        let s = 0.5 / tri.area;
        let (exx, eyy, gxy) = (exx * s, eyy * s, gxy * s);
        let k = self.e / (1.0 - self.nu * self.nu);
        let sig = [
            k * (exx + self.nu * eyy),
            k * (eyy + self.nu * exx),
            k * 0.5 * (1.0 - self.nu) * gxy,
        ];
        (sig, [exx, eyy, gxy])
    }

    /// Adds the elastic forces at positions `x` to `f`.
    pub fn add_forces(&self, x0: &[[f64; 2]], x: &[[f64; 2]], f: &mut [[f64; 2]]) {
        for tri in &self.tris {
            let (s, _) = self.stress(tri, x0, x);
            for a in 0..3 {
                let n = tri.nodes[a];
                f[n][0] -= 0.5 * self.t * (tri.b[a] * s[0] + tri.c[a] * s[2]);
                f[n][1] -= 0.5 * self.t * (tri.c[a] * s[1] + tri.b[a] * s[2]);
            }
        }
    }

    /// Strain energy `sum A t sigma : eps / 2` (J).
    pub fn energy(&self, x0: &[[f64; 2]], x: &[[f64; 2]]) -> f64 {
        self.tris
            .iter()
            .map(|tri| {
                let (s, e) = self.stress(tri, x0, x);
                0.5 * tri.area * self.t * (s[0] * e[0] + s[1] * e[1] + s[2] * e[2])
            })
            .sum()
    }

    /// Lumped masses `rho A t/3` per node.
    pub fn masses(&self, rho: f64, n_nodes: usize) -> Vec<f64> {
        let mut m = vec![0.0; n_nodes];
        for tri in &self.tris {
            for &a in &tri.nodes {
                m[a] += rho * tri.area * self.t / 3.0;
            }
        }
        m
    }
}

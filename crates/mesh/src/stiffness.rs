//! Small-strain (linear) stiffness of the same constant-strain triangles, assembled sparse
//! with faer, and a static solve with prescribed degrees of freedom.
//!
//! ```text
//! K_ab = A0 t B_a^T D B_b,   B_a = [[Na_x, 0], [0, Na_y], [Na_y, Na_x]]
//! D = [[lam* + 2mu, lam*, 0], [lam*, lam* + 2mu, 0], [0, 0, mu]]
//! ```
//! with reference gradients `grad N1`, `grad N2` the rows of `G0^-1` and
//! `grad N0 = -(grad N1 + grad N2)`. DOF `2i` is x of node i, `2i+1` is y.

use crate::elements::Elements;
use crate::error::MeshError;
use faer::Side;
use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};

/// Reference shape-function gradients of a triangle from `G0^-1` (row-major).
#[inline]
pub fn reference_gradients(ginv: [f64; 4]) -> [[f64; 2]; 3] {
    let n1 = [ginv[0], ginv[1]];
    let n2 = [ginv[2], ginv[3]];
    [[-n1[0] - n2[0], -n1[1] - n2[1]], n1, n2]
}

impl Elements {
    /// The 6x6 small-strain stiffness of triangle `t` (DOFs x0 y0 x1 y1 x2 y2).
    pub fn element_stiffness(&self, t: usize) -> [[f64; 6]; 6] {
        let td = &self.tris[t];
        let c = &self.materials[td.material as usize];
        let g = reference_gradients(td.ginv);
        let (l2m, l, m) = (c.lam + 2.0 * c.mu, c.lam, c.mu);
        let w = td.area0 * 2.0 * c.half_t;
        let mut k = [[0.0; 6]; 6];
        for a in 0..3 {
            let (ax, ay) = (g[a][0], g[a][1]);
            for b in 0..3 {
                let (bx, by) = (g[b][0], g[b][1]);
                k[2 * a][2 * b] = w * (l2m * ax * bx + m * ay * by);
                k[2 * a][2 * b + 1] = w * (l * ax * by + m * ay * bx);
                k[2 * a + 1][2 * b] = w * (l * ay * bx + m * ax * by);
                k[2 * a + 1][2 * b + 1] = w * (l2m * ay * by + m * ax * bx);
            }
        }
        k
    }

    /// The assembled small-strain stiffness (symmetric, both triangles stored), size
    /// `2 n_nodes`.
    pub fn stiffness(&self) -> SparseColMat<usize, f64> {
        let mut trip = Vec::with_capacity(36 * self.tris.len());
        for (t, td) in self.tris.iter().enumerate() {
            let k = self.element_stiffness(t);
            for a in 0..6 {
                for b in 0..6 {
                    let ra = 2 * td.nodes[a / 2] as usize + a % 2;
                    let cb = 2 * td.nodes[b / 2] as usize + b % 2;
                    trip.push(Triplet::new(ra, cb, k[a][b]));
                }
            }
        }
        let n = 2 * self.n_nodes;
        SparseColMat::try_new_from_triplets(n, n, &trip)
            .expect("indices are in range by construction")
    }
}

/// Solves `K u = f` with prescribed values `u(dof) = value` for the DOFs in `prescribed`
/// (sparse Cholesky of the free block; `f` at prescribed DOFs is ignored). Returns `u` of
/// length `K.nrows()`. Errors if the free block is not positive definite (a mechanism: too few
/// supports) or a DOF is out of range.
pub fn solve_static(
    k: &SparseColMat<usize, f64>,
    f: &[f64],
    prescribed: &[(usize, f64)],
) -> Result<Vec<f64>, MeshError> {
    let n = k.nrows();
    let bad = |m: String| MeshError::Parse {
        path: "<static solve>".into(),
        line: 0,
        message: m,
    };
    if f.len() != n {
        return Err(bad(format!(
            "load vector has {} entries, K has {n} rows",
            f.len()
        )));
    }
    let mut u = vec![0.0; n];
    let mut fixed = vec![false; n];
    for &(d, val) in prescribed {
        if d >= n {
            return Err(bad(format!("prescribed DOF {d} is out of range (n = {n})")));
        }
        fixed[d] = true;
        u[d] = val;
    }
    let mut free_index = vec![usize::MAX; n];
    let mut nf = 0;
    for d in 0..n {
        if !fixed[d] {
            free_index[d] = nf;
            nf += 1;
        }
    }
    let mut rhs = faer::Mat::<f64>::zeros(nf, 1);
    for d in 0..n {
        if !fixed[d] {
            rhs[(free_index[d], 0)] = f[d];
        }
    }
    let mut trip = Vec::new();
    let (cp, ri, vals) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for col in 0..n {
        for p in cp[col]..cp[col + 1] {
            let row = ri[p];
            let v = vals[p];
            match (fixed[row], fixed[col]) {
                (false, false) => trip.push(Triplet::new(free_index[row], free_index[col], v)),
                (false, true) => rhs[(free_index[row], 0)] -= v * u[col],
                _ => {}
            }
        }
    }
    let kf = SparseColMat::<usize, f64>::try_new_from_triplets(nf, nf, &trip)
        .map_err(|e| bad(format!("cannot build the free block: {e:?}")))?;
    let llt = kf.sp_cholesky(Side::Lower).map_err(|_| {
        bad(
            "the stiffness is singular (not positive definite): a body is not held (add supports)"
                .into(),
        )
    })?;
    llt.solve_in_place(rhs.as_mut());
    for d in 0..n {
        if !fixed[d] {
            u[d] = rhs[(free_index[d], 0)];
        }
    }
    Ok(u)
}

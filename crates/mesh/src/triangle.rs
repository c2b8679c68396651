//! Per-triangle kinematics and stress at finite strain (pure functions, no mesh).
//!
//! ```text
//! G0 = [X1-X0 | X2-X0]   G = [x1-x0 | x2-x0]   Gv = [v1-v0 | v2-v0]
//! F = G G0^-1   J = det F   B = F F^T   L = Gv G^-1   d = (L + L^T)/2
//! f_a = -A t sigma grad N_a = -(t/2) sigma rot(x_c - x_b),   rot(a) = (-a_y, a_x)
//! ```
//! with `(a, b, c)` over (0,1,2), (1,2,0), (2,0,1). Symmetric 2x2 tensors are `[xx, yy, xy]`;
//! 2x2 matrices are row-major `[m00, m01, m10, m11]`.

use crate::material::ElasticLaw;

/// A symmetric 2x2 tensor `[xx, yy, xy]`.
pub type Sym2 = [f64; 3];
/// A 2x2 matrix, row-major `[m00, m01, m10, m11]`.
pub type Mat2 = [f64; 4];

/// Edge matrix `[p1-p0 | p2-p0]` of three points (row-major).
#[inline(always)]
pub fn edge_matrix(p0: [f64; 2], p1: [f64; 2], p2: [f64; 2]) -> Mat2 {
    [p1[0] - p0[0], p2[0] - p0[0], p1[1] - p0[1], p2[1] - p0[1]]
}

/// Product of two 2x2 matrices.
#[inline(always)]
pub fn mul(a: Mat2, b: Mat2) -> Mat2 {
    [
        a[0] * b[0] + a[1] * b[2],
        a[0] * b[1] + a[1] * b[3],
        a[2] * b[0] + a[3] * b[2],
        a[2] * b[1] + a[3] * b[3],
    ]
}

/// Determinant.
#[inline(always)]
pub fn det(a: Mat2) -> f64 {
    a[0] * a[3] - a[1] * a[2]
}

/// Inverse (the caller guarantees `det != 0`).
#[inline(always)]
pub fn inv(a: Mat2) -> Mat2 {
    let r = 1.0 / det(a);
    [a[3] * r, -a[1] * r, -a[2] * r, a[0] * r]
}

/// `B = F F^T`.
#[inline(always)]
pub fn left_cauchy_green(f: Mat2) -> Sym2 {
    [
        f[0] * f[0] + f[1] * f[1],
        f[2] * f[2] + f[3] * f[3],
        f[0] * f[2] + f[1] * f[3],
    ]
}

/// Elastic Cauchy stress of the law for deformation gradient `f`.
#[inline(always)]
pub fn elastic_stress(law: ElasticLaw, mu: f64, lam: f64, f: Mat2) -> Sym2 {
    let b = left_cauchy_green(f);
    match law {
        ElasticLaw::Munjiza => {
            let (exx, eyy, exy) = (0.5 * (b[0] - 1.0), 0.5 * (b[1] - 1.0), 0.5 * b[2]);
            let tr = lam * (exx + eyy);
            [2.0 * mu * exx + tr, 2.0 * mu * eyy + tr, 2.0 * mu * exy]
        }
        ElasticLaw::NeoHookean => {
            let j = det(f);
            let rj = 1.0 / j;
            let l = lam * j.ln();
            [
                (mu * (b[0] - 1.0) + l) * rj,
                (mu * (b[1] - 1.0) + l) * rj,
                mu * b[2] * rj,
            ]
        }
    }
}

/// Out-of-plane Cauchy stress in plane strain (zero in plane stress).
#[inline]
pub fn elastic_stress_zz(law: ElasticLaw, lam: f64, f: Mat2) -> f64 {
    let b = left_cauchy_green(f);
    match law {
        ElasticLaw::Munjiza => lam * 0.5 * (b[0] + b[1] - 2.0),
        ElasticLaw::NeoHookean => {
            let j = det(f);
            lam * j.ln() / j
        }
    }
}

/// Strain energy per unit reference area and thickness. Neo-Hookean: its exact potential.
/// Munjiza: the small-strain value `mu e:e + lam*/2 tr(e)^2` (the law has no potential).
#[inline]
pub fn energy_density(law: ElasticLaw, mu: f64, lam: f64, f: Mat2) -> f64 {
    let b = left_cauchy_green(f);
    match law {
        ElasticLaw::Munjiza => {
            let (exx, eyy, exy) = (0.5 * (b[0] - 1.0), 0.5 * (b[1] - 1.0), 0.5 * b[2]);
            mu * (exx * exx + eyy * eyy + 2.0 * exy * exy) + 0.5 * lam * (exx + eyy).powi(2)
        }
        ElasticLaw::NeoHookean => {
            let lj = det(f).ln();
            0.5 * mu * (b[0] + b[1] - 2.0 - 2.0 * lj) + 0.5 * lam * lj * lj
        }
    }
}

/// Rate of deformation `d = sym(Gv G^-1)` from current edge matrices `g` and `gv`.
#[inline(always)]
pub fn rate_of_deformation(g: Mat2, gv: Mat2) -> Sym2 {
    let l = mul(gv, inv(g));
    [l[0], l[3], 0.5 * (l[1] + l[2])]
}

/// Nodal forces `f_a = -(t/2) sigma rot(x_c - x_b)` of a triangle with Cauchy stress `s`.
#[inline(always)]
pub fn nodal_forces(s: Sym2, half_t: f64, x: [[f64; 2]; 3]) -> [[f64; 2]; 3] {
    let mut out = [[0.0; 2]; 3];
    for a in 0..3 {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        // r = rot(x_c - x_b) = (-(y_c - y_b), x_c - x_b)
        let rx = x[b][1] - x[c][1];
        let ry = x[c][0] - x[b][0];
        out[a] = [
            -half_t * (s[0] * rx + s[2] * ry),
            -half_t * (s[2] * rx + s[1] * ry),
        ];
    }
    out
}

/// Cauchy stress `F S0 F^T / J` of a constant second Piola-Kirchhoff initial stress `s0`
/// (`[xx, yy, xy]`) at deformation gradient `f`: `s0` itself at `F = I`, `Q s0 Q^T` after a
/// rigid rotation `Q` (objective), and the stress of the potential `S0 : E` per reference
/// volume, `E = (F^T F - I)/2` ([`initial_stress_energy`]).
#[inline(always)]
pub fn initial_stress_cauchy(s0: Sym2, f: Mat2) -> Sym2 {
    // P = F S0
    let p = [
        f[0] * s0[0] + f[1] * s0[2],
        f[0] * s0[2] + f[1] * s0[1],
        f[2] * s0[0] + f[3] * s0[2],
        f[2] * s0[2] + f[3] * s0[1],
    ];
    let rj = 1.0 / det(f);
    [
        (p[0] * f[0] + p[1] * f[1]) * rj,
        (p[2] * f[2] + p[3] * f[3]) * rj,
        (p[0] * f[2] + p[1] * f[3]) * rj,
    ]
}

/// Energy of the initial stress per unit reference area and thickness, `S0 : E` with the
/// Green-Lagrange strain `E = (F^T F - I)/2` (its derivative is [`initial_stress_cauchy`]).
#[inline]
pub fn initial_stress_energy(s0: Sym2, f: Mat2) -> f64 {
    // C = F^T F
    let cxx = f[0] * f[0] + f[2] * f[2];
    let cyy = f[1] * f[1] + f[3] * f[3];
    let cxy = f[0] * f[1] + f[2] * f[3];
    0.5 * (s0[0] * (cxx - 1.0) + s0[1] * (cyy - 1.0)) + s0[2] * cxy
}

/// Directional derivative of [`initial_stress_cauchy`] along `df` (with `sp` its value at
/// `f`): `(dF S0 F^T + F S0 dF^T)/J - tr(F^-1 dF) sp`.
#[inline(always)]
pub fn initial_stress_cauchy_derivative(s0: Sym2, f: Mat2, df: Mat2, sp: Sym2) -> Sym2 {
    // A = dF S0 F^T; dsigma J = A + A^T
    let ds0 = [
        df[0] * s0[0] + df[1] * s0[2],
        df[0] * s0[2] + df[1] * s0[1],
        df[2] * s0[0] + df[3] * s0[2],
        df[2] * s0[2] + df[3] * s0[1],
    ];
    let a = [
        ds0[0] * f[0] + ds0[1] * f[1],
        ds0[0] * f[2] + ds0[1] * f[3],
        ds0[2] * f[0] + ds0[3] * f[1],
        ds0[2] * f[2] + ds0[3] * f[3],
    ];
    let j = det(f);
    let fi = inv(f);
    let c = fi[0] * df[0] + fi[1] * df[2] + fi[2] * df[1] + fi[3] * df[3];
    let rj = 1.0 / j;
    [
        2.0 * a[0] * rj - c * sp[0],
        2.0 * a[3] * rj - c * sp[1],
        (a[1] + a[2]) * rj - c * sp[2],
    ]
}

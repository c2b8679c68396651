//! Per-triangle outputs: Cauchy stress, principal stresses, von Mises stress, strain energy,
//! and the bound on the highest natural frequency used for the stable time step.
//!
//! Frequency bound (lumped mass, small strain about the given geometry):
//! `omega_e^2 <= 3 c_p^2 sum_a |grad N_a|^2 = 3 c_p^2 (l0^2 + l1^2 + l2^2)/(4 A^2)`,
//! `c_p^2 = (lam* + 2 mu)/rho`. The global `omega_max` of the assembled mesh is at most the
//! largest element value.

use crate::elements::Elements;
use crate::forces::tri_stress;
use crate::ids::TriId;
use crate::material::PlaneKind;
use crate::triangle::{
    det, edge_matrix, elastic_stress_zz, energy_density, initial_stress_energy, mul,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Cauchy stress of a triangle (Pa), tension positive, with the out-of-plane component.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stress {
    /// sigma_xx.
    pub xx: f64,
    /// sigma_yy.
    pub yy: f64,
    /// sigma_xy.
    pub xy: f64,
    /// sigma_zz (0 in plane stress; from the law in plane strain).
    pub zz: f64,
}

impl Stress {
    /// In-plane principal stresses `[s1, s2]`, `s1 >= s2`.
    pub fn principal(&self) -> [f64; 2] {
        let c = 0.5 * (self.xx + self.yy);
        let r = (0.25 * (self.xx - self.yy).powi(2) + self.xy * self.xy).sqrt();
        [c + r, c - r]
    }

    /// Angle (rad) from the x axis to the direction of the larger principal stress `s1`.
    pub fn principal_angle(&self) -> f64 {
        0.5 * (2.0 * self.xy).atan2(self.xx - self.yy)
    }

    /// Von Mises stress including `zz`:
    /// `sqrt(((s_xx-s_yy)^2 + (s_yy-s_zz)^2 + (s_zz-s_xx)^2)/2 + 3 s_xy^2)`.
    pub fn von_mises(&self) -> f64 {
        let (a, b, c) = (self.xx, self.yy, self.zz);
        (0.5 * ((a - b).powi(2) + (b - c).powi(2) + (c - a).powi(2)) + 3.0 * self.xy * self.xy)
            .sqrt()
    }
}

impl Elements {
    /// Cauchy stress (elastic + viscous) of triangle `t` at positions `x`, velocities `v`.
    pub fn stress(&self, t: TriId, x: &[[f64; 2]], v: &[[f64; 2]]) -> Stress {
        let td = &self.tris[t.idx()];
        let c = &self.materials[td.material as usize];
        let xs = td.nodes.map(|n| x[n as usize]);
        let s0 = self.initial_stress.get(t.idx());
        let (s, f) = if self.viscous {
            tri_stress::<true>(td, c, xs, v, s0)
        } else {
            tri_stress::<false>(td, c, xs, v, s0)
        };
        let zz = match c.material.plane {
            PlaneKind::Stress => 0.0,
            PlaneKind::Strain => elastic_stress_zz(c.law, c.lam, f),
        };
        Stress {
            xx: s[0],
            yy: s[1],
            xy: s[2],
            zz,
        }
    }

    /// Stresses of all triangles into `out` (parallel).
    pub fn stresses(&self, x: &[[f64; 2]], v: &[[f64; 2]], out: &mut [Stress]) {
        out.par_iter_mut()
            .enumerate()
            .for_each(|(t, o)| *o = self.stress(TriId(t as u32), x, v));
    }

    /// Deformation gradient `F = G G0^-1` of triangle `t`, row-major.
    pub fn deformation_gradient(&self, t: TriId, x: &[[f64; 2]]) -> [f64; 4] {
        let td = &self.tris[t.idx()];
        let [p0, p1, p2] = td.nodes.map(|n| x[n as usize]);
        mul(edge_matrix(p0, p1, p2), td.ginv)
    }

    /// Strain energy of triangle `t` (J): `A0 t W(F)` (see
    /// [`crate::triangle::energy_density`]), plus `A0 t S0 : E` for a triangle with an initial
    /// stress `S0` ([`crate::triangle::initial_stress_energy`]).
    pub fn element_energy(&self, t: TriId, x: &[[f64; 2]]) -> f64 {
        let td = &self.tris[t.idx()];
        let c = &self.materials[td.material as usize];
        let f = self.deformation_gradient(t, x);
        match self.initial_stress.get(t.idx()) {
            None => td.area0 * 2.0 * c.half_t * energy_density(c.law, c.mu, c.lam, f),
            Some(s0) => {
                td.area0
                    * 2.0
                    * c.half_t
                    * (energy_density(c.law, c.mu, c.lam, f) + initial_stress_energy(*s0, f))
            }
        }
    }

    /// The part of [`Elements::strain_energy`] that is the initial stresses' energy,
    /// `sum A0 t S0 : E` (J), summed in triangle order; 0 at once when no triangle has one.
    /// It is linear in the displacement at small strain and may be negative.
    pub fn initial_stress_energy(&self, x: &[[f64; 2]]) -> f64 {
        self.initial_stress
            .iter()
            .enumerate()
            .map(|(t, s0)| {
                let td = &self.tris[t];
                let c = &self.materials[td.material as usize];
                let f = self.deformation_gradient(TriId(t as u32), x);
                td.area0 * 2.0 * c.half_t * initial_stress_energy(*s0, f)
            })
            .sum()
    }

    /// Total strain energy (J), summed in triangle order (deterministic: the element
    /// energies are evaluated in parallel above 4 096 triangles, then summed in order).
    pub fn strain_energy(&self, x: &[[f64; 2]]) -> f64 {
        let n = self.tris.len();
        if n < 4096 {
            return (0..n)
                .map(|t| self.element_energy(TriId(t as u32), x))
                .sum();
        }
        let energies: Vec<f64> = (0..n)
            .into_par_iter()
            .with_min_len(1024)
            .map(|t| self.element_energy(TriId(t as u32), x))
            .collect();
        energies.iter().sum()
    }

    /// The elastic energy the initial stresses would store as strains (J),
    /// `sum A0 t (sxx^2 + syy^2 + 2 sxy^2) / (2 (lam* + 2 mu))`: a scale of the energies a
    /// prestressed body exchanges (0 without initial stress).
    pub fn initial_stress_energy_scale(&self) -> f64 {
        self.initial_stress
            .iter()
            .zip(&self.tris)
            .map(|(s, td)| {
                let c = &self.materials[td.material as usize];
                td.area0 * 2.0 * c.half_t * (s[0] * s[0] + s[1] * s[1] + 2.0 * s[2] * s[2])
                    / (2.0 * (c.lam + 2.0 * c.mu))
            })
            .sum()
    }

    /// Upper bound (rad/s) on the highest natural frequency of triangle `t` with lumped mass,
    /// at positions `x`: `sqrt(3 c_p^2 (l0^2 + l1^2 + l2^2)) / (2 A)`.
    pub fn frequency_bound(&self, t: TriId, x: &[[f64; 2]]) -> f64 {
        let td = &self.tris[t.idx()];
        let c = &self.materials[td.material as usize];
        let [p0, p1, p2] = td.nodes.map(|n| x[n as usize]);
        let a2 = det(edge_matrix(p0, p1, p2));
        let l2: f64 = [(p0, p1), (p1, p2), (p2, p0)]
            .iter()
            .map(|(a, b)| (b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2))
            .sum();
        let cp2 = match self.initial_stress.get(t.idx()) {
            None => (c.lam + 2.0 * c.mu) / c.rho,
            // the initial stress's geometric stiffness `A0 t (grad N_a . S0 grad N_b) I`
            // adds at most its largest principal magnitude to lam* + 2 mu
            Some(s0) => {
                let r = (0.25 * (s0[0] - s0[1]).powi(2) + s0[2] * s0[2]).sqrt();
                let smax = (0.5 * (s0[0] + s0[1])).abs() + r;
                (c.lam + 2.0 * c.mu + smax) / c.rho
            }
        };
        (3.0 * cp2 * l2).sqrt() / a2
    }

    /// The largest [`Elements::frequency_bound`] over all triangles (rad/s); the central
    /// difference step is stable for `dt <= 2 / omega_max`.
    pub fn max_frequency_bound(&self, x: &[[f64; 2]]) -> f64 {
        (0..self.tris.len())
            .into_par_iter()
            .map(|t| self.frequency_bound(TriId(t as u32), x))
            .reduce(|| 0.0, f64::max)
    }

    /// Damping ratio of a triangle's highest mode implied by its viscosity,
    /// `z = eta omega_e / (2 (lam* + 2 mu))` (about `2 xi` for the free element); use it in
    /// `dt <= (2/omega)(sqrt(1+z^2) - z)`.
    pub fn high_mode_damping(&self, t: TriId, x: &[[f64; 2]]) -> f64 {
        let td = &self.tris[t.idx()];
        let c = &self.materials[td.material as usize];
        td.eta * self.frequency_bound(t, x) / (2.0 * (c.lam + 2.0 * c.mu))
    }
}

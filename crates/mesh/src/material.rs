//! Materials of the triangles: Munjiza's objective finite-strain linear law or a compressible
//! neo-Hookean law, plane stress or plane strain, thickness, and viscous damping from a
//! damping ratio.
//!
//! Moduli (stress positive in tension):
//!
//! ```text
//! mu   = E / (2 (1 + nu))
//! lam* = E nu / ((1 + nu)(1 - 2 nu))   plane strain
//! lam* = E nu / (1 - nu^2)             plane stress
//! ```
//!
//! Munjiza (2004, eq. 4.177): `e = (B - I)/2`, `sigma_e = 2 mu e + lam* tr(e) I` (Cauchy, current
//! frame; `B = F F^T`). Neo-Hookean: `sigma_e = (mu (B - I) + lam* ln(J) I)/J` from
//! `W = mu/2 (tr B - 2 - 2 ln J) + lam*/2 (ln J)^2` per reference area and thickness. For plane
//! stress the neo-Hookean law uses `lam*` of plane stress: the 2D law is hyperelastic and exact
//! at small strain, but not the 3D neo-Hookean law under plane stress at large strain.
//!
//! Viscous stress `sigma_v = eta d`, `d = sym(L)`, `eta = 2 xi h sqrt(E rho)` per triangle, with
//! `h = 2 A0 / (longest reference edge)` (the smallest altitude).

use crate::error::MeshError;
use serde::{Deserialize, Serialize};

/// The elastic law of a material.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ElasticLaw {
    /// Munjiza's law: `sigma = 2 mu e + lam* tr(e) I`, `e = (B - I)/2`. Objective, exact for
    /// small strain at any rotation; not hyperelastic at large strain.
    #[default]
    Munjiza,
    /// Compressible neo-Hookean: `sigma = (mu (B - I) + lam* ln J I)/J`. Hyperelastic.
    NeoHookean,
}

/// Plane stress or plane strain.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum PlaneKind {
    /// Plane strain (`eps_zz = 0`; use thickness 1 m).
    #[default]
    Strain,
    /// Plane stress (`sigma_zz = 0`).
    Stress,
}

/// A material of one region of triangles.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Elastic law. Default Munjiza.
    #[serde(default)]
    pub law: ElasticLaw,
    /// Plane stress or strain. Default plane strain.
    #[serde(default)]
    pub plane: PlaneKind,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio nu (-), in [0, 0.5) (negative down to -1 allowed).
    pub poisson_ratio: f64,
    /// Density rho (kg/m^3).
    pub density: f64,
    /// Out-of-plane thickness t (m). Default 1.
    #[serde(default = "one")]
    pub thickness: f64,
    /// Damping ratio xi (-) of the viscous stress (`eta = 2 xi h sqrt(E rho)`). Default 0.
    #[serde(default)]
    pub damping_ratio: f64,
}

fn one() -> f64 {
    1.0
}

impl Material {
    /// A Munjiza-law, plane-strain material of unit thickness without damping.
    pub fn new(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> Material {
        Material {
            law: ElasticLaw::Munjiza,
            plane: PlaneKind::Strain,
            youngs_modulus,
            poisson_ratio,
            density,
            thickness: 1.0,
            damping_ratio: 0.0,
        }
    }

    /// Shear modulus `mu = E/(2(1+nu))` (Pa).
    pub fn mu(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// The 2D Lame modulus `lam*` of plane strain or plane stress (Pa).
    pub fn lambda(&self) -> f64 {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        match self.plane {
            PlaneKind::Strain => e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            PlaneKind::Stress => e * nu / (1.0 - nu * nu),
        }
    }

    /// P-wave speed of the 2D medium, `sqrt((lam* + 2 mu)/rho)` (m/s).
    pub fn p_wave_speed(&self) -> f64 {
        ((self.lambda() + 2.0 * self.mu()) / self.density).sqrt()
    }

    /// Checks the ranges; `index` names the material in the message.
    pub fn validate(&self, index: usize) -> Result<(), MeshError> {
        let bad = |field, value, fix| {
            Err(MeshError::Material {
                index,
                field,
                value,
                fix,
            })
        };
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(self.youngs_modulus) {
            return bad("youngs_modulus", self.youngs_modulus, "must be > 0 [Pa]");
        }
        let nu = self.poisson_ratio;
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return bad("poisson_ratio", nu, "must be in (-1, 0.5)");
        }
        if !ok(self.density) {
            return bad("density", self.density, "must be > 0 [kg/m^3]");
        }
        if !ok(self.thickness) {
            return bad("thickness", self.thickness, "must be > 0 [m]");
        }
        if !(self.damping_ratio.is_finite() && self.damping_ratio >= 0.0) {
            return bad("damping_ratio", self.damping_ratio, "must be >= 0");
        }
        Ok(())
    }
}

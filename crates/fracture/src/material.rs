//! Joint material: the user's inputs, their validation, and the derived peak and critical
//! displacements.
//!
//! Stiffness convention: a joint of reference edge length `h` has the initial normal stiffness
//! `p/h` and tangential stiffness `p_t/h` (Pa/m), as a layer of thickness `h` and modulus `p`.
//! Then
//!
//! ```text
//! o_p = 2 h ft/p,            o_c = o_p + (G_I  - (2/3) ft o_p)/(I_z ft)
//! s_p = 2 h fs/p_t,          s_c = s_p + (G_II - (2/3) fs s_p)/(I_z fs)
//! fs  = c + sigma_c tan(phi),  sigma_c = max(0, -sigma)   (sigma tension-positive)
//! ```
//!
//! so that the work to break a joint in pure mode I is exactly `G_I` per unit area
//! (`(2/3) ft o_p` before the peak plus `I_z ft (o_c - o_p)` after it), and likewise `G_II` in
//! pure mode II at the current `fs`. This needs `G_I > (2/3) ft o_p = (4/3) h ft^2/p` (and
//! `G_II > (4/3) h c^2/p_t`), checked per joint when the joint set is built.

use serde::{Deserialize, Serialize};

use crate::error::FractureError;
use crate::softening::softening_width;

/// The user's joint material (SI units). No defaults: every field is a property of the rock
/// or concrete modelled.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointMaterialInput {
    /// Tensile strength `ft` (Pa), > 0.
    pub tensile_strength: f64,
    /// Cohesion `c` (Pa), > 0: the shear strength without normal compression.
    pub cohesion: f64,
    /// Internal friction angle `phi` (degrees), in [0, 90).
    pub friction_angle_deg: f64,
    /// Mode I fracture energy `G_I` (J/m^2), > 0.
    pub fracture_energy_i: f64,
    /// Mode II fracture energy `G_II` (J/m^2), > 0.
    pub fracture_energy_ii: f64,
    /// Normal joint penalty `p` (Pa), > 0; the joint's normal stiffness is `p/h`. Take
    /// `p >= 10 E`: the joints add a compliance of about `beta/p` to the elements' `1/E`.
    pub penalty_normal: f64,
    /// Tangential joint penalty `p_t` (Pa), > 0; the tangential stiffness is `p_t/h`.
    pub penalty_tangential: f64,
}

/// Constants of one joint derived from its material and reference length `h`: those every
/// evaluation reads (the pre-peak law). The softening branch also reads the joint's
/// [`SofteningConsts`], kept in an array of their own so that a pass over joints before their
/// peaks does not move them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointConsts {
    /// Reference edge length `h` (m).
    pub h: f64,
    /// Normal stiffness `p/h` (Pa/m).
    pub kn: f64,
    /// Peak opening `o_p = 2 h ft/p` (m).
    pub o_p: f64,
    /// `1/o_p`.
    pub inv_o_p: f64,
    /// `2 h/p_t`: the peak slip per unit shear strength (m/Pa).
    pub slip_per_fs: f64,
    /// Peak slip without compression, `s_p0 = 2 h c/p_t` (m).
    pub s_p0: f64,
    /// `1/s_p0`.
    pub inv_s_p0: f64,
}

/// The constants of one joint that only its softening branch reads (see [`JointConsts`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SofteningConsts {
    /// Softening width `o_c - o_p` (m).
    pub o_soft: f64,
    /// `1/(o_c - o_p)`.
    pub inv_o_soft: f64,
    /// Shear softening width without compression (m), > 0 for a validated joint.
    pub s_soft0: f64,
    /// `1/s_soft0`.
    pub inv_s_soft0: f64,
}

/// A validated joint material with its derived constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointMaterial {
    /// Tensile strength `ft` (Pa).
    pub ft: f64,
    /// Cohesion `c` (Pa).
    pub cohesion: f64,
    /// `tan(phi)`.
    pub tan_phi: f64,
    /// Mode I fracture energy (J/m^2).
    pub g_i: f64,
    /// Mode II fracture energy (J/m^2).
    pub g_ii: f64,
    /// Normal penalty `p` (Pa).
    pub p: f64,
    /// Tangential penalty `p_t` (Pa).
    pub p_t: f64,
}

fn check(
    material: u32,
    field: &'static str,
    value: f64,
    ok: bool,
    requirement: &'static str,
) -> Result<(), FractureError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(FractureError::InvalidMaterial {
            material,
            field,
            value,
            requirement,
        })
    }
}

impl JointMaterialInput {
    /// Checks every field (the error names the field and its range) and derives the constants.
    /// `material` is the index used in error messages.
    pub fn validate(&self, material: u32) -> Result<JointMaterial, FractureError> {
        let pos = "finite and > 0";
        check(
            material,
            "tensile_strength",
            self.tensile_strength,
            self.tensile_strength > 0.0,
            pos,
        )?;
        check(
            material,
            "cohesion",
            self.cohesion,
            self.cohesion > 0.0,
            pos,
        )?;
        check(
            material,
            "friction_angle_deg",
            self.friction_angle_deg,
            (0.0..90.0).contains(&self.friction_angle_deg),
            "in [0, 90) degrees",
        )?;
        check(
            material,
            "fracture_energy_i",
            self.fracture_energy_i,
            self.fracture_energy_i > 0.0,
            pos,
        )?;
        check(
            material,
            "fracture_energy_ii",
            self.fracture_energy_ii,
            self.fracture_energy_ii > 0.0,
            pos,
        )?;
        check(
            material,
            "penalty_normal",
            self.penalty_normal,
            self.penalty_normal > 0.0,
            pos,
        )?;
        check(
            material,
            "penalty_tangential",
            self.penalty_tangential,
            self.penalty_tangential > 0.0,
            pos,
        )?;
        Ok(JointMaterial {
            ft: self.tensile_strength,
            cohesion: self.cohesion,
            tan_phi: self.friction_angle_deg.to_radians().tan(),
            g_i: self.fracture_energy_i,
            g_ii: self.fracture_energy_ii,
            p: self.penalty_normal,
            p_t: self.penalty_tangential,
        })
    }
}

impl JointMaterial {
    /// Peak opening `o_p = 2 h ft/p` (m) for reference edge length `h`.
    #[inline(always)]
    pub fn peak_opening(&self, h: f64) -> f64 {
        2.0 * h * self.ft / self.p
    }

    /// Critical opening `o_c = o_p + (G_I - (2/3) ft o_p)/(I_z ft)` (m): pure mode I dissipates
    /// exactly `G_I` per unit area.
    #[inline]
    pub fn critical_opening(&self, h: f64) -> f64 {
        let o_p = self.peak_opening(h);
        o_p + softening_width(self.g_i, self.ft, o_p)
    }

    /// Shear strength `fs = c + sigma_c tan(phi)` for the tension-positive normal stress `sigma`
    /// (`sigma_c = max(0, -sigma)`).
    #[inline]
    pub fn shear_strength(&self, sigma: f64) -> f64 {
        self.cohesion + (-sigma).max(0.0) * self.tan_phi
    }

    /// Peak slip `s_p = 2 h fs/p_t` (m) at shear strength `fs`.
    #[inline(always)]
    pub fn peak_slip(&self, h: f64, fs: f64) -> f64 {
        2.0 * h * fs / self.p_t
    }

    /// Shear softening width `s_c - s_p = max(0, G_II - (2/3) fs s_p)/(I_z fs)` (m). It is zero
    /// when compression raises `fs` so far that the pre-peak work exceeds `G_II`: the joint
    /// then breaks at the shear peak (brittle), dissipating `(2/3) fs s_p > G_II`.
    #[inline]
    pub fn slip_softening_width(&self, h: f64, fs: f64) -> f64 {
        softening_width(self.g_ii, fs, self.peak_slip(h, fs)).max(0.0)
    }

    /// The per-joint constants of an edge of reference length `h`.
    #[inline(always)]
    pub fn consts(&self, h: f64) -> JointConsts {
        let o_p = self.peak_opening(h);
        let s_p0 = self.peak_slip(h, self.cohesion);
        JointConsts {
            s_p0,
            inv_s_p0: 1.0 / s_p0,
            h,
            kn: self.p / h,
            o_p,
            inv_o_p: 1.0 / o_p,
            slip_per_fs: 2.0 * h / self.p_t,
        }
    }

    /// The softening constants of an edge of reference length `h` (divisions done once).
    pub fn softening_consts(&self, h: f64) -> SofteningConsts {
        let o_soft = self.critical_opening(h) - self.peak_opening(h);
        let s_soft0 = self.slip_softening_width(h, self.cohesion);
        SofteningConsts {
            s_soft0,
            inv_s_soft0: 1.0 / s_soft0,
            o_soft,
            inv_o_soft: 1.0 / o_soft,
        }
    }

    /// Checks that both pure modes can dissipate their fracture energy on an edge of length `h`
    /// (the error names the joint, the field and the fix).
    pub fn check_edge(&self, joint: u32, material: u32, h: f64) -> Result<(), FractureError> {
        let modes = [
            (
                "fracture_energy_i",
                "penalty_normal",
                self.g_i,
                self.ft,
                self.p,
            ),
            (
                "fracture_energy_ii",
                "penalty_tangential",
                self.g_ii,
                self.cohesion,
                self.p_t,
            ),
        ];
        for (field, penalty_field, g, f, p) in modes {
            let d_p = 2.0 * h * f / p;
            let w = 2.0 / 3.0 * f * d_p;
            if g <= w {
                return Err(FractureError::FractureEnergyTooSmall {
                    joint,
                    material,
                    field,
                    penalty_field,
                    h,
                    g,
                    f,
                    d_p,
                    w,
                    p_min: 4.0 * h * f * f / (3.0 * g),
                    h_max: 3.0 * g * p / (4.0 * f * f),
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rock() -> JointMaterialInput {
        JointMaterialInput {
            tensile_strength: 5e6,
            cohesion: 10e6,
            friction_angle_deg: 30.0,
            fracture_energy_i: 100.0,
            fracture_energy_ii: 500.0,
            penalty_normal: 300e9,
            penalty_tangential: 300e9,
        }
    }

    #[test]
    fn each_invalid_field_is_named() {
        let fields = [
            "tensile_strength",
            "cohesion",
            "friction_angle_deg",
            "fracture_energy_i",
            "fracture_energy_ii",
            "penalty_normal",
            "penalty_tangential",
        ];
        for (k, name) in fields.iter().enumerate() {
            let mut m = rock();
            let v = if k == 2 { 90.0 } else { -1.0 };
            match k {
                0 => m.tensile_strength = v,
                1 => m.cohesion = v,
                2 => m.friction_angle_deg = v,
                3 => m.fracture_energy_i = v,
                4 => m.fracture_energy_ii = v,
                5 => m.penalty_normal = v,
                _ => m.penalty_tangential = v,
            }
            let e = m.validate(3).unwrap_err();
            let text = e.to_string();
            assert!(text.contains(name) && text.contains("material 3"), "{text}");
        }
        let mut m = rock();
        m.tensile_strength = f64::NAN;
        assert!(m.validate(0).is_err());
    }

    #[test]
    fn too_small_fracture_energy_names_the_fix() {
        let m = rock().validate(0).unwrap();
        // (4/3) h ft^2/p = 100 J/m^2 at h = 100*3*300e9/(4*25e12) = 0.9 m
        let h_max = 3.0 * 100.0 * 300e9 / (4.0 * 25e12);
        assert!(m.check_edge(7, 0, 0.99 * h_max).is_ok());
        let e = m.check_edge(7, 0, 1.01 * h_max).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("joint 7") && text.contains("fracture_energy_i"),
            "{text}"
        );
        assert!(
            text.contains("penalty_normal") && text.contains("refine"),
            "{text}"
        );
        if let FractureError::FractureEnergyTooSmall { p_min, .. } = e {
            // p_min makes the pre-peak work equal G exactly: 4 h ft^2/(3 G)
            assert!((p_min - 4.0 * 1.01 * h_max * 25e12 / 300.0).abs() < 1e-6 * p_min);
        }
    }

    #[test]
    fn critical_opening_makes_the_work_equal_g() {
        let m = rock().validate(0).unwrap();
        let h = 0.01;
        let (o_p, o_c) = (m.peak_opening(h), m.critical_opening(h));
        assert!((o_p - 2.0 * 0.01 * 5e6 / 300e9).abs() < 1e-22);
        let w = crate::softening::work_to_break(m.ft, o_p, o_c);
        assert!((w - 100.0).abs() < 1e-12 * 100.0, "work {w}");
        assert!((m.shear_strength(-2e6) - (10e6 + 2e6 * 30f64.to_radians().tan())).abs() < 1e-6);
        assert_eq!(m.shear_strength(3e6), 10e6);
    }
}

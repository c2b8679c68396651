//! Errors of the fracture crate: each names the material or joint, the field and the fix.

use thiserror::Error;

/// What can be wrong with joint input. Nothing in the per-step kernels returns an error.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FractureError {
    /// A material field is out of its range.
    #[error(
        "joint material {material}: field `{field}` = {value} is invalid: it must be {requirement}"
    )]
    InvalidMaterial {
        /// Index of the material in the list given.
        material: u32,
        /// The field's name as written in the input.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The range the field must lie in.
        requirement: &'static str,
    },
    /// A parameter of a strength distribution is out of its range.
    #[error(
        "distribution parameter `{field}` = {value} is invalid: it must be finite and positive"
    )]
    InvalidDistribution {
        /// The parameter's name as written in the input (`modulus`, `scale`, `mean`, `cov`).
        field: &'static str,
        /// The value given.
        value: f64,
    },
    /// A distribution of a drawn joint material field is invalid.
    #[error("heterogeneity `{field}` = {value} is invalid: it must be finite and positive")]
    InvalidHeterogeneity {
        /// The path below the heterogeneity, e.g. `tensile_strength.weibull.modulus`.
        field: String,
        /// The value given.
        value: f64,
    },
    /// The fracture energy does not exceed the elastic work stored up to the peak, so no
    /// softening branch can dissipate it.
    #[error(
        "joint {joint} (material {material}, edge length h = {h:.4e} m): `{field}` = {g:.4e} J/m^2 is \
         not above the pre-peak work (2/3) f d_p = {w:.4e} J/m^2 (strength f = {f:.4e} Pa, peak \
         displacement d_p = 2 h f/p = {d_p:.4e} m); fix: raise `{penalty_field}` above {p_min:.4e} Pa, \
         or refine the mesh below h = {h_max:.4e} m, or raise `{field}`"
    )]
    FractureEnergyTooSmall {
        /// Joint index.
        joint: u32,
        /// Material index.
        material: u32,
        /// `fracture_energy_i` or `fracture_energy_ii`.
        field: &'static str,
        /// `penalty_normal` or `penalty_tangential`.
        penalty_field: &'static str,
        /// The reference edge length of the joint (m).
        h: f64,
        /// The fracture energy given (J/m^2).
        g: f64,
        /// The strength of that mode (Pa): ft, or the cohesion c for mode II.
        f: f64,
        /// The peak displacement (m).
        d_p: f64,
        /// The pre-peak work (2/3) f d_p (J/m^2).
        w: f64,
        /// The smallest penalty (Pa) that makes this joint valid.
        p_min: f64,
        /// The largest edge length (m) valid with this penalty.
        h_max: f64,
    },
    /// An initial (in-situ) traction at or above a joint's strength: the joint would start
    /// broken.
    #[error(
        "joint {joint} (material {material}): the initial stress gives it a {what} traction of \
         {traction:.4e} Pa, at or above its strength {strength:.4e} Pa, so it would start broken"
    )]
    InitialTractionTooHigh {
        /// Joint index.
        joint: u32,
        /// Material index.
        material: u32,
        /// `tensile` (normal, tension) or `shear`.
        what: &'static str,
        /// The traction's size (Pa): the normal tension, or `|tau0|`.
        traction: f64,
        /// The strength it reaches: `ft`, or `fs = c + <-sigma0> tan(phi)`.
        strength: f64,
    },
    /// An initial traction that is not finite, or given for another number of joints.
    #[error("initial tractions: {0}")]
    BadInitialTractions(String),
    /// A joint refers to a node that does not exist.
    #[error("joint {joint}: node id {node} is out of range (there are {n_nodes} nodes)")]
    NodeOutOfRange {
        /// Joint index.
        joint: u32,
        /// The node id given.
        node: u32,
        /// Number of nodes.
        n_nodes: usize,
    },
    /// A joint refers to a material that does not exist.
    #[error(
        "joint {joint}: material id {material} is out of range (there are {n_materials} joint materials)"
    )]
    MaterialOutOfRange {
        /// Joint index.
        joint: u32,
        /// The material id given.
        material: u32,
        /// Number of materials.
        n_materials: usize,
    },
    /// A joint's reference length is not a positive finite number.
    #[error(
        "joint {joint}: reference length h = {h} m must be finite and > 0 (a degenerate edge in the mesh)"
    )]
    BadLength {
        /// Joint index.
        joint: u32,
        /// The length given.
        h: f64,
    },
    /// The thickness is not a positive finite number.
    #[error("thickness = {0} m must be finite and > 0 (use 1 for plane strain)")]
    BadThickness(f64),
    /// A saved joint state ([`crate::JointStateSnapshot`]) that no run of this joint set can
    /// have reached (flags that disagree, a damage outside `[0, 1]`).
    #[error("saved joint state: {0}")]
    InvalidState(String),
    /// Two arrays that must have one entry per node or per joint differ in length.
    #[error("`{what}` has {got} entries, expected {expected}")]
    LengthMismatch {
        /// The array.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The length required.
        expected: usize,
    },
}

//! The joint materials of the `"fracture"` section: the unnamed `material` (of the regions
//! that name none), the named `materials`, each optionally with a `heterogeneity` (fields
//! drawn per joint from a distribution, `fdem_fracture::Heterogeneity`), and the
//! `interfaces` (the joints between two surface groups, with their own material).
//!
//! The materials are numbered in one list ([`material_list`]): the unnamed `material` first
//! (when given), then the named ones in name order; a joint's `material` in
//! `crate::stages::fracture` is an index into that list until the joint set is built.

use std::collections::BTreeMap;
use std::path::Path;

use fdem_fracture::{FractureError, Heterogeneity, JointMaterialInput};
use serde::{Deserialize, Serialize};

use crate::error::SceneError;

/// A joint material as the scene gives it (SI units): the fields of
/// [`JointMaterialInput`], of which `tensile_strength`, `cohesion`, `fracture_energy_i` and
/// `fracture_energy_ii` are either given as a value or drawn per joint by `heterogeneity`
/// (exactly one of the two).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct JointMaterialSpec {
    /// Tensile strength `ft` [Pa], > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tensile_strength: Option<f64>,
    /// Cohesion `c` [Pa], > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cohesion: Option<f64>,
    /// Internal friction angle [degrees], in [0, 90).
    pub friction_angle_deg: f64,
    /// Mode I fracture energy `G_I` [J/m^2], > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture_energy_i: Option<f64>,
    /// Mode II fracture energy `G_II` [J/m^2], > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture_energy_ii: Option<f64>,
    /// Normal joint penalty `p` [Pa], > 0.
    pub penalty_normal: f64,
    /// Tangential joint penalty `p_t` [Pa], > 0.
    pub penalty_tangential: f64,
    /// Fields drawn per joint (default none: every joint of the material has its values).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heterogeneity: Option<Heterogeneity>,
}

/// An interface: the joints with one triangle in `groups[0]` and the other in `groups[1]`
/// take `material`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Interface {
    /// Body name (needed when the scene has several bodies).
    #[serde(default)]
    pub body: Option<String>,
    /// The two surface groups the interface joins.
    pub groups: [String; 2],
    /// A key of `fracture.materials`.
    pub material: String,
}

/// One material of the list, with the JSON path of its entry.
#[derive(Debug, Clone, Copy)]
pub struct NamedMaterial<'a> {
    /// The key in `fracture.materials`, or `None` for `fracture.material`.
    pub name: Option<&'a str>,
    /// The material.
    pub spec: &'a JointMaterialSpec,
}

impl NamedMaterial<'_> {
    /// Its JSON path: `fracture.material` or `fracture.materials.NAME`.
    pub fn path(&self) -> String {
        match self.name {
            Some(n) => format!("fracture.materials.{n}"),
            None => "fracture.material".into(),
        }
    }
}

/// The materials in index order: `material` first (when given), then `materials` by name.
pub fn material_list<'a>(
    material: Option<&'a JointMaterialSpec>,
    materials: &'a BTreeMap<String, JointMaterialSpec>,
) -> Vec<NamedMaterial<'a>> {
    material
        .map(|spec| NamedMaterial { name: None, spec })
        .into_iter()
        .chain(materials.iter().map(|(n, spec)| NamedMaterial {
            name: Some(n.as_str()),
            spec,
        }))
        .collect()
}

impl JointMaterialSpec {
    /// The four fields that may be drawn: (name, value given, distribution).
    fn drawable(&self) -> [(&'static str, Option<f64>, bool); 4] {
        let h = self.heterogeneity.unwrap_or(Heterogeneity {
            seed: 0,
            tensile_strength: None,
            cohesion: None,
            fracture_energy_i: None,
            fracture_energy_ii: None,
        });
        let f = h.fields();
        [
            (f[0].0, self.tensile_strength, f[0].1.is_some()),
            (f[1].0, self.cohesion, f[1].1.is_some()),
            (f[2].0, self.fracture_energy_i, f[2].1.is_some()),
            (f[3].0, self.fracture_energy_ii, f[3].1.is_some()),
        ]
    }

    /// True when some field is drawn per joint.
    pub fn is_heterogeneous(&self) -> bool {
        self.heterogeneity.is_some()
    }

    /// The material with the given values; a drawn field is `fill` (the joint's draw
    /// replaces it, [`Self::row`]).
    fn base(&self, fill: f64) -> JointMaterialInput {
        JointMaterialInput {
            tensile_strength: self.tensile_strength.unwrap_or(fill),
            cohesion: self.cohesion.unwrap_or(fill),
            friction_angle_deg: self.friction_angle_deg,
            fracture_energy_i: self.fracture_energy_i.unwrap_or(fill),
            fracture_energy_ii: self.fracture_energy_ii.unwrap_or(fill),
            penalty_normal: self.penalty_normal,
            penalty_tangential: self.penalty_tangential,
        }
    }

    /// The material of the joint with global index `joint`: the given values, and the drawn
    /// ones from the heterogeneity's fields for that joint.
    pub fn row(&self, joint: u64) -> JointMaterialInput {
        match &self.heterogeneity {
            Some(h) => h.draw(&self.base(f64::NAN), joint),
            None => self.base(f64::NAN),
        }
    }

    /// Checks the material at `path`: every field in its range, each of the four drawable
    /// fields either given or drawn, and the distributions valid (the error names the field).
    pub fn validate(&self, file: &Path, path: &str) -> Result<(), SceneError> {
        for (field, value, drawn) in self.drawable() {
            match (value, drawn) {
                (Some(_), true) => {
                    return Err(SceneError::invalid(
                        file,
                        format!("{path}.{field}"),
                        format!(
                            "`{field}` is given a value and also drawn by {path}.heterogeneity.{field}"
                        ),
                        format!("remove {path}.{field} or {path}.heterogeneity.{field}"),
                    ));
                }
                (None, false) => {
                    return Err(SceneError::invalid(
                        file,
                        path,
                        format!("missing field `{field}`"),
                        format!(
                            "add \"{field}\": <value>, or draw it per joint under {path}.heterogeneity.{field}"
                        ),
                    ));
                }
                _ => {}
            }
        }
        if let Some(h) = &self.heterogeneity {
            if h.is_empty() {
                return Err(SceneError::invalid(
                    file,
                    format!("{path}.heterogeneity"),
                    "the heterogeneity draws no field",
                    "draw at least one of tensile_strength, cohesion, fracture_energy_i, \
                     fracture_energy_ii, or remove the heterogeneity",
                ));
            }
            h.validate().map_err(|e| {
                let sub = match &e {
                    FractureError::InvalidHeterogeneity { field, .. } => format!(".{field}"),
                    _ => String::new(),
                };
                SceneError::invalid(
                    file,
                    format!("{path}.heterogeneity{sub}"),
                    e.to_string(),
                    "give every parameter of the distribution a positive value",
                )
            })?;
        }
        // the given fields in their ranges (a drawn field is positive by construction)
        self.base(1.0).validate(0).map_err(|e| {
            let field = match &e {
                FractureError::InvalidMaterial { field, .. } => format!(".{field}"),
                _ => String::new(),
            };
            SceneError::invalid(
                file,
                format!("{path}{field}"),
                e.to_string(),
                "correct the value as described",
            )
        })?;
        Ok(())
    }
}

/// Checks the joint materials of a fracture section: at least one material, every region
/// that names none has `material`, every material valid.
pub fn validate(
    file: &Path,
    list: &[NamedMaterial<'_>],
    regions_without_material: Option<usize>,
) -> Result<(), SceneError> {
    if list.is_empty() {
        return Err(SceneError::invalid(
            file,
            "fracture",
            "the fracture section has no joint material",
            "add \"material\": {...} (the regions' material) or named \"materials\"",
        ));
    }
    if let Some(i) = regions_without_material
        && list[0].name.is_some()
    {
        let names: Vec<&str> = list.iter().filter_map(|m| m.name).collect();
        return Err(SceneError::invalid(
            file,
            format!("fracture.regions[{i}]"),
            "the region names no material and the section has no \"material\"",
            format!(
                "add \"material\": one of {} (the keys of fracture.materials)",
                names.join(", ")
            ),
        ));
    }
    for m in list {
        m.spec.validate(file, &m.path())?;
    }
    Ok(())
}

/// The largest penalty of the materials, as (JSON path of the field, value): the joints'
/// frequency bound is driven by it.
pub fn largest_penalty(list: &[NamedMaterial<'_>]) -> Option<(String, f64)> {
    let mut best: Option<(String, f64)> = None;
    for m in list {
        for (field, p) in [
            ("penalty_normal", m.spec.penalty_normal),
            ("penalty_tangential", m.spec.penalty_tangential),
        ] {
            if best.as_ref().is_none_or(|b| p > b.1) {
                best = Some((format!("{}.{field}", m.path()), p));
            }
        }
    }
    best
}

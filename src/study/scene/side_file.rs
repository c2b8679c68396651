//! The study file `SCENE.study.json` beside a scene: what the runs are measured against, and
//! the study's own settings.
//!
//! - `"reference"`: the answer the runs are measured against ([`Analytical`]; left out: the
//!   displacements against the reference run only):
//!   - `{"bar-arrival": {"probe", "length", "wave_speed", "particle_velocity"}}`: the free end
//!     of a bar under a pressure step moves at `2 v_p (t - L/c)` after arrival; a
//!     straight-line fit of the probe's displacement over `[1.25, 1.5] L/c` gives the arrival
//!     time; error `|t_arr - L/c| / (L/c)`;
//!   - `{"first-frequency": {"probe", "frequency"}}`: the first frequency from the upward
//!     crossings of the probe's displacement through its mean; error `|f - f_ref| / f_ref`;
//!   - `{"collision": {}}`: `K_end / K_0` (kinetic energy after separation over before),
//!     relative error against the reference run's; second, the momentum error
//!     `|P_end - P_0| / |P_0|` itself;
//!   - `{"fracture": {"wall", "radius"}}`: the peak of `|force_y[wall]|` (`walls.csv`),
//!     relative error against the reference run's; second, the crack path: mean `|x| / radius`
//!     of the broken joints (`fractures.csv`), absolute difference.
//! - `"set": {"/json/pointer": value, ...}`: changes to the scene for the study (a shorter or
//!   coarser version), written to `OUT/study-SCENE.json` ([`study_scene`]).
//! - `"fractions"` and `"schemes"`: defaults (the command line wins).
//! - `"probe_from": T` [s] or `"active"`: where the stability probes start
//!   ([`super::probes::ProbeStart`]).
//! - `"probe_amplitude"`: the probe field's largest displacement relative to the model size
//!   (default 1e-7; the fracture disc 1e-9, to keep the joints' pre-peak law linear over it).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

/// The analytical answer a scene may declare in `SCENE.study.json`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub(super) enum Analytical {
    /// Arrival of a pressure step at the free end of a bar.
    BarArrival {
        probe: String,
        length: f64,
        wave_speed: f64,
        particle_velocity: f64,
    },
    /// First natural frequency [Hz] seen at a probe.
    FirstFrequency { probe: String, frequency: f64 },
    /// A collision of free bodies: measure `K_end / K_0` (kinetic energy after separation
    /// over before), second measure `|P_end - P_0| / |P_0|` (momentum); no analytical value:
    /// the error is against the reference run's measure.
    Collision {},
    /// A fracturing specimen loaded by a wall: measure the peak of `|force_y[wall]|` in
    /// `walls.csv` [N], second measure the mean `|x| / radius` of the broken joints in
    /// `fractures.csv` (the crack path); errors against the reference run.
    Fracture { wall: String, radius: f64 },
}

impl Analytical {
    /// Whether the answer is analytical (else the measure is compared with the reference run).
    pub(super) fn is_analytical(&self) -> bool {
        matches!(self, Self::BarArrival { .. } | Self::FirstFrequency { .. })
    }
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SideFile {
    /// The answer the runs are measured against (default: the reference run's displacements).
    #[serde(default)]
    pub(super) reference: Option<Analytical>,
    /// Changes to the scene for the study, by JSON pointer (e.g. `"/duration": 2e-4`): a
    /// shorter or coarser version of the shipped scene, so that the study fits in minutes.
    #[serde(default)]
    pub(super) set: std::collections::BTreeMap<String, serde_json::Value>,
    /// Default fractions for this scene (the command line's `--fractions` wins).
    #[serde(default)]
    pub(super) fractions: Option<Vec<f64>>,
    /// Default schemes for this scene (the command line's `--schemes` wins).
    #[serde(default)]
    pub(super) schemes: Option<Vec<String>>,
    /// Start the stability probes from the scene's state at this time [s] (bodies in
    /// contact), or `"active"`: from the state where the bound run's engaged contact bound
    /// peaks, frozen there; not from the reference state: see
    /// [`ProbeStart`](super::probes::ProbeStart).
    #[serde(default)]
    pub(super) probe_from: Option<ProbeFrom>,
    /// Largest displacement of the probes' high-mode field, relative to the model size
    /// (default [`PROBE_AMPLITUDE`](super::probes::PROBE_AMPLITUDE)): small enough that the
    /// joints' and the contact's laws stay linear over it.
    #[serde(default)]
    pub(super) probe_amplitude: Option<f64>,
}

/// Where the stability probes start (side file `"probe_from"`).
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(untagged)]
pub(super) enum ProbeFrom {
    /// The scene's state at this time [s], walls held there, velocities kept.
    Time(f64),
    /// `"active"`: the state of the bound run's largest engaged contact bound, frozen.
    Named(ProbeFromName),
}

/// The named probe start.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum ProbeFromName {
    /// The state where the active contact bound peaks
    /// ([`Active::omega_contact_active_time`](super::active::Active::omega_contact_active_time)).
    Active,
}

/// Reads `SCENE.study.json` beside `scene`, if there is one.
pub(super) fn read(scene: &Path) -> Result<Option<SideFile>> {
    let p = scene.with_extension("study.json");
    if !p.exists() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&p).with_context(|| format!("reading {}", p.display()))?;
    let s: SideFile = serde_json::from_str(&text).map_err(|e| {
        crate::bad_input(format!(
            "{}: {}",
            p.display(),
            fdem_solver::shorten(&e.to_string())
        ))
    })?;
    Ok(Some(s))
}

/// The scene with the side file's `set` applied, written into `out` (mesh paths made
/// absolute); the scene itself when there is nothing to set.
pub(super) fn study_scene(scene: &Path, side: Option<&SideFile>, out: &Path) -> Result<PathBuf> {
    let Some(side) = side.filter(|s| !s.set.is_empty()) else {
        return Ok(scene.to_path_buf());
    };
    let text = std::fs::read_to_string(scene)
        .map_err(|e| crate::bad_input(format!("{}: cannot read the file: {e}", scene.display())))?;
    let mut v: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
        crate::bad_input(format!(
            "{}: {}",
            scene.display(),
            fdem_solver::shorten(&e.to_string())
        ))
    })?;
    let side_path = scene.with_extension("study.json");
    for (ptr, val) in &side.set {
        let slot = v.pointer_mut(ptr).ok_or_else(|| {
            crate::bad_input(format!(
                "{}: `set` names {}, which is not in {} (a JSON pointer to an existing field, e.g. /duration)",
                side_path.display(),
                fdem_solver::excerpt(ptr),
                scene.display()
            ))
        })?;
        *slot = val.clone();
    }
    let dir = scene.parent().unwrap_or(Path::new("."));
    let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    if let Some(bodies) = v.get_mut("bodies").and_then(|b| b.as_array_mut()) {
        for b in bodies {
            if let Some(m) = b.get("mesh").and_then(|m| m.as_str()) {
                let abs = dir.join(m).display().to_string();
                b["mesh"] = serde_json::Value::String(abs);
            }
        }
    }
    let name = scene
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| "scene.json".into());
    let p = out.join(format!("study-{name}"));
    crate::write_atomically(&p, serde_json::to_string_pretty(&v)?.as_bytes())?;
    Ok(p)
}

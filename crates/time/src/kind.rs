//! The schemes by name: what scene files and the command line select.

use std::fmt;
use std::str::FromStr;

/// One of the explicit schemes, with a stable lowercase name (used in scene files and on the
/// command line): `central-difference`, `pc3`, `pc4`, `pc5`, `chin`, `omf30`, `omf32`,
/// `forest-ruth`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SchemeKind {
    /// Central difference (kick-drift-kick), 1 force per step.
    CentralDifference,
    /// Gear predictor-corrector with `r_0..r_3`, 1 force per step.
    Pc3,
    /// Gear predictor-corrector with `r_0..r_4`, 1 force per step.
    Pc4,
    /// Gear predictor-corrector with `r_0..r_5`, 1 force per step.
    Pc5,
    /// Chin's force-gradient scheme, 2 forces + 1 gradient per step.
    Chin,
    /// Omelyan-Mryglod-Folk second-order scheme, 2 forces per step.
    Omf30,
    /// Omelyan-Mryglod-Folk fourth-order force-gradient scheme, 5 forces + 2 gradients.
    Omf32,
    /// Forest & Ruth fourth-order scheme, 3 forces per step.
    ForestRuth,
}

/// Force and gradient evaluations a scheme makes per step, in steady state (a force
/// evaluated at the end of one step and reused at the start of the next, "FSAL", counts once).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepCost {
    /// Force (acceleration) evaluations per step.
    pub forces: u32,
    /// Force-gradient products `G` per step.
    pub gradients: u32,
}

impl StepCost {
    /// Force evaluations per step counting each finite-difference gradient as two forces
    /// (`exact_gradient = false`) or as none (an exact product, `true`).
    pub fn force_equivalents(&self, exact_gradient: bool) -> u32 {
        self.forces
            + if exact_gradient {
                0
            } else {
                2 * self.gradients
            }
    }
}

/// An unknown scheme name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown time integration scheme `{name}`: valid names are {}",
    SchemeKind::valid_names()
)]
pub struct ParseSchemeError {
    /// The name that was given.
    pub name: String,
}

impl SchemeKind {
    /// Every scheme, in the order of the reference.
    pub const ALL: [SchemeKind; 8] = [
        SchemeKind::CentralDifference,
        SchemeKind::Pc3,
        SchemeKind::Pc4,
        SchemeKind::Pc5,
        SchemeKind::Chin,
        SchemeKind::Omf30,
        SchemeKind::Omf32,
        SchemeKind::ForestRuth,
    ];

    /// The stable lowercase name.
    pub fn name(self) -> &'static str {
        match self {
            SchemeKind::CentralDifference => "central-difference",
            SchemeKind::Pc3 => "pc3",
            SchemeKind::Pc4 => "pc4",
            SchemeKind::Pc5 => "pc5",
            SchemeKind::Chin => "chin",
            SchemeKind::Omf30 => "omf30",
            SchemeKind::Omf32 => "omf32",
            SchemeKind::ForestRuth => "forest-ruth",
        }
    }

    /// The valid names, comma separated (for error messages).
    pub fn valid_names() -> String {
        Self::ALL
            .iter()
            .map(|k| k.name())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Force and gradient evaluations per step, in steady state.
    pub fn cost(self) -> StepCost {
        let (forces, gradients) = match self {
            SchemeKind::CentralDifference | SchemeKind::Pc3 | SchemeKind::Pc4 | SchemeKind::Pc5 => {
                (1, 0)
            }
            SchemeKind::Chin => (2, 1),
            SchemeKind::Omf30 => (2, 0),
            SchemeKind::Omf32 => (5, 2),
            SchemeKind::ForestRuth => (3, 0),
        };
        StepCost { forces, gradients }
    }

    /// Whether the scheme is a symplectic splitting (bounded energy error on conservative
    /// systems). Gear PC is not.
    pub fn is_symplectic(self) -> bool {
        !matches!(self, SchemeKind::Pc3 | SchemeKind::Pc4 | SchemeKind::Pc5)
    }

    /// The global order of the position error on the oscillator, as measured by this
    /// crate's convergence tests (`tests/convergence.rs`), with the default start-up
    /// (Gear PC: 2, because its start-up sets `r_3..r_q` to zero; with exact derivatives
    /// PC-3 reaches 4 and PC-4, PC-5 reach 5).
    pub fn measured_order(self) -> u32 {
        match self {
            SchemeKind::CentralDifference | SchemeKind::Omf30 => 2,
            SchemeKind::Pc3 | SchemeKind::Pc4 | SchemeKind::Pc5 => 2,
            SchemeKind::Chin | SchemeKind::Omf32 | SchemeKind::ForestRuth => 4,
        }
    }
}

impl fmt::Display for SchemeKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SchemeKind {
    type Err = ParseSchemeError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| ParseSchemeError {
                name: s.to_string(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_list_the_valid_ones() {
        for k in SchemeKind::ALL {
            assert_eq!(k.name().parse::<SchemeKind>().unwrap(), k);
        }
        let e = "verlet".parse::<SchemeKind>().unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("`verlet`")
                && msg.contains("forest-ruth")
                && msg.contains("central-difference"),
            "{msg}"
        );
    }
}

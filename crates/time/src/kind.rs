//! The schemes by name: what scene files and the command line select.

use std::fmt;
use std::str::FromStr;
use std::sync::OnceLock;

use crate::{
    CentralDifference, Chin, ForestRuth, Integrator, Omf30, Omf32, Pc3, Pc4, Pc5, StepCost,
};

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

    /// A new integrator of this kind for `n` DOFs (buffers allocated once, here).
    pub fn build(self, n: usize) -> Box<dyn Integrator> {
        match self {
            SchemeKind::CentralDifference => Box::new(CentralDifference::new(n)),
            SchemeKind::Pc3 => Box::new(Pc3::new(n)),
            SchemeKind::Pc4 => Box::new(Pc4::new(n)),
            SchemeKind::Pc5 => Box::new(Pc5::new(n)),
            SchemeKind::Chin => Box::new(Chin::new(n)),
            SchemeKind::Omf30 => Box::new(Omf30::new(n)),
            SchemeKind::Omf32 => Box::new(Omf32::new(n)),
            SchemeKind::ForestRuth => Box::new(ForestRuth::new(n)),
        }
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

    /// The largest stable `h omega` on the undamped oscillator, computed from the spectral
    /// radius of the one-step operator ([`crate::stability::stability_limit`]); computed once
    /// per process and cached.
    pub fn stability_limit(self) -> f64 {
        static LIMITS: OnceLock<[f64; 8]> = OnceLock::new();
        let limits = LIMITS.get_or_init(|| Self::ALL.map(crate::stability::stability_limit));
        limits[Self::ALL.iter().position(|k| *k == self).expect("in ALL")]
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
            assert_eq!(k.build(3).kind(), k);
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

//! The integrators a scene may name (adapter over the time crate's schemes).

/// Names accepted in `integrator.scheme`.
pub const SCHEME_NAMES: [&str; 8] = [
    "central-difference",
    "pc3",
    "pc4",
    "pc5",
    "chin",
    "omf30",
    "omf32",
    "forest-ruth",
];

/// The scheme of this name, if it exists.
pub fn scheme_by_name(name: &str) -> Option<&'static str> {
    SCHEME_NAMES.iter().copied().find(|s| *s == name)
}

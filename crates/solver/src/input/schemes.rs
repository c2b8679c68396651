//! The integrators a scene may name (the time crate's schemes).

pub use fdem_time::SchemeKind;

/// The scheme of this name, if it exists.
pub fn scheme_by_name(name: &str) -> Option<SchemeKind> {
    name.parse().ok()
}

/// The accepted names, comma separated.
pub fn scheme_names() -> String {
    SchemeKind::valid_names()
}

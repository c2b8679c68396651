//! Explicit time integration for fdem.

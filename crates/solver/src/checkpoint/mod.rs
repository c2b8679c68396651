//! Checkpoints: the whole state of a dynamic or relaxation run in one binary file, from which
//! `fdem run --resume` continues bit for bit.

pub mod pack;

pub use pack::{Dec, DecodeError, Enc, Pack};

//! Per-scheme overhead on a 10^6-DOF chain: written next.
fn main() {}

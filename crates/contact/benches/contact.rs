//! Contact benchmarks (written below).
fn main() {}

//! Memory bandwidth (STREAM triad): written next.
fn main() {}

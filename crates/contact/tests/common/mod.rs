//! Shared helpers of the contact tests: a small deterministic random generator and random
//! triangles.
#![allow(dead_code)]

/// SplitMix64: deterministic, seedable.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
}

/// A random well-shaped CCW triangle about `c` with size `s`.
pub fn random_triangle(rng: &mut Rng, c: [f64; 2], s: f64) -> [[f64; 2]; 3] {
    let rot = rng.range(0.0, std::f64::consts::TAU);
    let mut x = [[0.0; 2]; 3];
    for k in 0..3 {
        let a = rot + k as f64 * std::f64::consts::TAU / 3.0 + rng.range(-0.5, 0.5);
        let r = s * rng.range(0.6, 1.0);
        x[k] = [c[0] + r * a.cos(), c[1] + r * a.sin()];
    }
    x
}

pub fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

pub fn area(x: &[[f64; 2]; 3]) -> f64 {
    0.5 * cross(
        [x[1][0] - x[0][0], x[1][1] - x[0][1]],
        [x[2][0] - x[0][0], x[2][1] - x[0][1]],
    )
}

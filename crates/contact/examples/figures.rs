//! Prints the validation figures of docs/contact.md for the pair kernel:
//! `cargo run --release -p fdem-contact --example figures`.

use fdem_contact::ContactLaw;
use fdem_contact::RigidPlane;
use fdem_contact::potential_tri_tri::{
    overlap_area, pair_energy, pair_force_area, pair_normal_force,
};

struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
    fn tri(&mut self, c: [f64; 2], s: f64) -> [[f64; 2]; 3] {
        let rot = self.range(0.0, std::f64::consts::TAU);
        let mut x = [[0.0; 2]; 3];
        for k in 0..3 {
            let a = rot + k as f64 * std::f64::consts::TAU / 3.0 + self.range(-0.5, 0.5);
            let r = s * self.range(0.6, 1.0);
            x[k] = [c[0] + r * a.cos(), c[1] + r * a.sin()];
        }
        x
    }
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn main() {
    let mut rng = Rng(2024);
    let (mut n, mut e_mom, mut e_ang, mut e_area, mut e_grad) = (0, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    while n < 10_000 {
        let (s1, s2) = (rng.range(0.3, 2.0), rng.range(0.3, 2.0));
        let c = rng.tri([0.0, 0.0], s1);
        let d = rng.range(0.0, 1.2) * (s1 + s2);
        let a = rng.range(0.0, std::f64::consts::TAU);
        let t = rng.tri([d * a.cos(), d * a.sin()], s2);
        if overlap_area(&c, &t) < 1e-3 * s1 * s2 {
            continue;
        }
        n += 1;
        let f = pair_normal_force(&c, &t, 1.0);
        let x = [c[0], c[1], c[2], t[0], t[1], t[2]];
        let fmax = f.iter().map(|g| g[0].hypot(g[1])).fold(0.0, f64::max);
        let xmax = x.iter().map(|g| g[0].hypot(g[1])).fold(0.0, f64::max);
        let s = f.iter().fold([0.0; 2], |s, g| [s[0] + g[0], s[1] + g[1]]);
        let m: f64 = (0..6).map(|k| cross(x[k], f[k])).sum();
        e_mom = e_mom.max(s[0].hypot(s[1]) / fmax);
        e_ang = e_ang.max(m.abs() / (fmax * xmax));
        let fc = [f[0][0] + f[1][0] + f[2][0], f[0][1] + f[1][1] + f[2][1]];
        let fa = pair_force_area(&c, &t, 1.0);
        e_area = e_area.max((fc[0] - fa[0]).hypot(fc[1] - fa[1]) / fmax);
        if n <= 1000 {
            let h = 1e-6;
            let w = |dx: f64| pair_energy(&c.map(|p| [p[0] + dx, p[1]]), &t, 1.0);
            let g = -(w(h) - w(-h)) / (2.0 * h);
            e_grad = e_grad.max((g - fc[0]).abs() / fmax);
        }
    }
    println!("random overlapping pairs: {n}");
    println!("  max |sum f| / max|f|                 = {e_mom:.2e}");
    println!("  max |sum x×f| / (max|f| max|x|)      = {e_ang:.2e}");
    println!("  max |f_edge - f_area| / max|f|       = {e_area:.2e}");
    println!("  max |f_x + dW/dx| / max|f| (h=1e-6)  = {e_grad:.2e} (first 1000 pairs)");
    println!(
        "flat overlap (H_c = 1 + d, H_t = 1.5, L = 1): relative error of 3 p d (1/H_c + 1/H_t) L"
    );
    for d in [1e-2, 1e-3, 1e-4, 1e-5] {
        let t = [[-1.0, 0.0], [0.0, -1.5], [1.0, 0.0]];
        let c = [[-0.5, -d], [0.5, -d], [0.0, 1.0]];
        let f = pair_normal_force(&c, &t, 1.0);
        let fy = f[0][1] + f[1][1] + f[2][1];
        let ex = 3.0 * d * (1.0 / (1.0 + d) + 1.0 / 1.5);
        let plane = RigidPlane::new([0.0, 0.0], [0.0, 1.0], ContactLaw::with_penalty(1.0));
        let fp = plane.normal_force(&c);
        let fpy = fp[0][1] + fp[1][1] + fp[2][1];
        let exp = 3.0 * d / (1.0 + d);
        println!(
            "  d = {d:.0e}: pair {:+.3e}, plane (3 p d/H_c) {:+.3e}",
            fy / ex - 1.0,
            fpy / exp - 1.0
        );
    }
}

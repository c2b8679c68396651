//! Two rigid squares (two triangles each) in a head-on collision, integrated as rigid bodies
//! (symplectic Euler) under the crate's contact forces alone: momentum to round-off, kinetic
//! energy restored after separation (the pair energy is an exact potential for rigid relative
//! motion), small overlap at the default penalty, and the check point at extreme speeds.

use fdem_contact::{Contact, ContactError, ContactLaw, ContactLaws, ContactSettings};

const L: f64 = 1.0;
const RHO: f64 = 2700.0;
const E: f64 = 30.0e9;

struct Bodies {
    x: Vec<[f64; 2]>,
    v: Vec<[f64; 2]>,
    tris: Vec<[u32; 3]>,
    vc: Vec<[f64; 2]>,
    omega: Vec<f64>,
}

impl Bodies {
    fn two_squares(gap: f64, speed: f64, offset_y: f64) -> Self {
        let mut x = Vec::new();
        let mut tris = Vec::new();
        for (b, (x0, y0)) in [(-L - gap / 2.0, 0.0), (gap / 2.0, offset_y)]
            .iter()
            .enumerate()
        {
            let base = 4 * b as u32;
            x.extend_from_slice(&[[*x0, *y0], [x0 + L, *y0], [x0 + L, y0 + L], [*x0, y0 + L]]);
            tris.push([base, base + 1, base + 2]);
            tris.push([base, base + 2, base + 3]);
        }
        let vc = vec![[speed, 0.0], [-speed, 0.0]];
        let v = (0..8).map(|i| vc[i / 4]).collect();
        Bodies {
            x,
            v,
            tris,
            vc,
            omega: vec![0.0; 2],
        }
    }

    fn mass() -> f64 {
        RHO * L * L
    }

    fn centre(&self, b: usize) -> [f64; 2] {
        let s = self.x[4 * b..4 * b + 4]
            .iter()
            .fold([0.0; 2], |a, p| [a[0] + p[0], a[1] + p[1]]);
        [s[0] / 4.0, s[1] / 4.0]
    }

    fn kinetic(&self) -> f64 {
        let m = Self::mass();
        let i = m * L * L / 6.0;
        (0..2)
            .map(|b| {
                0.5 * m * (self.vc[b][0].powi(2) + self.vc[b][1].powi(2))
                    + 0.5 * i * self.omega[b].powi(2)
            })
            .sum()
    }

    fn momentum(&self) -> [f64; 2] {
        let m = Self::mass();
        [
            m * (self.vc[0][0] + self.vc[1][0]),
            m * (self.vc[0][1] + self.vc[1][1]),
        ]
    }

    fn step(&mut self, c: &mut Contact, dt: f64) -> Result<f64, ContactError> {
        c.update_detection(&self.x, &self.tris);
        let stats = c.compute_forces(&self.x, &self.v, &self.tris, &[], dt);
        stats.check(c.settings.max_phi)?;
        let mut f = vec![[0.0; 2]; 8];
        c.add_forces(&self.tris, &mut f);
        let m = Self::mass();
        let inertia = m * L * L / 6.0;
        for b in 0..2 {
            let xc = self.centre(b);
            let (mut fr, mut tq) = ([0.0; 2], 0.0);
            for i in 4 * b..4 * b + 4 {
                fr = [fr[0] + f[i][0], fr[1] + f[i][1]];
                tq += (self.x[i][0] - xc[0]) * f[i][1] - (self.x[i][1] - xc[1]) * f[i][0];
            }
            self.vc[b] = [
                self.vc[b][0] + dt * fr[0] / m,
                self.vc[b][1] + dt * fr[1] / m,
            ];
            self.omega[b] += dt * tq / inertia;
            let (s, co) = (self.omega[b] * dt).sin_cos();
            let xn = [xc[0] + dt * self.vc[b][0], xc[1] + dt * self.vc[b][1]];
            for i in 4 * b..4 * b + 4 {
                let r = [self.x[i][0] - xc[0], self.x[i][1] - xc[1]];
                let r = [co * r[0] - s * r[1], s * r[0] + co * r[1]];
                self.x[i] = [xn[0] + r[0], xn[1] + r[1]];
                self.v[i] = [
                    self.vc[b][0] - self.omega[b] * r[1],
                    self.vc[b][1] + self.omega[b] * r[0],
                ];
            }
        }
        c.commit();
        Ok(self.x[1][0].max(self.x[2][0]) - self.x[4][0].min(self.x[7][0]))
    }
}

/// Stable step of the contact spring between the two rigid bodies: k = 3 p L (1/H + 1/H) per
/// unit thickness (flat overlap, H = L), reduced mass m/2.
fn dt_crit(p: f64) -> f64 {
    let k = 6.0 * p * L / L;
    2.0 / (k / (Bodies::mass() / 2.0)).sqrt()
}

#[test]
fn head_on_collision_conserves_momentum_and_restores_kinetic_energy() {
    // Default penalty 10 E; dt = 0.1 dt_crit; v = 10 m/s each. Momentum to 1e-12 of m v
    // (round-off), kinetic energy after separation within 0.5 % (O((omega dt)^2) of the
    // symplectic step), largest overlap below 1 % of L.
    let law = ContactLaw::from_young(E, 0.0);
    let mut c = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
    let speed = 10.0;
    let mut b = Bodies::two_squares(0.01, speed, 0.3);
    let k0 = b.kinetic();
    let dt = 0.1 * dt_crit(law.penalty);
    let mut max_overlap: f64 = 0.0;
    let mut touched = false;
    for _ in 0..20000 {
        let ov = b.step(&mut c, dt).unwrap();
        max_overlap = max_overlap.max(ov);
        let pm = b.momentum();
        assert!(
            pm[0].abs() < 1e-12 * Bodies::mass() * speed
                && pm[1].abs() < 1e-12 * Bodies::mass() * speed,
            "{pm:?}"
        );
        touched |= ov > 0.0;
        if touched && ov < -0.01 {
            break;
        }
    }
    assert!(touched);
    let k1 = b.kinetic();
    eprintln!(
        "collision: dK/K = {:.3e}, max overlap / L = {:.3e}",
        (k1 - k0) / k0,
        max_overlap / L
    );
    assert!(((k1 - k0) / k0).abs() < 5e-3, "K before {k0}, after {k1}");
    assert!(max_overlap < 0.01 * L, "overlap {max_overlap}");
    assert!(
        b.vc[0][0] < 0.0 && b.vc[1][0] > 0.0,
        "bodies did not rebound"
    );
}

#[test]
fn collision_near_the_stability_limit_stops_with_a_clear_message_or_stays_finite() {
    // dt = 0.9 dt_crit and an impact speed that would push the overlap to about H/3: the check
    // point (phi > 0.5) must fire with its message; at no point a NaN.
    let law = ContactLaw::with_penalty(1.0e9);
    for (speed, dt_frac) in [(50.0, 0.9), (500.0, 0.9), (500.0, 1.5)] {
        let mut c = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
        let mut b = Bodies::two_squares(0.001, speed, 0.0);
        let dt = dt_frac * dt_crit(law.penalty);
        let mut outcome = None;
        for _ in 0..2000 {
            match b.step(&mut c, dt) {
                Ok(_) => assert!(b.x.iter().all(|p| p[0].is_finite() && p[1].is_finite())),
                Err(e) => {
                    outcome = Some(e);
                    break;
                }
            }
        }
        eprintln!("speed {speed}, dt/dt_crit {dt_frac}: {outcome:?}");
        if speed >= 500.0 {
            let e = outcome.expect("a 500 m/s impact at p = 1 GPa must trip the check point");
            assert!(e.to_string().contains("time step is too large"), "{e}");
        }
    }
}

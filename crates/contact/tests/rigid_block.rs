//! A rigid square block (two triangles) on a floor: a rigid plane or a fixed ground triangle.
//! The block moves as a rigid body (3 DOF, symplectic Euler) under gravity and the contact
//! forces of the crate, so these tests check the contact laws alone: the floor carries the
//! weight at the predicted penetration, the block slides down an incline with
//! `a = g (sin θ - mu cos θ)` or sticks, friction history and dissipation behave.

use fdem_contact::{Contact, ContactEnergy, ContactLaw, ContactLaws, ContactSettings, RigidPlane};

const L: f64 = 1.0; // block side [m]
const RHO: f64 = 1000.0; // [kg/m^3] (per unit thickness)
const G: f64 = 9.81;
const P: f64 = 1.0e8; // penalty [Pa]

struct Block {
    x: Vec<[f64; 2]>,
    v: Vec<[f64; 2]>,
    tris: Vec<[u32; 3]>,
    /// Nodes of the block (the rest are fixed ground nodes).
    n_block: usize,
    vc: [f64; 2],
    omega: f64,
}

impl Block {
    /// Block with its bottom at y = y0 (node 0 at x = x0), plus fixed extra nodes/triangles.
    fn new(x0: f64, y0: f64, ground_x: &[[f64; 2]], ground_tris: &[[u32; 3]]) -> Self {
        let mut x = vec![[x0, y0], [x0 + L, y0], [x0 + L, y0 + L], [x0, y0 + L]];
        let mut tris = vec![[0, 1, 2], [0, 2, 3]];
        x.extend_from_slice(ground_x);
        tris.extend(ground_tris.iter().map(|t| t.map(|n| n + 4)));
        let v = vec![[0.0; 2]; x.len()];
        Block {
            x,
            v,
            tris,
            n_block: 4,
            vc: [0.0; 2],
            omega: 0.0,
        }
    }

    fn centre(&self) -> [f64; 2] {
        let n = self.n_block as f64;
        let s = self.x[..self.n_block]
            .iter()
            .fold([0.0; 2], |a, p| [a[0] + p[0], a[1] + p[1]]);
        [s[0] / n, s[1] / n]
    }

    /// One step: contact forces at (x, v), then symplectic Euler of the rigid body.
    fn step(&mut self, c: &mut Contact, gravity: [f64; 2], dt: f64) {
        c.update_detection(&self.x, &self.tris);
        let stats = c.compute_forces(&self.x, &self.v, &self.tris, &[], dt);
        stats.check(0.5).unwrap();
        let mut f = vec![[0.0; 2]; self.x.len()];
        c.add_forces(&self.tris, &mut f);
        let m = RHO * L * L;
        let inertia = m * L * L / 6.0;
        let xc = self.centre();
        let mut fr = [m * gravity[0], m * gravity[1]];
        let mut tq = 0.0;
        for i in 0..self.n_block {
            fr[0] += f[i][0];
            fr[1] += f[i][1];
            tq += (self.x[i][0] - xc[0]) * f[i][1] - (self.x[i][1] - xc[1]) * f[i][0];
        }
        self.vc = [self.vc[0] + dt * fr[0] / m, self.vc[1] + dt * fr[1] / m];
        self.omega += dt * tq / inertia;
        let th = self.omega * dt;
        let (s, co) = th.sin_cos();
        let xn = [xc[0] + dt * self.vc[0], xc[1] + dt * self.vc[1]];
        for i in 0..self.n_block {
            let r = [self.x[i][0] - xc[0], self.x[i][1] - xc[1]];
            let r = [co * r[0] - s * r[1], s * r[0] + co * r[1]];
            self.x[i] = [xn[0] + r[0], xn[1] + r[1]];
            self.v[i] = [
                self.vc[0] - self.omega * r[1],
                self.vc[1] + self.omega * r[0],
            ];
        }
        c.commit();
    }
}

fn law(mu: f64) -> ContactLaw {
    let m = RHO * L * L;
    let k = 3.0 * P * L / L; // bottom edge: 3 p L / H (H = L for the bottom triangle)
    ContactLaw {
        mu,
        // Damping of the normal block mode at ratio 0.5: c L = 2 * 0.5 * sqrt(k m).
        damping: (k * m).sqrt() / L,
        ..ContactLaw::with_penalty(P)
    }
}

fn dt() -> f64 {
    let k = 3.0 * P;
    0.05 / (k / (RHO * L * L)).sqrt()
}

#[test]
fn block_on_rigid_floor_carries_its_weight_at_the_predicted_depth() {
    // Reaction = m g to 1e-6 at rest; depth d = m g H / (3 p L) (flat-overlap stiffness with
    // 1/H_wall = 0) to 1 %.
    let mut c = Contact::new(
        ContactSettings::default(),
        ContactLaws::uniform(1, ContactLaw::disabled()),
    );
    c.walls
        .push(RigidPlane::new([0.0, 0.0], [0.0, 1.0], law(0.0)));
    let mut b = Block::new(0.0, 0.0, &[], &[]);
    for _ in 0..4000 {
        b.step(&mut c, [0.0, -G], dt());
    }
    let mut r = [[0.0; 2]];
    c.wall_reactions(&mut r);
    let w = RHO * L * L * G;
    assert!(
        (-r[0][1] - w).abs() < 1e-6 * w,
        "reaction {:?} weight {w}",
        r[0]
    );
    assert!(r[0][0].abs() < 1e-9 * w);
    let depth = -(b.x[0][1] + b.x[1][1]) / 2.0;
    let expect = w * L / (3.0 * P * L);
    assert!(
        (depth - expect).abs() < 0.01 * expect,
        "depth {depth} vs {expect}"
    );
}

/// Slides the block down an incline (gravity tilted by theta) for `t_end` and returns
/// (acceleration along the slope measured after 0.2 s, contact).
fn incline(theta: f64, mu: f64, ground: bool, t_end: f64) -> (f64, f64, ContactEnergy) {
    let laws = ContactLaws::uniform(1, law(mu));
    let mut c = Contact::new(ContactSettings::default(), laws);
    let m = RHO * L * L;
    let (ground_x, ground_tris): (Vec<[f64; 2]>, Vec<[u32; 3]>) = if ground {
        (
            vec![[-20.0, 0.0], [0.0, -20.0], [20.0, 0.0]],
            vec![[0, 1, 2]],
        )
    } else {
        c.walls
            .push(RigidPlane::new([0.0, 0.0], [0.0, 1.0], law(mu)));
        (vec![], vec![])
    };
    // Start at the static depth of the normal load to avoid a bounce.
    let hinv = if ground {
        1.0 / L + 1.0 / 20.0
    } else {
        1.0 / L
    };
    let d0 = m * G * theta.cos() / (3.0 * P * L * hinv);
    let mut b = Block::new(0.0, -d0, &ground_x, &ground_tris);
    let gravity = [-G * theta.sin(), -G * theta.cos()];
    let dt = dt();
    let n = (t_end / dt) as usize;
    let n0 = (0.2 / dt) as usize;
    let (mut x_a, mut v_a) = (0.0, 0.0);
    for k in 0..n {
        if k == n0 {
            x_a = b.centre()[0];
            v_a = b.vc[0];
        }
        b.step(&mut c, gravity, dt);
    }
    let t = (n - n0) as f64 * dt;
    let a = -(b.vc[0] - v_a) / t;
    let creep = (b.centre()[0] - x_a).abs();
    (a, creep, c.energy(&b.x, &b.tris, &[]))
}

#[test]
fn block_slides_down_incline_with_coulomb_acceleration_on_plane_and_on_ground_triangle() {
    // a = g (sin θ - mu cos θ) within 1 %; friction dissipation ≈ mu N × slip (1 %).
    let theta = 0.5f64; // tan θ = 0.546
    let mu = 0.3;
    let expect = G * (theta.sin() - mu * theta.cos());
    let mut figures = Vec::new();
    for ground in [false, true] {
        let (a, _, e) = incline(theta, mu, ground, 1.0);
        eprintln!(
            "ground={ground}: a = {a:.5} ({:+.2e}), slip dissipation {:.1} J/m",
            a / expect - 1.0,
            e.friction_dissipated
        );
        assert!(
            ((a - expect) / expect).abs() < 0.01,
            "ground={ground}: a = {a}, expected {expect}"
        );
        // From rest, slip s = a t^2 / 2 over 1 s (after a tiny stick transient).
        let n = RHO * L * L * G * theta.cos();
        let d = mu * n * 0.5 * expect;
        assert!(
            ((e.friction_dissipated - d) / d).abs() < 0.02,
            "ground={ground}: D = {} vs {d}",
            e.friction_dissipated
        );
        figures.push(format!("{:+.1e}", a / expect - 1.0));
    }
    fdem_figures::record(30, figures.join(", "));
}

#[test]
fn block_sticks_on_incline_when_mu_exceeds_tan_theta() {
    // mu = 0.7 > tan(0.5) = 0.546: the block stays. Creep over 1 s below 2 elastic slip
    // lengths m g sin θ / (2 k_t) (two sides share the load on the ground triangle; one edge on
    // the plane), i.e. below 1e-4 m here.
    let theta = 0.5f64;
    for ground in [false, true] {
        let (_, creep, _) = incline(theta, 0.7, ground, 1.0);
        let elastic = RHO * L * L * G * theta.sin() / P;
        eprintln!("ground={ground}: creep {creep:.3e} m, elastic slip {elastic:.3e} m");
        assert!(
            creep < 2.0 * elastic,
            "ground={ground}: creep {creep} vs elastic slip {elastic}"
        );
    }
}

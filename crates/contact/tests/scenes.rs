//! Whole scenes with deformable meshes (fdem-mesh) integrated by the central difference
//! scheme of fdem-time, with the contact crate wired as the solver will: contact forces in
//! `acceleration` (trial-safe), `commit` in `end_of_step`.

use fdem_contact::{Contact, ContactLaw, ContactLaws, ContactSettings, RigidPlane};
use fdem_mesh::{Elements, ForceScratch, Material, Mesh};
use fdem_time::{CentralDifference, Integrator, SecondOrderSystem, State};

/// A disc of radius `n h` meshed by concentric rings of spacing `h` (6k nodes on ring k),
/// centred at `c`, rotated by `rot`. Returns nodes and CCW triangles.
fn disc(c: [f64; 2], n: usize, h: f64, rot: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut x = vec![c];
    let mut start = vec![0usize];
    for k in 1..=n {
        start.push(x.len());
        for j in 0..6 * k {
            let a = rot + std::f64::consts::TAU * j as f64 / (6 * k) as f64;
            x.push([c[0] + k as f64 * h * a.cos(), c[1] + k as f64 * h * a.sin()]);
        }
    }
    let mut t = Vec::new();
    for k in 1..=n {
        let outer = |j: usize| (start[k] + j % (6 * k)) as u32;
        if k == 1 {
            for j in 0..6 {
                t.push([0, outer(j), outer(j + 1)]);
            }
            continue;
        }
        let n_in = 6 * (k - 1);
        let n_out = 6 * k;
        let inner = |i: usize| (start[k - 1] + i % n_in) as u32;
        let (mut i, mut j) = (0usize, 0usize);
        while i < n_in || j < n_out {
            let a_next = (i + 1) as f64 / n_in as f64;
            let b_next = (j + 1) as f64 / n_out as f64;
            if j < n_out && (i == n_in || b_next <= a_next) {
                t.push([inner(i), outer(j), outer(j + 1)]);
                j += 1;
            } else {
                t.push([inner(i), outer(j), inner(i + 1)]);
                i += 1;
            }
        }
    }
    (x, t)
}

/// A rectangle `w x hgt` of `nx x ny` cells, each split into two triangles, lower-left at
/// the origin.
fn rectangle(w: f64, hgt: f64, nx: usize, ny: usize) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut x = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            x.push([w * i as f64 / nx as f64, hgt * j as f64 / ny as f64]);
        }
    }
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut t = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                t.push([a, b, c]);
                t.push([a, c, d]);
            } else {
                t.push([a, b, d]);
                t.push([b, c, d]);
            }
        }
    }
    (x, t)
}

struct Scene {
    el: Elements,
    scratch: ForceScratch,
    inv_m: Vec<f64>,
    mass: Vec<f64>,
    contact: Contact,
    tris: Vec<[u32; 3]>,
    f: Vec<[f64; 2]>,
    gravity: [f64; 2],
    /// Mass-proportional damping `alpha` [1/s]: `f -= alpha m v`.
    alpha: f64,
    dt: f64,
    max_phi: f64,
}

impl Scene {
    fn new(
        nodes: Vec<[f64; 2]>,
        tris: Vec<[u32; 3]>,
        mat: Material,
        contact: Contact,
        dt: f64,
    ) -> Self {
        let mesh = Mesh::from_nodes_triangles(nodes, tris).unwrap();
        let el = Elements::new(&mesh, &[mat]).unwrap();
        let mass = el.lumped_masses();
        let inv_m = mass.iter().flat_map(|m| [1.0 / m, 1.0 / m]).collect();
        let scratch = ForceScratch::new(&el);
        let n = mesh.n_nodes();
        Scene {
            el,
            scratch,
            inv_m,
            mass,
            contact,
            tris: mesh.triangles.clone(),
            f: vec![[0.0; 2]; n],
            gravity: [0.0; 2],
            alpha: 0.0,
            dt,
            max_phi: 0.0,
        }
    }

    fn momentum(&self, v: &[f64]) -> [f64; 2] {
        let v = v.as_chunks::<2>().0;
        self.mass
            .iter()
            .zip(v)
            .fold([0.0; 2], |p, (m, v)| [p[0] + m * v[0], p[1] + m * v[1]])
    }
}

impl SecondOrderSystem for Scene {
    fn n_dofs(&self) -> usize {
        2 * self.mass.len()
    }
    fn inv_mass(&self) -> &[f64] {
        &self.inv_m
    }
    fn acceleration(&mut self, _t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        let xn = x.as_chunks::<2>().0;
        let vn = v.as_chunks::<2>().0;
        self.f.iter_mut().for_each(|g| *g = [0.0; 2]);
        self.el
            .internal_forces(xn, vn, &mut self.f, &mut self.scratch);
        self.contact.update_detection(xn, &self.tris);
        let s = self
            .contact
            .compute_forces(xn, vn, &self.tris, &[], self.dt);
        s.check(self.contact.settings.max_phi).unwrap();
        self.max_phi = self.max_phi.max(s.max_phi);
        self.contact.add_forces(&self.tris, &mut self.f);
        for (i, g) in self.f.iter().enumerate() {
            a[2 * i] = g[0] * self.inv_m[2 * i] + self.gravity[0] - self.alpha * v[2 * i];
            a[2 * i + 1] =
                g[1] * self.inv_m[2 * i + 1] + self.gravity[1] - self.alpha * v[2 * i + 1];
        }
    }
    fn end_of_step(&mut self, _t: f64, _x: &[f64], _v: &[f64]) {
        self.contact.commit();
    }
}

/// Stable step estimate: contact `omega h_min = 3.5 sqrt(p/rho)` (fdem-theory.md 6.3) and
/// the element bound `3 c_p / h_min`; safety 0.5.
fn stable_dt(h_min: f64, p: f64, mat: &Material) -> f64 {
    let w = (3.5 * (p / mat.density).sqrt()).max(3.0 * mat.p_wave_speed()) / h_min;
    0.5 * 2.0 / w
}

/// Outcome of a head-on collision of two identical discs.
struct Collision {
    max_overlap_over_h: f64,
    /// Kinetic energy after separation over before, minus 1.
    dk: f64,
    /// Kinetic + strain energy after separation over the initial kinetic energy, minus 1.
    de: f64,
    rebound: f64,
    max_momentum: f64,
    max_phi: f64,
    dt: f64,
}

/// Two discs R = n h, E = 10 GPa, nu = 0.25, rho = 2500, plane strain, `speed` each, disc B
/// rotated by `rot_b`, default penalty p = 10 E, no damping.
fn collide(n: usize, h: f64, speed: f64, rot_b: f64) -> Collision {
    let r = n as f64 * h;
    let gap = 1e-4;
    let (mut x, mut t) = disc([-r - gap / 2.0, 0.0], n, h, 0.0);
    let (xb, tb) = disc([r + gap / 2.0, 0.0], n, h, rot_b);
    let n_a = x.len();
    t.extend(tb.iter().map(|tr| tr.map(|k| k + n_a as u32)));
    x.extend_from_slice(&xb);
    let mat = Material::new(10e9, 0.25, 2500.0);
    let law = ContactLaw::from_young(mat.youngs_modulus, 0.0);
    let contact = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
    let h_min = 0.5 * h; // smallest altitude of the ring triangles is above h/2
    let dt = stable_dt(h_min, law.penalty, &mat);
    let mut scene = Scene::new(x.clone(), t, mat, contact, dt);
    let v0: Vec<f64> = (0..x.len())
        .flat_map(|i| if i < n_a { [speed, 0.0] } else { [-speed, 0.0] })
        .collect();
    let mut state = State::new(0.0, x.as_flattened().to_vec(), v0);
    let k0 = scene.kinetic_energy(&state.v);
    let m_total: f64 = scene.mass.iter().sum();
    let mut cd = CentralDifference::new(state.n_dofs());
    let (mut max_overlap, mut touched, mut separated_at) = (0.0f64, false, None);
    let mut max_momentum = 0.0f64;
    for step in 0..40000 {
        cd.step(&mut scene, &mut state, dt);
        let xn = state.x_nodes();
        let right_a = xn[..n_a].iter().map(|p| p[0]).fold(f64::MIN, f64::max);
        let left_b = xn[n_a..].iter().map(|p| p[0]).fold(f64::MAX, f64::min);
        let ov = right_a - left_b;
        max_overlap = max_overlap.max(ov);
        touched |= ov > 0.0;
        let p = scene.momentum(&state.v);
        max_momentum = max_momentum.max(p[0].abs().max(p[1].abs()) / (m_total * speed));
        if touched && ov < -0.2 * h && separated_at.is_none() {
            separated_at = Some(step);
        }
        if separated_at.is_some_and(|s| step > s + 200) {
            break;
        }
    }
    assert!(separated_at.is_some(), "discs did not separate");
    let k1 = scene.kinetic_energy(&state.v);
    let u1 = scene.el.strain_energy(state.x_nodes());
    let va: f64 = (0..n_a)
        .map(|i| scene.mass[i] * state.v[2 * i])
        .sum::<f64>()
        / scene.mass[..n_a].iter().sum::<f64>();
    Collision {
        max_overlap_over_h: max_overlap / h,
        dk: k1 / k0 - 1.0,
        de: (k1 + u1) / k0 - 1.0,
        rebound: -va / speed,
        max_momentum,
        max_phi: scene.max_phi,
        dt,
    }
}

#[test]
fn elastic_discs_head_on_momentum_overlap_and_kinetic_energy() {
    // R = 0.05 m with 20 rings (h = 2.5 mm), 5 m/s each, p = 10 E, no damping. Asserted:
    // momentum to 1e-12 of M v (round-off), max overlap < 1 % of h, kinetic energy after
    // separation within 2 % of before (the rest is vibration: kinetic + strain energy is
    // conserved to 1e-3, measured 3e-5).
    let c = collide(20, 0.0025, 5.0, 0.0);
    eprintln!(
        "discs: dt = {:.3e}, max overlap/h = {:.3e}, K1/K0 - 1 = {:.3e}, (K1 + U1)/K0 - 1 = {:.3e}, rebound v/v0 = {:.4}, max phi = {:.3e}",
        c.dt, c.max_overlap_over_h, c.dk, c.de, c.rebound, c.max_phi
    );
    assert!(c.max_momentum < 1e-12, "momentum {}", c.max_momentum);
    assert!(
        c.max_overlap_over_h < 0.01,
        "overlap/h {}",
        c.max_overlap_over_h
    );
    assert!(c.dk.abs() < 0.02, "dK/K {}", c.dk);
    assert!(c.de.abs() < 1e-3, "dE/K {}", c.de);
    assert!(c.rebound > 0.9);
}

/// A deformable block 0.1 x 0.05 m on a rigid incline at angle theta; returns the measured
/// acceleration along the slope (downwards positive) between t = 0.05 s and 0.25 s and the
/// displacement along the slope over that window.
fn incline(theta: f64, mu: f64, alpha: f64) -> (f64, f64) {
    let (w, hgt, nx, ny) = (0.1, 0.05, 10, 5);
    let (local, t) = rectangle(w, hgt, nx, ny);
    let mat = Material {
        damping_ratio: 0.05,
        ..Material::new(1e8, 0.25, 1000.0)
    };
    let g = 9.81;
    let p = 10.0 * mat.youngs_modulus;
    // Static penetration of the bottom edges: traction 3 p d / H = weight per length.
    let h_cell = hgt / ny as f64;
    let d0 = mat.density * hgt * g * theta.cos() * h_cell / (3.0 * p);
    let (s, c) = theta.sin_cos();
    let x: Vec<[f64; 2]> = local
        .iter()
        .map(|q| {
            let q = [q[0] - w / 2.0, q[1] - d0];
            [c * q[0] - s * q[1], s * q[0] + c * q[1]]
        })
        .collect();
    let mut law = ContactLaw {
        mu,
        ..ContactLaw::with_penalty(p)
    };
    law.damping = law.damping_for_ratio(0.5, mat.density);
    let mut contact = Contact::new(
        ContactSettings::default(),
        ContactLaws::uniform(1, ContactLaw::disabled()),
    );
    contact
        .walls
        .push(RigidPlane::new([0.0, 0.0], [-s, c], law));
    let dt = stable_dt(0.5 * h_cell, p, &mat);
    let mut scene = Scene::new(x.clone(), t, mat, contact, dt);
    scene.gravity = [0.0, -g];
    scene.alpha = alpha;
    let mut state = State::new(0.0, x.as_flattened().to_vec(), vec![0.0; 2 * x.len()]);
    let mut cd = CentralDifference::new(state.n_dofs());
    let m: f64 = scene.mass.iter().sum();
    let down = [-c, -s];
    let along = |st: &State, sc: &Scene| -> (f64, f64) {
        let xn = st.x_nodes();
        let vn = st.v_nodes();
        let (mut xs, mut vs) = (0.0, 0.0);
        for i in 0..sc.mass.len() {
            xs += sc.mass[i] * (xn[i][0] * down[0] + xn[i][1] * down[1]);
            vs += sc.mass[i] * (vn[i][0] * down[0] + vn[i][1] * down[1]);
        }
        (xs / m, vs / m)
    };
    let (n0, n1) = ((0.05 / dt) as usize, (0.25 / dt) as usize);
    let (mut x0, mut v0) = (0.0, 0.0);
    for k in 0..n1 {
        if k == n0 {
            (x0, v0) = along(&state, &scene);
        }
        cd.step(&mut scene, &mut state, dt);
    }
    let (x1, v1) = along(&state, &scene);
    let a = (v1 - v0) / ((n1 - n0) as f64 * dt);
    (a, x1 - x0)
}

#[test]
fn deformable_block_slides_down_incline_with_coulomb_acceleration() {
    // theta = 0.5 (tan = 0.546), mu = 0.3: a = g (sin - mu cos) within 1 %.
    let theta = 0.5f64;
    let (a, _) = incline(theta, 0.3, 0.0);
    let expect = 9.81 * (theta.sin() - 0.3 * theta.cos());
    eprintln!(
        "incline slide: a = {a:.5}, expected {expect:.5}, error {:.2e}",
        a / expect - 1.0
    );
    assert!(
        (a / expect - 1.0).abs() < 0.01,
        "a = {a}, expected {expect}"
    );
}

#[test]
fn deformable_block_sticks_on_incline_when_mu_exceeds_tan_theta() {
    // mu = 0.7 > tan(0.5) = 0.546. The block starts undeformed, so gravity excites
    // vibrations (~1e-7 m) far larger than the static contact penetration (~1e-9 m at
    // p = 10 E): without damping the bottom edges chatter, friction resets at each loss of
    // contact and the block creeps (measured 1.3e-4 m in 0.2 s). With mass-proportional
    // damping alpha = 2000/s the vibrations die within ~5 ms; the centre of mass then moves
    // less than 1e-6 m along the slope between t = 0.05 s and 0.25 s, while the same damping
    // with mu = 0.3 lets it slide more than 1e-4 m (damping alone does not hold it).
    let (_, creep) = incline(0.5, 0.7, 2000.0);
    let (_, slide) = incline(0.5, 0.3, 2000.0);
    eprintln!("incline stick: creep = {creep:.3e} m; same damping, mu = 0.3: {slide:.3e} m");
    assert!(creep.abs() < 1e-6, "creep {creep}");
    assert!(slide > 1e-4, "slide {slide}");
}

#[test]
fn stack_of_blocks_comes_to_rest_and_stays_at_rest() {
    // Three deformable blocks 0.1 x 0.05 m (100 triangles each), offset sideways by 1 cm,
    // dropped from 10 µm gaps onto a rigid floor under gravity with mass-proportional damping
    // alpha = 2000/s and friction mu = 0.5. After 0.1 s: every node slower than 1e-6 m/s,
    // the floor carries the total weight to 1e-6, and no node moves more than 1e-9 m
    // during the next 0.05 s.
    let (w, hgt, nx, ny) = (0.1, 0.05, 10, 5);
    let gap = 1e-5;
    let (mut x, mut t) = (Vec::new(), Vec::new());
    for b in 0..3 {
        let (xb, tb) = rectangle(w, hgt, nx, ny);
        let base = x.len() as u32;
        let y0 = gap + b as f64 * (hgt + gap);
        x.extend(xb.iter().map(|p| [p[0] + 0.01 * b as f64, p[1] + y0]));
        t.extend(tb.iter().map(|tr| tr.map(|k| k + base)));
    }
    let mat = Material {
        damping_ratio: 0.05,
        ..Material::new(1e8, 0.25, 1000.0)
    };
    let law = ContactLaw {
        mu: 0.5,
        ..ContactLaw::from_young(mat.youngs_modulus, 0.5)
    };
    let mut contact = Contact::new(ContactSettings::default(), ContactLaws::uniform(1, law));
    contact
        .walls
        .push(RigidPlane::new([0.0, 0.0], [0.0, 1.0], law));
    let dt = stable_dt(0.5 * hgt / ny as f64, law.penalty, &mat);
    let g = 9.81;
    let mut scene = Scene::new(x.clone(), t, mat, contact, dt);
    scene.gravity = [0.0, -g];
    scene.alpha = 2000.0;
    let mut state = State::new(0.0, x.as_flattened().to_vec(), vec![0.0; 2 * x.len()]);
    let mut cd = CentralDifference::new(state.n_dofs());
    let n0 = (0.1 / dt) as usize;
    for _ in 0..n0 {
        cd.step(&mut scene, &mut state, dt);
    }
    let vmax = state.v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut r = [[0.0; 2]];
    scene.contact.wall_reactions(&mut r);
    let weight = scene.mass.iter().sum::<f64>() * g;
    let x_rest = state.x.clone();
    for _ in 0..n0 / 2 {
        cd.step(&mut scene, &mut state, dt);
    }
    let drift = state
        .x
        .iter()
        .zip(&x_rest)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    eprintln!(
        "stack: max |v| = {vmax:.3e} m/s, floor reaction / weight - 1 = {:.3e}, drift over 0.05 s = {drift:.3e} m, couples {}",
        -r[0][1] / weight - 1.0,
        scene.contact.stats().n_active
    );
    assert!(vmax < 1e-6, "max |v| {vmax}");
    assert!(
        (-r[0][1] / weight - 1.0).abs() < 1e-6,
        "reaction {:?} weight {weight}",
        r[0]
    );
    assert!(drift < 1e-9, "drift {drift}");
    assert!(
        scene.contact.stats().n_active > 10,
        "blocks are not in contact with each other"
    );
}

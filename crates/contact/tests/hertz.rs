//! Hertz's 2D contact: an elastic disc pressed on a rigid plane (plane strain, frictionless),
//! brought to rest by dynamic relaxation, against the half-width and peak pressure of Hertz's
//! solution:
//!
//! ```text
//! a = sqrt(4 P R / (pi E*)),   p0 = 2 P / (pi a),   E* = E / (1 - nu^2),
//! p(x) = p0 sqrt(1 - x^2/a^2)
//! ```
//!
//! The disc (meshes/hertz-disc.msh, R = 25 mm, graded to a/12 at the contact) carries a
//! uniform body force of resultant P (a heavy roller), so the plane is its only support.
//! Static equilibrium does not depend on the masses, so the relaxation uses mass scaling
//! (every triangle the same mass, which makes the stable step the same everywhere) and
//! kinetic damping (all velocities set to zero at each peak of the kinetic energy).

use fdem_contact::{Contact, ContactLaw, ContactLaws, ContactSettings, Family, RigidPlane};
use fdem_mesh::{Elements, ForceScratch, Material, Mesh, read_mesh};
use fdem_time::{CentralDifference, Integrator, SecondOrderSystem, State};

struct Disc {
    el: Elements,
    scratch: ForceScratch,
    inv_m: Vec<f64>,
    mass: Vec<f64>,
    contact: Contact,
    tris: Vec<[u32; 3]>,
    f: Vec<[f64; 2]>,
    /// External nodal forces (the body force).
    ext: Vec<[f64; 2]>,
    dt: f64,
    /// The x DOF of the top pole, held: it removes the free rigid rotation and sliding of a
    /// disc on a frictionless plane (its reaction is round-off).
    held: [usize; 1],
    /// The bottom pole and its two neighbours on the rim.
    pole: [usize; 3],
    /// The nodes of the lower half of the rim, by x.
    rim: Vec<usize>,
}

impl SecondOrderSystem for Disc {
    fn prescribed_dofs(&self) -> &[usize] {
        &self.held
    }
    fn n_dofs(&self) -> usize {
        2 * self.mass.len()
    }
    fn inv_mass(&self) -> &[f64] {
        &self.inv_m
    }
    fn acceleration(&mut self, _t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        let xn = x.as_chunks::<2>().0;
        let vn = v.as_chunks::<2>().0;
        self.f.copy_from_slice(&self.ext);
        self.el
            .internal_forces(xn, vn, &mut self.f, &mut self.scratch);
        self.contact.update_detection(xn, &self.tris);
        let s = self
            .contact
            .compute_forces(xn, vn, &self.tris, &[], self.dt);
        s.check(self.contact.settings.max_phi).unwrap();
        self.contact.add_forces(&self.tris, &mut self.f);
        for (i, g) in self.f.iter().enumerate() {
            a[2 * i] = g[0] * self.inv_m[2 * i];
            a[2 * i + 1] = g[1] * self.inv_m[2 * i + 1];
        }
    }
    fn end_of_step(&mut self, _t: f64, _x: &[f64], _v: &[f64]) {
        self.contact.commit();
    }
}

/// What one relaxation measures.
#[derive(Debug)]
struct Hertz {
    /// Half-width from the plane's nodal forces over Hertz's.
    a_ratio: f64,
    /// Peak pressure (centre node force / tributary length) over Hertz's.
    p0_ratio: f64,
    /// Peak pressure from a least-squares fit of Hertz's shape `p0 sqrt(1 - x^2/a_H^2)` to the
    /// nodal pressures with `|x| < a_H/2`, over Hertz's (less sensitive to the node-to-node
    /// scatter of the penalty layer than the pole node alone).
    p0_fit_ratio: f64,
    /// Plane reaction over P, minus 1.
    equilibrium: f64,
    /// Largest speed at the end over the largest speed of the run.
    v_ratio: f64,
    n_tris: usize,
    /// Longest edge of the triangles at the pole over a.
    h_over_a: f64,
    dt: f64,
    /// Pressure profile `(x / a_H, p / p0_H)` at the rim nodes (nodal force over tributary
    /// length).
    profile: Vec<[f64; 2]>,
}

/// The committed mesh's path.
fn mesh_path(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name)
}

/// Relaxes the disc of `path` (centred at the origin) for `steps` steps, loaded so that
/// Hertz's half-width is `a_over_r R`, on a plane of penalty `penalty_factor E`.
fn relax(
    path: &std::path::Path,
    a_over_r: f64,
    penalty_factor: f64,
    steps: usize,
    verbose: bool,
) -> Hertz {
    let mesh: Mesh = read_mesh(path).unwrap();
    let (e, nu) = (1.0e9, 0.3);
    let mat = Material::new(e, nu, 1000.0);
    let el = Elements::new(&mesh, &[mat]).unwrap();
    let x0 = mesh.nodes.clone();
    let n = x0.len();
    // Radius from the mesh (centred at the origin).
    let r = x0.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
    let estar = e / (1.0 - nu * nu);
    let a_h = a_over_r * r;
    let p_load = std::f64::consts::PI * estar * a_h * a_h / (4.0 * r);
    let p0_h = 2.0 * p_load / (std::f64::consts::PI * a_h);
    // Body force: P shared in proportion to the true lumped masses.
    let true_m = el.lumped_masses();
    let m_total: f64 = true_m.iter().sum();
    let ext: Vec<[f64; 2]> = true_m
        .iter()
        .map(|m| [0.0, -p_load * m / m_total])
        .collect();
    // Mass scaling: every triangle gets the mass of the mean triangle.
    let tris = mesh.triangles.clone();
    let m_e = m_total / tris.len() as f64;
    let mut mass = vec![0.0; n];
    let area = |t: &[u32; 3]| {
        let [p, q, s] = t.map(|k| x0[k as usize]);
        0.5 * ((q[0] - p[0]) * (s[1] - p[1]) - (q[1] - p[1]) * (s[0] - p[0]))
    };
    let mut dt = f64::MAX;
    let p = penalty_factor * e;
    let p_mod = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mut h_contact = f64::MAX;
    for t in &tris {
        for k in t {
            mass[*k as usize] += m_e / 3.0;
        }
        // Stable step of the triangle with density m_e / A: omega h_min = max(3.5 sqrt(p/rho),
        // 3 c_p) (docs/contact.md, section 12), h_min its smallest altitude; safety 0.5.
        let a_t = area(t);
        let rho = m_e / a_t;
        let l_max = (0..3)
            .map(|k| {
                let (u, w) = (x0[t[k] as usize], x0[t[(k + 1) % 3] as usize]);
                (u[0] - w[0]).hypot(u[1] - w[1])
            })
            .fold(0.0, f64::max);
        let h_min = 2.0 * a_t / l_max;
        let w = (3.5 * (p / rho).sqrt()).max(3.0 * (p_mod / rho).sqrt()) / h_min;
        dt = dt.min(0.5 * 2.0 / w);
        if t.iter().any(|k| x0[*k as usize][1] < -r + 1e-9) {
            h_contact = h_contact.min(l_max);
        }
    }
    let inv_m = mass.iter().flat_map(|m| [1.0 / m, 1.0 / m]).collect();
    let mut contact = Contact::new(
        ContactSettings::default(),
        ContactLaws::uniform(1, ContactLaw::disabled()),
    );
    contact.walls.push(RigidPlane::new(
        [0.0, -r],
        [0.0, 1.0],
        ContactLaw::with_penalty(p),
    ));
    // The pole, where the peak pressure is read, and its neighbours on the rim.
    let pole = (0..n)
        .min_by(|&i, &j| x0[i][1].total_cmp(&x0[j][1]))
        .unwrap();
    let top = (0..n)
        .max_by(|&i, &j| x0[i][1].total_cmp(&x0[j][1]))
        .unwrap();
    let mut rim: Vec<usize> = mesh
        .boundary_edges
        .iter()
        .flat_map(|e| mesh.edges[e.0 as usize].nodes.map(|k| k.0 as usize))
        .filter(|&i| x0[i][1] < 0.0)
        .collect();
    rim.sort_by(|&i, &j| x0[i][0].total_cmp(&x0[j][0]));
    rim.dedup();
    let k = rim.iter().position(|&i| i == pole).unwrap();
    let mut disc = Disc {
        held: [2 * top],
        pole: [pole, rim[k - 1], rim[k + 1]],
        rim,
        scratch: ForceScratch::new(&el),
        el,
        inv_m,
        mass,
        contact,
        tris,
        f: vec![[0.0; 2]; n],
        ext,
        dt,
    };
    let mut state = State::new(0.0, x0.as_flattened().to_vec(), vec![0.0; 2 * n]);
    let mut cd = CentralDifference::new(state.n_dofs());
    let kinetic = |s: &State, d: &Disc| -> f64 {
        s.v_nodes()
            .iter()
            .zip(&d.mass)
            .map(|(v, m)| m * (v[0] * v[0] + v[1] * v[1]))
            .sum()
    };
    let speed = |s: &State| s.v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let (mut k_prev, mut v_peak) = (0.0f64, 0.0f64);
    for step in 1..=steps {
        cd.step(&mut disc, &mut state, dt);
        let k = kinetic(&state, &disc);
        if k < k_prev {
            // Kinetic damping: a peak of the kinetic energy has passed; stop every node.
            state.v.iter_mut().for_each(|v| *v = 0.0);
            k_prev = 0.0;
        } else {
            k_prev = k;
        }
        v_peak = v_peak.max(speed(&state));
        if verbose && step % 500 == 0 {
            let m = measure(&disc, &state);
            eprintln!(
                "  step {step}: sum F/P - 1 = {:+.2e}, a/a_H - 1 = {:+.3e}, p0/p0_H - 1 = {:+.3e}, max |v| / peak = {:.1e}",
                m.0 / p_load - 1.0,
                m.1 / a_h - 1.0,
                m.2 / p0_h - 1.0,
                speed(&state) / v_peak
            );
        }
    }
    let (sf, a_meas, p0) = measure(&disc, &state);
    let mut f = vec![[0.0; 2]; n];
    disc.contact.add_family(Family::Normal, &disc.tris, &mut f);
    let x = state.x_nodes();
    let profile: Vec<[f64; 2]> = disc
        .rim
        .windows(3)
        .filter(|w| f[w[1]][1] != 0.0)
        .map(|w| {
            let trib = 0.5 * (x[w[2]][0] - x[w[0]][0]);
            [x[w[1]][0] / a_h, f[w[1]][1] / trib / p0_h]
        })
        .collect();
    let (mut sqs, mut ss) = (0.0, 0.0);
    for [x, q] in profile.iter().filter(|p| p[0].abs() < 0.5) {
        let sh = (1.0 - x * x).sqrt();
        sqs += q * sh;
        ss += sh * sh;
    }
    Hertz {
        p0_fit_ratio: sqs / ss,
        profile,
        a_ratio: a_meas / a_h,
        p0_ratio: p0 / p0_h,
        equilibrium: sf / p_load - 1.0,
        v_ratio: speed(&state) / v_peak,
        n_tris: disc.tris.len(),
        h_over_a: h_contact / a_h,
        dt,
    }
}

/// The plane's resultant, the half-width `2 sqrt(sum x^2 F / sum F)` (Hertz:
/// `int x^2 p dx = P a^2 / 4`) and the peak pressure (the pole node's force over its
/// tributary length on the rim) from the nodal forces of the plane.
fn measure(disc: &Disc, state: &State) -> (f64, f64, f64) {
    let n = disc.mass.len();
    let mut f = vec![[0.0; 2]; n];
    disc.contact.add_family(Family::Normal, &disc.tris, &mut f);
    let x = state.x_nodes();
    let (mut sf, mut sx2) = (0.0, 0.0);
    for (g, p) in f.iter().zip(x) {
        sf += g[1];
        sx2 += p[0] * p[0] * g[1];
    }
    let [pole, left, right] = disc.pole;
    let trib = 0.5 * (x[right][0] - x[left][0]);
    (sf, 2.0 * (sx2 / sf).sqrt(), f[pole][1] / trib)
}

#[test]
fn disc_on_rigid_plane_matches_hertz_half_width_and_peak_pressure() {
    // meshes/hertz-disc.msh (6526 triangles, h = a/12.4 at the contact), a = R/20, the
    // default plane penalty p = 10 E, 14000 steps of relaxation (converged from about
    // 12000: the plane carries P to 1e-6). Measured: a +0.08 %, p0 +0.19 % (pole node) and
    // -0.20 % (fit); asserted within 2 % (the required tolerance is 5 % on a fine mesh). The error is
    // the penalty layer's compliance, about +0.11 (h/a)(E/p) on a (+0.94 % at p = E,
    // +0.45 % at p = E and h = a/24): docs/validation.md (Hertz).
    let h = relax(&mesh_path("hertz-disc.msh"), 0.05, 10.0, 14000, false);
    eprintln!(
        "hertz disc: a {:+.3} %, p0 (pole node) {:+.3} %, p0 (fit) {:+.3} %, sum F/P - 1 = {:+.1e}, v/v_peak = {:.1e}",
        100.0 * (h.a_ratio - 1.0),
        100.0 * (h.p0_ratio - 1.0),
        100.0 * (h.p0_fit_ratio - 1.0),
        h.equilibrium,
        h.v_ratio
    );
    assert!(h.equilibrium.abs() < 1e-4, "not at rest: {h:?}");
    assert!(h.v_ratio < 1e-3, "not at rest: {h:?}");
    assert!((h.a_ratio - 1.0).abs() < 0.02, "half-width: {h:?}");
    assert!((h.p0_ratio - 1.0).abs() < 0.02, "peak pressure: {h:?}");
    assert!(
        (h.p0_fit_ratio - 1.0).abs() < 0.02,
        "peak pressure (fit): {h:?}"
    );
    fdem_figures::record(
        34,
        format!(
            "a {:+.2} %, p0 {:+.2} % (pole), {:+.2} % (fit)",
            100.0 * (h.a_ratio - 1.0),
            100.0 * (h.p0_ratio - 1.0),
            100.0 * (h.p0_fit_ratio - 1.0)
        ),
    );
}

/// The study behind the Hertz row of docs/validation.md (not a check): the committed mesh at several loads and
/// penalties, plus any meshes listed (space-separated paths) in `FDEM_HERTZ_MESHES`
/// (`meshes/hertz-disc.geo` with another `lcl`). Run with
/// `cargo test --release -p fdem-contact --test all -- hertz:: --ignored --nocapture`.
#[test]
#[ignore = "parameter study for the docs, about 2 minutes"]
fn hertz_disc_study() {
    let mut runs: Vec<(std::path::PathBuf, f64, f64)> = vec![
        (mesh_path("hertz-disc.msh"), 0.05, 1.0),
        (mesh_path("hertz-disc.msh"), 0.05, 10.0),
        (mesh_path("hertz-disc.msh"), 0.05, 0.3),
        (mesh_path("hertz-disc.msh"), 0.025, 1.0),
        (mesh_path("hertz-disc.msh"), 0.1, 1.0),
    ];
    if let Ok(list) = std::env::var("FDEM_HERTZ_MESHES") {
        for p in list.split_whitespace() {
            runs.push((p.into(), 0.05, 1.0));
        }
    }
    for (run, (path, a_over_r, pf)) in runs.into_iter().enumerate() {
        // A stiffer plane needs a smaller step: more steps.
        let steps = (6000.0 * pf.max(1.0).sqrt()) as usize;
        let h = relax(&path, a_over_r, pf, steps, false);
        eprintln!(
            "{}: a/R = {a_over_r}, p = {pf} E: {} triangles, h = {:.3} a, dt = {:.2e} s, {steps} steps; a {:+.2} %, p0 {:+.2} % (fit {:+.2} %), sum F/P - 1 = {:+.1e}, v/v_peak = {:.1e}",
            path.file_name().unwrap().to_string_lossy(),
            h.n_tris,
            h.h_over_a,
            h.dt,
            100.0 * (h.a_ratio - 1.0),
            100.0 * (h.p0_ratio - 1.0),
            100.0 * (h.p0_fit_ratio - 1.0),
            h.equilibrium,
            h.v_ratio
        );
        // The pressure profiles of the runs at a/R = 0.05, for the plot
        // (docs/img/hertz-disc.png, made by crates/contact/scripts/hertz_disc_plot.py).
        if let Ok(dir) = std::env::var("FDEM_HERTZ_CSV")
            && a_over_r == 0.05
        {
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            let mut out = format!(
                "# {name}: h = {:.3} a, p = {pf} E\nx_over_a,p_over_p0\n",
                h.h_over_a
            );
            for [x, p] in &h.profile {
                out += &format!("{x:.6},{p:.6}\n");
            }
            std::fs::write(
                std::path::Path::new(&dir).join(format!("{run}-{name}.csv")),
                out,
            )
            .unwrap();
        }
    }
}

//! One joint driven through prescribed openings and slips: the traction follows the law point
//! by point, pure modes dissipate exactly G times the joint area, unloading and reloading are
//! secant, compression causes no damage, and a load-unload-reload cycle creates no energy.

use fdem_fracture::softening::{pre_peak, z};
use fdem_fracture::*;

const H: f64 = 0.01; // reference edge length (m)
const T: f64 = 0.5; // thickness (m)

fn material() -> JointMaterialInput {
    JointMaterialInput {
        tensile_strength: 5e6,
        cohesion: 8e6,
        friction_angle_deg: 30.0,
        fracture_energy_i: 50.0,
        fracture_energy_ii: 200.0,
        penalty_normal: 3e11,
        penalty_tangential: 2e11,
    }
}

/// One joint along x: P = (0,0), Q = (h,0) of T1 above, R = (h,0), S = (0,0) of T2 below, so
/// nn = (0,-1): moving T2 by (s, -o) opens by o and slides by s.
struct Rig {
    set: JointSet,
    state: JointState,
    scratch: JointScratch,
    events: Vec<FractureEvent>,
    time: f64,
}

impl Rig {
    fn new(mat: JointMaterialInput) -> Self {
        let joints = [Joint {
            nodes: [0, 1, 2, 3],
            triangles: [4, 9],
            ref_length: H,
            material: 0,
        }];
        let set = JointSet::new(&joints, &[mat], 4, T).unwrap();
        let state = JointState::new(&set, &positions(0.0, 0.0));
        Rig {
            set,
            state,
            scratch: JointScratch::new(1),
            events: Vec::new(),
            time: 0.0,
        }
    }

    /// Moves to (o, s), evaluates and commits; returns (sigma, tau) at both points.
    fn go(&mut self, o: f64, s: f64) -> [(f64, f64); 2] {
        let x = positions(o, s);
        let mut f = [[0.0; 2]; 4];
        accumulate_joint_forces(&self.set, &self.state, &x, &mut self.scratch, &mut f);
        let trial_forces = self.scratch.joint_forces(&self.set, 0);
        self.time += 1.0;
        commit_joints(
            &self.set,
            &mut self.state,
            &x,
            self.time,
            &mut self.scratch,
            &mut self.events,
        );
        assert_eq!(
            f, trial_forces,
            "one joint: the scattered forces are the joint's"
        );
        // the committed tractions: the law at the committed opening and sliding
        let (h, u) = (&self.state.history, self.state.history.local[0]);
        let t: [(f64, f64); 2] = std::array::from_fn(|p| {
            let pt = point_traction(
                &self.set.materials[0],
                &self.set.consts(0),
                &self.set.softening[0],
                u[2 * p],
                u[2 * p + 1],
                h.damage[0][p],
                h.mode_mix[0][p],
                h.shear_secant[0][p],
            );
            (pt.sigma, pt.tau)
        });
        t
    }

    /// The joint's energy books: work, stored and dissipated (J).
    fn hist(&self) -> Books {
        Books {
            work: self.state.work(0),
            stored: self.state.stored(0),
            dissipated: self.state.history.dissipated[0],
        }
    }
}

/// One joint's energy books (J).
struct Books {
    work: f64,
    stored: f64,
    dissipated: f64,
}

fn positions(o: f64, s: f64) -> Vec<[f64; 2]> {
    vec![[0.0, 0.0], [H, 0.0], [H + s, -o], [s, -o]]
}

#[test]
fn pure_tension_follows_the_law_and_dissipates_g_i_times_area() {
    let m = material().validate(0).unwrap();
    let (o_p, o_c) = (m.peak_opening(H), m.critical_opening(H));
    let mut rig = Rig::new(material());
    let n = 20_000;
    let mut peak: f64 = 0.0;
    let mut worst: f64 = 0.0;
    for i in 1..=n {
        let o = 1.0001 * o_c * i as f64 / n as f64;
        let [(s0, t0), (s1, t1)] = rig.go(o, 0.0);
        let law = if o <= o_p {
            m.ft * pre_peak(o / o_p)
        } else {
            m.ft * z((o - o_p) / (o_c - o_p))
        };
        // point by point: same formula, evaluated independently, to round-off (1e-9 ft)
        assert!(
            (s0 - law).abs() < 1e-9 * m.ft && (s1 - law).abs() < 1e-9 * m.ft,
            "o = {o}: {s0} vs {law}"
        );
        assert!(t0.abs() < 1e-9 * m.ft && t1.abs() < 1e-9 * m.ft);
        worst = [s0 - law, s1 - law, t0, t1]
            .into_iter()
            .fold(worst, |w, d| w.max(d.abs() / m.ft));
        peak = peak.max(s0);
    }
    // the peak is ft, reached at o_p (sampled within 1e-4 of it)
    assert!((peak - m.ft).abs() < 1e-6 * m.ft, "peak {peak}");
    assert_eq!(rig.events.len(), 1, "the joint breaks once, past o_c");
    let ev = rig.events[0];
    assert_eq!(ev.mode, FractureMode::I);
    assert_eq!(ev.triangles, [4, 9]);
    let g_area = m.g_i * H * T;
    // trapezoidal work over 20 000 steps: relative error ~1e-8; required: 1 %
    let err = (ev.energy_released - g_area).abs() / g_area;
    assert!(
        err < 1e-6,
        "dissipated {} vs G_I A = {g_area} (rel. error {err:e})",
        ev.energy_released
    );
    assert_eq!(ev.stored_at_break, 0.0);
    println!(
        "pure mode I: dissipated/(G_I A) - 1 = {:e}",
        ev.energy_released / g_area - 1.0
    );
    fdem_figures::record(
        35,
        format!(
            "law to {worst:.1e} ft, dissipation {:+.1e}",
            ev.energy_released / g_area - 1.0
        ),
    );
}

#[test]
fn pure_shear_follows_the_law_and_dissipates_g_ii_times_area() {
    let m = material().validate(0).unwrap();
    let fs = m.cohesion;
    let s_p = m.peak_slip(H, fs);
    let s_c = s_p + m.slip_softening_width(H, fs);
    let mut rig = Rig::new(material());
    let n = 20_000;
    let mut worst: f64 = 0.0;
    for i in 1..=n {
        // negative slip: the law is odd in s
        let s = -1.0001 * s_c * i as f64 / n as f64;
        let [(s0, t0), (_, t1)] = rig.go(0.0, s);
        let mag = if -s <= s_p {
            fs * pre_peak(-s / s_p)
        } else {
            fs * z((-s - s_p) / (s_c - s_p))
        };
        assert!(
            (t0 + mag).abs() < 1e-9 * fs && (t1 + mag).abs() < 1e-9 * fs,
            "s = {s}: {t0} vs {}",
            -mag
        );
        assert!(s0.abs() < 1e-9 * fs);
        worst = [t0 + mag, t1 + mag, s0]
            .into_iter()
            .fold(worst, |w, d| w.max(d.abs() / fs));
    }
    assert_eq!(rig.events.len(), 1);
    let ev = rig.events[0];
    assert_eq!(ev.mode, FractureMode::II);
    let g_area = m.g_ii * H * T;
    let err = (ev.energy_released - g_area).abs() / g_area;
    assert!(
        err < 1e-6,
        "dissipated {} vs G_II A = {g_area} (rel. error {err:e})",
        ev.energy_released
    );
    fdem_figures::record(
        36,
        format!(
            "law to {worst:.1e} c, dissipation {:+.1e}",
            ev.energy_released / g_area - 1.0
        ),
    );
}

#[test]
fn shear_peak_under_compression_is_c_plus_sigma_tan_phi() {
    let m = material().validate(0).unwrap();
    let mut rig = Rig::new(material());
    // compress to sigma = -6 MPa in 100 steps
    let o = -6e6 * H / m.p;
    for i in 1..=100 {
        rig.go(o * i as f64 / 100.0, 0.0);
    }
    let sigma_c = 6e6;
    let fs = m.cohesion + sigma_c * 30f64.to_radians().tan();
    let s_p = m.peak_slip(H, fs);
    let s_c = s_p + m.slip_softening_width(H, fs);
    let stored_normal = 0.5 * (m.p / H) * o * o * H * T;
    let mut peak: f64 = 0.0;
    let n = 20_000;
    for i in 1..=n {
        // s_p is hit exactly at i = 200
        let s = s_p * i as f64 / 200.0;
        if s > 1.0001 * s_c {
            break;
        }
        let [(s0, t0), _] = rig.go(o, s);
        assert!(
            (s0 + sigma_c).abs() < 1e-6 * sigma_c,
            "normal stress held: {s0}"
        );
        assert_eq!(
            rig.state.history.damage[0][0] > 0.0,
            s > s_p,
            "no damage before the shear peak"
        );
        peak = peak.max(t0);
    }
    // peak shear = c + sigma_c tan(phi) = 11.464 MPa, to round-off
    assert!((peak - fs).abs() < 1e-9 * fs, "peak {peak} vs {fs}");
    fdem_figures::record(37, format!("{:.1e}", (peak - fs).abs() / fs));
    // fully damaged but closed: it stays, carrying the compression only (no shear); the shear
    // branch has dissipated G_II A
    let g_area = m.g_ii * H * T;
    assert!(rig.events.is_empty(), "a closed joint does not break");
    assert_eq!(rig.state.history.damage[0], [1.0, 1.0]);
    let [(s0, t0), _] = rig.go(o, 1.2 * s_c);
    assert!((s0 + sigma_c).abs() < 1e-6 * sigma_c && t0 == 0.0);
    assert!(
        (rig.hist().dissipated - g_area).abs() < 1e-6 * g_area,
        "{} vs {g_area}",
        rig.hist().dissipated
    );
    assert!((rig.hist().stored - stored_normal).abs() < 1e-9 * stored_normal);
    // release the compression: the normal branch returns its energy, then the joint opens and
    // breaks with no traction and nothing stored (the faces meet contact without overlap)
    for i in (1..100).rev() {
        rig.go(o * i as f64 / 100.0, 1.2 * s_c);
    }
    assert!(rig.events.is_empty(), "still closed");
    rig.go(0.0, 1.2 * s_c);
    let ev = rig.events[0];
    assert_eq!(ev.mode, FractureMode::II);
    assert!(
        (ev.energy_released - g_area).abs() < 1e-6 * g_area,
        "{} vs {g_area}",
        ev.energy_released
    );
    assert_eq!(ev.stored_at_break, 0.0);
}

#[test]
fn mixed_mode_path_follows_the_combined_damage_and_breaks_where_predicted() {
    let m = material().validate(0).unwrap();
    let (o_p, o_soft) = (m.peak_opening(H), m.critical_opening(H) - m.peak_opening(H));
    let (s_p, s_soft) = (
        m.peak_slip(H, m.cohesion),
        m.slip_softening_width(H, m.cohesion),
    );
    // proportional path reaching both softening ranges: o = 0.6 o_c lambda, s = 0.6 s_c lambda
    let (alpha, beta) = (0.6 * (o_p + o_soft), 0.6 * (s_p + s_soft));
    let dam = |l: f64| {
        let di = ((alpha * l - o_p).max(0.0)) / o_soft;
        let dii = ((beta * l - s_p).max(0.0)) / s_soft;
        di.hypot(dii)
    };
    // the break: D(lambda*) = 1, by bisection
    let (mut lo, mut hi) = (0.0, 2.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if dam(mid) < 1.0 { lo = mid } else { hi = mid }
    }
    let lambda_star = 0.5 * (lo + hi);
    let n = 10_000;
    let dl = 2.0 / n as f64;
    let mut rig = Rig::new(material());
    let mut broke_at = None;
    for i in 1..=n {
        let l = i as f64 * dl;
        let (o, s) = (alpha * l, beta * l);
        let [(s0, t0), _] = rig.go(o, s);
        if let Some(ev) = rig.events.first() {
            assert_eq!(ev.mode, FractureMode::Mixed, "mode mix {}", ev.mode_mix);
            broke_at = Some(l);
            break;
        }
        let d = dam(l).min(1.0);
        let (sig, tau) = if d == 0.0 {
            (m.ft * pre_peak(o / o_p), m.cohesion * pre_peak(s / s_p))
        } else {
            let zd = z(d);
            (
                m.ft * zd * o / (o_p + d * o_soft),
                m.cohesion * zd * s / (s_p + d * s_soft),
            )
        };
        assert!(
            (s0 - sig).abs() < 1e-9 * m.ft,
            "lambda {l}: sigma {s0} vs {sig}"
        );
        assert!(
            (t0 - tau).abs() < 1e-9 * m.cohesion,
            "lambda {l}: tau {t0} vs {tau}"
        );
    }
    // the break happens in the first step past lambda*
    let lb = broke_at.expect("joint must break");
    assert!(
        lb >= lambda_star && lb - lambda_star <= dl * (1.0 + 1e-9),
        "{lb} vs {lambda_star}"
    );
    fdem_figures::record(
        38,
        format!(
            "breaks in the predicted step ({:.2} of a step past the root)",
            (lb - lambda_star) / dl
        ),
    );
    // dissipation is positive and below the sum of both pure-mode energies
    let e = rig.events[0].energy_released / (H * T);
    assert!(
        e > 0.0 && e < m.g_i + m.g_ii,
        "mixed-mode dissipation {e} J/m^2"
    );
    println!(
        "mixed mode: dissipated {e} J/m^2 (G_I = {}, G_II = {})",
        m.g_i, m.g_ii
    );
}

#[test]
fn unloading_and_reloading_follow_the_damaged_secant_and_create_no_energy() {
    let m = material().validate(0).unwrap();
    let (o_p, o_soft) = (m.peak_opening(H), m.critical_opening(H) - m.peak_opening(H));
    let mut rig = Rig::new(material());
    let o_d = o_p + 0.4 * o_soft;
    let n = 4000;
    for i in 1..=n {
        rig.go(o_d * i as f64 / n as f64, 0.0);
    }
    let d = rig.state.history.damage[0];
    assert!(
        (d[0] - 0.4).abs() < 1e-12 && (d[1] - 0.4).abs() < 1e-12,
        "damage {d:?}"
    );
    let (w0, diss0) = (rig.hist().work, rig.hist().dissipated);
    let secant = m.ft * z(0.4) / o_d;
    // unload to -o_p (into compression) and reload to o_d, hitting o = 0 exactly
    let path: Vec<f64> = (0..=2 * n)
        .map(|i| {
            let u = i as f64 / n as f64; // 0..2
            if u <= 1.0 {
                o_d * (1.0 - u) - o_p * u
            } else {
                -o_p * (2.0 - u) + o_d * (u - 1.0)
            }
        })
        .collect();
    for &o in &path {
        let [(s0, _), (s1, _)] = rig.go(o, 0.0);
        let law = if o >= 0.0 { secant * o } else { m.p / H * o };
        assert!(
            (s0 - law).abs() < 1e-9 * m.ft && (s1 - law).abs() < 1e-9 * m.ft,
            "o {o}: {s0} vs {law}"
        );
        assert_eq!(
            rig.state.history.damage[0], d,
            "damage must not change on the secant"
        );
    }
    // closed cycle on piecewise-linear branches: no work, no dissipation (round-off: 1e-12 G A)
    let g_area = m.g_i * H * T;
    assert!(
        (rig.hist().work - w0).abs() < 1e-12 * g_area,
        "cycle work {}",
        rig.hist().work - w0
    );
    assert!((rig.hist().dissipated - diss0).abs() < 1e-12 * g_area);
    assert!(diss0 > 0.0, "softening to D = 0.4 has dissipated energy");
}

#[test]
fn compression_causes_no_damage_and_returns_its_energy() {
    let m = material().validate(0).unwrap();
    let o_p = m.peak_opening(H);
    let g_area = m.g_i * H * T;
    // deep compression (100 o_p) without slip, then back: a linear branch, all returned
    let mut rig = Rig::new(material());
    for i in (1..=1000).chain((0..1000).rev()) {
        let o = -100.0 * o_p * i as f64 / 1000.0;
        let [(s0, _), _] = rig.go(o, 0.0);
        assert!((s0 - m.p / H * o).abs() < 1e-9 * m.ft, "sigma {s0}");
        assert_eq!(rig.state.history.damage[0], [0.0, 0.0]);
    }
    assert!(
        rig.hist().work.abs() < 1e-12 * g_area,
        "{}",
        rig.hist().work
    );

    // the same with a slip below the shear peak growing with the compression: no damage, the
    // normal branch returns its energy, the shear branch unloads on its secant k_t = tau/s and
    // keeps the pre-peak loss: in = sum of trapezoids of tau_law = fs (2y - y^2) with
    // fs = c + (p/h)|o| tan(phi), y = s/s_p(fs); out = k_max s_max^2/2
    let mut rig = Rig::new(material());
    let area = 0.5 * H * T;
    let tan_phi = 30f64.to_radians().tan();
    let (mut w_in, mut tau_prev, mut s_prev) = (0.0, 0.0, 0.0);
    let mut k_max = 0.0;
    let s_max = 0.5 * m.peak_slip(H, m.cohesion);
    for i in (1..=1000).chain((0..1000).rev()) {
        let o = -100.0 * o_p * i as f64 / 1000.0;
        let s = s_max * i as f64 / 1000.0;
        let [(s0, t0), _] = rig.go(o, s);
        assert!((s0 - m.p / H * o).abs() < 1e-9 * m.ft, "sigma {s0}");
        assert_eq!(rig.state.history.damage[0], [0.0, 0.0]);
        if i > 0 && s > s_prev {
            let fs = m.cohesion + m.p / H * o.abs() * tan_phi;
            let y = s / m.peak_slip(H, fs);
            let tau = fs * (2.0 * y - y * y);
            assert!(
                (t0 - tau).abs() < 1e-9 * fs,
                "loading: tau {t0} vs law {tau}"
            );
            w_in += 2.0 * area * 0.5 * (tau_prev + tau) * (s - s_prev);
            (tau_prev, s_prev) = (tau, s);
            k_max = tau / s;
        }
    }
    let expected = w_in - 2.0 * area * 0.5 * k_max * s_max * s_max;
    let h = rig.hist();
    println!(
        "slip under compression: dissipated {:.6e} J, expected {expected:.6e} J ({:.3e} of G_I A)",
        h.dissipated,
        expected / g_area
    );
    assert!(expected > 0.0 && h.stored.abs() < 1e-12 * g_area);
    // to the trapezoid round-off of the two sums: 1e-9
    assert!(
        (h.dissipated - expected).abs() < 1e-9 * expected,
        "{} vs {expected}",
        h.dissipated
    );
    assert!((h.work - h.dissipated).abs() < 1e-12 * g_area);
    assert!(rig.events.is_empty());
}

#[test]
fn slip_compress_and_slide_back_cycle_dissipates_and_never_creates_energy() {
    // fs grows with compression. Slide to y = 0.8 of the peak slip at sigma = 0, compress to
    // 20 MPa at that slip, slide back to 0 and release: with tau = tau_law(s, sigma) alone the
    // shear force would rise during the compression at a fixed slip and return more work than
    // went in (energy from nothing). The secant history k_t = min(k_t, tau_law/s) keeps it
    // below: the cycle dissipates exactly the pre-peak loss 2 A c s_p y^3/6.
    let m = material().validate(0).unwrap();
    let mut rig = Rig::new(material());
    let s_p = m.peak_slip(H, m.cohesion);
    let y = 0.8;
    let n = 20_000;
    for i in 1..=n {
        rig.go(0.0, y * s_p * i as f64 / n as f64);
    }
    let [(_, tau_top), _] = rig.go(0.0, y * s_p);
    let o_c = -20e6 * H / m.p;
    for i in 1..=100 {
        let [(_, t0), _] = rig.go(o_c * i as f64 / 100.0, y * s_p);
        assert!(
            (t0 - tau_top).abs() < 1e-9 * m.cohesion,
            "shear at a fixed slip must not rise with compression: {t0} vs {tau_top}"
        );
    }
    for i in (0..n).rev() {
        rig.go(o_c, y * s_p * i as f64 / n as f64);
    }
    for i in (0..100).rev() {
        rig.go(o_c * i as f64 / 100.0, 0.0);
    }
    let area = 0.5 * H * T;
    let expected = 2.0 * area * m.cohesion * s_p * y.powi(3) / 6.0;
    let h = rig.hist();
    println!(
        "slip-compress-slide back cycle: work {:.6e} J, dissipated {:.6e} J, expected {expected:.6e} J",
        h.work, h.dissipated
    );
    assert_eq!(rig.state.history.damage[0], [0.0, 0.0]);
    // trapezoid error of the loading branch with 20 000 steps: below 1e-7 relative
    assert!(
        (h.work - expected).abs() < 1e-7 * expected,
        "{} vs {expected}",
        h.work
    );
    assert!((h.dissipated - h.work).abs() < 1e-12 * expected);
    fdem_figures::record(39, format!("{:.6e} J", h.work));
}

//! Writes the validation figures of docs/fracture.md (SVG, no plotting dependency): traction
//! against opening or slip of one joint driven through the public API (fracture_mode_i.svg,
//! fracture_mode_ii.svg, fracture_z.svg).
//!
//! `cargo run -p fdem-fracture --example joint_curves -- [--out DIR]`: into DIR (default
//! `${TMPDIR:-/tmp}/fdem-figures`, created if missing); the docs' copies with `--out docs/img`.

use std::fmt::Write as _;

use fdem_fracture::*;

const H: f64 = 0.01;

fn material() -> JointMaterialInput {
    JointMaterialInput {
        tensile_strength: 5e6,
        cohesion: 8e6,
        friction_angle_deg: 30.0,
        fracture_energy_i: 50.0,
        fracture_energy_ii: 200.0,
        penalty_normal: 3e11,
        penalty_tangential: 3e11,
    }
}

/// Drives one joint through `path` (opening, slip) and returns (o, s, sigma, tau) per step.
fn drive(path: &[(f64, f64)]) -> Vec<[f64; 4]> {
    let joints = [Joint {
        nodes: [0, 1, 2, 3],
        triangles: [0, 1],
        ref_length: H,
        material: 0,
    }];
    let pos = |o: f64, s: f64| vec![[0.0, 0.0], [H, 0.0], [H + s, -o], [s, -o]];
    let set = JointSet::new(&joints, &[material()], 4, 1.0).expect("valid joint");
    let mut state = JointState::new(&set, &pos(0.0, 0.0));
    let mut scratch = JointScratch::new(1);
    let mut events = Vec::new();
    let mut out = Vec::new();
    for (k, &(o, s)) in path.iter().enumerate() {
        let x = pos(o, s);
        let mut f = [[0.0; 2]; 4];
        accumulate_joint_forces(&set, &state, &x, &mut scratch, &mut f);
        commit_joints(&set, &mut state, &x, k as f64, &mut scratch, &mut events);
        // the committed tractions at point P/S
        let (h, u) = (&state.history, state.history.local[0]);
        let t = point_traction(
            &set.materials[0],
            &set.consts(0),
            &set.softening[0],
            u[0],
            u[1],
            h.damage[0][0],
            h.mode_mix[0][0],
            h.shear_secant[0][0],
        );
        out.push([o, s, t.sigma, t.tau]);
    }
    out
}

fn lin(a: f64, b: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |i| a + (b - a) * i as f64 / n as f64)
}

struct Plot {
    svg: String,
    x: (f64, f64),
    y: (f64, f64),
}

const W: f64 = 560.0;
const HT: f64 = 360.0;
const M: f64 = 60.0;

impl Plot {
    fn new(title: &str, xlabel: &str, ylabel: &str, x: (f64, f64), y: (f64, f64)) -> Self {
        let mut svg = String::new();
        let _ = write!(
            svg,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{HT}" font-family="sans-serif" font-size="12">
<rect width="100%" height="100%" fill="white"/>
<text x="{}" y="20" text-anchor="middle" font-size="14">{title}</text>
<text x="{}" y="{}" text-anchor="middle">{xlabel}</text>
<text x="15" y="{}" text-anchor="middle" transform="rotate(-90 15 {})">{ylabel}</text>
<clipPath id="plot"><rect x="{M}" y="{M}" width="{}" height="{}"/></clipPath>
<rect x="{M}" y="{M}" width="{}" height="{}" fill="none" stroke="black"/>
"#,
            W / 2.0,
            W / 2.0,
            HT - 15.0,
            HT / 2.0,
            HT / 2.0,
            W - 1.5 * M,
            HT - 2.0 * M,
            W - 1.5 * M,
            HT - 2.0 * M
        );
        let mut p = Plot { svg, x, y };
        for i in 0..=4 {
            let (vx, vy) = (
                x.0 + (x.1 - x.0) * i as f64 / 4.0,
                y.0 + (y.1 - y.0) * i as f64 / 4.0,
            );
            let (px, py) = (p.px(vx), p.py(vy));
            let _ = writeln!(
                p.svg,
                r#"<text x="{px}" y="{}" text-anchor="middle">{vx:.3}</text><text x="{}" y="{}" text-anchor="end">{vy:.2}</text>"#,
                HT - M + 16.0,
                M - 4.0,
                py + 4.0
            );
        }
        p
    }
    fn px(&self, v: f64) -> f64 {
        M + (v - self.x.0) / (self.x.1 - self.x.0) * (W - 1.5 * M)
    }
    fn py(&self, v: f64) -> f64 {
        HT - M - (v - self.y.0) / (self.y.1 - self.y.0) * (HT - 2.0 * M)
    }
    fn line(&mut self, pts: &[(f64, f64)], color: &str, label: &str, k: usize) {
        let mut d = String::new();
        for (i, &(x, y)) in pts.iter().enumerate() {
            let _ = write!(
                d,
                "{}{:.2},{:.2} ",
                if i == 0 { "M" } else { "L" },
                self.px(x),
                self.py(y)
            );
        }
        let _ = writeln!(
            self.svg,
            r#"<path d="{d}" fill="none" stroke="{color}" stroke-width="1.8" stroke-dasharray="{}" clip-path="url(#plot)"/>"#,
            if k == 0 { "6,3" } else { "none" }
        );
        let ly = M + 18.0 + 16.0 * k as f64;
        let _ = writeln!(
            self.svg,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{color}" stroke-width="2"/><text x="{}" y="{}">{label}</text>"#,
            W - 0.5 * M - 190.0,
            ly - 4.0,
            W - 0.5 * M - 170.0,
            ly - 4.0,
            W - 0.5 * M - 165.0,
            ly
        );
    }
    fn save(mut self, path: &std::path::Path) {
        self.svg.push_str("</svg>\n");
        let tmp = path.with_extension("svg.tmp");
        std::fs::write(&tmp, &self.svg).expect("write figure");
        std::fs::rename(&tmp, path).expect("rename figure");
    }
}

/// The output folder: `--out DIR` (or a bare `DIR`); default `${TMPDIR:-/tmp}/fdem-figures`.
fn out_dir() -> std::path::PathBuf {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => std::env::temp_dir().join("fdem-figures"),
        [flag, dir] if flag == "--out" => dir.into(),
        [dir] if !dir.starts_with('-') => dir.into(),
        _ => {
            eprintln!(
                "usage: joint_curves [--out DIR]: writes fracture_mode_i.svg, fracture_mode_ii.svg \
                 and fracture_z.svg into DIR (default $TMPDIR/fdem-figures; the docs' copies: \
                 --out docs/img)"
            );
            std::process::exit(2);
        }
    }
}

fn main() {
    let dir = out_dir();
    std::fs::create_dir_all(&dir).expect("create output folder");
    let m = material().validate(0).expect("valid material");
    let (o_p, o_c) = (m.peak_opening(H), m.critical_opening(H));

    // 1. mode I: monotonic, and a cycle unload-to-compression/reload at D = 0.3
    let mono: Vec<(f64, f64)> = lin(0.0, 1.02 * o_c, 2000).map(|o| (o, 0.0)).collect();
    let o_d = o_p + 0.3 * (o_c - o_p);
    let mut cyc: Vec<(f64, f64)> = lin(0.0, o_d, 600).map(|o| (o, 0.0)).collect();
    cyc.extend(lin(o_d, -0.5 * o_p, 300).map(|o| (o, 0.0)));
    cyc.extend(lin(-0.5 * o_p, 1.02 * o_c, 2000).map(|o| (o, 0.0)));
    let mut p = Plot::new(
        "Mode I: traction-opening of one joint (G_I = 50 J/m², ft = 5 MPa)",
        "opening o / o_c",
        "σ / ft",
        (-0.05, 1.05),
        (-0.2, 1.05),
    );
    let r = drive(&cyc);
    p.line(
        &r.iter()
            .map(|v| (v[0] / o_c, v[2] / m.ft))
            .collect::<Vec<_>>(),
        "#d62728",
        "unload/reload at D = 0.3",
        1,
    );
    let r = drive(&mono);
    p.line(
        &r.iter()
            .map(|v| (v[0] / o_c, v[2] / m.ft))
            .collect::<Vec<_>>(),
        "#1f77b4",
        "monotonic",
        0,
    );
    p.save(&dir.join("fracture_mode_i.svg"));

    // 2. mode II under three normal stresses
    let mut p = Plot::new(
        "Mode II: shear-slip under normal compression (c = 8 MPa, φ = 30°)",
        "slip s (µm)",
        "τ (MPa)",
        (0.0, 40.0),
        (0.0, 16.0),
    );
    for (k, (sig, col)) in [(0.0, "#1f77b4"), (5e6, "#ff7f0e"), (10e6, "#2ca02c")]
        .into_iter()
        .enumerate()
    {
        let o = -sig * H / m.p;
        let mut path: Vec<(f64, f64)> = lin(0.0, o, 50).map(|o| (o, 0.0)).collect();
        path.extend(lin(0.0, 40e-6, 2000).map(|s| (o, s)));
        let r = drive(&path);
        let pts: Vec<(f64, f64)> = r[51..].iter().map(|v| (v[1] * 1e6, v[3] / 1e6)).collect();
        p.line(&pts, col, &format!("σ_c = {} MPa", sig / 1e6), k);
    }
    p.save(&dir.join("fracture_mode_ii.svg"));

    // 3. z(D) and the pre-peak curve, against the normalised displacement
    let mut p = Plot::new(
        "Softening curve z(D) (a = 0.63, b = 1.8, c = 6)",
        "D",
        "z",
        (0.0, 1.0),
        (0.0, 1.05),
    );
    let pts: Vec<(f64, f64)> = lin(0.0, 1.0, 400).map(|d| (d, z(d))).collect();
    p.line(&pts, "#1f77b4", "z(D), ∫z dD = 0.386307", 0);
    p.save(&dir.join("fracture_z.svg"));
    println!(
        "wrote {}/fracture_mode_i.svg, fracture_mode_ii.svg, fracture_z.svg",
        dir.display()
    );
}

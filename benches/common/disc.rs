//! The fracturing disc of the benchmarks: R = 25 mm, t = 10 mm, E = 30 GPa, ring mesh
//! h = R/129 (99 846 triangles, the whole disc fracturing: 149 382 joints), platens closing at
//! 2 x 10 m/s from the start, brittle joints (ft = 3 MPa, G_I = G_II = 1 J/m^2).

use std::path::PathBuf;

/// Rings of the mesh.
pub const RINGS: usize = 129;

/// Ring mesh of a disc (nodes, CCW triangles): ring k has 6k nodes at radius k R/n, with nodes
/// at the poles; consecutive rings are joined by merging their nodes by angle.
fn disc(r: f64, n: usize) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut nodes = vec![[0.0, 0.0]];
    let mut rings: Vec<Vec<u32>> = vec![vec![0]];
    for k in 1..=n {
        let m = 6 * k;
        let mut ring = Vec::with_capacity(m);
        for j in 0..m {
            let a = std::f64::consts::FRAC_PI_2 + 2.0 * std::f64::consts::PI * j as f64 / m as f64;
            let rk = r * k as f64 / n as f64;
            nodes.push([rk * a.cos(), rk * a.sin()]);
            ring.push((nodes.len() - 1) as u32);
        }
        rings.push(ring);
    }
    let mut tris = Vec::new();
    for j in 0..6 {
        tris.push([0, rings[1][j], rings[1][(j + 1) % 6]]);
    }
    for k in 2..=n {
        let (inner, outer) = (&rings[k - 1], &rings[k]);
        let (ni, no) = (inner.len(), outer.len());
        let (mut i, mut o) = (0, 0);
        while i < ni || o < no {
            let ai = if i < ni {
                (i + 1) as f64 / ni as f64
            } else {
                2.0
            };
            let ao = if o < no {
                (o + 1) as f64 / no as f64
            } else {
                2.0
            };
            if ao <= ai {
                tris.push([inner[i % ni], outer[o % no], outer[(o + 1) % no]]);
                o += 1;
            } else {
                tris.push([inner[i % ni], outer[o % no], inner[(i + 1) % ni]]);
                i += 1;
            }
        }
    }
    for t in &mut tris {
        let [a, b, c] = t.map(|i| nodes[i as usize]);
        if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0.0 {
            t.swap(1, 2);
        }
    }
    (nodes, tris)
}

/// A folder with the disc's mesh (`disc.json`) and scene (`disc.scene.json`).
#[allow(dead_code)]
pub fn scene_dir() -> PathBuf {
    scene_dir_rings(RINGS)
}

/// [`scene_dir`] for a ring mesh of `rings` rings (6 rings^2 triangles; the bench disc has
/// [`RINGS`]).
pub fn scene_dir_rings(rings: usize) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fdem-bench-fracture-disc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (nodes, tris) = disc(0.025, rings);
    let mesh = serde_json::json!({ "nodes": nodes, "triangles": tris });
    std::fs::write(dir.join("disc.json"), mesh.to_string()).unwrap();
    let scene = serde_json::json!({
        "bodies": [{
            "name": "disc",
            "mesh": dir.join("disc.json").display().to_string(),
            "materials": { "*": { "young": 30e9, "poisson": 0.2, "density": 2500.0, "plane": "stress" } },
            "thickness": 0.01
        }],
        "fracture": {
            "regions": [ { "body": "disc" } ],
            "material": {
                "tensile_strength": 3e6, "cohesion": 10e6, "friction_angle_deg": 30.0,
                "fracture_energy_i": 1.0, "fracture_energy_ii": 1.0,
                "penalty_normal": 300e9, "penalty_tangential": 300e9
            }
        },
        "contact": {
            "walls": [
                { "name": "top", "point": [0.0, 0.025], "normal": [0.0, -1.0], "velocity": [0.0, -10.0] },
                { "name": "bottom", "point": [0.0, -0.025], "normal": [0.0, 1.0], "velocity": [0.0, 10.0] }
            ]
        },
        "integrator": { "scheme": "central-difference", "time_step": "auto", "safety": 0.9 },
        "duration": 1.0,
        "output": { "frames": 0 }
    });
    std::fs::write(dir.join("disc.scene.json"), scene.to_string()).unwrap();
    dir
}

//! The set-up of a run is partly parallel (the mesh build and explode, the joints of a body and
//! of the scene, the joint set, the star bonds, the first contact detection): a fracturing,
//! pressed rectangle of 20 000 triangles (29 800 joints: many rayon tasks), loaded and run for
//! two steps in pools of 1, 2 and 3 threads, gives the same model, exploded mesh, joints, joint
//! set, time step and final state bit for bit; each joint's reference length is its edge's
//! length in the exploded mesh, and its nodes are its internal edge's (the serial construction's
//! definition).

use fdem_solver::driver::{self, RunOptions};
use serde_json::json;

use crate::common;

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn f64_bits<'a>(v: impl IntoIterator<Item = &'a f64>) -> Vec<u64> {
    v.into_iter().map(|x| x.to_bits()).collect()
}

fn pt_bits(v: &[[f64; 2]]) -> Vec<u64> {
    f64_bits(v.as_flattened())
}

/// Everything the set-up builds, and the state after two steps, as one string of bits.
fn setup_and_two_steps(scene: &std::path::Path, out: &std::path::Path) -> String {
    let mut l = driver::load(scene).unwrap_or_else(|e| panic!("{e}"));
    let m = &l.model;
    let mut key = format!(
        "{:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        pt_bits(&m.x0),
        f64_bits(&m.mass),
        m.triangles,
        m.tri_material,
        m.constrained,
        m.loads
            .iter()
            .map(|ld| ld.forces.iter().map(|(d, f)| (*d, f.to_bits())).collect())
            .collect::<Vec<Vec<_>>>(),
        [
            l.dt.to_bits(),
            l.omega_max().to_bits(),
            l.dt_limit.to_bits()
        ],
    );
    let mesh = &l.meshes[0];
    key += &format!(
        " {:?} {:?} {:?} {:?}",
        pt_bits(&mesh.nodes),
        mesh.triangles,
        mesh.edges,
        mesh.groups
    );
    let joints = &l.fracturing.bodies[0].1;
    assert_eq!(joints.len(), 29_800);
    for j in joints {
        let [p, q] = [j.nodes[0], j.nodes[1]].map(|n| mesh.nodes[n as usize]);
        let h = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        assert_eq!(j.ref_length.to_bits(), h.to_bits(), "{j:?}");
        key += &format!(" {:?}{:?}{}", j.nodes, j.triangles, j.material);
    }
    let set = l.fracturing.set.clone().unwrap();
    assert_eq!(
        set.nodes,
        joints.iter().map(|j| j.nodes).collect::<Vec<_>>()
    );
    key += &format!(
        " {:?} {:?} {:?} {:?}",
        f64_bits(&set.ref_length),
        (set.softening.iter().enumerate())
            .map(|(j, c)| {
                let k = set.consts(j);
                [k.kn, k.o_p, c.o_soft, k.s_p0, c.s_soft0].map(f64::to_bits)
            })
            .collect::<Vec<_>>(),
        set.node_offsets,
        set.node_slots
    );
    l.n_steps = 2;
    let opts = RunOptions {
        out_dir: out.to_path_buf(),
        ..Default::default()
    };
    let o = driver::run_outcome(&mut l, &opts, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let f = &o.last_frame;
    key += &format!(
        " {:?} {:?} {}",
        pt_bits(&f.points),
        pt_bits(&f.velocity),
        o.summary.stages["fracture"]["bonded_pairs"]
    );
    key
}

#[test]
fn setup_is_the_same_bits_on_any_number_of_threads() {
    let dir = common::temp_dir("setup_threads");
    common::rectangle_with_sides(&dir, 100, 100, 0.1, 0.1);
    let scene = json!({
        "bodies": [{
            "name": "rock", "mesh": "rect.json",
            "materials": { "*": { "young": 30e9, "poisson": 0.2, "density": 2500.0, "plane": "stress" } },
            "thickness": 0.01
        }],
        "fracture": {
            "regions": [ { "body": "rock", "groups": ["rock"] } ],
            "material": {
                "tensile_strength": 3e6, "cohesion": 10e6, "friction_angle_deg": 30.0,
                "fracture_energy_i": 1.0, "fracture_energy_ii": 1.0,
                "penalty_normal": 300e9, "penalty_tangential": 300e9
            }
        },
        "contact": { "default": { "friction": 0.3 } },
        "boundary_conditions": [
            { "fixed": { "group": "bottom", "y": true } },
            { "pressure": { "group": "top", "value": 5e6 } }
        ],
        "integrator": { "scheme": "central-difference", "safety": 0.9 },
        "duration": 1e-6,
        "output": { "frames": 0 }
    });
    let p = dir.join("scene.json");
    std::fs::write(&p, scene.to_string()).unwrap();
    let keys: Vec<String> = [1, 2, 3]
        .into_iter()
        .map(|t| in_pool(t, || setup_and_two_steps(&p, &dir.join(format!("out{t}")))))
        .collect();
    assert!(keys[1] == keys[0], "2 threads differ from 1");
    assert!(keys[2] == keys[0], "3 threads differ from 1");
    fdem_figures::record(95, "equal; as stated");
}

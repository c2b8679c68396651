//! The joint set is built in parallel (`JointSet::new`: the per-joint checks, constants and
//! columns): on an exploded grid of 20 000 triangles (29 800 joints, many rayon tasks) it is
//! the same bit for bit in pools of 1, 2 and 3 threads and the same as the serial loop it
//! replaced (kept here as the reference); a set with two bad joints names the first in every
//! pool; the joints' frequency bound of a fresh state without the state is the bound with it.

use crate::common;

use common::exploded_grid;
use fdem_fracture::*;

fn material(ft: f64, g: f64) -> JointMaterialInput {
    JointMaterialInput {
        tensile_strength: ft,
        cohesion: 2.0 * ft,
        friction_angle_deg: 30.0,
        fracture_energy_i: g,
        fracture_energy_ii: 5.0 * g,
        penalty_normal: 3e11,
        penalty_tangential: 2e11,
    }
}

/// 100 x 100 cells (20 000 triangles), two materials alternating, lengths varied by up to
/// 1 % so that no two neighbouring joints have the same constants.
fn joints() -> (Vec<Joint>, Vec<[f64; 2]>, Vec<JointMaterialInput>) {
    let mesh = exploded_grid(100, 100, 0.01, 0.012);
    let joints = (mesh.joints.iter().enumerate())
        .map(|(j, jt)| Joint {
            material: (j % 2) as u32,
            ref_length: jt.ref_length * (1.0 + 0.01 * ((j * 7919) % 101) as f64 / 101.0),
            ..*jt
        })
        .collect();
    (
        joints,
        mesh.x,
        vec![material(3e6, 50.0), material(5e6, 80.0)],
    )
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// Every value of a set as bits.
fn bits(set: &JointSet) -> Vec<u64> {
    let mut b: Vec<u64> = Vec::new();
    for j in 0..set.len() {
        b.extend(set.nodes[j].map(u64::from));
        b.extend(set.triangles[j].map(u64::from));
        b.push(set.ref_length[j].to_bits());
        b.push(u64::from(set.material[j]));
        let (k, c) = (&set.consts(j), &set.softening[j]);
        b.extend(
            [
                k.h,
                k.kn,
                k.o_p,
                k.inv_o_p,
                c.o_soft,
                c.inv_o_soft,
                k.slip_per_fs,
                k.s_p0,
                k.inv_s_p0,
                c.s_soft0,
                c.inv_s_soft0,
            ]
            .map(f64::to_bits),
        );
    }
    b.extend(set.node_offsets.iter().map(|&o| u64::from(o)));
    b.extend(set.node_slots.iter().map(|&s| u64::from(s)));
    b.push(set.thickness.to_bits());
    b.push(set.n_nodes as u64);
    b
}

/// The serial construction `JointSet::new` replaced: one loop over the joints pushing each
/// column, then the node map by a counting sort.
fn serial_reference(
    joints: &[Joint],
    inputs: &[JointMaterialInput],
    n_nodes: usize,
    thickness: f64,
) -> Vec<u64> {
    let materials: Vec<JointMaterial> = (inputs.iter().enumerate())
        .map(|(i, m)| m.validate(i as u32).unwrap())
        .collect();
    let mut set = JointSet::new(&joints[..1], inputs, n_nodes, thickness).unwrap();
    set.nodes.clear();
    set.triangles.clear();
    set.ref_length.clear();
    set.material.clear();
    set.softening.clear();
    for jt in joints {
        let m = &materials[jt.material as usize];
        set.nodes.push(jt.nodes);
        set.triangles.push(jt.triangles);
        set.ref_length.push(jt.ref_length);
        set.material.push(jt.material);
        set.softening.push(m.softening_consts(jt.ref_length));
    }
    let mut offsets = vec![0u32; n_nodes + 1];
    for nodes in &set.nodes {
        for &nd in nodes {
            offsets[nd as usize + 1] += 1;
        }
    }
    for i in 0..n_nodes {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut slots = vec![0u32; 4 * joints.len()];
    for (j, nodes) in set.nodes.iter().enumerate() {
        for (k, &nd) in nodes.iter().enumerate() {
            slots[fill[nd as usize] as usize] = (4 * j + k) as u32;
            fill[nd as usize] += 1;
        }
    }
    set.node_offsets = offsets;
    set.node_slots = slots;
    bits(&set)
}

#[test]
fn the_joint_set_is_the_same_bits_on_any_number_of_threads() {
    let (joints, x, inputs) = joints();
    let n = x.len();
    assert_eq!(joints.len(), 29_800);
    let reference = serial_reference(&joints, &inputs, n, 0.05);
    for threads in [1, 2, 3] {
        let set = in_pool(threads, || {
            JointSet::new(&joints, &inputs, n, 0.05).unwrap()
        });
        assert!(
            bits(&set) == reference,
            "{threads} thread(s): the set differs from the serial construction"
        );
    }
}

#[test]
fn the_first_bad_joint_is_named_on_any_number_of_threads() {
    let (mut joints, x, inputs) = joints();
    let n = x.len();
    // two bad joints in different rayon tasks: the first in joint order is reported
    joints[25_000].nodes[2] = n as u32;
    joints[7_001].ref_length = -1.0;
    for threads in [1, 2, 3] {
        let e = in_pool(threads, || JointSet::new(&joints, &inputs, n, 0.05)).unwrap_err();
        assert_eq!(
            e,
            FractureError::BadLength {
                joint: 7_001,
                h: -1.0
            },
            "{threads} thread(s)"
        );
    }
    joints[7_001].ref_length = 0.01;
    let e = JointSet::new(&joints, &inputs, n, 0.05).unwrap_err();
    assert!(
        matches!(e, FractureError::NodeOutOfRange { joint: 25_000, .. }),
        "{e}"
    );
}

#[test]
fn the_fresh_bound_without_a_state_is_the_bound_with_one() {
    let (joints, x, inputs) = joints();
    let set = JointSet::new(&joints, &inputs, x.len(), 0.05).unwrap();
    let mass: Vec<f64> = (0..x.len())
        .map(|i| 1e-3 * (1.0 + (i % 13) as f64))
        .collect();
    let with_state = joint_omega_sq_bound(&set, &JointState::new(&set, &x), &mass);
    let without = joint_omega_sq_bound_intact(&set, &mass);
    assert!(with_state > 0.0);
    assert_eq!(with_state.to_bits(), without.to_bits());
}

//! The joints of one frame as plain data: one line per joint along the joint's current
//! mid-surface, with the cell arrays of the `joints_NNNN.vtu` series (the table in
//! [`super::joints`]), each from the committed joint history at the frame's positions.

use fdem_fracture::{FractureMode, JointSet, JointState, kinematics, point_traction};
use rayon::prelude::*;
use serde::Serialize;

/// The joints of one frame (plain data, one entry per joint; `points` has two per joint).
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct JointFrame {
    /// The line of joint `j` runs from `points[2j]` (M0) to `points[2j + 1]` (M1) [m].
    pub points: Vec<[f64; 2]>,
    /// Mean damage of the two points, in `[0, 1]`.
    pub damage: Vec<f64>,
    /// 0 elastic, 1 mode I, 2 mode II, 3 mixed.
    pub mode: Vec<i32>,
    /// Mode indicator in `[0, 1]` (0 pure mode I, 1 pure mode II).
    pub mode_mix: Vec<f64>,
    /// 1 once broken, else 0.
    pub broken: Vec<i32>,
    /// Time of the break [s], -1 while unbroken.
    pub time_of_failure: Vec<f64>,
    /// Opening, mean of the two points [m].
    pub opening: Vec<f64>,
    /// Sliding, mean of the two points [m].
    pub sliding: Vec<f64>,
    /// Normal traction, mean of the two points [Pa] (0 once broken).
    pub normal_traction: Vec<f64>,
    /// Shear traction, mean of the two points [Pa] (0 once broken).
    pub shear_traction: Vec<f64>,
    /// Each joint's strengths and fracture energies, only in a scene whose joints differ in
    /// material (several joint materials, or drawn ones).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub properties: Option<JointProperties>,
    /// The fluid in the joints, only in a scene with a `"fluid"` section.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fluid: Option<JointFluid>,
}

/// The fluid in every joint (one entry per joint; 0 on the dry ones).
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct JointFluid {
    /// Mean pressure of the joint's two end cavities [Pa].
    pub pressure: Vec<f64>,
    /// Mean aperture of its two ends [m].
    pub aperture: Vec<f64>,
    /// Volume flow from end P to end Q [m^3/s].
    pub flow_rate: Vec<f64>,
    /// 1 for a wetted joint (a channel), else 0.
    pub wetted: Vec<i32>,
}

/// The material values of every joint (one entry per joint).
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct JointProperties {
    /// Tensile strength `ft` [Pa].
    pub tensile_strength: Vec<f64>,
    /// Cohesion `c` [Pa].
    pub cohesion: Vec<f64>,
    /// Mode I fracture energy [J/m^2].
    pub fracture_energy_i: Vec<f64>,
    /// Mode II fracture energy [J/m^2].
    pub fracture_energy_ii: Vec<f64>,
}

impl JointProperties {
    /// The values of the joints of `set`, from each joint's material row.
    pub fn new(set: &JointSet) -> Self {
        let of = |f: fn(&fdem_fracture::JointMaterial) -> f64| -> Vec<f64> {
            set.material
                .iter()
                .map(|&m| f(&set.materials[m as usize]))
                .collect()
        };
        Self {
            tensile_strength: of(|m| m.ft),
            cohesion: of(|m| m.cohesion),
            fracture_energy_i: of(|m| m.g_i),
            fracture_energy_ii: of(|m| m.g_ii),
        }
    }
}

/// Mode code of a joint: 0 with no damage, else [`FractureMode::from_mix`] as 1 (I), 2 (II),
/// 3 (mixed).
pub fn mode_code(damage: f64, mix: f64) -> i32 {
    if damage <= 0.0 {
        return 0;
    }
    match FractureMode::from_mix(mix) {
        FractureMode::I => 1,
        FractureMode::II => 2,
        FractureMode::Mixed => 3,
    }
}

/// One joint's entries of a [`JointFrame`].
struct Row {
    points: [[f64; 2]; 2],
    damage: f64,
    mode: i32,
    mode_mix: f64,
    broken: i32,
    time_of_failure: f64,
    opening: f64,
    sliding: f64,
    normal_traction: f64,
    shear_traction: f64,
}

/// Joint `j`'s entries of the frame at positions `x`.
fn row(set: &JointSet, state: &JointState, x: &[[f64; 2]], j: usize) -> Row {
    let xs = set.gather(j, x);
    let [p, q, r, s] = xs;
    let k = kinematics(&xs, set.ref_length[j]);
    let h = state.point_history(j);
    let intact = state.intact[j];
    let (sigma, tau) = if intact {
        let m = &set.materials[set.material[j] as usize];
        let off = set.initial_offset(j);
        let t: [_; 2] = std::array::from_fn(|i| {
            let (o, sl) = if set.initial_offsets.is_empty() {
                (k.o[i], k.s[i])
            } else {
                (k.o[i] + off[0], k.s[i] + off[1])
            };
            point_traction(
                m,
                &set.consts(j),
                &set.softening[j],
                o,
                sl,
                h.damage[i],
                h.mode_mix[i],
                h.shear_secant[i],
            )
        });
        (0.5 * (t[0].sigma + t[1].sigma), 0.5 * (t[0].tau + t[1].tau))
    } else {
        (0.0, 0.0)
    };
    let d = if intact {
        state.joint_damage(j).clamp(0.0, 1.0)
    } else {
        1.0
    };
    let mix = state.history.joint_mode_mix(j).clamp(0.0, 1.0);
    Row {
        points: [
            [0.5 * (p[0] + s[0]), 0.5 * (p[1] + s[1])],
            [0.5 * (q[0] + r[0]), 0.5 * (q[1] + r[1])],
        ],
        damage: d,
        mode: mode_code(d, mix),
        mode_mix: mix,
        broken: i32::from(!intact),
        time_of_failure: match state.broken_at[j] {
            Some(t) if !intact => t,
            _ => -1.0,
        },
        opening: 0.5 * (k.o[0] + k.o[1]),
        sliding: 0.5 * (k.s[0] + k.s[1]),
        normal_traction: sigma,
        shear_traction: tau,
    }
}

impl JointFrame {
    /// The joints of `set` with history `state` at positions `x`.
    pub fn new(set: &JointSet, state: &JointState, x: &[[f64; 2]]) -> Self {
        let n = set.len();
        let mut f = JointFrame {
            points: vec![[0.0; 2]; 2 * n],
            damage: vec![0.0; n],
            mode: vec![0; n],
            mode_mix: vec![0.0; n],
            broken: vec![0; n],
            time_of_failure: vec![0.0; n],
            opening: vec![0.0; n],
            sliding: vec![0.0; n],
            normal_traction: vec![0.0; n],
            shear_traction: vec![0.0; n],
            properties: None,
            fluid: None,
        };
        // one row per joint, evaluated in parallel (each from its own joint only) and written
        // straight into its place in every column
        (
            f.points.par_chunks_mut(2),
            f.damage.par_iter_mut(),
            f.mode.par_iter_mut(),
            f.mode_mix.par_iter_mut(),
            f.broken.par_iter_mut(),
            f.time_of_failure.par_iter_mut(),
            f.opening.par_iter_mut(),
            f.sliding.par_iter_mut(),
            f.normal_traction.par_iter_mut(),
            f.shear_traction.par_iter_mut(),
        )
            .into_par_iter()
            .with_min_len(1024)
            .enumerate()
            .for_each(|(j, (pts, d, m, mix, b, tf, o, s, sn, ts))| {
                let r = row(set, state, x, j);
                pts.copy_from_slice(&r.points);
                *d = r.damage;
                *m = r.mode;
                *mix = r.mode_mix;
                *b = r.broken;
                *tf = r.time_of_failure;
                *o = r.opening;
                *s = r.sliding;
                *sn = r.normal_traction;
                *ts = r.shear_traction;
            });
        f
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.damage.len()
    }

    /// True with no joints.
    pub fn is_empty(&self) -> bool {
        self.damage.is_empty()
    }

    /// True when every value is finite (a frame with a NaN or infinity is not written).
    pub fn is_finite(&self) -> bool {
        self.points.iter().flatten().all(|v| v.is_finite())
            && [
                &self.damage,
                &self.mode_mix,
                &self.time_of_failure,
                &self.opening,
                &self.sliding,
                &self.normal_traction,
                &self.shear_traction,
            ]
            .iter()
            .all(|a| a.iter().all(|v| v.is_finite()))
            && self.fluid.as_ref().is_none_or(|f| {
                [&f.pressure, &f.aperture, &f.flow_rate]
                    .iter()
                    .all(|a| a.iter().all(|v| v.is_finite()))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_codes_follow_the_fracture_modes() {
        assert_eq!(mode_code(0.0, 0.9), 0);
        assert_eq!(mode_code(0.5, 0.1), 1);
        assert_eq!(mode_code(1.0, 0.9), 2);
        assert_eq!(mode_code(0.2, 0.5), 3);
    }
}

//! The joints of a fracturing scene as a second ParaView series: `joints_NNNN.vtu` (line
//! cells, written by [`super::vtu::Grid`]) collected in `joints.pvd`,
//! written at the same frames as the triangles' `frame_NNNN.vtu`.
//!
//! One line cell per joint, cell `j` is joint `j` (the `joint` column of `fractures.csv`),
//! with its own two points: the current **mid-surface** of the joint,
//!
//! ```text
//! M0 = (x_P + x_S)/2,   M1 = (x_Q + x_R)/2
//! ```
//!
//! (edge P->Q of triangle T1 against R->S of T2; the two node pairs averaged, so the line
//! sits in the middle of an opening crack). Cell arrays, each from the committed joint
//! history at the frame's positions:
//!
//! | array | meaning |
//! |---|---|
//! | `damage` | mean damage of the two integration points, in `[0, 1]` (1 once broken) |
//! | `mode` | 0 elastic (no damage), 1 mode I, 2 mode II, 3 mixed (damaged or broken joints, from `mode_mix`: below 1/6, above 5/6, between) |
//! | `mode_mix` | mode indicator `(2/pi) atan2(d_II, d_I)` of the latest damage growth, mean of the two points (0 pure I, 1 pure II) |
//! | `broken` | 0 or 1 |
//! | `time_of_failure` | time of the break [s]; -1 for an unbroken joint (never NaN) |
//! | `opening`, `sliding` | `o = w . nn`, `s = w . tt`, mean of the two points [m] (`w` = x_S - x_P, x_R - x_Q) |
//! | `normal_traction`, `shear_traction` | `sigma`, `tau` of the law, mean of the two points [Pa], tension positive; 0 once broken |
//! | `tensile_strength`, `cohesion`, `fracture_energy_i`, `fracture_energy_ii` | the joint's material values [Pa, Pa, J/m^2, J/m^2], only in a scene whose joints differ in material (several joint materials, or drawn ones) |
//! | `fluid_pressure`, `aperture`, `flow_rate`, `wetted` | the fluid (scenes with a `"fluid"` section): mean pressure of the two end cavities [Pa], mean aperture [m], volume flow from end P to end Q [m^3/s], 1 on a channel; 0 on dry joints |

use std::path::{Path, PathBuf};

use super::joint_frame::JointFrame;
use super::pvd::Collection;
use super::vtu::{Column, Grid, VTK_LINE, Values};
use crate::input::arrays::ArraySet;

/// The grid of the joints' line cells with the arrays of `arrays`, borrowed from `j`.
pub fn grid<'a>(j: &'a JointFrame, arrays: &ArraySet) -> Grid<'a> {
    let n = j.len();
    let mut grid = Grid::new(&j.points, Values::Count(2 * n), n, 2, VTK_LINE);
    let mut cells = vec![
        Column::new("damage", 1, Values::F64(&j.damage)),
        Column::new("mode", 1, Values::I32(&j.mode)),
        Column::new("mode_mix", 1, Values::F64(&j.mode_mix)),
        Column::new("broken", 1, Values::I32(&j.broken)),
        Column::new("time_of_failure", 1, Values::F64(&j.time_of_failure)),
        Column::new("opening", 1, Values::F64(&j.opening)),
        Column::new("sliding", 1, Values::F64(&j.sliding)),
        Column::new("normal_traction", 1, Values::F64(&j.normal_traction)),
        Column::new("shear_traction", 1, Values::F64(&j.shear_traction)),
    ];
    if let Some(p) = &j.properties {
        cells.extend([
            Column::new("tensile_strength", 1, Values::F64(&p.tensile_strength)),
            Column::new("cohesion", 1, Values::F64(&p.cohesion)),
            Column::new("fracture_energy_i", 1, Values::F64(&p.fracture_energy_i)),
            Column::new("fracture_energy_ii", 1, Values::F64(&p.fracture_energy_ii)),
        ]);
    }
    if let Some(f) = &j.fluid {
        cells.extend([
            Column::new("fluid_pressure", 1, Values::F64(&f.pressure)),
            Column::new("aperture", 1, Values::F64(&f.aperture)),
            Column::new("flow_rate", 1, Values::F64(&f.flow_rate)),
            Column::new("wetted", 1, Values::I32(&f.wetted)),
        ]);
    }
    grid.cell_data = cells.into_iter().filter(|c| arrays.has(c.name)).collect();
    grid
}

/// Encodes the joints with every array as the bytes of a `.vtu` file of line cells (zlib
/// level `level`, 0 = uncompressed).
pub fn encode(j: &JointFrame, level: u32) -> Result<Vec<u8>, String> {
    grid(j, &ArraySet::all()).to_bytes(level)
}

/// The joint series of a run: `joints_NNNN.vtu` files and their collection `joints.pvd`,
/// started by the first frame that carries joints (a scene without joints writes neither).
#[derive(Debug, Clone, Default)]
pub struct JointSeries {
    pvd: Option<Collection>,
}

impl JointSeries {
    /// The file of the joints `j` of frame `index` (`joints_NNNN.vtu`), or the file and the
    /// message when a value is not finite (the frame is not written).
    pub fn file_name(
        dir: &Path,
        index: usize,
        j: &JointFrame,
    ) -> Result<String, (PathBuf, String)> {
        let name = format!("joints_{index:04}.vtu");
        if !j.is_finite() {
            let message = "non-finite joint values (frame not written)".into();
            return Err((dir.join(name), message));
        }
        Ok(name)
    }

    /// Adds the joint file `name` (written) at time `t` and rewrites `joints.pvd` in `dir`;
    /// on failure, the file and the message.
    pub fn push(&mut self, dir: &Path, t: f64, name: &str) -> Result<(), (PathBuf, String)> {
        let pvd = self
            .pvd
            .get_or_insert_with(|| Collection::new(&dir.join("joints.pvd")));
        pvd.push(t, name)
            .map_err(|e| (dir.join("joints.pvd"), e.to_string()))
    }

    /// Frames written.
    pub fn len(&self) -> usize {
        self.pvd.as_ref().map_or(0, Collection::len)
    }

    /// The joint frames so far (time, file), empty before the first.
    pub fn entries(&self) -> &[(f64, String)] {
        self.pvd.as_ref().map_or(&[], |c| c.entries())
    }

    /// The series of a resumed run in `dir` with the frames `entries` (`joints.pvd`
    /// rewritten; none when empty).
    pub fn with_entries(dir: &Path, entries: Vec<(f64, String)>) -> std::io::Result<Self> {
        let pvd = if entries.is_empty() {
            None
        } else {
            Some(Collection::with_entries(&dir.join("joints.pvd"), entries)?)
        };
        Ok(Self { pvd })
    }

    /// True before the first joint frame.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdem_fracture::{Joint, JointMaterialInput, JointSet, JointState};

    fn one_joint() -> (JointSet, Vec<[f64; 2]>) {
        let mat = JointMaterialInput {
            tensile_strength: 5e6,
            cohesion: 10e6,
            friction_angle_deg: 30.0,
            fracture_energy_i: 50.0,
            fracture_energy_ii: 250.0,
            penalty_normal: 3e12,
            penalty_tangential: 3e12,
        };
        let joints = [Joint {
            nodes: [0, 1, 2, 3],
            triangles: [0, 1],
            ref_length: 0.01,
            material: 0,
        }];
        let x = vec![[0.0, 0.0], [0.01, 0.0], [0.01, 0.0], [0.0, 0.0]];
        (JointSet::new(&joints, &[mat], 4, 1.0).unwrap(), x)
    }

    #[test]
    fn joint_frame_is_the_mid_surface_with_the_law_tractions() {
        let (set, mut x) = one_joint();
        let state = JointState::new(&set, &x);
        // Open by half the peak opening (nn points to -y: move R, S down): sigma = ft (2x - x^2)
        // with x = 1/2, i.e. 0.75 ft; the line is the mid-surface at y = -o/2.
        let o_p = 2.0 * 0.01 * 5e6 / 3e12;
        x[2][1] -= 0.5 * o_p;
        x[3][1] -= 0.5 * o_p;
        let f = JointFrame::new(&set, &state, &x);
        assert_eq!(f.len(), 1);
        assert_eq!(f.points, vec![[0.0, -0.25 * o_p], [0.01, -0.25 * o_p]]);
        assert!((f.opening[0] / (0.5 * o_p) - 1.0).abs() < 1e-12);
        assert!(f.sliding[0].abs() < 1e-20);
        assert!((f.normal_traction[0] / (0.75 * 5e6) - 1.0).abs() < 1e-12);
        assert_eq!((f.damage[0], f.mode[0], f.broken[0]), (0.0, 0, 0));
        assert_eq!(f.time_of_failure[0], -1.0);
        assert!(f.is_finite());
    }

    #[test]
    fn joint_vtu_has_one_line_cell_per_joint_and_reads_back() {
        let (set, x) = one_joint();
        let state = JointState::new(&set, &x);
        let f = JointFrame::new(&set, &state, &x);
        let bytes = encode(&f, 6).unwrap();
        let text = String::from_utf8_lossy(&bytes[..400]);
        assert!(text.contains("vtkZLibDataCompressor"));
        let a = crate::output::vtu::read(&bytes).unwrap();
        let names: Vec<&str> = a.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(names[4], "time_of_failure");
        assert_eq!(a.len(), 9 + 4);
        assert_eq!(a[12].bytes, vec![crate::output::vtu::VTK_LINE]);
        let pts: Vec<u8> = [0.0, 0.0, 0.0, 0.01, 0.0, 0.0f64]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        assert_eq!(a[9].bytes, pts);
    }
}

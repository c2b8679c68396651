//! The accuracy indicators that the prepared problem already decides, before a step is taken:
//! the resolution of the fracture process zone and the compliance that intact joints add (per
//! joint material), the mesh's quality and the triangle that sets the step, and input values
//! outside the range of the field's materials (a unit slip). `fdem check` prints them and a
//! run reports them again with what it measured (`crate::run::accuracy`), so the two agree.
//!
//! Each indicator carries its value, its threshold and the side that is good, what it means
//! and, when it fails, one warning in plain words with its fix (docs/accuracy.md derives the
//! thresholds).

use fdem_mesh::{Elements, PlaneKind, TriId};
use rayon::prelude::*;
use serde_json::json;

use crate::input::scene::Scene;
use crate::problem::Fracturing;
use crate::problem::indicator::{Good, Indicator, length};
use crate::problem::model::Model;

/// The smallest `l_ch / h` (characteristic length over the shortest joint of a joint
/// material, where a mesh is refined for its crack) without a warning. On the Griffith plate
/// the failure stress is 4.7 % above fracture mechanics at `l_ch / h = 5.9`, 42 % at 2.9 and
/// 85 % at 1.5 (docs/accuracy.md).
pub const PROCESS_ZONE_MIN: f64 = 5.0;

/// The largest `E / p` (Young's modulus over the joints' normal penalty) without a warning:
/// each intact joint crossed adds about `E / p` of one element's strain, so `p >= 10 E`
/// keeps the exploded region's added compliance to about 10-20 % (docs/fracture.md, section 2).
pub const JOINT_COMPLIANCE_MAX: f64 = 0.1;

/// The largest loading speed over the P-wave speed without a warning (with mass scaling, the
/// wave speed of the scaled masses): the strain a specimen takes per wave transit. On the
/// three fracturing specimens the peak load stays within 2 % of a slower reference up to
/// about 6e-6 and drifts by 2-5 % from about 1.2e-5 (docs/speed-vs-accuracy.md).
pub const LOADING_SPEED_MAX: f64 = 1e-5;

/// The smallest angle of a triangle without a warning [degrees]: a constant-strain triangle's
/// shape error grows as 1/sin of its smallest angle and a flat one sets a short step. The
/// Griffith plate's coarse mesh has a triangle of 7.9 degrees and fails within 4.7 % of
/// fracture mechanics; below 5 degrees (aspect ratios above about 12) a triangle is a sliver.
pub const MIN_ANGLE_DEG: f64 = 5.0;

/// The indicators decided by the problem: per joint material the process zone in modes I and
/// II and the joints' compliance, the mesh's quality, and the input values outside the
/// field's range.
pub fn predict(
    scene: &Scene,
    model: &Model,
    elements: &Elements,
    fracturing: &Fracturing,
) -> Vec<Indicator> {
    let mut out = fracture_indicators(scene, model, elements, fracturing);
    if !model.triangles.is_empty() {
        out.push(mesh_quality(model, elements));
    }
    if scene.analysis == crate::input::scene::Analysis::Dynamic {
        out.extend(loading_speed(scene, model, elements));
    }
    out.push(crate::problem::plausibility::units(scene));
    out
}

/// Young's modulus `E` and the plane modulus `E'` (`E / (1 - nu^2)` in plane strain) of
/// triangle `t`.
fn moduli(elements: &Elements, t: u32) -> (f64, f64) {
    let m = &elements.materials[elements.tris[t as usize].material as usize].material;
    let e = m.youngs_modulus;
    let nu = m.poisson_ratio;
    match m.plane {
        PlaneKind::Strain => (e, e / (1.0 - nu * nu)),
        PlaneKind::Stress => (e, e),
    }
}

/// The median of `v` (sorted in place); 0 when empty.
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The joints of one joint material: per joint `(h, l_ch I, l_ch II, E / p)`.
struct MaterialJoints {
    h: Vec<f64>,
    l_i: Vec<f64>,
    l_ii: Vec<f64>,
    compliance: Vec<f64>,
}

/// Process zone (modes I and II) and joint compliance per joint material.
fn fracture_indicators(
    scene: &Scene,
    model: &Model,
    elements: &Elements,
    fracturing: &Fracturing,
) -> Vec<Indicator> {
    let (Some(section), Some(set)) = (&scene.fracture, &fracturing.set) else {
        return Vec::new();
    };
    let list = section.material_list();
    // the named material of each joint (a heterogeneous one gives each joint its own row)
    let named = crate::problem::joints::global_joints(&fracturing.bodies, model);
    let mut per: Vec<MaterialJoints> = (0..list.len())
        .map(|_| MaterialJoints {
            h: Vec::new(),
            l_i: Vec::new(),
            l_ii: Vec::new(),
            compliance: Vec::new(),
        })
        .collect();
    for (j, joint) in named.iter().enumerate() {
        let row = &set.materials[set.material[j] as usize];
        let [t1, t2] = set.triangles[j];
        let ((e1, ep1), (e2, ep2)) = (moduli(elements, t1), moduli(elements, t2));
        let (e, ep) = (e1.max(e2), ep1.max(ep2));
        let m = &mut per[joint.material as usize];
        m.h.push(set.ref_length[j]);
        m.l_i.push(ep * row.g_i / (row.ft * row.ft));
        m.l_ii.push(ep * row.g_ii / (row.cohesion * row.cohesion));
        m.compliance.push(e / row.p);
    }
    let mut out = Vec::new();
    for (m, joints) in list.iter().zip(per.iter_mut()) {
        if joints.h.is_empty() {
            continue;
        }
        let path = m.path();
        let (h_min, h_max) = min_max(&joints.h);
        let h_med = median(&mut joints.h);
        let hs =
            json!({"joints": joints.h.len(), "h_min": h_min, "h_median": h_med, "h_max": h_max});
        for (mode, l) in [("i", &mut joints.l_i), ("ii", &mut joints.l_ii)] {
            out.push(process_zone(&path, mode, l, h_min, &hs));
        }
        let (_, worst) = min_max(&joints.compliance);
        out.push(joint_compliance(&path, worst));
    }
    out
}

/// The smallest and the largest of `v` (0, 0 when empty).
fn min_max(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// The process-zone indicator of one joint material in mode `mode` (`"i"` or `"ii"`):
/// `l_ch / h` with `l_ch` the median over its joints (they differ with drawn strengths) and
/// `h` the shortest joint.
fn process_zone(
    path: &str,
    mode: &str,
    l: &mut [f64],
    h_min: f64,
    hs: &serde_json::Value,
) -> Indicator {
    let (l_min, l_max) = min_max(l);
    let l_med = median(l);
    let ratio = l_med / h_min;
    let (what, g, f) = if mode == "i" {
        ("E' G_I / ft^2", "fracture_energy_i", "tensile_strength")
    } else {
        ("E' G_II / c^2", "fracture_energy_ii", "cohesion")
    };
    let mut details = hs.clone();
    details["l_ch_min"] = json!(l_min);
    details["l_ch_median"] = json!(l_med);
    details["l_ch_max"] = json!(l_max);
    let mut ind = Indicator {
        name: format!("process_zone_{mode}"),
        subject: path.to_string(),
        measure: format!("l_ch / h (l_ch = {what}, h the shortest joint)"),
        value: ratio,
        threshold: PROCESS_ZONE_MIN,
        good: Good::AtLeast,
        meaning: format!(
            "how many joints the mode-{} process zone spans: below {PROCESS_ZONE_MIN} the \
             elements cannot resolve it and peak loads come out too high",
            mode.to_uppercase()
        ),
        warning: None,
        details,
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "{path}'s shortest joints are {} long, {:.2} times l_ch = {} in mode {}: the \
             elements cannot resolve the process zone and the strength comes out too high; \
             refine where the crack grows to {} or less, or raise {path}.{g} / lower {path}.{f}",
            length(h_min),
            h_min / l_med,
            length(l_med),
            mode.to_uppercase(),
            length(l_med / PROCESS_ZONE_MIN),
        ));
    }
    ind
}

/// The joint-compliance indicator of one joint material: the largest `E / p` over its joints.
fn joint_compliance(path: &str, worst: f64) -> Indicator {
    let mut ind = Indicator {
        name: "joint_compliance".into(),
        subject: path.to_string(),
        measure: "E / p (per intact joint crossed, the strain it adds over the bulk strain)".into(),
        value: worst,
        threshold: JOINT_COMPLIANCE_MAX,
        good: Good::AtMost,
        meaning: "the artificial compliance of intact joints: a triangle mesh crosses about 2 \
                  joints per element, so the exploded region is about 2 E/p softer"
            .into(),
        warning: None,
        details: json!({"young_over_penalty": worst}),
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "{path}.penalty_normal is {:.2} E: the intact joints make the exploded region about \
             {:.0} % softer (stiffness, wave speeds and pre-peak displacements are off by that \
             much); raise {path}.penalty_normal (and penalty_tangential) to 10 E or more (the \
             stable step shrinks as 1 / sqrt(p))",
            1.0 / worst,
            100.0 * (2.0 * worst / (1.0 + 2.0 * worst)),
        ));
    }
    ind
}

/// The three angles of triangle `t` [radians] and its longest edge over its shortest
/// altitude.
fn shape(x: &[[f64; 2]], t: &[u32; 3]) -> (f64, f64) {
    let p = t.map(|i| x[i as usize]);
    let e = |a: usize, b: usize| [p[b][0] - p[a][0], p[b][1] - p[a][1]];
    let len = |v: [f64; 2]| v[0].hypot(v[1]);
    let (a, b, c) = (e(0, 1), e(1, 2), e(2, 0));
    let area2 = (a[0] * (-c[1]) - a[1] * (-c[0])).abs();
    let (la, lb, lc) = (len(a), len(b), len(c));
    let angle = |u: [f64; 2], v: [f64; 2]| {
        let d = -(u[0] * v[0] + u[1] * v[1]);
        let cross = u[0] * v[1] - u[1] * v[0];
        cross.abs().atan2(d)
    };
    let smallest = angle(a, b).min(angle(b, c)).min(angle(c, a));
    let longest = la.max(lb).max(lc);
    (smallest, longest * longest / area2)
}

/// The mesh's smallest angle, largest aspect ratio and the triangle that sets the step.
fn mesh_quality(model: &Model, elements: &Elements) -> Indicator {
    let x = &model.x0;
    let (angle, aspect, worst) = (0..model.triangles.len())
        .into_par_iter()
        .map(|t| {
            let (a, r) = shape(x, &model.triangles[t]);
            (a, r, t)
        })
        .reduce(
            || (f64::INFINITY, 0.0, usize::MAX),
            |p, q| {
                let (a, r) = (p.0.min(q.0), p.1.max(q.1));
                let t = if q.0 < p.0 || (q.0 == p.0 && q.2 < p.2) {
                    q.2
                } else {
                    p.2
                };
                (a, r, t)
            },
        );
    let mut bounds: Vec<f64> = (0..elements.len())
        .into_par_iter()
        .map(|t| elements.frequency_bound(TriId(t as u32), x))
        .collect();
    // the first triangle of the largest bound
    let (stepper, w_max) = bounds
        .iter()
        .enumerate()
        .fold((0, 0.0), |b, (t, &w)| if w > b.1 { (t, w) } else { b });
    let w_med = median(&mut bounds);
    let deg = angle.to_degrees();
    let (stepper_angle, _) = shape(x, &model.triangles[stepper]);
    let mut ind = Indicator {
        name: "mesh_quality".into(),
        subject: "mesh".into(),
        measure: "the smallest angle of a triangle [degrees]".into(),
        value: deg,
        threshold: MIN_ANGLE_DEG,
        good: Good::AtLeast,
        meaning: "flat triangles are stiff and inaccurate and set a short stable step".into(),
        warning: None,
        details: json!({
            "smallest_angle_deg": deg,
            "smallest_angle_triangle": worst,
            "largest_aspect_ratio": aspect,
            "step_triangle": stepper,
            "step_triangle_smallest_angle_deg": stepper_angle.to_degrees(),
            "step_triangle_bound_over_median": w_max / w_med,
        }),
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "triangle {worst} has an angle of {deg:.1} degrees (aspect ratio up to {aspect:.1}): \
             remesh with a smallest angle of {MIN_ANGLE_DEG} degrees or more (Gmsh: \
             Mesh.Algorithm 6 or 5, and Mesh.OptimizeNetgen)"
        ));
    }
    ind
}

/// The loading-speed indicator of a dynamic scene that moves walls or prescribes velocities:
/// the fastest of them ([`crate::problem::strains::fastest_loading`]) over the slowest P-wave speed `sqrt((lambda* + 2 mu) / rho)` of the
/// bodies, divided by the square root of the mass scaling factor.
fn loading_speed(scene: &Scene, model: &Model, elements: &Elements) -> Option<Indicator> {
    let (v, _) = crate::problem::strains::fastest_loading(scene, model);
    if v <= 0.0 || elements.materials.is_empty() {
        return None;
    }
    let c0 = elements
        .materials
        .iter()
        .map(|c| ((c.lam + 2.0 * c.mu) / c.rho).sqrt())
        .fold(f64::INFINITY, f64::min);
    let factor = model.mass_scaling.as_ref().map_or(1.0, |m| m.0);
    let c = c0 / factor.sqrt();
    let ratio = v / c;
    let mut ind = Indicator {
        name: "loading_speed".into(),
        subject: "loading".into(),
        measure: "the fastest wall or prescribed speed / the P-wave speed".into(),
        value: ratio,
        threshold: LOADING_SPEED_MAX,
        good: Good::AtMost,
        meaning: "the strain a specimen takes per wave transit: above the threshold the \
                  peak load of a fracturing specimen rises with the loading rate"
            .into(),
        warning: None,
        details: json!({"speed": v, "p_wave_speed": c0, "mass_scaling_factor": factor}),
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "the loading speed {v:.3e} m/s is {ratio:.2e} of the P-wave speed {c:.4e} m/s{}: \
             a peak load comes out several percent too high; load {:.1} times slower \
             (loading.rate, wall and boundary velocities) or check that the peak agrees with \
             a run at half the rate",
            if factor > 1.0 {
                " (with the mass scaling)"
            } else {
                ""
            },
            ratio / LOADING_SPEED_MAX
        ));
    }
    Some(ind)
}

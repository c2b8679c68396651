//! The result block of a run (`summary.json`'s `result`, and lines at the end of the
//! console): what the run found, read back from its own files at the end (so a resumed or
//! distributed run reports the whole run): the load-displacement curve
//! ([`crate::output::curve`]), whether the specimen failed and by which criterion, the peak
//! load and, for a specimen between platens, the peak stress, the strain at the peak and the
//! modulus of the loading branch; the broken joints by mode and the extent of the crack
//! pattern (`fractures.csv`).

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::output::curve::{Curve, CurveError, curve};
use crate::problem::model::Model;

/// The load drop after the largest load that, with a broken joint, marks a failed specimen:
/// the load falls to this fraction of its largest value or below.
pub const FAILURE_DROP: f64 = 0.8;

/// The window of the loading branch whose slope is the stiffness: loads between these
/// fractions of the largest load, before it.
pub const LOADING_BRANCH: [f64; 2] = [0.1, 0.5];

/// The failure criterion, in words.
pub fn criterion() -> String {
    format!("a joint broke and the load then fell to {FAILURE_DROP} of its largest value or below")
}

/// The failure criterion, short, for the console.
fn criterion_short() -> String {
    format!("a joint broke, then the load fell to {FAILURE_DROP} of its peak")
}

/// The result block (`summary.json`'s `result`).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RunResult {
    /// Where the curve comes from; `None` when the run has no load-displacement curve.
    pub curve: Option<CurveSource>,
    /// Whether the specimen failed ([`criterion`]); `None` without a curve.
    pub failed: Option<bool>,
    /// The failure criterion, in words.
    pub criterion: String,
    /// The largest load of the curve [N] (a peak only when the specimen failed).
    pub largest_load: Option<f64>,
    /// The load at the end of the run [N].
    pub final_load: Option<f64>,
    /// The peak load [N]: the largest load of a specimen that failed, else `None`.
    pub peak_load: Option<f64>,
    /// The displacement at the peak [m].
    pub displacement_at_peak: Option<f64>,
    /// The slope of the loading branch [N/m]: a least-squares line through the points with
    /// loads between [`LOADING_BRANCH`] of the largest load, before it.
    pub stiffness: Option<f64>,
    /// A specimen between platens: its shape and size, and its stresses.
    pub specimen: Option<Specimen>,
    /// Joints broken during the run.
    pub broken_joints: usize,
    /// Their count by mode (`I`, `II`, `mixed`).
    pub broken_by_mode: ByMode,
    /// The extent of the crack pattern: the smallest and the largest `x` and `y` of the
    /// broken joints' midpoints [m]; `None` when none broke.
    pub crack_extent: Option<Extent>,
    /// Whether the run wrote `fractures.csv` (a scene with joints).
    #[serde(skip)]
    pub joints: bool,
}

/// The file and columns of the curve.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct CurveSource {
    /// `walls.csv` or `histories.csv`.
    pub file: String,
    /// The load's column.
    pub load: String,
    /// The displacement's columns (summed).
    pub displacement: Vec<String>,
    /// Rows of the curve.
    pub points: usize,
}

/// A specimen between platens: its nominal stress and strain.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Specimen {
    /// `"disc"` (a Brazilian test), `"rectangle"` (a compression test) or `"other"`: from
    /// the bodies' area against their extents.
    pub shape: String,
    /// The extent across the load [m] (a disc's diameter).
    pub width: f64,
    /// The extent along the load [m].
    pub height: f64,
    /// The thickness [m] (area-weighted over the triangles).
    pub thickness: f64,
    /// The stress's formula: `2 P / (pi D t)` (the Brazilian tensile strength) for a disc,
    /// `P / (W t)` otherwise.
    pub stress_measure: String,
    /// The stress at the peak [Pa] (a specimen that failed).
    pub peak_stress: Option<f64>,
    /// The nominal strain at the peak: the platens' displacement over the height.
    pub strain_at_peak: Option<f64>,
    /// The modulus of the loading branch [Pa]: `stiffness H / (W t)`, for a rectangle only
    /// (a disc's loading branch has no modulus of its own).
    pub modulus: Option<f64>,
}

/// Broken joints by mode.
#[derive(Debug, Clone, Copy, Default, Serialize, PartialEq)]
pub struct ByMode {
    /// Mode I (opening).
    #[serde(rename = "I")]
    pub i: usize,
    /// Mode II (sliding).
    #[serde(rename = "II")]
    pub ii: usize,
    /// Mixed mode.
    pub mixed: usize,
}

/// An extent in the plane [m].
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Extent {
    /// Smallest and largest `x`.
    pub x: [f64; 2],
    /// Smallest and largest `y`.
    pub y: [f64; 2],
}

/// The result block of the run whose files are in `dir`, on `model`; `None` when the run has
/// neither a curve nor broken joints. A damaged file is an error.
pub fn read(dir: &Path, model: &Model) -> Result<Option<RunResult>, String> {
    let c = match curve(dir, None, None) {
        Ok(c) => Some(c),
        Err(CurveError::NoData(_)) => None,
        Err(CurveError::Bad(m)) => return Err(m),
    };
    let file = dir.join("fractures.csv");
    let joints = file.exists();
    let (broken_joints, broken_by_mode, crack_extent) = fractures(&file)?;
    if c.is_none() && broken_joints == 0 {
        return Ok(None);
    }
    let mut r = RunResult {
        curve: None,
        failed: None,
        criterion: criterion(),
        largest_load: None,
        final_load: None,
        peak_load: None,
        displacement_at_peak: None,
        stiffness: None,
        specimen: None,
        broken_joints,
        broken_by_mode,
        crack_extent,
        joints,
    };
    if let Some(c) = c.filter(|c| !c.points.is_empty()) {
        of_curve(&mut r, &c, model);
    }
    Ok(Some(r))
}

/// The curve's part of the block.
fn of_curve(r: &mut RunResult, c: &Curve, model: &Model) {
    let p = &c.points;
    let k = (0..p.len()).fold(0, |k, i| if p[i].1 > p[k].1 { i } else { k });
    let (u_peak, largest) = p[k];
    let lowest_after = p[k..].iter().map(|q| q.1).fold(f64::INFINITY, f64::min);
    let failed = r.broken_joints > 0 && lowest_after <= FAILURE_DROP * largest;
    r.curve = Some(CurveSource {
        file: c.file.clone(),
        load: c.load_column.clone(),
        displacement: c.displacement_columns.clone(),
        points: p.len(),
    });
    r.failed = Some(failed);
    r.largest_load = Some(largest);
    r.final_load = p.last().map(|q| q.1);
    if failed {
        r.peak_load = Some(largest);
        r.displacement_at_peak = Some(u_peak);
    }
    r.stiffness = loading_slope(&p[..=k], largest);
    if c.platens {
        r.specimen = Some(specimen(model, &c.axis, r));
    }
}

/// The least-squares slope of load against displacement over the points of `rising` whose
/// load lies within [`LOADING_BRANCH`] of `largest`; `None` with fewer than 3 such points
/// or no spread of displacement.
pub fn loading_slope(rising: &[(f64, f64)], largest: f64) -> Option<f64> {
    let [lo, hi] = LOADING_BRANCH.map(|f| f * largest);
    let pts: Vec<(f64, f64)> = rising
        .iter()
        .copied()
        .filter(|q| q.1 >= lo && q.1 <= hi)
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let (mu, mp) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), q| (a + q.0 / n, b + q.1 / n));
    let (suu, sup) = pts.iter().fold((0.0, 0.0), |(a, b), q| {
        (a + (q.0 - mu).powi(2), b + (q.0 - mu) * (q.1 - mp))
    });
    (suu > 0.0).then(|| sup / suu).filter(|s| s.is_finite())
}

/// The specimen between the platens loading along `axis`: every body of `model`.
fn specimen(model: &Model, axis: &str, r: &RunResult) -> Specimen {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for x in &model.x0 {
        for d in 0..2 {
            lo[d] = lo[d].min(x[d]);
            hi[d] = hi[d].max(x[d]);
        }
    }
    let (mut area, mut at) = (0.0, 0.0);
    for (t, tri) in model.triangles.iter().enumerate() {
        let a = fdem_mesh::tri_area(&model.x0, *tri).abs();
        area += a;
        at += a * model.tri_thickness[t];
    }
    let thickness = if area > 0.0 { at / area } else { 0.0 };
    let along = usize::from(axis == "y");
    let (width, height) = (hi[1 - along] - lo[1 - along], hi[along] - lo[along]);
    let shape = shape_of(area, width, height);
    let disc = shape == "disc";
    let stress = |p: f64| {
        if disc {
            2.0 * p / (std::f64::consts::PI * width * thickness)
        } else {
            p / (width * thickness)
        }
    };
    Specimen {
        shape: shape.into(),
        width,
        height,
        thickness,
        stress_measure: if disc { "2 P / (pi D t)" } else { "P / (W t)" }.into(),
        peak_stress: r.peak_load.map(stress),
        strain_at_peak: r.displacement_at_peak.map(|u| u / height),
        modulus: (shape == "rectangle")
            .then(|| r.stiffness.map(|s| s * height / (width * thickness)))
            .flatten(),
    }
}

/// The shape of a specimen of area `area` and extents `w` by `h`: a disc when the extents
/// agree within 2 % and the area is `pi w h / 4` within 3 % (a polygonal mesh of a circle is
/// a little smaller), a rectangle when the area is `w h` within 1 %, else other.
pub fn shape_of(area: f64, w: f64, h: f64) -> &'static str {
    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * a.abs().max(b.abs());
    if close(w, h, 0.02) && close(area, std::f64::consts::FRAC_PI_4 * w * h, 0.03) {
        "disc"
    } else if close(area, w * h, 0.01) {
        "rectangle"
    } else {
        "other"
    }
}

/// The broken joints of `fractures.csv` (none without the file): their count, by mode, and
/// the extent of their midpoints.
fn fractures(path: &Path) -> Result<(usize, ByMode, Option<Extent>), String> {
    if !path.exists() {
        return Ok((0, ByMode::default(), None));
    }
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = |name: &str| {
        head.iter()
            .position(|h| h.trim() == name)
            .ok_or_else(|| format!("{}: no column {name}", path.display()))
    };
    let (cx, cy, cm) = (col("x")?, col("y")?, col("mode")?);
    let mut by = ByMode::default();
    let mut ext: Option<Extent> = None;
    let mut n = 0;
    for (i, l) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let f: Vec<&str> = l.split(',').map(str::trim).collect();
        let bad = || format!("{} line {}: not a fracture row", path.display(), i + 2);
        let num = |c: usize| f.get(c).and_then(|s| s.parse::<f64>().ok()).ok_or_else(bad);
        let (x, y) = (num(cx)?, num(cy)?);
        match f.get(cm).copied() {
            Some("I") => by.i += 1,
            Some("II") => by.ii += 1,
            Some("mixed") => by.mixed += 1,
            _ => return Err(bad()),
        }
        n += 1;
        let e = ext.get_or_insert(Extent {
            x: [x, x],
            y: [y, y],
        });
        e.x = [e.x[0].min(x), e.x[1].max(x)];
        e.y = [e.y[0].min(y), e.y[1].max(y)];
    }
    Ok((n, by, ext))
}

/// The console lines of the block.
pub fn describe(r: &RunResult) -> String {
    let kn = |p: f64| format!("{:.4} kN", 1e-3 * p);
    let mm = |u: f64| format!("{:.4} mm", 1e3 * u);
    let mut s = match (r.failed, r.peak_load, r.largest_load) {
        (Some(true), Some(p), _) => format!(
            "result: failed ({}): peak load {} at {}",
            criterion_short(),
            kn(p),
            mm(r.displacement_at_peak.unwrap_or(0.0))
        ),
        (Some(false), _, Some(p)) if r.joints => format!(
            "result: not failed (no joint broke, or the load never fell to {FAILURE_DROP} of \
             its largest): largest load {}, final {}",
            kn(p),
            kn(r.final_load.unwrap_or(0.0))
        ),
        (Some(false), _, Some(p)) => format!(
            "result: no joints, so no failure: largest load {}, final {}",
            kn(p),
            kn(r.final_load.unwrap_or(0.0))
        ),
        _ => "result: no load-displacement curve".into(),
    };
    let mut parts = Vec::new();
    if let Some(sp) = &r.specimen {
        if let Some(st) = sp.peak_stress {
            let what = if sp.shape == "disc" {
                "tensile strength"
            } else {
                "peak stress"
            };
            parts.push(format!(
                "{what} {} = {:.4} MPa at strain {:.3e}",
                sp.stress_measure,
                1e-6 * st,
                sp.strain_at_peak.unwrap_or(0.0)
            ));
        }
        if let Some(m) = sp.modulus {
            parts.push(format!("loading-branch modulus {:.4} GPa", 1e-9 * m));
        }
    }
    if let Some(k) = r.stiffness {
        parts.push(format!("stiffness {k:.4e} N/m"));
    }
    if !parts.is_empty() {
        let _ = write!(s, "\n  {}", parts.join("; "));
    }
    if r.joints {
        let b = &r.broken_by_mode;
        let _ = write!(
            s,
            "\n  {} joints broken (I {}, II {}, mixed {})",
            r.broken_joints, b.i, b.ii, b.mixed
        );
        if let Some(e) = &r.crack_extent {
            let _ = write!(
                s,
                " over x {:.2}..{:.2} mm, y {:.2}..{:.2} mm",
                1e3 * e.x[0],
                1e3 * e.x[1],
                1e3 * e.y[0],
                1e3 * e.y[1]
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_loading_slope_is_the_least_squares_line_of_the_window() {
        // a line of slope 2e6 N/m with a flat start below 10 % and a knee above 50 %
        let mut p: Vec<(f64, f64)> = (0..=100)
            .map(|i| (1e-6 * i as f64, 2.0 * i as f64))
            .collect();
        p.insert(0, (0.0, 0.0));
        assert!((loading_slope(&p, 200.0).unwrap() - 2e6).abs() < 1e-6);
        // too few points in the window
        assert_eq!(loading_slope(&p[..3], 200.0), None);
    }

    #[test]
    fn shapes_follow_from_the_area_and_the_extents() {
        let pi4 = std::f64::consts::FRAC_PI_4;
        assert_eq!(shape_of(pi4 * 0.05 * 0.05 * 0.995, 0.05, 0.05), "disc");
        assert_eq!(shape_of(0.05 * 0.1, 0.05, 0.1), "rectangle");
        assert_eq!(shape_of(0.5 * 0.05 * 0.1, 0.05, 0.1), "other");
        // a square is not a disc
        assert_eq!(shape_of(0.05 * 0.05, 0.05, 0.05), "rectangle");
    }

    #[test]
    fn a_damaged_fractures_file_is_an_error_naming_the_line() {
        let d = std::env::temp_dir().join(format!("fdem-result-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let f = d.join("fractures.csv");
        std::fs::write(&f, "time,x,y,mode\n1,0.001,0.002,I\n1,-0.001,0.003,mixed\n").unwrap();
        let (n, by, e) = fractures(&f).unwrap();
        assert_eq!((n, by.i, by.ii, by.mixed), (2, 1, 0, 1));
        assert_eq!(e.unwrap().x, [-0.001, 0.001]);
        std::fs::write(&f, "time,x,y,mode\n1,0.001,0.002,III\n").unwrap();
        assert!(fractures(&f).unwrap_err().contains("line 2"));
        std::fs::remove_dir_all(&d).unwrap();
    }
}

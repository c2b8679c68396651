//! `fdem plot load-displacement DIR...`: the load-displacement curve of one or more runs as
//! `load_displacement.png` (and `.svg`), read from the run folders' CSV files.
//!
//! The curve is the run's own ([`fdem_solver::output::curve`]: the platens of `walls.csv`,
//! else a loaded group of `histories.csv`), unless `--load` and `--displacement` name the
//! columns.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Subcommand;
use fdem_solver::output::curve::Curve;

use crate::plot::{Plot, Scale, Series};

/// Plots of run results.
#[derive(Subcommand)]
pub enum PlotCommand {
    /// Load against displacement (platens from walls.csv, or a loaded group's reaction and
    /// displacement from histories.csv); several run folders give one curve each.
    LoadDisplacement {
        /// Run folders (the --out of fdem run).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Load column (in walls.csv or histories.csv), e.g. "reaction_y[load]".
        #[arg(long)]
        load: Option<String>,
        /// Displacement column of the same file, e.g. "u_y[load]".
        #[arg(long)]
        displacement: Option<String>,
        /// Output file stem (default DIR/load_displacement for the first DIR): writes .png
        /// and .svg, making its folder when missing.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Chart title (default: the first clause of the first run's scene title, cut to the
        /// chart's width at a comma or word with an ellipsis).
        #[arg(long)]
        title: Option<String>,
    },
    /// Nominal stress against nominal strain of specimens between platens (the platens' load
    /// and closure scaled by the specimen's size, from summary.json's "result"): a disc's
    /// Brazilian stress 2P/(pi D t), otherwise P/(W t), against the closure over the height.
    StressStrain {
        /// Run folders (the --out of fdem run) of specimens between platens.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output file stem (default DIR/stress_strain for the first DIR): writes .png and
        /// .svg, making its folder when missing.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Chart title (default as for load-displacement).
        #[arg(long)]
        title: Option<String>,
    },
}

/// Runs a plot command.
pub fn run(cmd: PlotCommand) -> Result<()> {
    match cmd {
        PlotCommand::LoadDisplacement {
            dirs,
            load,
            displacement,
            out,
            title,
        } => {
            let paths = load_displacement(
                &dirs,
                load.as_deref(),
                displacement.as_deref(),
                out.as_deref(),
                title,
            )?;
            for p in paths {
                println!("{}", p.display());
            }
            Ok(())
        }
        PlotCommand::StressStrain { dirs, out, title } => {
            for p in stress_strain(&dirs, out.as_deref(), title)? {
                println!("{}", p.display());
            }
            Ok(())
        }
    }
}

/// The curve of run folder `dir` ([`fdem_solver::output::curve`]): a damaged file, a missing
/// column or a folder without curves is bad input.
fn curve(dir: &Path, load: Option<&str>, disp: Option<&str>) -> Result<Curve> {
    fdem_solver::output::curve::curve(dir, load, disp).map_err(|e| crate::bad_input(e.to_string()))
}

/// The default title of a run folder's chart: the first clause (up to a `:` or `;`) of its
/// scene's title (the scene file named in summary.json), else the scene file's name, else the
/// folder's name. The chart cuts a title wider than itself at a clause or word, with an
/// ellipsis.
fn default_title(dir: &Path) -> String {
    let scene = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|s| serde_json::from_str::<serde_json::Value>(&s).ok())
        .and_then(|s| s.get("scene")?.as_str().map(PathBuf::from));
    let title = scene.as_ref().and_then(|p| {
        let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(p).ok()?).ok()?;
        let t = v.get("title")?.as_str()?;
        // The first clause: titles are long descriptions.
        let short = t.split([':', ';']).next().unwrap_or(t).trim();
        (!short.is_empty()).then(|| short.to_string())
    });
    let name = |p: &Path| {
        p.file_stem()
            .map(|n| n.to_string_lossy().into_owned())
            .filter(|n| !n.is_empty())
    };
    title
        .or_else(|| scene.as_deref().and_then(name))
        .or_else(|| name(dir))
        .unwrap_or_else(|| "load-displacement".into())
}

/// Draws the load-displacement curves of `dirs` into `out` (default
/// `dirs[0]/load_displacement`): returns the files written (PNG and SVG). Loads in kN,
/// displacements in mm.
pub fn load_displacement(
    dirs: &[PathBuf],
    load: Option<&str>,
    disp: Option<&str>,
    out: Option<&Path>,
    title: Option<String>,
) -> Result<Vec<PathBuf>> {
    let mut series = Vec::new();
    let mut labels = None;
    for d in dirs {
        let c = curve(d, load, disp)?;
        let name = run_name(d);
        series.push(Series {
            name,
            points: c.points.iter().map(|(u, p)| (1e3 * u, 1e-3 * p)).collect(),
        });
        labels.get_or_insert((c.x_label, c.y_label));
    }
    let (x_label, y_label) = labels.unwrap_or_default();
    let stem = out.map_or_else(|| dirs[0].join("load_displacement"), Path::to_path_buf);
    draw(
        &stem,
        title.unwrap_or_else(|| default_title(&dirs[0])),
        x_label,
        y_label,
        series,
    )
}

/// A run folder's name, for a chart's legend.
fn run_name(d: &Path) -> String {
    d.file_name()
        .map_or_else(|| d.display().to_string(), |n| n.to_string_lossy().into())
}

/// Draws `series` into `stem` (.png and .svg, making its folder when missing): returns the
/// files written.
fn draw(
    stem: &Path,
    title: String,
    x_label: String,
    y_label: String,
    series: Vec<Series>,
) -> Result<Vec<PathBuf>> {
    if let Some(parent) = stem.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).with_context(|| {
            format!(
                "making the folder {} of --out {}",
                parent.display(),
                stem.display()
            )
        })?;
    }
    let plot = Plot {
        title,
        x_label,
        y_label,
        x_scale: Scale::Linear,
        y_scale: Scale::Linear,
        series,
        y_range: None,
        lines: true,
    };
    plot.write(stem)
}

/// The specimen of run folder `dir` (`summary.json`'s `result.specimen`): the factors from
/// load to stress and from displacement to strain, and the stress's label; an error when the
/// run is not of a specimen between platens.
fn specimen_scale(dir: &Path) -> Result<(f64, f64, String)> {
    let file = dir.join("summary.json");
    let text =
        std::fs::read_to_string(&file).with_context(|| format!("reading {}", file.display()))?;
    let v: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| crate::bad_input(format!("{}: {e}", file.display())))?;
    let sp = v.pointer("/result/specimen").ok_or_else(|| {
        crate::bad_input(format!(
            "{}: no result.specimen: a stress-strain curve needs a specimen between moving \
             platens (walls in \"contact\"); plot its load instead (fdem plot load-displacement)",
            file.display()
        ))
    })?;
    let num = |k: &str| sp.get(k).and_then(|x| x.as_f64()).filter(|x| *x > 0.0);
    let (Some(w), Some(h), Some(t)) = (num("width"), num("height"), num("thickness")) else {
        return Err(crate::bad_input(format!(
            "{}: result.specimen lacks a positive width, height or thickness",
            file.display()
        )));
    };
    Ok(
        if sp.get("shape").and_then(|x| x.as_str()) == Some("disc") {
            (
                2.0 / (std::f64::consts::PI * w * t),
                1.0 / h,
                "Brazilian stress 2P/(\u{3c0}Dt) [MPa]".into(),
            )
        } else {
            (1.0 / (w * t), 1.0 / h, "stress P/(Wt) [MPa]".into())
        },
    )
}

/// Draws the nominal stress-strain curves of the specimens of `dirs` into `out` (default
/// `dirs[0]/stress_strain`): returns the files written (PNG and SVG). Stress in MPa, strain
/// in units of 1e-3.
pub fn stress_strain(
    dirs: &[PathBuf],
    out: Option<&Path>,
    title: Option<String>,
) -> Result<Vec<PathBuf>> {
    let mut series = Vec::new();
    let mut y_label = None;
    for d in dirs {
        let (to_stress, to_strain, label) = specimen_scale(d)?;
        let c = curve(d, None, None)?;
        let name = run_name(d);
        series.push(Series {
            name,
            points: c
                .points
                .iter()
                .map(|(u, p)| (1e3 * to_strain * u, 1e-6 * to_stress * p))
                .collect(),
        });
        y_label.get_or_insert(label);
    }
    let stem = out.map_or_else(|| dirs[0].join("stress_strain"), Path::to_path_buf);
    draw(
        &stem,
        title.unwrap_or_else(|| default_title(&dirs[0])),
        "strain: platen closure / height [10\u{207b}\u{b3}]".into(),
        y_label.unwrap_or_default(),
        series,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(tag: &str, files: &[(&str, &str)]) -> PathBuf {
        let d = std::env::temp_dir().join(format!("fdem-plot-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        for (name, text) in files {
            std::fs::write(d.join(name), text).unwrap();
        }
        d
    }

    #[test]
    fn platens_give_the_first_walls_force_against_the_closure() {
        let d = folder(
            "walls",
            &[(
                "walls.csv",
                "time,u_x[top],u_y[top],force_x[top],force_y[top],u_x[bottom],u_y[bottom],force_x[bottom],force_y[bottom]\n\
                 0,0,0,0,0,0,0,0,0\n\
                 1,0,-1e-6,0,-500,0,1e-6,0,500\n",
            )],
        );
        let c = curve(&d, None, None).unwrap();
        assert_eq!(c.points, vec![(0.0, 0.0), (2e-6, 500.0)]);
        assert_eq!(
            (c.x_label.as_str(), c.y_label.as_str()),
            ("platen closure [mm]", "load [kN]")
        );
        let files = load_displacement(std::slice::from_ref(&d), None, None, None, None).unwrap();
        assert!(files.iter().all(|f| f.exists()));
        // --out in a folder that does not exist yet: made
        let stem = d.join("figures").join("disc-load");
        let files =
            load_displacement(std::slice::from_ref(&d), None, None, Some(&stem), None).unwrap();
        assert_eq!(
            files,
            [
                d.join("figures/disc-load.png"),
                d.join("figures/disc-load.svg")
            ]
        );
        assert!(files.iter().all(|f| f.exists()));
        std::fs::remove_dir_all(&d).unwrap();
    }

    /// The texts of an SVG chart, in order (the title first, then the axis labels).
    fn svg_texts(svg: &Path) -> Vec<String> {
        let text = std::fs::read_to_string(svg).unwrap();
        text.split("<text")
            .skip(1)
            .map(|t| {
                let body = &t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()];
                body.trim().to_string()
            })
            .collect()
    }

    const WALLS: &str = "time,u_x[top],u_y[top],force_x[top],force_y[top]\n\
                         0,0,0,0,0\n\
                         1,0,-1e-6,0,-500\n";

    #[test]
    fn a_long_scene_title_is_cut_to_the_charts_width_and_the_axes_are_physical() {
        let clause = "Brazilian disc D = 50 mm, t = 10 mm, ring mesh h = R/12 (864 triangles), \
                      the whole disc fracturing (1260 joints), between two rigid platens closing \
                      at 2 x 0.02 m/s (ramped over 0.1 ms)";
        let d = folder("title", &[("walls.csv", WALLS)]);
        let scene = d.join("disc.json");
        std::fs::write(
            &scene,
            serde_json::json!({ "title": format!("{clause}; ft = 3 MPa") }).to_string(),
        )
        .unwrap();
        std::fs::write(
            d.join("summary.json"),
            serde_json::json!({ "scene": scene }).to_string(),
        )
        .unwrap();
        assert!(crate::plot::title_width(clause).unwrap() > crate::plot::TITLE_WIDTH);
        let files = load_displacement(std::slice::from_ref(&d), None, None, None, None).unwrap();
        let texts = svg_texts(&files[1]);
        let title = &texts[0];
        assert_eq!(
            title,
            "Brazilian disc D = 50 mm, t = 10 mm, ring mesh h = R/12 (864 triangles)\u{2026}"
        );
        assert!(crate::plot::title_width(title).unwrap() <= crate::plot::TITLE_WIDTH);
        // one moving wall: its displacement; the load without the column's name
        assert_eq!(texts[1..3], ["load [kN]", "platen displacement [mm]"]);
        assert!(
            !texts
                .iter()
                .any(|t| t.contains("force_") || t.contains("u_y"))
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn without_a_scene_title_the_chart_is_titled_by_the_scene_file_or_the_folder() {
        let d = folder("untitled", &[("walls.csv", WALLS)]);
        let files = load_displacement(std::slice::from_ref(&d), None, None, None, None).unwrap();
        let name = d.file_name().unwrap().to_string_lossy().into_owned();
        assert_eq!(svg_texts(&files[1])[0], name);
        let scene = d.join("my-specimen.json");
        std::fs::write(&scene, "{}").unwrap();
        std::fs::write(
            d.join("summary.json"),
            serde_json::json!({ "scene": scene }).to_string(),
        )
        .unwrap();
        let files = load_displacement(std::slice::from_ref(&d), None, None, None, None).unwrap();
        assert_eq!(svg_texts(&files[1])[0], "my-specimen");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_specimen_between_platens_gets_its_nominal_stress_strain_curve() {
        let d = folder(
            "stress",
            &[
                (
                    "walls.csv",
                    "time,u_x[top],u_y[top],force_x[top],force_y[top],u_x[bottom],u_y[bottom],force_x[bottom],force_y[bottom]\n\
                     0,0,0,0,0,0,0,0,0\n\
                     1,0,-1e-5,0,-2000,0,1e-5,0,2000\n",
                ),
                (
                    "summary.json",
                    r#"{"result": {"specimen": {"shape": "disc", "width": 0.05, "height": 0.05, "thickness": 0.01}}}"#,
                ),
            ],
        );
        let files = stress_strain(std::slice::from_ref(&d), None, None).unwrap();
        assert_eq!(
            files,
            [d.join("stress_strain.png"), d.join("stress_strain.svg")]
        );
        let texts = svg_texts(&files[1]);
        assert!(
            texts.iter().any(|t| t.starts_with("Brazilian stress 2P/")),
            "{texts:?}"
        );
        assert!(
            texts
                .iter()
                .any(|t| t.starts_with("strain: platen closure / height"))
        );
        // a rectangle: P / (W t); a folder without a specimen: refused, naming the fix
        std::fs::write(
            d.join("summary.json"),
            r#"{"result": {"specimen": {"shape": "rectangle", "width": 0.05, "height": 0.1, "thickness": 0.05}}}"#,
        )
        .unwrap();
        let (to_stress, to_strain, label) = specimen_scale(&d).unwrap();
        assert_eq!((to_stress, to_strain), (1.0 / (0.05 * 0.05), 1.0 / 0.1));
        assert_eq!(label, "stress P/(Wt) [MPa]");
        std::fs::write(d.join("summary.json"), r#"{"result": {}}"#).unwrap();
        let e = format!(
            "{}",
            stress_strain(std::slice::from_ref(&d), None, None).unwrap_err()
        );
        assert!(e.contains("fdem plot load-displacement"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_title_is_cut_at_a_clause_else_a_word_else_a_character() {
        // 10 px a character
        let w = |s: &str| Ok(10 * s.chars().count() as u32);
        let fit = |t: &str, max: u32| crate::plot::fit_title(t, max, w).unwrap();
        assert_eq!(fit("short title", 200), "short title");
        let t = "Block 50 x 50 mm, t = 50 mm, between platens";
        assert_eq!(fit(t, 300), "Block 50 x 50 mm, t = 50 mm\u{2026}");
        // the first clause alone is less than half the width: words instead
        assert_eq!(
            fit("A, bb cc dd ee ff gg hh", 180),
            "A, bb cc dd ee ff\u{2026}"
        );
        assert_eq!(fit("Abcdefghijklmnop", 60), "Abcde\u{2026}");
        assert_eq!(fit("Abcdefghijklmnop", 5), "\u{2026}");
    }

    #[test]
    fn histories_give_a_groups_reaction_against_its_displacement() {
        let d = folder(
            "hist",
            &[(
                "histories.csv",
                "time,reaction_x[load],reaction_y[load],u_x[load],u_y[load],kinetic\n\
                 0,0,0,0,0,0\n\
                 1,3,-700,1e-7,-1e-5,0\n",
            )],
        );
        let c = curve(&d, None, None).unwrap();
        assert_eq!(c.points, vec![(0.0, 0.0), (1e-5, 700.0)]);
        assert_eq!(
            (c.x_label.as_str(), c.y_label.as_str()),
            ("displacement of group load [mm]", "load [kN]")
        );
        // Named columns win; a missing column is an error that lists the columns.
        let c = curve(&d, Some("reaction_x[load]"), Some("u_x[load]")).unwrap();
        assert_eq!(c.points[1], (1e-7, 3.0));
        assert_eq!(
            (c.x_label.as_str(), c.y_label.as_str()),
            ("|u_x[load]| [mm]", "|reaction_x[load]| [kN]")
        );
        let e = curve(&d, Some("nope"), Some("u_x[load]")).unwrap_err();
        assert!(format!("{e}").contains("reaction_y[load]"));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_folder_without_curves_says_what_the_scene_needs() {
        let d = folder("none", &[("histories.csv", "time,kinetic\n0,0\n")]);
        let e = format!("{}", curve(&d, None, None).unwrap_err());
        assert!(
            e.contains("\"reaction\" and a \"displacement\" probe"),
            "{e}"
        );
        std::fs::remove_dir_all(&d).unwrap();
    }
}

//! `fdem plot load-displacement DIR...`: the load-displacement curve of one or more runs as
//! `load_displacement.png` (and `.svg`), read from the run folders' CSV files.
//!
//! Where the curve comes from, unless `--load` and `--displacement` name the columns:
//! - `walls.csv` with moving walls (platens): the load is the force of the first moving wall
//!   along its direction of motion, `|force_y[w]|` (or `x`), and the displacement is the sum of
//!   the moving walls' `|u_y|` (the platen closure when two platens approach each other);
//! - otherwise `histories.csv`: the first group with both `reaction_y[G]` and `u_y[G]` (then
//!   `x`): the load is `|reaction_y[G]|` (the force the prescribed nodes apply), the
//!   displacement `|u_y[G]|`.
//!
//! A column name that a file repeats (runs written before history columns were made unique)
//! is refused with the list of columns, never taken first.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Subcommand;

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
    }
}

/// A CSV file: column names and rows.
struct Table {
    path: PathBuf,
    head: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Table {
    fn read(path: &Path) -> Result<Option<Table>> {
        if !path.exists() {
            return Ok(None);
        }
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        let mut lines = text.lines();
        let head: Vec<String> = lines
            .next()
            .unwrap_or("")
            .split(',')
            .map(|s| s.trim().to_string())
            .collect();
        let mut rows = Vec::new();
        for (i, l) in lines.enumerate() {
            if l.trim().is_empty() {
                continue;
            }
            let row: Result<Vec<f64>, _> = l.split(',').map(|s| s.trim().parse::<f64>()).collect();
            let row = row.map_err(|_| {
                crate::bad_input(format!("{} line {}: not a number", path.display(), i + 2))
            })?;
            rows.push(row);
        }
        Ok(Some(Table {
            path: path.to_path_buf(),
            head,
            rows,
        }))
    }

    /// The index of column `name`; an error when the file has it more than once (runs that
    /// predate unique history columns), listing the columns.
    fn col(&self, name: &str) -> Result<Option<usize>> {
        let mut hits = self
            .head
            .iter()
            .enumerate()
            .filter(|(_, h)| *h == name)
            .map(|(i, _)| i);
        let first = hits.next();
        if let Some(second) = hits.next() {
            return Err(crate::bad_input(format!(
                "{}: the column {name} appears more than once (columns {} and {}), so it is not \
                 clear which one is meant; columns: {} (re-run the scene: runs now name such \
                 columns body/group, e.g. v_x[disc/center])",
                self.path.display(),
                first.unwrap_or(0) + 1,
                second + 1,
                self.head.join(",")
            )));
        }
        Ok(first)
    }

    fn values(&self, c: usize) -> Vec<f64> {
        self.rows
            .iter()
            .map(|r| r.get(c).copied().unwrap_or(f64::NAN))
            .collect()
    }
}

/// One run's curve: displacement [m] and load [N], and what they are.
#[derive(Debug)]
struct Curve {
    points: Vec<(f64, f64)>,
    x_label: String,
    y_label: String,
}

/// The curve of run folder `dir`.
fn curve(dir: &Path, load: Option<&str>, disp: Option<&str>) -> Result<Curve> {
    if !dir.is_dir() {
        return Err(crate::bad_input(format!(
            "{}: no such folder: give the folder of a run (the --out of fdem run)",
            dir.display()
        )));
    }
    let walls = Table::read(&dir.join("walls.csv"))?;
    let hist = Table::read(&dir.join("histories.csv"))?;
    let tables: Vec<&Table> = walls.iter().chain(hist.iter()).collect();
    if tables.is_empty() {
        return Err(crate::bad_input(format!(
            "{}: neither walls.csv nor histories.csv: is this an fdem run folder? (a scene \
             needs moving walls in \"contact\" or a \"reaction\" probe in \"histories\")",
            dir.display()
        )));
    }
    if load.is_some() || disp.is_some() {
        let (Some(l), Some(d)) = (load, disp) else {
            return Err(crate::bad_input("give both --load and --displacement"));
        };
        for t in &tables {
            if let (Some(cl), Some(cd)) = (t.col(l)?, t.col(d)?) {
                return Ok(Curve {
                    points: abs_pairs(t.values(cd), t.values(cl)),
                    x_label: format!("|{d}| [mm]"),
                    y_label: format!("|{l}| [kN]"),
                });
            }
        }
        return Err(crate::bad_input(format!(
            "{}: no file has both columns {} and {} (columns: {})",
            dir.display(),
            fdem_solver::excerpt(l),
            fdem_solver::excerpt(d),
            fdem_solver::shorten(
                &tables
                    .iter()
                    .map(|t| format!("{}: {}", t.path.display(), t.head.join(",")))
                    .collect::<Vec<_>>()
                    .join("; ")
            )
        )));
    }
    if let Some(w) = &walls {
        // Moving walls: their names from the u_y[...] columns, axis of the larger motion.
        let mut moving = Vec::new();
        for (i, h) in w.head.iter().enumerate() {
            let Some(name) = h.strip_prefix("u_x[").and_then(|s| s.strip_suffix(']')) else {
                continue;
            };
            w.col(h)?;
            let Some(iy) = w.col(&format!("u_y[{name}]"))? else {
                continue;
            };
            let last = |c: usize| {
                w.rows
                    .last()
                    .and_then(|r| r.get(c))
                    .map_or(0.0, |v| v.abs())
            };
            let (ux, uy) = (last(i), last(iy));
            if ux.max(uy) > 0.0 {
                let axis = if uy >= ux { "y" } else { "x" };
                moving.push((name.to_string(), axis));
            }
        }
        if let Some((first, axis)) = moving.first() {
            let f = w
                .col(&format!("force_{axis}[{first}]"))?
                .with_context(|| format!("{}: no force_{axis}[{first}]", w.path.display()))?;
            let mut u = vec![0.0; w.rows.len()];
            for (name, ax) in moving.iter().filter(|m| m.1 == *axis) {
                if let Some(c) = w.col(&format!("u_{ax}[{name}]"))? {
                    for (s, v) in u.iter_mut().zip(w.values(c)) {
                        *s += v.abs();
                    }
                }
            }
            let closing = moving.iter().filter(|m| m.1 == *axis).count();
            let x_label = if closing > 1 {
                "platen closure [mm]"
            } else {
                "platen displacement [mm]"
            };
            return Ok(Curve {
                points: abs_pairs(u, w.values(f)),
                x_label: x_label.into(),
                y_label: "load [kN]".into(),
            });
        }
    }
    if let Some(h) = &hist {
        for axis in ["y", "x"] {
            for (i, col) in h.head.iter().enumerate() {
                let prefix = format!("reaction_{axis}[");
                let Some(group) = col.strip_prefix(&prefix).and_then(|s| s.strip_suffix(']'))
                else {
                    continue;
                };
                // a repeated reaction or displacement column is refused, not taken first
                h.col(col)?;
                if let Some(cu) = h.col(&format!("u_{axis}[{group}]"))? {
                    return Ok(Curve {
                        points: abs_pairs(h.values(cu), h.values(i)),
                        x_label: format!("displacement of group {group} [mm]"),
                        y_label: "load [kN]".into(),
                    });
                }
            }
        }
    }
    Err(crate::bad_input(format!(
        "{}: no load-displacement data: no moving wall in walls.csv, and histories.csv has no \
         group with both a \"reaction\" and a \"displacement\" probe (add them to the scene, or \
         name the columns with --load and --displacement)",
        dir.display()
    )))
}

fn abs_pairs(x: Vec<f64>, y: Vec<f64>) -> Vec<(f64, f64)> {
    x.into_iter()
        .zip(y)
        .map(|(a, b)| (a.abs(), b.abs()))
        .collect()
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
        let name = d
            .file_name()
            .map_or_else(|| d.display().to_string(), |n| n.to_string_lossy().into());
        series.push(Series {
            name,
            points: c.points.iter().map(|(u, p)| (1e3 * u, 1e-3 * p)).collect(),
        });
        labels.get_or_insert((c.x_label, c.y_label));
    }
    let (x_label, y_label) = labels.unwrap_or_default();
    let stem = out.map_or_else(|| dirs[0].join("load_displacement"), Path::to_path_buf);
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
        title: title.unwrap_or_else(|| default_title(&dirs[0])),
        x_label,
        y_label,
        x_scale: Scale::Linear,
        y_scale: Scale::Linear,
        series,
        y_range: None,
        lines: true,
    };
    plot.write(&stem)
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

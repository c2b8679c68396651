//! A run folder's load-displacement curve, read back from its CSV files: the one source of
//! the curve for the run's result block ([`crate::run::result`]) and `fdem plot`.
//!
//! Where the curve comes from, unless the load and displacement columns are named:
//! - `walls.csv` with moving walls (platens): the load is the force of the first moving wall
//!   along its direction of motion, `|force_y[w]|` (or `x`), and the displacement is the sum of
//!   the moving walls' `|u_y|` along that axis (the platen closure when two platens approach
//!   each other);
//! - otherwise `histories.csv`: the first group with both `reaction_y[G]` and `u_y[G]` (then
//!   `x`): the load is `|reaction_y[G]|` (the force the prescribed nodes apply), the
//!   displacement `|u_y[G]|`.
//!
//! A column name that a file repeats (runs written before history columns were made unique)
//! is refused with the list of columns, never taken first.

use std::path::{Path, PathBuf};

/// Why a folder has no curve.
#[derive(Debug, Clone, PartialEq)]
pub enum CurveError {
    /// The folder holds no load-displacement data (no moving wall, no reaction probe with a
    /// displacement probe of the same group); the message says what the scene needs.
    NoData(String),
    /// A file is damaged or ambiguous, or a named column is missing: the message names the
    /// file and the fix.
    Bad(String),
}

impl std::fmt::Display for CurveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CurveError::NoData(m) | CurveError::Bad(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for CurveError {}

/// A CSV file of numbers: column names and rows.
pub struct Table {
    /// The file.
    pub path: PathBuf,
    /// The column names.
    pub head: Vec<String>,
    /// The rows.
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// The table in `path`; `None` when there is no such file.
    pub fn read(path: &Path) -> Result<Option<Table>, CurveError> {
        if !path.exists() {
            return Ok(None);
        }
        let text = std::fs::read_to_string(path)
            .map_err(|e| CurveError::Bad(format!("reading {}: {e}", path.display())))?;
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
                CurveError::Bad(format!("{} line {}: not a number", path.display(), i + 2))
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
    pub fn col(&self, name: &str) -> Result<Option<usize>, CurveError> {
        let mut hits = self
            .head
            .iter()
            .enumerate()
            .filter(|(_, h)| *h == name)
            .map(|(i, _)| i);
        let first = hits.next();
        if let Some(second) = hits.next() {
            return Err(CurveError::Bad(format!(
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

    /// The values of column `c` (NaN in a short row).
    pub fn values(&self, c: usize) -> Vec<f64> {
        self.rows
            .iter()
            .map(|r| r.get(c).copied().unwrap_or(f64::NAN))
            .collect()
    }
}

/// A run's curve: displacement [m] and load [N] (both as magnitudes), and what they are.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// `(displacement, load)` per row of the file.
    pub points: Vec<(f64, f64)>,
    /// The file the curve was read from (`walls.csv` or `histories.csv`).
    pub file: String,
    /// The load's column.
    pub load_column: String,
    /// The displacement's columns (summed: the platens' closure).
    pub displacement_columns: Vec<String>,
    /// The axis of the load (`"x"` or `"y"`; empty for named columns).
    pub axis: String,
    /// Whether the curve comes from moving walls (a specimen between platens).
    pub platens: bool,
    /// The displacement axis's label (in mm).
    pub x_label: String,
    /// The load axis's label (in kN).
    pub y_label: String,
}

/// The curve of run folder `dir`, from the named columns `load` and `disp` when given (both
/// or neither), else found as the module says.
pub fn curve(dir: &Path, load: Option<&str>, disp: Option<&str>) -> Result<Curve, CurveError> {
    if !dir.is_dir() {
        return Err(CurveError::Bad(format!(
            "{}: no such folder: give the folder of a run (the --out of fdem run)",
            dir.display()
        )));
    }
    let walls = Table::read(&dir.join("walls.csv"))?;
    let hist = Table::read(&dir.join("histories.csv"))?;
    let tables: Vec<&Table> = walls.iter().chain(hist.iter()).collect();
    if tables.is_empty() {
        return Err(CurveError::NoData(format!(
            "{}: neither walls.csv nor histories.csv: is this an fdem run folder? (a scene \
             needs moving walls in \"contact\" or a \"reaction\" probe in \"histories\")",
            dir.display()
        )));
    }
    if load.is_some() || disp.is_some() {
        return named(dir, &tables, load, disp);
    }
    if let Some(c) = walls.as_ref().map(platens).transpose()?.flatten() {
        return Ok(c);
    }
    if let Some(c) = hist.as_ref().map(reaction).transpose()?.flatten() {
        return Ok(c);
    }
    Err(CurveError::NoData(format!(
        "{}: no load-displacement data: no moving wall in walls.csv, and histories.csv has no \
         group with both a \"reaction\" and a \"displacement\" probe (add them to the scene, or \
         name the load and displacement columns)",
        dir.display()
    )))
}

fn file_name(t: &Table) -> String {
    t.path.file_name().map_or_else(
        || t.path.display().to_string(),
        |n| n.to_string_lossy().into(),
    )
}

/// The curve of the columns `load` and `disp` of the first table with both.
fn named(
    dir: &Path,
    tables: &[&Table],
    load: Option<&str>,
    disp: Option<&str>,
) -> Result<Curve, CurveError> {
    let (Some(l), Some(d)) = (load, disp) else {
        return Err(CurveError::Bad(
            "give both the load and the displacement column".into(),
        ));
    };
    for t in tables {
        if let (Some(cl), Some(cd)) = (t.col(l)?, t.col(d)?) {
            return Ok(Curve {
                points: abs_pairs(t.values(cd), t.values(cl)),
                file: file_name(t),
                load_column: l.into(),
                displacement_columns: vec![d.into()],
                axis: String::new(),
                platens: false,
                x_label: format!("|{d}| [mm]"),
                y_label: format!("|{l}| [kN]"),
            });
        }
    }
    Err(CurveError::Bad(format!(
        "{}: no file has both columns {} and {} (columns: {})",
        dir.display(),
        crate::excerpt(l),
        crate::excerpt(d),
        crate::shorten(
            &tables
                .iter()
                .map(|t| format!("{}: {}", t.path.display(), t.head.join(",")))
                .collect::<Vec<_>>()
                .join("; ")
        )
    )))
}

/// The moving walls' curve of `walls.csv` (`None`: no wall moved).
fn platens(w: &Table) -> Result<Option<Curve>, CurveError> {
    // moving walls: their names from the u_x[...] columns, axis of the larger motion
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
    let Some((first, axis)) = moving.first() else {
        return Ok(None);
    };
    let load_column = format!("force_{axis}[{first}]");
    let f = w
        .col(&load_column)?
        .ok_or_else(|| CurveError::Bad(format!("{}: no column {load_column}", w.path.display())))?;
    let mut u = vec![0.0; w.rows.len()];
    let mut columns = Vec::new();
    for (name, ax) in moving.iter().filter(|m| m.1 == *axis) {
        let c = format!("u_{ax}[{name}]");
        if let Some(k) = w.col(&c)? {
            for (s, v) in u.iter_mut().zip(w.values(k)) {
                *s += v.abs();
            }
            columns.push(c);
        }
    }
    let x_label = if columns.len() > 1 {
        "platen closure [mm]"
    } else {
        "platen displacement [mm]"
    };
    Ok(Some(Curve {
        points: abs_pairs(u, w.values(f)),
        file: file_name(w),
        load_column,
        displacement_columns: columns,
        axis: (*axis).into(),
        platens: true,
        x_label: x_label.into(),
        y_label: "load [kN]".into(),
    }))
}

/// The first loaded group's curve of `histories.csv` (`None`: no group has both a reaction
/// and a displacement column).
fn reaction(h: &Table) -> Result<Option<Curve>, CurveError> {
    for axis in ["y", "x"] {
        let prefix = format!("reaction_{axis}[");
        for (i, col) in h.head.iter().enumerate() {
            let Some(group) = col.strip_prefix(&prefix).and_then(|s| s.strip_suffix(']')) else {
                continue;
            };
            // a repeated reaction or displacement column is refused, not taken first
            h.col(col)?;
            let disp = format!("u_{axis}[{group}]");
            if let Some(cu) = h.col(&disp)? {
                return Ok(Some(Curve {
                    points: abs_pairs(h.values(cu), h.values(i)),
                    file: file_name(h),
                    load_column: col.clone(),
                    displacement_columns: vec![disp],
                    axis: axis.into(),
                    platens: false,
                    x_label: format!("displacement of group {group} [mm]"),
                    y_label: "load [kN]".into(),
                }));
            }
        }
    }
    Ok(None)
}

fn abs_pairs(x: Vec<f64>, y: Vec<f64>) -> Vec<(f64, f64)> {
    x.into_iter()
        .zip(y)
        .map(|(a, b)| (a.abs(), b.abs()))
        .collect()
}

//! A run owns its output folder: before writing its first file, a run removes every file that
//! fdem writes into a run folder ([`is_run_file`]), so that no file of an earlier run (a
//! `joints.pvd`, a `fractures.csv`, a plot) is left to be read as this run's. Files of any
//! other name are left alone, and sub-folders are never entered.

use std::path::{Path, PathBuf};

/// The fixed names of the files a run writes (with [`NUMBERED`] and the temporaries of
/// [`is_run_file`]). A new output file must be added here.
pub const FIXED: [&str; 12] = [
    "results.pvd",
    "checkpoint.fdem",
    crate::checkpoint::RUN_ID_FILE,
    "summary.json",
    "histories.csv",
    "joints.pvd",
    "fractures.csv",
    "walls.csv",
    "load_displacement.png",
    "load_displacement.svg",
    "stress_strain.png",
    "stress_strain.svg",
];

/// The numbered series a run writes: (prefix, extension) of `prefix_NNNN.extension`.
pub const NUMBERED: [(&str, &str); 3] = [("frame_", "vtu"), ("frame_", "json"), ("joints_", "vtu")];

fn is_output_name(name: &str) -> bool {
    FIXED.contains(&name)
        || NUMBERED.iter().any(|(prefix, ext)| {
            name.strip_prefix(prefix)
                .and_then(|r| r.strip_suffix(ext))
                .and_then(|r| r.strip_suffix('.'))
                .is_some_and(|digits| {
                    !digits.is_empty() && digits.bytes().all(|c| c.is_ascii_digit())
                })
        })
}

/// Whether `name` is a file fdem writes into a run folder: an output file, or the temporary
/// of one left by an interrupted write (`.NAME.tmpPID`, `NAME.part`, `STEM.part.png`).
pub fn is_run_file(name: &str) -> bool {
    if is_output_name(name) {
        return true;
    }
    if let Some(base) = name
        .strip_prefix('.')
        .and_then(|r| r.rsplit_once(".tmp"))
        .filter(|(_, pid)| !pid.is_empty() && pid.bytes().all(|c| c.is_ascii_digit()))
        .map(|(base, _)| base)
    {
        return is_output_name(base);
    }
    if let Some(base) = name.strip_suffix(".part") {
        return is_output_name(base);
    }
    if let Some(stem) = name.strip_suffix(".part.png") {
        return is_output_name(&format!("{stem}.png"));
    }
    false
}

/// Creates `dir` if needed and removes the run files in it ([`is_run_file`]); returns the
/// files removed. Other files and sub-folders are left alone.
pub fn claim(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut removed = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let Some(name) = entry.file_name().to_str().map(str::to_owned) else {
            continue;
        };
        if is_run_file(&name) && !entry.file_type()?.is_dir() {
            let p = entry.path();
            std::fs::remove_file(&p)?;
            removed.push(p);
        }
    }
    removed.sort();
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_files_are_recognised_and_others_are_not() {
        for n in [
            "results.pvd",
            "frame_0000.vtu",
            "frame_12345.json",
            "joints_0003.vtu",
            "joints.pvd",
            "histories.csv",
            "summary.json",
            "run_id.txt",
            "fractures.csv",
            "walls.csv",
            "load_displacement.png",
            "load_displacement.svg",
            "stress_strain.png",
            "stress_strain.part.png",
            ".frame_0001.vtu.tmp4242",
            ".summary.json.tmp7",
            "load_displacement.svg.part",
            "load_displacement.part.png",
        ] {
            assert!(is_run_file(n), "{n}");
        }
        for n in [
            "notes.txt",
            "scene.json",
            "frame_.vtu",
            "frame_12a.vtu",
            "frame_0001.vtu.bak",
            "my_results.pvd",
            "histories.csv.orig",
            ".scene.json.tmp1",
            ".frame_0001.vtu.tmp",
            "mesh.part",
        ] {
            assert!(!is_run_file(n), "{n}");
        }
    }

    #[test]
    fn claim_removes_run_files_only() {
        let d = std::env::temp_dir().join(format!("fdem-claim-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("frame_0000.vtu")).unwrap();
        for n in ["joints.pvd", "frame_0001.vtu", "notes.txt", "fractures.csv"] {
            std::fs::write(d.join(n), "x").unwrap();
        }
        let removed = claim(&d).unwrap();
        assert_eq!(removed.len(), 3, "{removed:?}");
        assert!(d.join("notes.txt").exists() && d.join("frame_0000.vtu").is_dir());
        assert!(!d.join("joints.pvd").exists() && !d.join("fractures.csv").exists());
        std::fs::remove_dir_all(&d).unwrap();
    }
}

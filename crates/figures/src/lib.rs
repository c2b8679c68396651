//! The measured figures of docs/validation.md, written by the tests that measure them.
//!
//! Each row of the Summary table of docs/validation.md has a stable number (its `#` column).
//! The test that checks a row calls [`record`] with the figure its "today" column shows,
//! formatted by the test; `scripts/validation_figures.py` renders the column from these files
//! (`render`) and fails when the committed table differs from them (`--check`, run by
//! `scripts/test.sh`). A row measured by several tests has numbered parts ([`record_part`]),
//! shown in order, joined by `"; "`.
//!
//! Each figure is one file, `<row>.txt` or `<row>.<part>.txt`, in [`dir`]. Files are written
//! whole (a temporary file renamed over the old one), so tests in parallel threads and in
//! several test binaries may record at once. Only a dev-dependency: no library depends on it.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The folder of the figure files: `$FDEM_FIGURES_DIR` when set, otherwise
/// `validation-figures` in the target folder (`$CARGO_TARGET_DIR`, when set at run time or at
/// build time, otherwise `target` in the workspace root). A relative path is taken from the
/// workspace root. `scripts/validation_figures.py` finds the same folder by the same rule.
pub fn dir() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let from_root = |p: PathBuf| if p.is_absolute() { p } else { root.join(p) };
    if let Some(d) = std::env::var_os("FDEM_FIGURES_DIR").filter(|d| !d.is_empty()) {
        return from_root(PathBuf::from(d));
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            option_env!("CARGO_TARGET_DIR")
                .filter(|d| !d.is_empty())
                .map(PathBuf::from)
        })
        .unwrap_or_else(|| PathBuf::from("target"));
    from_root(target).join("validation-figures")
}

/// Records the measured figure of validation row `row` (the whole "today" cell).
///
/// # Panics
/// When the text is empty or holds a line break, or the file cannot be written (the test
/// then fails, naming the file).
pub fn record(row: u32, text: impl AsRef<str>) {
    write(&format!("{row}.txt"), text.as_ref());
}

/// Records part `part` (1, 2, ...) of the figure of validation row `row`, for a row whose
/// figure comes from several tests. The parts are shown in order, joined by `"; "`, so a
/// part's text holds no `"; "`.
///
/// # Panics
/// As [`record`], and when the text holds `"; "` or `part` is 0.
pub fn record_part(row: u32, part: u32, text: impl AsRef<str>) {
    let text = text.as_ref();
    assert!(part >= 1, "validation row {row}: parts are numbered from 1");
    assert!(
        !text.contains("; "),
        "validation row {row} part {part}: a part's figure may not hold \"; \" (the parts' separator): {text:?}"
    );
    write(&format!("{row}.{part}.txt"), text);
}

/// `value` in scientific notation with `digits` after the point (`1.9e-9`), or `0` when it is
/// exactly zero.
pub fn sci(value: f64, digits: usize) -> String {
    if value == 0.0 {
        "0".to_string()
    } else {
        format!("{value:.digits$e}")
    }
}

fn write(name: &str, text: &str) {
    write_in(&dir(), name, text);
}

/// Writes `text` as the file `name` of `dir`: a temporary file of this process and call,
/// renamed over the old one, so that a reader never sees a part of it.
fn write_in(dir: &Path, name: &str, text: &str) {
    assert!(
        !text.trim().is_empty() && !text.contains(['\n', '\r']),
        "validation figure {name}: the figure must be one non-empty line: {text:?}"
    );
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let path = dir.join(name);
    let tmp = dir.join(format!(
        ".{name}.{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let result = std::fs::create_dir_all(dir)
        .and_then(|()| std::fs::write(&tmp, text.trim()))
        .and_then(|()| std::fs::rename(&tmp, &path));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        panic!("cannot write the validation figure {}: {e}", path.display());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writers_in_parallel_leave_one_whole_figure_and_no_temporary_file() {
        let dir = std::env::temp_dir().join(format!("fdem-figures-test-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let texts: Vec<String> = (0..8)
            .map(|k| format!("{k} {}", "x".repeat(10_000)))
            .collect();
        std::thread::scope(|s| {
            for t in &texts {
                let dir = &dir;
                s.spawn(move || {
                    for _ in 0..50 {
                        write_in(dir, "7.txt", t);
                    }
                });
            }
        });
        let got = std::fs::read_to_string(dir.join("7.txt")).unwrap();
        assert!(texts.contains(&got), "a mixed or partial file");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["7.txt"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    #[should_panic(expected = "one non-empty line")]
    fn a_figure_of_two_lines_is_refused() {
        write_in(&std::env::temp_dir(), "0.txt", "a\nb");
    }

    #[test]
    #[should_panic(expected = "the parts' separator")]
    fn a_part_holding_the_separator_is_refused() {
        record_part(1, 1, "a; b");
    }

    #[test]
    fn sci_writes_zero_as_zero() {
        assert_eq!(sci(0.0, 1), "0");
        assert_eq!(sci(1.94e-9, 1), "1.9e-9");
    }
}

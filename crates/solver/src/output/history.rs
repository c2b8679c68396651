//! Histories as CSV: a header of column names, then one row per record; rewritten atomically
//! at each flush, so the file on disk is always complete. A row with a value that is not
//! finite (a run going unstable, stopped at its next check) is not written, nor is any row
//! after it: the file holds the rows up to the last finite state.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::atomic::write_atomic;

/// Accumulates history rows in memory and writes `histories.csv` whole.
#[derive(Debug, Clone)]
pub struct HistoryWriter {
    path: PathBuf,
    text: String,
    columns: usize,
    /// The length of the text before its first row with a value that is not finite, if any.
    finite: Option<usize>,
}

/// The length of `text` (a header and rows) before its first row with a value that is not
/// finite, if it has one.
fn finite_length(text: &str) -> Option<usize> {
    let mut at = 0;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        let finite = |v: &str| v.trim().parse::<f64>().is_ok_and(f64::is_finite);
        if i > 0 && !line.trim().is_empty() && !line.split(',').all(finite) {
            return Some(at);
        }
        at += line.len();
    }
    None
}

impl HistoryWriter {
    /// A writer with the given column names (the first should be `time`).
    pub fn new(path: &Path, columns: &[String]) -> Self {
        let mut text = columns.join(",");
        text.push('\n');
        Self {
            path: path.to_path_buf(),
            text,
            columns: columns.len(),
            finite: None,
        }
    }

    /// Appends one row (must have as many values as columns).
    pub fn push(&mut self, row: &[f64]) {
        debug_assert_eq!(row.len(), self.columns);
        if self.finite.is_none() && !row.iter().all(|v| v.is_finite()) {
            self.finite = Some(self.text.len());
        }
        for (i, v) in row.iter().enumerate() {
            if i > 0 {
                self.text.push(',');
            }
            let _ = write!(self.text, "{v:.17e}");
        }
        self.text.push('\n');
    }

    /// The text so far (header and rows, the rows with values that are not finite too).
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Takes up the text of a run being resumed; it must begin with this writer's header.
    pub fn restore_text(&mut self, text: String) -> Result<(), String> {
        let header = self.text.lines().next().unwrap_or_default();
        if text.lines().next() != Some(header) {
            return Err("the histories' columns differ from the scene's probes".into());
        }
        self.finite = finite_length(&text);
        self.text = text;
        Ok(())
    }

    /// Writes the file whole: the header and the rows before the first with a value that
    /// is not finite.
    pub fn flush(&self) -> std::io::Result<()> {
        let end = self.finite.unwrap_or(self.text.len());
        write_atomic(&self.path, &self.text.as_bytes()[..end])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_from_the_first_that_is_not_finite_are_not_written() {
        let dir = std::env::temp_dir().join(format!("fdem-history-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("histories.csv");
        let mut w = HistoryWriter::new(&p, &["time".into(), "u".into()]);
        w.push(&[0.0, 1.0]);
        w.push(&[1.0, 2.0]);
        w.flush().unwrap();
        let finite = std::fs::read_to_string(&p).unwrap();
        assert_eq!(finite.lines().count(), 3);
        w.push(&[2.0, f64::INFINITY]);
        w.push(&[3.0, 4.0]);
        w.flush().unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), finite);
        // the text (a checkpoint's) keeps every row; taken up again, the same rows are written
        let text = w.text().to_string();
        assert_eq!(text.lines().count(), 5);
        let mut r = HistoryWriter::new(&p, &["time".into(), "u".into()]);
        r.restore_text(text).unwrap();
        std::fs::remove_file(&p).unwrap();
        r.flush().unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), finite);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

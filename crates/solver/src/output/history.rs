//! Histories as CSV: a header of column names, then one row per record; rewritten atomically
//! at each flush, so the file on disk is always complete.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::atomic::write_atomic;

/// Accumulates history rows in memory and writes `histories.csv` whole.
#[derive(Debug, Clone)]
pub struct HistoryWriter {
    path: PathBuf,
    text: String,
    columns: usize,
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
        }
    }

    /// Appends one row (must have as many values as columns).
    pub fn push(&mut self, row: &[f64]) {
        debug_assert_eq!(row.len(), self.columns);
        for (i, v) in row.iter().enumerate() {
            if i > 0 {
                self.text.push(',');
            }
            let _ = write!(self.text, "{v:.17e}");
        }
        self.text.push('\n');
    }

    /// The text so far (header and rows).
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Takes up the text of a run being resumed; it must begin with this writer's header.
    pub fn restore_text(&mut self, text: String) -> Result<(), String> {
        let header = self.text.lines().next().unwrap_or_default();
        if text.lines().next() != Some(header) {
            return Err("the histories' columns differ from the scene's probes".into());
        }
        self.text = text;
        Ok(())
    }

    /// Writes the file whole.
    pub fn flush(&self) -> std::io::Result<()> {
        write_atomic(&self.path, self.text.as_bytes())
    }
}

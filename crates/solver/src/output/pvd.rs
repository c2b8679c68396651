//! The `.pvd` collection (ParaView data): one `DataSet` entry per frame, rewritten atomically
//! after every frame so that it is valid whenever a run stops.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::write_atomic;

/// A growing `.pvd` collection of `.vtu` frames.
#[derive(Debug, Clone)]
pub struct Collection {
    path: PathBuf,
    entries: Vec<(f64, String)>,
}

impl Collection {
    /// A collection to be written at `path` (nothing is written until the first frame).
    pub fn new(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
            entries: Vec::new(),
        }
    }

    /// Adds a frame written at `file` (relative to the collection's folder) for time `t`, then
    /// rewrites the collection.
    pub fn push(&mut self, t: f64, file: &str) -> std::io::Result<()> {
        self.entries.push((t, file.to_string()));
        write_atomic(&self.path, self.xml().as_bytes())
    }

    /// The collection's XML text.
    pub fn xml(&self) -> String {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, f) in &self.entries {
            let _ = writeln!(
                s,
                "    <DataSet timestep=\"{t:e}\" group=\"\" part=\"0\" file=\"{f}\"/>"
            );
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        s
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True before the first frame.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

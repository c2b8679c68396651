//! The `.pvd` collection (ParaView data): one `DataSet` entry per frame, rewritten atomically
//! after every frame so that it is valid whenever a run stops.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::atomic::write_atomic;

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

    /// The frames so far: (time, file) of each.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// The collection at `path` with the frames `entries` (a resumed run's), rewritten.
    pub fn with_entries(path: &Path, entries: Vec<(f64, String)>) -> std::io::Result<Self> {
        let c = Self {
            path: path.to_path_buf(),
            entries,
        };
        write_atomic(&c.path, c.xml().as_bytes())?;
        Ok(c)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collection_on_disk_is_complete_after_every_frame() {
        let dir = std::env::temp_dir().join(format!("fdem-pvd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("results.pvd");
        let mut c = Collection::new(&p);
        for (i, t) in [0.0, 1.5e-3].iter().enumerate() {
            c.push(*t, &format!("frame_{i:04}.vtu")).unwrap();
            let text = std::fs::read_to_string(&p).unwrap();
            assert!(text.trim_end().ends_with("</VTKFile>"));
            assert_eq!(text.matches("<DataSet ").count(), i + 1);
        }
        assert!(
            std::fs::read_to_string(&p)
                .unwrap()
                .contains("timestep=\"1.5e-3\"")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

//! The CSV files a stage appends to during a run (`fractures.csv`, `walls.csv`): created with
//! their header by a fresh run; a resumed run reopens them, cuts them back to their length at
//! the checkpoint ([`truncate_csv`]) and appends.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::Path;

/// `dir/name` for appending rows: created with `header` (a fresh run), or opened as it is
/// (`resume`: its length is set from the checkpoint by [`truncate_csv`]). `None` when the
/// file cannot be opened.
pub fn open_csv(dir: &Path, name: &str, header: &str, resume: bool) -> Option<BufWriter<File>> {
    let path = dir.join(name);
    if resume {
        let f = OpenOptions::new().write(true).open(&path).ok()?;
        return Some(BufWriter::new(f));
    }
    let mut w = BufWriter::new(File::create(&path).ok()?);
    writeln!(w, "{header}").ok()?;
    Some(w)
}

/// The bytes written to `w` so far, flushed to the file (a checkpoint records it).
pub fn csv_length(w: &mut BufWriter<File>) -> std::io::Result<u64> {
    w.flush()?;
    w.get_mut().stream_position()
}

/// Cuts the file of `w` back to `len` bytes (its length at the checkpoint) and positions it
/// there; a file shorter than `len` is an error (it is not the file the checkpoint wrote).
pub fn truncate_csv(w: &mut BufWriter<File>, len: u64) -> Result<(), String> {
    w.flush().map_err(|e| e.to_string())?;
    let f = w.get_mut();
    let now = f.metadata().map_err(|e| e.to_string())?.len();
    if now < len {
        return Err(format!(
            "has {now} bytes, fewer than the {len} it had at the checkpoint"
        ));
    }
    f.set_len(len).map_err(|e| e.to_string())?;
    f.seek(SeekFrom::Start(len)).map_err(|e| e.to_string())?;
    Ok(())
}

//! Checkpoints: the whole state of a dynamic or relaxation run in one binary file
//! (`checkpoint.fdem` in the run's folder), from which `fdem run --resume` continues bit for
//! bit.
//!
//! The file: the magic bytes `FDEMCKPT`, the format version ([`FORMAT`], `u32`), a header
//! ([`Header`]: the fdem version, the hashes of the scene and of the mesh it belongs to, the
//! step and time, the run's id and the files of its folder that a resume needs), the length of the state, the state (sections written by [`pack`]: the run,
//! the scheme, the step control, the energy books, the system, each stage, each observer), and
//! an XXH3 checksum of header and state. It is written whole or not at all
//! ([`CheckpointWriter`]: a temporary file, fsync, rename, fsync of the folder) on a
//! background thread, so a run waits only for the encoding into memory.
//!
//! What may change between the run that wrote a checkpoint and the run that resumes it: the
//! end (`duration`), the output (`output`), the history interval (`histories.every`) and the
//! title (`crate::run::scene_hash` leaves them out); anything else is a different scene and
//! is refused.
//!
//! A checkpoint belongs to its folder: a run draws an id ([`new_run_id`]) at its first
//! checkpoint and writes it into the folder ([`RUN_ID_FILE`]) and into the header of each
//! checkpoint; a resumed run keeps it. A resume checks the id, and that the folder holds the
//! files the header lists ([`check_folder`]), before anything in the folder changes.

pub mod pack;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::thread::JoinHandle;
use std::time::Instant;

pub use pack::{Dec, DecodeError, Enc, Pack};

/// The checkpoint file's name in a run folder.
pub const FILE_NAME: &str = "checkpoint.fdem";
/// The format version this fdem writes and the only one it reads.
pub const FORMAT: u32 = 6;
/// The file of a run folder that holds the id of the run whose checkpoints it holds.
pub const RUN_ID_FILE: &str = "run_id.txt";
const MAGIC: &[u8; 8] = b"FDEMCKPT";

/// What a checkpoint says of itself before its state.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// The fdem version that wrote it.
    pub version: String,
    /// The hash of the scene it belongs to (`crate::run::scene_hash`).
    pub scene: u64,
    /// The hash of the mesh it belongs to (`crate::run::mesh_hash`).
    pub mesh: u64,
    /// Steps done.
    pub step: u64,
    /// Simulated time [s].
    pub time: f64,
    /// The run's time step [s] (a fixed step; the loaded one for an adaptive step): a
    /// resumed run keeps it, whatever its new duration.
    pub time_step: f64,
    /// The scene file (absolute), for `fdem run --resume DIR` without a scene.
    pub scene_file: PathBuf,
    /// The id of the run that wrote it (its folder's [`RUN_ID_FILE`] holds the same).
    pub run_id: u64,
    /// The files of the run's folder that a resume goes on from (the frames listed in the
    /// collections at the checkpoint, the stages' CSV files), by name.
    pub files: Vec<String>,
}

impl Header {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.version);
        e.put(&self.scene);
        e.put(&self.mesh);
        e.put(&self.step);
        e.put(&self.time);
        e.put(&self.time_step);
        e.put(&self.scene_file.to_string_lossy().into_owned());
        e.put(&self.run_id);
        e.put(&self.files);
    }

    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok(Self {
            version: d.get()?,
            scene: d.get()?,
            mesh: d.get()?,
            step: d.get()?,
            time: d.get()?,
            time_step: d.get()?,
            scene_file: PathBuf::from(d.get::<String>()?),
            run_id: d.get()?,
            files: d.get()?,
        })
    }
}

/// A checkpoint read back: its header and its state (the sections, not yet decoded).
#[derive(Debug)]
pub struct Checkpoint {
    /// The header.
    pub header: Header,
    /// The state.
    pub state: Vec<u8>,
}

/// Why a checkpoint cannot be used; the message says what to do.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CheckpointError {
    /// The checkpoint file.
    pub file: PathBuf,
    /// What is wrong.
    pub message: String,
    /// What to do.
    pub fix: String,
}

impl CheckpointError {
    /// An error of `file`: `message`, and what to do.
    pub fn new(file: &Path, message: impl Into<String>, fix: impl Into<String>) -> Self {
        Self {
            file: file.to_path_buf(),
            message: message.into(),
            fix: fix.into(),
        }
    }
}

/// The whole file: magic, format, header, state, checksum.
pub fn encode_file(header: &Header, state: &[u8]) -> Vec<u8> {
    let mut h = Enc::default();
    header.pack(&mut h);
    let mut out = Vec::with_capacity(state.len() + h.buf.len() + 40);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT.to_le_bytes());
    out.extend_from_slice(&(h.buf.len() as u64).to_le_bytes());
    out.extend_from_slice(&h.buf);
    out.extend_from_slice(&(state.len() as u64).to_le_bytes());
    out.extend_from_slice(state);
    let sum = twox_hash::XxHash3_64::oneshot(&out[MAGIC.len()..]);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// Reads and checks the checkpoint at `file`: an fdem checkpoint, of a format this fdem
/// reads, whole (its length and checksum).
pub fn read(file: &Path) -> Result<Checkpoint, CheckpointError> {
    let bytes = std::fs::read(file).map_err(|e| {
        CheckpointError::new(
            file,
            format!("cannot read the checkpoint: {e}"),
            "resume a folder that holds a checkpoint (a run writes one every `--checkpoint-every`, when it is interrupted, and at its end after a first one)",
        )
    })?;
    decode_file(file, &bytes)
}

/// [`read`] on bytes already in memory.
pub fn decode_file(file: &Path, bytes: &[u8]) -> Result<Checkpoint, CheckpointError> {
    let damaged = |what: String| {
        CheckpointError::new(
            file,
            format!("the checkpoint is damaged: {what}"),
            "resume from a complete checkpoint (the file may have been cut short or changed after it was written; an interrupted write leaves the previous checkpoint in place), or start the run afresh",
        )
    };
    if bytes.len() < 12 || &bytes[..8] != MAGIC {
        return Err(CheckpointError::new(
            file,
            "not an fdem checkpoint (it does not begin with FDEMCKPT)",
            "give the run folder that holds checkpoint.fdem",
        ));
    }
    let format = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
    if format > FORMAT {
        return Err(CheckpointError::new(
            file,
            format!(
                "the checkpoint has format {format}, newer than this fdem reads (up to {FORMAT}, fdem {})",
                env!("CARGO_PKG_VERSION")
            ),
            "resume it with the fdem version that wrote it, or a newer one",
        ));
    }
    if format < FORMAT {
        return Err(CheckpointError::new(
            file,
            format!(
                "the checkpoint has format {format}, written by an older fdem (this one reads {FORMAT}, fdem {})",
                env!("CARGO_PKG_VERSION")
            ),
            "resume it with the fdem version that wrote it, or run the scene afresh",
        ));
    }
    if bytes.len() < 12 + 8 + 8 {
        return Err(damaged(format!("{} bytes is too short", bytes.len())));
    }
    let body = &bytes[..bytes.len() - 8];
    let sum = u64::from_le_bytes(bytes[bytes.len() - 8..].try_into().expect("8 bytes"));
    let mut d = Dec::new(&body[12..]);
    let header_len = d.get::<u64>().map_err(|e| damaged(e.0))? as usize;
    let head = d.take(header_len).map_err(|e| damaged(e.0))?;
    let state_len = d.get::<u64>().map_err(|e| damaged(e.0))? as usize;
    if d.remaining() != state_len {
        return Err(damaged(format!(
            "its state should have {state_len} bytes, the file holds {}",
            d.remaining()
        )));
    }
    if twox_hash::XxHash3_64::oneshot(&body[8..]) != sum {
        return Err(damaged("its checksum does not match its contents".into()));
    }
    let header = Header::unpack(&mut Dec::new(head)).map_err(|e| damaged(e.0))?;
    let state = d.take(state_len).map_err(|e| damaged(e.0))?.to_vec();
    Ok(Checkpoint { header, state })
}

/// When a run writes its checkpoints.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Every {
    /// Every this many steps.
    Steps(u64),
    /// Every this many seconds of wall-clock time.
    Seconds(f64),
    /// Never on its own (only when interrupted).
    Off,
}

/// The default interval: ten minutes of wall-clock time.
pub const DEFAULT_EVERY: Every = Every::Seconds(600.0);

impl Every {
    /// Parses `5000` (steps), `90s`, `30min`, `2h`, or `off`.
    pub fn parse(s: &str) -> Result<Every, String> {
        let t = s.trim();
        if t == "off" {
            return Ok(Every::Off);
        }
        if let Ok(n) = t.parse::<u64>() {
            return if n > 0 {
                Ok(Every::Steps(n))
            } else {
                Err(
                    "0 steps: give a positive number of steps, a time such as `30min`, or `off`"
                        .into(),
                )
            };
        }
        let split = t.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(t.len());
        let (num, unit) = t.split_at(split);
        let scale = match unit.trim() {
            "s" => 1.0,
            "min" => 60.0,
            "h" => 3600.0,
            _ => {
                return Err(format!(
                    "`{s}` is not a number of steps (`5000`), a wall-clock time (`90s`, `30min`, `2h`) or `off`"
                ));
            }
        };
        match num.trim().parse::<f64>() {
            Ok(x) if x.is_finite() && x > 0.0 => Ok(Every::Seconds(x * scale)),
            _ => Err(format!(
                "`{s}`: the time must be a positive number followed by s, min or h"
            )),
        }
    }
}

/// In a scene (`output.checkpoint_every`): a number of steps, or a text (`"30min"`, `"off"`).
impl<'de> serde::Deserialize<'de> for Every {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Steps(u64),
            Text(String),
        }
        let text = match Raw::deserialize(d).map_err(|_| {
            serde::de::Error::custom(
                "expected a number of steps (5000), a wall-clock time (\"90s\", \"30min\", \"2h\") or \"off\"",
            )
        })? {
            Raw::Steps(n) => n.to_string(),
            Raw::Text(t) => t,
        };
        Every::parse(&text).map_err(serde::de::Error::custom)
    }
}

impl serde::Serialize for Every {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Every::Steps(n) => s.serialize_u64(*n),
            Every::Seconds(x) => s.serialize_str(&format!("{x}s")),
            Every::Off => s.serialize_str("off"),
        }
    }
}

/// What a run's checkpoints cost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// Checkpoints written.
    pub written: u64,
    /// Bytes of the last one.
    pub bytes: u64,
    /// Wall time the run waited for them (encoding) [s].
    pub encode_time: f64,
    /// Wall time of their writes, on the writer's thread [s].
    pub write_time: f64,
}

/// Writes checkpoints whole or not at all, each on a background thread while the run goes
/// on; the next one (and the end of the run) first waits for the one before.
#[derive(Debug)]
pub struct CheckpointWriter {
    path: PathBuf,
    pending: Option<JoinHandle<std::io::Result<f64>>>,
    /// Checkpoints written.
    pub written: u64,
    /// Bytes of the last one.
    pub bytes: u64,
    /// Wall time spent in the run's thread (encoding) [s].
    pub encode_time: f64,
    /// Wall time of the writes (on the background thread) [s].
    pub write_time: f64,
}

impl CheckpointWriter {
    /// A writer of `dir/checkpoint.fdem`.
    pub fn new(dir: &Path) -> Self {
        Self {
            path: dir.join(FILE_NAME),
            pending: None,
            written: 0,
            bytes: 0,
            encode_time: 0.0,
            write_time: 0.0,
        }
    }

    /// What the checkpoints written so far cost.
    pub fn stats(&self) -> Stats {
        Stats {
            written: self.written,
            bytes: self.bytes,
            encode_time: self.encode_time,
            write_time: self.write_time,
        }
    }

    /// The checkpoint file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes `file` (the whole file: [`encode_file`]) on a background thread, after the
    /// previous write has finished.
    pub fn submit(&mut self, file: Vec<u8>) -> std::io::Result<()> {
        self.wait()?;
        self.bytes = file.len() as u64;
        let path = self.path.clone();
        self.pending = Some(std::thread::spawn(move || {
            let s = Instant::now();
            write_durably(&path, &file)?;
            Ok(s.elapsed().as_secs_f64())
        }));
        Ok(())
    }

    /// Waits for the write in flight, if any.
    pub fn wait(&mut self) -> std::io::Result<()> {
        if let Some(h) = self.pending.take() {
            let secs = h
                .join()
                .map_err(|_| std::io::Error::other("the checkpoint writer panicked"))??;
            self.write_time += secs;
            self.written += 1;
        }
        Ok(())
    }
}

/// Writes `bytes` to `path` so that after a crash the file is the old one or the new one:
/// a temporary file beside it, fsync, rename, fsync of the folder.
pub fn write_durably(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)?;
        // the rename itself made durable (a folder opened read-only can be synced on Linux)
        if let Ok(d) = std::fs::File::open(dir) {
            let _ = d.sync_all();
        }
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// A new run id: a hash of the wall-clock time, the process, a count of the ids this process
/// drew and the folder `dir`, so that two runs (of one scene, in one folder or two) differ.
pub fn new_run_id(dir: &Path) -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static DRAWN: AtomicU64 = AtomicU64::new(0);
    let mut e = Enc::default();
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    e.put(&now);
    e.put(&u64::from(std::process::id()));
    e.put(&DRAWN.fetch_add(1, Ordering::Relaxed));
    e.put(&dir.to_string_lossy().into_owned());
    twox_hash::XxHash3_64::oneshot(&e.buf)
}

/// A run id as the folder's [`RUN_ID_FILE`] and the messages write it: 16 hex digits.
pub fn run_id_text(id: u64) -> String {
    format!("{id:016x}")
}

/// Writes run `id` into `dir` ([`RUN_ID_FILE`]), whole or not at all.
pub fn write_run_id(dir: &Path, id: u64) -> std::io::Result<()> {
    write_durably(
        &dir.join(RUN_ID_FILE),
        format!("{}\n", run_id_text(id)).as_bytes(),
    )
}

/// Checks that the folder `dir` of checkpoint `file` (with `header`) is the one its run
/// wrote: its [`RUN_ID_FILE`] holds the checkpoint's run id, and every file the header lists
/// is there. Reads only: a refused folder is left as it is.
pub fn check_folder(dir: &Path, file: &Path, header: &Header) -> Result<(), CheckpointError> {
    let id = run_id_text(header.run_id);
    let id_file = dir.join(RUN_ID_FILE);
    let fix_id = format!(
        "resume the folder in which the checkpoint was written (a copy of that whole folder resumes too), or start the run afresh: fdem run SCENE --out {}",
        dir.display()
    );
    match std::fs::read_to_string(&id_file) {
        Err(e) => {
            return Err(CheckpointError::new(
                file,
                format!(
                    "the checkpoint belongs to run {id}, but {} cannot be read ({e}): the checkpoint was written in another folder, or the folder's run id was removed",
                    id_file.display()
                ),
                fix_id,
            ));
        }
        Ok(text) if text.trim() != id => {
            let folder = fdem_mesh::excerpt(text.trim());
            return Err(CheckpointError::new(
                file,
                format!(
                    "the checkpoint belongs to run {id}, but the folder holds the files of run {folder} ({}): the checkpoint was copied from another run's folder",
                    id_file.display()
                ),
                fix_id,
            ));
        }
        Ok(_) => {}
    }
    let missing: Vec<&str> = header
        .files
        .iter()
        .filter(|f| !dir.join(f).is_file())
        .map(String::as_str)
        .collect();
    if let Some(first) = missing.first() {
        let more = match missing.len() {
            1 => String::new(),
            n => format!(
                " (and {} more: {})",
                n - 1,
                missing[1..]
                    .iter()
                    .take(5)
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        return Err(CheckpointError::new(
            file,
            format!(
                "{first}{more}, written by the run before its checkpoint at step {}, is missing from {}: a resumed run goes on from the files written before its checkpoint and does not write them again",
                header.step,
                dir.display()
            ),
            format!(
                "put the missing file back (or resume a whole copy of the folder), or start the run afresh: fdem run SCENE --out {}",
                dir.display()
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> Header {
        Header {
            version: "0.1.0".into(),
            scene: 1,
            mesh: 2,
            step: 300,
            time: 1.5e-3,
            time_step: 1e-7,
            scene_file: "/x/scene.json".into(),
            run_id: 0x0123_4567_89ab_cdef,
            files: vec!["frame_0000.vtu".into(), "joints_0000.vtu".into()],
        }
    }

    #[test]
    fn a_file_reads_back_and_every_damage_is_named() {
        let p = Path::new("ck.fdem");
        let bytes = encode_file(&header(), &[1, 2, 3, 4, 5]);
        let c = decode_file(p, &bytes).unwrap();
        assert_eq!((c.header, c.state), (header(), vec![1, 2, 3, 4, 5]));
        for cut in 0..bytes.len() {
            let e = decode_file(p, &bytes[..cut]).unwrap_err();
            assert!(
                e.message.contains("damaged") || e.message.contains("not an fdem"),
                "{cut}: {}",
                e.message
            );
        }
        let mut flipped = bytes.clone();
        flipped[30] ^= 1;
        assert!(
            decode_file(p, &flipped)
                .unwrap_err()
                .message
                .contains("checksum")
        );
        let mut newer = bytes.clone();
        newer[8..12].copy_from_slice(&(FORMAT + 1).to_le_bytes());
        let e = decode_file(p, &newer).unwrap_err();
        assert!(
            e.message.contains("newer than this fdem reads"),
            "{}",
            e.message
        );
    }

    #[test]
    fn intervals_parse_in_steps_or_wall_clock_time() {
        assert_eq!(Every::parse("5000"), Ok(Every::Steps(5000)));
        assert_eq!(Every::parse("90s"), Ok(Every::Seconds(90.0)));
        assert_eq!(Every::parse("30min"), Ok(Every::Seconds(1800.0)));
        assert_eq!(Every::parse("1.5h"), Ok(Every::Seconds(5400.0)));
        assert_eq!(Every::parse("off"), Ok(Every::Off));
        for bad in ["0", "-3", "10 days", "min", "0s"] {
            assert!(Every::parse(bad).is_err(), "{bad}");
        }
    }
}

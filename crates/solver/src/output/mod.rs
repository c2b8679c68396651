//! Output: `.vtu` frames collected in a `.pvd`, histories as CSV, and the JSON run summary;
//! in fracturing scenes a second series of the joints as line cells (`joints.pvd`).
//!
//! Every file is written whole or not at all ([`atomic::write_atomic`]: a temporary file in
//! the same folder, then a rename), and the `.pvd` collection is rewritten after each frame,
//! so an interrupted run leaves a readable result. A run owns its folder: it first removes
//! every file an earlier run wrote there ([`folder::claim`]).

pub mod atomic;
pub mod csv;
pub mod curve;
pub mod folder;
pub mod frame;
pub mod history;
pub mod joint_frame;
pub mod joints;
pub mod pvd;
pub mod recovery;
pub mod vtu;
#[cfg(test)]
mod vtu_vtkio;

pub use crate::input::arrays::ArraySet;
pub use atomic::{write_atomic, write_atomic_with};
pub use csv::{csv_length, open_csv, truncate_csv};
pub use frame::{FrameData, frame_from_parts, make_frame, make_frame_of};
pub use history::HistoryWriter;
pub use joint_frame::{JointFluid, JointFrame, JointProperties};
pub use joints::JointSeries;
pub use pvd::Collection;

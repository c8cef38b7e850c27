//! The kuka-bridge file protocol, version 1: the one contract between the
//! service and the controller side (the KRL program or the simulated
//! controller). Nothing else in the project knows the file format.
//!
//! Three files live in one channel directory: [`COMMAND_FILE`] (written by
//! the service), [`RESULT_FILE`] and [`STATE_FILE`] (written by the
//! controller). Every file is a sequence of ASCII lines that KRL's
//! `krl_fgets` + `SREAD` can read: a three-letter tag, numeric fields in a
//! fixed order, and a checksum as the last field; each file ends with an
//! `END` line. A half-written or corrupted file fails to decode and is read
//! again later; it is never misparsed. See `krl/PROTOCOL.md` for the
//! normative description.
#![deny(missing_docs)]

mod codec;
pub mod files;
mod records;

pub use codec::{DecodeError, EncodeError, MAX_LINE_LEN, MAX_REAL, REAL_STEP, checksum};
pub use records::*;

/// Protocol version written into every header record.
pub const PROTOCOL_VERSION: i32 = 1;
/// Command file name (service → controller).
pub const COMMAND_FILE: &str = "kb_cmd.txt";
/// Result file name (controller → service).
pub const RESULT_FILE: &str = "kb_res.txt";
/// State / heartbeat file name (controller → service).
pub const STATE_FILE: &str = "kb_state.txt";
/// Maximum number of motions in one command (one continuous batch).
pub const MAX_BATCH: usize = 1000;
/// Number of most recent results the controller keeps in the result file.
pub const RESULT_HISTORY: usize = 8;

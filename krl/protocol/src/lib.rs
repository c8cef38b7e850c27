//! The kuka-bridge file protocol, version 2: the one contract between the
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
pub const PROTOCOL_VERSION: i32 = 2;
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
/// The largest result or state file a reader accepts, in bytes. A valid
/// result file is at most about 2 KB (8 `RSL` lines of under 200
/// characters), a state file under 1 KB; anything bigger is junk, and a
/// reader refuses it after a `stat` instead of reading it on every poll.
pub const MAX_CONTROLLER_FILE_LEN: u64 = 64 * 1024;

/// The size of the command id space: ids are 1..=2147483647 (`i32::MAX`).
const CID_SPACE: i64 = i32::MAX as i64;
/// How far ahead of the last accepted id a new id may be and still count
/// as newer (2^30, half the id space).
pub const CID_WINDOW: i64 = 1 << 30;

/// True when command id `cid` is newer than `last` (PROTOCOL.md §8):
/// serial-number arithmetic over the id space 1..=2147483647 (RFC 1982),
/// so that ids wrap from 2147483647 to 1 instead of running out. `cid` is
/// newer when it lies 1..2^30 − 1 steps after `last`; `last` = 0 (nothing
/// accepted yet) makes every positive id newer. Below the wrap this is
/// exactly `cid > last` whenever the two are less than 2^30 apart.
pub fn cid_is_newer(cid: Cid, last: Cid) -> bool {
    if cid <= 0 {
        return false;
    }
    if last <= 0 {
        return true;
    }
    let d = (i64::from(cid) - i64::from(last)).rem_euclid(CID_SPACE);
    d > 0 && d < CID_WINDOW
}

/// The id after `cid`: `cid + 1`, wrapping from 2147483647 to 1.
pub fn cid_after(cid: Cid) -> Cid {
    if cid <= 0 || cid == Cid::MAX {
        1
    } else {
        cid + 1
    }
}

/// The newer of two ids by [`cid_is_newer`] (`a` when neither is newer).
pub fn newest_cid(a: Cid, b: Cid) -> Cid {
    if cid_is_newer(b, a) { b } else { a }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cids_compare_like_integers_below_the_wrap() {
        assert!(cid_is_newer(2, 1));
        assert!(!cid_is_newer(1, 2));
        assert!(!cid_is_newer(5, 5));
        assert!(cid_is_newer(1, 0), "nothing accepted yet");
        assert!(!cid_is_newer(0, 0));
        assert!(!cid_is_newer(-3, 0));
        assert!(cid_is_newer(1_000_000, 17));
    }

    #[test]
    fn cids_wrap_instead_of_running_out() {
        assert_eq!(cid_after(i32::MAX), 1);
        assert_eq!(cid_after(41), 42);
        assert!(cid_is_newer(1, i32::MAX), "1 follows the last id");
        assert!(cid_is_newer(5000, i32::MAX));
        assert!(!cid_is_newer(i32::MAX, 5000), "a poisoned maximum is old");
        // Whatever the controller last accepted, the id after it is newer.
        for last in [
            1,
            2,
            1 << 29,
            (1 << 30) - 1,
            1 << 30,
            i32::MAX - 1,
            i32::MAX,
        ] {
            assert!(cid_is_newer(cid_after(last), last), "after {last}");
            assert!(!cid_is_newer(last, cid_after(last)), "before {last}");
        }
        assert_eq!(newest_cid(5000, i32::MAX), 5000);
        assert_eq!(newest_cid(7, 9), 9);
    }
}

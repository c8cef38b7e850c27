//! The service's side of the file channel: writing commands, reading
//! results and heartbeats, watching the directory, the persistent command
//! id counter, and the lock that keeps two services off one channel.

use std::fs::File;
use std::path::{Path, PathBuf};

use kuka_protocol::files::{self, ReadError, ReplacedFile, WriteError};
use kuka_protocol::{
    COMMAND_FILE, Cid, CommandFile, DecodeError, RESULT_FILE, ResultFile, STATE_FILE, StateFile,
};
use notify::{RecursiveMode, Watcher};

/// Errors of the channel.
#[derive(Debug, thiserror::Error)]
pub enum ChannelError {
    /// Writing the command file failed.
    #[error(transparent)]
    Write(#[from] WriteError),
    /// The command could not be encoded.
    #[error("cannot encode command")]
    Encode(#[from] kuka_protocol::EncodeError),
    /// Directory or counter I/O failed.
    #[error("{what} {path}")]
    Io {
        /// What was attempted.
        what: &'static str,
        /// The path.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// Another service instance holds the channel.
    #[error("another kuka-bridge already serves channel {0} (its lock file is held)")]
    InUse(String),
}

/// A read that did not yield a record.
#[derive(Debug)]
pub enum ReadOutcome<T> {
    /// The record.
    Record(T),
    /// No file yet.
    Missing,
    /// Held by another process.
    Locked,
    /// The same version as read last time (not read again).
    Unchanged,
    /// Half-written or corrupt: read again later.
    Invalid(DecodeError),
    /// Larger than any protocol file ([`kuka_protocol::MAX_CONTROLLER_FILE_LEN`]):
    /// refused without reading it. The size.
    TooLarge(u64),
    /// Other I/O failure.
    Failed(String),
}

/// A version of a file as its metadata tells (see [`Channel::results_stamp`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileStamp {
    id: u64,
    len: u64,
    modified: Option<std::time::SystemTime>,
}

/// Which controller files a watcher event (or a poll) says to read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Changed {
    /// The result file may have changed.
    pub results: bool,
    /// The state file may have changed.
    pub state: bool,
}

impl Changed {
    /// Both files (a poll, or an event the watcher could not attribute):
    /// read whatever their stamps say.
    pub const BOTH: Changed = Changed {
        results: true,
        state: true,
    };
}

/// The channel directory as the service sees it.
#[derive(Debug)]
pub struct Channel {
    dir: PathBuf,
    command: ReplacedFile,
    /// The result file's version at the last read.
    results_read: Option<FileStamp>,
}

impl Channel {
    /// Opens (creating if needed) a channel directory.
    pub fn open(dir: &Path) -> Result<Self, ChannelError> {
        std::fs::create_dir_all(dir).map_err(|source| ChannelError::Io {
            what: "cannot create channel directory",
            path: dir.display().to_string(),
            source,
        })?;
        let tag = format!("svc{}", std::process::id());
        Ok(Channel {
            dir: dir.to_path_buf(),
            command: ReplacedFile::new(dir, COMMAND_FILE, &tag),
            results_read: None,
        })
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// One attempt to write the command file atomically.
    pub fn write_command(&mut self, cmd: &CommandFile) -> Result<(), ChannelError> {
        let text = cmd.encode()?;
        self.command.write(text.as_bytes())?;
        Ok(())
    }

    /// Removes the command file (the controller has read it): until the
    /// next command its polls find no file, which costs a KRL program one
    /// failed open instead of an open, a line and a close. Locked: the
    /// controller is reading it; try again later.
    pub fn remove_command(&mut self) -> Result<(), ChannelError> {
        self.command.remove()?;
        Ok(())
    }

    fn read<T>(
        &self,
        name: &str,
        decode: impl Fn(&str) -> Result<T, DecodeError>,
    ) -> ReadOutcome<T> {
        match files::read_bounded(&self.dir, name, kuka_protocol::MAX_CONTROLLER_FILE_LEN) {
            Ok(Some(text)) => match decode(&text) {
                Ok(v) => ReadOutcome::Record(v),
                Err(e) => ReadOutcome::Invalid(e),
            },
            Ok(None) => ReadOutcome::Missing,
            Err(ReadError::Locked { .. }) => ReadOutcome::Locked,
            Err(ReadError::TooLarge { len, .. }) => ReadOutcome::TooLarge(len),
            Err(e) => ReadOutcome::Failed(e.to_string()),
        }
    }

    /// Checks that a file can be created in the channel folder (in the
    /// temporary subfolder the atomic writes use, so the controller's
    /// watcher sees nothing).
    pub fn probe_writable(&self) -> Result<(), ChannelError> {
        probe_dir(&self.dir.join(files::TEMP_DIR), "channel folder")
    }

    /// True while another process holds the command file locked.
    pub fn command_locked(&self) -> bool {
        self.command.is_locked()
    }

    /// What identifies the result file's current version, without opening
    /// it (an open would wake every watcher of the directory): its inode
    /// (Unix), size and modification time. A new value means a new file.
    pub fn results_stamp(&self) -> Option<FileStamp> {
        let m = std::fs::metadata(self.dir.join(RESULT_FILE)).ok()?;
        #[cfg(unix)]
        let id = std::os::unix::fs::MetadataExt::ino(&m);
        #[cfg(not(unix))]
        let id = 0;
        Some(FileStamp {
            id,
            len: m.len(),
            modified: m.modified().ok(),
        })
    }

    /// Reads the result file; unless `always`, only if its stamp differs
    /// from the last read's. The watcher's event for a result the engine's
    /// busy wait has already read then costs a `stat`, not an open (which
    /// would wake every watcher again). The periodic poll reads `always`,
    /// so a change the stamp cannot tell is still seen.
    pub fn read_results(&mut self, always: bool) -> ReadOutcome<ResultFile> {
        let stamp = self.results_stamp();
        if !always && stamp.is_some() && stamp == self.results_read {
            return ReadOutcome::Unchanged;
        }
        let outcome = self.read(RESULT_FILE, ResultFile::decode);
        // Taken before the read: a newer file read meanwhile is read again
        // at its own event, never missed. A file that could not be read
        // (locked, I/O error) is read again at the next event.
        if !matches!(outcome, ReadOutcome::Locked | ReadOutcome::Failed(_)) {
            self.results_read = stamp;
        }
        outcome
    }

    /// Reads the state file.
    pub fn read_state(&self) -> ReadOutcome<StateFile> {
        self.read(STATE_FILE, StateFile::decode)
    }

    /// Watches the directory; a message means "result or state file may
    /// have changed". Events are a hint: the caller still polls. Returns
    /// the watcher (keep it alive) or None when watching is unavailable.
    pub fn watch(
        &self,
        on_change: impl Fn(Changed) + Send + 'static,
    ) -> Option<notify::RecommendedWatcher> {
        let result = notify::recommended_watcher(move |ev: notify::Result<notify::Event>| {
            let changed = match &ev {
                // Our own reads raise access events; reacting to them would
                // make every read trigger the next one.
                Ok(ev) if matches!(ev.kind, notify::EventKind::Access(_)) => None,
                Ok(ev) => {
                    let named = |file: &str| {
                        ev.paths
                            .iter()
                            .any(|p| p.file_name().is_some_and(|n| n == file))
                    };
                    let c = Changed {
                        results: named(RESULT_FILE),
                        state: named(STATE_FILE),
                    };
                    (c.results || c.state).then_some(c)
                }
                // Overflow and errors: look at everything.
                Err(_) => Some(Changed::BOTH),
            };
            if let Some(c) = changed {
                on_change(c);
            }
        })
        .and_then(|mut w| w.watch(&self.dir, RecursiveMode::NonRecursive).map(|()| w));
        match result {
            Ok(w) => Some(w),
            Err(e) => {
                tracing::warn!(error = %e, dir = %self.dir.display(), "file watcher unavailable; polling only");
                None
            }
        }
    }
}

/// Creates, writes and removes a small file in `dir` (created if missing).
fn probe_dir(dir: &Path, what: &'static str) -> Result<(), ChannelError> {
    use std::io::Write;
    let path = dir.join(format!(".probe.svc{}", std::process::id()));
    let io = |source| ChannelError::Io {
        what,
        path: dir.display().to_string(),
        source,
    };
    std::fs::create_dir_all(dir).map_err(io)?;
    let written = File::create(&path).and_then(|mut f| f.write_all(b"probe"));
    let _ = std::fs::remove_file(&path);
    written.map_err(io)
}

/// Holds an exclusive lock on `<channel>/kb_service.lock` while the service runs.
#[derive(Debug)]
pub struct ServiceLock {
    _file: File,
}

impl ServiceLock {
    /// Takes the lock (creating the channel directory if needed) or fails
    /// with [`ChannelError::InUse`].
    pub fn acquire(dir: &Path) -> Result<Self, ChannelError> {
        std::fs::create_dir_all(dir).map_err(|source| ChannelError::Io {
            what: "cannot create channel directory",
            path: dir.display().to_string(),
            source,
        })?;
        let path = dir.join("kb_service.lock");
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|source| ChannelError::Io {
                what: "cannot open lock file",
                path: path.display().to_string(),
                source,
            })?;
        match file.try_lock() {
            Ok(()) => Ok(ServiceLock { _file: file }),
            Err(_) => Err(ChannelError::InUse(dir.display().to_string())),
        }
    }
}

/// Persistent command ids, each newer than the last ([`kuka_protocol::cid_is_newer`]:
/// ids wrap from 2147483647 to 1, so they never run out). Ids are reserved
/// in blocks written (and synced) to `<data_dir>/next_cid` before use, so a
/// restarted service — even after a crash — starts after every id it ever
/// sent.
#[derive(Debug)]
pub struct CidStore {
    path: PathBuf,
    next: Cid,
    /// Ids left in the block on disk (0: write a new block first).
    reserved: i64,
    /// The value last written to the file.
    on_disk: Option<i64>,
}

const CID_BLOCK: i64 = 1024;

impl CidStore {
    /// Opens the counter in `data_dir` (created if needed).
    pub fn open(data_dir: &Path) -> Result<Self, ChannelError> {
        std::fs::create_dir_all(data_dir).map_err(|source| ChannelError::Io {
            what: "cannot create data directory",
            path: data_dir.display().to_string(),
            source,
        })?;
        let path = data_dir.join("next_cid");
        let next = match std::fs::read_to_string(&path) {
            Ok(text) => text.trim().parse::<Cid>().ok().filter(|v| *v >= 1).unwrap_or_else(|| {
                tracing::warn!(path = %path.display(), "command id counter unreadable; starting from the controller's ids");
                1
            }),
            Err(_) => 1,
        };
        Ok(CidStore {
            path,
            next,
            reserved: 0,
            on_disk: None,
        })
    }

    /// The next id, newer than `last_accepted` (the last id the controller
    /// reports having accepted; 0 if unknown). Fails only when the counter
    /// cannot be persisted (the data folder is not writable).
    pub fn next(&mut self, last_accepted: Cid) -> Result<Cid, ChannelError> {
        self.raise(last_accepted);
        if self.reserved <= 0 {
            self.reserve()?;
        }
        Ok(self.take())
    }

    /// Like [`Self::next`], for a STOP: it never fails. If the block cannot
    /// be persisted the id is used anyway (a STOP must always go out) and
    /// the error is returned beside it for the caller to report. The cost
    /// is small: after a restart with a lost counter, the controller's own
    /// `last_cid` still keeps new ids newer.
    pub fn next_for_stop(&mut self, last_accepted: Cid) -> (Cid, Option<ChannelError>) {
        self.raise(last_accepted);
        let error = if self.reserved <= 0 {
            self.reserve().err()
        } else {
            None
        };
        (self.take(), error)
    }

    /// Checks that the counter file can be replaced, by writing it again
    /// with the value it holds (or the next id, which no restart can find
    /// used). When ids were used beyond the block on disk (STOPs sent while
    /// it could not be written), it reserves a new block instead, so the
    /// file is ahead of every id sent as soon as it can be written again.
    pub fn probe_writable(&mut self) -> Result<(), ChannelError> {
        match self.on_disk {
            Some(value) if self.reserved > 0 => self.persist(value),
            Some(_) => self.reserve(),
            None => self.persist(i64::from(self.next)),
        }
    }

    /// Makes the next id newer than `last_accepted`.
    fn raise(&mut self, last_accepted: Cid) {
        if last_accepted > 0 && !kuka_protocol::cid_is_newer(self.next, last_accepted) {
            self.next = kuka_protocol::cid_after(last_accepted);
            // The block on disk may lie before the new id.
            self.reserved = 0;
        }
    }

    fn take(&mut self) -> Cid {
        let cid = self.next;
        self.next = kuka_protocol::cid_after(cid);
        self.reserved -= 1;
        cid
    }

    /// Writes the start of the block after the next one to the file.
    fn reserve(&mut self) -> Result<(), ChannelError> {
        let end = (i64::from(self.next) - 1 + CID_BLOCK).rem_euclid(i64::from(Cid::MAX)) + 1;
        self.persist(end)?;
        self.reserved = CID_BLOCK;
        self.on_disk = Some(end);
        Ok(())
    }

    fn persist(&self, value: i64) -> Result<(), ChannelError> {
        let io = |source| ChannelError::Io {
            what: "cannot persist command id counter",
            path: self.path.display().to_string(),
            source,
        };
        write_replacing(&self.path, value.to_string().as_bytes()).map_err(io)
    }
}

/// Replaces a data file (a counter) atomically and durably: a crash leaves
/// the old or the new value, never a mix (the `atomic-write-file` crate:
/// temporary file, sync, rename).
pub(crate) fn write_replacing(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut file = atomic_write_file::AtomicWriteFile::open(path)?;
    file.write_all(bytes)?;
    file.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cids_increase_across_restarts() {
        let dir = tempfile::tempdir().expect("tempdir");
        let mut a = CidStore::open(dir.path()).expect("open");
        let first: Vec<_> = (0..5).map(|_| a.next(0).expect("cid")).collect();
        assert_eq!(first, vec![1, 2, 3, 4, 5]);
        drop(a);
        let mut b = CidStore::open(dir.path()).expect("open");
        let after = b.next(0).expect("cid");
        assert!(after > 5, "restart reused {after}");
        assert!(
            b.next(5000).expect("cid") == 5001,
            "floor from the controller wins"
        );
    }

    #[test]
    fn cids_wrap_after_the_largest_and_never_run_out() {
        let dir = tempfile::tempdir().expect("tempdir");
        let mut a = CidStore::open(dir.path()).expect("open");
        // A controller that reports the largest id (or a forged state file).
        assert_eq!(a.next(i32::MAX).expect("cid"), 1);
        assert_eq!(
            a.next(i32::MAX).expect("cid"),
            2,
            "an old maximum is not newer"
        );
        drop(a);
        let mut b = CidStore::open(dir.path()).expect("open");
        let after = b.next(0).expect("cid");
        assert!(
            after > 2 && after <= 1025,
            "restart continues after the wrap: {after}"
        );
    }

    #[test]
    fn a_stop_gets_an_id_even_when_the_counter_cannot_be_written() {
        let dir = tempfile::tempdir().expect("tempdir");
        let mut a = CidStore::open(dir.path()).expect("open");
        // The counter's place is taken by a directory: it cannot be replaced.
        std::fs::create_dir(dir.path().join("next_cid")).expect("dir");
        assert!(a.next(0).is_err(), "a command waits for a persisted id");
        let (cid, error) = a.next_for_stop(0);
        assert!(cid >= 1);
        assert!(error.is_some(), "the failure is reported");
        assert!(a.probe_writable().is_err());
        // Writable again: the probe puts the file ahead of the stop's id.
        std::fs::remove_dir(dir.path().join("next_cid")).expect("unblock");
        a.probe_writable().expect("probe");
        let on_disk: i64 = std::fs::read_to_string(dir.path().join("next_cid"))
            .expect("read")
            .trim()
            .parse()
            .expect("number");
        assert!(on_disk > i64::from(cid), "{on_disk} after {cid}");
    }

    #[test]
    fn second_service_on_a_channel_is_refused() {
        let dir = tempfile::tempdir().expect("tempdir");
        let _held = ServiceLock::acquire(dir.path()).expect("first");
        assert!(matches!(
            ServiceLock::acquire(dir.path()),
            Err(ChannelError::InUse(_))
        ));
    }
}

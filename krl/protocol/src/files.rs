//! File operations both sides of the channel use: atomic replace of a file
//! (temp file + rename) that reports a locked target instead of blocking,
//! and reads that tell "missing" from "locked".
//!
//! Locking: on Windows a reader that holds a file open without share-delete
//! makes the rename fail (sharing violation, error 32, or access denied, 5).
//! On other systems nothing stops a rename, so the writer also honours an
//! advisory lock (`flock`) held on the target: a peer — or a test — that
//! locks the file keeps it, exactly as a KRL program holding it open does on
//! a KRC.

use std::fs::{self, File, OpenOptions};
use std::io::{self, ErrorKind, Write};
use std::path::{Path, PathBuf};

/// Why a write did not happen.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The target is held by another process; try again later.
    #[error("{path} is locked by another process")]
    Locked {
        /// The file.
        path: String,
    },
    /// Any other I/O failure.
    #[error("cannot write {path}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        #[source]
        source: io::Error,
    },
}

/// Why a read did not happen.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file is held by another process; try again later.
    #[error("{path} is locked by another process")]
    Locked {
        /// The file.
        path: String,
    },
    /// The file is larger than the reader accepts (junk, not a protocol file).
    #[error("{path} is {len} bytes, more than the {max} a protocol file can be")]
    TooLarge {
        /// The file.
        path: String,
        /// Its size.
        len: u64,
        /// The limit.
        max: u64,
    },
    /// Any other I/O failure.
    #[error("cannot read {path}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        #[source]
        source: io::Error,
    },
}

fn is_lock_error(e: &io::Error) -> bool {
    // Windows: ERROR_SHARING_VIOLATION (32), ERROR_LOCK_VIOLATION (33),
    // ERROR_ACCESS_DENIED (5, also returned when the target is open).
    // Only Windows reports locks as errors; elsewhere these numbers mean other things.
    cfg!(windows)
        && (matches!(e.raw_os_error(), Some(5 | 32 | 33))
            || e.kind() == ErrorKind::PermissionDenied)
}

/// Subdirectory of the channel directory that holds the temp files of
/// atomic writes (same volume, so the rename is atomic).
pub const TEMP_DIR: &str = ".kb-tmp";

/// Atomically replaces `dir/name` with `text`: writes `dir/.kb-tmp/name.<tag>.tmp`,
/// then renames it over the target. A reader sees the old or the new file,
/// never a mix. `tag` keeps temp files of different writers apart.
pub fn atomic_write(dir: &Path, name: &str, tag: &str, text: &str) -> Result<(), WriteError> {
    atomic_write_bytes(dir, name, tag, text.as_bytes())
}

/// [`atomic_write`] for bytes (e.g. a KRL module in the controller's
/// 8-bit code page).
pub fn atomic_write_bytes(
    dir: &Path,
    name: &str,
    tag: &str,
    bytes: &[u8],
) -> Result<(), WriteError> {
    ReplacedFile::new(dir, name, tag).write(bytes)
}

/// A file that one writer replaces atomically again and again (the command
/// file for the service; the result and state files for the controller).
///
/// Before each write the lock of the current file is checked (see the
/// module doc). On Unix the writer keeps the file it last put in place
/// open and checks that one, as long as it is still the current file: an
/// open in the channel directory would raise an event that wakes every
/// watcher of the directory, twice per command round trip otherwise.
#[derive(Debug)]
pub struct ReplacedFile {
    target: PathBuf,
    tmp_dir: PathBuf,
    tmp: PathBuf,
    /// The file this writer last renamed into place (Unix only).
    last: Option<File>,
}

impl ReplacedFile {
    /// The writer of `dir/name`; `tag` keeps temp files of different
    /// writers apart.
    pub fn new(dir: &Path, name: &str, tag: &str) -> Self {
        let tmp_dir = dir.join(TEMP_DIR);
        ReplacedFile {
            target: dir.join(name),
            tmp: tmp_dir.join(format!("{name}.{tag}.tmp")),
            tmp_dir,
            last: None,
        }
    }

    /// True if another process holds the file locked right now; a missing
    /// file is not locked.
    pub fn is_locked(&self) -> bool {
        if let Some(last) = self.last.as_ref().filter(|f| is_current(f, &self.target)) {
            return lock_held(last);
        }
        match File::open(&self.target) {
            Ok(f) => lock_held(&f),
            Err(e) => is_lock_error(&e),
        }
    }

    /// Replaces the file with `bytes`: writes the temp file in
    /// `.kb-tmp/`, then renames it over the target, unless the target is
    /// locked.
    pub fn write(&mut self, bytes: &[u8]) -> Result<(), WriteError> {
        let display = || self.target.display().to_string();
        if self.is_locked() {
            return Err(WriteError::Locked { path: display() });
        }
        // The temp file lives in a subdirectory: watchers of the channel
        // directory (non-recursive) then see one rename per write instead of
        // create/open/modify/close/rename events for the temp file as well.
        let write = || -> io::Result<File> {
            let open = || {
                OpenOptions::new()
                    .write(true)
                    .create(true)
                    .truncate(true)
                    .open(&self.tmp)
            };
            let mut f = match open() {
                Err(e) if e.kind() == ErrorKind::NotFound => {
                    fs::create_dir_all(&self.tmp_dir)?;
                    open()?
                }
                other => other?,
            };
            f.write_all(bytes)?;
            Ok(f)
        };
        let written = write().map_err(|source| WriteError::Io {
            path: self.tmp.display().to_string(),
            source,
        })?;
        // Windows: nothing of ours may hold the file when it is renamed.
        let keep = cfg!(unix).then_some(written);
        self.last = None;
        match fs::rename(&self.tmp, &self.target) {
            Ok(()) => {
                self.last = keep;
                Ok(())
            }
            Err(e) => {
                let _ = fs::remove_file(&self.tmp);
                Err(self.target_error(e))
            }
        }
    }

    /// Removes the file, unless another process holds it locked (then
    /// [`WriteError::Locked`]: try again later). A missing file is fine.
    /// The service removes a command the controller has read, so that the
    /// controller's polls until the next command open nothing (PROTOCOL.md
    /// §9.2).
    pub fn remove(&mut self) -> Result<(), WriteError> {
        let display = || self.target.display().to_string();
        if self.is_locked() {
            return Err(WriteError::Locked { path: display() });
        }
        self.last = None;
        match fs::remove_file(&self.target) {
            Err(e) if e.kind() != ErrorKind::NotFound => Err(self.target_error(e)),
            _ => Ok(()),
        }
    }

    /// An OS error on the target: "locked" when another process holds it.
    fn target_error(&self, source: io::Error) -> WriteError {
        let path = self.target.display().to_string();
        if is_lock_error(&source) {
            WriteError::Locked { path }
        } else {
            WriteError::Io { path, source }
        }
    }
}

/// True if `f` is still the file at `path` (same device and inode; no
/// open, so no watcher event). Always false where that cannot be told.
fn is_current(f: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (f.metadata(), fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (f, path);
        false
    }
}

/// True if another process holds a lock on the open file `f` (a lock
/// taken here to find out is released at once).
fn lock_held(f: &File) -> bool {
    match f.try_lock() {
        Ok(()) => {
            let _ = f.unlock();
            false
        }
        Err(fs::TryLockError::WouldBlock) => true,
        Err(fs::TryLockError::Error(e)) => is_lock_error(&e),
    }
}

/// Reads `dir/name`; `Ok(None)` when it does not exist.
pub fn read(dir: &Path, name: &str) -> Result<Option<String>, ReadError> {
    let path = dir.join(name);
    match fs::read(&path) {
        Ok(bytes) => Ok(Some(String::from_utf8_lossy(&bytes).into_owned())),
        Err(e) if e.kind() == ErrorKind::NotFound => Ok(None),
        Err(e) if is_lock_error(&e) => Err(ReadError::Locked {
            path: path.display().to_string(),
        }),
        Err(source) => Err(ReadError::Io {
            path: path.display().to_string(),
            source,
        }),
    }
}

/// [`read`] for a file that may be at most `max` bytes long: a larger file
/// is refused with [`ReadError::TooLarge`] after a `stat` (it is never
/// read into memory), and at most `max` bytes are read even if it grows
/// meanwhile.
pub fn read_bounded(dir: &Path, name: &str, max: u64) -> Result<Option<String>, ReadError> {
    use std::io::Read;
    let path = dir.join(name);
    let io = |source: io::Error| {
        if is_lock_error(&source) {
            ReadError::Locked {
                path: path.display().to_string(),
            }
        } else {
            ReadError::Io {
                path: path.display().to_string(),
                source,
            }
        }
    };
    let file = match File::open(&path) {
        Ok(f) => f,
        Err(e) if e.kind() == ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(io(e)),
    };
    let len = file.metadata().map_err(io)?.len();
    if len > max {
        return Err(ReadError::TooLarge {
            path: path.display().to_string(),
            len,
            max,
        });
    }
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    file.take(max + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > max {
        return Err(ReadError::TooLarge {
            path: path.display().to_string(),
            len: bytes.len() as u64,
            max,
        });
    }
    Ok(Some(String::from_utf8_lossy(&bytes).into_owned()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lock on the current file stops the next write, whether the file
    /// is the one this writer put in place or one put there by someone else.
    #[test]
    fn a_locked_target_is_never_replaced() {
        let dir = tempfile::tempdir().expect("dir");
        let mut w = ReplacedFile::new(dir.path(), "f.txt", "t");
        w.write(b"one").expect("first write");
        let path = dir.path().join("f.txt");
        for round in ["our own file", "a file put there by someone else"] {
            let holder = File::open(&path).expect("open");
            holder.lock().expect("lock");
            assert!(w.is_locked(), "{round}: lock not seen");
            assert!(
                matches!(w.write(b"two"), Err(WriteError::Locked { .. })),
                "{round}: written over a lock"
            );
            drop(holder);
            assert!(!w.is_locked(), "{round}: lock seen after release");
            w.write(b"two").expect("write after release");
            assert_eq!(fs::read_to_string(&path).expect("read"), "two");
            // Next round: the file is replaced behind the writer's back.
            atomic_write(dir.path(), "f.txt", "other", "one").expect("other writer");
        }
        assert!(!ReplacedFile::new(dir.path(), "missing.txt", "t").is_locked());
    }

    /// A locked file stays (the reader is still at it); an unlocked one
    /// goes; a missing one is no error; a write after a removal creates it.
    #[test]
    fn a_file_is_removed_only_when_nobody_holds_it() {
        let dir = tempfile::tempdir().expect("dir");
        let mut w = ReplacedFile::new(dir.path(), "f.txt", "t");
        w.write(b"one").expect("write");
        let path = dir.path().join("f.txt");
        let holder = File::open(&path).expect("open");
        holder.lock_shared().expect("lock");
        assert!(matches!(w.remove(), Err(WriteError::Locked { .. })));
        assert!(path.exists(), "removed under a lock");
        drop(holder);
        w.remove().expect("remove");
        assert!(!path.exists());
        w.remove().expect("a missing file is removed already");
        w.write(b"two").expect("write after removal");
        assert_eq!(fs::read_to_string(&path).expect("read"), "two");
    }
}

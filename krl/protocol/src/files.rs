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
use std::path::Path;

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
    let target = dir.join(name);
    let display = || target.display().to_string();
    // Honour a lock held on the current file (see the module doc).
    match File::open(&target) {
        Ok(f) => match f.try_lock() {
            Ok(()) => drop(f),
            Err(fs::TryLockError::WouldBlock) => {
                return Err(WriteError::Locked { path: display() });
            }
            Err(fs::TryLockError::Error(e)) if is_lock_error(&e) => {
                return Err(WriteError::Locked { path: display() });
            }
            Err(fs::TryLockError::Error(_)) => {}
        },
        Err(e) if is_lock_error(&e) => return Err(WriteError::Locked { path: display() }),
        Err(_) => {}
    }
    // The temp file lives in a subdirectory: watchers of the channel
    // directory (non-recursive) then see one rename per write instead of
    // create/open/modify/close/rename events for the temp file as well.
    let tmp_dir = dir.join(TEMP_DIR);
    let tmp = tmp_dir.join(format!("{name}.{tag}.tmp"));
    let write = || -> io::Result<()> {
        let open = || {
            OpenOptions::new()
                .write(true)
                .create(true)
                .truncate(true)
                .open(&tmp)
        };
        let mut f = match open() {
            Err(e) if e.kind() == ErrorKind::NotFound => {
                fs::create_dir_all(&tmp_dir)?;
                open()?
            }
            other => other?,
        };
        f.write_all(bytes)?;
        Ok(())
    };
    write().map_err(|source| WriteError::Io {
        path: tmp.display().to_string(),
        source,
    })?;
    match fs::rename(&tmp, &target) {
        Ok(()) => Ok(()),
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            if is_lock_error(&e) {
                Err(WriteError::Locked { path: display() })
            } else {
                Err(WriteError::Io {
                    path: display(),
                    source: e,
                })
            }
        }
    }
}

/// True if another process holds `dir/name` locked right now (see the
/// module doc); a missing file is not locked.
pub fn is_locked(dir: &Path, name: &str) -> bool {
    match File::open(dir.join(name)) {
        Ok(f) => match f.try_lock() {
            Ok(()) => false,
            Err(fs::TryLockError::WouldBlock) => true,
            Err(fs::TryLockError::Error(e)) => is_lock_error(&e),
        },
        Err(e) => is_lock_error(&e),
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

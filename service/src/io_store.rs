//! The site's I/O configuration as an admin edited it over HTTP
//! (`PUT /api/v1/io/config`): kept in `<data_dir>/io.json`, private to the
//! service account and administrators like the token file (it decides which
//! outputs clients may switch), and used instead of the configuration
//! file's `[io]` while it exists. `DELETE /api/v1/io/config` removes it and
//! goes back to the file's.

use std::path::{Path, PathBuf};

use kuka_engine::io::IoConfig;

/// Why the stored I/O configuration cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum IoStoreError {
    /// The file cannot be read, written or removed.
    #[error("{path}: {source}")]
    File {
        /// The file.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The file is not a valid I/O configuration (edited by hand?).
    #[error("{path} is not a valid I/O configuration: {why}")]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong.
        why: String,
    },
}

/// Where the admin's I/O configuration lives, and the configuration file's
/// own `[io]` to go back to.
#[derive(Debug)]
pub struct IoStore {
    path: PathBuf,
    from_file: IoConfig,
}

impl IoStore {
    /// The store in `data_dir`; `from_file` is the configuration file's
    /// `[io]`.
    pub fn new(data_dir: &Path, from_file: IoConfig) -> Self {
        IoStore {
            path: data_dir.join("io.json"),
            from_file,
        }
    }

    /// The configuration the service starts with: the stored one if there
    /// is one (a stored file that cannot be used stops the start: falling
    /// back to another allow-list silently could let clients switch
    /// outputs the admin took away), else the file's.
    pub fn initial(&self) -> Result<(IoConfig, bool), IoStoreError> {
        let text = match std::fs::read_to_string(&self.path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Ok((self.from_file.clone(), false));
            }
            Err(source) => return Err(self.file_error(source)),
        };
        let invalid = |why: String| IoStoreError::Invalid {
            path: self.path.display().to_string(),
            why,
        };
        let io: IoConfig = serde_json::from_str(&text).map_err(|e| invalid(e.to_string()))?;
        io.validate().map_err(invalid)?;
        Ok((io, true))
    }

    /// Keeps `io` (already validated) for the next starts.
    pub fn save(&self, io: &IoConfig) -> Result<(), IoStoreError> {
        let mut text = serde_json::to_vec_pretty(io).map_err(|e| IoStoreError::Invalid {
            path: self.path.display().to_string(),
            why: e.to_string(),
        })?;
        text.push(b'\n');
        crate::platform::private_file::write(&self.path, &text).map_err(|e| self.file_error(e))
    }

    /// Forgets the stored configuration; the configuration file's `[io]`,
    /// which applies again.
    pub fn reset(&self) -> Result<IoConfig, IoStoreError> {
        match std::fs::remove_file(&self.path) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(self.file_error(e)),
        }
        Ok(self.from_file.clone())
    }

    fn file_error(&self, source: std::io::Error) -> IoStoreError {
        IoStoreError::File {
            path: self.path.display().to_string(),
            source,
        }
    }
}

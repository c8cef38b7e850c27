//! Bearer tokens: random 256-bit secrets shown once, stored only as SHA-256
//! hashes in `<data_dir>/tokens.json` with a name and a role. The CLI and
//! the running service share the file (writes under a file lock, atomic
//! replace, private permissions); the service re-reads it when it changes,
//! so `token revoke` takes effect without a restart.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::RwLock;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use utoipa::ToSchema;

use super::Role;
use crate::platform::private_file;

/// The prefix of every secret (recognisable in a leaked file or paste).
pub const SECRET_PREFIX: &str = "kb_";

/// Token store errors.
#[derive(Debug, thiserror::Error)]
pub enum TokenError {
    /// Reading, locking or writing the file failed.
    #[error("token file {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The file is not a token file.
    #[error("token file {path} is damaged: {message}")]
    Damaged {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// A token with this name exists.
    #[error("a token named {0:?} already exists")]
    Exists(String),
    /// No token with this name.
    #[error("no token named {0:?}")]
    NotFound(String),
    /// The name is not allowed.
    #[error(
        "token name {0:?}: use 1 to 64 letters, digits, '.', '_', '-' or '@' (not `anonymous`)"
    )]
    BadName(String),
    /// The OS random generator failed.
    #[error("no randomness from the operating system: {0}")]
    Random(String),
}

/// A token as listed: never its secret.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[schema(example = json!({"name": "line-3-pc", "role": "operator", "created_ms": 1763856000000_u64}))]
pub struct TokenInfo {
    /// Unique name (who appears in the audit trail).
    pub name: String,
    /// What it may do.
    pub role: Role,
    /// When it was created (Unix ms).
    pub created_ms: u64,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct Record {
    #[serde(flatten)]
    info: TokenInfo,
    /// Hex SHA-256 of the secret.
    sha256: String,
}

#[derive(Debug, Default, Serialize, Deserialize)]
struct TokenFile {
    version: u32,
    tokens: Vec<Record>,
}

#[derive(Debug, Default)]
struct Snapshot {
    raw: Vec<u8>,
    by_hash: HashMap<String, TokenInfo>,
    list: Vec<TokenInfo>,
}

/// The token file and its in-memory index.
#[derive(Debug)]
pub struct TokenStore {
    path: PathBuf,
    current: RwLock<Snapshot>,
}

/// The hex SHA-256 of a secret.
fn hash(secret: &str) -> String {
    hex::encode(Sha256::digest(secret.as_bytes()))
}

/// `n` random bytes from the OS, as hex.
pub fn random_hex(n: usize) -> Result<String, TokenError> {
    let mut buf = vec![0u8; n];
    getrandom::fill(&mut buf).map_err(|e| TokenError::Random(e.to_string()))?;
    Ok(hex::encode(&buf))
}

/// Unix ms as `YYYY-MM-DD hh:mm:ss UTC` (for listings).
pub fn utc_text(ms: u64) -> String {
    let secs = ms / 1000;
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Howard Hinnant's civil_from_days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02} UTC",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// Checks a token name (`anonymous` is the identity of requests when auth
/// is off, so no token may use it).
pub fn check_name(name: &str) -> Result<(), TokenError> {
    let ok = !name.is_empty()
        && !name.eq_ignore_ascii_case("anonymous")
        && name.len() <= 64
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-' | '@'));
    if ok {
        Ok(())
    } else {
        Err(TokenError::BadName(name.into()))
    }
}

impl TokenStore {
    /// Opens (does not create) `<data_dir>/tokens.json`.
    pub fn open(data_dir: &Path) -> Result<TokenStore, TokenError> {
        let store = TokenStore {
            path: data_dir.join("tokens.json"),
            current: RwLock::new(Snapshot::default()),
        };
        store.reload()?;
        Ok(store)
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn io(&self, source: std::io::Error) -> TokenError {
        TokenError::Io {
            path: self.path.display().to_string(),
            source,
        }
    }

    fn parse(&self, raw: &[u8]) -> Result<TokenFile, TokenError> {
        if raw.is_empty() {
            return Ok(TokenFile {
                version: 1,
                tokens: Vec::new(),
            });
        }
        serde_json::from_slice(raw).map_err(|e| TokenError::Damaged {
            path: self.path.display().to_string(),
            message: e.to_string(),
        })
    }

    fn read_raw(&self) -> Result<Vec<u8>, TokenError> {
        match std::fs::read(&self.path) {
            Ok(raw) => Ok(raw),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
            Err(e) => Err(self.io(e)),
        }
    }

    /// Re-reads the file if it changed; returns true if it did. A damaged
    /// file keeps the previous tokens in force (and is reported).
    pub fn reload(&self) -> Result<bool, TokenError> {
        let raw = self.read_raw()?;
        if self.read().raw == raw && !raw.is_empty() {
            return Ok(false);
        }
        let file = self.parse(&raw)?;
        let mut by_hash = HashMap::new();
        let mut list = Vec::new();
        for r in file.tokens {
            by_hash.insert(r.sha256.to_ascii_lowercase(), r.info.clone());
            list.push(r.info);
        }
        list.sort_by(|a, b| a.name.cmp(&b.name));
        let mut cur = self
            .current
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let changed = cur.raw != raw;
        *cur = Snapshot { raw, by_hash, list };
        Ok(changed)
    }

    fn read(&self) -> std::sync::RwLockReadGuard<'_, Snapshot> {
        self.current
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// The token a secret belongs to.
    pub fn verify(&self, secret: &str) -> Option<TokenInfo> {
        if !secret.starts_with(SECRET_PREFIX) || secret.len() > 200 {
            return None;
        }
        self.read().by_hash.get(&hash(secret)).cloned()
    }

    /// All tokens, by name.
    pub fn list(&self) -> Vec<TokenInfo> {
        self.read().list.clone()
    }

    /// True if a token with this name exists.
    pub fn exists(&self, name: &str) -> bool {
        self.read().list.iter().any(|t| t.name == name)
    }

    /// The token with this name, if it exists.
    pub fn get(&self, name: &str) -> Option<TokenInfo> {
        self.read().list.iter().find(|t| t.name == name).cloned()
    }

    /// True if an admin token exists.
    pub fn has_admin(&self) -> bool {
        self.read().list.iter().any(|t| t.role == Role::Admin)
    }

    /// Runs `change` on the file's contents under an exclusive lock, writes
    /// the result atomically and updates the index.
    fn modify<T>(
        &self,
        change: impl FnOnce(&mut TokenFile) -> Result<T, TokenError>,
    ) -> Result<T, TokenError> {
        if let Some(dir) = self.path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| self.io(e))?;
        }
        let lock_path = self.path.with_extension("lock");
        let lock = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|e| self.io(e))?;
        lock.lock().map_err(|e| self.io(e))?;
        let raw = self.read_raw()?;
        let mut file = self.parse(&raw)?;
        file.version = 1;
        let out = change(&mut file)?;
        let text = serde_json::to_vec_pretty(&file).map_err(|e| TokenError::Damaged {
            path: self.path.display().to_string(),
            message: e.to_string(),
        })?;
        private_file::write(&self.path, &text).map_err(|e| self.io(e))?;
        drop(lock);
        self.reload()?;
        Ok(out)
    }

    /// Creates a token; returns its secret (shown once, never stored).
    pub fn create(&self, name: &str, role: Role) -> Result<(TokenInfo, String), TokenError> {
        check_name(name)?;
        let secret = format!("{SECRET_PREFIX}{}", random_hex(32)?);
        let info = TokenInfo {
            name: name.into(),
            role,
            created_ms: crate::clock::now_ms(),
        };
        let record = Record {
            info: info.clone(),
            sha256: hash(&secret),
        };
        self.modify(|file| {
            if file.tokens.iter().any(|t| t.info.name == name) {
                return Err(TokenError::Exists(name.into()));
            }
            file.tokens.push(record);
            Ok(())
        })?;
        Ok((info, secret))
    }

    /// Revokes (deletes) a token by name.
    pub fn revoke(&self, name: &str) -> Result<TokenInfo, TokenError> {
        self.modify(|file| {
            let i = file
                .tokens
                .iter()
                .position(|t| t.info.name == name)
                .ok_or_else(|| TokenError::NotFound(name.into()))?;
            Ok(file.tokens.remove(i).info)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn create_verify_revoke() {
        let dir = tempfile::tempdir().expect("tempdir");
        let store = TokenStore::open(dir.path()).expect("open");
        let (info, secret) = store.create("ops", Role::Operator).expect("create");
        assert_eq!(secret.len(), SECRET_PREFIX.len() + 64);
        assert_eq!(store.verify(&secret), Some(info.clone()));
        assert_eq!(store.verify(&format!("{secret}x")), None);
        let text = std::fs::read_to_string(store.path()).expect("file");
        assert!(!text.contains(&secret[3..]), "secret stored in clear");
        assert!(matches!(
            store.create("ops", Role::Admin),
            Err(TokenError::Exists(_))
        ));
        // A second store on the same folder (the CLI) sees it and revokes it.
        let other = TokenStore::open(dir.path()).expect("open");
        other.revoke("ops").expect("revoke");
        assert!(store.reload().expect("reload"));
        assert_eq!(store.verify(&secret), None);
        assert!(matches!(
            store.create("a b", Role::Admin),
            Err(TokenError::BadName(_))
        ));
        assert!(matches!(
            store.create("anonymous", Role::Admin),
            Err(TokenError::BadName(_))
        ));
        assert_eq!(utc_text(1_763_856_000_123), "2025-11-23 00:00:00 UTC");
        assert_eq!(utc_text(0), "1970-01-01 00:00:00 UTC");
    }
}

//! Installed WASM plugins: the registry of active plugins (swapped as a
//! whole on install, reload and removal, so requests in flight finish on
//! the version they started with), their files in the plugins folder, and
//! the reconciliation that keeps the two in step (driven by the HTTP API
//! and by the folder watcher in [`watch`]).
//!
//! A file that fails to load never replaces a working version: the old
//! version keeps serving and the listing shows the file's error.

mod bridge;
pub mod watch;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, RwLock};
use std::time::SystemTime;

use kuka_plugin_host::{LoadedPlugin, PluginError, PluginHost, PluginLimits};
use serde::Serialize;
use utoipa::ToSchema;

pub use bridge::{EngineBridge, motion_request};

use crate::config::Config;
use crate::error::{BridgeError, ErrorCode};

/// A route of an installed plugin, as listed.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct PluginRouteInfo {
    /// `GET` or `POST`.
    pub method: String,
    /// The full URL path, e.g. `/api/v1/plugins/draw-circle/circle`.
    pub url: String,
    /// The plugin's summary of the route.
    pub summary: String,
}

/// An installed plugin, as listed by `GET /api/v1/plugins`.
#[derive(Debug, Clone, Serialize, ToSchema)]
#[schema(example = json!({
    "name": "draw-circle", "version": "0.1.0", "status": "active",
    "routes": [{"method": "POST", "url": "/api/v1/plugins/draw-circle/circle", "summary": "Draw a circle"}],
    "sha256": "3f1c…", "wasm_bytes": 134326, "load_ms": 1.2, "from_cache": true,
    "limits": {"memory_mib": 64, "cpu_time_ms": 2000, "request_timeout_ms": 120000, "max_motions": 1000}
}))]
pub struct PluginInfo {
    /// Its name (the URL prefix and the file name `<name>.wasm`).
    pub name: String,
    /// The version it describes (of the active code).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
    /// `active` (serving), or `failed` (its file could not be loaded and no
    /// earlier version is active).
    pub status: &'static str,
    /// Its routes.
    pub routes: Vec<PluginRouteInfo>,
    /// SHA-256 of the active .wasm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sha256: Option<String>,
    /// Size of the active .wasm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wasm_bytes: Option<usize>,
    /// Time to load it (compile or take from the cache, link, describe), ms.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_ms: Option<f64>,
    /// Its compiled code came from the cache.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub from_cache: Option<bool>,
    /// Why the file on disk could not be loaded (the active version, if
    /// any, is the previous one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file_error: Option<ErrorBody>,
    /// The limits its requests run with (`[plugins]`, or
    /// `[plugins.limits.<name>]` when set).
    pub limits: LimitsInfo,
}

/// A plugin's limits, as listed.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct LimitsInfo {
    /// Largest linear memory, MiB.
    pub memory_mib: usize,
    /// Guest time per request, ms.
    pub cpu_time_ms: u128,
    /// Wall time per request, motions included, ms.
    pub request_timeout_ms: u128,
    /// Motions per request.
    pub max_motions: usize,
}

/// A plugin load error as listed.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct ErrorBody {
    /// Stable code (`plugin_invalid`, ...).
    pub code: &'static str,
    /// Sentence.
    pub detail: String,
}

/// What is known about one `<name>.wasm` file.
#[derive(Debug, Clone, PartialEq)]
struct FileStamp {
    modified: Option<SystemTime>,
    len: u64,
}

impl FileStamp {
    /// Matches no file: the next scan reads it again.
    const UNSEEN: FileStamp = FileStamp {
        modified: None,
        len: u64::MAX,
    };
}

/// A `<name>.wasm` file as last seen.
#[derive(Debug, Clone)]
struct FileSeen {
    stamp: FileStamp,
    /// SHA-256 of the content last read.
    sha256: String,
    /// Why that content could not be loaded.
    error: Option<ErrorBody>,
}

#[derive(Default)]
struct Table {
    active: BTreeMap<String, Arc<LoadedPlugin>>,
    files: BTreeMap<String, FileSeen>,
}

/// Plugin failures as the API's errors.
pub fn plugin_error(e: &PluginError) -> BridgeError {
    let code = match e {
        PluginError::NotComponent(_)
        | PluginError::WrongWorld(_)
        | PluginError::InvalidDescription(_) => ErrorCode::PluginInvalid,
        PluginError::Timeout { .. } => ErrorCode::PluginTimeout,
        PluginError::Memory { .. } => ErrorCode::PluginMemory,
        PluginError::Trap(_) => ErrorCode::PluginTrap,
        PluginError::BadResponse(_) => ErrorCode::PluginBadResponse,
        PluginError::Busy(_) => ErrorCode::QueueFull,
        PluginError::Host(_) => ErrorCode::Internal,
    };
    BridgeError::new(code, e.to_string())
}

/// The installed plugins.
pub struct PluginRegistry {
    host: PluginHost,
    dir: PathBuf,
    max_wasm_bytes: usize,
    max_body_bytes: usize,
    table: RwLock<Table>,
    /// Serialises installs, removals and folder scans.
    changes: tokio::sync::Mutex<()>,
}

/// How an install went.
pub enum Installed {
    /// A new plugin.
    Created(PluginInfo),
    /// A new version replaced the old one.
    Replaced(PluginInfo),
}

impl PluginRegistry {
    /// Opens the plugins folder of `config` (loading happens in [`Self::scan`]).
    pub fn open(
        config: &Config,
        engine: crate::engine::Engine,
        control: Arc<crate::access::Control>,
    ) -> Result<Self, BridgeError> {
        let p = &config.plugins;
        let dir = config.plugin_dir();
        std::fs::create_dir_all(&dir).map_err(|e| {
            BridgeError::new(
                ErrorCode::Internal,
                format!("cannot create the plugins folder {}: {e}", dir.display()),
            )
        })?;
        let ms = std::time::Duration::from_millis;
        let limits = PluginLimits {
            memory_bytes: p.memory_mib << 20,
            cpu_time: ms(p.cpu_time_ms),
            request_time: ms(p.request_timeout_ms),
            max_motions: p.max_motions,
            max_response_bytes: 1 << 20,
        };
        let overrides = p
            .limits
            .iter()
            .map(|(name, o)| {
                let l = PluginLimits {
                    memory_bytes: o.memory_mib.map_or(limits.memory_bytes, |m| m << 20),
                    cpu_time: o.cpu_time_ms.map_or(limits.cpu_time, ms),
                    request_time: o.request_timeout_ms.map_or(limits.request_time, ms),
                    max_motions: o.max_motions.unwrap_or(limits.max_motions),
                    max_response_bytes: limits.max_response_bytes,
                };
                (name.clone(), l)
            })
            .collect();
        let api = Arc::new(EngineBridge { engine, control });
        let host = PluginHost::new(limits, overrides, Some(dir.join(".cache")), api)
            .map_err(|e| plugin_error(&e))?;
        Ok(PluginRegistry {
            host,
            dir,
            max_wasm_bytes: p.max_wasm_bytes,
            max_body_bytes: p.max_body_bytes,
            table: RwLock::new(Table::default()),
            changes: tokio::sync::Mutex::new(()),
        })
    }

    /// The plugins folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Largest .wasm accepted.
    pub fn max_wasm_bytes(&self) -> usize {
        self.max_wasm_bytes
    }

    /// Largest request body passed to a plugin.
    pub fn max_body_bytes(&self) -> usize {
        self.max_body_bytes
    }

    /// The plugin host (to call a plugin).
    pub fn host(&self) -> &PluginHost {
        &self.host
    }

    fn table(&self) -> std::sync::RwLockReadGuard<'_, Table> {
        self.table.read().unwrap_or_else(|p| p.into_inner())
    }

    fn table_mut(&self) -> std::sync::RwLockWriteGuard<'_, Table> {
        self.table.write().unwrap_or_else(|p| p.into_inner())
    }

    /// The active version of a plugin.
    pub fn get(&self, name: &str) -> Option<Arc<LoadedPlugin>> {
        self.table().active.get(name).cloned()
    }

    /// All active plugins, by name.
    pub fn active(&self) -> Vec<Arc<LoadedPlugin>> {
        self.table().active.values().cloned().collect()
    }

    fn file_path(&self, name: &str) -> PathBuf {
        self.dir.join(format!("{name}.wasm"))
    }

    /// One plugin as listed (`None`: neither active nor a file).
    pub fn info(&self, name: &str) -> Option<PluginInfo> {
        let table = self.table();
        let active = table.active.get(name);
        let file_error = table.files.get(name).and_then(|f| f.error.clone());
        let l = self.host.limits(name);
        let limits = LimitsInfo {
            memory_mib: l.memory_bytes >> 20,
            cpu_time_ms: l.cpu_time.as_millis(),
            request_timeout_ms: l.request_time.as_millis(),
            max_motions: l.max_motions,
        };
        if active.is_none() && file_error.is_none() {
            return None;
        }
        let routes = active.map_or_else(Vec::new, |p| {
            p.routes
                .iter()
                .map(|r| PluginRouteInfo {
                    method: r.method.clone(),
                    url: format!("/api/v1/plugins/{name}{}", r.path),
                    summary: r.summary.clone(),
                })
                .collect()
        });
        Some(PluginInfo {
            name: name.to_string(),
            version: active.map(|p| p.version.to_string()),
            status: if active.is_some() { "active" } else { "failed" },
            routes,
            sha256: active.map(|p| p.sha256.clone()),
            wasm_bytes: active.map(|p| p.wasm_bytes),
            load_ms: active.map(|p| p.load_time.as_secs_f64() * 1000.0),
            from_cache: active.map(|p| p.from_cache),
            file_error,
            limits,
        })
    }

    /// Every plugin as listed, by name.
    pub fn list(&self) -> Vec<PluginInfo> {
        let names: Vec<String> = {
            let table = self.table();
            let mut names: Vec<String> = table.active.keys().cloned().collect();
            names.extend(table.files.keys().cloned());
            names.sort();
            names.dedup();
            names
        };
        names.iter().filter_map(|n| self.info(n)).collect()
    }

    /// Checks and activates a plugin, then stores its file (the old version
    /// serves until the new one is ready; a refused one changes nothing).
    pub async fn install(&self, name: &str, wasm: Vec<u8>) -> Result<Installed, BridgeError> {
        kuka_plugin_host::check_name(name).map_err(BridgeError::invalid)?;
        if wasm.len() > self.max_wasm_bytes {
            return Err(BridgeError::new(
                ErrorCode::PayloadTooLarge,
                format!(
                    "the plugin has {} bytes; plugins.max_wasm_bytes is {}",
                    wasm.len(),
                    self.max_wasm_bytes
                ),
            ));
        }
        let _guard = self.changes.lock().await;
        let plugin = self
            .host
            .load(name, wasm.clone().into())
            .await
            .map_err(|e| plugin_error(&e))?;
        let path = self.file_path(name);
        write_atomically(&path, &wasm).map_err(|e| {
            tracing::error!(file = %path.display(), error = %e, "plugin file not written");
            BridgeError::new(
                ErrorCode::StorageUnavailable,
                "the service cannot write the plugin into its plugins folder; the service log (under this request's id) says why",
            )
        })?;
        let seen = FileSeen {
            stamp: stamp(&path),
            sha256: plugin.sha256.clone(),
            error: None,
        };
        let replaced = {
            let mut table = self.table_mut();
            table.files.insert(name.to_string(), seen);
            table
                .active
                .insert(name.to_string(), Arc::new(plugin))
                .is_some()
        };
        self.prune_cache();
        let info = self.info(name).ok_or_else(|| {
            BridgeError::new(ErrorCode::Internal, "the plugin vanished while installing")
        })?;
        tracing::info!(plugin = name, version = ?info.version, replaced, "plugin installed");
        Ok(if replaced {
            Installed::Replaced(info)
        } else {
            Installed::Created(info)
        })
    }

    /// Unloads a plugin and deletes its file.
    pub async fn remove(&self, name: &str) -> Result<(), BridgeError> {
        // The name becomes a file name: never let it leave the folder.
        kuka_plugin_host::check_name(name).map_err(BridgeError::invalid)?;
        let _guard = self.changes.lock().await;
        let path = self.file_path(name);
        let known = {
            let mut table = self.table_mut();
            let active = table.active.remove(name).is_some();
            let file = table.files.remove(name).is_some();
            active || file
        };
        match std::fs::remove_file(&path) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                if !known {
                    return Err(BridgeError::new(
                        ErrorCode::NotFound,
                        format!("no plugin named {name:?} is installed"),
                    ));
                }
            }
            Err(e) => {
                tracing::error!(plugin = name, file = %path.display(), error = %e, "plugin file not deleted");
                return Err(BridgeError::new(
                    ErrorCode::Internal,
                    format!(
                        "plugin {name} unloaded, but its file {name}.wasm in the plugins folder could not be deleted (it will load again at the next start); the service log has the cause"
                    ),
                ));
            }
        }
        self.prune_cache();
        tracing::info!(plugin = name, "plugin removed");
        Ok(())
    }

    /// Brings the registry in line with the folder: loads new and changed
    /// `<name>.wasm` files, unloads plugins whose file is gone. A file counts
    /// as changed when its modification time or size changed, or, with
    /// `deep` (after change events), when its content did (file times can
    /// be coarse). Returns the number of changes.
    pub async fn scan(&self, deep: bool) -> usize {
        let _guard = self.changes.lock().await;
        let on_disk = list_folder(&self.dir);
        let mut changes = 0;
        let gone: Vec<String> = {
            let table = self.table();
            table
                .files
                .keys()
                .chain(table.active.keys())
                .filter(|n| !on_disk.contains_key(*n))
                .cloned()
                .collect()
        };
        for name in gone {
            let mut table = self.table_mut();
            table.files.remove(&name);
            if table.active.remove(&name).is_some() {
                tracing::info!(plugin = %name, "plugin file removed; plugin unloaded");
                changes += 1;
            }
        }
        for (name, stamp) in on_disk {
            let seen = self.table().files.get(&name).cloned();
            if !deep && seen.as_ref().is_some_and(|s| s.stamp == stamp) {
                continue;
            }
            if self.load_file(&name, stamp, seen).await {
                changes += 1;
            }
        }
        if changes > 0 {
            self.prune_cache();
        }
        changes
    }

    /// Loads a file unless its content is the one last seen; true when
    /// something changed.
    async fn load_file(&self, name: &str, stamp: FileStamp, seen: Option<FileSeen>) -> bool {
        let path = self.file_path(name);
        let bytes = std::fs::read(&path);
        let sha256 = bytes
            .as_ref()
            .map_or_else(|_| String::new(), |b| kuka_plugin_host::sha256_hex(b));
        if let Some(seen) = seen.filter(|s| !sha256.is_empty() && s.sha256 == sha256) {
            // Same content: only the file's times changed.
            let seen = FileSeen { stamp, ..seen };
            self.table_mut().files.insert(name.to_string(), seen);
            return false;
        }
        let result = match bytes {
            Err(e) => {
                tracing::error!(plugin = name, file = %path.display(), error = %e, "plugin file not readable");
                Err(ErrorBody {
                    code: ErrorCode::Internal.as_str(),
                    detail: format!(
                        "{name}.wasm in the plugins folder cannot be read; the service log has the cause"
                    ),
                })
            }
            Ok(bytes) if bytes.len() > self.max_wasm_bytes => Err(ErrorBody {
                code: ErrorCode::PayloadTooLarge.as_str(),
                detail: format!(
                    "{name}.wasm has {} bytes; plugins.max_wasm_bytes is {}",
                    bytes.len(),
                    self.max_wasm_bytes
                ),
            }),
            Ok(bytes) => {
                if self.get(name).is_some_and(|p| p.sha256 == sha256) {
                    let seen = FileSeen {
                        stamp,
                        sha256,
                        error: None,
                    };
                    self.table_mut().files.insert(name.to_string(), seen);
                    return false;
                }
                self.host.load(name, bytes.into()).await.map_err(|e| {
                    let b = plugin_error(&e);
                    ErrorBody {
                        code: b.code.as_str(),
                        detail: b.detail,
                    }
                })
            }
        };
        let mut table = self.table_mut();
        match result {
            Ok(plugin) => {
                tracing::info!(plugin = name, version = %plugin.version, file = %path.display(), "plugin loaded from the plugins folder");
                table.active.insert(name.to_string(), Arc::new(plugin));
                let seen = FileSeen {
                    stamp,
                    sha256,
                    error: None,
                };
                table.files.insert(name.to_string(), seen);
            }
            Err(e) => {
                let serving = table.active.get(name).map(|p| p.version.to_string());
                tracing::warn!(plugin = name, file = %path.display(), code = e.code, error = %e.detail,
                    still_serving = ?serving, "plugin file not loaded");
                // A busy instance pool is no verdict on the file: forget
                // what was seen, so the next scan tries again.
                let transient = e.code == ErrorCode::QueueFull.as_str();
                let seen = FileSeen {
                    stamp: if transient { FileStamp::UNSEEN } else { stamp },
                    sha256: if transient { String::new() } else { sha256 },
                    error: Some(e),
                };
                table.files.insert(name.to_string(), seen);
            }
        }
        true
    }

    fn prune_cache(&self) {
        let keep: Vec<String> = self.active().iter().map(|p| p.sha256.clone()).collect();
        self.host.prune_cache(&keep);
    }
}

fn stamp(path: &Path) -> FileStamp {
    let meta = std::fs::metadata(path).ok();
    FileStamp {
        modified: meta.as_ref().and_then(|m| m.modified().ok()),
        len: meta.map_or(0, |m| m.len()),
    }
}

/// The `<name>.wasm` files of the folder with valid names.
fn list_folder(dir: &Path) -> BTreeMap<String, FileStamp> {
    let mut out = BTreeMap::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let Some(name) = path
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_suffix(".wasm"))
        else {
            continue;
        };
        if !path.is_file() {
            continue;
        }
        if let Err(e) = kuka_plugin_host::check_name(name) {
            warn_once(&path, &e);
            continue;
        }
        out.insert(name.to_string(), stamp(&path));
    }
    out
}

/// Says once per file (not every scan) that a `.wasm` with an invalid
/// name is ignored (e.g. cargo's `my_plugin.wasm`: rename it `my-plugin.wasm`).
fn warn_once(path: &Path, problem: &str) {
    use std::collections::BTreeSet;
    use std::sync::Mutex;
    static WARNED: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());
    let mut warned = WARNED.lock().unwrap_or_else(|p| p.into_inner());
    if warned.insert(path.to_path_buf()) {
        tracing::warn!(file = %path.display(), error = %problem,
            "ignoring a file in the plugins folder: the file name (without .wasm) must be the plugin's name");
    }
}

/// Writes through a temporary file and a rename, so the folder watcher
/// never sees half a plugin.
fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut file = atomic_write_file::AtomicWriteFile::open(path)?;
    file.write_all(bytes)?;
    file.commit()
}

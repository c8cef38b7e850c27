//! The compiled-artifact cache: a component is compiled once (81 ms for a
//! small Rust guest, ~6 s for a Python one) and its native code kept as
//! `<cache>/<sha256 of the .wasm>-<engine key>.cwasm`, so restarts and
//! reloads only deserialize it (< 1 ms). Stale or foreign artifacts are
//! ignored and rebuilt.
//!
//! Deserializing runs native code that wasmtime produced: only files this
//! host wrote into its own cache folder are loaded, and that folder must be
//! writable by the service account and administrators only (it lives in
//! the service's data folder).

use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};
use wasmtime::Engine;
use wasmtime::component::Component;

/// Where compiled components are kept.
#[derive(Debug, Clone)]
pub(crate) struct ArtifactCache {
    dir: Option<PathBuf>,
    engine_key: String,
}

/// Hex SHA-256 of some bytes.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex::encode(Sha256::digest(bytes))
}

impl ArtifactCache {
    /// A cache in `dir` (`None`: always compile).
    pub(crate) fn new(dir: Option<PathBuf>, engine: &Engine) -> Self {
        // Artifacts are only valid for the same wasmtime version and engine
        // settings: wasmtime's own compatibility hash names them.
        let mut h = std::collections::hash_map::DefaultHasher::new();
        engine.precompile_compatibility_hash().hash(&mut h);
        let engine_key = format!("{:016x}", h.finish());
        ArtifactCache { dir, engine_key }
    }

    fn path(&self, sha: &str) -> Option<PathBuf> {
        self.dir
            .as_ref()
            .map(|d| d.join(format!("{sha}-{}.cwasm", self.engine_key)))
    }

    /// The component for these bytes, from the cache when possible.
    /// Returns the component and whether it came from the cache. A miss is
    /// compiled by `compiler` (an engine of its own, dropped afterwards with
    /// Cranelift's working memory, see `runtime::compiler`) and loaded into
    /// `engine`.
    pub(crate) fn component(
        &self,
        engine: &Engine,
        compiler: impl FnOnce() -> Result<Engine, crate::PluginError>,
        wasm: &[u8],
        sha: &str,
    ) -> Result<(Component, bool), wasmtime::Error> {
        let path = self.path(sha);
        if let Some(c) = path.as_deref().and_then(|p| load(engine, p)) {
            return Ok((c, true));
        }
        let artifact = {
            let compiler = compiler().map_err(wasmtime::Error::msg)?;
            compiler.precompile_component(wasm)?
        };
        if let Some(path) = &path {
            store(path, &artifact);
        }
        // SAFETY: the bytes are an artifact `precompile_component` has just
        // produced with the settings of `engine` (wasmtime checks that too).
        #[allow(unsafe_code)]
        let component = unsafe { Component::deserialize(engine, &artifact)? };
        Ok((component, false))
    }

    /// Removes artifacts of other wasmtime versions, and those whose source
    /// is no longer installed except the [`KEEP_UNINSTALLED`] newest: going
    /// back to a recent version does not recompile it.
    pub(crate) fn prune(&self, keep: &[String]) {
        let Some(dir) = &self.dir else { return };
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        let mut uninstalled = Vec::new();
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let Some(stem) = name.strip_suffix(".cwasm") else {
                continue;
            };
            let sha = stem.split('-').next().unwrap_or_default();
            if !stem.ends_with(&self.engine_key) {
                let _ = std::fs::remove_file(entry.path());
            } else if !keep.iter().any(|k| k == sha) {
                let modified = entry.metadata().and_then(|m| m.modified()).ok();
                uninstalled.push((modified, entry.path()));
            }
        }
        // Newest first; the oldest beyond the allowance go.
        uninstalled.sort_by_key(|u| std::cmp::Reverse(u.0));
        for (_, path) in uninstalled.into_iter().skip(KEEP_UNINSTALLED) {
            let _ = std::fs::remove_file(path);
        }
    }
}

/// Artifacts of plugin versions no longer installed that are kept (newest
/// first) for a quick roll-back.
const KEEP_UNINSTALLED: usize = 8;

/// Loads an artifact; `None` when missing or not loadable (then it is rebuilt).
fn load(engine: &Engine, path: &Path) -> Option<Component> {
    // Read into memory rather than mmap (`deserialize_file`): the mmap path
    // fails under Wine, and a plugin is small next to the time this saves.
    let bytes = std::fs::read(path).ok()?;
    // SAFETY: `Component::deserialize` trusts that the bytes are an artifact
    // of `Engine::precompile_component`. The file's name carries the SHA-256
    // of its source and wasmtime's compatibility hash; it lives in the
    // service's private cache folder, written only by `store` below, and
    // wasmtime itself rejects artifacts of another version or configuration.
    #[allow(unsafe_code)]
    let result = unsafe { Component::deserialize(engine, &bytes) };
    match result {
        Ok(c) => Some(c),
        Err(e) => {
            tracing::warn!(path = %path.display(), error = %e, "cached plugin artifact not usable; recompiling");
            let _ = std::fs::remove_file(path);
            None
        }
    }
}

/// Writes an artifact atomically (temp file + rename); a failure only costs
/// a recompilation next time.
fn store(path: &Path, artifact: &[u8]) {
    let tmp = path.with_extension("cwasm.tmp");
    let result = path
        .parent()
        .map_or(Ok(()), std::fs::create_dir_all)
        .and_then(|()| std::fs::write(&tmp, artifact))
        .and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        tracing::warn!(path = %path.display(), error = %e, "cannot cache the compiled plugin");
    }
}

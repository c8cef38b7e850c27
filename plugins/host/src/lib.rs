//! The kuka-bridge WASM plugin host, in the spirit of Spin's narrow wasmtime
//! wrapper: it compiles components of the `kuka-bridge:plugin/bridge-plugin`
//! world (`plugins/wit/plugin.wit`), checks what they describe, and runs each
//! HTTP request to a plugin in a fresh, limited store.
//!
//! - [`PluginHost::load`]: compile (or take from the artifact cache),
//!   link against the host interface, call `describe()` once and validate it.
//! - [`PluginHost::call`]: one request → one fresh store with its memory
//!   limit, guest-CPU budget (epoch interruption), total time limit and
//!   motion allowance; errors come back as [`PluginError`] with stable codes.
//! - The plugin reaches the robot only through [`BridgeApi`], which the
//!   service implements with its own validation, safety checks and queue.
//!
//! This is the only crate of the workspace that depends on wasmtime.

/// Plugin requests (instances) that may run at the same time.
pub const MAX_CONCURRENT_REQUESTS: u32 = 64;

mod bindings;
mod cache;
mod call;
mod describe;
mod error;
mod imports;
mod memory;
mod runtime;
mod schema;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

pub use bindings::{
    AnyMotion, AnyStep, Axes, CircMotion, Description, Done, HostError, LinMotion, LogLevel,
    Motion, MotionParams, Point, Pose, Position, PtpAxesMotion, PtpMotion, Request, Response,
    ScircMotion, SetOutput, SlinMotion, SplPoint, SptpMotion, Step, SwitchOutput, WaitInput,
};
pub use cache::sha256_hex;
pub use describe::{METHODS, RouteSpec, check_name};
pub use error::PluginError;
pub use imports::{BoxFuture, BridgeApi, CallContext, Caller, host_error};
pub use schema::{Refusal, Violation, query_object};

/// The WIT package version this host implements.
pub const WIT_VERSION: &str = "kuka-bridge:plugin@0.1.0";

/// Limits applied to every plugin request.
#[derive(Debug, Clone)]
pub struct PluginLimits {
    /// Largest size of one linear memory of the guest, in bytes.
    pub memory_bytes: usize,
    /// Guest CPU time per request (time spent in host calls not counted).
    pub cpu_time: Duration,
    /// Wall time per request, host calls (motions) included.
    pub request_time: Duration,
    /// Most motions one request may run, over all its `run-motions`,
    /// `run-steps` and `run-spline-motions` calls.
    pub max_motions: usize,
    /// Largest response body, in bytes.
    pub max_response_bytes: usize,
}

impl Default for PluginLimits {
    fn default() -> Self {
        PluginLimits {
            memory_bytes: 64 << 20,
            cpu_time: Duration::from_millis(500),
            request_time: Duration::from_secs(600),
            max_motions: 1000,
            max_response_bytes: 1 << 20,
        }
    }
}

/// A plugin ready to serve requests (immutable; replaced as a whole on reload).
pub struct LoadedPlugin {
    /// Its name (the URL prefix).
    pub name: Arc<str>,
    /// The version it describes.
    pub version: Arc<str>,
    /// Its checked routes.
    pub routes: Vec<RouteSpec>,
    /// SHA-256 of the .wasm, hex.
    pub sha256: String,
    /// Size of the .wasm in bytes.
    pub wasm_bytes: usize,
    /// True when the compiled code came from the artifact cache.
    pub from_cache: bool,
    /// Time to compile (or deserialize), link and describe it.
    pub load_time: Duration,
    pre: bindings::BridgePluginPre<imports::RequestState>,
    /// Last field: dropped after `pre` (the compiled code and its metadata),
    /// it hands the freed memory back to the operating system.
    _trim: memory::TrimOnDrop,
}

impl std::fmt::Debug for LoadedPlugin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedPlugin")
            .field("name", &self.name)
            .field("version", &self.version)
            .field("routes", &self.routes.len())
            .field("sha256", &self.sha256)
            .finish_non_exhaustive()
    }
}

impl LoadedPlugin {
    /// The route for a method and path, if the plugin declared it.
    pub fn route(&self, method: &str, path: &str) -> Option<&RouteSpec> {
        self.routes
            .iter()
            .find(|r| r.method == method && r.path == path)
    }
}

/// Compiles, checks and runs plugins.
pub struct PluginHost {
    runtime: runtime::Runtime,
    cache: cache::ArtifactCache,
    limits: PluginLimits,
    overrides: BTreeMap<String, PluginLimits>,
    api: Arc<dyn BridgeApi>,
}

impl PluginHost {
    /// A host whose plugins reach the robot through `api`; compiled code is
    /// cached in `cache_dir` (`None`: compile on every load). `overrides`
    /// replaces `limits` for the plugins it names; no memory limit may
    /// exceed `limits.memory_bytes` (the size of the pool's memory slots).
    pub fn new(
        limits: PluginLimits,
        overrides: BTreeMap<String, PluginLimits>,
        cache_dir: Option<PathBuf>,
        api: Arc<dyn BridgeApi>,
    ) -> Result<Self, PluginError> {
        if let Some((name, _)) = overrides
            .iter()
            .find(|(_, l)| l.memory_bytes > limits.memory_bytes)
        {
            return Err(PluginError::Host(format!(
                "the memory limit of plugin {name} is above the global one"
            )));
        }
        memory::tune_allocator();
        let runtime = runtime::Runtime::new(limits.memory_bytes)?;
        let cache = cache::ArtifactCache::new(cache_dir, runtime.engine());
        Ok(PluginHost {
            runtime,
            cache,
            limits,
            overrides,
            api,
        })
    }

    /// The limits applied to the requests of one plugin.
    pub fn limits(&self, plugin: &str) -> &PluginLimits {
        self.overrides.get(plugin).unwrap_or(&self.limits)
    }

    /// Compiles `wasm` (or takes it from the cache), checks that it is a
    /// plugin of our world named `name`, and describes it. Compilation runs
    /// on a blocking thread (a Python plugin takes seconds).
    pub async fn load(&self, name: &str, wasm: Arc<[u8]>) -> Result<LoadedPlugin, PluginError> {
        check_name(name).map_err(|e| PluginError::InvalidDescription(vec![e]))?;
        // However the load ends, the memory it freed (a compilation's working
        // memory) goes back to the system.
        let trim = memory::TrimOnDrop;
        let started = Instant::now();
        let sha256 = sha256_hex(&wasm);
        let (component, from_cache) = {
            let engine = self.runtime.engine().clone();
            let cache = self.cache.clone();
            let wasm = wasm.clone();
            let sha = sha256.clone();
            tokio::task::spawn_blocking(move || {
                cache.component(&engine, runtime::compiler, &wasm, &sha)
            })
            .await
            .map_err(|e| PluginError::Host(format!("compiler thread: {e}")))?
            .map_err(|e| PluginError::NotComponent(error::one_line(&format!("{e:#}"))))?
        };
        let pre = self.runtime.link(&component)?;
        let description = call::describe(&self.runtime, &pre, name, &self.limits).await?;
        let routes =
            describe::check(name, &description).map_err(PluginError::InvalidDescription)?;
        drop(trim);
        let plugin = LoadedPlugin {
            name: name.into(),
            version: description.version.into(),
            routes,
            sha256,
            wasm_bytes: wasm.len(),
            from_cache,
            load_time: started.elapsed(),
            pre,
            _trim: memory::TrimOnDrop,
        };
        tracing::info!(
            plugin = name, version = %plugin.version, routes = plugin.routes.len(),
            from_cache, load_ms = plugin.load_time.as_millis() as u64, "plugin loaded"
        );
        Ok(plugin)
    }

    /// Runs one request in a fresh store with the configured limits;
    /// `caller` comes back to [`BridgeApi`] in [`CallContext::caller`].
    pub async fn call(
        &self,
        plugin: &LoadedPlugin,
        request: Request,
        caller: Option<Caller>,
    ) -> Result<Response, PluginError> {
        call::handle(
            &self.runtime,
            plugin,
            request,
            self.limits(&plugin.name),
            self.api.clone(),
            caller,
        )
        .await
    }

    /// Deletes cached artifacts of plugins no longer installed.
    pub fn prune_cache(&self, installed_sha256: &[String]) {
        self.cache.prune(installed_sha256);
    }
}

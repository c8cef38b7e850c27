//! What a plugin may call: the `host`, `paths`, `io` and `splines`
//! interfaces of the WIT, implemented by forwarding to a [`BridgeApi`] that
//! the service provides through the same validation, safety checks and
//! queue as its HTTP endpoints. Also the
//! per-request store state (empty WASI, captured stderr, memory limiter,
//! time spent in host calls, motions asked for).

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::time::{Duration, Instant};

use wasmtime::component::ResourceTable;
use wasmtime::{ResourceLimiter, StoreLimits, StoreLimitsBuilder};
use wasmtime_wasi::p2::pipe::MemoryOutputPipe;
use wasmtime_wasi::{WasiCtx, WasiCtxBuilder, WasiCtxView, WasiView};

use crate::PluginLimits;
use crate::bindings::{
    AnyMotion, AnyStep, Done, HostError, LogLevel, Motion, Pose, Position, Step,
};

/// A boxed future, as [`BridgeApi::run_motions`] returns it.
pub type BoxFuture<'a, T> = Pin<Box<dyn Future<Output = T> + Send + 'a>>;

/// Who is calling the bridge: the plugin, on behalf of one HTTP request.
#[derive(Debug, Clone)]
pub struct CallContext {
    /// The plugin's name.
    pub plugin: Arc<str>,
    /// The plugin's version.
    pub version: Arc<str>,
    /// How long the plugin's request may take (a batch may run as long).
    pub request_time: std::time::Duration,
    /// Who made the request, as the embedder passed it to
    /// [`crate::PluginHost::call`]: opaque to the host, handed back
    /// untouched (the service puts its request context here, so a
    /// plugin's motions run as the HTTP caller's).
    pub caller: Option<Caller>,
}

/// The embedder's identity of a plugin request's caller (see
/// [`CallContext::caller`]).
pub type Caller = Arc<dyn std::any::Any + Send + Sync>;

/// The bridge as a plugin sees it. The service implements it with the same
/// code path as its REST API, so a plugin cannot do what a client could not.
pub trait BridgeApi: Send + Sync + 'static {
    /// Validates the motions and runs them as one continuous batch; resolves
    /// when the batch has ended.
    fn run_motions<'a>(
        &'a self,
        ctx: &'a CallContext,
        motions: Vec<Motion>,
    ) -> BoxFuture<'a, Result<Done, HostError>>;
    /// The latest known position.
    fn position(&self) -> Result<Position, HostError>;
    /// The state as `GET /api/v1/state` answers it (JSON text).
    fn state_json(&self) -> String;
    /// The current tool frame.
    fn tool(&self) -> Result<Pose, HostError>;
    /// The current base frame.
    fn base(&self) -> Result<Pose, HostError>;
    /// Opens a path (a motion stream) for the plugin's caller; its id.
    fn open_path<'a>(&'a self, ctx: &'a CallContext) -> BoxFuture<'a, Result<u64, HostError>> {
        let _ = ctx;
        Box::pin(async { Err(paths_unavailable()) })
    }
    /// Appends motions to a path (all or none, waiting while it is full);
    /// how many it holds now.
    fn append<'a>(
        &'a self,
        ctx: &'a CallContext,
        path: u64,
        motions: Vec<Motion>,
    ) -> BoxFuture<'a, Result<u32, HostError>> {
        let _ = (ctx, path, motions);
        Box::pin(async { Err(paths_unavailable()) })
    }
    /// Closes a path and waits until its last motion has run.
    fn finish_path<'a>(
        &'a self,
        ctx: &'a CallContext,
        path: u64,
    ) -> BoxFuture<'a, Result<Done, HostError>> {
        let _ = (ctx, path);
        Box::pin(async { Err(paths_unavailable()) })
    }
    /// Stops the robot and cancels a path.
    fn cancel_path<'a>(&'a self, path: u64) -> BoxFuture<'a, Result<(), HostError>> {
        let _ = path;
        Box::pin(async { Err(paths_unavailable()) })
    }
    /// Validates the steps (motions and I/O actions) and runs them as one
    /// continuous batch; resolves when the batch has ended.
    fn run_steps<'a>(
        &'a self,
        ctx: &'a CallContext,
        steps: Vec<Step>,
    ) -> BoxFuture<'a, Result<Done, HostError>> {
        let _ = (ctx, steps);
        Box::pin(async { Err(io_unavailable()) })
    }
    /// The value of an input (`output` false) or output, by number or
    /// configured name, from the controller's latest state.
    fn read_signal(&self, output: bool, signal: &str) -> Result<bool, HostError> {
        let _ = (output, signal);
        Err(io_unavailable())
    }
    /// Sets an allow-listed output (queued like every command).
    fn write_output<'a>(
        &'a self,
        ctx: &'a CallContext,
        signal: String,
        value: bool,
        pulse_ms: Option<u32>,
    ) -> BoxFuture<'a, Result<(), HostError>> {
        let _ = (ctx, signal, value, pulse_ms);
        Box::pin(async { Err(io_unavailable()) })
    }
    /// Validates the motions of either family (conventional and spline)
    /// and runs them as one continuous batch; resolves when the batch has
    /// ended.
    fn run_spline_motions<'a>(
        &'a self,
        ctx: &'a CallContext,
        motions: Vec<AnyMotion>,
    ) -> BoxFuture<'a, Result<Done, HostError>> {
        let _ = (ctx, motions);
        Box::pin(async { Err(splines_unavailable()) })
    }
    /// Appends motions of either family to a path (all or none, waiting
    /// while it is full); how many it holds now.
    fn append_spline_motions<'a>(
        &'a self,
        ctx: &'a CallContext,
        path: u64,
        motions: Vec<AnyMotion>,
    ) -> BoxFuture<'a, Result<u32, HostError>> {
        let _ = (ctx, path, motions);
        Box::pin(async { Err(splines_unavailable()) })
    }
    /// Validates steps (motions of either family and I/O actions, outputs
    /// switched at a distance) and runs them as one continuous batch;
    /// resolves when the batch has ended.
    fn run_any_steps<'a>(
        &'a self,
        ctx: &'a CallContext,
        steps: Vec<AnyStep>,
    ) -> BoxFuture<'a, Result<Done, HostError>> {
        let _ = (ctx, steps);
        Box::pin(async { Err(steps_unavailable()) })
    }
    /// Appends such steps to a path (all or none, waiting while it is
    /// full); how many motions it holds now.
    fn append_any_steps<'a>(
        &'a self,
        ctx: &'a CallContext,
        path: u64,
        steps: Vec<AnyStep>,
    ) -> BoxFuture<'a, Result<u32, HostError>> {
        let _ = (ctx, path, steps);
        Box::pin(async { Err(steps_unavailable()) })
    }
    /// A path the plugin's request left open when it ended (returned,
    /// trapped, timed out): closed in the background, so the robot ends at
    /// its last appended motion and the controller is free again.
    fn abandon_path(&self, path: u64) {
        let _ = path;
    }
}

fn paths_unavailable() -> HostError {
    host_error(
        "not_allowed",
        "paths are not available in this bridge",
        None,
    )
}

fn splines_unavailable() -> HostError {
    host_error(
        "not_allowed",
        "spline motions are not available in this bridge",
        None,
    )
}

fn steps_unavailable() -> HostError {
    host_error(
        "not_allowed",
        "motion steps are not available in this bridge",
        None,
    )
}

fn io_unavailable() -> HostError {
    host_error("not_allowed", "I/O is not available in this bridge", None)
}

/// Builds a [`HostError`].
pub fn host_error(code: &str, detail: impl Into<String>, motion: Option<u32>) -> HostError {
    HostError {
        code: code.to_string(),
        detail: detail.into(),
        motion,
    }
}

/// Most bytes of guest stderr kept per request.
const STDERR_CAPACITY: usize = 64 * 1024;

/// The state of one request's store.
pub(crate) struct RequestState {
    wasi: WasiCtx,
    table: ResourceTable,
    pub(crate) limiter: Limiter,
    pub(crate) stderr: MemoryOutputPipe,
    api: Option<Arc<dyn BridgeApi>>,
    ctx: CallContext,
    /// Wall time spent inside host calls, given back to the guest's CPU budget.
    pub(crate) host_time: Duration,
    /// Set by the epoch callback when the CPU budget ran out.
    pub(crate) cpu_exhausted: bool,
    motions_left: usize,
    /// Paths this request opened and has not finished or cancelled.
    open_paths: Vec<u64>,
}

impl Drop for RequestState {
    fn drop(&mut self) {
        if let Some(api) = &self.api {
            for path in self.open_paths.drain(..) {
                tracing::info!(plugin = %self.ctx.plugin, path, "the plugin's request ended with its path open; closing it");
                api.abandon_path(path);
            }
        }
    }
}

impl RequestState {
    /// `api` is `None` while `describe()` runs: no motions, no state reads.
    pub(crate) fn new(
        limits: &PluginLimits,
        api: Option<Arc<dyn BridgeApi>>,
        ctx: CallContext,
    ) -> Self {
        let stderr = MemoryOutputPipe::new(STDERR_CAPACITY);
        // No preopened folders, environment, arguments, network or stdin:
        // the only way out of the sandbox is the `host` interface. (Sockets
        // are denied by wasmtime's default address check already; switched
        // off here explicitly.) Clocks and random numbers stay: a guest
        // language runtime needs them and they reach nothing.
        let wasi = WasiCtxBuilder::new()
            .stderr(stderr.clone())
            .allow_tcp(false)
            .allow_udp(false)
            .allow_ip_name_lookup(false)
            .build();
        RequestState {
            wasi,
            table: ResourceTable::new(),
            limiter: Limiter::new(limits.memory_bytes),
            stderr,
            api,
            ctx,
            host_time: Duration::ZERO,
            cpu_exhausted: false,
            motions_left: limits.max_motions,
            open_paths: Vec::new(),
        }
    }

    /// Takes `count` motions (or steps) from the request's allowance
    /// (`max_motions`), or refuses them all with `plugin_motion_limit`.
    fn take_motions(&mut self, count: usize) -> Result<(), HostError> {
        if count > self.motions_left {
            return Err(host_error(
                "plugin_motion_limit",
                format!(
                    "this request may run {} more motions, the plugin asked for {count}",
                    self.motions_left,
                ),
                None,
            ));
        }
        self.motions_left -= count;
        Ok(())
    }

    fn api(&self, what: &str) -> Result<Arc<dyn BridgeApi>, HostError> {
        self.api.clone().ok_or_else(|| {
            host_error(
                "not_allowed",
                format!("{what} is not available while the plugin describes itself"),
                None,
            )
        })
    }
}

impl WasiView for RequestState {
    fn ctx(&mut self) -> WasiCtxView<'_> {
        WasiCtxView {
            ctx: &mut self.wasi,
            table: &mut self.table,
        }
    }
}

/// Memory limits that remember a refusal (so the error is `plugin_memory`,
/// whatever the guest's language does with a failed allocation).
pub(crate) struct Limiter {
    inner: StoreLimits,
    pub(crate) refused: bool,
}

impl Limiter {
    fn new(memory_bytes: usize) -> Self {
        Limiter {
            inner: StoreLimitsBuilder::new()
                .memory_size(memory_bytes)
                // Counts of *core* instances/tables/memories inside the
                // component: a componentize-py guest needs more than 4.
                .instances(64)
                .tables(64)
                .memories(8)
                .trap_on_grow_failure(true)
                .build(),
            refused: false,
        }
    }
}

impl ResourceLimiter for Limiter {
    fn memory_growing(
        &mut self,
        current: usize,
        desired: usize,
        maximum: Option<usize>,
    ) -> wasmtime::Result<bool> {
        let r = self.inner.memory_growing(current, desired, maximum);
        if !matches!(r, Ok(true)) {
            self.refused = true;
        }
        r
    }

    fn table_growing(
        &mut self,
        current: usize,
        desired: usize,
        maximum: Option<usize>,
    ) -> wasmtime::Result<bool> {
        self.inner.table_growing(current, desired, maximum)
    }

    fn instances(&self) -> usize {
        self.inner.instances()
    }

    fn tables(&self) -> usize {
        self.inner.tables()
    }

    fn memories(&self) -> usize {
        self.inner.memories()
    }
}

impl crate::bindings::kuka_bridge::plugin::types::Host for RequestState {}

impl RequestState {
    /// A path this request opened, else the error to return.
    fn own_path(&self, path: u64) -> Result<Arc<dyn BridgeApi>, HostError> {
        let api = self.api("paths")?;
        if self.open_paths.contains(&path) {
            Ok(api)
        } else {
            Err(host_error(
                "not_allowed",
                format!("path {path} was not opened by this request (or is finished)"),
                None,
            ))
        }
    }
}

impl crate::bindings::kuka_bridge::plugin::paths::Host for RequestState {
    async fn open_path(&mut self) -> wasmtime::Result<Result<u64, HostError>> {
        let api = match self.api("open-path") {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        let started = Instant::now();
        let result = api.open_path(&self.ctx).await;
        self.host_time += started.elapsed();
        if let Ok(path) = result {
            tracing::debug!(plugin = %self.ctx.plugin, path, "plugin opened a path");
            self.open_paths.push(path);
        }
        Ok(result)
    }

    async fn append(
        &mut self,
        path: u64,
        motions: Vec<Motion>,
    ) -> wasmtime::Result<Result<u32, HostError>> {
        let api = match self.own_path(path) {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        let started = Instant::now();
        let result = api.append(&self.ctx, path, motions).await;
        self.host_time += started.elapsed();
        Ok(result)
    }

    async fn finish(&mut self, path: u64) -> wasmtime::Result<Result<Done, HostError>> {
        let api = match self.own_path(path) {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        let started = Instant::now();
        let result = api.finish_path(&self.ctx, path).await;
        self.host_time += started.elapsed();
        self.open_paths.retain(|p| *p != path);
        Ok(result)
    }

    async fn cancel(&mut self, path: u64) -> wasmtime::Result<Result<(), HostError>> {
        let api = match self.own_path(path) {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        let result = api.cancel_path(path).await;
        self.open_paths.retain(|p| *p != path);
        Ok(result)
    }
}

impl crate::bindings::kuka_bridge::plugin::io::Host for RequestState {
    async fn run_steps(&mut self, steps: Vec<Step>) -> wasmtime::Result<Result<Done, HostError>> {
        let api = match self.api("run-steps") {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        if let Err(e) = self.take_motions(steps.len()) {
            return Ok(Err(e));
        }
        tracing::debug!(plugin = %self.ctx.plugin, steps = steps.len(), "plugin runs steps");
        let started = Instant::now();
        let result = api.run_steps(&self.ctx, steps).await;
        self.host_time += started.elapsed();
        Ok(result)
    }

    async fn read_input(&mut self, signal: String) -> wasmtime::Result<Result<bool, HostError>> {
        Ok(self
            .api("read-input")
            .and_then(|api| api.read_signal(false, &signal)))
    }

    async fn read_output(&mut self, signal: String) -> wasmtime::Result<Result<bool, HostError>> {
        Ok(self
            .api("read-output")
            .and_then(|api| api.read_signal(true, &signal)))
    }

    async fn write_output(
        &mut self,
        signal: String,
        value: bool,
        pulse_ms: Option<u32>,
    ) -> wasmtime::Result<Result<(), HostError>> {
        let api = match self.api("write-output") {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        let started = Instant::now();
        let result = api.write_output(&self.ctx, signal, value, pulse_ms).await;
        self.host_time += started.elapsed();
        Ok(result)
    }
}

impl crate::bindings::kuka_bridge::plugin::splines::Host for RequestState {
    async fn run_spline_motions(
        &mut self,
        motions: Vec<AnyMotion>,
    ) -> wasmtime::Result<Result<Done, HostError>> {
        let api = match self.api("run-spline-motions") {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        if let Err(e) = self.take_motions(motions.len()) {
            return Ok(Err(e));
        }
        tracing::debug!(plugin = %self.ctx.plugin, motions = motions.len(), "plugin runs spline motions");
        let started = Instant::now();
        let result = api.run_spline_motions(&self.ctx, motions).await;
        self.host_time += started.elapsed();
        Ok(result)
    }

    async fn append_spline_motions(
        &mut self,
        path: u64,
        motions: Vec<AnyMotion>,
    ) -> wasmtime::Result<Result<u32, HostError>> {
        let api = match self.own_path(path) {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        let started = Instant::now();
        let result = api.append_spline_motions(&self.ctx, path, motions).await;
        self.host_time += started.elapsed();
        Ok(result)
    }
}

impl crate::bindings::kuka_bridge::plugin::steps::Host for RequestState {
    async fn run_steps(
        &mut self,
        steps: Vec<AnyStep>,
    ) -> wasmtime::Result<Result<Done, HostError>> {
        let api = match self.api("steps.run-steps") {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        if let Err(e) = self.take_motions(steps.len()) {
            return Ok(Err(e));
        }
        tracing::debug!(plugin = %self.ctx.plugin, steps = steps.len(), "plugin runs steps of either family");
        let started = Instant::now();
        let result = api.run_any_steps(&self.ctx, steps).await;
        self.host_time += started.elapsed();
        Ok(result)
    }

    async fn append_steps(
        &mut self,
        path: u64,
        steps: Vec<AnyStep>,
    ) -> wasmtime::Result<Result<u32, HostError>> {
        let api = match self.own_path(path) {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        let started = Instant::now();
        let result = api.append_any_steps(&self.ctx, path, steps).await;
        self.host_time += started.elapsed();
        Ok(result)
    }
}

impl crate::bindings::kuka_bridge::plugin::host::Host for RequestState {
    async fn run_motions(
        &mut self,
        motions: Vec<Motion>,
    ) -> wasmtime::Result<Result<Done, HostError>> {
        let api = match self.api("run-motions") {
            Ok(api) => api,
            Err(e) => return Ok(Err(e)),
        };
        if let Err(e) = self.take_motions(motions.len()) {
            return Ok(Err(e));
        }
        tracing::debug!(plugin = %self.ctx.plugin, motions = motions.len(), "plugin runs motions");
        let started = Instant::now();
        let result = api.run_motions(&self.ctx, motions).await;
        self.host_time += started.elapsed();
        Ok(result)
    }

    async fn get_position(&mut self) -> wasmtime::Result<Result<Position, HostError>> {
        Ok(self.api("get-position").and_then(|api| api.position()))
    }

    async fn get_state(&mut self) -> wasmtime::Result<String> {
        Ok(self
            .api("get-state")
            .map_or_else(|_| "{}".to_string(), |api| api.state_json()))
    }

    async fn get_tool(&mut self) -> wasmtime::Result<Result<Pose, HostError>> {
        Ok(self.api("get-tool").and_then(|api| api.tool()))
    }

    async fn get_base(&mut self) -> wasmtime::Result<Result<Pose, HostError>> {
        Ok(self.api("get-base").and_then(|api| api.base()))
    }

    async fn log(&mut self, level: LogLevel, message: String) -> wasmtime::Result<()> {
        let message = crate::error::first_chars(&message, 4000);
        let plugin = &*self.ctx.plugin;
        match level {
            LogLevel::Debug => tracing::debug!(plugin, "{message}"),
            LogLevel::Info => tracing::info!(plugin, "{message}"),
            LogLevel::Warn => tracing::warn!(plugin, "{message}"),
            LogLevel::Error => tracing::error!(plugin, "{message}"),
        }
        Ok(())
    }
}

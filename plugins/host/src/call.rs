//! One call into a plugin: a fresh store with the request's limits (memory,
//! guest-CPU budget via epochs, total time via a host-side timeout, motion
//! allowance), the call, and the check of what came back.

use std::sync::Arc;
use std::time::{Duration, Instant};

use wasmtime::{Store, UpdateDeadline};

use crate::bindings::{BridgePluginPre, Description, Request, Response};
use crate::error::{PluginError, Symptoms, classify};
use crate::imports::{BridgeApi, CallContext, Caller, RequestState};
use crate::runtime::Runtime;
use crate::{LoadedPlugin, PluginLimits};

/// CPU budget of `describe()` at load time.
const DESCRIBE_CPU: Duration = Duration::from_secs(2);

/// A store for one call, with the memory limiter and a guest-only CPU budget:
/// each epoch tick the callback gives back the time spent in host calls
/// (a motion may take minutes) and yields to the async runtime, so the
/// host-side timeout can always fire.
fn new_store(
    runtime: &Runtime,
    limits: &PluginLimits,
    cpu: Duration,
    api: Option<Arc<dyn BridgeApi>>,
    ctx: CallContext,
) -> Store<RequestState> {
    let mut store = Store::new(runtime.engine(), RequestState::new(limits, api, ctx));
    store.limiter(|s| &mut s.limiter);
    let started = Instant::now();
    store.set_epoch_deadline(1);
    store.epoch_deadline_callback(move |mut ctx| {
        let state = ctx.data_mut();
        let guest = started.elapsed().saturating_sub(state.host_time);
        if guest >= cpu {
            state.cpu_exhausted = true;
            Ok(UpdateDeadline::Interrupt)
        } else {
            Ok(UpdateDeadline::Yield(1))
        }
    });
    store
}

fn symptoms(store: &Store<RequestState>) -> Symptoms {
    Symptoms {
        memory_refused: store.data().limiter.refused,
        cpu_exhausted: store.data().cpu_exhausted,
    }
}

fn stderr_text(store: &Store<RequestState>) -> String {
    String::from_utf8_lossy(&store.data().stderr.contents()).into_owned()
}

/// Calls `describe()` on a fresh instance (host calls refused).
pub(crate) async fn describe(
    runtime: &Runtime,
    pre: &BridgePluginPre<RequestState>,
    name: &str,
    limits: &PluginLimits,
) -> Result<Description, PluginError> {
    let ctx = CallContext {
        plugin: name.into(),
        version: "".into(),
        request_time: DESCRIBE_CPU * 2,
        caller: None,
    };
    let mut store = new_store(runtime, limits, DESCRIBE_CPU, None, ctx);
    let wall = DESCRIBE_CPU * 2;
    let result = tokio::time::timeout(wall, async {
        let instance = pre.instantiate_async(&mut store).await?;
        instance
            .kuka_bridge_plugin_plugin()
            .call_describe(&mut store)
            .await
    })
    .await;
    let limits = PluginLimits {
        cpu_time: DESCRIBE_CPU,
        ..limits.clone()
    };
    match result {
        Err(_) => Err(PluginError::timeout(wall, "request time")),
        Ok(Err(e)) => Err(classify(
            &e,
            symptoms(&store),
            &stderr_text(&store),
            &limits,
        )),
        Ok(Ok(d)) => Ok(d),
    }
}

/// Runs one request.
pub(crate) async fn handle(
    runtime: &Runtime,
    plugin: &LoadedPlugin,
    request: Request,
    limits: &PluginLimits,
    api: Arc<dyn BridgeApi>,
    caller: Option<Caller>,
) -> Result<Response, PluginError> {
    let _running = runtime.admit()?;
    let ctx = CallContext {
        plugin: plugin.name.clone(),
        version: plugin.version.clone(),
        request_time: limits.request_time,
        caller,
    };
    let mut store = new_store(runtime, limits, limits.cpu_time, Some(api), ctx);
    let result = tokio::time::timeout(limits.request_time, async {
        let instance = plugin.pre.instantiate_async(&mut store).await?;
        instance
            .kuka_bridge_plugin_plugin()
            .call_handle(&mut store, &request)
            .await
    })
    .await;
    let stderr = stderr_text(&store);
    let response = match result {
        Err(_) => Err(PluginError::timeout(limits.request_time, "request time")),
        Ok(Err(e)) => Err(classify(&e, symptoms(&store), &stderr, limits)),
        Ok(Ok(response)) => check_response(response, limits),
    };
    if let Err(e) = &response {
        tracing::warn!(plugin = %plugin.name, code = e.code(), error = %e, "plugin request failed");
    } else if !stderr.is_empty() {
        tracing::debug!(plugin = %plugin.name, stderr = %crate::error::last_chars(&stderr, 2000), "plugin wrote to stderr");
    }
    drop_later(runtime, store);
    response
}

/// Drops a finished store in a task of its own, after the answer has gone:
/// returning its memory and tables to the pool (resetting the pages the
/// guest touched) is work the client need not wait for (≈ 9 µs per request
/// on the 2-vCPU machine, `tests/benches/plugins.rs`). At most
/// [`crate::runtime::MAX_DEFERRED_DROPS`] wait; beyond that a store is dropped here, so a
/// burst of requests cannot pile up unreleased pool slots.
fn drop_later(runtime: &Runtime, store: Store<RequestState>) {
    match runtime.deferred_drops.take() {
        Some(place) => {
            tokio::spawn(async move {
                drop(store);
                drop(place);
            });
        }
        None => drop(store),
    }
}

/// A response must have an HTTP status a handler may send and a JSON body.
fn check_response(response: Response, limits: &PluginLimits) -> Result<Response, PluginError> {
    if !(200..=599).contains(&response.status) {
        return Err(PluginError::BadResponse(format!(
            "status {} is not an HTTP status a plugin may answer (200 to 599)",
            response.status
        )));
    }
    if response.body.len() > limits.max_response_bytes {
        return Err(PluginError::BadResponse(format!(
            "the body has {} bytes; at most {}",
            response.body.len(),
            limits.max_response_bytes
        )));
    }
    if response.status == 204 && response.body.is_empty() {
        return Ok(response);
    }
    if let Err(e) = serde_json::from_str::<serde_json::Value>(&response.body) {
        return Err(PluginError::BadResponse(format!(
            "the body is not JSON ({e}): {:?}",
            crate::error::first_chars(&response.body, 80)
        )));
    }
    Ok(response)
}

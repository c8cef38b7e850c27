//! What can go wrong with a plugin, with the stable codes the REST API
//! answers (`plugin_invalid`, `plugin_timeout`, `plugin_memory`,
//! `plugin_trap`, `plugin_bad_response`, ...), and the classification of
//! wasmtime errors into them.

use std::time::Duration;

/// A plugin could not be loaded or a request to it failed.
#[derive(Debug, thiserror::Error)]
pub enum PluginError {
    /// The bytes are not a WebAssembly component (or do not compile).
    #[error("not a WebAssembly component: {0}")]
    NotComponent(String),
    /// A component, but not of the `kuka-bridge:plugin/bridge-plugin` world
    /// (missing exports, or imports this bridge does not provide).
    #[error("not a kuka-bridge plugin: {0}")]
    WrongWorld(String),
    /// `describe()` returned something the bridge cannot serve.
    #[error("invalid plugin description: {}", .0.join("; "))]
    InvalidDescription(Vec<String>),
    /// The guest used more CPU time than its budget, or the whole request
    /// (host calls included) took longer than allowed.
    #[error("the plugin did not answer within {limit_ms} ms ({what})")]
    Timeout {
        /// The limit that was hit.
        limit_ms: u128,
        /// `CPU time` or `request time`.
        what: &'static str,
    },
    /// The guest tried to grow its memory beyond the limit.
    #[error("the plugin tried to use more than {limit_mib} MiB of memory")]
    Memory {
        /// The limit in MiB.
        limit_mib: usize,
    },
    /// The guest trapped (panic, abort, out-of-bounds access, stack overflow...).
    #[error("the plugin crashed: {0}")]
    Trap(String),
    /// The guest answered, but not with a valid response.
    #[error("the plugin's response is invalid: {0}")]
    BadResponse(String),
    /// All instance slots are taken by requests in flight.
    #[error("{0} plugin requests are already running; try again later")]
    Busy(u32),
    /// Anything else on the host side (a bug, an I/O error of the cache...).
    #[error("plugin host: {0}")]
    Host(String),
}

impl PluginError {
    /// The stable error code of the REST API.
    pub fn code(&self) -> &'static str {
        match self {
            PluginError::NotComponent(_)
            | PluginError::WrongWorld(_)
            | PluginError::InvalidDescription(_) => "plugin_invalid",
            PluginError::Timeout { .. } => "plugin_timeout",
            PluginError::Memory { .. } => "plugin_memory",
            PluginError::Trap(_) => "plugin_trap",
            PluginError::BadResponse(_) => "plugin_bad_response",
            PluginError::Busy(_) => "queue_full",
            PluginError::Host(_) => "plugin_host",
        }
    }

    /// A request-time timeout.
    pub(crate) fn timeout(limit: Duration, what: &'static str) -> Self {
        PluginError::Timeout {
            limit_ms: limit.as_millis(),
            what,
        }
    }
}

/// What the store saw while the guest ran, used to classify its error.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Symptoms {
    /// The memory limiter refused a growth.
    pub memory_refused: bool,
    /// The guest-CPU budget ran out.
    pub cpu_exhausted: bool,
}

/// Turns a wasmtime error of a call into a [`PluginError`].
pub(crate) fn classify(
    e: &wasmtime::Error,
    symptoms: Symptoms,
    stderr: &str,
    limits: &crate::PluginLimits,
) -> PluginError {
    if e.downcast_ref::<wasmtime::PoolConcurrencyLimitError>()
        .is_some()
    {
        return PluginError::Busy(crate::MAX_CONCURRENT_REQUESTS);
    }
    if symptoms.memory_refused {
        return PluginError::Memory {
            limit_mib: limits.memory_bytes >> 20,
        };
    }
    match e.downcast_ref::<wasmtime::Trap>() {
        Some(wasmtime::Trap::Interrupt) => PluginError::timeout(limits.cpu_time, "CPU time"),
        Some(trap) => {
            // A std guest writes its panic message to stderr: the most useful detail.
            let detail = stderr.trim();
            if detail.is_empty() {
                PluginError::Trap(trap.to_string())
            } else {
                PluginError::Trap(format!("{trap}: {}", last_chars(detail, 2000)))
            }
        }
        None if symptoms.cpu_exhausted => PluginError::timeout(limits.cpu_time, "CPU time"),
        None => PluginError::Trap(last_chars(&format!("{e:#}"), 2000).to_string()),
    }
}

/// The last `n` characters of `s` (messages are capped, their end matters most).
pub(crate) fn last_chars(s: &str, n: usize) -> &str {
    let count = s.chars().count();
    if count <= n {
        return s;
    }
    let skip = s.char_indices().nth(count - n).map_or(0, |(i, _)| i);
    &s[skip..]
}

/// A multi-line message (wasmtime pretty-prints some details) on one line.
pub(crate) fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The first `n` characters of `s`.
pub(crate) fn first_chars(s: &str, n: usize) -> &str {
    s.char_indices().nth(n).map_or(s, |(i, _)| &s[..i])
}

//! The wasmtime side that every plugin shares: one engine with epoch
//! interruption and a pooling allocator, the thread that advances its
//! epoch, and the linker that offers a component the `host` interface and
//! an empty WASI.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

use wasmtime::component::{Component, HasSelf, Linker};
use wasmtime::{Config, Enabled, Engine, InstanceAllocationStrategy, PoolingAllocationConfig};

use crate::PluginError;
use crate::bindings::{BridgePlugin, BridgePluginPre};
use crate::imports::RequestState;

/// Period of the epoch ticker: CPU budgets are checked at this granularity.
pub(crate) const TICK: Duration = Duration::from_millis(10);

/// Bytes of each pooled memory and table kept mapped between requests.
const KEEP_RESIDENT: usize = 1 << 20;

use crate::MAX_CONCURRENT_REQUESTS;

/// Finished stores that may wait to be dropped after their answer left
/// (see `call::drop_later`); the pool has room for them on top of
/// [`MAX_CONCURRENT_REQUESTS`], so they never make a request busy.
pub(crate) const MAX_DEFERRED_DROPS: usize = 8;

/// Instances for `describe()` at install and load time, which run outside
/// [`Runtime::admit`] (installs are serialised, so one is enough).
const DESCRIBE_SLOTS: u32 = 1;

/// A pool of pre-reserved memories, tables, instances and fiber stacks: a
/// fresh instance per request then maps and unmaps nothing (measured with
/// `benches/call.rs`: p50 22–35 µs per request instead of 44 µs with the
/// on-demand allocator, whose `munmap`s cost TLB shootdowns). On Linux ≥ 6.7
/// the pages a request dirtied are found with the `PAGEMAP_SCAN` ioctl and
/// zeroed in place, up to [`KEEP_RESIDENT`] bytes, instead of `madvise`
/// (which costs page faults on the next request): p50 10–14 µs. Elsewhere
/// the two options change nothing. More than [`MAX_CONCURRENT_REQUESTS`]
/// requests at once are refused as busy by [`Runtime::admit`]; the pool
/// itself has room for [`MAX_DEFERRED_DROPS`] releases and an install's
/// `describe()` more, so neither can make an admitted request busy.
fn pooling(memory_bytes: usize) -> PoolingAllocationConfig {
    let mut pool = PoolingAllocationConfig::new();
    let n = MAX_CONCURRENT_REQUESTS + MAX_DEFERRED_DROPS as u32 + DESCRIBE_SLOTS;
    pool.total_component_instances(n)
        // A componentize-py guest has a dozen core instances and several
        // memories and tables; a Rust guest has a few.
        .total_core_instances(n * 16)
        .total_memories(n * 4)
        .total_tables(n * 8)
        .total_stacks(n)
        .table_elements(100_000)
        .max_memory_size(memory_bytes)
        .linear_memory_keep_resident(KEEP_RESIDENT)
        .table_keep_resident(KEEP_RESIDENT)
        .pagemap_scan(Enabled::Auto);
    pool
}

/// Engine, linker and epoch ticker.
pub(crate) struct Runtime {
    engine: Engine,
    linker: Linker<RequestState>,
    ticker_stop: Arc<AtomicBool>,
    /// Stores waiting to be dropped (at most [`MAX_DEFERRED_DROPS`]).
    pub(crate) deferred_drops: Places,
    /// Requests running (at most [`MAX_CONCURRENT_REQUESTS`]).
    running: Places,
}

/// A bounded number of places, taken without waiting.
#[derive(Clone)]
pub(crate) struct Places {
    taken: Arc<AtomicUsize>,
    max: usize,
}

impl Places {
    fn new(max: usize) -> Places {
        Places {
            taken: Arc::default(),
            max,
        }
    }

    /// A place, or None when all are taken.
    pub(crate) fn take(&self) -> Option<Place> {
        if self.taken.fetch_add(1, Ordering::AcqRel) >= self.max {
            self.taken.fetch_sub(1, Ordering::AcqRel);
            return None;
        }
        Some(Place(self.taken.clone()))
    }
}

/// A taken place; given back on drop.
pub(crate) struct Place(Arc<AtomicUsize>);

impl Drop for Place {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::AcqRel);
    }
}

/// The settings code is compiled with (the runtime engine adds its pool,
/// which does not change the code: artifacts of one load in the other).
fn code_config() -> Config {
    let mut config = Config::new();
    config.epoch_interruption(true);
    config
}

/// A throwaway engine to compile one component with. Cranelift keeps the
/// working memory of its largest function in its engine for the next
/// compilation (≈ 50 MiB after a Python plugin: its interpreter loop is a
/// huge function); compiling in an engine of its own, dropped with the
/// compilation, gives that memory back (docs/BENCHMARKS.md §7).
pub(crate) fn compiler() -> Result<Engine, PluginError> {
    Engine::new(&code_config()).map_err(|e| PluginError::Host(format!("compiler: {e:#}")))
}

impl Runtime {
    pub(crate) fn new(memory_bytes: usize) -> Result<Self, PluginError> {
        let mut config = code_config();
        config.allocation_strategy(InstanceAllocationStrategy::Pooling(pooling(memory_bytes)));
        let engine = Engine::new(&config).map_err(|e| PluginError::Host(format!("{e:#}")))?;
        let mut linker = Linker::<RequestState>::new(&engine);
        // A std guest imports wasi:cli/io; the context behind it is empty
        // (no files, env, args, network), so linking it grants nothing.
        wasmtime_wasi::p2::add_to_linker_async(&mut linker)
            .and_then(|()| {
                BridgePlugin::add_to_linker::<RequestState, HasSelf<RequestState>>(
                    &mut linker,
                    |s| s,
                )
            })
            .map_err(|e| PluginError::Host(format!("linker: {e:#}")))?;
        let ticker_stop = Arc::new(AtomicBool::new(false));
        let (e, stop) = (engine.clone(), ticker_stop.clone());
        std::thread::Builder::new()
            .name("plugin-epoch".into())
            .spawn(move || {
                while !stop.load(Ordering::Relaxed) {
                    std::thread::sleep(TICK);
                    e.increment_epoch();
                }
            })
            .map_err(|e| PluginError::Host(format!("epoch thread: {e}")))?;
        Ok(Runtime {
            engine,
            linker,
            ticker_stop,
            deferred_drops: Places::new(MAX_DEFERRED_DROPS),
            running: Places::new(MAX_CONCURRENT_REQUESTS as usize),
        })
    }

    /// A place for one more request, unless [`MAX_CONCURRENT_REQUESTS`] run.
    pub(crate) fn admit(&self) -> Result<Place, PluginError> {
        self.running
            .take()
            .ok_or(PluginError::Busy(MAX_CONCURRENT_REQUESTS))
    }

    pub(crate) fn engine(&self) -> &Engine {
        &self.engine
    }

    /// Links a component against the host; refuses components of another world.
    pub(crate) fn link(
        &self,
        component: &Component,
    ) -> Result<BridgePluginPre<RequestState>, PluginError> {
        let pre = self.linker.instantiate_pre(component).map_err(|e| {
            PluginError::WrongWorld(format!(
                "{} (this bridge implements {}: was the plugin built against another version of plugin.wit?)",
                crate::error::one_line(&format!("{e:#}")),
                crate::WIT_VERSION
            ))
        })?;
        BridgePluginPre::new(pre).map_err(|e| {
            PluginError::WrongWorld(format!(
                "{} (a plugin exports the interface kuka-bridge:plugin/plugin)",
                crate::error::one_line(&format!("{e:#}"))
            ))
        })
    }
}

impl Drop for Runtime {
    fn drop(&mut self) {
        self.ticker_stop.store(true, Ordering::Relaxed);
    }
}

//! The engine's settings: the `[channel]`, `[motion]` and `[workspace]`
//! sections of the service's configuration (the binary reads, merges and
//! validates the file and builds an [`EngineSettings`] from it), plus the
//! folders the engine writes.

use std::path::PathBuf;
use std::time::Duration;

use serde::{Deserialize, Serialize};

/// Everything the engine needs to start, built and validated by the binary.
#[derive(Debug, Clone)]
pub struct EngineSettings {
    /// The channel directory shared with the controller.
    pub channel_dir: PathBuf,
    /// Channel timing.
    pub channel: ChannelConfig,
    /// Default speeds and caps.
    pub motion: MotionConfig,
    /// The data folder (command id and job id counters).
    pub data_dir: PathBuf,
    /// The controller's program folder for RUN modules (None: programs off).
    pub program_dir: Option<PathBuf>,
    /// Generated program modules kept in it.
    pub keep_modules: usize,
}

/// File channel settings.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ChannelConfig {
    /// Directory shared with the controller (on a KRC: C:\KRC\ROBOTER\UserFiles).
    /// Default with `--simulate`: `<data_dir>/sim-channel`.
    pub dir: Option<PathBuf>,
    /// Poll period for the result and state files (notify events are a hint).
    pub poll_interval_ms: u64,
    /// Controller counts as offline when its heartbeat has not changed for this long.
    pub offline_after_ms: u64,
    /// The controller must pick a command up within this time.
    pub ack_timeout_ms: u64,
    /// A command must finish within this time (per-request `timeout_ms` may lower or raise it).
    pub command_timeout_ms: u64,
    /// How long to retry writing a locked command file before failing with `channel_locked`.
    pub lock_timeout_ms: u64,
    /// After writing a command, how long (µs) the engine watches for the
    /// answer in a busy loop (result file metadata and its queue) before it
    /// waits for file events: a quick answer arrives without two thread
    /// wake-ups. 0 turns it off. Unset: 300 with the embedded simulator,
    /// 0 otherwise (a real controller answers after its Submit cycle of
    /// 12 ms or more, so the loop would only burn the controller PC's CPU).
    pub answer_spin_us: Option<u64>,
    /// After a command's answer, how long (µs) the engine watches its queue
    /// in a busy loop before it sleeps: the next request of a client that
    /// sends one command after the other is then taken without a thread
    /// wake-up. 0 turns it off. Unset: 250 with the embedded simulator, 0
    /// otherwise.
    pub request_spin_us: Option<u64>,
    /// Set by the service from `simulator.enabled` (not a config key): the
    /// defaults of the two busy loops above depend on it.
    #[serde(skip)]
    pub simulated: bool,
}

/// Default speeds and the caps no request may exceed.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MotionConfig {
    /// PTP velocity when a request gives none (% of max axis speed).
    pub default_ptp_velocity_pct: f64,
    /// LIN/CIRC velocity when a request gives none (m/s).
    pub default_cp_velocity: f64,
    /// Acceleration when a request gives none (%).
    pub default_acceleration_pct: f64,
    /// Approximation between motions of a batch when a request gives none (mm).
    pub default_batch_approx_mm: f64,
    /// Highest PTP velocity accepted (%).
    pub max_ptp_velocity_pct: f64,
    /// Highest LIN/CIRC velocity accepted (m/s).
    pub max_cp_velocity: f64,
    /// Largest approximation distance accepted (mm).
    pub max_approx_mm: f64,
    /// Most motions in one batch.
    pub max_batch: usize,
    /// Most jobs waiting in the queue.
    pub max_queue: usize,
}

/// An axis-aligned box in the base frame (mm).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WorkspaceBox {
    /// [min, max] X.
    pub x: [f64; 2],
    /// [min, max] Y.
    pub y: [f64; 2],
    /// [min, max] Z.
    pub z: [f64; 2],
}

impl WorkspaceBox {
    /// True if the point lies inside (borders included).
    pub fn contains(&self, x: f64, y: f64, z: f64) -> bool {
        (self.x[0]..=self.x[1]).contains(&x)
            && (self.y[0]..=self.y[1]).contains(&y)
            && (self.z[0]..=self.z[1]).contains(&z)
    }
}

impl Default for ChannelConfig {
    fn default() -> Self {
        ChannelConfig {
            dir: None,
            poll_interval_ms: 50,
            offline_after_ms: 1000,
            ack_timeout_ms: 2000,
            command_timeout_ms: 60_000,
            lock_timeout_ms: 2000,
            answer_spin_us: None,
            request_spin_us: None,
            simulated: false,
        }
    }
}

impl Default for MotionConfig {
    fn default() -> Self {
        MotionConfig {
            default_ptp_velocity_pct: 20.0,
            default_cp_velocity: 0.25,
            default_acceleration_pct: 100.0,
            default_batch_approx_mm: 2.0,
            max_ptp_velocity_pct: 100.0,
            max_cp_velocity: 1.0,
            max_approx_mm: 100.0,
            max_batch: kuka_protocol::MAX_BATCH,
            max_queue: 100,
        }
    }
}

fn ms(v: u64) -> Duration {
    Duration::from_millis(v)
}

impl ChannelConfig {
    /// Busy-wait for a quick answer.
    pub fn answer_spin(&self) -> Duration {
        let default = if self.simulated { 300 } else { 0 };
        Duration::from_micros(self.answer_spin_us.unwrap_or(default))
    }
    /// Busy-wait for the next request after an answer.
    pub fn request_spin(&self) -> Duration {
        let default = if self.simulated { 250 } else { 0 };
        Duration::from_micros(self.request_spin_us.unwrap_or(default))
    }
    /// Poll period.
    pub fn poll_interval(&self) -> Duration {
        ms(self.poll_interval_ms)
    }
    /// Offline threshold.
    pub fn offline_after(&self) -> Duration {
        ms(self.offline_after_ms)
    }
    /// Acknowledge timeout.
    pub fn ack_timeout(&self) -> Duration {
        ms(self.ack_timeout_ms)
    }
    /// Default command timeout.
    pub fn command_timeout(&self) -> Duration {
        ms(self.command_timeout_ms)
    }
    /// Lock retry budget.
    pub fn lock_timeout(&self) -> Duration {
        ms(self.lock_timeout_ms)
    }
}

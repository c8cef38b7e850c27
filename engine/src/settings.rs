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
    pub channel: ChannelTiming,
    /// Default speeds and caps.
    pub motion: MotionConfig,
    /// The data folder (command id and job id counters).
    pub data_dir: PathBuf,
    /// The controller's program folder for RUN modules (None: programs off).
    pub program_dir: Option<PathBuf>,
    /// Generated program modules kept in it.
    pub keep_modules: usize,
    /// Named digital I/O and the outputs clients may write.
    pub io: crate::io::IoConfig,
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
    /// While a path runs (a path, or a batch of more than 4 motions),
    /// removes the command file once the controller has read it (its state
    /// or result file says so): the controller's polls until the next
    /// APPEND then find no file, instead of reading the same header again
    /// and again (a KRL program's one failed `krl_fopen` against an open,
    /// a line and a close). false keeps the last command on the channel.
    pub remove_read_command: bool,
}

/// How a Cartesian PTP without `s` gets its arm configuration
/// (docs/CONFIGURATION.md).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize, utoipa::ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum Configuration {
    /// The bridge chooses Status and Turn: reachable, the Cartesian motions
    /// after it executable, away from singularities, least axis travel.
    #[default]
    Auto,
    /// KUKA's rule: keep the current Status (the PTP may then fail where
    /// another configuration would reach).
    Keep,
}

impl From<Configuration> for kuka_kinematics::ConfigMode {
    fn from(c: Configuration) -> Self {
        match c {
            Configuration::Auto => kuka_kinematics::ConfigMode::Auto,
            Configuration::Keep => kuka_kinematics::ConfigMode::Keep,
        }
    }
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
    /// How a Cartesian PTP without `s` gets its arm configuration when
    /// the request does not say: `auto` (the bridge chooses) or `keep`
    /// (KUKA's rule). The thesis endpoints always use `auto`.
    pub configuration: Configuration,
    /// Thesis clients: consecutive `/krl/linmov` and `/krl/circ` calls of
    /// one client that come within this many ms of each other are
    /// appended to one path and blend (0 = off, the default). The answer
    /// then comes when the motion is checked and queued, not when it has
    /// run (README, "Thesis clients that never stop").
    pub thesis_blend_ms: u64,
}

/// An axis-aligned box in the base frame (mm).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
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

/// What the swept TCP path must keep clear of besides the workspace box:
/// a floor or table plane and keep-out boxes around fixtures (base frame,
/// mm). Checked along the whole dry-run path, not only at targets.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Zones {
    /// The TCP stays at or above this Z (a table or the floor).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub floor_z: Option<f64>,
    /// Boxes the TCP must not enter.
    pub keep_out: Vec<KeepOut>,
}

/// A named box the TCP must not enter (base frame, mm).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct KeepOut {
    /// Shown in errors and on the dashboard, e.g. `fixture`.
    pub name: String,
    /// [min, max] X.
    pub x: [f64; 2],
    /// [min, max] Y.
    pub y: [f64; 2],
    /// [min, max] Z.
    pub z: [f64; 2],
}

impl KeepOut {
    /// True if the point lies inside, grown by `margin` mm on every side.
    pub fn contains(&self, p: [f64; 3], margin: f64) -> bool {
        [self.x, self.y, self.z]
            .iter()
            .zip(p)
            .all(|(r, v)| v > r[0] - margin && v < r[1] + margin)
    }
}

impl Zones {
    /// Every problem of this section (keys without the `zones.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        if self.floor_z.is_some_and(|z| !z.is_finite()) {
            bad.push(Problem::new("floor_z", "is not a finite number"));
        }
        for (i, k) in self.keep_out.iter().enumerate() {
            if self.keep_out[..i].iter().any(|o| o.name == k.name) {
                bad.push(Problem::new(
                    "keep_out",
                    format!("entry {i}: the name `{}` is used twice", k.name),
                ));
            }
            if k.name.trim().is_empty() {
                bad.push(Problem::new(
                    "keep_out",
                    format!("entry {i}: the name is empty"),
                ));
            }
            for (axis, r) in [("x", k.x), ("y", k.y), ("z", k.z)] {
                if !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]) {
                    bad.push(Problem::new(
                        "keep_out",
                        format!(
                            "entry {i} ({}): {axis} = {r:?} is not [min, max] with min < max",
                            k.name
                        ),
                    ));
                }
            }
        }
        bad
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
            remove_read_command: true,
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
            configuration: Configuration::Auto,
            thesis_blend_ms: 0,
        }
    }
}

/// One problem with a configuration value: the key within its section
/// and a sentence. The binary prefixes the section's name and the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// The key within the section (e.g. `poll_interval_ms`).
    pub key: &'static str,
    /// What is wrong, as a sentence fragment (e.g. "0 is below the minimum 1").
    pub message: String,
}

impl Problem {
    /// A problem with `key`.
    pub fn new(key: &'static str, message: impl Into<String>) -> Self {
        Problem {
            key,
            message: message.into(),
        }
    }
}

/// Pushes a problem for each `(key, value, min)` whose value is below its minimum.
pub fn check_minimums(problems: &mut Vec<Problem>, checks: &[(&'static str, u64, u64)]) {
    for &(key, v, min) in checks {
        if v < min {
            problems.push(Problem::new(key, format!("{v} is below the minimum {min}")));
        }
    }
}

/// Pushes a problem for each `(key, value, max)` whose value is above its maximum.
pub fn check_maximums(problems: &mut Vec<Problem>, checks: &[(&'static str, u64, u64)]) {
    for &(key, v, max) in checks {
        if v > max {
            problems.push(Problem::new(key, format!("{v} is above the maximum {max}")));
        }
    }
}

/// The channel's timing as durations: what the engine uses, built from a
/// checked [`ChannelConfig`] by [`ChannelConfig::timing`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelTiming {
    /// Poll period for the result and state files.
    pub poll_interval: Duration,
    /// The controller counts as offline when its heartbeat is older.
    pub offline_after: Duration,
    /// The controller must pick a command up within this time.
    pub ack_timeout: Duration,
    /// A command must finish within this time unless a request says otherwise.
    pub command_timeout: Duration,
    /// Retry budget for a locked command file.
    pub lock_timeout: Duration,
    /// Busy-wait for a quick answer after a command was written (zero: off).
    pub answer_spin: Duration,
    /// Busy-wait for the next request after an answer (zero: off).
    pub request_spin: Duration,
    /// Remove the command file once the controller has read it, while a path runs.
    pub remove_read_command: bool,
}

impl Default for ChannelTiming {
    fn default() -> Self {
        ChannelConfig::default().timing(false)
    }
}

/// The largest busy loop accepted (µs): a longer one wastes a core.
pub const MAX_SPIN_US: u64 = 10_000;

impl ChannelConfig {
    /// The timing in effect; `simulated` (the embedded simulator answers
    /// within microseconds) switches the two busy loops on by default.
    pub fn timing(&self, simulated: bool) -> ChannelTiming {
        let ms = Duration::from_millis;
        let spin = |set: Option<u64>, sim_default: u64| {
            Duration::from_micros(set.unwrap_or(if simulated { sim_default } else { 0 }))
        };
        ChannelTiming {
            poll_interval: ms(self.poll_interval_ms),
            offline_after: ms(self.offline_after_ms),
            ack_timeout: ms(self.ack_timeout_ms),
            command_timeout: ms(self.command_timeout_ms),
            lock_timeout: ms(self.lock_timeout_ms),
            answer_spin: spin(self.answer_spin_us, 300),
            request_spin: spin(self.request_spin_us, 250),
            remove_read_command: self.remove_read_command,
        }
    }

    /// Every problem of this section (keys without the `channel.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        check_minimums(
            &mut bad,
            &[
                ("poll_interval_ms", self.poll_interval_ms, 1),
                ("offline_after_ms", self.offline_after_ms, 10),
                ("ack_timeout_ms", self.ack_timeout_ms, 10),
                ("command_timeout_ms", self.command_timeout_ms, 10),
            ],
        );
        for (key, v) in [
            ("answer_spin_us", self.answer_spin_us.unwrap_or(0)),
            ("request_spin_us", self.request_spin_us.unwrap_or(0)),
        ] {
            if v > MAX_SPIN_US {
                bad.push(Problem::new(
                    key,
                    format!("{v} is above the maximum {MAX_SPIN_US} (a busy loop longer than 10 ms wastes a core)"),
                ));
            }
        }
        bad
    }
}

/// The longest blend window for thesis calls (ms): a path held open longer
/// waits on a client that is gone (the controller closes an idle path
/// after 5 s anyway).
pub const MAX_THESIS_BLEND_MS: u64 = 5_000;

impl MotionConfig {
    /// Every problem of this section (keys without the `motion.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        for (key, v) in [
            ("default_ptp_velocity_pct", self.default_ptp_velocity_pct),
            ("default_acceleration_pct", self.default_acceleration_pct),
            ("max_ptp_velocity_pct", self.max_ptp_velocity_pct),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= 100.0) {
                bad.push(Problem::new(key, format!("{v} is not in (0, 100]")));
            }
        }
        if !(self.max_cp_velocity.is_finite()
            && self.max_cp_velocity > 0.0
            && self.max_cp_velocity <= 2.0)
        {
            bad.push(Problem::new(
                "max_cp_velocity",
                format!("{} m/s is not in (0, 2]", self.max_cp_velocity),
            ));
        }
        if !(self.default_cp_velocity > 0.0 && self.default_cp_velocity <= self.max_cp_velocity) {
            bad.push(Problem::new(
                "default_cp_velocity",
                format!(
                    "{} m/s is not in (0, max_cp_velocity]",
                    self.default_cp_velocity
                ),
            ));
        }
        if self.default_ptp_velocity_pct > self.max_ptp_velocity_pct {
            bad.push(Problem::new(
                "default_ptp_velocity_pct",
                "exceeds motion.max_ptp_velocity_pct",
            ));
        }
        if !(self.max_approx_mm.is_finite()
            && self.max_approx_mm >= 0.0
            && self.max_approx_mm <= 1000.0)
        {
            bad.push(Problem::new(
                "max_approx_mm",
                format!("{} is not in [0, 1000]", self.max_approx_mm),
            ));
        }
        if !(self.default_batch_approx_mm >= 0.0
            && self.default_batch_approx_mm <= self.max_approx_mm)
        {
            bad.push(Problem::new(
                "default_batch_approx_mm",
                "must be in [0, max_approx_mm]",
            ));
        }
        check_maximums(
            &mut bad,
            &[("thesis_blend_ms", self.thesis_blend_ms, MAX_THESIS_BLEND_MS)],
        );
        if self.max_batch == 0 || self.max_batch > kuka_protocol::MAX_BATCH {
            bad.push(Problem::new(
                "max_batch",
                format!(
                    "{} is not in 1..={}",
                    self.max_batch,
                    kuka_protocol::MAX_BATCH
                ),
            ));
        }
        if self.max_queue == 0 {
            bad.push(Problem::new("max_queue", "must be at least 1"));
        }
        bad
    }
}

impl WorkspaceBox {
    /// Every problem of this section (keys without the `workspace.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        for (key, r) in [("x", self.x), ("y", self.y), ("z", self.z)] {
            if !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]) {
                bad.push(Problem::new(
                    key,
                    format!("{r:?} is not [min, max] with min < max"),
                ));
            }
        }
        bad
    }
}

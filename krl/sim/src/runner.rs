//! The simulated controller's thread: watches the command file, feeds the
//! state machine, writes the result and state files, and offers handles for
//! tests (pause = hang, injected error state, trace).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use kuka_kinematics::{Axes, PlanSettings, RobotModel};
use kuka_protocol::files::{self, ReplacedFile, WriteError};
use kuka_protocol::{
    COMMAND_FILE, CommandFile, DecodeError, OperatingMode, RESULT_FILE, ResultCode, ResultFile,
    STATE_FILE,
};
use notify::{RecursiveMode, Watcher};

use kuka_protocol::AcknowledgeRefused;

use crate::controller::{Changes, Controller, TraceSample};

/// Errors starting the simulator.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The channel directory cannot be created or watched.
    #[error("channel directory {path}")]
    Channel {
        /// The directory.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// Another simulated controller already serves this channel.
    #[error("another simulated controller already serves {0} (its lock file kb_sim.lock is held)")]
    InUse(String),
    /// The thread could not be spawned.
    #[error("cannot start the simulator thread")]
    Thread(#[source] std::io::Error),
}

/// How to run the simulated controller.
#[derive(Debug, Clone)]
pub struct SimConfig {
    /// Directory holding the channel files.
    pub channel_dir: PathBuf,
    /// Robot model.
    pub model: RobotModel,
    /// Simulated seconds per wall-clock second: 1.0 = real time, 10.0 = ten
    /// times faster, 0 = instant (motions complete at once; simulated time
    /// still counts their duration).
    pub time_scale: f64,
    /// Heartbeat period of the state file.
    pub heartbeat: Duration,
    /// Fallback poll period for the command file (notify events are a hint).
    pub poll: Duration,
    /// Axis angles at start (default: the model's home).
    pub start_axes: Option<Axes>,
    /// Planner settings.
    pub plan: PlanSettings,
    /// Operating mode reported.
    pub mode: OperatingMode,
    /// Maximum number of trace samples kept (oldest dropped).
    pub trace_capacity: usize,
    /// The program folder RUN commands take `kbu<n>.src`/`.dat` from
    /// (default: `<channel_dir>/programs`).
    pub program_dir: PathBuf,
}

impl SimConfig {
    /// Defaults for a channel directory: KR 3 R540, real time, 50 ms heartbeat.
    pub fn new(channel_dir: impl Into<PathBuf>) -> Self {
        let channel_dir: PathBuf = channel_dir.into();
        SimConfig {
            program_dir: channel_dir.join("programs"),
            channel_dir,
            model: RobotModel::kr3_r540(),
            time_scale: 1.0,
            heartbeat: Duration::from_millis(50),
            poll: Duration::from_millis(20),
            start_axes: None,
            plan: PlanSettings::default(),
            mode: OperatingMode::Ext,
            trace_capacity: 200_000,
        }
    }
}

/// A snapshot of the simulated controller for tests and the API.
#[derive(Debug, Clone, serde::Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct SimSnapshot {
    /// Robot model id.
    pub model: String,
    /// Simulated seconds spent moving since start.
    pub sim_time_s: f64,
    /// Current axis angles.
    #[cfg_attr(feature = "openapi", schema(value_type = Vec<f64>))]
    pub axes: Axes,
    /// Current TCP `[x, y, z, a, b, c]`.
    #[cfg_attr(feature = "openapi", schema(value_type = Vec<f64>))]
    pub pose: [f64; 6],
    /// Highest accepted CID.
    pub last_cid: i32,
    /// Executing a batch.
    pub busy: bool,
    /// Heartbeats written.
    pub heartbeats: i32,
}

struct Shared {
    controller: Mutex<Controller>,
    shutdown: AtomicBool,
    paused: AtomicBool,
    wake: mpsc::Sender<()>,
}

/// A running simulated controller. Dropping it stops the thread.
pub struct SimController {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    channel_dir: PathBuf,
    _lock: std::fs::File,
}

impl SimController {
    /// Starts the controller thread on `config.channel_dir` (created if missing).
    pub fn start(config: SimConfig) -> Result<Self, SimError> {
        let dir = config.channel_dir.clone();
        std::fs::create_dir_all(&dir).map_err(|source| SimError::Channel {
            path: dir.display().to_string(),
            source,
        })?;
        // Two controllers on one channel would both execute commands.
        let lock_path = dir.join("kb_sim.lock");
        let lock_file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|source| SimError::Channel {
                path: lock_path.display().to_string(),
                source,
            })?;
        if lock_file.try_lock().is_err() {
            return Err(SimError::InUse(dir.display().to_string()));
        }
        let start = config.start_axes.unwrap_or(config.model.home);
        let controller = Controller::new(
            config.model.clone(),
            config.plan.clone(),
            config.mode,
            start,
            config.trace_capacity,
        );
        let (tx, rx) = mpsc::channel();
        let shared = Arc::new(Shared {
            controller: Mutex::new(controller),
            shutdown: AtomicBool::new(false),
            paused: AtomicBool::new(false),
            wake: tx.clone(),
        });
        let runner = Arc::new(Mutex::new(Runner::new(config, shared.clone())));
        lock(&runner).recover_last_cid();
        // notify is a hint only: a failing watcher leaves the poll in charge.
        // A new command is handled right in the watcher's callback (one
        // thread hand-off less per round trip); the thread then re-plans
        // its wake-up.
        let (cb_runner, cb_shared) = (runner.clone(), shared.clone());
        let watcher = notify::recommended_watcher(move |ev: notify::Result<notify::Event>| {
            // Reading a file raises access events: reacting to those would
            // make every read trigger the next one.
            if let Ok(ev) = ev
                && !matches!(ev.kind, notify::EventKind::Access(_))
                && ev
                    .paths
                    .iter()
                    .any(|p| p.file_name().is_some_and(|n| n == COMMAND_FILE))
            {
                let handled = !cb_shared.paused.load(Ordering::SeqCst)
                    && !cb_shared.shutdown.load(Ordering::SeqCst);
                if handled {
                    lock(&cb_runner).step(Instant::now());
                }
                // The thread only needs to re-plan its sleep when a motion now
                // plays in real time (or nothing was handled here); an extra
                // wake-up costs CPU on small machines.
                if !handled || lock(&cb_shared.controller).is_busy() {
                    let _ = tx.send(());
                }
            }
        })
        .and_then(|mut w| w.watch(&dir, RecursiveMode::NonRecursive).map(|()| w));
        let watcher = match watcher {
            Ok(w) => Some(w),
            Err(e) => {
                tracing::warn!(error = %e, "file watcher unavailable; polling only");
                None
            }
        };
        let thread_shared = shared.clone();
        let thread = std::thread::Builder::new()
            .name("kuka-sim".into())
            .spawn(move || {
                let _watcher = watcher;
                run(&runner, &thread_shared, &rx);
            })
            .map_err(SimError::Thread)?;
        Ok(SimController {
            shared,
            thread: Some(thread),
            channel_dir: dir,
            _lock: lock_file,
        })
    }

    fn lock(&self) -> MutexGuard<'_, Controller> {
        self.shared
            .controller
            .lock()
            .unwrap_or_else(|p| p.into_inner())
    }

    /// The channel directory.
    pub fn channel_dir(&self) -> &std::path::Path {
        &self.channel_dir
    }

    /// The executed TCP trace (oldest first).
    pub fn trace(&self) -> Vec<TraceSample> {
        self.trace_since(f64::NEG_INFINITY)
    }

    /// The samples after simulated time `since` (oldest first). Only those
    /// are copied, so that polling clients do not hold up the controller
    /// thread with a copy of the whole trace.
    pub fn trace_since(&self, since: f64) -> Vec<TraceSample> {
        let c = self.lock();
        // Samples are appended in time order.
        let start = c.trace.partition_point(|s| s.t <= since);
        c.trace.range(start..).copied().collect()
    }

    /// Clears the trace.
    pub fn clear_trace(&self) {
        self.lock().trace.clear();
    }

    /// Current state.
    pub fn snapshot(&self) -> SimSnapshot {
        let c = self.lock();
        let (pose, _, _) = c.position();
        SimSnapshot {
            model: c.model.name.clone(),
            sim_time_s: c.sim_time,
            axes: c.axes,
            pose: pose.to_array(),
            last_cid: c.last_cid,
            busy: c.is_busy(),
            heartbeats: c.seq,
        }
    }

    /// Hangs the controller: no commands are read and no heartbeat is
    /// written until [`resume`](Self::resume) — like a stuck KRL program.
    pub fn pause(&self) {
        self.shared.paused.store(true, Ordering::SeqCst);
    }

    /// Ends a [`pause`](Self::pause).
    pub fn resume(&self) {
        self.shared.paused.store(false, Ordering::SeqCst);
        let _ = self.shared.wake.send(());
    }

    /// Sets a digital input `$IN[index]` (1..=4096), as the plant would;
    /// false for an index out of range.
    pub fn set_input(&self, index: u16, value: bool) -> bool {
        let mut c = self.lock();
        match c.inputs.get_mut(usize::from(index)).filter(|_| index > 0) {
            Some(slot) => {
                *slot = value;
                drop(c);
                let _ = self.shared.wake.send(());
                true
            }
            None => false,
        }
    }

    /// A variable as KRL text, as KUKAVARPROXY reads it on a KRC (the few
    /// this simulator models: `$OV_PRO`, `$POS_ACT`, `$AXIS_ACT`, `$TOOL`,
    /// `$BASE`, `$MODE_OP`, `$IN[n]`, `$OUT[n]`, `TOOL_DATA[n]`,
    /// `BASE_DATA[n]` and their components); `None` for any other.
    pub fn read_krl(&self, path: &str) -> Option<String> {
        self.lock().read_krl(path)
    }

    /// Writes `$OV_PRO`, `TOOL_DATA[n]` or `BASE_DATA[n]` (or a component)
    /// from KRL text; the value afterwards, `None` when it cannot.
    pub fn write_krl(&self, path: &str, text: &str) -> Option<String> {
        self.lock().write_krl(path, text)
    }

    /// Sets the analog input `$ANIN[index]` (1..=32) to `value`
    /// (−1..=1), as a sensor would; false when out of range.
    pub fn set_analog_input(&self, index: u8, value: f64) -> bool {
        if !(value.is_finite() && (-1.0..=1.0).contains(&value)) {
            return false;
        }
        let mut c = self.lock();
        match c
            .analog_inputs
            .get_mut(usize::from(index))
            .filter(|_| index > 0)
        {
            Some(slot) => {
                *slot = value;
                drop(c);
                let _ = self.shared.wake.send(());
                true
            }
            None => false,
        }
    }

    /// `$ANIN[index]` or `$ANOUT[index]` (1..=32).
    pub fn analog(&self, output: bool, index: u8) -> Option<f64> {
        let c = self.lock();
        let v = if output {
            &c.analog_outputs
        } else {
            &c.analog_inputs
        };
        v.get(usize::from(index)).filter(|_| index > 0).copied()
    }

    /// `$IN[index]` or `$OUT[index]` (1..=4096).
    pub fn io(&self, output: bool, index: u16) -> Option<bool> {
        let c = self.lock();
        let v = if output { &c.outputs } else { &c.inputs };
        v.get(usize::from(index)).filter(|_| index > 0).copied()
    }

    /// The safety circuit changes, as on a real cell: an emergency stop
    /// pressed (`Some(true)`) or released, the operator safety closed
    /// (`Some(true)`) or opened; `None` leaves that part as it is. Opening
    /// the circuit stops the robot where it is, switches the drives off and
    /// ends the running command CONTROLLER_ERROR (details:
    /// docs/RELIABILITY.md, "Safety stops").
    pub fn set_safety(&self, emergency_stop: Option<bool>, user_safety: Option<bool>) {
        self.lock().set_safety(emergency_stop, user_safety);
        let _ = self.shared.wake.send(());
    }

    /// What the operator does after a safety stop: acknowledge the message
    /// and switch the drives on. Refused while the circuit is still open.
    pub fn acknowledge(&self) -> Result<(), AcknowledgeRefused> {
        let r = self.lock().acknowledge();
        let _ = self.shared.wake.send(());
        r
    }

    /// Puts the controller into an error state (as an acknowledgeable KRC
    /// message would) until a RESET command.
    pub fn inject_error(&self, code: ResultCode, axis: u8) {
        self.lock().set_error(code, axis);
        let _ = self.shared.wake.send(());
    }

    /// Stops the thread and waits for it.
    pub fn shutdown(mut self) {
        self.stop_thread();
    }

    fn stop_thread(&mut self) {
        self.shared.shutdown.store(true, Ordering::SeqCst);
        let _ = self.shared.wake.send(());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for SimController {
    fn drop(&mut self) {
        self.stop_thread();
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Largest program file the simulator reads.
const MAX_PROGRAM_BYTES: u64 = 1 << 20;

/// Reads `kbu<n>.src` and the optional `kbu<n>.dat` from the program folder.
fn load_program(dir: &std::path::Path, n: i32) -> crate::controller::LoadedProgram {
    let read = |ext: &str| -> Result<Option<String>, String> {
        let path = dir.join(format!("kbu{n}.{ext}"));
        match std::fs::metadata(&path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(format!("{}: {e}", path.display())),
            Ok(m) if m.len() > MAX_PROGRAM_BYTES => {
                return Err(format!(
                    "{} is larger than {MAX_PROGRAM_BYTES} bytes",
                    path.display()
                ));
            }
            Ok(_) => {}
        }
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        // KRL files are 8-bit (Windows-1252); UTF-8 is accepted too.
        Ok(Some(match String::from_utf8(bytes) {
            Ok(s) => s,
            Err(e) => e.into_bytes().iter().map(|&b| char::from(b)).collect(),
        }))
    };
    let src = read("src")?.ok_or_else(|| format!("kbu{n}.src is not in {}", dir.display()))?;
    Ok((src, read("dat")?))
}

/// The controller thread: steps on wake-ups, sample times, heartbeats and polls.
fn run(runner: &Mutex<Runner>, shared: &Shared, rx: &mpsc::Receiver<()>) {
    let (poll, dir, model) = {
        let r = lock(runner);
        (
            r.config.poll,
            r.config.channel_dir.clone(),
            r.config.model.name.clone(),
        )
    };
    tracing::info!(dir = %dir.display(), %model, "simulated controller running");
    while !shared.shutdown.load(Ordering::SeqCst) {
        if shared.paused.load(Ordering::SeqCst) {
            let _ = rx.recv_timeout(poll);
            continue;
        }
        let wait = lock(runner).step_and_plan_wait(Instant::now());
        match rx.recv_timeout(wait) {
            Ok(()) => while rx.try_recv().is_ok() {},
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
    }
    tracing::info!("simulated controller stopped");
}

struct Runner {
    config: SimConfig,
    shared: Arc<Shared>,
    result_file: ReplacedFile,
    state_file: ReplacedFile,
    last_text: String,
    pending_results: bool,
    pending_state: bool,
    next_heartbeat: Instant,
    status_key: (
        kuka_protocol::Cid,
        bool,
        kuka_protocol::IoState,
        crate::controller::SafetyCircuit,
    ),
}

impl Runner {
    fn new(config: SimConfig, shared: Arc<Shared>) -> Self {
        let tag = format!("sim{}", std::process::id());
        Runner {
            result_file: ReplacedFile::new(&config.channel_dir, RESULT_FILE, &tag),
            state_file: ReplacedFile::new(&config.channel_dir, STATE_FILE, &tag),
            config,
            shared,
            last_text: String::new(),
            pending_results: false,
            pending_state: true,
            next_heartbeat: Instant::now(),
            status_key: (
                0,
                false,
                kuka_protocol::IoState::default(),
                crate::controller::SafetyCircuit::default(),
            ),
        }
    }

    /// Steps, then returns how long the thread may sleep: until the next
    /// heartbeat, poll or trajectory sample, whichever comes first.
    fn step_and_plan_wait(&mut self, now: Instant) -> Duration {
        self.step(now);
        let due = lock(&self.shared.controller).next_sample_due(self.config.time_scale);
        let mut wait_until = self.next_heartbeat.min(now + self.config.poll);
        if let Some(d) = due {
            wait_until = wait_until.min(d);
        }
        wait_until.saturating_duration_since(Instant::now())
    }

    /// A restarted simulator must not execute an old command again: it
    /// remembers the newest CID ([`kuka_protocol::newest_cid`]) from its
    /// own result and state files.
    fn recover_last_cid(&mut self) {
        let dir = &self.config.channel_dir;
        let results = files::read(dir, RESULT_FILE)
            .ok()
            .flatten()
            .and_then(|text| ResultFile::decode(&text).ok())
            .map(|r| r.results)
            .unwrap_or_default();
        let from_state = files::read(dir, STATE_FILE)
            .ok()
            .flatten()
            .and_then(|text| kuka_protocol::StateFile::decode(&text).ok())
            .map_or(0, |s| s.last_cid);
        let last = results
            .iter()
            .map(|r| r.cid)
            .fold(from_state, kuka_protocol::newest_cid);
        let mut c = lock(&self.shared.controller);
        c.last_cid = last;
        c.results = results.into_iter().collect();
    }

    fn step(&mut self, now: Instant) {
        let mut changes = Changes::default();
        // Play up to now first: a command acts on where the robot is now
        // (an APPEND to a path the robot has run out of starts from here).
        {
            let mut c = lock(&self.shared.controller);
            changes.results |= c.advance(now, self.config.time_scale).results;
        }
        self.read_command(now, &mut changes);
        {
            let mut c = self
                .shared
                .controller
                .lock()
                .unwrap_or_else(|p| p.into_inner());
            let ch = c.advance(now, self.config.time_scale);
            changes.results |= ch.results;
            let key = c.status_key();
            if key != self.status_key {
                // Busy/idle/error changed: the service hears it now; the
                // pose follows at the heartbeat rate.
                self.status_key = key;
                self.pending_state = true;
            }
        }
        self.pending_results |= changes.results;
        if self.pending_results {
            self.write_results();
        }
        if self.pending_state || now >= self.next_heartbeat {
            self.write_state();
        }
    }

    fn read_command(&mut self, now: Instant, changes: &mut Changes) {
        let text = match files::read(&self.config.channel_dir, COMMAND_FILE) {
            Ok(Some(t)) => t,
            Ok(None) => return,
            Err(e) => {
                tracing::debug!(error = %e, "command file not readable now");
                return;
            }
        };
        if text == self.last_text {
            return;
        }
        let mut c = self
            .shared
            .controller
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        match CommandFile::decode(&text) {
            Ok(cmd) => {
                self.last_text = text;
                if kuka_protocol::cid_is_newer(cmd.cid, c.last_cid) {
                    let program = match cmd.command {
                        kuka_protocol::Command::Run(n) => {
                            Some(load_program(&self.config.program_dir, n))
                        }
                        _ => None,
                    };
                    let ch = c.accept(cmd.cid, cmd.command, now, program);
                    changes.results |= ch.results;
                } else {
                    tracing::debug!(cid = cmd.cid, last = c.last_cid, "stale command ignored");
                }
            }
            Err(DecodeError::Truncated | DecodeError::Empty) => {
                // Half-written: read again at the next event or poll.
            }
            Err(e) => {
                self.last_text = text.clone();
                if let Some(cid) = CommandFile::peek_cid(&text)
                    && kuka_protocol::cid_is_newer(cid, c.last_cid)
                {
                    tracing::warn!(cid, error = %e, "malformed command");
                    c.reject_malformed(cid);
                    changes.results = true;
                } else {
                    tracing::warn!(error = %e, "unreadable command file ignored");
                }
            }
        }
    }

    fn write_results(&mut self) {
        let text = {
            let c = self
                .shared
                .controller
                .lock()
                .unwrap_or_else(|p| p.into_inner());
            ResultFile {
                results: c.results.iter().copied().collect(),
            }
            .encode()
        };
        match text {
            Ok(text) => match self.result_file.write(text.as_bytes()) {
                Ok(()) => self.pending_results = false,
                Err(WriteError::Locked { .. }) => {
                    tracing::debug!("result file locked; retrying")
                }
                Err(e) => tracing::warn!(error = %e, "cannot write result file"),
            },
            Err(e) => {
                tracing::error!(error = %e, "cannot encode results");
                self.pending_results = false;
            }
        }
    }

    fn write_state(&mut self) {
        let text = {
            let mut c = self
                .shared
                .controller
                .lock()
                .unwrap_or_else(|p| p.into_inner());
            c.state_record().encode()
        };
        self.next_heartbeat = Instant::now() + self.config.heartbeat;
        match text {
            Ok(text) => match self.state_file.write(text.as_bytes()) {
                Ok(()) => self.pending_state = false,
                Err(WriteError::Locked { .. }) => {
                    tracing::debug!("state file locked; retrying")
                }
                Err(e) => tracing::warn!(error = %e, "cannot write state file"),
            },
            Err(e) => {
                tracing::error!(error = %e, "cannot encode state");
                self.pending_state = false;
            }
        }
    }
}

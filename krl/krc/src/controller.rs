//! The running runtime: a thread that advances the controller clock, and
//! the handle the service and tests hold (snapshot, trace, statistics,
//! shutdown).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use kuka_kinematics::Axes;
use kuka_protocol::AcknowledgeRefused;
use serde::Serialize;

use crate::config::KrcConfig;
use crate::scheduler::{KrcTraceSample, Scheduler};

/// Errors starting the runtime.
#[derive(Debug, thiserror::Error)]
pub enum KrcError {
    /// The channel folder cannot be created.
    #[error("channel directory {path}")]
    Channel {
        /// The folder.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// Another simulated controller (native or KRC-like) already serves
    /// the channel.
    #[error("another simulated controller already serves {0} (its lock file kb_sim.lock is held)")]
    InUse(String),
    /// The KRL program cannot be loaded or started.
    #[error("KRL program: {0}")]
    Program(String),
    /// The thread could not be spawned.
    #[error("cannot start the runtime thread")]
    Thread(#[source] std::io::Error),
}

/// A snapshot of the runtime.
#[derive(Debug, Clone, Serialize)]
pub struct KrcSnapshot {
    /// Controller clock in ms (`$ROB_TIMER`).
    pub time_ms: i64,
    /// Current axis angles.
    pub axes: Axes,
    /// Current TCP `[x, y, z, a, b, c]` with the last motion's tool and base.
    pub pose: [f64; 6],
    /// The robot is moving.
    pub moving: bool,
    /// `$PRO_STATE1` without `#`.
    pub pro_state: String,
    /// `$PRO_NAME1` (the selected module).
    pub pro_name: String,
    /// Errors that stopped a robot program, oldest first.
    pub robot_errors: Vec<String>,
    /// The error that stopped the Submit interpreter, if any.
    pub submit_error: Option<String>,
    /// `$CMD` commands the program sent, oldest first.
    pub commands: Vec<String>,
}

/// Cost figures of the program in the runtime (docs/BENCHMARKS.md).
#[derive(Debug, Clone, Default, Serialize)]
pub struct KrcStats {
    /// Interpreter cycles run.
    pub cycles: u64,
    /// Cycles in which the robot stood still.
    pub standstill_cycles: u64,
    /// Seconds of simulated motion.
    pub moving_s: f64,
    /// Motions completed.
    pub motions_done: u64,
    /// Motions that started from a standstill (exact stops before them).
    pub chains_started: u64,
    /// Controller time (ms, `$ROB_TIMER`) of the cycle in which the last
    /// motion from a standstill started.
    pub last_chain_start_ms: Option<i64>,
    /// Completed passes of `kb_submit_cycle`.
    pub passes: u64,
    /// Statements of the longest pass.
    pub pass_statements_max: u64,
    /// Median statements per pass (of the last 100,000 passes).
    pub pass_statements_p50: u64,
    /// 99th percentile of statements per pass (of the last 100,000 passes).
    pub pass_statements_p99: u64,
    /// Passes that needed more statements than one cycle's Submit budget
    /// ([`KrcConfig::submit_budget`](crate::KrcConfig::submit_budget)):
    /// wherever they start, they cannot finish within one cycle.
    pub passes_overrun: u64,
    /// File functions the program called through `CWRITE($FCT_CALL, …)`,
    /// by name (`krl_fgets` …).
    pub file_calls: std::collections::BTreeMap<String, u64>,
    /// Motion errors, `line: error`.
    pub motion_errors: Vec<String>,
}

struct Shared {
    scheduler: Mutex<Scheduler>,
    shutdown: AtomicBool,
    /// The controller is frozen (tests of a hung controller).
    paused: AtomicBool,
}

/// A running KRC-like runtime. Dropping it stops the thread.
pub struct KrcController {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    /// `kb_sim.lock` in the channel folder, held while the runtime runs.
    _lock: std::fs::File,
}

impl KrcController {
    /// Loads the KRL program, boots the interpreters and starts the clock.
    pub fn start(config: KrcConfig) -> Result<Self, KrcError> {
        std::fs::create_dir_all(&config.channel_dir).map_err(|source| KrcError::Channel {
            path: config.channel_dir.display().to_string(),
            source,
        })?;
        // Two controllers on one channel would both execute commands: the
        // same lock file as the native simulator's.
        let lock_path = config.channel_dir.join("kb_sim.lock");
        let lock = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|source| KrcError::Channel {
                path: lock_path.display().to_string(),
                source,
            })?;
        if lock.try_lock().is_err() {
            return Err(KrcError::InUse(config.channel_dir.display().to_string()));
        }
        let time_scale = config.time_scale;
        let cycle = config.cycle;
        let mut scheduler = Scheduler::new(config).map_err(KrcError::Program)?;
        scheduler.boot().map_err(KrcError::Program)?;
        let shared = Arc::new(Shared {
            scheduler: Mutex::new(scheduler),
            shutdown: AtomicBool::new(false),
            paused: AtomicBool::new(false),
        });
        let s = shared.clone();
        let thread = std::thread::Builder::new()
            .name("krc-clock".into())
            .spawn(move || clock(&s, cycle, time_scale))
            .map_err(KrcError::Thread)?;
        Ok(KrcController {
            shared,
            thread: Some(thread),
            _lock: lock,
        })
    }

    fn lock(&self) -> MutexGuard<'_, Scheduler> {
        self.shared
            .scheduler
            .lock()
            .unwrap_or_else(|e| e.into_inner())
    }

    /// The runtime's state now.
    pub fn snapshot(&self) -> KrcSnapshot {
        let s = self.lock();
        let p = s.exec.pose();
        KrcSnapshot {
            time_ms: s.t_ms,
            axes: s.exec.axes,
            pose: [p.x, p.y, p.z, p.a, p.b, p.c],
            moving: s.exec.moving(),
            pro_state: format!("{:?}", s.pro_state).to_ascii_uppercase(),
            pro_name: s.pro_name.clone(),
            robot_errors: s.counters.robot_errors.clone(),
            submit_error: s.counters.submit_error.clone(),
            commands: s.counters.commands.clone(),
        }
    }

    /// The cost figures so far.
    pub fn stats(&self) -> KrcStats {
        let s = self.lock();
        let p = s.passes.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let mut sorted: Vec<u64> = p.recent.iter().copied().collect();
        sorted.sort_unstable();
        let pct = |q: f64| {
            if sorted.is_empty() {
                0
            } else {
                sorted[((sorted.len() - 1) as f64 * q).round() as usize]
            }
        };
        let p99 = pct(0.99);
        KrcStats {
            cycles: s.counters.cycles,
            standstill_cycles: s.counters.standstill_cycles,
            moving_s: s.exec.moving_s,
            motions_done: s.exec.motions_done,
            chains_started: s.exec.chains_started,
            last_chain_start_ms: s.counters.last_chain_start_ms,
            passes: p.count,
            pass_statements_max: p.max,
            pass_statements_p50: pct(0.5),
            pass_statements_p99: p99,
            file_calls: s
                .file_calls
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .clone(),
            passes_overrun: p.over,
            motion_errors: s
                .exec
                .failures
                .iter()
                .map(|f| format!("line {}: {}", f.line, f.error))
                .collect(),
        }
    }

    /// Runs cycles until `done` holds for the snapshot or `limit` of
    /// simulated time passed; whether it held. For tests and benchmarks
    /// with `time_scale` 0 this runs as fast as the host allows.
    pub fn wait_until(&self, limit: Duration, mut done: impl FnMut(&KrcSnapshot) -> bool) -> bool {
        let start = self.lock().t_ms;
        let limit_ms = limit.as_millis() as i64;
        loop {
            let snap = self.snapshot();
            if done(&snap) {
                return true;
            }
            if snap.time_ms - start > limit_ms || self.shared.shutdown.load(Ordering::Relaxed) {
                return false;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// The upper-case names of every variable the controller provides to
    /// a program: its system variables and the globals of its `.dat`
    /// files (`$config.dat` included). What an uploaded program may use
    /// without declaring it (the service's upload check).
    pub fn global_names(&self) -> std::collections::BTreeSet<String> {
        self.lock()
            .vars
            .as_ref()
            .map(|v| v.names().map(str::to_string).collect())
            .unwrap_or_default()
    }

    /// A global variable of the running program in the interpreter's debug
    /// form, read between two cycles (diagnostics); `None` when it does
    /// not exist.
    pub fn variable(&self, name: &str) -> Option<String> {
        self.lock().vars.as_ref()?.describe(name)
    }

    /// A global INT of the program (e.g. `kb_last_cid`), read between two
    /// cycles; `None` when it does not exist or is not an INT.
    pub fn int_variable(&self, name: &str) -> Option<i64> {
        self.lock().vars.as_ref()?.int(name, &[])
    }

    /// An element of a global BOOL array of the program (e.g. `$OUT`, 9 for
    /// `$OUT[9]`), read between two cycles; `None` when it does not exist.
    pub fn bool_element(&self, name: &str, index: i64) -> Option<bool> {
        self.lock().vars.as_ref()?.bool(name, &[index])
    }

    /// Sets an element of a global BOOL array of the program between two
    /// cycles (a simulated input: `$IN`, 3 for `$IN[3]`); false when it
    /// does not exist.
    pub fn set_bool_element(&self, name: &str, index: i64, v: bool) -> bool {
        self.lock()
            .vars
            .as_mut()
            .is_some_and(|g| g.set_bool_element(name, index, v))
    }

    /// An element of a global REAL array of the program (e.g. `$ANOUT`, 2
    /// for `$ANOUT[2]`), read between two cycles; `None` when it does not
    /// exist.
    pub fn real_element(&self, name: &str, index: i64) -> Option<f64> {
        self.lock().vars.as_ref()?.real(name, &[index])
    }

    /// Sets an element of a global REAL array of the program between two
    /// cycles (a simulated analog input: `$ANIN`, 3 for `$ANIN[3]`); false
    /// when it does not exist or is not a REAL.
    pub fn set_real_element(&self, name: &str, index: i64, v: f64) -> bool {
        self.lock()
            .vars
            .as_mut()
            .is_some_and(|g| g.set_real_element(name, index, v))
    }

    /// A variable or a part of one (`$OV_PRO`, `$POS_ACT`, `TOOL_DATA[3]`,
    /// `$OUT[2]`) as KRL text, as KUKAVARPROXY reads it on a KRC, between
    /// two cycles; `None` when it does not exist or is not set.
    pub fn read_krl(&self, path: &str) -> Option<String> {
        self.lock().vars.as_ref()?.krl_text(path)
    }

    /// Assigns KRL text to a variable or a part of one between two cycles,
    /// as KUKAVARPROXY writes on a KRC; its value afterwards.
    pub fn write_krl(&self, path: &str, text: &str) -> Result<String, String> {
        if path.trim().eq_ignore_ascii_case("$OV_PRO")
            && !text
                .trim()
                .parse::<f64>()
                .is_ok_and(|v| (0.0..=100.0).contains(&v.round()))
        {
            // A KRC refuses a program override outside 0..100 %.
            return Err("$OV_PRO takes 0..100".into());
        }
        let mut s = self.lock();
        let g = s.vars.as_mut().ok_or("the program is not loaded")?;
        g.assign_krl(path, text)?;
        g.krl_text(path)
            .ok_or_else(|| "the value cannot be shown".into())
    }

    /// The executed path since the start (or the last [`clear_trace`]),
    /// oldest first: a sample per cycle in motion, stops marked.
    ///
    /// [`clear_trace`]: KrcController::clear_trace
    pub fn trace(&self) -> Vec<KrcTraceSample> {
        self.lock().trace.iter().copied().collect()
    }

    /// The samples with `t > since`, oldest first. Copies only those, so a
    /// client polling the trace does not hold the runtime up
    /// (docs/SECURITY.md: a whole-trace copy per poll starved the
    /// heartbeat).
    pub fn trace_since(&self, since: f64) -> Vec<KrcTraceSample> {
        let s = self.lock();
        // Samples are appended in time order.
        let start = s.trace.partition_point(|x| x.t <= since);
        s.trace.range(start..).copied().collect()
    }

    /// Empties the trace.
    pub fn clear_trace(&self) {
        self.lock().trace.clear();
    }

    /// What the operator (or the PLC's AUTOEXT fold) does after an error
    /// stop: acknowledge the stop message (`$STOPMESS`), cancel the halted
    /// program, select and start kb_main.
    pub fn operator_restart(&self) {
        self.lock().operator_restart();
    }

    /// The safety circuit changes, as on a real cell: an emergency stop
    /// pressed (`Some(true)`) or released, the operator safety closed
    /// (`Some(true)`) or opened; `None` leaves that part as it is. Opening
    /// it stops the robot where it is, switches the drives off and posts a
    /// stop message; the KRL program then ends the running command.
    pub fn set_safety(&self, emergency_stop: Option<bool>, user_safety: Option<bool>) {
        self.lock().set_safety(emergency_stop, user_safety);
    }

    /// What the operator does after a safety stop: acknowledge the stop
    /// message, switch the drives on and start kb_main again. Refused while
    /// the circuit is still open.
    pub fn acknowledge(&self) -> Result<(), AcknowledgeRefused> {
        let mut s = self.lock();
        match s.safety_closed() {
            (false, _) => Err(AcknowledgeRefused::EmergencyStop),
            (_, false) => Err(AcknowledgeRefused::UserSafety),
            (true, true) => {
                s.drives_on();
                s.operator_restart();
                Ok(())
            }
        }
    }

    /// Whether a stop message waits for acknowledgement (`$STOPMESS`).
    pub fn stop_message(&self) -> bool {
        self.lock().stopmess
    }

    /// Freezes the controller: no interpreter runs, no file is read or
    /// written, until [`resume`](Self::resume) (a hung controller, for
    /// tests).
    pub fn pause(&self) {
        self.shared.paused.store(true, Ordering::SeqCst);
    }

    /// Ends a [`pause`](Self::pause).
    pub fn resume(&self) {
        self.shared.paused.store(false, Ordering::SeqCst);
    }

    /// Runs `f` between two cycles, with the controller time (ms) of the
    /// last one: nothing runs on the controller meanwhile, so a command
    /// file written in `f` appears at a known time.
    pub fn between_cycles<R>(&self, f: impl FnOnce(i64) -> R) -> R {
        let s = self.lock();
        f(s.t_ms)
    }

    /// Stops the clock and the interpreters (open files are closed).
    pub fn shutdown(mut self) {
        self.stop();
    }

    fn stop(&mut self) {
        self.shared.shutdown.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        self.lock().stop_all();
    }
}

impl Drop for KrcController {
    fn drop(&mut self) {
        self.stop();
    }
}

/// The clock thread: a cycle, then wait for its simulated time to pass
/// in wall time (scaled).
fn clock(shared: &Shared, cycle: Duration, time_scale: f64) {
    let mut started = Instant::now();
    let mut simulated = Duration::ZERO;
    while !shared.shutdown.load(Ordering::Relaxed) {
        if shared.paused.load(Ordering::Relaxed) {
            // Frozen: no cycle, no file touched; real time passes without
            // the controller's.
            std::thread::sleep(Duration::from_millis(1));
            started = Instant::now();
            simulated = Duration::ZERO;
            continue;
        }
        shared
            .scheduler
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .cycle();
        simulated += cycle;
        if time_scale > 0.0 {
            let due = started + simulated.div_f64(time_scale);
            let now = Instant::now();
            if due > now {
                std::thread::sleep(due - now);
            }
        } else {
            // As fast as possible, but let others take the lock.
            std::thread::yield_now();
        }
    }
}

//! The controller's clock: one interpreter cycle after the other, the
//! motion played, the system variables updated, the robot interpreter and
//! then the Submit interpreter given their turns, `$CMD` commands carried
//! out.

use std::collections::{BTreeMap, VecDeque};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use kuka_kinematics::Axes;
use kuka_krl::Program;
use kuka_krl_runtime::interp::{
    ANALOG_CHANNELS, Globals, HostedFiles, OpenFiles, RunError, SharedOpenFiles, Start, Wait,
    run_hosted,
};
use kuka_protocol::SpeedRecord;

use crate::config::KrcConfig;
use crate::executor::Executor;
use crate::modules;
use crate::port::{Msg, PassStats, Port, Resume, Who};

/// `$PRO_STATE1` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ProState {
    Free,
    Active,
    Stop,
    End,
}

impl ProState {
    fn krl(self) -> &'static str {
        match self {
            ProState::Free => "P_FREE",
            ProState::Active => "P_ACTIVE",
            ProState::Stop => "P_STOP",
            ProState::End => "P_END",
        }
    }
}

/// One interpreter thread as the scheduler sees it.
struct Interpreter {
    to: Sender<Resume>,
    thread: Option<JoinHandle<()>>,
    /// What it waits for; `None` while it has not yielded yet.
    waiting: Option<Option<Wait>>,
    generation: u64,
}

impl Interpreter {
    /// Ends its thread: the next turn it waits for answers "cancelled".
    fn cancel(mut self) {
        let _ = self.to.send(Resume {
            vars: Globals::default(),
            ready: false,
            new_cycle: false,
            fired: Vec::new(),
            cancel: true,
        });
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// What one run of the scheduler has seen (the controller's statistics).
#[derive(Debug, Default, Clone)]
pub(crate) struct Counters {
    pub(crate) cycles: u64,
    pub(crate) standstill_cycles: u64,
    pub(crate) robot_errors: Vec<String>,
    pub(crate) submit_error: Option<String>,
    pub(crate) commands: Vec<String>,
    /// Chains (motions from a standstill) seen started.
    pub(crate) chains_seen: u64,
    /// Controller time (ms) at the end of the cycle in which the last chain
    /// started.
    pub(crate) last_chain_start_ms: Option<i64>,
}

/// The scheduler's state (owned by the controller thread).
pub(crate) struct Scheduler {
    pub(crate) config: KrcConfig,
    pub(crate) vars: Option<Globals>,
    pub(crate) exec: Executor,
    pub(crate) t_ms: i64,
    rx: Receiver<Msg>,
    tx: Sender<Msg>,
    robot: Option<Interpreter>,
    submit: Option<Interpreter>,
    program: Arc<Program>,
    pub(crate) pro_state: ProState,
    pub(crate) pro_name: String,
    pub(crate) passes: Arc<Mutex<PassStats>>,
    /// File functions called through `CWRITE($FCT_CALL, …)`, by name
    /// (both interpreters).
    pub(crate) file_calls: Arc<Mutex<BTreeMap<String, u64>>>,
    /// The files open through `CWRITE($FCT_CALL, …)`, shared by every run
    /// of both interpreters for the controller's life: a leaked handle
    /// holds its file until `krl_fclose_all` or a reboot (a new runtime).
    pub(crate) open_files: SharedOpenFiles,
    pub(crate) counters: Counters,
    fired: Vec<u64>,
    commands: VecDeque<String>,
    generation: u64,
    /// The robot program reached its END while the robot still moves:
    /// `$PRO_STATE1` becomes `#P_END` when the last motion is done.
    end_pending: bool,
    /// `$STOPMESS`: a stop message waits for acknowledgement (a motion
    /// failed).
    pub(crate) stopmess: bool,
    /// The executed path, one sample per cycle in motion and one where
    /// the robot came to a standstill (oldest dropped beyond
    /// `trace_capacity`).
    pub(crate) trace: VecDeque<KrcTraceSample>,
    /// The robot moved in the last cycle.
    was_moving: bool,
    /// Running `PULSE`s: signal, index, the level it returns to, and when
    /// (controller ms).
    pulses: Vec<Pulse>,
}

/// A running `PULSE` of a signal.
#[derive(Debug, Clone, PartialEq)]
struct Pulse {
    signal: String,
    index: i64,
    restore: bool,
    until_ms: i64,
}

/// The controller timers `$TIMER[1..64]` (ms), `$TIMER_STOP[]` and
/// `$TIMER_FLAG[]` (KSS 8.x has 64; unconfirmed for every version).
const TIMERS: i64 = 64;

/// One cycle of the executed path.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct KrcTraceSample {
    /// Controller time in seconds (standstill counts).
    pub t: f64,
    /// The command the KRL program was running (`kb_run_cid`; 0: none).
    pub cid: i64,
    /// Index of the motion being played within its batch (0 = first; the
    /// KRL program's `kb_busy_idx`, set by a TRIGGER at each motion's
    /// start).
    pub motion: usize,
    /// TCP `[x, y, z, a, b, c]` with the motion's tool and base.
    pub pose: [f64; 6],
    /// Axis angles A1..A6.
    pub axes: [f64; 6],
    /// The robot stands still from here on (an exact stop, the end of a
    /// batch, an error stop): the trace marks every stop.
    pub stop: bool,
}

impl Scheduler {
    pub(crate) fn new(config: KrcConfig) -> Result<Self, String> {
        let budget = config.submit_budget;
        let program =
            modules::shipped_program(config.krl_dir.as_deref()).map_err(|e| e.to_string())?;
        let axes: Axes = config.start_axes.unwrap_or(config.model.home);
        let exec = Executor::new(config.model.clone(), config.plan.clone(), axes);
        let (tx, rx) = mpsc::channel();
        Ok(Scheduler {
            config,
            vars: None,
            exec,
            t_ms: 0,
            rx,
            tx,
            robot: None,
            submit: None,
            program: Arc::new(program),
            pro_state: ProState::Free,
            pro_name: String::new(),
            passes: Arc::new(Mutex::new(PassStats::new(budget))),
            file_calls: Arc::new(Mutex::new(BTreeMap::new())),
            open_files: OpenFiles::shared(),
            counters: Counters::default(),
            fired: Vec::new(),
            commands: VecDeque::new(),
            generation: 0,
            end_pending: false,
            stopmess: false,
            trace: VecDeque::new(),
            was_moving: false,
            pulses: Vec::new(),
        })
    }

    /// Starts the interpreters: `kb_main` (if configured) and the Submit.
    pub(crate) fn boot(&mut self) -> Result<(), String> {
        if self.config.start_main {
            let program = self.program.clone();
            self.start_robot(program, "kb_main")?;
        }
        let program = self.program.clone();
        let submit = self.spawn(Who::Submit, program, "kb_sps_lines")?;
        self.submit = Some(submit);
        self.await_first(Who::Submit);
        Ok(())
    }

    fn start_robot(&mut self, program: Arc<Program>, entry: &str) -> Result<(), String> {
        let robot = self.spawn(Who::Robot, program, entry)?;
        self.robot = Some(robot);
        self.pro_state = ProState::Active;
        self.end_pending = false;
        self.pro_name = entry.to_ascii_uppercase();
        self.await_first(Who::Robot);
        Ok(())
    }

    /// Lets a new interpreter run up to its first turn (its `.dat`
    /// initialisation); its globals join the shared ones.
    fn await_first(&mut self, who: Who) {
        self.sync_sysvars();
        self.run_turns(who, None);
    }

    fn spawn(
        &mut self,
        who: Who,
        program: Arc<Program>,
        entry: &str,
    ) -> Result<Interpreter, String> {
        self.generation += 1;
        let generation = self.generation;
        let (to, from) = mpsc::channel();
        let budget = match who {
            Who::Robot => self.config.robot_budget,
            Who::Submit => self.config.submit_budget,
        }
        .max(1);
        let port = Port {
            who,
            generation,
            tx: self.tx.clone(),
            rx: from,
            budget,
            // The first statement hands over the globals the thread built
            // and waits for the shared ones.
            left: 0,
            passes: (who == Who::Submit).then(|| self.passes.clone()),
            file_calls: self.file_calls.clone(),
            max_passes: self.config.submit_passes_per_cycle,
            passes_this_cycle: 0,
            deferred: false,
        };
        let tx = self.tx.clone();
        let model = self.config.model.clone();
        let axes = self.exec.axes;
        let files = HostedFiles {
            root: self.config.channel_dir.clone(),
            success: self.config.fct_success.clone(),
            text_offset_base: self.config.text_offset_base,
            open: self.open_files.clone(),
            interpreter: format!("{who:?}").to_ascii_lowercase(),
        };
        let entry = entry.to_string();
        let thread = std::thread::Builder::new()
            .name(format!("krc-{who:?}").to_ascii_lowercase())
            .stack_size(kuka_krl_runtime::program::DRY_RUN_STACK_BYTES)
            .spawn(move || {
                let start = Start {
                    model: &model,
                    axes,
                    tool: kuka_kinematics::Pose::IDENTITY,
                    base: kuka_kinematics::Pose::IDENTITY,
                    speed: SpeedRecord {
                        ptp_velocity_pct: 100.0,
                        ptp_acceleration_pct: 100.0,
                        cp_velocity: 2.0,
                        cp_acceleration_pct: 100.0,
                        override_pct: 100.0,
                    },
                };
                let (result, vars) = run_hosted(&program, &entry, &start, Box::new(port), files);
                let _ = tx.send(Msg::Ended {
                    who,
                    result,
                    vars,
                    generation,
                });
            })
            .map_err(|e| format!("cannot start the {who:?} interpreter: {e}"))?;
        Ok(Interpreter {
            to,
            thread: Some(thread),
            waiting: None,
            generation,
        })
    }

    fn interpreter(&mut self, who: Who) -> Option<&mut Interpreter> {
        match who {
            Who::Robot => self.robot.as_mut(),
            Who::Submit => self.submit.as_mut(),
        }
    }

    /// Whether what `wait` waits for holds now.
    fn satisfied(&self, wait: Option<Wait>) -> bool {
        match wait {
            None | Some(Wait::Cycle) => true,
            Some(Wait::Advance) => {
                let advance = self
                    .vars
                    .as_ref()
                    .and_then(|v| v.int("$ADVANCE", &[]))
                    .unwrap_or(3)
                    .clamp(1, 5) as usize;
                self.exec.ahead() <= advance
            }
            Some(Wait::Standstill) => self.exec.idle(),
            Some(Wait::Until(ms)) => self.t_ms >= ms,
            Some(Wait::Brake) => self.exec.braked || self.exec.idle(),
        }
    }

    /// Gives `who` its turns in this cycle: resumes it (unless `resume`
    /// is `None`: it is starting) and handles its messages until it
    /// yields with something to wait for, or ends. A wait that already
    /// holds is answered at once, within the cycle.
    fn run_turns(&mut self, who: Who, resume: Option<Resume>) {
        let Some(generation) = self.interpreter(who).map(|i| i.generation) else {
            return;
        };
        if let Some(r) = resume
            && let Some(i) = self.interpreter(who)
            && i.to.send(r).is_err()
        {
            return;
        }
        loop {
            let Ok(msg) = self.rx.recv() else {
                return;
            };
            match msg {
                Msg::Motion { step, triggers } => self.exec.queue(step, triggers),
                Msg::Discard => self.exec.discard(),
                Msg::Command(c) => self.commands.push_back(c),
                Msg::Pulse {
                    signal,
                    index,
                    restore,
                    until_ms,
                } => {
                    // A new pulse of the same signal replaces the one
                    // running (its end is the new one's).
                    self.pulses
                        .retain(|p| !(p.signal == signal && p.index == index));
                    self.pulses.push(Pulse {
                        signal,
                        index,
                        restore,
                        until_ms,
                    });
                }
                Msg::Yield {
                    vars,
                    wait,
                    generation: g,
                    ..
                } if g == generation => {
                    let first = self.interpreter(who).is_some_and(|i| i.waiting.is_none());
                    match self.vars.as_mut() {
                        // The first turn of a thread: the globals it built
                        // join the shared ones (kept if already there).
                        Some(shared) if first => shared.merge_missing(vars),
                        Some(shared) => *shared = vars,
                        None => self.vars = Some(vars),
                    }
                    if wait == Some(Wait::Brake) {
                        self.exec.braked = true;
                    } else if wait.is_some() {
                        self.exec.braked = false;
                    }
                    if let Some(i) = self.interpreter(who) {
                        i.waiting = Some(wait);
                    }
                    // Within the cycle: a wait that holds goes on at once
                    // (a queued motion with room in the advance run).
                    if matches!(
                        wait,
                        Some(Wait::Advance | Wait::Standstill | Wait::Until(_))
                    ) && self.satisfied(wait)
                    {
                        let r = self.resume(false);
                        if let Some(i) = self.interpreter(who)
                            && i.to.send(r).is_ok()
                        {
                            continue;
                        }
                    }
                    return;
                }
                Msg::Ended {
                    who: w,
                    result,
                    vars,
                    generation: g,
                } => {
                    self.ended(w, result, vars, g);
                    if g == generation {
                        return;
                    }
                }
                // A turn of a cancelled thread: let it end.
                Msg::Yield { .. } => {}
            }
        }
    }

    fn resume(&mut self, new_cycle: bool) -> Resume {
        Resume {
            vars: self.vars.take().unwrap_or_default(),
            ready: true,
            new_cycle,
            fired: std::mem::take(&mut self.fired),
            cancel: false,
        }
    }

    fn ended(
        &mut self,
        who: Who,
        result: Result<(), RunError>,
        vars: Option<Globals>,
        generation: u64,
    ) {
        let current = self
            .interpreter(who)
            .is_some_and(|i| i.generation == generation);
        if !current {
            return;
        }
        // The program held the shared globals when it ended: they live on
        // (a KRC's .dat globals outlast the program that wrote them).
        if self.vars.is_none() {
            self.vars = vars;
        }
        let finished = match who {
            Who::Robot => self.robot.take(),
            Who::Submit => self.submit.take(),
        };
        if let Some(t) = finished.and_then(|mut i| i.thread.take()) {
            let _ = t.join();
        }
        match (who, result) {
            (Who::Robot, Ok(())) => {
                if self.exec.idle() {
                    self.pro_state = ProState::End;
                } else {
                    self.end_pending = true;
                }
            }
            (Who::Robot, Err(RunError::Cancelled)) => self.pro_state = ProState::Free,
            (Who::Robot, Err(e)) => {
                tracing::warn!(program = %self.pro_name, error = %e, "KRC runtime: the robot program stopped with an error");
                self.counters
                    .robot_errors
                    .push(format!("{}: {e}", self.pro_name));
                // A KRC halts the program with a stop message.
                self.pro_state = ProState::Stop;
                self.stopmess = true;
                self.exec.discard();
            }
            (Who::Submit, Ok(())) => {}
            (Who::Submit, Err(e)) => {
                tracing::warn!(error = %e, "KRC runtime: the Submit interpreter stopped with an error");
                self.counters.submit_error = Some(e.to_string());
            }
        }
    }

    /// Cancels the robot program (`CANCEL 1`, a new `RUN`, shutdown).
    fn cancel_robot(&mut self) {
        if let Some(i) = self.robot.take() {
            i.cancel();
        }
        // Its last messages (motions, Ended) are stale now: a cancelled
        // program's motions are not played.
        while self.rx.try_recv().is_ok() {}
        self.exec.discard();
        self.end_pending = false;
        self.pro_state = ProState::Free;
        self.pro_name.clear();
    }

    /// Cancels everything (shutdown).
    pub(crate) fn stop_all(&mut self) {
        self.cancel_robot();
        if let Some(i) = self.submit.take() {
            i.cancel();
        }
    }

    fn command(&mut self, text: &str) {
        self.counters.commands.push(text.to_string());
        if self.counters.commands.len() > 100 {
            self.counters.commands.remove(0);
        }
        let t = text.trim();
        let upper = t.to_ascii_uppercase();
        if let Some(rest) = upper.strip_prefix("RUN") {
            let path = rest.trim();
            let prefix = self.config.run_prefix.to_ascii_uppercase();
            let Some(call) = path.strip_prefix(&prefix) else {
                tracing::info!(command = t, "KRC runtime: RUN path not found (KSS01422)");
                return;
            };
            let module = call.trim_end_matches("()").trim().to_ascii_lowercase();
            if self.pro_state != ProState::Free && self.pro_state != ProState::End {
                return;
            }
            if self.stopmess {
                // A KRC starts no program while a stop message waits.
                tracing::info!(
                    command = t,
                    "KRC runtime: RUN refused: acknowledge the stop message first"
                );
                return;
            }
            let program = if module == "kb_main" {
                Ok(self.program.clone())
            } else {
                modules::uploaded_program(&self.config.program_dir, &module).map(Arc::new)
            };
            match program {
                Ok(p) => {
                    self.cancel_robot();
                    if let Err(e) = self.start_robot(p, &module) {
                        self.counters.robot_errors.push(e);
                    }
                }
                Err(e) => {
                    tracing::info!(command = t, error = %e, "KRC runtime: RUN refused");
                    self.counters.robot_errors.push(e);
                }
            }
        } else if upper.starts_with("CANCEL") || upper.starts_with("RESET") {
            self.cancel_robot();
        } else if upper.starts_with("STOP") && self.pro_state == ProState::Active {
            self.pro_state = ProState::Stop;
        }
    }

    /// Adds this cycle to the trace: a sample while moving, and one
    /// marked `stop` when the robot has just come to a standstill.
    fn record_trace(&mut self) {
        let moving = self.exec.moving();
        if !moving && !self.was_moving {
            return;
        }
        self.was_moving = moving;
        let p = self.exec.pose();
        let global = |name: &str| {
            self.vars
                .as_ref()
                .and_then(|v| v.int(name, &[]))
                .unwrap_or(0)
        };
        let (cid, motion) = (global("KB_RUN_CID"), global("KB_BUSY_IDX"));
        self.trace.push_back(KrcTraceSample {
            t: self.t_ms as f64 / 1000.0,
            cid,
            motion: usize::try_from(motion).unwrap_or(0),
            pose: [p.x, p.y, p.z, p.a, p.b, p.c],
            axes: self.exec.axes,
            stop: !moving,
        });
        while self.trace.len() > self.config.trace_capacity.max(1) {
            self.trace.pop_front();
        }
    }

    /// The safety circuit changes: an emergency stop pressed (`Some(true)`)
    /// or released, the operator safety closed (`Some(true)`) or opened;
    /// `None` leaves that part as it is. Opening the circuit stops the
    /// robot where it is (a STOP 0 here: no braking distance), switches the
    /// drives off (`$PERI_RDY`), posts a stop message (`$STOPMESS`) and
    /// stops the robot program, as a KRC does; closing it changes nothing
    /// else until the operator acknowledges.
    pub(crate) fn set_safety(&mut self, emergency_stop: Option<bool>, user_safety: Option<bool>) {
        let Some(v) = self.vars.as_mut() else {
            return;
        };
        let closed = |v: &Globals| {
            v.bool("$ALARM_STOP", &[]).unwrap_or(true) && v.bool("$USER_SAF", &[]).unwrap_or(true)
        };
        let was_closed = closed(v);
        if let Some(pressed) = emergency_stop {
            v.set_bool("$ALARM_STOP", !pressed);
        }
        if let Some(ok) = user_safety {
            v.set_bool("$USER_SAF", ok);
        }
        if was_closed && !closed(v) {
            v.set_bool("$PERI_RDY", false);
            self.exec.discard();
            self.stopmess = true;
            self.end_pending = false;
            if self.pro_state == ProState::Active {
                self.pro_state = ProState::Stop;
            }
            tracing::info!(program = %self.pro_name, "KRC runtime: safety stop, drives off");
        }
    }

    /// Whether the safety circuit is closed (no emergency stop, operator
    /// safety closed).
    pub(crate) fn safety_closed(&self) -> (bool, bool) {
        let get = |name: &str| {
            self.vars
                .as_ref()
                .and_then(|v| v.bool(name, &[]))
                .unwrap_or(true)
        };
        (get("$ALARM_STOP"), get("$USER_SAF"))
    }

    /// Switches the drives on (`$PERI_RDY`), as the operator or the PLC
    /// does once the circuit is closed.
    pub(crate) fn drives_on(&mut self) {
        if let Some(v) = self.vars.as_mut() {
            v.set_bool("$PERI_RDY", true);
        }
    }

    /// What the operator (or the PLC's AUTOEXT fold) does after an error
    /// stop: acknowledge the messages, select and start kb_main.
    pub(crate) fn operator_restart(&mut self) {
        self.stopmess = false;
        self.command("CANCEL 1");
        let run = format!("RUN {}kb_main()", self.config.run_prefix);
        self.command(&run);
    }

    /// The system variables the controller maintains.
    fn sync_sysvars(&mut self) {
        let mode = self.config.mode.clone();
        let t = self.t_ms;
        let axes = self.exec.axes;
        let state = self.pro_state.krl();
        let name = self.pro_name.clone();
        let model = self.config.model.clone();
        let Some(v) = self.vars.as_mut() else {
            return;
        };
        v.set_int("$ROB_TIMER", t);
        v.set_axes("$AXIS_ACT", &axes);
        if let Some(p) = &self.config.site_run_prefix {
            // The site's edit of kb_main.dat, once its globals exist.
            if v.has("kb_run_pfx") && v.text("kb_run_pfx").as_deref() != Some(p.as_str()) {
                v.set_text("kb_run_pfx", p, 40);
            }
        }
        v.set_enum("$PRO_STATE1", state);
        v.set_chars("$PRO_NAME1", &name, 24);
        v.set_enum("$MODE_OP", &mode);
        v.set_bool("$POWER_FAIL", false);
        v.set_bool("$STOPMESS", self.stopmess);
        // Drives on, fence closed, no emergency stop, unless a test or the
        // operator changed them.
        for ready in ["$PERI_RDY", "$USER_SAF", "$ALARM_STOP"] {
            if !v.has(ready) {
                v.set_bool(ready, true);
            }
        }
        // No real robot moves here: the state file says so (kb_main.dat).
        v.set_bool("kb_simulated", true);
        if !v.has("$IPO_MODE") {
            v.set_enum("$IPO_MODE", "BASE");
        }
        if !v.has("$VEL_MA") {
            v.set_real_struct(
                "$VEL_MA",
                "VEL_STRUC",
                &[("CP", 2.0), ("ORI1", 400.0), ("ORI2", 400.0)],
            );
            v.set_real_struct(
                "$ACC_MA",
                "ACC_STRUC",
                &[("CP", 10.0), ("ORI1", 1000.0), ("ORI2", 1000.0)],
            );
            let (lo, hi): (Vec<f64>, Vec<f64>) = model.limits_deg.iter().copied().unzip();
            v.set_reals("$SOFTN_END", &lo);
            v.set_reals("$SOFTP_END", &hi);
            v.ensure_bools("$IN", 4096, false);
            v.ensure_bools("$OUT", 4096, false);
        }
        // The analog channels, 0.0 after a cold start (a test or the
        // service sets a simulated input with set_real_element).
        v.ensure_reals("$ANIN", ANALOG_CHANNELS, 0.0);
        v.ensure_reals("$ANOUT", ANALOG_CHANNELS, 0.0);
        // The controller timers: stopped at 0 after a cold start.
        v.ensure_ints("$TIMER", TIMERS as usize, 0);
        v.ensure_bools("$TIMER_STOP", TIMERS as usize, true);
        v.ensure_bools("$TIMER_FLAG", TIMERS as usize, true);
        // Pulses whose time is over return to their other level.
        self.pulses.retain(|p| {
            if t < p.until_ms {
                return true;
            }
            v.set_bool_element(&p.signal, p.index, p.restore);
            false
        });
    }

    /// One cycle of the controller timers: every `$TIMER[n]` whose
    /// `$TIMER_STOP[n]` is FALSE counts `ms` on; `$TIMER_FLAG[n]` is
    /// `$TIMER[n] >= 0`.
    fn count_timers(&mut self, ms: i64) {
        let Some(v) = self.vars.as_mut() else {
            return;
        };
        for n in 1..=TIMERS {
            if v.bool("$TIMER_STOP", &[n]) != Some(false) {
                continue;
            }
            let Some(t) = v.int("$TIMER", &[n]) else {
                continue;
            };
            let t = t.saturating_add(ms).min(i64::from(i32::MAX));
            v.set_int_element("$TIMER", n, t);
            v.set_bool_element("$TIMER_FLAG", n, t >= 0);
        }
    }

    /// One interpreter cycle.
    pub(crate) fn cycle(&mut self) {
        let dt = self.config.cycle.as_secs_f64();
        let dt_ms = (dt * 1000.0).round() as i64;
        self.t_ms += dt_ms;
        self.count_timers(dt_ms);
        self.counters.cycles += 1;
        if !self.exec.moving() {
            self.counters.standstill_cycles += 1;
        }
        // The program override $OV_PRO (the Submit side writes it for
        // SET_OVR) scales the robot's progress along its planned path: at
        // 50 % a motion takes twice as long. A KRC ramps to a new override;
        // here it applies from the next cycle.
        let ov = self
            .vars
            .as_ref()
            .and_then(|v| v.int("$OV_PRO", &[]))
            .unwrap_or(100)
            .clamp(0, 100) as f64
            / 100.0;
        let fired = self.exec.advance(dt * ov);
        self.fired.extend(fired);
        self.record_trace();
        if std::mem::take(&mut self.exec.failed) {
            // Error stop: the robot program halts with a stop message until
            // it is acknowledged and started again (or cancelled).
            self.stopmess = true;
            self.end_pending = false;
            if self.pro_state == ProState::Active {
                self.pro_state = ProState::Stop;
            }
            tracing::info!(program = %self.pro_name, "KRC runtime: motion error, error stop");
        }
        if self.end_pending && self.exec.idle() {
            self.end_pending = false;
            self.pro_state = ProState::End;
        }
        self.sync_sysvars();
        // The robot interpreter (unless its program is stopped).
        if self.pro_state == ProState::Active
            && let Some(w) = self.robot.as_ref().and_then(|i| i.waiting)
        {
            let mut r = self.resume(true);
            r.ready = self.satisfied(w);
            self.run_turns(Who::Robot, Some(r));
        }
        // The Submit interpreter.
        if let Some(w) = self.submit.as_ref().and_then(|i| i.waiting) {
            let mut r = self.resume(true);
            r.ready = self.satisfied(w);
            self.run_turns(Who::Submit, Some(r));
        }
        while let Some(c) = self.commands.pop_front() {
            self.command(&c);
        }
        if self.exec.chains_started > self.counters.chains_seen {
            self.counters.chains_seen = self.exec.chains_started;
            self.counters.last_chain_start_ms = Some(self.t_ms);
        }
    }
}

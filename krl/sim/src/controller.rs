//! The controller's state machine: what a command does to the simulated
//! robot, independent of files and threads.

use std::collections::VecDeque;
use std::time::Instant;

use kuka_kinematics::{
    Axes, Execution, IkError, Motion, MotionError, MotionKind, PlanSettings, Pose, RobotModel,
};
use kuka_krl_runtime::interp::{self, RunError};
use kuka_krl_runtime::program::{Phase, PrepareError, phases};
use kuka_krl_runtime::{frame_to_pose, pose_to_frame, to_motions};
use kuka_protocol::{
    AcknowledgeRefused, Cid, Command, ControllerStatus, Frame, IoState, OperatingMode,
    RESULT_HISTORY, ResultCode, ResultRecord, SpeedRecord, StateFile, whole_blocks,
};
use serde::Serialize;

use crate::actions::{Actions, OutputAction, Wait, decide, run_earlier};
use crate::path::{PathEnd, PathRun};

/// One executed point of the TCP trace.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct TraceSample {
    /// Simulated time in seconds since the controller started.
    pub t: f64,
    /// Command that moved the robot here.
    pub cid: Cid,
    /// Motion index within that command's batch.
    pub motion: usize,
    /// TCP pose in the base frame `[x, y, z, a, b, c]`.
    #[cfg_attr(feature = "openapi", schema(value_type = Vec<f64>))]
    pub pose: [f64; 6],
    /// Axis angles A1..A6.
    #[cfg_attr(feature = "openapi", schema(value_type = Vec<f64>))]
    pub axes: Axes,
    /// The robot stands still from here on. The KRC-like runtime marks
    /// every stop (exact stops inside a batch, its end, an error stop);
    /// the native simulator marks where each batch ends.
    pub stop: bool,
}

/// A batch being played back.
struct Active {
    cid: Cid,
    execution: Execution,
    motions: usize,
    started_wall: Instant,
    next_sample: usize,
    current_motion: usize,
    /// Set while a RUN command plays an uploaded program.
    program: Option<ProgramRun>,
    /// The batch's I/O actions (protocol §5.6).
    actions: Actions,
    /// The `WIN` whose input did not come in time: the batch ends there.
    timed_out: Option<usize>,
}

impl Active {
    /// Motions (and dwells) completed or running, over the whole command.
    fn progress(&self) -> usize {
        self.program.as_ref().map_or(0, |p| p.steps_before) + self.current_motion
    }
}

/// The part of a running program after the current phase.
struct ProgramRun {
    /// Source line of each motion of the current phase.
    lines: Vec<u32>,
    /// Phases still to play.
    rest: VecDeque<Phase>,
    /// Steps of the phases already played.
    steps_before: usize,
}

/// What one step of [`Controller::advance`] did.
enum Advanced {
    /// Done for now, with these changes.
    Changes(Changes),
    /// A program phase ended and the next one started: play on.
    NextPhase,
}

/// A RUN command whose program is being parsed and run ahead.
struct Preparing {
    cid: Cid,
    rx: std::sync::mpsc::Receiver<Result<Vec<interp::Step>, (ResultCode, u32)>>,
}

/// Parses module `kbu<n>` and runs it ahead with the interpreter (on the
/// program thread); the steps, or the result code and line of the error.
fn prepare(
    n: i32,
    loaded: LoadedProgram,
    model: &RobotModel,
    axes: kuka_kinematics::Axes,
    tool: Pose,
    base: Pose,
    speed: SpeedRecord,
) -> Result<Vec<interp::Step>, (ResultCode, u32)> {
    let module = format!("kbu{n}");
    let (src, dat) = loaded.map_err(|why| {
        tracing::warn!(%module, %why, "program cannot be read");
        (ResultCode::RuntimeError, 0)
    })?;
    let start = interp::Start {
        model,
        axes,
        tool,
        base,
        speed,
    };
    kuka_krl_runtime::program::interpret(&src, dat.as_deref(), &module, &start).map_err(|e| {
        tracing::info!(%module, error = %e, "program refused");
        match &e {
            PrepareError::Parse(p) => (ResultCode::BadCommand, p.line().unwrap_or(0)),
            PrepareError::Run(RunError::Unsupported(u)) => (ResultCode::Unsupported, u.line),
            PrepareError::Run(
                RunError::Runtime { line, .. }
                | RunError::TooLong { line, .. }
                | RunError::Limit { line, .. },
            ) => (ResultCode::RuntimeError, *line),
            // Hosted-mode outcomes: an unhosted run never returns them.
            PrepareError::Run(RunError::Cancelled | RunError::Resumed { .. }) => {
                (ResultCode::RuntimeError, 0)
            }
        }
    })
}

/// An uploaded program as the runner read it from the program folder:
/// `(src, dat)`, or why it could not be read.
pub(crate) type LoadedProgram = Result<(String, Option<String>), String>;

/// The simulated controller's memory.
pub(crate) struct Controller {
    pub(crate) model: RobotModel,
    pub(crate) plan: PlanSettings,
    pub(crate) mode: OperatingMode,
    pub(crate) axes: Axes,
    pub(crate) tool: Pose,
    pub(crate) base: Pose,
    pub(crate) speed: SpeedRecord,
    pub(crate) last_cid: Cid,
    pub(crate) results: VecDeque<ResultRecord>,
    pub(crate) error: Option<(ResultCode, u8)>,
    pub(crate) seq: i32,
    pub(crate) sim_time: f64,
    pub(crate) trace: VecDeque<TraceSample>,
    pub(crate) trace_capacity: usize,
    active: Option<Active>,
    /// A RUN command being prepared on its thread.
    preparing: Option<Preparing>,
    /// The open motion stream (protocol version 2), with the wall time of
    /// its path time 0 and of its last APPEND.
    path: Option<(PathRun, Instant, Instant)>,
    /// Digital inputs `$IN[1..=4096]` (index 0 unused): set from outside
    /// ([`crate::SimController::set_input`]), as a plant would.
    pub(crate) inputs: Vec<bool>,
    /// Digital outputs `$OUT[1..=4096]` (index 0 unused).
    pub(crate) outputs: Vec<bool>,
    /// The running output pulse: output, the value it returns to, when.
    pulse: Option<(u16, bool, Instant)>,
    /// `$ANIN[1..=32]` (index 0 unused), normalised −1..=1.
    pub(crate) analog_inputs: Vec<f64>,
    /// `$ANOUT[1..=32]` (index 0 unused).
    pub(crate) analog_outputs: Vec<f64>,
    /// `TOOL_DATA[1..=16]` (read and written through KUKAVARPROXY only).
    pub(crate) tool_data: Vec<Pose>,
    /// `BASE_DATA[1..=32]`.
    pub(crate) base_data: Vec<Pose>,
    /// `TOOL_NAME[1..=16,]`: the tool table's names (empty at start).
    pub(crate) tool_names: Vec<String>,
    /// `BASE_NAME[1..=32,]`.
    pub(crate) base_names: Vec<String>,
    /// The safety circuit and drives as a teach pendant shows them.
    pub(crate) safety: SafetyCircuit,
    /// The error state was set by a safety stop (it ended a job): once
    /// the operator has acknowledged, it is no stop message any more, only
    /// the error RESET clears (as the KRL program's `kb_err` 30).
    safety_error: bool,
    /// Results pushed outside a command or a motion step (an emergency
    /// stop ended the running command): the next [`Controller::advance`]
    /// reports them so that the runner writes the result file.
    results_pending: bool,
}

/// The simulated controller's safety circuit: what `$ALARM_STOP`,
/// `$USER_SAF`, `$PERI_RDY` and `$STOPMESS` say on a KRC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SafetyCircuit {
    /// `$ALARM_STOP`: TRUE while no emergency stop is pressed.
    pub(crate) alarm_stop: bool,
    /// `$USER_SAF`: the operator safety (fence, enabling device) closed.
    pub(crate) user_safety: bool,
    /// `$PERI_RDY`: the drives are on.
    pub(crate) drives: bool,
    /// `$STOPMESS`: a safety stop's message waits for acknowledgement.
    pub(crate) stop_message: bool,
}

impl Default for SafetyCircuit {
    fn default() -> Self {
        SafetyCircuit {
            alarm_stop: true,
            user_safety: true,
            drives: true,
            stop_message: false,
        }
    }
}

/// Entries of `TOOL_DATA`.
pub(crate) const TOOLS: usize = 16;
/// Entries of `BASE_DATA`.
pub(crate) const BASES: usize = 32;

/// First I/O index of the state file's window (the KRL program's
/// `kb_io_base`).
pub(crate) const IO_BASE: u16 = 1;

/// An open path whose robot has stood at the end of its motions this long
/// without an APPEND ends (its service is gone); as `kb_path_idle_ms` in
/// the KRL program.
pub(crate) const PATH_IDLE: std::time::Duration = std::time::Duration::from_secs(5);

/// What handling a command changed, so the runner knows whether to write
/// the result file. (The state file follows the heartbeat, and at once when
/// [`Controller::status_key`] changes.)
#[derive(Debug, Default, PartialEq, Eq)]
pub(crate) struct Changes {
    pub(crate) results: bool,
}

impl Changes {
    fn results() -> Self {
        Changes { results: true }
    }
}

fn motion_error_code(e: &MotionError) -> (ResultCode, u8) {
    match e {
        MotionError::Ik(IkError::Unreachable) => (ResultCode::Unreachable, 0),
        MotionError::Ik(IkError::SoftwareLimit { axis, .. }) => (ResultCode::SoftwareLimit, *axis),
        MotionError::Ik(IkError::NoMatchingConfiguration { .. }) => {
            (ResultCode::NoConfiguration, 0)
        }
        MotionError::Singularity(_) => (ResultCode::Singularity, 0),
        MotionError::Geometry(_) => (ResultCode::Geometry, 0),
        MotionError::Parameter(_) => (ResultCode::BadCommand, 0),
    }
}

impl Controller {
    pub(crate) fn new(
        model: RobotModel,
        plan: PlanSettings,
        mode: OperatingMode,
        start: Axes,
        trace_capacity: usize,
    ) -> Self {
        Controller {
            model,
            speed: SpeedRecord {
                override_pct: plan.override_pct,
                ptp_velocity_pct: 20.0,
                ptp_acceleration_pct: 100.0,
                cp_velocity: 0.25,
                cp_acceleration_pct: 100.0,
            },
            plan,
            mode,
            axes: start,
            tool: Pose::IDENTITY,
            base: Pose::IDENTITY,
            last_cid: 0,
            results: VecDeque::with_capacity(RESULT_HISTORY + 1),
            error: None,
            seq: 0,
            sim_time: 0.0,
            trace: VecDeque::new(),
            trace_capacity,
            active: None,
            preparing: None,
            path: None,
            inputs: vec![false; usize::from(kuka_protocol::MAX_IO_INDEX) + 1],
            outputs: vec![false; usize::from(kuka_protocol::MAX_IO_INDEX) + 1],
            pulse: None,
            analog_inputs: vec![0.0; usize::from(kuka_protocol::MAX_ANALOG_INDEX) + 1],
            analog_outputs: vec![0.0; usize::from(kuka_protocol::MAX_ANALOG_INDEX) + 1],
            tool_data: vec![Pose::IDENTITY; TOOLS],
            base_data: vec![Pose::IDENTITY; BASES],
            tool_names: vec![String::new(); TOOLS],
            base_names: vec![String::new(); BASES],
            safety: SafetyCircuit::default(),
            safety_error: false,
            results_pending: false,
        }
    }

    /// Brakes where the robot is now and ends whatever runs (a path, a
    /// program being prepared, a batch) with `code`.
    fn brake_all(&mut self, code: ResultCode) {
        if let Some((run, _, _)) = self.path.take() {
            self.sim_time += run.t;
            self.push_result(run.cid, code, run.current as u32, 0, None);
        }
        if let Some(p) = self.preparing.take() {
            // Nothing moved yet; the program thread's answer is dropped.
            self.push_result(p.cid, code, 0, 0, None);
        }
        if let Some(active) = self.active.take() {
            // Brake where the robot is now (the sample reached last).
            let elapsed = active
                .execution
                .samples
                .get(active.next_sample.saturating_sub(1))
                .map_or(0.0, |s| s.t);
            self.sim_time += elapsed;
            self.push_result(active.cid, code, active.progress() as u32, 0, None);
        }
    }

    /// The safety circuit changes: an emergency stop pressed or released,
    /// the operator safety opened or closed (`None`: unchanged). Opening it
    /// stops the robot where it is (a STOP 0 here, no braking distance),
    /// switches the drives off and posts a stop message: the running
    /// command ends CONTROLLER_ERROR and the controller stays in its error
    /// state until RESET; an idle controller is NOT_READY until the
    /// message is acknowledged. Closing it changes nothing else: the
    /// drives stay off until [`acknowledge`](Self::acknowledge).
    pub(crate) fn set_safety(&mut self, emergency_stop: Option<bool>, user_safety: Option<bool>) {
        let was_closed = self.safety.alarm_stop && self.safety.user_safety;
        if let Some(pressed) = emergency_stop {
            self.safety.alarm_stop = !pressed;
        }
        if let Some(closed) = user_safety {
            self.safety.user_safety = closed;
        }
        let closed = self.safety.alarm_stop && self.safety.user_safety;
        if was_closed && !closed {
            let running = self.is_busy();
            self.brake_all(ResultCode::ControllerError);
            self.results_pending |= running;
            self.safety.drives = false;
            self.safety.stop_message = true;
            if self.error.is_none() {
                self.error = Some(if running {
                    (ResultCode::ControllerError, 0)
                } else {
                    (ResultCode::NotReady, 0)
                });
                self.safety_error = true;
            }
        }
    }

    /// Puts the controller into an error state that is a stop message (a
    /// runtime error, until RESET).
    pub(crate) fn set_error(&mut self, code: ResultCode, axis: u8) {
        self.error = Some((code, axis));
        self.safety_error = false;
    }

    /// Whether the error state is a stop message waiting for the operator:
    /// any error but one a safety stop left behind (which, acknowledged,
    /// only waits for RESET).
    fn error_is_message(&self) -> bool {
        self.error.is_some() && !self.safety_error
    }

    /// The operator acknowledges the stop message and switches the drives
    /// on; refused while the safety circuit is open. An idle controller is
    /// ready again; one whose command was ended by the stop keeps its
    /// error state until RESET (as the KRL program).
    pub(crate) fn acknowledge(&mut self) -> Result<(), AcknowledgeRefused> {
        if !self.safety.alarm_stop {
            return Err(AcknowledgeRefused::EmergencyStop);
        }
        if !self.safety.user_safety {
            return Err(AcknowledgeRefused::UserSafety);
        }
        self.safety.stop_message = false;
        self.safety.drives = true;
        if matches!(self.error, Some((ResultCode::NotReady, _))) {
            self.error = None;
            self.safety_error = false;
        }
        Ok(())
    }

    /// The state file's I/O window.
    pub(crate) fn io_state(&self) -> IoState {
        let bits = |v: &[bool]| {
            (0..IoState::WIDTH).fold(0u32, |acc, k| {
                if v[usize::from(IO_BASE + k)] {
                    acc | (1 << k)
                } else {
                    acc
                }
            })
        };
        IoState {
            base: IO_BASE,
            inputs: bits(&self.inputs),
            outputs: bits(&self.outputs),
        }
    }

    /// Switches outputs the robot has passed (`SOT` records), as SETOUT
    /// does: one pulse at a time, a new output ends a running pulse first.
    fn switch_outputs(&mut self, outputs: Vec<OutputAction>, now: Instant) {
        for (index, value, pulse_ms) in outputs {
            if let Some((i, back, _)) = self.pulse.take() {
                self.outputs[usize::from(i)] = back;
            }
            self.outputs[usize::from(index)] = value;
            if pulse_ms > 0 {
                let at = now + std::time::Duration::from_millis(u64::from(pulse_ms));
                self.pulse = Some((index, !value, at));
            }
        }
    }

    /// The state file's analog channels (`$ANIN`/`$ANOUT[1..=8]`).
    pub(crate) fn analog_state(&self) -> kuka_protocol::AnalogState {
        let mut a = kuka_protocol::AnalogState::default();
        a.inputs
            .copy_from_slice(&self.analog_inputs[1..=kuka_protocol::AnalogState::WIDTH]);
        a.outputs
            .copy_from_slice(&self.analog_outputs[1..=kuka_protocol::AnalogState::WIDTH]);
        a
    }

    /// Ends an output pulse that is due.
    fn end_pulse(&mut self, now: Instant) {
        if let Some((index, back, at)) = self.pulse
            && now >= at
        {
            self.outputs[usize::from(index)] = back;
            self.pulse = None;
        }
    }

    /// TCP pose with Status and Turn.
    pub(crate) fn position(&self) -> (Pose, u8, u8) {
        let pose = self.model.forward(&self.axes, &self.tool, &self.base);
        (
            pose,
            self.model.status(&self.axes),
            RobotModel::turn(&self.axes),
        )
    }

    pub(crate) fn is_busy(&self) -> bool {
        self.active.is_some() || self.preparing.is_some() || self.path.is_some()
    }

    /// Wall-clock instant when the next sample of the active batch is due.
    pub(crate) fn next_sample_due(&self, time_scale: f64) -> Option<Instant> {
        if let Some((p, wall, last)) = &self.path {
            if time_scale <= 0.0 {
                // Instant: what is playable plays now; the held last motion
                // waits for more (or the idle timeout).
                return match p.next_sample_t() {
                    Some(t) if t <= p.hold_t() => Some(*wall),
                    _ => Some(*last + PATH_IDLE),
                };
            }
            return match p.next_sample_t() {
                Some(t) => {
                    Some(*wall + std::time::Duration::from_secs_f64((t / time_scale).max(0.0)))
                }
                // Standing at the end: the idle timeout is the next thing due.
                None => Some(*last + PATH_IDLE),
            };
        }
        let a = self.active.as_ref()?;
        let s = a.execution.samples.get(a.next_sample)?;
        if time_scale <= 0.0 {
            return Some(a.started_wall);
        }
        Some(a.started_wall + std::time::Duration::from_secs_f64((s.t / time_scale).max(0.0)))
    }

    fn push_result(
        &mut self,
        cid: Cid,
        code: ResultCode,
        completed: u32,
        axis: u8,
        position: Option<Frame>,
    ) {
        let (pose, s, t) = self.position();
        let position = position.unwrap_or_else(|| pose_to_frame(&pose));
        self.results.push_back(ResultRecord {
            cid,
            code,
            completed,
            axis,
            position,
            s,
            t,
            axes: self.axes,
        });
        while self.results.len() > RESULT_HISTORY {
            self.results.pop_front();
        }
    }

    /// Answers a command whose header is intact but whose body is not.
    pub(crate) fn reject_malformed(&mut self, cid: Cid) {
        self.last_cid = cid;
        self.push_result(cid, ResultCode::BadCommand, 0, 0, None);
    }

    /// Executes a newly read command (the caller guarantees `cid > last_cid`).
    pub(crate) fn accept(
        &mut self,
        cid: Cid,
        command: Command,
        now: Instant,
        program: Option<LoadedProgram>,
    ) -> Changes {
        self.last_cid = cid;
        tracing::debug!(cid, op = command.name(), "command accepted");
        if self.error.is_some() && !matches!(command, Command::Stop | Command::Reset) {
            self.push_result(cid, ResultCode::ControllerError, 0, 0, None);
            return Changes::results();
        }
        if let Command::Append(chunk) = command {
            return self.append(cid, chunk, now);
        }
        if self.is_busy() && !matches!(command, Command::Stop) {
            self.push_result(cid, ResultCode::Busy, 0, 0, None);
            return Changes::results();
        }
        match command {
            Command::Append(_) => {}
            Command::OpenPath(chunk) => {
                let mut run = PathRun::new(cid, self.axes);
                let take = whole_blocks(&chunk.motions, crate::path::STREAM_CAPACITY as usize);
                run.append(
                    &self.model,
                    &self.tool,
                    &self.base,
                    &self.plan,
                    &chunk.motions[..take],
                );
                run.closed = chunk.close && take == chunk.motions.len();
                self.path = Some((run, now, now));
                // Answered when the path ends.
                return Changes::default();
            }
            Command::Stop => {
                self.brake_all(ResultCode::Cancelled);
                self.push_result(cid, ResultCode::Ok, 0, 0, None);
            }
            Command::Reset => {
                // A stop message RESET cannot acknowledge leaves the
                // controller NOT_READY (as the KRL program's KsErrWatch).
                self.error = (self.safety.stop_message || !self.safety.drives)
                    .then_some((ResultCode::NotReady, 0));
                self.safety_error = self.error.is_some();
                self.push_result(cid, ResultCode::Ok, 0, 0, None);
            }
            Command::GetPosition => self.push_result(cid, ResultCode::Ok, 0, 0, None),
            Command::SetAnalogOutput(a) => {
                // (The decoder checked the ranges.)
                self.analog_outputs[usize::from(a.index)] = a.value;
                self.push_result(cid, ResultCode::Ok, 0, 0, None);
            }
            Command::SetOutput(o) => {
                // (The decoder checked the ranges.)
                self.switch_outputs(vec![(o.index, o.value, o.pulse_ms)], now);
                self.push_result(cid, ResultCode::Ok, 0, 0, None);
            }
            Command::SetTool(f) => {
                self.tool = frame_to_pose(&f);
                self.push_result(cid, ResultCode::Ok, 0, 0, Some(f));
            }
            Command::GetTool => {
                let f = pose_to_frame(&self.tool);
                self.push_result(cid, ResultCode::Ok, 0, 0, Some(f));
            }
            Command::SetBase(f) => {
                self.base = frame_to_pose(&f);
                self.push_result(cid, ResultCode::Ok, 0, 0, Some(f));
            }
            Command::GetBase => {
                let f = pose_to_frame(&self.base);
                self.push_result(cid, ResultCode::Ok, 0, 0, Some(f));
            }
            Command::SetSpeed(s) => {
                let valid = [
                    s.override_pct,
                    s.ptp_velocity_pct,
                    s.ptp_acceleration_pct,
                    s.cp_acceleration_pct,
                ]
                .iter()
                .all(|v| (0.0..=100.0).contains(v) && *v > 0.0)
                    && s.cp_velocity > 0.0;
                if valid {
                    self.speed = s;
                    self.plan.override_pct = s.override_pct;
                    self.push_result(cid, ResultCode::Ok, 0, 0, None);
                } else {
                    self.push_result(cid, ResultCode::BadCommand, 0, 0, None);
                }
            }
            Command::Home => {
                let home = Motion {
                    kind: MotionKind::PtpAxes {
                        axes: self.model.home,
                    },
                    velocity: self.speed.ptp_velocity_pct,
                    acceleration_pct: self.speed.ptp_acceleration_pct,
                    approx_mm: 0.0,
                };
                self.start(cid, vec![home], Actions::default(), now);
            }
            Command::Move(records) => {
                let mut actions = Actions::default();
                actions.extend(&records, 0);
                self.start(cid, to_motions(&records), actions, now);
            }
            Command::Run(n) => {
                let loaded = program.unwrap_or_else(|| Err("program not loaded".into()));
                self.run_program(cid, n, loaded, now);
            }
        }
        Changes::results()
    }

    /// APPEND: stores what fits of the chunk into the open path and answers
    /// at once with the path's stored count.
    fn append(&mut self, cid: Cid, chunk: kuka_protocol::PathChunk, now: Instant) -> Changes {
        let Some((run, _, last)) = self.path.as_mut().filter(|(r, _, _)| r.cid == chunk.path)
        else {
            self.push_result(cid, ResultCode::PathClosed, 0, 0, None);
            return Changes::results();
        };
        if chunk.first > run.stored {
            // A gap: motions between the stored ones and these are missing.
            self.push_result(cid, ResultCode::BadCommand, 0, 0, None);
            return Changes::results();
        }
        if run.closed {
            let stored = run.stored;
            self.push_result(cid, ResultCode::PathClosed, stored, 0, None);
            return Changes::results();
        }
        // Motions already stored (a resend) are skipped: each runs once.
        let skip = (run.stored - chunk.first) as usize;
        let fresh = chunk.motions.get(skip..).unwrap_or(&[]);
        // (Never part of a spline block: the rest is sent again.)
        let take = whole_blocks(fresh, run.room() as usize);
        run.append(
            &self.model,
            &self.tool,
            &self.base,
            &self.plan,
            &fresh[..take],
        );
        if chunk.close && take == fresh.len() {
            run.closed = true;
        }
        *last = now;
        let stored = run.stored;
        self.push_result(cid, ResultCode::Ok, stored, 0, None);
        Changes::results()
    }

    /// Plays the open path up to `now`; answers it when it ends.
    fn advance_path(&mut self, now: Instant, time_scale: f64) -> Changes {
        let Some((run, wall, last)) = self.path.as_mut() else {
            return Changes::default();
        };
        // Idle: nothing appended for PATH_IDLE while the robot has run out
        // of motions (an instant controller holds the last ones for more to
        // come): the path is closed; the robot finishes what was stored.
        let stalled = run.waiting || time_scale <= 0.0;
        if stalled && !run.closed && now.saturating_duration_since(*last) >= PATH_IDLE {
            tracing::warn!(
                cid = run.cid,
                "path idle: no motions appended; it ends after the stored ones"
            );
            run.closed = true;
        }
        let until = if time_scale <= 0.0 {
            run.hold_t()
        } else {
            now.saturating_duration_since(*wall).as_secs_f64() * time_scale
        };
        let (played, switched) = run.play(until, &self.inputs);
        let waiting = run.waiting;
        let n = played.len();
        let cid = run.cid;
        for (k, s) in played.into_iter().enumerate() {
            self.axes = s.axes;
            if self.trace_capacity > 0 {
                if self.trace.len() >= self.trace_capacity {
                    self.trace.pop_front();
                }
                self.trace.push_back(TraceSample {
                    t: self.sim_time + s.t,
                    cid,
                    motion: s.motion,
                    pose: s.pose.to_array(),
                    axes: s.axes,
                    stop: waiting && k + 1 == n,
                });
            }
        }
        if waiting {
            self.axes = run.end_axes();
        }
        let ended = run.ended();
        self.switch_outputs(switched, now);
        let Some(end) = ended else {
            return Changes::default();
        };
        let Some((run, _, _)) = self.path.take() else {
            return Changes::default();
        };
        self.sim_time += run.t;
        match end {
            PathEnd::Done => self.push_result(run.cid, ResultCode::Ok, run.stored, 0, None),
            PathEnd::TimedOut(w) => {
                tracing::info!(cid, motion = w, "input did not come in time");
                self.push_result(run.cid, ResultCode::InputTimeout, w as u32, 0, None);
            }
            PathEnd::Failed(k, err) => {
                let (code, axis) = motion_error_code(&err);
                tracing::info!(cid, motion = k, %err, "path motion failed");
                self.push_result(run.cid, code, k as u32, axis, None);
            }
        }
        Changes::results()
    }

    /// RUN: parses the uploaded module, runs it through the interpreter
    /// and plays the result phase by phase. Errors are answered with the
    /// failing source line in `done`.
    fn run_program(&mut self, cid: Cid, n: i32, loaded: LoadedProgram, _now: Instant) {
        // Parsing and running a program ahead can take a while (up to the
        // interpreter's limits): it happens on a thread of its own, so the
        // heartbeat goes on and STOP is answered meanwhile. The controller
        // is busy with the command until the steps are there.
        let (tx, rx) = std::sync::mpsc::channel();
        let model = self.model.clone();
        let (axes, tool, base, speed) = (self.axes, self.tool, self.base, self.speed);
        let spawned = std::thread::Builder::new()
            .name(format!("kuka-sim-kbu{n}"))
            .stack_size(kuka_krl_runtime::program::DRY_RUN_STACK_BYTES)
            .spawn(move || {
                let _ = tx.send(prepare(n, loaded, &model, axes, tool, base, speed));
            });
        match spawned {
            Ok(_) => self.preparing = Some(Preparing { cid, rx }),
            Err(e) => {
                tracing::error!(cid, error = %e, "cannot start the program thread");
                self.push_result(cid, ResultCode::RuntimeError, 0, 0, None);
            }
        }
    }

    /// Takes the prepared program's steps, if ready: starts its first
    /// phase, or answers its error.
    fn poll_preparing(&mut self, now: Instant) -> Changes {
        let Some(p) = &self.preparing else {
            return Changes::default();
        };
        let cid = p.cid;
        let outcome = match p.rx.try_recv() {
            Ok(o) => o,
            Err(std::sync::mpsc::TryRecvError::Empty) => return Changes::default(),
            Err(std::sync::mpsc::TryRecvError::Disconnected) => Err((ResultCode::RuntimeError, 0)),
        };
        self.preparing = None;
        match outcome {
            Err((code, line)) => self.push_result(cid, code, line, 0, None),
            Ok(steps) => {
                let mut rest = phases(steps);
                match rest.pop_front() {
                    None => self.push_result(cid, ResultCode::Ok, 0, 0, None),
                    Some(first) => {
                        let run = ProgramRun {
                            lines: Vec::new(),
                            rest,
                            steps_before: 0,
                        };
                        self.start_phase(cid, first, run, now);
                        if self.active.is_some() {
                            return Changes::default();
                        }
                    }
                }
            }
        }
        Changes::results()
    }

    /// Starts one phase of a program run (or answers its pre-check error).
    fn start_phase(&mut self, cid: Cid, phase: Phase, mut run: ProgramRun, now: Instant) {
        let (execution, count) = match phase {
            Phase::Moves {
                tool,
                base,
                motions,
                lines,
            } => {
                self.tool = tool;
                self.base = base;
                let e = kuka_kinematics::plan::plan(
                    &self.model,
                    &self.axes,
                    &self.tool,
                    &self.base,
                    &motions,
                    &self.plan,
                );
                run.lines = lines;
                (e, motions.len())
            }
            Phase::Dwell { seconds, line } => {
                let pose = self.model.forward(&self.axes, &self.tool, &self.base);
                let sample = |t| kuka_kinematics::plan::Sample {
                    t,
                    motion: 0,
                    axes: self.axes,
                    pose,
                };
                run.lines = vec![line];
                let e = Execution {
                    samples: vec![sample(0.0), sample(seconds)],
                    end_axes: self.axes,
                    duration_s: seconds,
                    error: None,
                    junctions: Vec::new(),
                };
                (e, 1)
            }
        };
        if let Some((index, err)) = &execution.error
            && execution.samples.len() <= 1
            && *index == 0
        {
            let (code, axis) = motion_error_code(err);
            let line = run.lines.first().copied().unwrap_or(0);
            tracing::info!(cid, line, %err, "program motion rejected");
            self.push_result(cid, code, line, axis, None);
            return;
        }
        self.active = Some(Active {
            cid,
            execution,
            motions: count,
            started_wall: now,
            next_sample: 0,
            current_motion: 0,
            program: Some(run),
            actions: Actions::default(),
            timed_out: None,
        });
    }

    fn start(&mut self, cid: Cid, motions: Vec<Motion>, actions: Actions, now: Instant) {
        let execution = kuka_kinematics::plan::plan(
            &self.model,
            &self.axes,
            &self.tool,
            &self.base,
            &motions,
            &self.plan,
        );
        if let Some((index, err)) = &execution.error
            && execution.samples.len() <= 1
            && *index == 0
        {
            // Rejected before moving (the KRL program's INVERSE pre-check).
            let (code, axis) = motion_error_code(err);
            tracing::info!(cid, %err, "motion rejected");
            self.push_result(cid, code, 0, axis, None);
            return;
        }
        self.active = Some(Active {
            cid,
            execution,
            motions: motions.len(),
            started_wall: now,
            next_sample: 0,
            current_motion: 0,
            program: None,
            actions,
            timed_out: None,
        });
    }

    /// Plays the active batch (and, for a program, the phases after it)
    /// up to `now`; returns what changed.
    pub(crate) fn advance(&mut self, now: Instant, time_scale: f64) -> Changes {
        self.end_pulse(now);
        if std::mem::take(&mut self.results_pending) {
            return Changes::results();
        }
        if self.path.is_some() {
            return self.advance_path(now, time_scale);
        }
        if self.preparing.is_some() {
            let c = self.poll_preparing(now);
            if self.active.is_none() {
                return c;
            }
        }
        loop {
            match self.advance_phase(now, time_scale) {
                Advanced::Changes(c) => return c,
                Advanced::NextPhase => {}
            }
        }
    }

    fn advance_phase(&mut self, now: Instant, time_scale: f64) -> Advanced {
        let Some(active) = self.active.as_mut() else {
            return Advanced::Changes(Changes::default());
        };
        let elapsed = if time_scale <= 0.0 {
            f64::INFINITY
        } else {
            now.saturating_duration_since(active.started_wall)
                .as_secs_f64()
                * time_scale
        };
        let mut switched = Vec::new();
        // Inside a wait (its start played, its end ahead) whose input has
        // come since the last look: the robot leaves now.
        if let Some(prev) = active
            .next_sample
            .checked_sub(1)
            .and_then(|k| active.execution.samples.get(k))
            .copied()
            && let Some(&next) = active.execution.samples.get(active.next_sample)
            && next.motion == prev.motion
            && let Some((index, value)) = active.actions.wait(prev.motion)
            && self.inputs[usize::from(index)] == value
        {
            let e = &mut active.execution;
            let leave = elapsed.min(next.t).max(prev.t);
            let dt = next.t - leave;
            e.samples.remove(active.next_sample);
            for x in &mut e.samples[active.next_sample..] {
                x.t -= dt;
            }
            for j in e.junctions.iter_mut().filter(|j| j.t > prev.t) {
                j.t -= dt;
            }
            e.duration_s -= dt;
        }
        while let Some(&s) = active.execution.samples.get(active.next_sample) {
            if s.t > elapsed {
                break;
            }
            let last = active.execution.samples.len().saturating_sub(1);
            let stop = active.next_sample == last;
            self.axes = s.axes;
            active.current_motion = s.motion;
            active.next_sample += 1;
            let ahead = active.execution.samples[active.next_sample..].iter();
            switched.extend(active.actions.passed(&s, ahead));
            if self.trace_capacity > 0 {
                if self.trace.len() >= self.trace_capacity {
                    self.trace.pop_front();
                }
                self.trace.push_back(TraceSample {
                    t: self.sim_time + s.t,
                    cid: active.cid,
                    motion: s.motion,
                    pose: s.pose.to_array(),
                    axes: s.axes,
                    stop,
                });
            }
            if let Some((index, value)) = active.actions.wait(s.motion) {
                let e = &mut active.execution;
                let rest: Vec<_> = e.samples[active.next_sample..]
                    .iter()
                    .take_while(|x| x.motion == s.motion)
                    .collect();
                let ok = self.inputs[usize::from(index)] == value;
                match decide(&s, &rest, ok) {
                    Wait::Goes => {}
                    Wait::Came(dt) => {
                        let n = rest.len();
                        e.samples.drain(active.next_sample..active.next_sample + n);
                        let later = &mut e.samples[active.next_sample..];
                        run_earlier(later, &mut e.junctions, s.t, dt);
                        e.duration_s -= dt;
                    }
                    Wait::TimedOut => {
                        e.samples.truncate(active.next_sample);
                        e.duration_s = s.t;
                        e.end_axes = s.axes;
                        e.error = None;
                        active.timed_out = Some(s.motion);
                    }
                }
            }
        }
        if !switched.is_empty() {
            self.switch_outputs(switched, now);
        }
        let Some(active) = self.active.as_mut() else {
            return Advanced::Changes(Changes::default());
        };
        if active.next_sample < active.execution.samples.len() {
            return Advanced::Changes(Changes::default());
        }
        // Batch finished (or stopped at an error point).
        let Some(active) = self.active.take() else {
            return Advanced::Changes(Changes::default());
        };
        // When the phase ended on the wall clock: the next one starts there.
        let ended = if time_scale > 0.0 {
            active.started_wall
                + std::time::Duration::from_secs_f64(active.execution.duration_s / time_scale)
        } else {
            now
        };
        self.axes = active.execution.end_axes;
        self.sim_time += active.execution.duration_s;
        let Active {
            cid,
            execution,
            motions,
            program,
            mut actions,
            timed_out,
            ..
        } = active;
        if let Some(w) = timed_out {
            tracing::info!(cid, motion = w, "input did not come in time");
            self.push_result(cid, ResultCode::InputTimeout, w as u32, 0, None);
            return Advanced::Changes(Changes::results());
        }
        match (&execution.error, program) {
            (None, None) => {
                // Outputs after the last motion: switched once it has ended.
                let left = actions.all_left();
                self.switch_outputs(left, now);
                self.push_result(cid, ResultCode::Ok, motions as u32, 0, None)
            }
            (None, Some(mut run)) => {
                run.steps_before += motions;
                match run.rest.pop_front() {
                    None => self.push_result(cid, ResultCode::Ok, run.steps_before as u32, 0, None),
                    Some(next) => {
                        self.start_phase(cid, next, run, ended.min(now));
                        if self.active.is_some() {
                            // The next phase runs on; nothing to report yet.
                            return Advanced::NextPhase;
                        }
                    }
                }
            }
            (Some((index, err)), program) => {
                let (code, axis) = motion_error_code(err);
                let done = match &program {
                    Some(run) => run.lines.get(*index).copied().unwrap_or(0),
                    None => *index as u32,
                };
                tracing::info!(cid, motion = index, done, %err, "motion stopped");
                self.push_result(cid, code, done, axis, None);
            }
        }
        Advanced::Changes(Changes::results())
    }

    /// What the service must learn at once rather than at the next
    /// heartbeat: idle/busy/error and the command being executed.
    pub(crate) fn status_key(&self) -> (Cid, bool, IoState, SafetyCircuit) {
        let cid = match (&self.active, &self.preparing, &self.path) {
            (Some(a), _, _) => a.cid,
            (None, Some(p), _) => p.cid,
            (None, None, Some((r, _, _))) => r.cid,
            (None, None, None) => 0,
        };
        (cid, self.error.is_some(), self.io_state(), self.safety)
    }

    /// The heartbeat record (increments the sequence number).
    pub(crate) fn state_record(&mut self) -> StateFile {
        self.seq = self.seq.checked_add(1).unwrap_or(1);
        let (pose, s, t) = self.position();
        let (status, busy_cid, busy_index) = match (&self.active, &self.error, &self.path) {
            (_, Some(_), _) => (ControllerStatus::Error, 0, 0),
            (_, None, Some((r, _, _))) => (ControllerStatus::Busy, r.cid, r.current as u32),
            (Some(a), None, None) => (ControllerStatus::Busy, a.cid, a.progress() as u32),
            (None, None, None) => match &self.preparing {
                Some(p) => (ControllerStatus::Busy, p.cid, 0),
                None => (ControllerStatus::Idle, 0, 0),
            },
        };
        let (room, stored) = match &self.path {
            Some((r, _, _)) => (r.room(), r.stored),
            None => (crate::path::STREAM_CAPACITY, 0),
        };
        StateFile {
            seq: self.seq,
            status,
            mode: self.mode,
            busy_cid,
            busy_index,
            last_cid: self.last_cid,
            error: self.error.map(|e| e.0),
            error_axis: self.error.map_or(0, |e| e.1),
            override_pct: self.plan.override_pct,
            simulated: true,
            room,
            stored,
            position: pose_to_frame(&pose),
            s,
            t,
            axes: self.axes,
            tool: pose_to_frame(&self.tool),
            base: pose_to_frame(&self.base),
            io: Some(self.io_state()),
            analog: Some(self.analog_state()),
            // The safety circuit ([`Controller::set_safety`]); an error is
            // a stop message too, and the robot program stops meanwhile.
            safety: Some(kuka_protocol::SafetyState {
                drives_ready: self.safety.drives,
                user_safety: self.safety.user_safety,
                alarm_stop: self.safety.alarm_stop,
                stop_message: self.safety.stop_message || self.error_is_message(),
                program_state: if self.safety.stop_message || self.error_is_message() {
                    3
                } else {
                    2
                },
            }),
        }
    }
}

//! The engine's public vocabulary: operations, jobs, robot state and
//! events, as the API serialises them.

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::error::BridgeError;
use crate::motion::{MotionRequest, SpeedSettings};

pub use crate::clock::{JobId, now_ms};

/// A Cartesian frame in mm and degrees (A, B, C about Z, Y, X).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"x": 0.0, "y": 0.0, "z": 100.0, "a": 0.0, "b": 0.0, "c": 0.0}))]
pub struct CartesianFrame {
    /// X in mm.
    pub x: f64,
    /// Y in mm.
    pub y: f64,
    /// Z in mm.
    pub z: f64,
    /// A (about Z) in degrees.
    pub a: f64,
    /// B (about Y) in degrees.
    pub b: f64,
    /// C (about X) in degrees.
    pub c: f64,
}

/// To the protocol's resolution (thousandths, PROTOCOL.md 12), without a
/// negative zero: a pose the service computed (the planned end of an
/// append) reads like one the controller reported, not `200.00000000000003`.
fn thousandths(v: f64) -> f64 {
    let r = (v * 1000.0).round() / 1000.0;
    if r == 0.0 { 0.0 } else { r }
}

impl From<kuka_protocol::Frame> for CartesianFrame {
    fn from(f: kuka_protocol::Frame) -> Self {
        CartesianFrame {
            x: thousandths(f.x),
            y: thousandths(f.y),
            z: thousandths(f.z),
            a: thousandths(f.a),
            b: thousandths(f.b),
            c: thousandths(f.c),
        }
    }
}

impl From<CartesianFrame> for kuka_protocol::Frame {
    fn from(f: CartesianFrame) -> Self {
        kuka_protocol::Frame {
            x: f.x,
            y: f.y,
            z: f.z,
            a: f.a,
            b: f.b,
            c: f.c,
        }
    }
}

/// TCP position in the base frame with Status and Turn (a KUKA E6POS without external axes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, ToSchema)]
#[schema(example = json!({"x": 200.0, "y": 0.0, "z": 70.0, "a": 0.0, "b": 180.0, "c": 0.0, "s": 2, "t": 2}))]
pub struct Position {
    /// X in mm.
    pub x: f64,
    /// Y in mm.
    pub y: f64,
    /// Z in mm.
    pub z: f64,
    /// A in degrees.
    pub a: f64,
    /// B in degrees.
    pub b: f64,
    /// C in degrees.
    pub c: f64,
    /// Status bits.
    pub s: u8,
    /// Turn bits.
    pub t: u8,
}

impl Position {
    /// From a protocol frame plus S/T.
    pub fn new(f: &kuka_protocol::Frame, s: u8, t: u8) -> Self {
        Position {
            x: f.x,
            y: f.y,
            z: f.z,
            a: f.a,
            b: f.b,
            c: f.c,
            s,
            t,
        }
    }

    /// `[x, y, z, a, b, c]` (the thesis's response format).
    pub fn xyzabc(&self) -> [f64; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }
}

/// Axis angles A1..A6 in degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, ToSchema)]
#[schema(example = json!({"a1": 0.0, "a2": -90.0, "a3": 90.0, "a4": 0.0, "a5": 0.0, "a6": 0.0}))]
pub struct AxisAngles {
    /// A1.
    pub a1: f64,
    /// A2.
    pub a2: f64,
    /// A3.
    pub a3: f64,
    /// A4.
    pub a4: f64,
    /// A5.
    pub a5: f64,
    /// A6.
    pub a6: f64,
}

impl From<[f64; 6]> for AxisAngles {
    fn from(a: [f64; 6]) -> Self {
        AxisAngles {
            a1: a[0],
            a2: a[1],
            a3: a[2],
            a4: a[3],
            a5: a[4],
            a6: a[5],
        }
    }
}

/// What a job asks the controller to do.
#[derive(Debug, Clone, PartialEq)]
pub enum Operation {
    /// Motions as one continuous batch.
    Move(Vec<MotionRequest>),
    /// Read the position through the controller program.
    GetPosition,
    /// PTP to home.
    Home,
    /// Set the tool frame.
    SetTool(CartesianFrame),
    /// Read the tool frame.
    GetTool,
    /// Set the base frame.
    SetBase(CartesianFrame),
    /// Read the base frame.
    GetBase,
    /// Set override and default speeds.
    SetSpeed(SpeedSettings),
    /// Acknowledge a controller error state.
    Reset,
    /// Run an uploaded KRL program (written as a fresh module first).
    RunProgram(std::sync::Arc<crate::programs::StoredProgram>),
    /// Open a path (a motion stream): motions are appended while it runs
    /// ([`crate::engine::Engine::append`]).
    Path(PathOptions),
    /// Set a digital output (only one on the site's allow-list).
    SetOutput(crate::io::OutputRequest),
    /// Set an analog output (only one on the site's allow-list).
    SetAnalogOutput(crate::io::AnalogOutputRequest),
}

/// How an open path treats the motions appended to it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PathOptions {
    /// How PTPs without `s` get their arm configuration (default: the
    /// site's `motion.configuration`).
    pub config: Option<crate::settings::Configuration>,
}

/// A path's progress, in its job record.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, ToSchema)]
#[schema(example = json!({"appended": 120, "sent": 80, "closed": false}))]
pub struct PathProgress {
    /// Motions appended by clients (checked and accepted).
    pub appended: usize,
    /// Motions the controller has stored (the rest wait in the service).
    pub sent: usize,
    /// The path was closed: it ends when its last motion has run.
    pub closed: bool,
}

/// The answer to an append.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, ToSchema)]
#[schema(example = json!({"path": 12, "first": 40, "appended": 20, "total": 60, "closed": false,
    "end": {"x": 200.0, "y": 40.0, "z": 100.0, "a": 0.0, "b": 180.0, "c": 0.0}}))]
pub struct AppendOutcome {
    /// The path (its job id).
    pub path: JobId,
    /// Path-wide index of the first motion of this append.
    pub first: usize,
    /// Motions appended by this request.
    pub appended: usize,
    /// Motions appended to the path so far.
    pub total: usize,
    /// The path is closed now.
    pub closed: bool,
    /// Where the path ends after this append (TCP in the base frame).
    pub end: CartesianFrame,
}

impl Operation {
    /// Lowercase name used in jobs and logs.
    pub fn name(&self) -> &'static str {
        match self {
            Operation::Move(_) => "move",
            Operation::GetPosition => "get_position",
            Operation::Home => "home",
            Operation::SetTool(_) => "set_tool",
            Operation::GetTool => "get_tool",
            Operation::SetBase(_) => "set_base",
            Operation::GetBase => "get_base",
            Operation::SetSpeed(_) => "set_speed",
            Operation::Reset => "reset",
            Operation::RunProgram(_) => "run_program",
            Operation::Path(_) => "path",
            Operation::SetOutput(_) => "set_output",
            Operation::SetAnalogOutput(_) => "set_analog_output",
        }
    }
}

/// Life of a job: queued → sent → executing → done | failed | cancelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum JobState {
    /// Waiting for the controller.
    Queued,
    /// Written to the command file.
    Sent,
    /// The controller is executing it.
    Executing,
    /// Finished successfully.
    Done,
    /// Finished with an error (see `error`).
    Failed,
    /// Cancelled by stop or cancel.
    Cancelled,
}

impl JobState {
    /// The state as it appears in JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            JobState::Queued => "queued",
            JobState::Sent => "sent",
            JobState::Executing => "executing",
            JobState::Done => "done",
            JobState::Failed => "failed",
            JobState::Cancelled => "cancelled",
        }
    }

    /// Done, failed or cancelled.
    pub fn is_terminal(self) -> bool {
        matches!(
            self,
            JobState::Done | JobState::Failed | JobState::Cancelled
        )
    }
}

/// A job as clients see it.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
#[schema(example = json!({
    "id": 7, "operation": "move", "state": "done", "motions": 2, "completed": 2, "cid": 1042,
    "created_ms": 1795373060215_u64, "sent_ms": 1795373060221_u64, "finished_ms": 1795373060931_u64,
    "position": {"x": 250.0, "y": 100.0, "z": 70.0, "a": 180.0, "b": 0.0, "c": 180.0, "s": 6, "t": 51},
    "axes": {"a1": -21.801, "a2": -13.511, "a3": 108.689, "a4": 0.0, "a5": -5.178, "a6": -21.801},
    "frame": null, "error": null
}))]
pub struct Job {
    /// Job id.
    pub id: JobId,
    /// Operation name (`move`, `home`, `get_position`, ...).
    pub operation: String,
    /// Current state.
    pub state: JobState,
    /// Number of motions (for `move`).
    pub motions: usize,
    /// Motions completed so far.
    pub completed: usize,
    /// Command id used on the channel, once sent.
    pub cid: Option<i32>,
    /// Creation time (Unix ms).
    pub created_ms: u64,
    /// When written to the channel (Unix ms).
    pub sent_ms: Option<u64>,
    /// When finished (Unix ms).
    pub finished_ms: Option<u64>,
    /// Position at the end (for motions and position reads).
    pub position: Option<Position>,
    /// Axis angles at the end.
    pub axes: Option<AxisAngles>,
    /// Tool or base frame (for the frame operations).
    pub frame: Option<CartesianFrame>,
    /// Why it failed or was cancelled.
    pub error: Option<BridgeError>,
    /// Who asked for it when not an HTTP client directly: `plugin:<name>@<version>`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub origin: Option<String>,
    /// The token name of the client whose request created it (`anonymous`
    /// when auth is off).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub requested_by: Option<String>,
    /// True when the controller's result came after the job had already
    /// ended (reported `timeout` while the result file was unreadable, for
    /// example): `state`, `error` and `completed` are then the controller's
    /// own outcome, which replaced the earlier one.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub late_result: bool,
    /// The arm configuration each Cartesian PTP of a move got (with a
    /// robot model): send these `s`/`t` to replay it exactly.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub configurations: Vec<PtpConfiguration>,
    /// For a path: how many motions were appended and sent, and whether it
    /// is closed. `motions` counts the appended ones, `completed` the ones
    /// the robot has finished (at the controller's heartbeat rate).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path: Option<PathProgress>,
}

/// The arm configuration (Status and Turn) one Cartesian PTP got.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[schema(example = json!({"motion": 0, "s": 6, "t": 27, "chosen": "auto"}))]
pub struct PtpConfiguration {
    /// 0-based index of the motion in the batch.
    pub motion: usize,
    /// Status.
    pub s: u8,
    /// Turn.
    pub t: u8,
    /// Who chose it.
    pub chosen: ConfigurationSource,
}

/// Who chose a PTP's configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum ConfigurationSource {
    /// The request gave `s` (and `t`).
    Given,
    /// The bridge (`config: auto`).
    Auto,
    /// KUKA's rule (`config: keep`): the current Status.
    Keep,
}

/// Connection to the controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum Connection {
    /// Heartbeat is alive.
    Online,
    /// No heartbeat within `offline_after_ms` (or none seen yet).
    Offline,
    /// Heartbeat alive but the command file is locked by another process.
    Locked,
}

/// What the controller reports about itself.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ControllerInfo {
    /// `idle`, `busy`, `error` or `unknown`.
    pub status: String,
    /// `T1`, `T2`, `AUT`, `EXT` or `unknown`.
    pub mode: String,
    /// The controller's error state, if any.
    pub error: Option<BridgeError>,
    /// True when the controller is the simulator.
    pub simulated: bool,
    /// Program override in %.
    pub override_pct: f64,
    /// Last heartbeat sequence number.
    pub heartbeat_seq: Option<i32>,
    /// Milliseconds since the heartbeat last changed.
    pub heartbeat_age_ms: Option<u64>,
    /// Highest command id the controller has accepted.
    pub last_cid: Option<i32>,
    /// What a teach pendant shows of safety and program state, as the
    /// controller program reports it (none from a program without it).
    pub safety: Option<ControllerSafety>,
}

/// The controller's safety and program state (the KRL system variables
/// `$PERI_RDY`, `$USER_SAF`, `$ALARM_STOP`, `$STOPMESS`, `$PRO_STATE1`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, ToSchema)]
pub struct ControllerSafety {
    /// `$PERI_RDY`: the drives are switched on.
    pub drives_ready: bool,
    /// `$USER_SAF`: the operator safety (fence, enabling device) is closed.
    pub user_safety: bool,
    /// An emergency stop is pressed (`$ALARM_STOP` FALSE).
    pub emergency_stop: bool,
    /// `$STOPMESS`: a stop message waits for acknowledgement.
    pub stop_message: bool,
    /// The robot program (`$PRO_STATE1`): `free`, `reset`, `active`,
    /// `stopped` or `ended`.
    pub program: String,
}

impl From<&kuka_protocol::SafetyState> for ControllerSafety {
    fn from(s: &kuka_protocol::SafetyState) -> Self {
        ControllerSafety {
            drives_ready: s.drives_ready,
            user_safety: s.user_safety,
            emergency_stop: !s.alarm_stop,
            stop_message: s.stop_message,
            program: ["free", "reset", "active", "stopped", "ended"]
                [usize::from(s.program_state.min(4))]
            .into(),
        }
    }
}

/// The robot's state as the service knows it.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
#[schema(example = json!({
    "connection": "online",
    "controller": {"status": "idle", "mode": "EXT", "error": null, "simulated": true, "override_pct": 100.0,
                   "heartbeat_seq": 184, "heartbeat_age_ms": 28, "last_cid": 3},
    "busy": false, "current_job": null, "queue_length": 0,
    "position": {"x": 355.0, "y": 0.0, "z": 625.0, "a": 0.0, "b": 90.0, "c": 0.0, "s": 2, "t": 2},
    "axes": {"a1": 0.0, "a2": -90.0, "a3": 90.0, "a4": 0.0, "a5": 0.0, "a6": 0.0},
    "tool": {"x": 0.0, "y": 0.0, "z": 0.0, "a": 0.0, "b": 0.0, "c": 0.0},
    "base": {"x": 0.0, "y": 0.0, "z": 0.0, "a": 0.0, "b": 0.0, "c": 0.0},
    "speed": {"override_pct": 100.0, "ptp_velocity_pct": 20.0, "ptp_acceleration_pct": 100.0,
              "cp_velocity_m_s": 0.25, "cp_acceleration_pct": 100.0},
    "model": "kr3_r540", "degraded": []
}))]
pub struct RobotState {
    /// Connection to the controller.
    pub connection: Connection,
    /// Controller details.
    pub controller: ControllerInfo,
    /// A job is on the controller.
    pub busy: bool,
    /// The job on the controller.
    pub current_job: Option<JobId>,
    /// Jobs waiting.
    pub queue_length: usize,
    /// TCP position (base frame) with Status/Turn.
    pub position: Option<Position>,
    /// Axis angles.
    pub axes: Option<AxisAngles>,
    /// When the service read the file that carried `position` and `axes`
    /// (the state file's heartbeat or a result); not serialised.
    #[serde(skip)]
    pub position_read_at: Option<std::time::Instant>,
    /// Tool frame ($TOOL).
    pub tool: Option<CartesianFrame>,
    /// Base frame ($BASE).
    pub base: Option<CartesianFrame>,
    /// Default speeds and override.
    pub speed: SpeedSettings,
    /// Robot model used for checks (None: checks off).
    pub model: Option<String>,
    /// Why commands cannot be sent now; empty when they can. Each entry has
    /// a stable `code` (`controller_offline`, `channel_locked`,
    /// `storage_unavailable`, `controller_error`, `protocol_error`,
    /// `shutting_down`) and a sentence. `/health` says `degraded` while
    /// this is not empty.
    pub degraded: Vec<BridgeError>,
    /// Digital I/O as the controller last reported it (31 inputs and
    /// outputs from `base`); none from a controller program without it.
    pub io: Option<crate::io::IoWindow>,
    /// Analog I/O as the controller last reported it (`$ANIN`/`$ANOUT[1..8]`,
    /// normalised −1..1); none from a controller program without it.
    pub analog: Option<crate::io::AnalogWindow>,
}

/// The robot's position as the controller last reported it while moving.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LivePosition {
    /// TCP in the base frame with Status/Turn.
    pub position: Position,
    /// Axis angles.
    pub axes: Option<AxisAngles>,
    /// Time since the service read the file that carried it.
    pub age: std::time::Duration,
}

/// A push event (Server-Sent Events on `/api/v1/events`).
#[derive(Debug, Clone, Serialize, ToSchema)]
#[serde(tag = "type", content = "data", rename_all = "snake_case")]
pub enum Event {
    /// A job changed state or progressed.
    Job(Box<Job>),
    /// The robot state changed (at most at the heartbeat rate).
    State(Box<RobotState>),
    /// Something went wrong outside a job (channel locked, controller offline...).
    Alarm(BridgeError),
    /// A move job's motions as written to the controller (the planned path).
    Plan(Box<JobPlan>),
    /// A watched digital input or output changed (`[io]` entries with
    /// `watch = true`), as the controller's state file reported it.
    Io(crate::io::IoChange),
    /// A watched analog channel (`[io] analog_*` entries with
    /// `watch = true`) moved by its deadband.
    Analog(crate::io::AnalogChange),
}

/// The motions of a move job as written to the controller, with omitted
/// and relative coordinates resolved: what the robot is about to do.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
#[schema(example = json!({"job": 7, "cid": 1042, "motions": [
    {"type": "lin", "target": [200.0, 0.0, 70.0, 0.0, 180.0, 0.0]},
    {"type": "circ", "aux": [250.0, 50.0, 70.0], "target": [200.0, 100.0, 70.0, 0.0, 180.0, 0.0]}
]}))]
pub struct JobPlan {
    /// The job.
    pub job: JobId,
    /// Command id on the channel.
    pub cid: i32,
    /// The motions in order.
    pub motions: Vec<PlannedMotion>,
    /// For a path: the index in the path of the first of these motions (a
    /// path publishes one plan per append, from where the last one ended);
    /// 0 for a batch.
    pub first: usize,
}

/// One motion of a [`JobPlan`].
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PlannedMotion {
    /// `ptp`, `ptp_axes`, `lin`, `circ`, `slin`, `scirc`, `sptp`,
    /// `sptp_axes`, `spl`,
    /// or an action (`set_output`, `wait_input`, `dwell`: no target).
    #[serde(rename = "type")]
    pub kind: String,
    /// Target TCP pose in the base frame `[x, y, z, a, b, c]` (not for `ptp_axes`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target: Option<[f64; 6]>,
    /// Auxiliary point `[x, y, z]` of a `circ` or `scirc`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aux: Option<[f64; 3]>,
    /// Target axis angles A1..A6 of a `ptp_axes` or `sptp_axes`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axes: Option<[f64; 6]>,
    /// Of an `spl`: the points of its spline block from this one to the
    /// block's end (1 = the last point).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub left: Option<u8>,
}

impl From<&kuka_protocol::MotionRecord> for PlannedMotion {
    fn from(m: &kuka_protocol::MotionRecord) -> Self {
        use kuka_protocol::MotionRecord as M;
        let (kind, target, aux, axes) = match m {
            M::Ptp { target, .. } => ("ptp", Some(target.to_array()), None, None),
            M::PtpAxes { axes, .. } => ("ptp_axes", None, None, Some(*axes)),
            M::SptpAxes { axes, .. } => ("sptp_axes", None, None, Some(*axes)),
            M::Lin { target, .. } => ("lin", Some(target.to_array()), None, None),
            M::Circ { aux, target, .. } => ("circ", Some(target.to_array()), Some(*aux), None),
            M::Slin { target, .. } => ("slin", Some(target.to_array()), None, None),
            M::Scirc { aux, target, .. } => ("scirc", Some(target.to_array()), Some(*aux), None),
            M::Sptp { target, .. } => ("sptp", Some(target.to_array()), None, None),
            M::Spl { target, .. } => ("spl", Some(target.to_array()), None, None),
            M::SetOutput { .. } => ("set_output", None, None, None),
            M::WaitInput { .. } => ("wait_input", None, None, None),
            M::Dwell { .. } => ("dwell", None, None, None),
        };
        let left = match m {
            M::Spl { left, .. } => Some(*left),
            _ => None,
        };
        PlannedMotion {
            kind: kind.into(),
            target,
            aux,
            axes,
            left,
        }
    }
}

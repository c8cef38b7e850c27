//! The records of the three channel files and their encode/decode.

use crate::codec::{DecodeError, EncodeError, Field, Reader, real, write_line};
use crate::{MAX_BATCH, PROTOCOL_VERSION, RESULT_HISTORY};

/// A KUKA FRAME on the wire: mm and degrees (A, B, C about Z, Y, X).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Frame {
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
}

impl Frame {
    /// Builds a frame from `[x, y, z, a, b, c]`.
    pub fn from_array(v: [f64; 6]) -> Self {
        Frame {
            x: v[0],
            y: v[1],
            z: v[2],
            a: v[3],
            b: v[4],
            c: v[5],
        }
    }

    /// `[x, y, z, a, b, c]`.
    pub fn to_array(&self) -> [f64; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }

    fn fields(&self, out: &mut Vec<Field>) -> Result<(), EncodeError> {
        for (name, v) in ["x", "y", "z", "a", "b", "c"]
            .into_iter()
            .zip(self.to_array())
        {
            out.push(real(name, v)?);
        }
        Ok(())
    }

    fn read(line: &mut crate::codec::Line) -> Self {
        Frame {
            x: line.real(),
            y: line.real(),
            z: line.real(),
            a: line.real(),
            b: line.real(),
            c: line.real(),
        }
    }
}

/// Command id: a positive 31-bit integer, strictly increasing.
pub type Cid = i32;

/// One motion of a batch. Speeds: PTP in % of the maximum axis speed,
/// LIN/CIRC in m/s ($VEL.CP); acceleration in %; approximation in mm (C_DIS,
/// 0 = exact stop).
#[derive(Debug, Clone, PartialEq)]
pub enum MotionRecord {
    /// `PTP i x y z a b c s t vel acc apo K` — Cartesian PTP; `s`/`t` = -1 when not set.
    Ptp {
        /// Target TCP pose in the base frame.
        target: Frame,
        /// Status, if set.
        s: Option<u8>,
        /// Turn, if set.
        t: Option<u8>,
        /// Motion parameters.
        params: MotionParams,
    },
    /// `PTA i a1 a2 a3 a4 a5 a6 vel acc apo K` — axis-specific PTP (degrees).
    PtpAxes {
        /// Target axis angles.
        axes: [f64; 6],
        /// Motion parameters.
        params: MotionParams,
    },
    /// `LIN i x y z a b c vel acc apo K`.
    Lin {
        /// Target TCP pose in the base frame.
        target: Frame,
        /// Motion parameters.
        params: MotionParams,
    },
    /// `CIR i ax ay az x y z a b c vel acc apo K` — through the auxiliary point's position.
    Circ {
        /// Auxiliary point position (x, y, z in mm).
        aux: [f64; 3],
        /// End point.
        target: Frame,
        /// Motion parameters.
        params: MotionParams,
    },
    /// `SLN i x y z a b c vel acc apo K` — SLIN, a straight line of the
    /// spline family (blends only into spline motions, with C_SPL).
    Slin {
        /// Target TCP pose in the base frame.
        target: Frame,
        /// Motion parameters.
        params: MotionParams,
    },
    /// `SCI i ax ay az x y z a b c vel acc apo K` — SCIRC, a circular arc
    /// of the spline family through the auxiliary point's position.
    Scirc {
        /// Auxiliary point position (x, y, z in mm).
        aux: [f64; 3],
        /// End point.
        target: Frame,
        /// Motion parameters.
        params: MotionParams,
    },
    /// `SPT i x y z a b c s t vel acc apo K` — SPTP to a Cartesian target;
    /// `s`/`t` = -1 when not set. Stops exactly at its end, like PTP.
    Sptp {
        /// Target TCP pose in the base frame.
        target: Frame,
        /// Status, if set.
        s: Option<u8>,
        /// Turn, if set.
        t: Option<u8>,
        /// Motion parameters.
        params: MotionParams,
    },
    /// `SPA i a1 a2 a3 a4 a5 a6 vel acc apo K` — SPTP to axis angles
    /// (degrees; KRL `SPTP` to an E6AXIS, as `SPTP XHOME`). Stops exactly
    /// at its end, like PTP.
    SptpAxes {
        /// Target axis angles.
        axes: [f64; 6],
        /// Motion parameters.
        params: MotionParams,
    },
    /// `SPL i x y z a b c vel acc apo left K` — a point of a KRL `SPLINE`
    /// block: the curve runs through the block's points without stopping.
    /// `left` counts the block's points from this one to its end (1 = the
    /// last point, whose `apo` is the block's C_SPL distance). A block has
    /// 1 to [`MAX_SPLINE_POINTS`] points and is never split between two
    /// commands.
    Spl {
        /// The point (TCP pose in the base frame).
        target: Frame,
        /// Motion parameters (the block's: the same on all its points).
        params: MotionParams,
        /// Points of the block from this one to its end, 1..=8.
        left: u8,
    },
    /// `SOT i index value pulse_ms K` — an I/O action, not a motion: set
    /// `$OUT[index]` when the robot passes this point of the sequence (the
    /// start of the next motion: KRL `TRIGGER WHEN DISTANCE=0` / `PATH=0
    /// ONSTART`; after the last motion, once it has ended). It does not
    /// stop the robot: motions on either side blend as if it were not
    /// there. A pulse returns the output after `pulse_ms` (0 = it stays).
    ///
    /// With `path_mm` it is the record `SOP i index value pulse_ms path K`:
    /// the output switches where the robot is `path` mm along the path
    /// from the end point of the motion before the record (negative:
    /// before that end point; positive: after it, along the next motions),
    /// KRL `TRIGGER WHEN PATH = path DELAY = 0` on that motion.
    SetOutput {
        /// `$OUT` index, 1..=[`MAX_IO_INDEX`].
        index: u16,
        /// The value to set.
        value: bool,
        /// Pulse length in ms, 0..=[`MAX_PULSE_MS`] (0 = no pulse).
        pulse_ms: u32,
        /// Where it switches, in mm along the path from the end point of
        /// the motion before it (`SOP`); `None` = at the start of the next
        /// motion (`SOT`). |path| ≤ [`MAX_TRIGGER_PATH_MM`].
        path_mm: Option<f64>,
    },
    /// `WIN i index value timeout_ms K` — wait until `$IN[index] == value`
    /// (KRL `WAIT FOR` with a timer). The robot stops exactly at the end
    /// of the motion before it (an advance-run stop). Not true within
    /// `timeout_ms` (1..=[`MAX_WAIT_MS`]): the command ends with
    /// INPUT_TIMEOUT (25) and `done` = this record's index.
    WaitInput {
        /// `$IN` index, 1..=[`MAX_IO_INDEX`].
        index: u16,
        /// The value waited for.
        value: bool,
        /// Longest wait in ms, 1..=[`MAX_WAIT_MS`].
        timeout_ms: u32,
    },
    /// `DWL i ms K` — dwell: the robot stops exactly at the end of the
    /// motion before it and stands for `ms` (KRL `WAIT SEC`),
    /// 0..=[`MAX_WAIT_MS`].
    Dwell {
        /// Standstill in ms.
        ms: u32,
    },
}

/// Largest |path| of an `SOP` record in mm: a KRL `TRIGGER WHEN PATH`
/// shifts its switching point at most back to the start of its motion and
/// forward to the next exact stop, and no motion of a KUKA arm is longer.
pub const MAX_TRIGGER_PATH_MM: f64 = 5000.0;

/// Longest wait of a `WIN` or `DWL` record in ms (10 minutes): nothing in
/// a motion sequence waits for ever.
pub const MAX_WAIT_MS: u32 = 600_000;

/// Most points a spline block (`SPL` records) holds: the KRL program
/// plays a block as one of its static `SPLINE … ENDSPLINE` statements of
/// 1 to 8 points, and reads a block within one Submit pass.
pub const MAX_SPLINE_POINTS: usize = 8;

impl MotionRecord {
    /// Its motion parameters (none for an I/O action or a dwell).
    pub fn params(&self) -> Option<&MotionParams> {
        match self {
            MotionRecord::Ptp { params, .. }
            | MotionRecord::PtpAxes { params, .. }
            | MotionRecord::SptpAxes { params, .. }
            | MotionRecord::Lin { params, .. }
            | MotionRecord::Circ { params, .. }
            | MotionRecord::Slin { params, .. }
            | MotionRecord::Scirc { params, .. }
            | MotionRecord::Sptp { params, .. }
            | MotionRecord::Spl { params, .. } => Some(params),
            MotionRecord::SetOutput { .. }
            | MotionRecord::WaitInput { .. }
            | MotionRecord::Dwell { .. } => None,
        }
    }

    /// A motion (as opposed to an action: `SOT`, `WIN`, `DWL`).
    pub fn is_motion(&self) -> bool {
        self.params().is_some()
    }

    /// An action that stops the robot exactly at the end of the motion
    /// before it (`WIN`, `DWL`: an advance-run stop in KRL).
    pub fn stops_robot(&self) -> bool {
        matches!(
            self,
            MotionRecord::WaitInput { .. } | MotionRecord::Dwell { .. }
        )
    }

    /// A motion of the spline family (SLIN, SCIRC, SPTP, SPL): a KRC plans
    /// them with another motion planner than PTP/LIN/CIRC, and the two
    /// families never blend into each other.
    pub fn is_spline_family(&self) -> bool {
        matches!(
            self,
            MotionRecord::Slin { .. }
                | MotionRecord::Scirc { .. }
                | MotionRecord::Sptp { .. }
                | MotionRecord::SptpAxes { .. }
                | MotionRecord::Spl { .. }
        )
    }

    /// Its Cartesian target (all but an axis PTP).
    pub fn target(&self) -> Option<&Frame> {
        match self {
            MotionRecord::Ptp { target, .. }
            | MotionRecord::Lin { target, .. }
            | MotionRecord::Circ { target, .. }
            | MotionRecord::Slin { target, .. }
            | MotionRecord::Scirc { target, .. }
            | MotionRecord::Sptp { target, .. }
            | MotionRecord::Spl { target, .. } => Some(target),
            MotionRecord::PtpAxes { .. }
            | MotionRecord::SptpAxes { .. }
            | MotionRecord::SetOutput { .. }
            | MotionRecord::WaitInput { .. }
            | MotionRecord::Dwell { .. } => None,
        }
    }

    /// The auxiliary point of a CIRC or SCIRC.
    pub fn aux(&self) -> Option<[f64; 3]> {
        match self {
            MotionRecord::Circ { aux, .. } | MotionRecord::Scirc { aux, .. } => Some(*aux),
            _ => None,
        }
    }

    /// Points of its spline block from this one to the end (1 for every
    /// other record).
    pub fn block_left(&self) -> usize {
        match self {
            MotionRecord::Spl { left, .. } => usize::from(*left),
            _ => 1,
        }
    }
}

/// How many of `motions` (from the first, which starts a block or is no
/// spline point) can go into one command of at most `max` motions without
/// splitting a spline block, nor a motion from the `set_output` records
/// after it (the controller arms them when it plans the motion, so they
/// must arrive with it): `max` or fewer, never more.
pub fn whole_blocks(motions: &[MotionRecord], max: usize) -> usize {
    let output = |m: &MotionRecord| matches!(m, MotionRecord::SetOutput { .. });
    // The cuts are between whole blocks (a single record is a block of
    // one); a good one is not followed by a `set_output`.
    let (mut n, mut good) = (0, 0);
    while n < motions.len() {
        let block = motions[n].block_left();
        if n + block > max {
            break;
        }
        n += block;
        if motions.get(n).is_none_or(|m| !output(m)) {
            good = n;
        }
    }
    // No good cut at all (outputs after a motion more than `max`): the
    // controller switches those cut off as the next motion starts.
    if good == 0 {
        n.min(motions.len())
    } else {
        good
    }
}

/// Speed, acceleration and approximation of one motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionParams {
    /// PTP: % of max axis speed; LIN/CIRC: m/s.
    pub velocity: f64,
    /// % of max acceleration.
    pub acceleration_pct: f64,
    /// Approximation distance in mm; 0 = exact stop.
    pub approx_mm: f64,
}

impl MotionParams {
    fn fields(&self, out: &mut Vec<Field>) -> Result<(), EncodeError> {
        out.push(real("velocity", self.velocity)?);
        out.push(real("acceleration", self.acceleration_pct)?);
        out.push(real("approximation", self.approx_mm)?);
        Ok(())
    }

    fn read(line: &mut crate::codec::Line) -> Self {
        MotionParams {
            velocity: line.real(),
            acceleration_pct: line.real(),
            approx_mm: line.real(),
        }
    }
}

/// Default speeds the controller applies to HOME (and reports back).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedRecord {
    /// Program override $OV_PRO in %.
    pub override_pct: f64,
    /// Default PTP velocity in %.
    pub ptp_velocity_pct: f64,
    /// Default PTP acceleration in %.
    pub ptp_acceleration_pct: f64,
    /// Default path velocity in m/s.
    pub cp_velocity: f64,
    /// Default path acceleration in %.
    pub cp_acceleration_pct: f64,
}

/// Highest digital I/O index (`$IN`/`$OUT` of KSS 8.x have 4096).
pub const MAX_IO_INDEX: u16 = 4096;

/// Longest output pulse the protocol carries (ms).
pub const MAX_PULSE_MS: u32 = 60_000;

/// Highest analog I/O channel (`$ANIN`/`$ANOUT` of KSS 8.x have 32).
pub const MAX_ANALOG_INDEX: u8 = 32;

/// The body of a SETANOUT (op 15): `ANO index value K`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogOutputRecord {
    /// `$ANOUT` index, 1..=[`MAX_ANALOG_INDEX`].
    pub index: u8,
    /// The normalised value, −1.0..=1.0 (±1.0 = the channel's full scale).
    pub value: f64,
}

/// The analog I/O a controller reports (the state file's optional `ANS`
/// line): `$ANIN[1..=8]` and `$ANOUT[1..=8]`, normalised −1.0..=1.0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AnalogState {
    /// `$ANIN[1..=8]`.
    pub inputs: [f64; AnalogState::WIDTH],
    /// `$ANOUT[1..=8]`.
    pub outputs: [f64; AnalogState::WIDTH],
}

impl AnalogState {
    /// Channels reported of each kind.
    pub const WIDTH: usize = 8;
}

/// The body of a SETOUT (op 14): `OUT index value pulse_ms K`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputRecord {
    /// `$OUT` index, 1..=[`MAX_IO_INDEX`].
    pub index: u16,
    /// The value to set.
    pub value: bool,
    /// 0: stay; else the output returns to `!value` after this many ms
    /// (at most [`MAX_PULSE_MS`]).
    pub pulse_ms: u32,
}

/// Digital I/O the controller reports in its state file (the `IOS` line):
/// 31 inputs and 31 outputs from `base` on, bit `k` = signal `base + k`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IoState {
    /// Index of bit 0 (1..=[`MAX_IO_INDEX`] − 30).
    pub base: u16,
    /// `$IN[base..base+30]`.
    pub inputs: u32,
    /// `$OUT[base..base+30]`.
    pub outputs: u32,
}

impl IoState {
    /// Signals per direction in the state file.
    pub const WIDTH: u16 = 31;

    /// The value of `$IN[index]`/`$OUT[index]` if the window holds it.
    pub fn get(&self, output: bool, index: u16) -> Option<bool> {
        let k = index.checked_sub(self.base).filter(|k| *k < Self::WIDTH)?;
        let bits = if output { self.outputs } else { self.inputs };
        Some(bits & (1 << k) != 0)
    }
}

/// What a teach pendant shows of the controller's safety and program
/// state (the state file's optional `SAF` line): the KRL system variables
/// `sps.sub` programs read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SafetyState {
    /// `$PERI_RDY`: the drives are switched on (peripherals ready).
    pub drives_ready: bool,
    /// `$USER_SAF`: the operator safety (fence, enabling) is closed.
    pub user_safety: bool,
    /// `$ALARM_STOP`: the emergency-stop chain is closed (FALSE = an
    /// emergency stop is pressed).
    pub alarm_stop: bool,
    /// `$STOPMESS`: a stop message waits for acknowledgement.
    pub stop_message: bool,
    /// `$PRO_STATE1` of the robot interpreter: 0 free, 1 reset, 2 active,
    /// 3 stopped, 4 ended.
    pub program_state: u8,
}

/// Why a simulated controller could not switch the drives on when the
/// operator acknowledged: the part of the safety circuit still open.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum AcknowledgeRefused {
    /// The emergency stop is still pressed (`$ALARM_STOP` FALSE).
    #[error("the emergency stop is still pressed")]
    EmergencyStop,
    /// The operator safety is still open (`$USER_SAF` FALSE).
    #[error("the operator safety is still open")]
    UserSafety,
}

/// What a command asks the controller to do.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Op 1: execute motions as one continuous batch.
    Move(Vec<MotionRecord>),
    /// Op 3: report the current position (a round trip through the program).
    GetPosition,
    /// Op 4 (version 2): open a motion stream (a path): the command's own
    /// id names it; the controller executes motions as they arrive and
    /// answers this id when the path ends.
    OpenPath(PathChunk),
    /// Op 5 (version 2): append motions to the open path; answered at once
    /// with the path's stored count.
    Append(PathChunk),
    /// Op 6: PTP to the home position.
    Home,
    /// Op 8: set the tool frame ($TOOL).
    SetTool(Frame),
    /// Op 9: report the tool frame.
    GetTool,
    /// Op 10: run the uploaded program module `kbu<n>` (`PRG n`) and answer
    /// when it ends.
    Run(i32),
    /// Op 11: set the base frame ($BASE).
    SetBase(Frame),
    /// Op 12: report the base frame.
    GetBase,
    /// Op 13: set override and default speeds.
    SetSpeed(SpeedRecord),
    /// Op 14: set a digital output (`$OUT[index]`), optionally as a pulse
    /// of `pulse_ms` after which it returns to the other value.
    SetOutput(OutputRecord),
    /// Op 15: set an analog output (`$ANOUT[index]`) at once.
    SetAnalogOutput(AnalogOutputRecord),
    /// Op 20: brake, flush the motion buffer, cancel the running command.
    /// The only command accepted while another one is running.
    Stop,
    /// Op 21: acknowledge an error state.
    Reset,
}

impl Command {
    /// The op code on the wire.
    pub fn op(&self) -> i32 {
        match self {
            Command::Move(_) => 1,
            Command::GetPosition => 3,
            Command::OpenPath(_) => 4,
            Command::Append(_) => 5,
            Command::Home => 6,
            Command::SetTool(_) => 8,
            Command::GetTool => 9,
            Command::Run(_) => 10,
            Command::SetBase(_) => 11,
            Command::GetBase => 12,
            Command::SetSpeed(_) => 13,
            Command::SetOutput(_) => 14,
            Command::SetAnalogOutput(_) => 15,
            Command::Stop => 20,
            Command::Reset => 21,
        }
    }

    /// A short lowercase name for logs.
    pub fn name(&self) -> &'static str {
        match self {
            Command::Move(_) => "move",
            Command::GetPosition => "get_position",
            Command::OpenPath(_) => "open_path",
            Command::Append(_) => "append",
            Command::Home => "home",
            Command::SetTool(_) => "set_tool",
            Command::GetTool => "get_tool",
            Command::Run(_) => "run",
            Command::SetBase(_) => "set_base",
            Command::GetBase => "get_base",
            Command::SetSpeed(_) => "set_speed",
            Command::SetOutput(_) => "set_output",
            Command::SetAnalogOutput(_) => "set_analog_output",
            Command::Stop => "stop",
            Command::Reset => "reset",
        }
    }
}

/// The body of a PATH (op 4) or APPEND (op 5) command: `APD path first
/// close K`, then the motions with indices `first`, `first + 1`, ...
#[derive(Debug, Clone, PartialEq)]
pub struct PathChunk {
    /// The path: the id of the PATH command that opened it (for op 4 its
    /// own id).
    pub path: Cid,
    /// Index of the first motion in the path (0-based, path-wide). For
    /// op 4 always 0.
    pub first: u32,
    /// The motions, at most [`MAX_BATCH`].
    pub motions: Vec<MotionRecord>,
    /// After these motions the path ends: the controller answers the path
    /// when the last one has run.
    pub close: bool,
}

/// Writes motion records with indices `first..`, appending to `body`.
fn encode_motions(
    body: &mut String,
    motions: &[MotionRecord],
    first: u32,
) -> Result<i32, EncodeError> {
    let mut f = Vec::with_capacity(16);
    let mut n = 0;
    for (i, m) in motions.iter().enumerate() {
        f.clear();
        let index = i32::try_from(u64::from(first) + i as u64)
            .map_err(|_| EncodeError::Shape("motion index beyond 2147483647".into()))?;
        f.push(Field::Int(index));
        let tag = match m {
            MotionRecord::Ptp {
                target,
                s,
                t,
                params,
            } => {
                target.fields(&mut f)?;
                f.push(Field::Int(s.map_or(-1, i32::from)));
                f.push(Field::Int(t.map_or(-1, i32::from)));
                params.fields(&mut f)?;
                "PTP"
            }
            MotionRecord::PtpAxes { axes, params } | MotionRecord::SptpAxes { axes, params } => {
                for (name, v) in ["a1", "a2", "a3", "a4", "a5", "a6"].into_iter().zip(axes) {
                    f.push(real(name, *v)?);
                }
                params.fields(&mut f)?;
                if matches!(m, MotionRecord::SptpAxes { .. }) {
                    "SPA"
                } else {
                    "PTA"
                }
            }
            MotionRecord::Lin { target, params } => {
                target.fields(&mut f)?;
                params.fields(&mut f)?;
                "LIN"
            }
            MotionRecord::Circ {
                aux,
                target,
                params,
            } => {
                for (name, v) in ["aux_x", "aux_y", "aux_z"].into_iter().zip(aux) {
                    f.push(real(name, *v)?);
                }
                target.fields(&mut f)?;
                params.fields(&mut f)?;
                "CIR"
            }
            MotionRecord::Slin { target, params } => {
                target.fields(&mut f)?;
                params.fields(&mut f)?;
                "SLN"
            }
            MotionRecord::Scirc {
                aux,
                target,
                params,
            } => {
                for (name, v) in ["aux_x", "aux_y", "aux_z"].into_iter().zip(aux) {
                    f.push(real(name, *v)?);
                }
                target.fields(&mut f)?;
                params.fields(&mut f)?;
                "SCI"
            }
            MotionRecord::Sptp {
                target,
                s,
                t,
                params,
            } => {
                target.fields(&mut f)?;
                f.push(Field::Int(s.map_or(-1, i32::from)));
                f.push(Field::Int(t.map_or(-1, i32::from)));
                params.fields(&mut f)?;
                "SPT"
            }
            MotionRecord::Spl {
                target,
                params,
                left,
            } => {
                if *left == 0 || usize::from(*left) > MAX_SPLINE_POINTS {
                    return Err(EncodeError::Shape(format!(
                        "a spline point's block has 1 to {MAX_SPLINE_POINTS} points left, not {left}"
                    )));
                }
                target.fields(&mut f)?;
                params.fields(&mut f)?;
                f.push(Field::Int(i32::from(*left)));
                "SPL"
            }
            MotionRecord::SetOutput {
                index,
                value,
                pulse_ms,
                path_mm,
            } => {
                if *index == 0 || *index > MAX_IO_INDEX || *pulse_ms > MAX_PULSE_MS {
                    return Err(EncodeError::Shape(format!(
                        "output {index} (1..={MAX_IO_INDEX}) or pulse {pulse_ms} ms (0..={MAX_PULSE_MS}) out of range"
                    )));
                }
                f.push(Field::Int(i32::from(*index)));
                f.push(Field::Int(i32::from(*value)));
                f.push(Field::Int(*pulse_ms as i32));
                match path_mm {
                    None => "SOT",
                    Some(p) => {
                        if !p.is_finite() || p.abs() > MAX_TRIGGER_PATH_MM {
                            return Err(EncodeError::Shape(format!(
                                "a switching point {p} mm along the path is not within ±{MAX_TRIGGER_PATH_MM} mm"
                            )));
                        }
                        f.push(crate::codec::real("path", *p)?);
                        "SOP"
                    }
                }
            }
            MotionRecord::WaitInput {
                index,
                value,
                timeout_ms,
            } => {
                if *index == 0 || *index > MAX_IO_INDEX || !(1..=MAX_WAIT_MS).contains(timeout_ms) {
                    return Err(EncodeError::Shape(format!(
                        "input {index} (1..={MAX_IO_INDEX}) or timeout {timeout_ms} ms (1..={MAX_WAIT_MS}) out of range"
                    )));
                }
                f.push(Field::Int(i32::from(*index)));
                f.push(Field::Int(i32::from(*value)));
                f.push(Field::Int(*timeout_ms as i32));
                "WIN"
            }
            MotionRecord::Dwell { ms } => {
                if *ms > MAX_WAIT_MS {
                    return Err(EncodeError::Shape(format!(
                        "dwell {ms} ms (0..={MAX_WAIT_MS}) out of range"
                    )));
                }
                f.push(Field::Int(*ms as i32));
                "DWL"
            }
        };
        let continues = match i.checked_sub(1).map(|k| &motions[k]) {
            Some(MotionRecord::Spl { left, .. }) if *left > 1 => Some(*left - 1),
            _ => None,
        };
        match (continues, m) {
            (None, _) => {}
            (Some(e), MotionRecord::Spl { left, .. }) if *left == e => {}
            (Some(_), _) => {
                return Err(EncodeError::Shape(format!(
                    "motion {index} interrupts a spline block"
                )));
            }
        }
        write_line(body, tag, &f);
        n += 1;
    }
    if let Some(MotionRecord::Spl { left, .. }) = motions.last()
        && *left > 1
    {
        return Err(EncodeError::Shape(format!(
            "a spline block ends inside the command ({left} points left)"
        )));
    }
    Ok(n)
}

/// Reads `n` motion records whose indices must be `first`, `first + 1`, ...
fn decode_motions(
    r: &mut Reader<'_>,
    n: i32,
    first: i64,
) -> Result<Vec<MotionRecord>, DecodeError> {
    let mut motions = Vec::with_capacity(n.max(0) as usize);
    for k in 0..i64::from(n) {
        let tag = r.peek_tag().ok_or(DecodeError::Truncated)?;
        let (l, m) = match tag {
            "PTP" | "SPT" => {
                let tag = if tag == "PTP" { "PTP" } else { "SPT" };
                let mut l = r.line(tag, "irrrrrriirrr")?;
                let idx = l.int();
                let target = Frame::read(&mut l);
                let s = l.int();
                let t = l.int();
                let params = MotionParams::read(&mut l);
                let st = |v: i32, max: i32| {
                    if v == -1 {
                        Ok(None)
                    } else if (0..=max).contains(&v) {
                        Ok(Some(v as u8))
                    } else {
                        Err(v)
                    }
                };
                let s =
                    st(s, 7).map_err(|v| l.invalid(format!("Status {v} is not in 0..=7 or -1")))?;
                let t =
                    st(t, 63).map_err(|v| l.invalid(format!("Turn {v} is not in 0..=63 or -1")))?;
                let m = if tag == "PTP" {
                    MotionRecord::Ptp {
                        target,
                        s,
                        t,
                        params,
                    }
                } else {
                    MotionRecord::Sptp {
                        target,
                        s,
                        t,
                        params,
                    }
                };
                (l, (idx, m))
            }
            "PTA" | "SPA" => {
                let spline = tag == "SPA";
                let mut l = r.line(if spline { "SPA" } else { "PTA" }, "irrrrrrrrr")?;
                let idx = l.int();
                let axes = [l.real(), l.real(), l.real(), l.real(), l.real(), l.real()];
                let params = MotionParams::read(&mut l);
                let m = if spline {
                    MotionRecord::SptpAxes { axes, params }
                } else {
                    MotionRecord::PtpAxes { axes, params }
                };
                (l, (idx, m))
            }
            "LIN" | "SLN" => {
                let spline = tag == "SLN";
                let mut l = r.line(if spline { "SLN" } else { "LIN" }, "irrrrrrrrr")?;
                let idx = l.int();
                let target = Frame::read(&mut l);
                let params = MotionParams::read(&mut l);
                let m = if spline {
                    MotionRecord::Slin { target, params }
                } else {
                    MotionRecord::Lin { target, params }
                };
                (l, (idx, m))
            }
            "CIR" | "SCI" => {
                let spline = tag == "SCI";
                let mut l = r.line(if spline { "SCI" } else { "CIR" }, "irrrrrrrrrrrr")?;
                let idx = l.int();
                let aux = [l.real(), l.real(), l.real()];
                let target = Frame::read(&mut l);
                let params = MotionParams::read(&mut l);
                let m = if spline {
                    MotionRecord::Scirc {
                        aux,
                        target,
                        params,
                    }
                } else {
                    MotionRecord::Circ {
                        aux,
                        target,
                        params,
                    }
                };
                (l, (idx, m))
            }
            "SPL" => {
                let mut l = r.line("SPL", "irrrrrrrrri")?;
                let idx = l.int();
                let target = Frame::read(&mut l);
                let params = MotionParams::read(&mut l);
                let left = l.int();
                let left = u8::try_from(left)
                    .ok()
                    .filter(|n| (1..=MAX_SPLINE_POINTS).contains(&usize::from(*n)))
                    .ok_or_else(|| {
                        l.invalid(format!(
                            "a spline point's block has 1 to {MAX_SPLINE_POINTS} points left, not {left}"
                        ))
                    })?;
                (
                    l,
                    (
                        idx,
                        MotionRecord::Spl {
                            target,
                            params,
                            left,
                        },
                    ),
                )
            }
            "SOT" | "SOP" | "WIN" => {
                let output = tag != "WIN";
                let mut l = match tag {
                    "SOT" => r.line("SOT", "iiii")?,
                    "SOP" => r.line("SOP", "iiiir")?,
                    _ => r.line("WIN", "iiii")?,
                };
                let at_path = tag == "SOP";
                let idx = l.int();
                let index = l.int();
                let value = l.int();
                let ms = l.int();
                let path_mm = if at_path {
                    let p = l.real();
                    if p.abs() > MAX_TRIGGER_PATH_MM {
                        return Err(l.invalid(format!(
                            "a switching point {p} mm along the path is not within ±{MAX_TRIGGER_PATH_MM} mm"
                        )));
                    }
                    Some(p)
                } else {
                    None
                };
                let index = u16::try_from(index)
                    .ok()
                    .filter(|i| (1..=MAX_IO_INDEX).contains(i))
                    .ok_or_else(|| {
                        l.invalid(format!("I/O index {index} is not in 1..={MAX_IO_INDEX}"))
                    })?;
                let value = match value {
                    0 => false,
                    1 => true,
                    v => return Err(l.invalid(format!("I/O value {v} is not 0 or 1"))),
                };
                let (lo, hi) = if output {
                    (0, MAX_PULSE_MS)
                } else {
                    (1, MAX_WAIT_MS)
                };
                let ms = u32::try_from(ms)
                    .ok()
                    .filter(|m| (lo..=hi).contains(m))
                    .ok_or_else(|| l.invalid(format!("{ms} ms is not in {lo}..={hi}")))?;
                let m = if output {
                    MotionRecord::SetOutput {
                        index,
                        value,
                        pulse_ms: ms,
                        path_mm,
                    }
                } else {
                    MotionRecord::WaitInput {
                        index,
                        value,
                        timeout_ms: ms,
                    }
                };
                (l, (idx, m))
            }
            "DWL" => {
                let mut l = r.line("DWL", "ii")?;
                let idx = l.int();
                let ms = l.int();
                let ms = u32::try_from(ms)
                    .ok()
                    .filter(|m| *m <= MAX_WAIT_MS)
                    .ok_or_else(|| {
                        l.invalid(format!("dwell {ms} ms is not in 0..={MAX_WAIT_MS}"))
                    })?;
                (l, (idx, MotionRecord::Dwell { ms }))
            }
            "END" => return Err(DecodeError::Truncated),
            other => {
                return Err(DecodeError::Tag {
                    line: r.next_line_number(),
                    expected: "PTP, PTA, LIN, CIR, SLN, SCI, SPT, SPA, SPL, SOT, SOP, WIN or DWL",
                    found: other.to_string(),
                });
            }
        };
        let want = first + k;
        if i64::from(m.0) != want {
            return Err(l.invalid(format!("motion index {} where {want} was expected", m.0)));
        }
        // A spline block is whole: each point after the first has one
        // point left fewer, and no command ends inside a block.
        let expect = match motions.last() {
            Some(MotionRecord::Spl { left, .. }) if *left > 1 => Some(*left - 1),
            _ => None,
        };
        match (expect, &m.1) {
            (None, _) => {}
            (Some(e), MotionRecord::Spl { left, .. }) if *left == e => {}
            (Some(e), _) => {
                return Err(l.invalid(format!(
                    "motion {} continues a spline block and must be an SPL point with {e} left",
                    m.0
                )));
            }
        }
        motions.push(m.1);
    }
    if let Some(MotionRecord::Spl { left, .. }) = motions.last()
        && *left > 1
    {
        return Err(DecodeError::Value {
            line: r.next_line_number(),
            what: format!("a spline block ends inside the command ({left} points left)"),
        });
    }
    Ok(motions)
}

/// The command file: `CMD 2 cid op n K`, `n` body lines, `END cid n K`.
#[derive(Debug, Clone, PartialEq)]
pub struct CommandFile {
    /// Command id.
    pub cid: Cid,
    /// The command.
    pub command: Command,
}

impl CommandFile {
    /// Encodes the file text.
    pub fn encode(&self) -> Result<String, EncodeError> {
        if self.cid <= 0 {
            return Err(EncodeError::Shape(format!(
                "CID {} is not positive",
                self.cid
            )));
        }
        let mut body = String::new();
        let mut n = 0i32;
        let mut f = Vec::with_capacity(16);
        match &self.command {
            Command::Move(motions) => {
                if motions.is_empty() || motions.len() > MAX_BATCH {
                    return Err(EncodeError::Shape(format!(
                        "a batch holds 1 to {MAX_BATCH} motions, not {}",
                        motions.len()
                    )));
                }
                n = encode_motions(&mut body, motions, 0)?;
            }
            Command::OpenPath(chunk) | Command::Append(chunk) => {
                if chunk.motions.len() > MAX_BATCH {
                    return Err(EncodeError::Shape(format!(
                        "a path chunk holds at most {MAX_BATCH} motions, not {}",
                        chunk.motions.len()
                    )));
                }
                let first_ok = matches!(self.command, Command::Append(_)) || chunk.first == 0;
                if chunk.path <= 0 || !first_ok || i32::try_from(chunk.first).is_err() {
                    return Err(EncodeError::Shape(format!(
                        "path {} from motion {} is not a valid chunk",
                        chunk.path, chunk.first
                    )));
                }
                write_line(
                    &mut body,
                    "APD",
                    &[
                        Field::Int(chunk.path),
                        Field::Int(chunk.first as i32),
                        Field::Int(i32::from(chunk.close)),
                    ],
                );
                n = 1 + encode_motions(&mut body, &chunk.motions, chunk.first)?;
            }
            Command::SetTool(frame) | Command::SetBase(frame) => {
                frame.fields(&mut f)?;
                write_line(&mut body, "FRM", &f);
                n = 1;
            }
            Command::Run(program) => {
                if *program <= 0 {
                    return Err(EncodeError::Shape(format!(
                        "program number {program} is not positive"
                    )));
                }
                write_line(&mut body, "PRG", &[Field::Int(*program)]);
                n = 1;
            }
            Command::SetOutput(o) => {
                if o.index == 0 || o.index > MAX_IO_INDEX || o.pulse_ms > MAX_PULSE_MS {
                    return Err(EncodeError::Shape(format!(
                        "output {} (1..={MAX_IO_INDEX}) or pulse {} ms (0..={MAX_PULSE_MS}) out of range",
                        o.index, o.pulse_ms
                    )));
                }
                write_line(
                    &mut body,
                    "OUT",
                    &[
                        Field::Int(i32::from(o.index)),
                        Field::Int(i32::from(o.value)),
                        Field::Int(o.pulse_ms as i32),
                    ],
                );
                n = 1;
            }
            Command::SetAnalogOutput(a) => {
                if a.index == 0
                    || a.index > MAX_ANALOG_INDEX
                    || !(a.value.is_finite() && (-1.0..=1.0).contains(&a.value))
                {
                    return Err(EncodeError::Shape(format!(
                        "analog output {} (1..={MAX_ANALOG_INDEX}) or value {} (-1..=1) out of range",
                        a.index, a.value
                    )));
                }
                write_line(
                    &mut body,
                    "ANO",
                    &[Field::Int(i32::from(a.index)), real("value", a.value)?],
                );
                n = 1;
            }
            Command::SetSpeed(s) => {
                f.push(real("override", s.override_pct)?);
                f.push(real("ptp_velocity", s.ptp_velocity_pct)?);
                f.push(real("ptp_acceleration", s.ptp_acceleration_pct)?);
                f.push(real("cp_velocity", s.cp_velocity)?);
                f.push(real("cp_acceleration", s.cp_acceleration_pct)?);
                write_line(&mut body, "SPD", &f);
                n = 1;
            }
            _ => {}
        }
        let mut out = String::with_capacity(body.len() + 64);
        write_line(
            &mut out,
            "CMD",
            &[
                Field::Int(PROTOCOL_VERSION),
                Field::Int(self.cid),
                Field::Int(self.command.op()),
                Field::Int(n),
            ],
        );
        out.push_str(&body);
        write_line(&mut out, "END", &[Field::Int(self.cid), Field::Int(n)]);
        Ok(out)
    }

    /// The CID of a file whose header line is intact, even if the rest is
    /// not: lets the controller answer a malformed command instead of
    /// ignoring it.
    pub fn peek_cid(text: &str) -> Option<Cid> {
        let mut r = Reader::new(text).ok()?;
        let mut h = r.line("CMD", "iiii").ok()?;
        let _version = h.int();
        let cid = h.int();
        (cid > 0).then_some(cid)
    }

    /// Decodes a complete command file.
    pub fn decode(text: &str) -> Result<Self, DecodeError> {
        if let Some(v) = other_version(text, "CMD") {
            return Err(DecodeError::Version(v));
        }
        let mut r = Reader::new(text)?;
        let mut h = r.line("CMD", "iiii")?;
        let version = h.int();
        if version != PROTOCOL_VERSION {
            return Err(DecodeError::Version(i64::from(version)));
        }
        let cid = h.int();
        let op = h.int();
        let n = h.int();
        if cid <= 0 {
            return Err(h.invalid(format!("CID {cid} is not positive")));
        }
        let expect_n = |want: i32| {
            if n == want {
                Ok(())
            } else {
                Err(h.invalid(format!("op {op} takes {want} body lines, not {n}")))
            }
        };
        let command = match op {
            1 => {
                if n < 1 || n as usize > MAX_BATCH {
                    return Err(
                        h.invalid(format!("a batch holds 1 to {MAX_BATCH} motions, not {n}"))
                    );
                }
                let motions = decode_motions(&mut r, n, 0)?;
                Command::Move(motions)
            }
            4 | 5 => {
                if n < 1 || n as usize > MAX_BATCH + 1 {
                    return Err(h.invalid(format!(
                        "a path chunk has its APD line and at most {MAX_BATCH} motions, not {n} lines"
                    )));
                }
                let mut l = r.line("APD", "iii")?;
                let path = l.int();
                let first = l.int();
                let close = l.int();
                if path <= 0 || first < 0 || !(0..=1).contains(&close) {
                    return Err(l.invalid("path, first motion or close flag out of range"));
                }
                if op == 4 && (path != cid || first != 0) {
                    return Err(
                        l.invalid("a PATH command opens the path of its own id from motion 0")
                    );
                }
                let motions = decode_motions(&mut r, n - 1, i64::from(first))?;
                let chunk = PathChunk {
                    path,
                    first: first as u32,
                    motions,
                    close: close == 1,
                };
                if op == 4 {
                    Command::OpenPath(chunk)
                } else {
                    Command::Append(chunk)
                }
            }
            3 | 6 | 9 | 12 | 20 | 21 => {
                expect_n(0)?;
                match op {
                    3 => Command::GetPosition,
                    6 => Command::Home,
                    9 => Command::GetTool,
                    12 => Command::GetBase,
                    20 => Command::Stop,
                    _ => Command::Reset,
                }
            }
            8 | 11 => {
                expect_n(1)?;
                let mut l = r.line("FRM", "rrrrrr")?;
                let frame = Frame::read(&mut l);
                if op == 8 {
                    Command::SetTool(frame)
                } else {
                    Command::SetBase(frame)
                }
            }
            10 => {
                expect_n(1)?;
                let mut l = r.line("PRG", "i")?;
                let program = l.int();
                if program <= 0 {
                    return Err(l.invalid("program number must be positive"));
                }
                Command::Run(program)
            }
            13 => {
                expect_n(1)?;
                let mut l = r.line("SPD", "rrrrr")?;
                Command::SetSpeed(SpeedRecord {
                    override_pct: l.real(),
                    ptp_velocity_pct: l.real(),
                    ptp_acceleration_pct: l.real(),
                    cp_velocity: l.real(),
                    cp_acceleration_pct: l.real(),
                })
            }
            14 => {
                expect_n(1)?;
                let mut l = r.line("OUT", "iii")?;
                let (index, value, pulse) = (l.int(), l.int(), l.int());
                if !(1..=i32::from(MAX_IO_INDEX)).contains(&index)
                    || !(0..=1).contains(&value)
                    || !(0..=MAX_PULSE_MS as i32).contains(&pulse)
                {
                    return Err(l.invalid("output index, value or pulse out of range"));
                }
                Command::SetOutput(OutputRecord {
                    index: index as u16,
                    value: value == 1,
                    pulse_ms: pulse as u32,
                })
            }
            15 => {
                expect_n(1)?;
                let mut l = r.line("ANO", "ir")?;
                let (index, value) = (l.int(), l.real());
                if !(1..=i32::from(MAX_ANALOG_INDEX)).contains(&index)
                    || !(-1.0..=1.0).contains(&value)
                {
                    return Err(l.invalid("analog output index or value out of range"));
                }
                Command::SetAnalogOutput(AnalogOutputRecord {
                    index: index as u8,
                    value,
                })
            }
            other => return Err(h.invalid(format!("unknown op {other}"))),
        };
        let mut e = r.line("END", "ii")?;
        if e.int() != cid || e.int() != n {
            return Err(e.invalid("END record does not match the header"));
        }
        r.finish()?;
        Ok(CommandFile { cid, command })
    }
}

/// Result codes (thesis-compatible: 1 is success).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ResultCode {
    /// 1: done.
    Ok,
    /// 2: cancelled by STOP (motions completed before it are reported).
    Cancelled,
    /// 3: rejected because another command was running.
    Busy,
    /// 10: the command file decoded but is not valid.
    BadCommand,
    /// 11: op not supported by this controller program.
    Unsupported,
    /// 12 (version 2): an APPEND for a path that is not open (it ended,
    /// failed or was cancelled, or never existed).
    PathClosed,
    /// 20: target or path point out of reach.
    Unreachable,
    /// 21: a software limit switch would be passed (`axis` names it).
    SoftwareLimit,
    /// 22: the path passes a singularity.
    Singularity,
    /// 23: no solution with the requested Status/Turn.
    NoConfiguration,
    /// 24: degenerate geometry (e.g. CIRC points collinear).
    Geometry,
    /// 25: a `WIN` record's input did not come within its timeout; the
    /// robot stands at the end of the motion before it.
    InputTimeout,
    /// 30: the controller is in an error state; RESET first.
    ControllerError,
    /// 31: drives off, wrong mode or program not ready.
    NotReady,
    /// 40: a KRL runtime error was caught ($ERR).
    RuntimeError,
    /// Any other code.
    Other(i32),
}

impl ResultCode {
    /// The number on the wire.
    pub fn code(self) -> i32 {
        match self {
            ResultCode::Ok => 1,
            ResultCode::Cancelled => 2,
            ResultCode::Busy => 3,
            ResultCode::BadCommand => 10,
            ResultCode::Unsupported => 11,
            ResultCode::PathClosed => 12,
            ResultCode::Unreachable => 20,
            ResultCode::SoftwareLimit => 21,
            ResultCode::Singularity => 22,
            ResultCode::NoConfiguration => 23,
            ResultCode::Geometry => 24,
            ResultCode::InputTimeout => 25,
            ResultCode::ControllerError => 30,
            ResultCode::NotReady => 31,
            ResultCode::RuntimeError => 40,
            ResultCode::Other(c) => c,
        }
    }

    /// Maps a wire number to a code (0 in state records means "no error").
    pub fn from_code(code: i32) -> Self {
        match code {
            1 => ResultCode::Ok,
            2 => ResultCode::Cancelled,
            3 => ResultCode::Busy,
            10 => ResultCode::BadCommand,
            11 => ResultCode::Unsupported,
            12 => ResultCode::PathClosed,
            20 => ResultCode::Unreachable,
            21 => ResultCode::SoftwareLimit,
            22 => ResultCode::Singularity,
            23 => ResultCode::NoConfiguration,
            24 => ResultCode::Geometry,
            25 => ResultCode::InputTimeout,
            30 => ResultCode::ControllerError,
            31 => ResultCode::NotReady,
            40 => ResultCode::RuntimeError,
            c => ResultCode::Other(c),
        }
    }
}

/// One result: `RSL cid code done axis x y z a b c s t a1 a2 a3 a4 a5 a6 K`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResultRecord {
    /// The command it answers.
    pub cid: Cid,
    /// Outcome.
    pub code: ResultCode,
    /// Motions of the batch completed (for MOVE; 0 otherwise).
    pub completed: u32,
    /// 1-based axis for SOFTWARE_LIMIT, else 0.
    pub axis: u8,
    /// TCP pose at the end (tool frame for GETTOOL, base frame for GETBASE).
    pub position: Frame,
    /// Status of `position`.
    pub s: u8,
    /// Turn of `position`.
    pub t: u8,
    /// Axis angles A1..A6 at the end.
    pub axes: [f64; 6],
}

/// The result file: `RES 1 n K`, `n` (≤ 8) RSL lines oldest first, `END n K`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ResultFile {
    /// The most recent results, oldest first.
    pub results: Vec<ResultRecord>,
}

impl ResultFile {
    /// Encodes the file text (keeps only the newest [`RESULT_HISTORY`]).
    pub fn encode(&self) -> Result<String, EncodeError> {
        let skip = self.results.len().saturating_sub(RESULT_HISTORY);
        let results = &self.results[skip..];
        let n = results.len() as i32;
        let mut out = String::with_capacity(96 * (results.len() + 2));
        write_line(
            &mut out,
            "RES",
            &[Field::Int(PROTOCOL_VERSION), Field::Int(n)],
        );
        let mut f = Vec::with_capacity(13);
        for r in results {
            f.clear();
            f.extend([
                Field::Int(r.cid),
                Field::Int(r.code.code()),
                Field::Int(r.completed as i32),
                Field::Int(i32::from(r.axis)),
            ]);
            r.position.fields(&mut f)?;
            f.extend([Field::Int(i32::from(r.s)), Field::Int(i32::from(r.t))]);
            for (name, v) in ["a1", "a2", "a3", "a4", "a5", "a6"].into_iter().zip(r.axes) {
                f.push(real(name, v)?);
            }
            write_line(&mut out, "RSL", &f);
        }
        write_line(&mut out, "END", &[Field::Int(n)]);
        Ok(out)
    }

    /// Decodes a complete result file.
    pub fn decode(text: &str) -> Result<Self, DecodeError> {
        if let Some(v) = other_version(text, "RES") {
            return Err(DecodeError::Version(v));
        }
        let mut r = Reader::new(text)?;
        let mut h = r.line("RES", "ii")?;
        let version = h.int();
        if version != PROTOCOL_VERSION {
            return Err(DecodeError::Version(i64::from(version)));
        }
        let n = h.int();
        if !(0..=RESULT_HISTORY as i32).contains(&n) {
            return Err(h.invalid(format!("{n} results (at most {RESULT_HISTORY})")));
        }
        let mut results = Vec::with_capacity(n as usize);
        for _ in 0..n {
            let mut l = r.line("RSL", "iiiirrrrrriirrrrrr")?;
            let cid = l.int();
            let code = ResultCode::from_code(l.int());
            let completed = l.int();
            let axis = l.int();
            let position = Frame::read(&mut l);
            let s = l.int();
            let t = l.int();
            let axes = [l.real(), l.real(), l.real(), l.real(), l.real(), l.real()];
            if completed < 0
                || !(0..=6).contains(&axis)
                || !(0..=7).contains(&s)
                || !(0..=63).contains(&t)
            {
                return Err(l.invalid("count, axis, Status or Turn out of range"));
            }
            results.push(ResultRecord {
                cid,
                code,
                completed: completed as u32,
                axis: axis as u8,
                position,
                s: s as u8,
                t: t as u8,
                axes,
            });
        }
        let mut e = r.line("END", "i")?;
        if e.int() != n {
            return Err(e.invalid("END record does not match the header"));
        }
        r.finish()?;
        Ok(ResultFile { results })
    }
}

/// What the controller side is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControllerStatus {
    /// 0: waiting for a command.
    Idle,
    /// 1: executing `busy_cid`.
    Busy,
    /// 2: in an error state (see `error`); only STOP and RESET are accepted.
    Error,
}

/// Operating mode of the controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OperatingMode {
    /// 1: manual reduced velocity.
    T1,
    /// 2: manual high velocity.
    T2,
    /// 3: automatic.
    Aut,
    /// 4: automatic external.
    Ext,
    /// 0 or anything else: unknown.
    Unknown,
}

impl OperatingMode {
    fn code(self) -> i32 {
        match self {
            OperatingMode::T1 => 1,
            OperatingMode::T2 => 2,
            OperatingMode::Aut => 3,
            OperatingMode::Ext => 4,
            OperatingMode::Unknown => 0,
        }
    }

    fn from_code(c: i32) -> Self {
        match c {
            1 => OperatingMode::T1,
            2 => OperatingMode::T2,
            3 => OperatingMode::Aut,
            4 => OperatingMode::Ext,
            _ => OperatingMode::Unknown,
        }
    }
}

/// The state (heartbeat) file, rewritten by the controller at a fixed rate:
/// `STA 2 seq status mode busy_cid busy_idx last_cid err err_axis ovr sim room stored K`,
/// `POS x y z a b c s t K`, `AXS a1..a6 K`, `TOL x..c K`, `BAS x..c K`, `END seq K`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateFile {
    /// Heartbeat counter: increases with every write.
    pub seq: i32,
    /// What the controller is doing.
    pub status: ControllerStatus,
    /// Operating mode.
    pub mode: OperatingMode,
    /// Command being executed (0 when idle).
    pub busy_cid: Cid,
    /// Motion of the batch being executed.
    pub busy_index: u32,
    /// Highest CID the controller has accepted (executed or rejected).
    pub last_cid: Cid,
    /// Current error (only in `Error` status).
    pub error: Option<ResultCode>,
    /// Axis of a software-limit error, 0 otherwise.
    pub error_axis: u8,
    /// Program override in %.
    pub override_pct: f64,
    /// True when the controller is the simulator.
    pub simulated: bool,
    /// Free motion slots of the controller's stream buffer: how many
    /// motions an APPEND could store now (0 = none; a controller without
    /// streams always reports 0).
    pub room: u32,
    /// Motions of the running path stored so far (the controller's read
    /// position: the next APPEND starts there); 0 when no path runs.
    pub stored: u32,
    /// TCP pose in the base frame.
    pub position: Frame,
    /// Status bits.
    pub s: u8,
    /// Turn bits.
    pub t: u8,
    /// Axis angles A1..A6.
    pub axes: [f64; 6],
    /// Tool frame.
    pub tool: Frame,
    /// Base frame.
    pub base: Frame,
    /// Digital I/O (the optional `IOS` line; a controller program without
    /// I/O support writes none).
    pub io: Option<IoState>,
    /// Safety and program state (the optional `SAF` line).
    pub safety: Option<SafetyState>,
    /// Analog I/O (the optional `ANS` line).
    pub analog: Option<AnalogState>,
}

impl StateFile {
    /// Encodes the file text.
    pub fn encode(&self) -> Result<String, EncodeError> {
        let mut out = String::with_capacity(400);
        let status = match self.status {
            ControllerStatus::Idle => 0,
            ControllerStatus::Busy => 1,
            ControllerStatus::Error => 2,
        };
        write_line(
            &mut out,
            "STA",
            &[
                Field::Int(PROTOCOL_VERSION),
                Field::Int(self.seq),
                Field::Int(status),
                Field::Int(self.mode.code()),
                Field::Int(self.busy_cid),
                Field::Int(self.busy_index as i32),
                Field::Int(self.last_cid),
                Field::Int(self.error.map_or(0, ResultCode::code)),
                Field::Int(i32::from(self.error_axis)),
                real("override", self.override_pct)?,
                Field::Int(i32::from(self.simulated)),
                Field::Int(i32::try_from(self.room).unwrap_or(i32::MAX)),
                Field::Int(i32::try_from(self.stored).unwrap_or(i32::MAX)),
            ],
        );
        let mut f = Vec::with_capacity(8);
        self.position.fields(&mut f)?;
        f.extend([Field::Int(i32::from(self.s)), Field::Int(i32::from(self.t))]);
        write_line(&mut out, "POS", &f);
        f.clear();
        for (name, v) in ["a1", "a2", "a3", "a4", "a5", "a6"]
            .into_iter()
            .zip(self.axes)
        {
            f.push(real(name, v)?);
        }
        write_line(&mut out, "AXS", &f);
        f.clear();
        self.tool.fields(&mut f)?;
        write_line(&mut out, "TOL", &f);
        f.clear();
        self.base.fields(&mut f)?;
        write_line(&mut out, "BAS", &f);
        if let Some(io) = &self.io {
            write_line(
                &mut out,
                "IOS",
                &[
                    Field::Int(i32::from(io.base)),
                    Field::Int((io.inputs & 0x7fff_ffff) as i32),
                    Field::Int((io.outputs & 0x7fff_ffff) as i32),
                ],
            );
        }
        if let Some(s) = &self.safety {
            write_line(
                &mut out,
                "SAF",
                &[
                    Field::Int(i32::from(s.drives_ready)),
                    Field::Int(i32::from(s.user_safety)),
                    Field::Int(i32::from(s.alarm_stop)),
                    Field::Int(i32::from(s.stop_message)),
                    Field::Int(i32::from(s.program_state.min(4))),
                ],
            );
        }
        if let Some(a) = &self.analog {
            let mut f = Vec::with_capacity(2 * AnalogState::WIDTH);
            for v in a.inputs.iter().chain(&a.outputs) {
                f.push(real("analog value", *v)?);
            }
            write_line(&mut out, "ANS", &f);
        }
        write_line(&mut out, "END", &[Field::Int(self.seq)]);
        Ok(out)
    }

    /// Decodes a complete state file.
    pub fn decode(text: &str) -> Result<Self, DecodeError> {
        // Another version's header may have another field count: name the
        // version rather than the shape.
        if let Some(v) = other_version(text, "STA") {
            return Err(DecodeError::Version(v));
        }
        let mut r = Reader::new(text)?;
        let mut h = r.line("STA", "iiiiiiiiiriii")?;
        let version = h.int();
        if version != PROTOCOL_VERSION {
            return Err(DecodeError::Version(i64::from(version)));
        }
        let seq = h.int();
        let status = match h.int() {
            0 => ControllerStatus::Idle,
            1 => ControllerStatus::Busy,
            2 => ControllerStatus::Error,
            other => return Err(h.invalid(format!("unknown status {other}"))),
        };
        let mode = OperatingMode::from_code(h.int());
        let busy_cid = h.int();
        let busy_index = h.int();
        let last_cid = h.int();
        let err = h.int();
        let error_axis = h.int();
        let override_pct = h.real();
        let simulated = h.int() != 0;
        let room = h.int();
        let stored = h.int();
        if busy_index < 0 || !(0..=6).contains(&error_axis) || room < 0 || stored < 0 {
            return Err(h.invalid("busy index, error axis, room or stored count out of range"));
        }
        let mut p = r.line("POS", "rrrrrrii")?;
        let position = Frame::read(&mut p);
        let (s, t) = (p.int(), p.int());
        if !(0..=7).contains(&s) || !(0..=63).contains(&t) {
            return Err(p.invalid("Status or Turn out of range"));
        }
        let mut a = r.line("AXS", "rrrrrr")?;
        let axes = [a.real(), a.real(), a.real(), a.real(), a.real(), a.real()];
        let tool = Frame::read(&mut r.line("TOL", "rrrrrr")?);
        let base = Frame::read(&mut r.line("BAS", "rrrrrr")?);
        let io = if r.peek_tag() == Some("IOS") {
            let mut l = r.line("IOS", "iii")?;
            let (b, i, o) = (l.int(), l.int(), l.int());
            let top = i32::from(MAX_IO_INDEX) - i32::from(IoState::WIDTH) + 1;
            if !(1..=top).contains(&b) || i < 0 || o < 0 {
                return Err(l.invalid("I/O base or bits out of range"));
            }
            Some(IoState {
                base: b as u16,
                inputs: i as u32,
                outputs: o as u32,
            })
        } else {
            None
        };
        let safety = if r.peek_tag() == Some("SAF") {
            let mut l = r.line("SAF", "iiiii")?;
            let v = [l.int(), l.int(), l.int(), l.int(), l.int()];
            if v[..4].iter().any(|b| !(0..=1).contains(b)) || !(0..=4).contains(&v[4]) {
                return Err(l.invalid("safety flags must be 0/1 and the program state 0..4"));
            }
            Some(SafetyState {
                drives_ready: v[0] == 1,
                user_safety: v[1] == 1,
                alarm_stop: v[2] == 1,
                stop_message: v[3] == 1,
                program_state: v[4] as u8,
            })
        } else {
            None
        };
        let analog = if r.peek_tag() == Some("ANS") {
            let mut l = r.line("ANS", "rrrrrrrrrrrrrrrr")?;
            let mut a = AnalogState::default();
            for v in a.inputs.iter_mut().chain(a.outputs.iter_mut()) {
                *v = l.real();
            }
            if a.inputs
                .iter()
                .chain(&a.outputs)
                .any(|v| !(-1.0..=1.0).contains(v))
            {
                return Err(l.invalid("analog values must be within -1..1"));
            }
            Some(a)
        } else {
            None
        };
        let mut e = r.line("END", "i")?;
        if e.int() != seq {
            return Err(e.invalid("END record does not match the header"));
        }
        r.finish()?;
        Ok(StateFile {
            seq,
            status,
            mode,
            busy_cid,
            busy_index: busy_index as u32,
            last_cid,
            error: (err != 0).then(|| ResultCode::from_code(err)),
            error_axis: error_axis as u8,
            override_pct,
            simulated,
            room: room as u32,
            stored: stored as u32,
            position,
            s: s as u8,
            t: t as u8,
            axes,
            tool,
            base,
            io,
            safety,
            analog,
        })
    }
}

/// The version of a file whose first line is a `tag` header of another
/// protocol version (its first field), whatever the rest of the line.
fn other_version(text: &str, tag: &str) -> Option<i64> {
    let line = text.lines().next()?;
    let mut fields = line.strip_prefix(tag)?.strip_prefix(' ')?.split(' ');
    let v: i64 = fields.next()?.parse().ok()?;
    (v != i64::from(PROTOCOL_VERSION)).then_some(v)
}

//! Motion requests as clients send them (coordinates may be omitted or
//! relative), and their resolution into the absolute protocol records the
//! controller executes.

use kuka_protocol::{Frame, MAX_SPLINE_POINTS, MotionParams, MotionRecord};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::error::{BridgeError, Result};
use crate::io::{IoConfig, IoKind};
use crate::settings::MotionConfig;

pub use crate::settings::Configuration;

/// A Cartesian target; omitted components keep their current value (the
/// previous motion's target inside a batch).
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"x": 200.0, "y": 0.0, "z": 70.0, "a": 0.0, "b": 180.0, "c": 0.0}))]
pub struct TargetSpec {
    /// X in mm.
    pub x: Option<f64>,
    /// Y in mm.
    pub y: Option<f64>,
    /// Z in mm.
    pub z: Option<f64>,
    /// A (about Z) in degrees.
    pub a: Option<f64>,
    /// B (about Y) in degrees.
    pub b: Option<f64>,
    /// C (about X) in degrees.
    pub c: Option<f64>,
    /// Status (0..=7), PTP only; always obeyed. Omitted: chosen by the
    /// PTP's `config` (`auto`: the bridge chooses; `keep`: the current
    /// Status).
    pub s: Option<i64>,
    /// Turn (0..=63), PTP only; always obeyed. Omitted: chosen with the
    /// Status (`auto`) or the shortest axis path (`keep`).
    pub t: Option<i64>,
}

impl TargetSpec {
    fn components(&self) -> [Option<f64>; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }
}

/// Auxiliary point of a CIRC (position only, as in KRL).
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize, Serialize, ToSchema)]
#[schema(example = json!({"x": 250.0, "y": 0.0}))]
#[serde(deny_unknown_fields)]
pub struct AuxPoint {
    /// X in mm.
    pub x: Option<f64>,
    /// Y in mm.
    pub y: Option<f64>,
    /// Z in mm.
    pub z: Option<f64>,
}

/// Axis angles; omitted axes keep their value.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize, Serialize, ToSchema)]
#[schema(example = json!({"a1": 30.0, "a5": 45.0}))]
#[serde(deny_unknown_fields)]
pub struct AxesSpec {
    /// A1 in degrees.
    pub a1: Option<f64>,
    /// A2 in degrees.
    pub a2: Option<f64>,
    /// A3 in degrees.
    pub a3: Option<f64>,
    /// A4 in degrees.
    pub a4: Option<f64>,
    /// A5 in degrees.
    pub a5: Option<f64>,
    /// A6 in degrees.
    pub a6: Option<f64>,
}

/// One motion. PTP/SPTP speeds are % of the maximum axis speed, the path
/// motions' (LIN, CIRC, SLIN, SCIRC, SPL) m/s; `approx_mm` > 0 blends into
/// the next motion of a batch (C_DIS for LIN/CIRC, C_SPL for the spline
/// motions; the two families never blend into each other, and a PTP/SPTP
/// always stops exactly). `relative: true` adds the given components to the
/// start of the motion. An omitted speed is the default speed, not the
/// previous motion's.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum MotionRequest {
    /// Point-to-point (synchronous axes) to a Cartesian target.
    #[schema(example = json!({"type": "ptp", "target": {"x": 200, "y": 0, "z": 200, "a": 0, "b": 90, "c": 0}}))]
    Ptp {
        /// Target.
        target: TargetSpec,
        /// Add to the start instead of replacing.
        #[serde(default)]
        relative: bool,
        /// % of max axis speed (default from config).
        velocity_pct: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm.
        approx_mm: Option<f64>,
        /// How the arm configuration is chosen when `s` is omitted
        /// (default: the request's `config`, else the site's
        /// `motion.configuration`, `auto` unless changed).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        config: Option<Configuration>,
    },
    /// Axis-specific PTP.
    PtpAxes {
        /// Target axis angles.
        axes: AxesSpec,
        /// Add to the start instead of replacing.
        #[serde(default)]
        relative: bool,
        /// % of max axis speed.
        velocity_pct: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm.
        approx_mm: Option<f64>,
    },
    /// Straight line of the TCP.
    #[schema(example = json!({"type": "lin", "target": {"x": 250, "y": 100}, "velocity_m_s": 0.1}))]
    Lin {
        /// Target.
        target: TargetSpec,
        /// Add to the start instead of replacing.
        #[serde(default)]
        relative: bool,
        /// TCP speed in m/s.
        velocity_m_s: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm.
        approx_mm: Option<f64>,
    },
    /// Circular arc through `aux` to `target`.
    Circ {
        /// Auxiliary point.
        aux: AuxPoint,
        /// End point.
        target: TargetSpec,
        /// Add both points to the start instead of replacing.
        #[serde(default)]
        relative: bool,
        /// TCP speed in m/s.
        velocity_m_s: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm.
        approx_mm: Option<f64>,
    },
    /// SLIN: a straight line of the spline family (KRL `SLIN`). Blends
    /// (`C_SPL`) only into spline motions (`slin`, `scirc`, `spl`); before
    /// a `ptp`/`lin`/`circ` the robot stops exactly, as on a KRC.
    #[schema(example = json!({"type": "slin", "target": {"x": 250, "y": 100}, "velocity_m_s": 0.1, "approx_mm": 5}))]
    Slin {
        /// Target.
        target: TargetSpec,
        /// Add to the start instead of replacing.
        #[serde(default)]
        relative: bool,
        /// TCP speed in m/s.
        velocity_m_s: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm (C_SPL).
        approx_mm: Option<f64>,
    },
    /// SCIRC: a circular arc of the spline family through `aux` to
    /// `target` (KRL `SCIRC`).
    Scirc {
        /// Auxiliary point.
        aux: AuxPoint,
        /// End point.
        target: TargetSpec,
        /// Add both points to the start instead of replacing.
        #[serde(default)]
        relative: bool,
        /// TCP speed in m/s.
        velocity_m_s: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm (C_SPL).
        approx_mm: Option<f64>,
    },
    /// SPTP: point-to-point of the spline family (KRL `SPTP`) to a
    /// Cartesian target; stops exactly at its end, like `ptp`.
    #[schema(example = json!({"type": "sptp", "target": {"x": 300, "y": 0, "z": 400, "a": 0, "b": 90, "c": 0}}))]
    Sptp {
        /// Target.
        target: TargetSpec,
        /// Add to the start instead of replacing.
        #[serde(default)]
        relative: bool,
        /// % of max axis speed (default from config).
        velocity_pct: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm (not used: an SPTP stops exactly).
        approx_mm: Option<f64>,
        /// How the arm configuration is chosen when `s` is omitted, as for
        /// `ptp`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        config: Option<Configuration>,
    },
    /// SPTP to axis angles (KRL `SPTP` to an E6AXIS, as `SPTP XHOME`):
    /// the spline family's axis PTP; stops exactly at its end, like
    /// `ptp_axes`, and follows its rules within a batch.
    #[schema(example = json!({"type": "sptp_axes", "axes": {"a1": 0, "a2": -90, "a3": 90, "a4": 0, "a5": 0, "a6": 0}}))]
    SptpAxes {
        /// Target axis angles.
        axes: AxesSpec,
        /// Add to the start instead of replacing.
        #[serde(default)]
        relative: bool,
        /// % of max axis speed.
        velocity_pct: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm (not used: an SPTP stops exactly).
        approx_mm: Option<f64>,
    },
    /// SPL: a point of a spline block (KRL `SPLINE … SPL … ENDSPLINE`).
    /// Consecutive `spl` motions of one request form a block: the TCP
    /// follows a smooth curve through their points without stopping. A
    /// block ends after 8 points, at a point with `approx_mm: 0`, where
    /// the speed or acceleration changes, and at the end of the request;
    /// the next block follows with the last point's approximation
    /// (`C_SPL`).
    #[schema(example = json!({"type": "spl", "target": {"x": 300, "y": 50}, "velocity_m_s": 0.2}))]
    Spl {
        /// The point.
        target: TargetSpec,
        /// Add to the previous point instead of replacing.
        #[serde(default)]
        relative: bool,
        /// TCP speed in m/s.
        velocity_m_s: Option<f64>,
        /// % of max acceleration.
        acceleration_pct: Option<f64>,
        /// Approximation distance in mm (C_SPL) where the block ends; 0
        /// ends the block here with an exact stop.
        approx_mm: Option<f64>,
    },
    /// An I/O action, not a motion: set a digital output when the robot
    /// passes this point of the sequence, i.e. as the next motion starts
    /// (KRL `TRIGGER WHEN DISTANCE=0`), without stopping the robot: the
    /// motions on either side blend as if it were not there. Before a
    /// `wait_input`/`dwell`, or at the end, it switches once the motions
    /// before it have ended. With `path_mm` it switches at that distance
    /// along the path from the end point of the motion before it (KRL
    /// `TRIGGER WHEN PATH`). Only outputs on the site's allow-list
    /// (`[io] outputs`, docs/IO.md).
    #[schema(example = json!({"type": "set_output", "signal": "glue_valve", "value": false, "path_mm": -5.0}))]
    SetOutput {
        /// The output: its number (1..=4096) or its configured name.
        signal: SignalRef,
        /// The value to set.
        value: bool,
        /// Return to the other value after this many ms (default: the
        /// signal's configured `pulse_ms`, else none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[schema(minimum = 0, maximum = 60000)]
        pulse_ms: Option<u32>,
        /// Switch at this distance in mm along the path from the end point
        /// of the motion before the action (KRL `TRIGGER WHEN PATH =
        /// path_mm DELAY = 0` on that motion): negative = that many mm
        /// before the end point (on that motion), positive = after it,
        /// along the next motion (the motion before must blend into it).
        /// Needs a `lin`, `circ`, `slin` or `scirc` before it in the same
        /// request (only other `set_output` actions between); a positive
        /// value also a motion after it into which that one blends. With a
        /// robot model, |path_mm| is at most the length of the motion
        /// before (negative) or after (positive). Else 422
        /// `invalid_input`. Omitted: as the next motion starts.
        /// Resolution 0.001 mm.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[schema(minimum = -5000, maximum = 5000)]
        path_mm: Option<f64>,
    },
    /// An I/O action: the robot stops exactly at the end of the motion
    /// before it and waits until the input has `value` (KRL `WAIT FOR`).
    /// If it does not within `timeout_ms`, the job fails with
    /// `input_timeout` and the robot stands there; nothing after it runs.
    #[schema(example = json!({"type": "wait_input", "signal": "part_present", "value": true, "timeout_ms": 2000}))]
    WaitInput {
        /// The input: its number (1..=4096) or its configured name.
        signal: SignalRef,
        /// The value waited for (default true).
        #[serde(default = "yes")]
        value: bool,
        /// Longest wait in ms, 1..=600000 (nothing waits for ever).
        #[schema(minimum = 1, maximum = 600000)]
        timeout_ms: u32,
    },
    /// The robot stops exactly at the end of the motion before it and
    /// stands for `ms` (KRL `WAIT SEC`).
    #[schema(example = json!({"type": "dwell", "ms": 500}))]
    Dwell {
        /// Standstill in ms, 0..=600000.
        #[schema(minimum = 0, maximum = 600000)]
        ms: u32,
    },
}

fn yes() -> bool {
    true
}

/// A digital signal in a request: its number or its configured name.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(
    untagged,
    expecting = "a signal number (1..=4096) or a configured name"
)]
pub enum SignalRef {
    /// `$IN`/`$OUT` index.
    Index(i64),
    /// A name from the site's `[io]` configuration.
    Name(String),
}

/// Replaces the signal names of `requests`' I/O actions by their numbers
/// and checks them: an output must be on the site's allow-list
/// (`output_not_allowed`), a name must exist (`unknown_signal`), a number
/// must be 1..=4096, a pulse at most 60000 ms, a timeout 1..=600000 ms. An
/// output's omitted `pulse_ms` becomes its configured pulse. Nothing with
/// an unchecked signal reaches the channel.
pub fn resolve_signals(requests: &mut [MotionRequest], io: &IoConfig) -> Result<()> {
    for (i, req) in requests.iter_mut().enumerate() {
        let at = |e: BridgeError| {
            let detail = format!("motion {i}: {}", e.detail);
            BridgeError { detail, ..e }.at_motion(i)
        };
        let (kind, signal) = match req {
            MotionRequest::SetOutput { signal, .. } => (IoKind::Output, signal),
            MotionRequest::WaitInput { signal, .. } => (IoKind::Input, signal),
            MotionRequest::Dwell { ms } => {
                if *ms > kuka_protocol::MAX_WAIT_MS {
                    return Err(at(BridgeError::invalid(format!(
                        "a dwell of {ms} ms is longer than {} ms",
                        kuka_protocol::MAX_WAIT_MS
                    ))));
                }
                continue;
            }
            _ => continue,
        };
        let text = match signal {
            SignalRef::Index(n) if (1..=i64::from(kuka_protocol::MAX_IO_INDEX)).contains(n) => {
                n.to_string()
            }
            SignalRef::Index(n) => {
                return Err(at(BridgeError::invalid(format!(
                    "signal {n} does not exist: indices are 1..={}",
                    kuka_protocol::MAX_IO_INDEX
                ))));
            }
            SignalRef::Name(name) => name.clone(),
        };
        let (index, config) = io.resolve(kind, &text).map_err(at)?;
        let configured_pulse = config.map(|c| c.pulse_ms).filter(|p| *p > 0);
        *signal = SignalRef::Index(i64::from(index));
        match req {
            MotionRequest::SetOutput { pulse_ms, .. } => {
                io.writable(index).map_err(at)?;
                let p = pulse_ms.or(configured_pulse).unwrap_or(0);
                if p > kuka_protocol::MAX_PULSE_MS {
                    return Err(at(BridgeError::invalid(format!(
                        "pulse_ms = {p} is above {} ms",
                        kuka_protocol::MAX_PULSE_MS
                    ))));
                }
                *pulse_ms = Some(p);
            }
            MotionRequest::WaitInput { timeout_ms, .. }
                if !(1..=kuka_protocol::MAX_WAIT_MS).contains(timeout_ms) =>
            {
                return Err(at(BridgeError::invalid(format!(
                    "timeout_ms = {timeout_ms} is not in 1..={} (nothing waits for ever)",
                    kuka_protocol::MAX_WAIT_MS
                ))));
            }
            _ => {}
        }
    }
    Ok(())
}

/// Most `set_output` actions with `path_mm` after one motion: the KRL
/// program issues one `TRIGGER WHEN PATH` each with the motion, besides
/// its own trigger (docs/CONTROLLER.md point 25).
pub const MAX_SWITCH_POINTS: usize = 4;

/// Why a `set_output` with `path_mm` without a motion before it is refused.
const NO_MOTION_BEFORE: &str = "a set_output with path_mm switches relative to the end point of \
     the motion before it: it needs a motion before it in the same request (only set_output \
     actions between)";

/// Checks where the `set_output` actions with `path_mm` of one request
/// switch (docs/IO.md, "I/O inside motions"): a finite distance of at most
/// [`kuka_protocol::MAX_TRIGGER_PATH_MM`], a `lin`, `circ`, `slin` or
/// `scirc` before the action in the same request (only other `set_output`
/// actions between: the KRL program attaches the trigger to that motion
/// when it plans it) and, for a positive distance, a motion after it into
/// which that one blends; at most [`MAX_SWITCH_POINTS`] after one motion.
/// The distance against the
/// motions' lengths is checked by the dry run with the robot model
/// (`Safety::check_resolved`).
pub fn check_switch_points(requests: &[MotionRequest]) -> Result<()> {
    for (i, req) in requests.iter().enumerate() {
        let MotionRequest::SetOutput {
            path_mm: Some(p), ..
        } = req
        else {
            continue;
        };
        let refuse =
            |why: String| Err(BridgeError::invalid(format!("motion {i}: {why}")).at_motion(i));
        if !p.is_finite() || p.abs() > kuka_protocol::MAX_TRIGGER_PATH_MM {
            return refuse(format!(
                "path_mm = {} is not within ±{} mm",
                crate::error::shown(*p),
                kuka_protocol::MAX_TRIGGER_PATH_MM
            ));
        }
        let is_sot = |r: &&MotionRequest| matches!(r, MotionRequest::SetOutput { .. });
        let Some(before) = requests[..i].iter().rev().find(|r| !is_sot(r)) else {
            return refuse(NO_MOTION_BEFORE.into());
        };
        if before.is_action() {
            return refuse(NO_MOTION_BEFORE.into());
        }
        // The KRL program arms at most MAX_SWITCH_POINTS path triggers on
        // one motion (docs/CONTROLLER.md point 25).
        let same_motion = requests[..i]
            .iter()
            .rev()
            .take_while(|r| is_sot(r))
            .filter(|r| {
                matches!(
                    r,
                    MotionRequest::SetOutput {
                        path_mm: Some(_),
                        ..
                    }
                )
            })
            .count();
        if same_motion >= MAX_SWITCH_POINTS {
            return refuse(format!(
                "more than {MAX_SWITCH_POINTS} set_output actions with path_mm after one motion"
            ));
        }
        let (lin_circ, slin_scirc) = (["lin", "circ"], ["slin", "scirc"]);
        let kind = before.kind();
        if !lin_circ.contains(&kind) && !slin_scirc.contains(&kind) {
            return refuse(format!(
                "a set_output with path_mm follows a {kind}: a KRL path trigger belongs to a lin, \
                 circ, slin or scirc (a PTP takes none, a spline block's points are static KRL); \
                 leave path_mm out, or move with a lin"
            ));
        }
        if *p > 0.0 {
            let after = requests[i + 1..].iter().find(|r| !is_sot(r));
            let blends = after.is_some_and(|a| {
                let next = a.kind();
                before.speed().2 != Some(0.0)
                    && if lin_circ.contains(&kind) {
                        lin_circ.contains(&next)
                    } else {
                        slin_scirc.contains(&next) || next == "spl"
                    }
            });
            if !blends {
                return refuse(format!(
                    "path_mm = {p} lies after the end point of the motion before it, where the robot \
                     stops exactly: a positive path_mm needs a motion after it in the same request \
                     into which the motion before blends (approx_mm not 0, the same motion family)"
                ));
            }
        }
    }
    Ok(())
}

/// For each `SOP` record (a `set_output` with `path_mm`) of `records`, the
/// record index, its distance and the motions it is measured along: the
/// motion before it (negative distance) or the motion after it (positive),
/// by record index. What [`check_switch_points`] let through has both.
pub fn switch_points(records: &[MotionRecord]) -> Vec<(usize, f64, usize)> {
    let is_sot = |r: &MotionRecord| matches!(r, MotionRecord::SetOutput { .. });
    records
        .iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let MotionRecord::SetOutput {
                path_mm: Some(p), ..
            } = r
            else {
                return None;
            };
            let motion = if *p < 0.0 {
                (0..i).rev().find(|&k| !is_sot(&records[k]))?
            } else {
                (i + 1..records.len()).find(|&k| !is_sot(&records[k]))?
            };
            Some((i, *p, motion))
        })
        .collect()
}

impl MotionRequest {
    /// The (S)PTP's `config`, if it is a Cartesian PTP that has one.
    pub fn config(&self) -> Option<Configuration> {
        match self {
            MotionRequest::Ptp { config, .. } | MotionRequest::Sptp { config, .. } => *config,
            _ => None,
        }
    }

    /// Gives a Cartesian (S)PTP without `config` this one.
    pub fn default_config(&mut self, c: Configuration) {
        if let MotionRequest::Ptp { config, .. } | MotionRequest::Sptp { config, .. } = self {
            config.get_or_insert(c);
        }
    }

    /// An I/O action or a dwell (`set_output`, `wait_input`, `dwell`), not
    /// a motion.
    pub fn is_action(&self) -> bool {
        matches!(
            self,
            MotionRequest::SetOutput { .. }
                | MotionRequest::WaitInput { .. }
                | MotionRequest::Dwell { .. }
        )
    }

    /// `ptp`, `ptp_axes`, `lin`, `circ`, `slin`, `scirc`, `sptp`, `spl`, or
    /// an action: `set_output`, `wait_input`, `dwell`.
    pub fn kind(&self) -> &'static str {
        match self {
            MotionRequest::Ptp { .. } => "ptp",
            MotionRequest::PtpAxes { .. } => "ptp_axes",
            MotionRequest::SptpAxes { .. } => "sptp_axes",
            MotionRequest::Lin { .. } => "lin",
            MotionRequest::Circ { .. } => "circ",
            MotionRequest::Slin { .. } => "slin",
            MotionRequest::Scirc { .. } => "scirc",
            MotionRequest::Sptp { .. } => "sptp",
            MotionRequest::Spl { .. } => "spl",
            MotionRequest::SetOutput { .. } => "set_output",
            MotionRequest::WaitInput { .. } => "wait_input",
            MotionRequest::Dwell { .. } => "dwell",
        }
    }

    /// PTP, axis PTP or SPTP (speed in %), as opposed to the path motions
    /// (speed in m/s).
    pub fn is_ptp(&self) -> bool {
        matches!(
            self,
            MotionRequest::Ptp { .. }
                | MotionRequest::PtpAxes { .. }
                | MotionRequest::Sptp { .. }
                | MotionRequest::SptpAxes { .. }
        )
    }

    /// `ptp_axes` or `sptp_axes`: a target in axis angles, whose
    /// Cartesian end only the controller computes.
    pub fn is_axis_ptp(&self) -> bool {
        matches!(
            self,
            MotionRequest::PtpAxes { .. } | MotionRequest::SptpAxes { .. }
        )
    }

    /// Its Cartesian target, if it has one (all but `ptp_axes`,
    /// `sptp_axes` and the actions).
    pub fn target(&self) -> Option<&TargetSpec> {
        match self {
            MotionRequest::Ptp { target, .. }
            | MotionRequest::Lin { target, .. }
            | MotionRequest::Circ { target, .. }
            | MotionRequest::Slin { target, .. }
            | MotionRequest::Scirc { target, .. }
            | MotionRequest::Sptp { target, .. }
            | MotionRequest::Spl { target, .. } => Some(target),
            MotionRequest::PtpAxes { .. }
            | MotionRequest::SptpAxes { .. }
            | MotionRequest::SetOutput { .. }
            | MotionRequest::WaitInput { .. }
            | MotionRequest::Dwell { .. } => None,
        }
    }

    /// `(velocity, acceleration_pct, approx_mm)` as given.
    pub fn speed(&self) -> (Option<f64>, Option<f64>, Option<f64>) {
        match self {
            MotionRequest::Ptp {
                velocity_pct,
                acceleration_pct,
                approx_mm,
                ..
            }
            | MotionRequest::Sptp {
                velocity_pct,
                acceleration_pct,
                approx_mm,
                ..
            }
            | MotionRequest::PtpAxes {
                velocity_pct,
                acceleration_pct,
                approx_mm,
                ..
            }
            | MotionRequest::SptpAxes {
                velocity_pct,
                acceleration_pct,
                approx_mm,
                ..
            } => (*velocity_pct, *acceleration_pct, *approx_mm),
            MotionRequest::Lin {
                velocity_m_s,
                acceleration_pct,
                approx_mm,
                ..
            }
            | MotionRequest::Circ {
                velocity_m_s,
                acceleration_pct,
                approx_mm,
                ..
            }
            | MotionRequest::Slin {
                velocity_m_s,
                acceleration_pct,
                approx_mm,
                ..
            }
            | MotionRequest::Scirc {
                velocity_m_s,
                acceleration_pct,
                approx_mm,
                ..
            }
            | MotionRequest::Spl {
                velocity_m_s,
                acceleration_pct,
                approx_mm,
                ..
            } => (*velocity_m_s, *acceleration_pct, *approx_mm),
            MotionRequest::SetOutput { .. }
            | MotionRequest::WaitInput { .. }
            | MotionRequest::Dwell { .. } => (None, None, None),
        }
    }
}

/// Where the robot is (or will be) when a motion starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StartPoint {
    /// TCP pose in the base frame.
    pub pose: Frame,
    /// Axis angles.
    pub axes: [f64; 6],
}

/// The current default speeds (settable through the API).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, ToSchema)]
#[schema(example = json!({"override_pct": 100.0, "ptp_velocity_pct": 20.0, "ptp_acceleration_pct": 100.0,
                          "cp_velocity_m_s": 0.25, "cp_acceleration_pct": 100.0}))]
pub struct SpeedSettings {
    /// Program override in % ($OV_PRO).
    pub override_pct: f64,
    /// Default PTP velocity in %.
    pub ptp_velocity_pct: f64,
    /// Default PTP acceleration in %.
    pub ptp_acceleration_pct: f64,
    /// Default LIN/CIRC velocity in m/s.
    pub cp_velocity_m_s: f64,
    /// Default LIN/CIRC acceleration in %.
    pub cp_acceleration_pct: f64,
}

impl SpeedSettings {
    /// Defaults from the configuration, override 100 %.
    pub fn from_config(m: &MotionConfig) -> Self {
        SpeedSettings {
            override_pct: 100.0,
            ptp_velocity_pct: m.default_ptp_velocity_pct,
            ptp_acceleration_pct: m.default_acceleration_pct,
            cp_velocity_m_s: m.default_cp_velocity,
            cp_acceleration_pct: m.default_acceleration_pct,
        }
    }
}

impl From<SpeedSettings> for kuka_protocol::SpeedRecord {
    fn from(s: SpeedSettings) -> Self {
        kuka_protocol::SpeedRecord {
            override_pct: s.override_pct,
            ptp_velocity_pct: s.ptp_velocity_pct,
            ptp_acceleration_pct: s.ptp_acceleration_pct,
            cp_velocity: s.cp_velocity_m_s,
            cp_acceleration_pct: s.cp_acceleration_pct,
        }
    }
}

/// A pose as the controller gets it: the file protocol carries thousandths
/// (so relative motions and appends do not gather floating-point noise).
fn thousandths(pose: [f64; 6]) -> Frame {
    Frame::from_array(pose.map(|v| (v * 1000.0).round() / 1000.0))
}

fn pick(given: Option<f64>, relative: bool, previous: f64) -> f64 {
    match (given, relative) {
        (Some(v), true) => previous + v,
        (Some(v), false) => v,
        (None, _) => previous,
    }
}

/// Gives every motion whose request leaves `approx_mm` out the default
/// approximation, the last one too: within a path the last motion of an
/// append blends into the next append's first (the robot stops exactly at
/// the path's end, where nothing follows).
pub fn set_default_approx(
    requests: &[MotionRequest],
    records: &mut [MotionRecord],
    default_approx_mm: f64,
) {
    for (req, rec) in requests.iter().zip(records) {
        if req.speed().2.is_none() {
            let params = match rec {
                MotionRecord::Ptp { params, .. }
                | MotionRecord::PtpAxes { params, .. }
                | MotionRecord::SptpAxes { params, .. }
                | MotionRecord::Lin { params, .. }
                | MotionRecord::Circ { params, .. }
                | MotionRecord::Slin { params, .. }
                | MotionRecord::Scirc { params, .. }
                | MotionRecord::Sptp { params, .. }
                | MotionRecord::Spl { params, .. } => params,
                MotionRecord::SetOutput { .. }
                | MotionRecord::WaitInput { .. }
                | MotionRecord::Dwell { .. } => continue,
            };
            params.approx_mm = default_approx_mm;
        }
    }
}

/// Resolves a batch against its start: omitted coordinates keep the
/// previous target's value, relative ones are added to it, speeds fall
/// back to the defaults; intermediate motions of a batch are approximated
/// by `default_approx_mm` unless set, the last one stops exactly unless set.
pub fn resolve(
    requests: &[MotionRequest],
    start: &StartPoint,
    speeds: &SpeedSettings,
    default_approx_mm: f64,
) -> Result<Vec<MotionRecord>> {
    let mut pose = start.pose.to_array();
    let mut axes = start.axes;
    // The last motion stops exactly unless set (the actions after it do
    // not move the robot).
    let last = requests
        .iter()
        .rposition(|r| !r.is_action())
        .unwrap_or(requests.len().saturating_sub(1));
    let mut out = Vec::with_capacity(requests.len());
    for (i, req) in requests.iter().enumerate() {
        let (vel, acc, apo) = req.speed();
        let is_ptp = req.is_ptp();
        let params = MotionParams {
            velocity: vel.unwrap_or(if is_ptp {
                speeds.ptp_velocity_pct
            } else {
                speeds.cp_velocity_m_s
            }),
            acceleration_pct: acc.unwrap_or(if is_ptp {
                speeds.ptp_acceleration_pct
            } else {
                speeds.cp_acceleration_pct
            }),
            approx_mm: apo.unwrap_or(if i == last { 0.0 } else { default_approx_mm }),
        };
        let st = |v: Option<i64>| v.and_then(|v| u8::try_from(v).ok());
        let index = |signal: &SignalRef| match signal {
            SignalRef::Index(n) => u16::try_from(*n)
                .ok()
                .filter(|n| (1..=kuka_protocol::MAX_IO_INDEX).contains(n))
                .ok_or_else(|| {
                    BridgeError::invalid(format!("motion {i}: signal {n} is not in 1..=4096"))
                        .at_motion(i)
                }),
            SignalRef::Name(name) => Err(BridgeError::invalid(format!(
                "motion {i}: signal {name:?} was not resolved (resolve_signals first)"
            ))
            .at_motion(i)),
        };
        let record = match req {
            MotionRequest::SetOutput {
                signal,
                value,
                pulse_ms,
                path_mm,
            } => MotionRecord::SetOutput {
                index: index(signal)?,
                value: *value,
                pulse_ms: pulse_ms.unwrap_or(0),
                // (as the protocol carries it: thousandths)
                path_mm: path_mm.map(|p| (p * 1000.0).round() / 1000.0),
            },
            MotionRequest::WaitInput {
                signal,
                value,
                timeout_ms,
            } => MotionRecord::WaitInput {
                index: index(signal)?,
                value: *value,
                timeout_ms: *timeout_ms,
            },
            MotionRequest::Dwell { ms } => MotionRecord::Dwell { ms: *ms },
            MotionRequest::Ptp {
                target, relative, ..
            } => {
                for (p, c) in pose.iter_mut().zip(target.components()) {
                    *p = pick(c, *relative, *p);
                }
                MotionRecord::Ptp {
                    target: thousandths(pose),
                    s: st(target.s),
                    t: st(target.t),
                    params,
                }
            }
            MotionRequest::Sptp {
                target, relative, ..
            } => {
                for (p, c) in pose.iter_mut().zip(target.components()) {
                    *p = pick(c, *relative, *p);
                }
                MotionRecord::Sptp {
                    target: thousandths(pose),
                    s: st(target.s),
                    t: st(target.t),
                    params,
                }
            }
            MotionRequest::Lin {
                target, relative, ..
            }
            | MotionRequest::Slin {
                target, relative, ..
            }
            | MotionRequest::Spl {
                target, relative, ..
            } => {
                for (p, c) in pose.iter_mut().zip(target.components()) {
                    *p = pick(c, *relative, *p);
                }
                let target = thousandths(pose);
                match req {
                    MotionRequest::Slin { .. } => MotionRecord::Slin { target, params },
                    // (Its block: `form_spline_blocks` below.)
                    MotionRequest::Spl { .. } => MotionRecord::Spl {
                        target,
                        params,
                        left: 1,
                    },
                    _ => MotionRecord::Lin { target, params },
                }
            }
            MotionRequest::Circ {
                aux,
                target,
                relative,
                ..
            }
            | MotionRequest::Scirc {
                aux,
                target,
                relative,
                ..
            } => {
                let aux = [
                    pick(aux.x, *relative, pose[0]),
                    pick(aux.y, *relative, pose[1]),
                    pick(aux.z, *relative, pose[2]),
                ];
                for (p, c) in pose.iter_mut().zip(target.components()) {
                    *p = pick(c, *relative, *p);
                }
                let target = thousandths(pose);
                if matches!(req, MotionRequest::Scirc { .. }) {
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
                }
            }
            MotionRequest::PtpAxes {
                axes: spec,
                relative,
                ..
            }
            | MotionRequest::SptpAxes {
                axes: spec,
                relative,
                ..
            } => {
                let given = [spec.a1, spec.a2, spec.a3, spec.a4, spec.a5, spec.a6];
                let after_cartesian = requests[..i]
                    .iter()
                    .any(|r| !r.is_action() && !r.is_axis_ptp());
                if after_cartesian && (*relative || given.iter().any(Option::is_none)) {
                    return Err(BridgeError::invalid(format!(
                        "motion {i}: an axis PTP after a Cartesian motion in the same batch must give all six axes absolutely"
                    ))
                    .at_motion(i));
                }
                for (a, g) in axes.iter_mut().zip(given) {
                    *a = pick(g, *relative, *a);
                }
                if matches!(req, MotionRequest::SptpAxes { .. }) {
                    MotionRecord::SptpAxes { axes, params }
                } else {
                    MotionRecord::PtpAxes { axes, params }
                }
            }
        };
        // After an axis PTP the Cartesian start of the next motion is only
        // known to the controller, so a batch cannot mix them that way.
        if req.is_axis_ptp() && i < last {
            let needs_pose = requests[i + 1..]
                .iter()
                .any(|r| !r.is_action() && !r.is_axis_ptp());
            if needs_pose {
                return Err(BridgeError::invalid(format!(
                    "motion {i}: an axis PTP may only be followed by other axis PTPs in one batch (its Cartesian end is computed by the controller); send the Cartesian motions in a later request (or, in a path, a later append)"
                ))
                .at_motion(i));
            }
        }
        out.push(record);
    }
    form_spline_blocks(requests, &mut out);
    Ok(out)
}

/// How many of the last `requests` form a spline block the next motion
/// could still continue: its `spl` points after the last complete block
/// (8 points, or ended by `approx_mm: 0` or a change of speed or
/// acceleration as [`resolve`] forms blocks; speeds compared as given).
/// A stream appends everything before them, so that its blocks do not
/// depend on how its bytes arrive.
pub fn open_spline_tail(requests: &[MotionRequest]) -> usize {
    let run = requests
        .iter()
        .rev()
        .take_while(|r| matches!(r, MotionRequest::Spl { .. }))
        .count();
    let mut block = 0;
    for (i, r) in requests[requests.len() - run..].iter().enumerate() {
        let ends = r.speed().2 == Some(0.0);
        let next = requests.get(requests.len() - run + i + 1);
        let (v, a, _) = r.speed();
        let changes = next.is_some_and(|n| (n.speed().0, n.speed().1) != (v, a));
        block += 1;
        if block == MAX_SPLINE_POINTS || ends || changes {
            block = 0;
        }
    }
    block
}

/// Groups each run of consecutive `spl` records into spline blocks of at
/// most [`MAX_SPLINE_POINTS`] points with the same speed and acceleration;
/// a point whose request sets `approx_mm: 0` ends its block (an exact
/// stop there). Sets every point's `left`.
fn form_spline_blocks(requests: &[MotionRequest], records: &mut [MotionRecord]) {
    let ends_block = |records: &[MotionRecord], i: usize| -> bool {
        let (MotionRecord::Spl { params, .. }, Some(MotionRecord::Spl { params: next, .. })) =
            (&records[i], records.get(i + 1))
        else {
            return true;
        };
        requests.get(i).is_some_and(|r| r.speed().2 == Some(0.0))
            || params.velocity != next.velocity
            || params.acceleration_pct != next.acceleration_pct
    };
    let mut i = 0;
    while i < records.len() {
        if !matches!(records[i], MotionRecord::Spl { .. }) {
            i += 1;
            continue;
        }
        let mut n = 1;
        while n < MAX_SPLINE_POINTS && !ends_block(records, i + n - 1) {
            n += 1;
        }
        for (k, rec) in records[i..i + n].iter_mut().enumerate() {
            if let MotionRecord::Spl { left, .. } = rec {
                *left = (n - k) as u8;
            }
        }
        i += n;
    }
}

//! Motion planning and timing for PTP, axis PTP, LIN and CIRC with
//! approximation: the trajectory the simulated controller executes and the
//! service's safety module dry-runs before sending anything.

use serde::{Deserialize, Serialize};

use crate::model::{Axes, IkError, RobotModel};
use crate::pose::Pose;

/// The geometric part of one motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum MotionKind {
    /// Cartesian PTP: synchronous axis motion to a TCP target.
    Ptp {
        /// TCP target in the base frame.
        target: Pose,
        /// Status, if the caller set it.
        s: Option<u8>,
        /// Turn, if the caller set it.
        t: Option<u8>,
    },
    /// Axis-specific PTP to axis angles (degrees).
    PtpAxes {
        /// Target axes.
        axes: Axes,
    },
    /// Straight line of the TCP with orientation interpolation.
    Lin {
        /// TCP target in the base frame.
        target: Pose,
    },
    /// Circular arc from the start through `aux` to `target`.
    Circ {
        /// Auxiliary point (only its position is used, as in KRL).
        aux: Pose,
        /// End point (position and orientation).
        target: Pose,
    },
}

/// One motion with its speed, acceleration and approximation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    /// What to do.
    pub kind: MotionKind,
    /// PTP: % of maximum axis speed (1..=100); LIN/CIRC: TCP speed in m/s.
    pub velocity: f64,
    /// % of maximum acceleration (1..=100).
    pub acceleration_pct: f64,
    /// Approximation distance in mm (C_DIS); 0 = exact stop at the end.
    pub approx_mm: f64,
}

/// Machine-wide planner settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanSettings {
    /// Program override $OV_PRO in % (scales all speeds).
    pub override_pct: f64,
    /// Maximum Cartesian acceleration at 100 % in m/s² ($ACC.CP).
    pub max_acc_cp: f64,
    /// Maximum axis acceleration at 100 % in deg/s² (one value per axis).
    pub max_acc_axis_deg_s2: [f64; 6],
    /// Sample period of the returned trajectory in seconds (KRC IPO: 0.012).
    pub sample_period_s: f64,
}

impl Default for PlanSettings {
    fn default() -> Self {
        todo!("helper")
    }
}

/// One point of an executed trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Time since the start of the batch in seconds.
    pub t: f64,
    /// Index of the motion in the batch this sample belongs to.
    pub motion: usize,
    /// Axis angles.
    pub axes: Axes,
    /// TCP pose in the base frame.
    pub pose: Pose,
}

/// Why a motion could not be (fully) executed; KRC-like.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    /// Target or a path point cannot be reached.
    #[error(transparent)]
    Ik(#[from] IkError),
    /// The path passes through (or too close to) a singularity.
    #[error("path passes a singularity ({0})")]
    Singularity(&'static str),
    /// Geometry is degenerate (e.g. CIRC points collinear or coincident).
    #[error("invalid motion geometry: {0}")]
    Geometry(&'static str),
    /// A parameter is out of range (speed, acceleration, ...).
    #[error("invalid parameter: {0}")]
    Parameter(&'static str),
}

/// The outcome of planning a batch: what would actually be executed.
#[derive(Debug, Clone, PartialEq)]
pub struct Execution {
    /// Sampled trajectory, from the start pose to the end (or the error point).
    pub samples: Vec<Sample>,
    /// Axis angles at the end (or where the error stopped the robot).
    pub end_axes: Axes,
    /// Total time of the trajectory in seconds.
    pub duration_s: f64,
    /// The first failing motion (index) and why; motions before it are executed.
    pub error: Option<(usize, MotionError)>,
}

/// Plans a batch of motions from `start`, blending consecutive motions that
/// have `approx_mm > 0`.
pub fn plan(
    model: &RobotModel,
    start: &Axes,
    tool: &Pose,
    base: &Pose,
    motions: &[Motion],
    settings: &PlanSettings,
) -> Execution {
    todo!("helper")
}

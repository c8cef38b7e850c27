//! Robot models (OPW geometry, software limit switches, axis speeds, home),
//! forward and inverse kinematics in KUKA conventions, Status and Turn.

use serde::{Deserialize, Serialize};

use crate::pose::Pose;

/// Axis angles A1..A6 in degrees (pendant angles).
pub type Axes = [f64; 6];

/// Why no axis solution was found for a Cartesian target.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IkError {
    /// No solution at all: the target is outside the workspace.
    #[error("target is out of reach of the robot")]
    Unreachable,
    /// Solutions exist but every one violates a software limit switch;
    /// `axis` is 1-based, `value` the angle of the closest candidate.
    #[error("axis A{axis} would be at {value:.3}° outside its software limits [{min:.1}°, {max:.1}°]")]
    SoftwareLimit {
        /// 1-based axis number.
        axis: u8,
        /// Angle the axis would have (degrees).
        value: f64,
        /// Negative limit (degrees).
        min: f64,
        /// Positive limit (degrees).
        max: f64,
    },
    /// No solution matches the requested Status/Turn.
    #[error("no solution with Status {s} and Turn {t}")]
    NoMatchingConfiguration {
        /// Requested Status.
        s: u8,
        /// Requested Turn.
        t: u8,
    },
}

/// Geometry and machine data of one robot type.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobotModel {
    /// Model id, e.g. `kr3_r540`.
    pub name: String,
    /// OPW lengths in mm: a1, a2, b, c1, c2, c3, c4 (see rs-opw-kinematics).
    pub opw_mm: [f64; 7],
    /// Software limit switches per axis (degrees): ($SOFTN_END, $SOFTP_END).
    pub limits_deg: [(f64, f64); 6],
    /// Maximum axis speeds in deg/s.
    pub max_speed_deg_s: [f64; 6],
    /// Home position (axis angles, degrees).
    pub home: Axes,
}

impl RobotModel {
    /// KUKA KR 3 R540 (the default: closest public match to the OrangeApps ERS).
    pub fn kr3_r540() -> Self {
        todo!("helper")
    }
    /// KUKA KR 6 R700 sixx.
    pub fn kr6_r700_sixx() -> Self {
        todo!("helper")
    }
    /// KUKA KR 6 R900 sixx.
    pub fn kr6_r900_sixx() -> Self {
        todo!("helper")
    }
    /// KUKA KR 10 R1100 sixx.
    pub fn kr10_r1100_sixx() -> Self {
        todo!("helper")
    }
    /// Looks a built-in model up by id (`kr3_r540`, `kr6_r700_sixx`, `kr6_r900_sixx`, `kr10_r1100_sixx`).
    pub fn by_name(name: &str) -> Option<Self> {
        todo!("helper")
    }
    /// Ids of all built-in models.
    pub fn builtin_names() -> &'static [&'static str] {
        &["kr3_r540", "kr6_r700_sixx", "kr6_r900_sixx", "kr10_r1100_sixx"]
    }

    /// Flange pose in the robot root frame ($ROBROOT) for these axes.
    pub fn flange(&self, axes: &Axes) -> Pose {
        todo!("helper")
    }

    /// TCP pose in the base frame: `inv(base) · flange(axes) · tool`.
    pub fn forward(&self, axes: &Axes, tool: &Pose, base: &Pose) -> Pose {
        todo!("helper")
    }

    /// KUKA Status bits for these axes (bit 0 overhead, bit 1 elbow A3 ≥ φ, bit 2 A5 < 0).
    pub fn status(&self, axes: &Axes) -> u8 {
        todo!("helper")
    }

    /// KUKA Turn bits for these axes (bit n set when axis n+1 < 0).
    pub fn turn(axes: &Axes) -> u8 {
        todo!("helper")
    }

    /// First axis (1-based) outside its software limits, as an `IkError::SoftwareLimit`.
    pub fn check_limits(&self, axes: &Axes) -> Result<(), IkError> {
        todo!("helper")
    }

    /// Axis solution for a TCP target in the base frame, KUKA style: with
    /// `s`/`t` given, the solution with exactly that Status/Turn; without,
    /// keep the current Status and take the shortest axis path from
    /// `current`. Only solutions within software limits are returned.
    pub fn inverse(
        &self,
        target: &Pose,
        tool: &Pose,
        base: &Pose,
        s: Option<u8>,
        t: Option<u8>,
        current: &Axes,
    ) -> Result<Axes, IkError> {
        todo!("helper")
    }

    /// Solution closest to `previous` (continuous path following for
    /// LIN/CIRC sampling): no limit filtering, no S/T selection.
    pub fn inverse_continuing(
        &self,
        target: &Pose,
        tool: &Pose,
        base: &Pose,
        previous: &Axes,
    ) -> Option<Axes> {
        todo!("helper")
    }
}

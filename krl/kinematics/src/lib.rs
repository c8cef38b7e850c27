//! KUKA robot models and kinematics in KUKA conventions.
//!
//! Positions are KUKA FRAMEs (mm, degrees; A, B, C rotate about Z, Y, X:
//! R = Rz(A)·Ry(B)·Rx(C)), axis angles are pendant angles in degrees.
//! Inverse kinematics come from rs-opw-kinematics; this crate adds KUKA's
//! flange/tool/base frames, Status/Turn, software limit switches and the
//! motion planner shared by the simulated controller and the service's
//! safety checks, and the configuration planning that chooses Status and
//! Turn when a client gives none ([`configure`]).
#![deny(missing_docs)]

pub mod configure;
pub mod model;
pub mod plan;
pub mod pose;

pub use configure::{ConfigError, ConfigMode, Margins};
pub use model::{
    Axes, IkError, LIMIT_TOL_DEG, RobotModel, ST_MATCH_TOL_DEG, ST_MATCH_TOL_MM, TURN_MATCH_TOL_DEG,
};
pub use plan::{Execution, Motion, MotionError, MotionKind, PlanSettings, Sample, catmull_rom};
pub use pose::Pose;

//! The simulator's KRL interpreter (placeholder: being written).
//!
//! Runs an uploaded program's syntax tree ([`kuka_krl`]) ahead of motion,
//! like KRL's advance run, and turns it into the motions and dwells the
//! controller plays back.

use kuka_kinematics::{Axes, Motion, Pose, RobotModel};
use kuka_krl::Program;
use kuka_protocol::SpeedRecord;

/// What the program starts from.
#[derive(Debug, Clone)]
pub struct Start<'a> {
    /// The robot model (for forward kinematics of axis targets and `$AXIS_ACT`).
    pub model: &'a RobotModel,
    /// Current axis angles.
    pub axes: Axes,
    /// Current `$TOOL`.
    pub tool: Pose,
    /// Current `$BASE`.
    pub base: Pose,
    /// Current default speeds (`$VEL_AXIS` %, `$ACC_AXIS` %, `$VEL.CP` m/s, `$ACC.CP` %).
    pub speed: SpeedRecord,
}

/// One thing for the controller to do, with the source line it came from.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A motion, planned with this tool and base.
    Move {
        /// `$TOOL` in effect.
        tool: Pose,
        /// `$BASE` in effect.
        base: Pose,
        /// The motion (targets are TCP poses in `base`, as the planner takes them).
        motion: Motion,
        /// Source line.
        line: u32,
    },
    /// `WAIT SEC`: stand still.
    Dwell {
        /// Seconds.
        seconds: f64,
        /// Source line.
        line: u32,
    },
}

/// A statement, expression or system variable outside the simulator's subset.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {what} is not supported by the simulator")]
pub struct Unsupported {
    /// Source line.
    pub line: u32,
    /// What is not supported.
    pub what: String,
}

/// Why a program could not be run.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RunError {
    /// Outside the subset.
    #[error(transparent)]
    Unsupported(#[from] Unsupported),
    /// A runtime error (undefined variable, type mismatch, endless loop…).
    #[error("line {line}: {message}")]
    Runtime {
        /// Source line.
        line: u32,
        /// What went wrong.
        message: String,
    },
}

/// Refuses, before anything runs, every statement outside the subset.
pub fn check_subset(program: &Program) -> Result<(), Unsupported> {
    let _ = program;
    Ok(())
}

/// Runs `entry` and returns the steps it produces.
pub fn run(program: &Program, entry: &str, start: &Start<'_>) -> Result<Vec<Step>, RunError> {
    let _ = (program, entry, start);
    Ok(Vec::new())
}

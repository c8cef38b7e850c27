//! Playing a program's steps: grouping interpreter [`Step`]s into phases
//! (consecutive motions with the same tool and base plan as one blended
//! batch; a dwell stands alone), and planning a whole run ahead — the dry
//! run the service's safety gate does before it sends a RUN command. The
//! simulated controller plays the same phases, so the dry run and the
//! execution agree.

use std::collections::VecDeque;

use kuka_kinematics::plan::{self, PlanSettings};
use kuka_kinematics::{Axes, Motion, MotionError, Pose, RobotModel};

use crate::interp::{self, RunError, Start, Step};

/// Steps that play as one execution.
#[derive(Debug, Clone, PartialEq)]
pub enum Phase {
    /// Motions with one tool and base: one blended batch.
    Moves {
        /// `$TOOL` in effect.
        tool: Pose,
        /// `$BASE` in effect.
        base: Pose,
        /// The motions.
        motions: Vec<Motion>,
        /// Source line of each motion.
        lines: Vec<u32>,
    },
    /// `WAIT SEC`.
    Dwell {
        /// Seconds.
        seconds: f64,
        /// Source line.
        line: u32,
    },
}

/// Why a module could not be turned into steps.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PrepareError {
    /// The module does not parse.
    #[error(transparent)]
    Parse(#[from] kuka_krl::ProgramError),
    /// The interpreter refused or failed (outside the subset, runtime
    /// error, or the run did not end within its limits).
    #[error(transparent)]
    Run(#[from] RunError),
}

/// Stack size for a thread that runs [`interpret`] (the service's dry run,
/// the simulated controller's program thread): 8 MiB.
///
/// A margin, not a requirement: the parser's limits ([`kuka_krl::limits`])
/// and the interpreter's ([`interp::MAX_NESTING`], [`interp::MAX_CALL_DEPTH`])
/// keep the deepest program within about 1.4 MiB of stack in a debug build,
/// so it runs on the default 2 MiB of a spawned thread too (tested in
/// `tests/limits.rs`); release builds need far less. Stack memory is
/// reserved, not committed: the unused part costs nothing.
pub const DRY_RUN_STACK_BYTES: usize = 8 * 1024 * 1024;

/// Parses module `module` (its `.src` and optional `.dat`) and runs it
/// ahead with the interpreter from `start`: what the simulated controller
/// plays and what the service's dry run checks.
pub fn interpret(
    src: &str,
    dat: Option<&str>,
    module: &str,
    start: &Start<'_>,
) -> Result<Vec<Step>, PrepareError> {
    let program = kuka_krl::Program::parse(src, dat, Some(module))?;
    Ok(interp::run(&program, module, start)?)
}

/// Groups interpreter steps into phases, in order.
pub fn phases(steps: Vec<Step>) -> VecDeque<Phase> {
    let mut out: VecDeque<Phase> = VecDeque::new();
    for step in steps {
        match step {
            Step::Move {
                tool,
                base,
                motion,
                line,
            } => {
                if let Some(Phase::Moves {
                    tool: t,
                    base: b,
                    motions,
                    lines,
                }) = out.back_mut()
                    && *t == tool
                    && *b == base
                {
                    motions.push(motion);
                    lines.push(line);
                    continue;
                }
                out.push_back(Phase::Moves {
                    tool,
                    base,
                    motions: vec![motion],
                    lines: vec![line],
                });
            }
            Step::Dwell { seconds, line } => out.push_back(Phase::Dwell { seconds, line }),
        }
    }
    out
}

/// Where a dry run stopped: the source line and the planner's error.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}: {error}")]
pub struct DryRunError {
    /// Source line of the failing motion.
    pub line: u32,
    /// Why it cannot be executed.
    pub error: MotionError,
}

/// Plans every phase from `start` in order, as the controller will play
/// them; returns the axes at the end, or the first failing motion's line.
pub fn dry_run(
    model: &RobotModel,
    start: &Axes,
    phases: &VecDeque<Phase>,
    settings: &PlanSettings,
) -> Result<Axes, DryRunError> {
    let mut axes = *start;
    for phase in phases {
        if let Phase::Moves {
            tool,
            base,
            motions,
            lines,
        } = phase
        {
            let e = plan::plan(model, &axes, tool, base, motions, settings);
            if let Some((i, error)) = e.error {
                return Err(DryRunError {
                    line: lines.get(i).copied().unwrap_or(0),
                    error,
                });
            }
            axes = e.end_axes;
        }
    }
    Ok(axes)
}

//! Configuration planning: which arm configuration (Status and Turn) each
//! Cartesian PTP of a batch gets when the caller did not say.
//!
//! A KRC keeps the current Status for a PTP without `S` ([`ConfigMode::Keep`],
//! [`RobotModel::inverse`]); a user who never sends S/T then fails as soon as
//! the kept Status cannot reach a target, or reaches one from which the next
//! LIN cannot go on (LIN and CIRC never change the Status). With
//! [`ConfigMode::Auto`] the planner chooses, for each such PTP, among every
//! solution inside the software limits, as a careful programmer would:
//!
//! 1. the PTP's own target is reachable (every candidate is);
//! 2. every LIN/CIRC after it, up to the next PTP, is executable from that
//!    configuration (planned as the dry run plans it: reachability, limits
//!    and singularities along the path);
//! 3. among those, first the ones that keep a margin ([`Margins`]) from the
//!    singularities (A5 = 0, the wrist on the A1 axis, the stretched arm),
//!    then the least axis travel from where the PTP starts, weighted by
//!    each axis' speed so that the fast wrist axes A4–A6 count less (the
//!    idea of KUKA's KUE_WEG: the shortest motion in time).
//!
//! The chosen S/T are written into the motion, so the controller executes
//! exactly that configuration and a client can replay it. If no
//! configuration satisfies 2., the batch is refused before anything is sent
//! ([`ConfigError::NoConfiguration`]), naming the motion, the first motion
//! that failed and the configurations tried. An explicit `s` is always
//! obeyed; a PTP with only `t` keeps that Turn.

use serde::{Deserialize, Serialize};

use crate::model::{Axes, IkError, RobotModel};
use crate::plan::{self, Motion, MotionError, MotionKind, PlanSettings, Sample};
use crate::pose::Pose;

/// How a Cartesian PTP without `s` gets its configuration.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ConfigMode {
    /// The planner chooses (module documentation).
    #[default]
    Auto,
    /// KUKA's rule: keep the current Status, shortest Turn.
    Keep,
}

/// How far from each singularity `auto` prefers to stay.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Margins {
    /// |A5| at least this (degrees): the wrist singularity.
    pub wrist_deg: f64,
    /// |A3 − φ| at least this (degrees): the stretched arm.
    pub elbow_deg: f64,
    /// The wrist point at least this far (mm) from the A1 axis.
    pub overhead_mm: f64,
}

impl Default for Margins {
    /// 5°, 5°, 50 mm.
    fn default() -> Self {
        Margins {
            wrist_deg: 5.0,
            elbow_deg: 5.0,
            overhead_mm: 50.0,
        }
    }
}

impl Margins {
    /// How many margins these axes violate (0 = clear of all three).
    pub fn violations(&self, model: &RobotModel, axes: &Axes) -> u8 {
        u8::from(axes[4].abs() < self.wrist_deg)
            + u8::from((axes[2] - model.elbow_angle_deg()).abs() < self.elbow_deg)
            + u8::from(model.wrist_in_a1_frame(axes).0.abs() < self.overhead_mm)
    }
}

/// The configuration one Cartesian PTP got.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Chosen {
    /// Status.
    pub s: u8,
    /// Turn.
    pub t: u8,
    /// The axes at the PTP's target.
    pub axes: Axes,
}

/// A configuration `auto` tried and why it could not be used.
#[derive(Debug, Clone, PartialEq)]
pub struct Tried {
    /// Status.
    pub s: u8,
    /// Turn.
    pub t: u8,
    /// The first motion (batch index) that failed from it.
    pub failed_motion: usize,
    /// Why.
    pub error: Failure,
}

/// Why a configuration could not be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Failure {
    /// A motion cannot be executed from it (reachability, limits,
    /// singularities).
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// The swept path breaks a workspace rule ([`Context::path_check`]).
    #[error("{0}")]
    Path(String),
}

/// Why no configuration could be chosen.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// Every configuration that reaches the PTP's target fails on a later
    /// LIN/CIRC (or none reaches the target within the limits).
    #[error("{}", describe(*.index, tried))]
    NoConfiguration {
        /// The PTP (batch index) whose configuration was to be chosen.
        index: usize,
        /// Every configuration tried, best first.
        tried: Vec<Tried>,
    },
    /// No configuration reaches the PTP's target within the software
    /// limits at all.
    #[error("{}", describe_out_of_reach(*.index, per_status))]
    OutOfReach {
        /// The PTP (batch index).
        index: usize,
        /// Why each Status (0..=7) fails.
        per_status: Vec<(u8, IkError)>,
    },
}

fn describe_out_of_reach(index: usize, per_status: &[(u8, IkError)]) -> String {
    let list: Vec<String> = per_status
        .iter()
        .map(|(s, e)| format!("S {s}: {e}"))
        .collect();
    format!(
        "motion {index}: no arm configuration reaches this target within the software limits ({})",
        list.join("; ")
    )
}

fn describe(index: usize, tried: &[Tried]) -> String {
    let list: Vec<String> = tried
        .iter()
        .take(8)
        .map(|c| {
            format!(
                "S {} T {}: motion {}: {}",
                c.s, c.t, c.failed_motion, c.error
            )
        })
        .collect();
    format!(
        "motion {index}: no arm configuration of this PTP (or SPTP) lets the Cartesian motions after it run; tried {} ({})",
        tried.len(),
        list.join("; ")
    )
}

/// Most configurations tried per PTP (each costs a plan of the motions
/// after it); a target has at most 8 Status values, the Turn variants of
/// each are ordered by travel.
pub const MAX_TRIED: usize = 16;

/// Checks a planned path against rules the planner does not know (the
/// service's workspace box and keep-out zones): given the batch index of
/// the first planned motion and the samples, the batch index of the motion
/// where the path breaks a rule and why, or `None`.
pub type PathCheck<'a> = &'a dyn Fn(usize, &[Sample]) -> Option<(usize, String)>;

/// What configuration planning works with: the robot, its tool and base,
/// the planner's settings, the singularity margins and an optional check of
/// the swept path.
#[derive(Clone, Copy)]
pub struct Context<'a> {
    /// The robot.
    pub model: &'a RobotModel,
    /// Tool frame of the motions.
    pub tool: &'a Pose,
    /// Base frame of the motions.
    pub base: &'a Pose,
    /// Planner settings (as the dry run uses them).
    pub settings: &'a PlanSettings,
    /// Singularity margins.
    pub margins: &'a Margins,
    /// With it, a configuration is also dropped when the PTP's own joint
    /// path or the motions after it break the check.
    pub path_check: Option<PathCheck<'a>>,
}

/// Chooses the configuration of every Cartesian PTP whose mode is
/// [`ConfigMode::Auto`] and that has no `s` (the module documentation has
/// the rules). `modes[i]` is motion i's mode (missing: `Auto`). Returns,
/// per motion, the configuration chosen (`None`: not chosen here — not a
/// Cartesian PTP, `s` given, or `Keep`). Errors other than a missing
/// configuration (a bad parameter, a LIN that fails whatever was chosen
/// before it) are left to the dry run, which reports them with the motion.
pub fn choose(
    cx: &Context<'_>,
    start: &Axes,
    motions: &[Motion],
    modes: &[ConfigMode],
) -> Result<Vec<Option<Chosen>>, ConfigError> {
    let Context {
        model,
        tool,
        base,
        settings,
        ..
    } = *cx;
    let n = motions.len();
    let mut out = vec![None; n];
    let mut axes = *start;
    let mut i = 0;
    while i < n {
        // The block: this motion and the LIN/CIRCs after it, up to the next PTP.
        let end = (i + 1..n)
            .find(|&j| {
                matches!(
                    motions[j].kind,
                    MotionKind::Ptp { .. } | MotionKind::PtpAxes { .. }
                )
            })
            .unwrap_or(n);
        let tail = &motions[i + 1..end];
        match &motions[i].kind {
            MotionKind::Ptp { target, s: None, t }
                if modes.get(i).copied().unwrap_or_default() == ConfigMode::Auto =>
            {
                // Where the block ends comes with the choice (its tail was
                // planned from it).
                let (chosen, block_end) = choose_one(cx, &axes, &motions[i], target, *t, tail, i)?;
                out[i] = Some(chosen);
                axes = block_end;
            }
            _ => {
                // As given: the dry run reports a failure here.
                let run = plan::plan(model, &axes, tool, base, &motions[i..end], settings);
                if run.error.is_some() {
                    return Ok(out);
                }
                axes = run.end_axes;
            }
        }
        i = end;
    }
    Ok(out)
}

/// The configuration of one PTP: the first candidate, in the order of the
/// module documentation, from which `tail` plans without an error, and the
/// axes where `tail` then ends.
fn choose_one(
    cx: &Context<'_>,
    from: &Axes,
    ptp: &Motion,
    target: &Pose,
    t: Option<u8>,
    tail: &[Motion],
    index: usize,
) -> Result<(Chosen, Axes), ConfigError> {
    let Context {
        model,
        tool,
        base,
        settings,
        margins,
        path_check,
    } = *cx;
    let mut candidates: Vec<(Axes, u8, u8)> = model
        .solutions(target, tool, base, from)
        .into_iter()
        .filter(|(a, _, _)| t.is_none_or(|t| model.matches(a, 0, 0, Some(t))))
        .collect();
    // `solutions` sorts by travel; a stable sort keeps that within each
    // margin class.
    candidates.sort_by_key(|(a, _, _)| margins.violations(model, a));
    if candidates.is_empty() {
        let per_status: Vec<(u8, IkError)> = (0..8u8)
            .filter_map(|s| {
                model
                    .inverse(target, tool, base, Some(s), t, from)
                    .err()
                    .map(|e| (s, e))
            })
            .collect();
        return Err(ConfigError::OutOfReach { index, per_status });
    }
    let mut tried = Vec::new();
    for (axes, s, t) in candidates.into_iter().take(MAX_TRIED) {
        let fail = |k: usize, error: Failure| Tried {
            s,
            t,
            failed_motion: k,
            error,
        };
        let Some(check) = path_check else {
            // The tail alone, from the candidate.
            let run = plan::plan(model, &axes, tool, base, tail, settings);
            match run.error {
                None => return Ok((Chosen { s, t, axes }, run.end_axes)),
                Some((k, e)) => tried.push(fail(index + 1 + k, e.into())),
            }
            continue;
        };
        // The PTP's own joint path too (as an axis PTP to the candidate),
        // then the tail, all checked against the path rules.
        let mut run_motions = Vec::with_capacity(tail.len() + 1);
        run_motions.push(Motion {
            kind: MotionKind::PtpAxes { axes },
            approx_mm: 0.0,
            ..ptp.clone()
        });
        run_motions.extend_from_slice(tail);
        let run = plan::plan(model, from, tool, base, &run_motions, settings);
        // A motion that cannot run at all is the first reason; then the
        // path rules.
        if let Some((k, e)) = run.error {
            tried.push(fail(index + k, e.into()));
            continue;
        }
        match check(index, &run.samples) {
            Some((k, why)) => tried.push(fail(k, Failure::Path(why))),
            None => return Ok((Chosen { s, t, axes }, run.end_axes)),
        }
    }
    Err(ConfigError::NoConfiguration { index, tried })
}

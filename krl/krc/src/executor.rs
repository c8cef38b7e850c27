//! The robot's motion: the queue the advance run fills, planned by the
//! kinematics planner and played in simulated time, with blending,
//! exact stops, path triggers and BRAKE.
//!
//! A **chain** is a run of motions planned together from a standstill:
//! a motion joins the chain being played if the chain's last motion is
//! approximated, has the same tool and base, and the robot has not yet
//! started that last motion — the advance run delivered the motion in
//! time, as a KRC needs it to blend. Otherwise it waits for the chain to
//! end and starts a new one: an exact stop. A joining motion re-plans the
//! chain from its start (the planner is deterministic, so the part
//! already played stays the same up to the new blend).

use std::collections::VecDeque;

use kuka_kinematics::plan::{self, Execution, PlanSettings};
use kuka_kinematics::{Axes, Motion, MotionError, Pose, RobotModel};
use kuka_krl_runtime::interp::{Step, TriggerAt};

/// A motion waiting in the advance run.
struct Queued {
    tool: Pose,
    base: Pose,
    motion: Motion,
    line: u32,
    triggers: Vec<TriggerAt>,
}

/// Motions being played.
/// Plans a chain's motions from its start (again, when motions joined).
fn plan_chain(model: &RobotModel, settings: &PlanSettings, chain: &Chain) -> Execution {
    plan::plan(
        model,
        &chain.start,
        &chain.tool,
        &chain.base,
        &chain.motions,
        settings,
    )
}

struct Chain {
    start: Axes,
    tool: Pose,
    base: Pose,
    motions: Vec<Motion>,
    lines: Vec<u32>,
    triggers: Vec<Vec<TriggerAt>>,
    exec: Execution,
    /// Seconds played.
    t: f64,
    /// Triggers already fired.
    fired: Vec<u64>,
}

/// A motion that failed.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct MotionFailure {
    pub(crate) line: u32,
    pub(crate) error: MotionError,
}

/// The robot's motion state.
pub(crate) struct Executor {
    model: RobotModel,
    settings: PlanSettings,
    /// Current axes.
    pub(crate) axes: Axes,
    /// Tool and base of the last motion (for the trace's pose).
    pub(crate) tool: Pose,
    pub(crate) base: Pose,
    queue: VecDeque<Queued>,
    chain: Option<Chain>,
    /// BRAKE: the chain is held where it is.
    pub(crate) braked: bool,
    /// Index of the motion being played in its chain (for the trace).
    pub(crate) motion_index: usize,
    /// Seconds spent moving.
    pub(crate) moving_s: f64,
    /// Motions completed.
    pub(crate) motions_done: u64,
    /// Motions whose start was an exact stop (a new chain).
    pub(crate) chains_started: u64,
    /// Errors of motions, oldest first (bounded).
    pub(crate) failures: Vec<MotionFailure>,
    /// A motion failed since the scheduler last looked: the robot stopped
    /// (the scheduler puts the program into an error stop).
    pub(crate) failed: bool,
}

impl Executor {
    pub(crate) fn new(model: RobotModel, settings: PlanSettings, axes: Axes) -> Self {
        Executor {
            model,
            settings,
            axes,
            tool: Pose::IDENTITY,
            base: Pose::IDENTITY,
            queue: VecDeque::new(),
            chain: None,
            braked: false,
            motion_index: 0,
            moving_s: 0.0,
            motions_done: 0,
            chains_started: 0,
            failures: Vec::new(),
            failed: false,
        }
    }

    /// The robot stands and nothing is queued.
    pub(crate) fn idle(&self) -> bool {
        self.chain.is_none() && self.queue.is_empty()
    }

    /// Whether the robot is moving now.
    pub(crate) fn moving(&self) -> bool {
        self.chain.is_some() && !self.braked
    }

    /// Motions planned but not started (the advance run's content).
    pub(crate) fn ahead(&self) -> usize {
        let in_chain = self
            .chain
            .as_ref()
            .map_or(0, |c| c.motions.len().saturating_sub(self.motion_index + 1));
        self.queue.len() + in_chain
    }

    pub(crate) fn queue(&mut self, step: Step, triggers: Vec<TriggerAt>) {
        if let Step::Move {
            tool,
            base,
            motion,
            line,
        } = step
        {
            self.queue.push_back(Queued {
                tool,
                base,
                motion,
                line,
                triggers,
            });
        }
    }

    /// `RESUME`: the queue and the rest of the chain are dropped; the
    /// robot stays where it is.
    pub(crate) fn discard(&mut self) {
        self.queue.clear();
        self.chain = None;
        self.braked = false;
    }

    /// Plays `dt` seconds; returns the triggers that fired.
    pub(crate) fn advance(&mut self, dt: f64) -> Vec<u64> {
        if self.braked {
            return Vec::new();
        }
        self.join_or_start();
        let mut fired = Vec::new();
        let Some(chain) = self.chain.as_mut() else {
            return fired;
        };
        chain.t += dt;
        self.moving_s += dt;
        let t = chain.t;
        let samples = &chain.exec.samples;
        let i = samples.partition_point(|s| s.t <= t);
        let sample = &samples[i.saturating_sub(1).min(samples.len().saturating_sub(1))];
        self.axes = sample.axes;
        self.motion_index = sample.motion;
        // Triggers: DISTANCE=0 at the motion's start, =1 (and PATH) at its
        // end, plus DELAY.
        for (k, list) in chain.triggers.iter().enumerate() {
            for tr in list {
                if chain.fired.contains(&tr.id) {
                    continue;
                }
                let at_end = tr.path || tr.at >= 0.5;
                let when = motion_time(&chain.exec, k, at_end) + tr.delay_ms / 1000.0;
                if when <= t {
                    chain.fired.push(tr.id);
                    fired.push(tr.id);
                }
            }
        }
        if t >= chain.exec.duration_s {
            self.axes = chain.exec.end_axes;
            if let Some((k, error)) = chain.exec.error.clone() {
                self.failures.push(MotionFailure {
                    line: chain.lines.get(k).copied().unwrap_or(0),
                    error,
                });
                if self.failures.len() > 100 {
                    self.failures.remove(0);
                }
                // The robot stops where the motion failed; nothing queued
                // is played, no trigger of the rest fires (a KRC's error
                // stop). The program halts with a stop message.
                self.queue.clear();
                self.failed = true;
                self.motions_done += k as u64;
                self.chain = None;
                self.motion_index = 0;
                return fired;
            }
            self.motions_done += chain.motions.len() as u64;
            // Triggers not reached by the path (e.g. a DELAY past the end)
            // fire now, so that the program's bookkeeping goes on.
            for list in &chain.triggers {
                for tr in list {
                    if !chain.fired.contains(&tr.id) {
                        fired.push(tr.id);
                    }
                }
            }
            self.chain = None;
            self.motion_index = 0;
        }
        fired
    }

    /// Starts a chain from the queue, or lets queued motions join the one
    /// being played.
    fn join_or_start(&mut self) {
        if self.queue.is_empty() {
            return;
        }
        match self.chain.as_mut() {
            None => {
                let first = self.queue.pop_front().expect("queue not empty");
                self.tool = first.tool;
                self.base = first.base;
                let mut chain = Chain {
                    start: self.axes,
                    tool: first.tool,
                    base: first.base,
                    motions: vec![first.motion],
                    lines: vec![first.line],
                    triggers: vec![first.triggers],
                    exec: Execution {
                        samples: Vec::new(),
                        end_axes: self.axes,
                        duration_s: 0.0,
                        error: None,
                    },
                    t: 0.0,
                    fired: Vec::new(),
                };
                self.chains_started += 1;
                Self::extend(&mut chain, &mut self.queue);
                chain.exec = plan_chain(&self.model, &self.settings, &chain);
                self.motion_index = 0;
                self.chain = Some(chain);
            }
            Some(chain) => {
                // Only while the robot has not started the chain's last
                // motion: later, the blend is missed (exact stop).
                if self.motion_index + 1 < chain.motions.len()
                    && Self::extend(chain, &mut self.queue)
                {
                    chain.exec = plan_chain(&self.model, &self.settings, chain);
                }
            }
        }
    }

    /// Moves queued motions into the chain while they can blend; whether
    /// any did.
    fn extend(chain: &mut Chain, queue: &mut VecDeque<Queued>) -> bool {
        let mut any = false;
        while let Some(next) = queue.front() {
            let last = chain.motions.last().map_or(0.0, |m| m.approx_mm);
            if last <= 0.0 || next.tool != chain.tool || next.base != chain.base {
                break;
            }
            let q = queue.pop_front().expect("front exists");
            chain.motions.push(q.motion);
            chain.lines.push(q.line);
            chain.triggers.push(q.triggers);
            any = true;
        }
        any
    }

    /// TCP pose of the current axes with the last motion's tool and base.
    pub(crate) fn pose(&self) -> Pose {
        self.model.forward(&self.axes, &self.tool, &self.base)
    }
}

/// When motion `k` of an execution starts (or ends).
fn motion_time(exec: &Execution, k: usize, end: bool) -> f64 {
    let s = &exec.samples;
    if end {
        match s.iter().rposition(|x| x.motion == k) {
            Some(i) => s[i].t,
            None => exec.duration_s,
        }
    } else {
        s.iter()
            .find(|x| x.motion >= k)
            .map_or(exec.duration_s, |x| x.t)
    }
}

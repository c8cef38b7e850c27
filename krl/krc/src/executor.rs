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
//! chain from the next junction the robot has not reached
//! ([`plan::plan_from`]): what the robot already does never changes, and
//! the cost of a join does not grow with the chain. Motions the robot has
//! finished leave the chain, so a path of any length (a motion stream)
//! runs in bounded memory.

use std::collections::VecDeque;

use kuka_kinematics::plan::{self, Junction, PlanSettings, Sample};
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

/// Motions being played (chain-wide indices count from the chain's start).
struct Chain {
    tool: Pose,
    base: Pose,
    /// Chain-wide index of `motions[0]`: the motions before it are done.
    first: usize,
    motions: VecDeque<Motion>,
    lines: VecDeque<u32>,
    triggers: VecDeque<Vec<TriggerAt>>,
    /// Planned samples (chain time, chain-wide motion indices) of the
    /// motions from `first` on.
    samples: VecDeque<Sample>,
    /// Where the planned motions start.
    junctions: VecDeque<Junction>,
    end_axes: Axes,
    duration_s: f64,
    /// The first failing motion (chain-wide) and why.
    error: Option<(usize, MotionError)>,
    /// Seconds played.
    t: f64,
    /// Triggers already fired.
    fired: Vec<u64>,
}

impl Chain {
    /// Motions in the chain so far.
    fn total(&self) -> usize {
        self.first + self.motions.len()
    }

    /// Plans `self.motions[from - first ..]` from junction `j` (chain-wide
    /// motion `from`) and puts the plan in place of what followed `j`.
    fn plan_tail(&mut self, model: &RobotModel, settings: &PlanSettings, from: usize, j: Junction) {
        let motions: Vec<Motion> = self.motions.range(from - self.first..).cloned().collect();
        let local = Junction { motion: 0, ..j };
        let exec = plan::plan_from(model, &self.tool, &self.base, &motions, settings, &local);
        self.samples.retain(|s| s.t <= j.t + 1e-9);
        self.junctions.retain(|x| x.motion < from);
        self.samples.extend(
            exec.samples
                .iter()
                .filter(|s| s.t > j.t + 1e-9)
                .map(|s| Sample {
                    motion: s.motion + from,
                    ..*s
                }),
        );
        self.junctions
            .extend(exec.junctions.iter().map(|x| Junction {
                motion: x.motion + from,
                ..*x
            }));
        self.end_axes = exec.end_axes;
        self.duration_s = exec.duration_s.max(j.t);
        self.error = exec.error.map(|(k, e)| (k + from, e));
    }
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
            .map_or(0, |c| c.total().saturating_sub(self.motion_index + 1));
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
        let i = chain.samples.partition_point(|s| s.t <= t);
        if let Some(sample) = chain.samples.get(i.saturating_sub(1)) {
            self.axes = sample.axes;
            self.motion_index = sample.motion;
            // Between two samples (12 ms of planned motion apart): the
            // axes in proportion, so that an override below 100 %, which
            // plays less than a sample per cycle, moves the robot smoothly
            // instead of holding a sample for several cycles and jumping.
            if let Some(next) = chain.samples.get(i)
                && next.t > sample.t
                && t > sample.t
            {
                let f = ((t - sample.t) / (next.t - sample.t)).clamp(0.0, 1.0);
                for (a, b) in self.axes.iter_mut().zip(next.axes) {
                    *a += (b - *a) * f;
                }
            }
        }
        // Triggers: DISTANCE=0 at the motion's start, =1 at its end, PATH
        // at that many mm along the path from its end, plus DELAY.
        for (k, list) in chain.triggers.iter().enumerate() {
            for tr in list {
                if chain.fired.contains(&tr.id) {
                    continue;
                }
                let when = trigger_time(chain, chain.first + k, tr) + tr.delay_ms / 1000.0;
                if when <= t {
                    chain.fired.push(tr.id);
                    fired.push(tr.id);
                }
            }
        }
        if t >= chain.duration_s {
            self.axes = chain.end_axes;
            if let Some((k, error)) = chain.error.clone() {
                self.failures.push(MotionFailure {
                    line: chain
                        .lines
                        .get(k.saturating_sub(chain.first))
                        .copied()
                        .unwrap_or(0),
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
            self.motions_done += chain.total() as u64;
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
            return fired;
        }
        // Motions done whose triggers have all fired leave the chain.
        while chain.first < self.motion_index
            && chain.motions.len() > 1
            && chain
                .triggers
                .front()
                .is_some_and(|l| l.iter().all(|tr| chain.fired.contains(&tr.id)))
        {
            if let Some(list) = chain.triggers.pop_front() {
                chain.fired.retain(|id| !list.iter().any(|tr| tr.id == *id));
            }
            chain.motions.pop_front();
            chain.lines.pop_front();
            chain.first += 1;
        }
        let first = chain.first;
        // Keep one sample before the window for the position in between.
        while chain.samples.len() > 1 && chain.samples[1].motion < first && chain.samples[1].t <= t
        {
            chain.samples.pop_front();
        }
        while chain.junctions.front().is_some_and(|j| j.motion < first) {
            chain.junctions.pop_front();
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
                    tool: first.tool,
                    base: first.base,
                    first: 0,
                    motions: VecDeque::from([first.motion]),
                    lines: VecDeque::from([first.line]),
                    triggers: VecDeque::from([first.triggers]),
                    samples: VecDeque::new(),
                    junctions: VecDeque::new(),
                    end_axes: self.axes,
                    duration_s: 0.0,
                    error: None,
                    t: 0.0,
                    fired: Vec::new(),
                };
                self.chains_started += 1;
                Self::extend(&mut chain, &mut self.queue);
                let start = Junction {
                    motion: 0,
                    t: 0.0,
                    axes: self.axes,
                    speed: 0.0,
                };
                chain.plan_tail(&self.model, &self.settings, 0, start);
                self.motion_index = 0;
                self.chain = Some(chain);
            }
            Some(chain) => {
                // Only while the robot has not started the chain's last
                // motion (a junction lies ahead) and nothing failed: later,
                // the blend is missed (exact stop).
                if chain.error.is_some() {
                    return;
                }
                let (current, t) = (self.motion_index, chain.t);
                // (Not inside a spline block where a segment does not
                // know the point before it: such a block is replanned from
                // its first point.)
                let inner_spl = |motion: usize| {
                    motion
                        .checked_sub(chain.first)
                        .and_then(|k| chain.motions.get(k))
                        .is_some_and(plan::needs_block_start)
                };
                let Some(j) = chain
                    .junctions
                    .iter()
                    .find(|j| j.motion > current && j.t > t + 1e-9 && !inner_spl(j.motion))
                    .copied()
                else {
                    return;
                };
                if Self::extend(chain, &mut self.queue) {
                    chain.plan_tail(&self.model, &self.settings, j.motion, j);
                }
            }
        }
    }

    /// Moves queued motions into the chain while they can blend; whether
    /// any did.
    fn extend(chain: &mut Chain, queue: &mut VecDeque<Queued>) -> bool {
        let mut any = false;
        while let Some(next) = queue.front() {
            let last = chain.motions.back().map_or(0.0, |m| m.approx_mm);
            if last <= 0.0 || next.tool != chain.tool || next.base != chain.base {
                break;
            }
            let q = queue.pop_front().expect("front exists");
            chain.motions.push_back(q.motion);
            chain.lines.push_back(q.line);
            chain.triggers.push_back(q.triggers);
            any = true;
        }
        any
    }

    /// TCP pose of the current axes with the last motion's tool and base.
    pub(crate) fn pose(&self) -> Pose {
        self.model.forward(&self.axes, &self.tool, &self.base)
    }
}

/// When motion `k` (chain-wide) starts (or ends) in the chain's plan.
/// Chain time at which trigger `tr` of motion `k` (chain-wide) switches.
/// `PATH = d`: where the TCP is `d` mm along the path from the motion's
/// end (before it for d < 0, into the following motions for d > 0), or
/// with `ONSTART` from its start point. The
/// end of an approximated motion is taken where the planned path passes
/// from it to the next (the middle of the blend in this planner; KSS
/// relates the switching point to the approximation contour, which the
/// documentation describes only loosely). A point before the path's start
/// switches at the start, one beyond its end at the end.
fn trigger_time(chain: &Chain, k: usize, tr: &TriggerAt) -> f64 {
    if !tr.path {
        return motion_time(chain, k, tr.at >= 0.5);
    }
    let s = &chain.samples;
    let found = if tr.onstart {
        // From the motion's start point: the last sample of the motions
        // before it (or its first, at the chain's start).
        s.iter()
            .position(|x| x.motion >= k)
            .map(|i| i.saturating_sub(1))
    } else {
        s.iter().rposition(|x| x.motion == k)
    };
    let Some(end) = found else {
        return chain.duration_s;
    };
    let mut run = 0.0;
    if tr.at <= 0.0 {
        let want = -tr.at;
        let mut i = end;
        while i > 0 && run < want {
            run += s[i].pose.distance_mm(&s[i - 1].pose);
            i -= 1;
        }
        s[i].t
    } else {
        let mut i = end;
        while i + 1 < s.len() && run < tr.at {
            run += s[i + 1].pose.distance_mm(&s[i].pose);
            i += 1;
        }
        if run < tr.at {
            chain.duration_s
        } else {
            s[i].t
        }
    }
}

fn motion_time(chain: &Chain, k: usize, end: bool) -> f64 {
    let s = &chain.samples;
    if end {
        match s.iter().rposition(|x| x.motion == k) {
            Some(i) => s[i].t,
            None => chain.duration_s,
        }
    } else {
        s.iter()
            .find(|x| x.motion >= k)
            .map_or(chain.duration_s, |x| x.t)
    }
}

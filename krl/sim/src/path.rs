//! A motion stream (protocol version 2, ops PATH and APPEND): a path whose
//! motions arrive while the robot executes it.
//!
//! The path keeps a window of its motions (from the first one the robot
//! has not finished) and the plan being played. When motions are appended,
//! the part of the plan the robot has not reached yet is planned again from
//! the next junction ([`kuka_kinematics::plan::plan_from`]): motions that
//! arrive before the robot starts the last stored one blend into it
//! (approximation), as a KRC's advance run does; motions that arrive later
//! start from a standstill. Memory stays bounded by the controller's stream
//! buffer, however long the path.

use std::collections::VecDeque;

use kuka_kinematics::plan::{self, Junction, Sample};
use kuka_kinematics::{Axes, Motion, MotionError, PlanSettings, Pose, RobotModel};
use kuka_protocol::{Cid, MotionRecord};

use crate::actions::{Actions, OutputAction, Wait, decide, run_earlier};

/// Motions the stream buffer holds (stored and not yet started), as the
/// shipped KRL program's ring `kb_sq` (`kb_main.dat`).
pub(crate) const STREAM_CAPACITY: u32 = 200;

/// See [`PathRun::hold_t`]: longer than braking from any path speed up to
/// 2 m/s at the default path acceleration (0.87 s).
const HOLD_S: f64 = 1.0;

/// How the path ended.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PathEnd {
    /// Closed and every stored motion ran.
    Done,
    /// A motion failed (path-wide index): the robot stopped where it did.
    Failed(usize, MotionError),
    /// The input of a `WIN` (path-wide index) did not come in time.
    TimedOut(usize),
}

/// A path being executed.
pub(crate) struct PathRun {
    /// The PATH command's id (names the path).
    pub(crate) cid: Cid,
    /// Motions stored so far (the next APPEND starts here).
    pub(crate) stored: u32,
    /// An APPEND with the close flag has come: the path ends after the
    /// last stored motion.
    pub(crate) closed: bool,
    /// Stored motions from `queue_from` on (planned or not).
    queue: VecDeque<Motion>,
    /// Path-wide index of `queue[0]`.
    queue_from: usize,
    /// Samples planned and not yet played (path time, path-wide motion
    /// indices), oldest first.
    samples: VecDeque<Sample>,
    /// Where the planned motions start (path-wide indices).
    junctions: VecDeque<Junction>,
    /// Path time at which the plan ends, and the axes there.
    end_t: f64,
    end_axes: Axes,
    /// The plan's error (path-wide index), if a motion failed.
    error: Option<(usize, MotionError)>,
    /// Path time played so far.
    pub(crate) t: f64,
    /// Motion being executed (path-wide index).
    pub(crate) current: usize,
    /// The robot stands at the end of what was stored (waiting for more).
    pub(crate) waiting: bool,
    /// The last stored record: whether the next one may blend into it
    /// (the same motion family) decides its approximation.
    last_record: Option<MotionRecord>,
    /// The path's I/O actions (protocol §5.6).
    actions: Actions,
    /// The `WIN` whose input did not come in time: the path ends there.
    timed_out: Option<usize>,
}

impl PathRun {
    /// A new path with the robot standing at `axes`.
    pub(crate) fn new(cid: Cid, axes: Axes) -> Self {
        PathRun {
            cid,
            stored: 0,
            closed: false,
            queue: VecDeque::new(),
            queue_from: 0,
            samples: VecDeque::new(),
            junctions: VecDeque::new(),
            end_t: 0.0,
            end_axes: axes,
            error: None,
            t: 0.0,
            current: 0,
            waiting: true,
            last_record: None,
            actions: Actions::default(),
            timed_out: None,
        }
    }

    /// Free slots: motions stored and not yet started count against the
    /// capacity.
    pub(crate) fn room(&self) -> u32 {
        let held = (self.stored as usize).saturating_sub(self.current);
        STREAM_CAPACITY.saturating_sub(held as u32)
    }

    /// Stores `motions` (path-wide indices from `self.stored` on) and plans
    /// them: from the next junction the robot has not reached, or from the
    /// standstill at the end of the plan.
    pub(crate) fn append(
        &mut self,
        model: &RobotModel,
        tool: &Pose,
        base: &Pose,
        settings: &PlanSettings,
        records: &[MotionRecord],
    ) {
        let Some(first_record) = records.first() else {
            return;
        };
        let motions = kuka_krl_runtime::to_motions(records);
        // The last stored motion blended optimistically: it stops exactly
        // if the new one is of the other motion family (replanned below if
        // the robot has not started it yet).
        if let Some(prev) = self.last_record.replace(records[records.len() - 1].clone())
            && prev.is_spline_family() != first_record.is_spline_family()
            && let Some(m) = self.queue.back_mut()
        {
            m.approx_mm = 0.0;
        }
        let first_new = self.stored as usize;
        self.stored += motions.len() as u32;
        self.actions.extend(records, first_new);
        if self.error.is_some() || self.timed_out.is_some() {
            // The robot stops at the failing motion: nothing after it runs.
            return;
        }
        self.queue.extend(motions);
        // The first junction ahead of the robot (a motion not yet started).
        // (Not inside a spline block where a segment does not know the
        // point before it: such a block is replanned from its first point.)
        let inner_spl = |motion: usize| {
            motion
                .checked_sub(self.queue_from)
                .and_then(|k| self.queue.get(k))
                .is_some_and(plan::needs_block_start)
        };
        let ahead = self
            .junctions
            .iter()
            .position(|j| j.t > self.t + 1e-9 && j.motion > self.current && !inner_spl(j.motion));
        let from = match ahead {
            Some(k) => {
                let j = self.junctions[k];
                self.samples.retain(|s| s.t <= j.t + 1e-9);
                self.junctions.truncate(k);
                j
            }
            None => {
                // The robot is in the last planned motion, or stands: the
                // new motions start where the plan ends, from a standstill.
                Junction {
                    motion: first_new,
                    t: self.end_t.max(self.t),
                    axes: self.end_axes,
                    speed: 0.0,
                }
            }
        };
        let start = from.motion - self.queue_from;
        let motions: Vec<Motion> = self.queue.range(start..).cloned().collect();
        let local = Junction { motion: 0, ..from };
        let exec = plan::plan_from(model, tool, base, &motions, settings, &local);
        let offset = from.motion;
        self.samples.extend(
            exec.samples
                .iter()
                .filter(|s| s.t > from.t + 1e-9)
                .map(|s| Sample {
                    motion: s.motion + offset,
                    ..*s
                }),
        );
        self.junctions
            .extend(exec.junctions.iter().map(|j| Junction {
                motion: j.motion + offset,
                ..*j
            }));
        self.end_t = exec.duration_s.max(from.t);
        self.end_axes = exec.end_axes;
        self.error = exec.error.map(|(k, e)| (k + offset, e));
        self.waiting = false;
    }

    /// Plays the path up to path time `until` (never past the end of the
    /// plan), with the digital inputs `inputs` (for `WIN` records); returns
    /// the samples reached, oldest first, and the outputs (`SOT`) the robot
    /// passed.
    pub(crate) fn play(&mut self, until: f64, inputs: &[bool]) -> (Vec<Sample>, Vec<OutputAction>) {
        let mut out = Vec::new();
        let mut switched = Vec::new();
        // Inside a wait (its start played, its end ahead) whose input has
        // come since the last look: the robot leaves now.
        if let Some(&end) = self.samples.front()
            && end.motion == self.current
            && end.t > until
            && let Some((index, value)) = self.actions.wait(self.current)
            && inputs.get(usize::from(index)) == Some(&value)
        {
            let dt = end.t - until.max(self.t);
            self.samples.pop_front();
            for x in &mut self.samples {
                x.t -= dt;
            }
            for j in self.junctions.iter_mut().filter(|j| j.t > until) {
                j.t -= dt;
            }
            self.end_t -= dt;
        }
        while let Some(s) = self.samples.front() {
            if s.t > until + 1e-12 {
                break;
            }
            let s = self.samples.pop_front().expect("front exists");
            self.current = s.motion;
            switched.extend(self.actions.passed(&s, self.samples.iter()));
            out.push(s);
            if let Some((index, value)) = self.actions.wait(s.motion) {
                let rest: Vec<_> = self
                    .samples
                    .iter()
                    .take_while(|x| x.motion == s.motion)
                    .collect();
                let ok = inputs.get(usize::from(index)) == Some(&value);
                match decide(&s, &rest, ok) {
                    Wait::Goes => {}
                    Wait::Came(dt) => {
                        let n = rest.len();
                        self.samples.drain(..n);
                        run_earlier(&mut self.samples, &mut self.junctions, s.t, dt);
                        self.end_t -= dt;
                    }
                    Wait::TimedOut => {
                        // The robot stands here; nothing after it runs.
                        self.samples.clear();
                        self.junctions.retain(|j| j.t <= s.t);
                        self.end_t = s.t;
                        self.end_axes = s.axes;
                        self.error = None;
                        self.timed_out = Some(s.motion);
                        break;
                    }
                }
            }
        }
        if self.samples.is_empty() && until >= self.end_t - 1e-12 {
            // The robot reached the end of the plan: it stands there while
            // the path's time goes on.
            self.t = until.max(self.t);
            self.waiting = true;
            if self.error.is_none() && self.timed_out.is_none() {
                // Every stored motion is done.
                self.current = self.stored as usize;
                if self.closed {
                    // Outputs after the last motion: switched at its end.
                    switched.extend(self.actions.all_left());
                }
            }
        } else if self.timed_out.is_some() {
            self.t = self.end_t.max(self.t);
        } else {
            self.t = until.min(self.end_t).max(self.t);
        }
        // Motions finished for good leave the window.
        let done = self.current.saturating_sub(self.queue_from);
        let keep_from = done.min(self.queue.len());
        if keep_from > 0 {
            self.queue.drain(..keep_from);
            self.queue_from += keep_from;
        }
        while self
            .junctions
            .front()
            .is_some_and(|j| j.motion < self.current)
        {
            self.junctions.pop_front();
        }
        (out, switched)
    }

    /// Path time of the next sample, if any is planned.
    pub(crate) fn next_sample_t(&self) -> Option<f64> {
        self.samples.front().map(|s| s.t)
    }

    /// How far an instant controller plays an open path: [`HOLD_S`] before
    /// the end of the plan (or further, until half the buffer is free). A real robot is that far behind the motions
    /// stored ahead of it whenever a client appends faster than it moves;
    /// an instant one playing to the end would re-plan every append from
    /// the braking phase of the last motion.
    pub(crate) fn hold_t(&self) -> f64 {
        if self.closed || self.error.is_some() || self.timed_out.is_some() {
            return self.end_t;
        }
        // Never hold so much that the buffer stays full: play on until half
        // of it is free again.
        let free_from = (self.stored as usize).saturating_sub(STREAM_CAPACITY as usize / 2);
        let to_free = self
            .junctions
            .iter()
            .find(|j| j.motion >= free_from)
            .map_or(self.t, |j| j.t - 1e-6);
        (self.end_t - HOLD_S).max(to_free).max(self.t)
    }

    /// The axes at the end of the plan.
    pub(crate) fn end_axes(&self) -> Axes {
        self.end_axes
    }

    /// How the path ended, once the robot has played everything: `None`
    /// while it runs or waits for motions.
    pub(crate) fn ended(&self) -> Option<PathEnd> {
        if !self.samples.is_empty() || self.t < self.end_t - 1e-12 {
            return None;
        }
        if let Some(w) = self.timed_out {
            return Some(PathEnd::TimedOut(w));
        }
        match &self.error {
            Some((k, e)) => Some(PathEnd::Failed(*k, e.clone())),
            None if self.closed => Some(PathEnd::Done),
            None => None,
        }
    }
}

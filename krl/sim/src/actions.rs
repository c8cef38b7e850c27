//! The I/O actions of a MOVE batch or a path (protocol §5.6): outputs
//! switched as the robot passes their point of the sequence (`SOT`), waits
//! for an input with a timeout (`WIN`). A `WIN` is planned as a standstill
//! of its whole timeout ([`kuka_kinematics::MotionKind::Hold`]); when the
//! input comes the rest of the standstill is cut out of the plan and what
//! follows moves earlier (the robot starts from a standstill after it, so
//! the rest of the plan is otherwise the same).
//!
//! An `SOP` (an `SOT` with a distance along the path, KRL `TRIGGER WHEN
//! PATH`) switches where the robot reaches that point of its planned path:
//! `path` mm along the samples from the end point of the motion before it
//! (the last sample of that motion: its target, or the middle of the
//! approximation arc where it blends into the next), before it when
//! negative, after it when positive. It switches at the first sample at or
//! past that point (at most one 12 ms sample late, as the KRC-like runtime's
//! triggers); when the sequence ends before a point after the end, it
//! switches at the end (a KRC clamps the point to the next exact stop).

use std::collections::BTreeMap;

use kuka_kinematics::plan::Sample;
use kuka_protocol::MotionRecord;

/// An output to switch: `$OUT` index, value, pulse length in ms (0 = none).
pub(crate) type OutputAction = (u16, bool, u32);

/// An `SOP` record not switched yet.
#[derive(Debug, Clone, Copy)]
struct PathOutput {
    /// What it switches.
    action: OutputAction,
    /// mm along the path from the end point of `motion`.
    path_mm: f64,
    /// The motion before it (record index).
    motion: usize,
    /// mm travelled past that end point so far (for `path_mm` > 0).
    travelled: f64,
}

/// The actions of one sequence, by record index (path-wide in a path).
#[derive(Debug, Default)]
pub(crate) struct Actions {
    /// `SOT` records not switched yet.
    outputs: BTreeMap<usize, OutputAction>,
    /// `SOP` records not switched yet.
    paths: BTreeMap<usize, PathOutput>,
    /// `WIN` records: input index and the value waited for.
    waits: BTreeMap<usize, (u16, bool)>,
    /// The last motion record seen by [`Actions::extend`] (a `WIN`/`DWL`
    /// clears it: an `SOP` after one has no motion to measure from).
    last_motion: Option<usize>,
    /// The sample played last.
    last_sample: Option<Sample>,
}

impl Actions {
    /// Adds the actions of `records`, the first of which has index `first`.
    pub(crate) fn extend(&mut self, records: &[MotionRecord], first: usize) {
        for (k, r) in records.iter().enumerate() {
            match r {
                MotionRecord::SetOutput {
                    index,
                    value,
                    pulse_ms,
                    path_mm,
                } => {
                    let action = (*index, *value, *pulse_ms);
                    match (path_mm, self.last_motion) {
                        (Some(p), Some(motion)) => {
                            let path = PathOutput {
                                action,
                                path_mm: *p,
                                motion,
                                travelled: 0.0,
                            };
                            self.paths.insert(first + k, path);
                        }
                        // (No motion before it: as the next motion starts,
                        // as the KRL program does.)
                        _ => {
                            self.outputs.insert(first + k, action);
                        }
                    }
                }
                MotionRecord::WaitInput { index, value, .. } => {
                    self.waits.insert(first + k, (*index, *value));
                    self.last_motion = None;
                }
                MotionRecord::Dwell { .. } => self.last_motion = None,
                _ => self.last_motion = Some(first + k),
            }
        }
    }

    /// The outputs the robot passes as it plays `sample`, in record order;
    /// they are switched only once. `ahead` are the samples planned after
    /// it, in order. An `SOT` is passed once the robot executes a record
    /// after it; an `SOP` once the robot is at or past its point of the
    /// path.
    pub(crate) fn passed<'a>(
        &mut self,
        sample: &Sample,
        ahead: impl Iterator<Item = &'a Sample> + Clone,
    ) -> Vec<OutputAction> {
        let rest = self.outputs.split_off(&sample.motion);
        let mut due: Vec<(usize, OutputAction)> = std::mem::replace(&mut self.outputs, rest)
            .into_iter()
            .collect();
        let prev = self.last_sample.replace(*sample);
        let mut reached = Vec::new();
        for (&k, p) in &mut self.paths {
            let at = if sample.motion > p.motion {
                // Past the end point: count the way from it.
                if let Some(prev) = prev.filter(|x| x.motion >= p.motion) {
                    p.travelled += sample.pose.distance_mm(&prev.pose);
                }
                p.travelled >= p.path_mm - 1e-9
            } else if sample.motion == p.motion || p.path_mm < 0.0 {
                // Up to the end point: how far it still is along the plan.
                let mut left = 0.0;
                let mut from = sample;
                for x in ahead.clone().take_while(|x| x.motion <= p.motion) {
                    left += x.pose.distance_mm(&from.pose);
                    from = x;
                }
                left <= -p.path_mm + 1e-9
            } else {
                false
            };
            if at {
                reached.push(k);
            }
        }
        for k in reached {
            if let Some(p) = self.paths.remove(&k) {
                due.push((k, p.action));
            }
        }
        due.sort_by_key(|(k, _)| *k);
        due.into_iter().map(|(_, a)| a).collect()
    }

    /// Every output not switched yet (the sequence ended after them), in
    /// record order.
    pub(crate) fn all_left(&mut self) -> Vec<OutputAction> {
        let mut due: Vec<(usize, OutputAction)> =
            std::mem::take(&mut self.outputs).into_iter().collect();
        due.extend(
            std::mem::take(&mut self.paths)
                .into_iter()
                .map(|(k, p)| (k, p.action)),
        );
        due.sort_by_key(|(k, _)| *k);
        due.into_iter().map(|(_, a)| a).collect()
    }

    /// The input record `motion` waits for, if it is a `WIN`.
    pub(crate) fn wait(&self, motion: usize) -> Option<(u16, bool)> {
        self.waits.get(&motion).copied()
    }
}

/// What a `WIN`'s standstill does at the sample just played.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Wait {
    /// Not a wait, or the input has not come and time is left.
    Goes,
    /// The input came: the rest of the standstill, this long, is cut.
    Came(f64),
    /// The standstill ran out without the input.
    TimedOut,
}

/// Decides a wait at `samples[k]`, which was just played and belongs to a
/// `WIN` whose input currently has `ok` (the value waited for); `next` is
/// the sample after it, if any. When the input came, the samples of the
/// same standstill after `k` are the ones to drop (the caller does that)
/// and the returned time is how much earlier the rest of the plan runs.
pub(crate) fn decide(sample: &Sample, rest: &[&Sample], ok: bool) -> Wait {
    let end = rest
        .iter()
        .take_while(|s| s.motion == sample.motion)
        .last()
        .map(|s| s.t);
    match (ok, end) {
        (true, Some(end)) => Wait::Came(end - sample.t),
        (true, None) => Wait::Goes,
        (false, Some(_)) => Wait::Goes,
        (false, None) => Wait::TimedOut,
    }
}

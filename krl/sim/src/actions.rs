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

use kuka_kinematics::plan::{Junction, Sample};
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
                // Up to the end point: how far it still is along the plan
                // (looked at no further than the distance: a batch of many
                // motions is not walked to its end at every sample).
                let want = -p.path_mm + 1e-9;
                let mut left = 0.0;
                let mut from = sample;
                for x in ahead.clone().take_while(|x| x.motion <= p.motion) {
                    left += x.pose.distance_mm(&from.pose);
                    from = x;
                    if left > want {
                        break;
                    }
                }
                left <= want
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

/// Runs the rest of a plan `dt` seconds earlier once a wait's input came
/// at time `at`: the samples `later` (those after the dropped standstill)
/// and the junctions after `at` move back by `dt`. The native simulator's
/// batch and path runs share this.
pub(crate) fn run_earlier<'a>(
    later: impl IntoIterator<Item = &'a mut Sample>,
    junctions: impl IntoIterator<Item = &'a mut Junction>,
    at: f64,
    dt: f64,
) {
    for x in later {
        x.t -= dt;
    }
    for j in junctions.into_iter().filter(|j| j.t > at) {
        j.t -= dt;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kuka_kinematics::Pose;

    fn at(motion: usize, x: f64, y: f64) -> Sample {
        Sample {
            t: 0.0,
            motion,
            axes: [0.0; 6],
            pose: Pose::new(x, y, 0.0, 0.0, 0.0, 0.0),
        }
    }

    fn sop(index: u16, path_mm: f64) -> MotionRecord {
        MotionRecord::SetOutput {
            index,
            value: true,
            pulse_ms: 0,
            path_mm: Some(path_mm),
        }
    }

    /// LIN along x to 100 mm (motion 0), then an SOT, SOP(-30), SOP(+20),
    /// SOP(-60), then LIN along y (motion 4), sampled every mm: each output
    /// switches at the first sample at or past its point, in the order the
    /// robot reaches the points; the SOT as motion 4 starts.
    #[test]
    fn outputs_switch_at_their_point_of_the_sampled_path() {
        let lin = MotionRecord::Lin {
            target: kuka_protocol::Frame::default(),
            params: kuka_protocol::MotionParams {
                velocity: 0.1,
                acceleration_pct: 100.0,
                approx_mm: 0.0,
            },
        };
        let sot = MotionRecord::SetOutput {
            index: 1,
            value: true,
            pulse_ms: 0,
            path_mm: None,
        };
        let records = [
            lin.clone(),
            sot,
            sop(2, -30.0),
            sop(3, 20.0),
            sop(4, -60.0),
            lin,
        ];
        let mut actions = Actions::default();
        actions.extend(&records, 0);
        let mut samples: Vec<Sample> = (0..=100).map(|x| at(0, f64::from(x), 0.0)).collect();
        samples.extend((1..=50).map(|y| at(4, 100.0, f64::from(y))));
        let mut switched = Vec::new();
        for (k, s) in samples.iter().enumerate() {
            for (index, _, _) in actions.passed(s, samples[k + 1..].iter()) {
                switched.push((index, s.pose.position().x, s.pose.position().y));
            }
        }
        assert_eq!(
            switched,
            [
                (4, 40.0, 0.0),
                (2, 70.0, 0.0),
                (1, 100.0, 1.0),
                (3, 100.0, 20.0)
            ]
        );
        assert!(actions.all_left().is_empty());
    }

    /// An SOP with no motion before it (the first record, or after a
    /// dwell) switches like an SOT: as the next motion starts, or at the
    /// end of the sequence when none follows.
    #[test]
    fn an_sop_without_a_motion_before_it_switches_as_an_sot() {
        let records = [sop(1, -5.0), MotionRecord::Dwell { ms: 0 }, sop(2, 500.0)];
        let mut actions = Actions::default();
        actions.extend(&records, 0);
        let s = at(1, 0.0, 0.0);
        let first: Vec<u16> = actions.passed(&s, [].iter()).iter().map(|a| a.0).collect();
        assert_eq!(first, [1]);
        let left: Vec<u16> = actions.all_left().iter().map(|a| a.0).collect();
        assert_eq!(left, [2]);
    }
}

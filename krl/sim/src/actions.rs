//! The I/O actions of a MOVE batch or a path (protocol §5.6): outputs
//! switched as the robot passes their point of the sequence (`SOT`), waits
//! for an input with a timeout (`WIN`). A `WIN` is planned as a standstill
//! of its whole timeout ([`kuka_kinematics::MotionKind::Hold`]); when the
//! input comes the rest of the standstill is cut out of the plan and what
//! follows moves earlier (the robot starts from a standstill after it, so
//! the rest of the plan is otherwise the same).

use std::collections::BTreeMap;

use kuka_kinematics::plan::Sample;
use kuka_protocol::MotionRecord;

/// An output to switch: `$OUT` index, value, pulse length in ms (0 = none).
pub(crate) type OutputAction = (u16, bool, u32);

/// The actions of one sequence, by record index (path-wide in a path).
#[derive(Debug, Default)]
pub(crate) struct Actions {
    /// `SOT` records not switched yet.
    outputs: BTreeMap<usize, OutputAction>,
    /// `WIN` records: input index and the value waited for.
    waits: BTreeMap<usize, (u16, bool)>,
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
                } => {
                    self.outputs.insert(first + k, (*index, *value, *pulse_ms));
                }
                MotionRecord::WaitInput { index, value, .. } => {
                    self.waits.insert(first + k, (*index, *value));
                }
                _ => {}
            }
        }
    }

    /// The outputs the robot has passed once it executes record `motion`
    /// (every `SOT` before it), in order; they are switched only once.
    pub(crate) fn passed(&mut self, motion: usize) -> Vec<OutputAction> {
        let rest = self.outputs.split_off(&motion);
        let due = std::mem::replace(&mut self.outputs, rest);
        due.into_values().collect()
    }

    /// Every output not switched yet (the sequence ended after them).
    pub(crate) fn all_left(&mut self) -> Vec<OutputAction> {
        std::mem::take(&mut self.outputs).into_values().collect()
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

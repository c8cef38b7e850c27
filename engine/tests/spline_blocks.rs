//! Spline blocks: how consecutive `spl` motions are grouped into KRL
//! SPLINE blocks (`resolve`), and that a JSON-lines stream, which appends
//! what it has parsed whenever its bytes pause, forms the same blocks
//! however the bytes break (`open_spline_tail`).

use kuka_engine::motion::{MotionRequest, SpeedSettings, StartPoint, open_spline_tail, resolve};
use kuka_protocol::{Frame, MotionRecord};
use proptest::prelude::*;
use serde_json::json;

fn start() -> StartPoint {
    StartPoint {
        pose: Frame {
            x: 200.0,
            y: 0.0,
            z: 100.0,
            a: 0.0,
            b: 180.0,
            c: 0.0,
        },
        axes: [0.0, -90.0, 90.0, 0.0, 0.0, 0.0],
    }
}

fn speeds() -> SpeedSettings {
    serde_json::from_value(json!({"override_pct": 100.0, "ptp_velocity_pct": 20.0,
        "ptp_acceleration_pct": 100.0, "cp_velocity_m_s": 0.25, "cp_acceleration_pct": 100.0}))
    .expect("speeds")
}

/// A motion: `spl` with a speed (`v` 0 or 1) and maybe `approx_mm: 0`, or a `lin`.
fn motion(kind: u8, v: u8, stop: bool, i: usize) -> MotionRequest {
    let x = 200.0 + i as f64;
    let body = match kind {
        0 => json!({"type": "lin", "target": {"x": x}, "velocity_m_s": 0.1}),
        _ if stop => {
            json!({"type": "spl", "target": {"x": x}, "velocity_m_s": 0.1 + f64::from(v) * 0.1, "approx_mm": 0})
        }
        _ => json!({"type": "spl", "target": {"x": x}, "velocity_m_s": 0.1 + f64::from(v) * 0.1}),
    };
    serde_json::from_value(body).expect("a motion")
}

/// The `left` of every record (0 for what is not an SPL point).
fn lefts(records: &[MotionRecord]) -> Vec<u8> {
    records
        .iter()
        .map(|r| match r {
            MotionRecord::Spl { left, .. } => *left,
            _ => 0,
        })
        .collect()
}

#[test]
fn runs_of_spl_points_become_blocks_of_at_most_eight() {
    let reqs: Vec<MotionRequest> = (0..20)
        .map(|i| motion(if i == 12 { 0 } else { 1 }, 0, i == 3, i))
        .collect();
    let r = resolve(&reqs, &start(), &speeds(), 1.0).expect("resolved");
    // 0..=3 (ends at approx 0), 4..=11 (8 points), a LIN, 13..=19.
    assert_eq!(
        lefts(&r),
        [4, 3, 2, 1, 8, 7, 6, 5, 4, 3, 2, 1, 0, 7, 6, 5, 4, 3, 2, 1]
    );
    // A change of speed ends a block too.
    let reqs: Vec<MotionRequest> = (0..4)
        .map(|i| motion(1, u8::from(i >= 2), false, i))
        .collect();
    let r = resolve(&reqs, &start(), &speeds(), 1.0).expect("resolved");
    assert_eq!(lefts(&r), [2, 1, 2, 1]);
}

proptest! {
    /// A stream cut anywhere appends the same blocks as the whole at once.
    #[test]
    fn a_stream_forms_the_same_blocks_however_its_bytes_break(
        spec in prop::collection::vec((0u8..4, 0u8..2, prop::bool::weighted(0.1)), 1..60),
        cuts in prop::collection::vec(1usize..60, 0..8),
    ) {
        let reqs: Vec<MotionRequest> = spec
            .iter()
            .enumerate()
            .map(|(i, (k, v, stop))| motion(u8::from(*k > 0), *v, *stop, i))
            .collect();
        let whole = lefts(&resolve(&reqs, &start(), &speeds(), 1.0).expect("resolved"));
        let mut cuts: Vec<usize> = cuts.into_iter().filter(|c| *c < reqs.len()).collect();
        cuts.sort_unstable();
        cuts.push(reqs.len());
        let mut sent: Vec<u8> = Vec::new();
        let mut batch: Vec<MotionRequest> = Vec::new();
        let mut parsed = 0;
        for (n, cut) in cuts.iter().enumerate() {
            batch.extend(reqs[parsed..*cut].iter().cloned());
            parsed = *cut;
            let last = n + 1 == cuts.len();
            let take = if last { batch.len() } else { batch.len() - open_spline_tail(&batch) };
            let part: Vec<MotionRequest> = batch.drain(..take).collect();
            if !part.is_empty() {
                sent.extend(lefts(&resolve(&part, &start(), &speeds(), 1.0).expect("resolved")));
            }
        }
        prop_assert_eq!(sent, whole);
    }
}

/// A batch of `lin`/`spl` motions, each maybe followed by `set_output`
/// actions (with and without a distance).
fn with_outputs(kinds: &[(u8, u8)]) -> Vec<MotionRequest> {
    let mut out = Vec::new();
    for (i, (kind, outputs)) in kinds.iter().enumerate() {
        out.push(motion(*kind, 0, false, i));
        for k in 0..*outputs {
            let path = if k % 2 == 0 { json!(null) } else { json!(-0.5) };
            out.push(
                serde_json::from_value(json!({"type": "set_output", "signal": 1 + u16::from(k),
                    "value": true, "path_mm": path}))
                .expect("an action"),
            );
        }
    }
    out
}

proptest! {
    /// Cut into commands of at most `max` records by `whole_blocks` (as the
    /// engine streams a batch or a path), no command ends inside a spline
    /// block, and none starts with a `set_output`: the controller gets
    /// every output with the motion it follows (it arms them when it plans
    /// that motion), as long as a motion's outputs fit into one command.
    #[test]
    fn commands_keep_blocks_and_a_motions_outputs_whole(
        kinds in proptest::collection::vec((0u8..2, 0u8..5), 1..40),
        max in 8usize..41,
    ) {
        let reqs = with_outputs(&kinds);
        let records = resolve(&reqs, &start(), &speeds(), 1.0).expect("resolved");
        let mut at = 0;
        while at < records.len() {
            let n = kuka_protocol::whole_blocks(&records[at..], max);
            prop_assert!(n >= 1 && n <= max, "{n} of at most {max}");
            at += n;
            if let Some(next) = records.get(at) {
                prop_assert!(
                    !matches!(next, MotionRecord::SetOutput { .. }),
                    "a command starts with an output at {at}"
                );
                prop_assert!(
                    !matches!(records[at - 1], MotionRecord::Spl { left, .. } if left > 1),
                    "a command ends inside a spline block at {at}"
                );
            }
        }
    }
}

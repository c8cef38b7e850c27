//! Protocol records and frames (`kuka_protocol`) as kinematics motions and
//! poses (`kuka_kinematics`): the one translation between the two, used
//! wherever motions from a command file or a program are planned.

use kuka_kinematics::{Motion, MotionKind, Pose};
use kuka_protocol::{Frame, MotionRecord};

/// Converts a protocol frame to a kinematics pose.
pub fn frame_to_pose(f: &Frame) -> Pose {
    Pose::new(f.x, f.y, f.z, f.a, f.b, f.c)
}

/// Converts a kinematics pose to a protocol frame.
pub fn pose_to_frame(p: &Pose) -> Frame {
    Frame {
        x: p.x,
        y: p.y,
        z: p.z,
        a: p.a,
        b: p.b,
        c: p.c,
    }
}

/// Approximation the planner gets between two points of one spline block:
/// the curve is tangent-continuous there, so the corner needs no rounding;
/// any distance above 0 only tells the planner not to stop.
const SPL_INNER_APPROX_MM: f64 = 1.0;

/// Converts a command's motion records (in order) to planner motions, one
/// per record, with the blending rules of the KRL program:
///
/// * SLIN/SCIRC/SPTP are planned as LIN/CIRC/PTP; a PTP/SPTP/axis PTP
///   never blends (its approximation is 0 here);
/// * an `SPL` is a segment of its block's curve (its neighbours from the
///   block), and a block's inner points never stop;
/// * the conventional (PTP/LIN/CIRC) and the spline family (SLIN/SCIRC/
///   SPTP/SPL) never blend into each other: a motion followed by one of
///   the other family stops exactly (a KRC's two motion planners,
///   docs/CONTROLLER.md point 21). The last record blends as asked (in a
///   path the next motion may come later).
///
/// The actions become planner steps of their own, so that index `i` of the
/// result is record `i`: a `WIN`/`DWL` is a [`MotionKind::Hold`] (a `WIN`
/// held for its whole timeout; the caller cuts it short when the input
/// comes) before which the robot stops exactly, an `SOT` a
/// [`MotionKind::Mark`] the planner skips (the motions on either side
/// blend as if it were not there).
pub fn to_motions(records: &[MotionRecord]) -> Vec<Motion> {
    records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            // The next record that is not an SOT: what this one blends into.
            let next = records[i + 1..]
                .iter()
                .find(|n| !matches!(n, MotionRecord::SetOutput { .. }));
            let Some(p) = r.params() else {
                let kind = match r {
                    MotionRecord::WaitInput { timeout_ms, .. } => MotionKind::Hold {
                        seconds: f64::from(*timeout_ms) / 1000.0,
                    },
                    MotionRecord::Dwell { ms } => MotionKind::Hold {
                        seconds: f64::from(*ms) / 1000.0,
                    },
                    _ => MotionKind::Mark,
                };
                return Motion {
                    kind,
                    velocity: 1.0,
                    acceleration_pct: 100.0,
                    approx_mm: 0.0,
                };
            };
            let kind = match r {
                MotionRecord::Ptp { target, s, t, .. }
                | MotionRecord::Sptp { target, s, t, .. } => MotionKind::Ptp {
                    target: frame_to_pose(target),
                    s: *s,
                    t: *t,
                },
                MotionRecord::PtpAxes { axes, .. } | MotionRecord::SptpAxes { axes, .. } => {
                    MotionKind::PtpAxes { axes: *axes }
                }
                MotionRecord::Lin { target, .. } | MotionRecord::Slin { target, .. } => {
                    MotionKind::Lin {
                        target: frame_to_pose(target),
                    }
                }
                MotionRecord::Circ { aux, target, .. }
                | MotionRecord::Scirc { aux, target, .. } => MotionKind::Circ {
                    aux: Pose::new(aux[0], aux[1], aux[2], 0.0, 0.0, 0.0),
                    target: frame_to_pose(target),
                },
                MotionRecord::Spl { target, left, .. } => MotionKind::Spl {
                    target: frame_to_pose(target),
                    first: !matches!(
                        i.checked_sub(1).map(|k| &records[k]),
                        Some(MotionRecord::Spl { left: l, .. }) if *l > 1
                    ),
                    // The point before this segment's start: the record
                    // two back, when it has a Cartesian target (else the
                    // planner takes it from the segment before).
                    prev: i
                        .checked_sub(2)
                        .and_then(|k| records[k].target())
                        .map(frame_to_pose),
                    next: match next {
                        Some(MotionRecord::Spl { target, .. }) if *left > 1 => {
                            Some(frame_to_pose(target))
                        }
                        _ => None,
                    },
                },
                MotionRecord::SetOutput { .. }
                | MotionRecord::WaitInput { .. }
                | MotionRecord::Dwell { .. } => unreachable!("actions have no parameters"),
            };
            let inner = matches!(r, MotionRecord::Spl { left, .. } if *left > 1);
            let ptp = matches!(
                r,
                MotionRecord::Ptp { .. }
                    | MotionRecord::PtpAxes { .. }
                    | MotionRecord::Sptp { .. }
                    | MotionRecord::SptpAxes { .. }
            );
            // (A PTP/SPTP always stops exactly: its approximation would
            // only widen the swept path the checks allow.)
            let approx_mm = if ptp {
                0.0
            } else if inner {
                SPL_INNER_APPROX_MM
            } else if next
                .is_some_and(|n| n.stops_robot() || n.is_spline_family() != r.is_spline_family())
            {
                0.0
            } else {
                p.approx_mm
            };
            Motion {
                kind,
                velocity: p.velocity,
                acceleration_pct: p.acceleration_pct,
                approx_mm,
            }
        })
        .collect()
}

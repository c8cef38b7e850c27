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

/// Converts a protocol motion record to a planner motion.
pub fn to_motion(r: &MotionRecord) -> Motion {
    let (kind, p) = match r {
        MotionRecord::Ptp {
            target,
            s,
            t,
            params,
        } => (
            MotionKind::Ptp {
                target: frame_to_pose(target),
                s: *s,
                t: *t,
            },
            params,
        ),
        MotionRecord::PtpAxes { axes, params } => (MotionKind::PtpAxes { axes: *axes }, params),
        MotionRecord::Lin { target, params } => (
            MotionKind::Lin {
                target: frame_to_pose(target),
            },
            params,
        ),
        MotionRecord::Circ {
            aux,
            target,
            params,
        } => (
            MotionKind::Circ {
                aux: Pose::new(aux[0], aux[1], aux[2], 0.0, 0.0, 0.0),
                target: frame_to_pose(target),
            },
            params,
        ),
    };
    Motion {
        kind,
        velocity: p.velocity,
        acceleration_pct: p.acceleration_pct,
        approx_mm: p.approx_mm,
    }
}

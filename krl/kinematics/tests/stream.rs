//! Planning a path that grows while it is played (`plan::plan_from`): a
//! continuation from a junction reproduces the whole plan, and a path
//! appended piece by piece while the robot moves runs as fast as the whole
//! path planned at once, with no stop between the pieces.

use kuka_kinematics::plan::{self, Execution, Junction, plan_from};
use kuka_kinematics::{Motion, MotionKind, PlanSettings, Pose, RobotModel};

/// A circle of `n` LIN segments (radius 50 mm, flange down, KR 3 R540's
/// A5 < 0 region), 0.2 m/s, approximated.
fn circle(n: usize) -> (Pose, Vec<Motion>) {
    let p = |i: usize| {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        Pose::new(
            190.0 + 50.0 * a.cos(),
            50.0 * a.sin(),
            100.0,
            0.0,
            180.0,
            0.0,
        )
    };
    let motions = (1..=n)
        .map(|i| Motion {
            kind: MotionKind::Lin { target: p(i) },
            velocity: 0.2,
            acceleration_pct: 100.0,
            approx_mm: 2.0,
        })
        .collect();
    (p(0), motions)
}

fn start_axes(m: &RobotModel, at: &Pose) -> kuka_kinematics::Axes {
    m.inverse(at, &Pose::IDENTITY, &Pose::IDENTITY, Some(6), None, &m.home)
        .expect("start reachable")
}

fn pose_at(e: &Execution, t: f64) -> Pose {
    let i = e.samples.partition_point(|s| s.t <= t + 1e-9);
    e.samples[i.saturating_sub(1)].pose
}

#[test]
fn a_continuation_from_any_junction_reproduces_the_whole_plan() {
    let m = RobotModel::kr3_r540();
    let settings = PlanSettings::for_model(&m);
    let (start, motions) = circle(60);
    let axes = start_axes(&m, &start);
    let id = Pose::IDENTITY;
    let whole = plan::plan(&m, &axes, &id, &id, &motions, &settings);
    assert!(whole.error.is_none(), "{:?}", whole.error);
    assert_eq!(
        whole.junctions.len(),
        motions.len(),
        "one junction per motion"
    );
    for j in whole.junctions.iter().step_by(7) {
        let rest = plan_from(&m, &id, &id, &motions[j.motion..], &settings, j);
        assert!(rest.error.is_none(), "{:?}", rest.error);
        assert!(
            (rest.duration_s - whole.duration_s).abs() < 1e-9,
            "junction {}: {} vs {}",
            j.motion,
            rest.duration_s,
            whole.duration_s
        );
        // Every later sample is on the same grid, at the same place.
        for s in rest.samples.iter().skip(1) {
            let w = pose_at(&whole, s.t);
            let d = (s.pose.position() - w.position()).length();
            assert!(d < 1e-6, "junction {} t {}: {d} mm apart", j.motion, s.t);
            assert_eq!(
                s.motion + j.motion,
                whole.samples[whole.samples.partition_point(|x| x.t < s.t - 1e-9)].motion
            );
        }
    }
}

/// Appends the circle 5 segments at a time, each time from the next
/// junction the robot has not reached when the append comes (the robot plays
/// 30 ms between appends): the path runs without a stop and takes no longer
/// than the whole path planned at once.
#[test]
fn a_path_appended_while_it_plays_does_not_stop_between_pieces() {
    let m = RobotModel::kr3_r540();
    let settings = PlanSettings::for_model(&m);
    let (start, motions) = circle(200);
    let axes = start_axes(&m, &start);
    let id = Pose::IDENTITY;
    let whole = plan::plan(&m, &axes, &id, &id, &motions, &settings);
    // The first piece: 20 motions planned from the standstill.
    let mut known = 20;
    let mut exec = plan::plan(&m, &axes, &id, &id, &motions[..known], &settings);
    let mut offset = 0; // motion index of exec's motion 0
    let mut played: Vec<(f64, Pose)> = Vec::new();
    let mut t = 0.0;
    while known < motions.len() {
        t += 0.030;
        // The next junction ahead of the robot.
        let j: Junction =
            *exec.junctions.iter().find(|j| j.t > t).expect(
                "the robot has not reached the last motion: appends come faster than it moves",
            );
        let last = played.last().map_or(-1.0, |p| p.0);
        played.extend(
            exec.samples
                .iter()
                .filter(|s| s.t <= j.t && s.t > last)
                .map(|s| (s.t, s.pose)),
        );
        known = (known + 5).min(motions.len());
        let from = offset + j.motion;
        exec = plan_from(&m, &id, &id, &motions[from..known], &settings, &j);
        assert!(exec.error.is_none(), "{:?}", exec.error);
        offset = from;
    }
    let total = exec.duration_s;
    assert!(
        total <= whole.duration_s * 1.001,
        "appended: {total:.4} s, whole: {:.4} s",
        whole.duration_s
    );
    let last = played.last().map_or(-1.0, |p| p.0);
    played.extend(
        exec.samples
            .iter()
            .filter(|s| s.t > last)
            .map(|s| (s.t, s.pose)),
    );
    // No stop: between two samples the TCP keeps its speed (a stop would
    // show as a slow-down towards 0), after the first acceleration and
    // before the last deceleration.
    let end = played.last().map_or(0.0, |p| p.0);
    for w in played.windows(2) {
        let dt = w[1].0 - w[0].0;
        if dt < 1e-6 || w[0].0 < 0.15 || w[1].0 > end - 0.15 {
            continue;
        }
        let v = (w[1].1.position() - w[0].1.position()).length() / dt;
        assert!(v > 150.0, "slowed to {v:.1} mm/s at t = {:.3} s", w[0].0);
    }
}

//! Planner tests: PTP timing, LIN/CIRC geometry, approximation, errors and
//! planning speed.

use std::f64::consts::PI;
use std::time::Instant;

use kuka_kinematics::plan::plan;
use kuka_kinematics::{
    Axes, Execution, IkError, Motion, MotionError, MotionKind, PlanSettings, Pose, RobotModel,
};

const NONE: Pose = Pose::IDENTITY;
const HOME: Axes = [0.0, -90.0, 90.0, 0.0, 0.0, 0.0];

fn lin(target: Pose, v: f64, approx: f64) -> Motion {
    Motion {
        kind: MotionKind::Lin { target },
        velocity: v,
        acceleration_pct: 100.0,
        approx_mm: approx,
    }
}

fn ptp_axes(axes: Axes, v: f64) -> Motion {
    Motion {
        kind: MotionKind::PtpAxes { axes },
        velocity: v,
        acceleration_pct: 100.0,
        approx_mm: 0.0,
    }
}

fn ptp(target: Pose) -> Motion {
    Motion {
        kind: MotionKind::Ptp {
            target,
            s: None,
            t: None,
        },
        velocity: 100.0,
        acceleration_pct: 100.0,
        approx_mm: 0.0,
    }
}

/// Common sanity checks on every execution.
fn check_samples(m: &RobotModel, ex: &Execution, settings: &PlanSettings) {
    assert!(!ex.samples.is_empty());
    assert_eq!(ex.samples[0].t, 0.0);
    for w in ex.samples.windows(2) {
        assert!(w[1].t > w[0].t, "{} {}", w[0].t, w[1].t);
        assert!(w[1].t - w[0].t <= settings.sample_period_s + 1e-9);
        assert!(w[1].motion >= w[0].motion);
    }
    for s in &ex.samples {
        let fk = m.forward(&s.axes, &NONE, &NONE);
        assert!(fk.approx_eq(&s.pose, 1e-6, 1e-6), "{fk:?} vs {:?}", s.pose);
        assert!(m.check_limits(&s.axes).is_ok());
    }
    let last = ex.samples.last().expect("samples");
    assert!((last.t - ex.duration_s).abs() < 1e-9);
    assert_eq!(last.axes, ex.end_axes);
}

#[test]
fn ptp_duration_matches_trapezoid() {
    let m = RobotModel::kr3_r540();
    let mut settings = PlanSettings::default();
    // Triangular profile: 90° of A1 at 300 deg/s² never reaches 530 deg/s.
    let ex = plan(
        &m,
        &HOME,
        &NONE,
        &NONE,
        &[ptp_axes([90.0, -90.0, 90.0, 0.0, 0.0, 0.0], 100.0)],
        &settings,
    );
    assert_eq!(ex.error, None);
    check_samples(&m, &ex, &settings);
    let want = 2.0 * (90.0f64 / 300.0).sqrt();
    assert!(
        (ex.duration_s - want).abs() < 1e-9,
        "{} vs {want}",
        ex.duration_s
    );
    // Trapezoid with cruise: 300° of A1 at 50 % (265 deg/s), 3000 deg/s².
    settings.max_acc_axis_deg_s2 = [3000.0; 6];
    let start = [-150.0, -90.0, 90.0, 0.0, 0.0, 0.0];
    let ex = plan(
        &m,
        &start,
        &NONE,
        &NONE,
        &[ptp_axes([150.0, -90.0, 90.0, 0.0, 0.0, 0.0], 50.0)],
        &settings,
    );
    let want = 300.0 / 265.0 + 265.0 / 3000.0;
    assert!(
        (ex.duration_s - want).abs() < 1e-9,
        "{} vs {want}",
        ex.duration_s
    );
    // Override halves the speed again.
    settings.override_pct = 50.0;
    let ex = plan(
        &m,
        &start,
        &NONE,
        &NONE,
        &[ptp_axes([150.0, -90.0, 90.0, 0.0, 0.0, 0.0], 100.0)],
        &settings,
    );
    assert!(
        (ex.duration_s - want).abs() < 1e-9,
        "{} vs {want}",
        ex.duration_s
    );
}

#[test]
fn ptp_is_synchronous_and_led_by_slowest_axis() {
    let m = RobotModel::kr10_r1100_sixx();
    let settings = PlanSettings::default();
    let target = [40.0, -60.0, 100.0, 90.0, 30.0, -120.0];
    let ex = plan(
        &m,
        &HOME,
        &NONE,
        &NONE,
        &[ptp_axes(target, 100.0)],
        &settings,
    );
    assert_eq!(ex.error, None);
    check_samples(&m, &ex, &settings);
    assert_eq!(ex.end_axes, target);
    // Leading axis: the largest single-axis trapezoid time.
    let single = |d: f64, v: f64, a: f64| {
        if d >= v * v / a {
            d / v + v / a
        } else {
            2.0 * (d / a).sqrt()
        }
    };
    let lead = (0..6)
        .map(|i| single((target[i] - HOME[i]).abs(), m.max_speed_deg_s[i], 300.0))
        .fold(0.0, f64::max);
    assert!(
        (ex.duration_s - lead).abs() < 1e-9,
        "{} vs {lead}",
        ex.duration_s
    );
    // Every axis is at the same fraction of its way at every sample.
    for s in &ex.samples {
        let f0 = (s.axes[5] - HOME[5]) / (target[5] - HOME[5]);
        for i in 0..5 {
            let f = (s.axes[i] - HOME[i]) / (target[i] - HOME[i]);
            assert!((f - f0).abs() < 1e-9);
        }
    }
}

#[test]
fn cartesian_ptp_reaches_target() {
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let target = Pose::new(400.0, 150.0, 300.0, 0.0, 180.0, 0.0);
    let ex = plan(&m, &HOME, &NONE, &NONE, &[ptp(target)], &settings);
    assert_eq!(ex.error, None);
    check_samples(&m, &ex, &settings);
    assert!(
        m.forward(&ex.end_axes, &NONE, &NONE)
            .approx_eq(&target, 1e-6, 1e-6)
    );
    // Unreachable PTP: nothing moves.
    let far = Pose::new(1500.0, 0.0, 300.0, 0.0, 180.0, 0.0);
    let ex = plan(&m, &HOME, &NONE, &NONE, &[ptp(target), ptp(far)], &settings);
    assert_eq!(ex.error, Some((1, MotionError::Ik(IkError::Unreachable))));
    assert!(
        m.forward(&ex.end_axes, &NONE, &NONE)
            .approx_eq(&target, 1e-6, 1e-6)
    );
    check_samples(&m, &ex, &settings);
}

#[test]
fn lin_stays_on_the_line() {
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let start_pose = Pose::new(450.0, -150.0, 400.0, 0.0, 180.0, 0.0);
    let target = Pose::new(350.0, 200.0, 250.0, 30.0, 160.0, 10.0);
    let v = 0.25;
    let ex = plan(
        &m,
        &HOME,
        &NONE,
        &NONE,
        &[ptp(start_pose), lin(target, v, 0.0)],
        &settings,
    );
    assert_eq!(ex.error, None);
    check_samples(&m, &ex, &settings);
    let p0 = start_pose.position();
    let dir = (target.position() - p0).normalize();
    let mut on_lin = 0;
    for s in ex.samples.iter().filter(|s| s.motion == 1) {
        let d = s.pose.position() - p0;
        let off = (d - dir * d.dot(dir)).length();
        assert!(off < 1e-6, "{off}");
        on_lin += 1;
    }
    assert!(on_lin > 50);
    let end = m.forward(&ex.end_axes, &NONE, &NONE);
    assert!(end.approx_eq(&target, 1e-6, 1e-6), "{end:?}");
    // Timing: the LIN alone is L/v + v/a (it reaches cruise speed), with a
    // the path acceleration (2.3 m/s²) or, if lower, the one that keeps the
    // re-orientation within ORI_ACC_DEG_S2 (100 °/s²).
    let t_ptp = plan(&m, &HOME, &NONE, &NONE, &[ptp(start_pose)], &settings).duration_s;
    let len = start_pose.distance_mm(&target);
    let angle = start_pose.angle_deg(&target);
    let le = len.max(angle * v * 1000.0 / kuka_kinematics::plan::ORI_SPEED_DEG_S);
    let a = (2.3_f64).min(kuka_kinematics::plan::ORI_ACC_DEG_S2 * le / angle / 1000.0);
    assert!(a < 2.3, "this LIN is limited by its re-orientation: {a}");
    let want = le / (v * 1000.0) + v / a;
    let got = ex.duration_s - t_ptp;
    assert!((got - want).abs() < 1e-6, "{got} vs {want}");
}

#[test]
fn circ_passes_through_aux() {
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    // Vertical circle in the plane X = 400, centre (400, 0, 400), r = 100.
    let start = Pose::new(400.0, 0.0, 500.0, 0.0, 180.0, 0.0);
    let aux = Pose::new(400.0, 100.0, 400.0, 0.0, 180.0, 0.0);
    let target = Pose::new(400.0, 0.0, 300.0, 0.0, 170.0, 0.0);
    let circ = Motion {
        kind: MotionKind::Circ { aux, target },
        velocity: 0.2,
        acceleration_pct: 100.0,
        approx_mm: 0.0,
    };
    let ex = plan(&m, &HOME, &NONE, &NONE, &[ptp(start), circ], &settings);
    assert_eq!(ex.error, None);
    check_samples(&m, &ex, &settings);
    let centre = Pose::new(400.0, 0.0, 400.0, 0.0, 0.0, 0.0).position();
    let mut closest = f64::INFINITY;
    for s in ex.samples.iter().filter(|s| s.motion == 1) {
        let p = s.pose.position();
        assert!(((p - centre).length() - 100.0).abs() < 1e-6);
        assert!((p.x - 400.0).abs() < 1e-6);
        assert!(p.y > -1e-6, "took the wrong half: {p:?}");
        closest = closest.min(s.pose.distance_mm(&aux));
    }
    // At 200 mm/s samples are 2.4 mm apart.
    assert!(closest < 1.3, "{closest}");
    assert!(
        m.forward(&ex.end_axes, &NONE, &NONE)
            .approx_eq(&target, 1e-6, 1e-6)
    );
    let t_ptp = plan(&m, &HOME, &NONE, &NONE, &[ptp(start)], &settings).duration_s;
    let want = PI * 100.0 / 200.0 + 0.2 / 2.3;
    assert!((ex.duration_s - t_ptp - want).abs() < 1e-6);
}

#[test]
fn circ_with_collinear_points_is_rejected() {
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let start = Pose::new(400.0, 0.0, 500.0, 0.0, 180.0, 0.0);
    let p1 = Pose::new(400.0, 50.0, 500.0, 0.0, 180.0, 0.0);
    let bad = Motion {
        kind: MotionKind::Circ {
            aux: Pose::new(400.0, 100.0, 500.0, 0.0, 180.0, 0.0),
            target: Pose::new(400.0, 200.0, 500.0, 0.0, 180.0, 0.0),
        },
        velocity: 0.2,
        acceleration_pct: 100.0,
        approx_mm: 0.0,
    };
    let ex = plan(
        &m,
        &HOME,
        &NONE,
        &NONE,
        &[ptp(start), lin(p1, 0.2, 10.0), bad.clone()],
        &settings,
    );
    assert!(
        matches!(ex.error, Some((2, MotionError::Geometry(_)))),
        "{:?}",
        ex.error
    );
    // The LIN before it ran (and stopped exactly at its end).
    assert!(
        m.forward(&ex.end_axes, &NONE, &NONE)
            .approx_eq(&p1, 1e-6, 1e-6)
    );
    check_samples(&m, &ex, &settings);
    // Coincident points.
    let coincident = Motion {
        kind: MotionKind::Circ {
            aux: start,
            target: p1,
        },
        ..bad
    };
    let ex = plan(
        &m,
        &HOME,
        &NONE,
        &NONE,
        &[ptp(start), coincident],
        &settings,
    );
    assert!(
        matches!(ex.error, Some((1, MotionError::Geometry(_)))),
        "{:?}",
        ex.error
    );
}

/// A 200-segment polygon approximating a circle of radius 100 mm in the
/// horizontal plane, flange pointing down, starting and ending at `centre + (100, 0, 0)`.
fn polygon(v: f64, approx: f64) -> (Pose, Vec<Motion>, f64) {
    let (cx, cy, z, r) = (400.0, 0.0, 300.0, 100.0);
    let n = 200;
    let motions: Vec<Motion> = (1..=n)
        .map(|k| {
            let phi = 2.0 * PI * k as f64 / n as f64;
            lin(
                Pose::new(cx + r * phi.cos(), cy + r * phi.sin(), z, 0.0, 180.0, 0.0),
                v,
                approx,
            )
        })
        .collect();
    let len = n as f64 * 2.0 * r * (PI / n as f64).sin();
    (Pose::new(cx + r, cy, z, 0.0, 180.0, 0.0), motions, len)
}

#[test]
fn blended_polygon_runs_at_constant_speed() {
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let v = 0.2;
    let (start_pose, poly, len) = polygon(v, 5.0);
    let start = m
        .inverse(&start_pose, &NONE, &NONE, None, None, &HOME)
        .expect("reachable");
    let ex = plan(&m, &start, &NONE, &NONE, &poly, &settings);
    assert_eq!(ex.error, None);
    check_samples(&m, &ex, &settings);
    let ideal = len / (v * 1000.0) + v / 2.3;
    println!(
        "blended 200-segment polygon: {:.4} s, ideal {:.4} s, ratio {:.4}",
        ex.duration_s,
        ideal,
        ex.duration_s / ideal
    );
    assert!(
        ex.duration_s <= 1.05 * ideal,
        "{} vs {ideal}",
        ex.duration_s
    );
    // In the middle the TCP moves at the programmed speed.
    let mid: Vec<_> = ex
        .samples
        .iter()
        .filter(|s| s.t > 0.5 && s.t < ex.duration_s - 0.5)
        .collect();
    for w in mid.windows(2) {
        let speed = w[0].pose.distance_mm(&w[1].pose) / (w[1].t - w[0].t);
        assert!(
            speed > 0.97 * v * 1000.0 && speed < v * 1000.0 + 1e-6,
            "{speed}"
        );
    }
    assert!(
        m.forward(&ex.end_axes, &NONE, &NONE)
            .approx_eq(&start_pose, 1e-6, 1e-6)
    );

    // Without approximation every corner is an exact stop: much slower.
    let (_, exact, _) = polygon(v, 0.0);
    let ex0 = plan(&m, &start, &NONE, &NONE, &exact, &settings);
    assert_eq!(ex0.error, None);
    println!("exact-stop 200-segment polygon: {:.4} s", ex0.duration_s);
    assert!(
        ex0.duration_s > 3.0 * ex.duration_s,
        "{} vs {}",
        ex0.duration_s,
        ex.duration_s
    );
}

#[test]
fn polygon_plans_fast() {
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let (start_pose, poly, _) = polygon(0.2, 5.0);
    let start = m
        .inverse(&start_pose, &NONE, &NONE, None, None, &HOME)
        .expect("reachable");
    let t0 = Instant::now();
    let mut n = 0;
    for _ in 0..5 {
        n += plan(&m, &start, &NONE, &NONE, &poly, &settings)
            .samples
            .len();
    }
    let per = t0.elapsed().as_secs_f64() / 5.0;
    println!(
        "200-segment batch ({} samples): {:.2} ms per plan",
        n / 5,
        per * 1000.0
    );
    let budget = if cfg!(debug_assertions) { 1.0 } else { 0.05 };
    assert!(per < budget, "{per} s");
}

#[test]
fn corner_speed_follows_approximation() {
    // Two LINs at a right angle: with approximation the corner is passed at
    // √(a·r), r = d / tan(45°) = d; without, the robot stops.
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let a = Pose::new(400.0, -100.0, 300.0, 0.0, 180.0, 0.0);
    let b = Pose::new(400.0, 100.0, 300.0, 0.0, 180.0, 0.0);
    let c = Pose::new(500.0, 100.0, 300.0, 0.0, 180.0, 0.0);
    let start = m
        .inverse(&a, &NONE, &NONE, None, None, &HOME)
        .expect("reachable");
    let t = |approx: f64| {
        plan(
            &m,
            &start,
            &NONE,
            &NONE,
            &[lin(b, 1.0, approx), lin(c, 1.0, 0.0)],
            &settings,
        )
    };
    let exact = t(0.0);
    let blended = t(20.0);
    assert_eq!(exact.error, None);
    assert_eq!(blended.error, None);
    assert!(
        blended.duration_s < exact.duration_s - 0.05,
        "{} {}",
        blended.duration_s,
        exact.duration_s
    );
    // The slowest point of the blended run (away from start and end) is the
    // corner, passed at about √(a·r) (sample pairs average over 12 ms, during
    // which the speed changes by at most a·dt).
    let slowest = |ex: &Execution| {
        ex.samples
            .windows(2)
            .filter(|w| w[0].t > 0.15 && w[1].t < ex.duration_s - 0.15)
            .map(|w| {
                // Path length, also for the pair that straddles the corner.
                let d = if w[0].motion == w[1].motion {
                    w[0].pose.distance_mm(&w[1].pose)
                } else {
                    w[0].pose.distance_mm(&b) + b.distance_mm(&w[1].pose)
                };
                d / (w[1].t - w[0].t)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let vj = (2300.0f64 * 20.0).sqrt();
    let v_blend = slowest(&blended);
    let v_exact = slowest(&exact);
    println!("corner speed {v_blend:.1} mm/s (limit {vj:.1}), exact stop {v_exact:.1} mm/s");
    assert!(
        v_blend > 0.8 * vj && v_blend < vj + 2300.0 * 0.012,
        "{v_blend} vs {vj}"
    );
    // Without approximation the robot stops at the corner.
    assert!(v_exact < 2300.0 * 0.012, "{v_exact}");
}

#[test]
fn wrist_singularity_is_detected() {
    // From home (A5 = 0) a sideways LIN with the orientation kept needs
    // A4 to jump by ~90° at once.
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let home = m.forward(&HOME, &NONE, &NONE);
    let target = Pose { y: 200.0, ..home };
    let ex = plan(&m, &HOME, &NONE, &NONE, &[lin(target, 0.5, 0.0)], &settings);
    assert_eq!(
        ex.error,
        Some((0, MotionError::Singularity("wrist"))),
        "{:?}",
        ex.end_axes
    );
    check_samples(&m, &ex, &settings);
}

#[test]
fn software_limit_on_the_path() {
    // Behind the robot: from A1 ≈ −146° to +146° the straight line crosses
    // A1 = ±180°, beyond the ±170° limit switches.
    let m = RobotModel::kr6_r900_sixx();
    let settings = PlanSettings::default();
    let a = Pose::new(-300.0, 200.0, 500.0, 0.0, 180.0, 0.0);
    let b = Pose::new(-300.0, -200.0, 500.0, 0.0, 180.0, 0.0);
    let start = m
        .inverse(&a, &NONE, &NONE, None, None, &HOME)
        .expect("reachable");
    let ex = plan(&m, &start, &NONE, &NONE, &[lin(b, 0.3, 0.0)], &settings);
    assert!(
        matches!(
            ex.error,
            Some((0, MotionError::Ik(IkError::SoftwareLimit { axis: 1, .. })))
        ),
        "{:?}",
        ex.error
    );
    check_samples(&m, &ex, &settings);
    assert!(ex.end_axes[0].abs() > 160.0, "{:?}", ex.end_axes);
}

#[test]
fn unreachable_lin_target_stops_before() {
    let m = RobotModel::kr3_r540();
    let settings = PlanSettings::default();
    let home = m.forward(&HOME, &NONE, &NONE);
    let a = Pose {
        z: home.z - 100.0,
        ..home
    };
    let far = Pose { x: 2000.0, ..home };
    let ex = plan(
        &m,
        &HOME,
        &NONE,
        &NONE,
        &[lin(a, 0.2, 10.0), lin(far, 0.2, 0.0)],
        &settings,
    );
    assert_eq!(ex.error, Some((1, MotionError::Ik(IkError::Unreachable))));
    assert!(
        m.forward(&ex.end_axes, &NONE, &NONE)
            .approx_eq(&a, 1e-6, 1e-6)
    );
    check_samples(&m, &ex, &settings);
}

#[test]
fn parameters_are_validated() {
    let m = RobotModel::kr3_r540();
    let settings = PlanSettings::default();
    let home = m.forward(&HOME, &NONE, &NONE);
    let ok = ptp_axes([10.0, -90.0, 90.0, 0.0, 0.0, 0.0], 50.0);
    let bad_motions = [
        ptp_axes(HOME, 0.0),
        ptp_axes(HOME, 150.0),
        ptp_axes([f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0], 50.0),
        lin(home, 3.0, 0.0),
        lin(home, -0.1, 0.0),
        lin(home, 0.1, -1.0),
        lin(home, f64::INFINITY, 0.0),
        Motion {
            acceleration_pct: 0.0,
            ..lin(home, 0.1, 0.0)
        },
        Motion {
            acceleration_pct: 101.0,
            ..lin(home, 0.1, 0.0)
        },
        Motion {
            kind: MotionKind::Ptp {
                target: home,
                s: Some(8),
                t: None,
            },
            ..ok.clone()
        },
    ];
    for bad in bad_motions {
        let ex = plan(
            &m,
            &HOME,
            &NONE,
            &NONE,
            &[ok.clone(), bad.clone()],
            &settings,
        );
        assert!(
            matches!(ex.error, Some((1, MotionError::Parameter(_)))),
            "{bad:?}: {:?}",
            ex.error
        );
        // The valid first motion was executed.
        assert_eq!(ex.end_axes, [10.0, -90.0, 90.0, 0.0, 0.0, 0.0]);
    }
    let bad_settings = PlanSettings {
        sample_period_s: 0.0,
        ..PlanSettings::default()
    };
    let ex = plan(&m, &HOME, &NONE, &NONE, &[ok], &bad_settings);
    assert!(matches!(ex.error, Some((0, MotionError::Parameter(_)))));
    assert_eq!(ex.end_axes, HOME);
}

#[test]
fn ptp_software_limit_and_empty_batch() {
    let m = RobotModel::kr3_r540();
    let settings = PlanSettings::default();
    let ex = plan(
        &m,
        &HOME,
        &NONE,
        &NONE,
        &[ptp_axes([0.0, -90.0, 160.0, 0.0, 0.0, 0.0], 50.0)],
        &settings,
    );
    assert!(matches!(
        ex.error,
        Some((0, MotionError::Ik(IkError::SoftwareLimit { axis: 3, .. })))
    ));
    assert_eq!(ex.end_axes, HOME);
    let ex = plan(&m, &HOME, &NONE, &NONE, &[], &settings);
    assert_eq!(ex.error, None);
    assert_eq!(ex.samples.len(), 1);
    assert_eq!(ex.duration_s, 0.0);
}

#[test]
fn mixed_batch_with_tool_and_base() {
    let m = RobotModel::kr3_r540();
    let settings = PlanSettings::default();
    let tool = Pose::new(0.0, 0.0, 60.0, 0.0, 0.0, 0.0);
    // Kept where A5 stays positive with this tool pointing down: a LIN or
    // CIRC crossing A5 = 0 (about 215 mm out at this height) is a singularity.
    let base = Pose::new(280.0, 0.0, 100.0, 0.0, 0.0, 0.0);
    let p = |x: f64, y: f64| Pose::new(x, y, 50.0, 0.0, 180.0, 0.0);
    let motions = vec![
        Motion {
            kind: MotionKind::Ptp {
                target: p(0.0, 0.0),
                s: Some(2),
                t: None,
            },
            velocity: 100.0,
            acceleration_pct: 100.0,
            approx_mm: 10.0,
        },
        lin(p(50.0, 0.0), 0.3, 5.0),
        Motion {
            kind: MotionKind::Circ {
                aux: p(0.0, 50.0),
                target: p(-50.0, 0.0),
            },
            velocity: 0.3,
            acceleration_pct: 50.0,
            approx_mm: 5.0,
        },
        lin(p(0.0, 0.0), 0.3, 0.0),
        ptp_axes(HOME, 100.0),
    ];
    let ex = plan(&m, &HOME, &tool, &base, &motions, &settings);
    assert_eq!(ex.error, None);
    assert_eq!(ex.end_axes, HOME);
    for s in &ex.samples {
        assert!(
            m.forward(&s.axes, &tool, &base)
                .approx_eq(&s.pose, 1e-6, 1e-6)
        );
    }
    for i in 0..motions.len() {
        assert!(
            ex.samples.iter().any(|s| s.motion == i),
            "motion {i} has no samples"
        );
    }
}

/// A LIN whose wrist point crosses the A1 axis would change Status bit 0
/// (overhead): a Cartesian path cannot, so it stops with a singularity.
#[test]
fn lin_through_the_a1_axis_is_an_overhead_singularity() {
    let model = RobotModel::kr3_r540();
    let tool = Pose::IDENTITY;
    let base = Pose::IDENTITY;
    let motion = Motion {
        kind: MotionKind::Lin {
            target: Pose::new(0.0, 0.0, 625.0, 0.0, 90.0, 0.0),
        },
        velocity: 0.25,
        acceleration_pct: 100.0,
        approx_mm: 0.0,
    };
    let ex = plan(
        &model,
        &model.home,
        &tool,
        &base,
        &[motion],
        &PlanSettings::default(),
    );
    match ex.error {
        Some((0, MotionError::Singularity(_))) => {}
        other => panic!("expected a singularity, got {other:?}"),
    }
}

/// Spline points (a block of `SPL`) on a circle, planned as the simulated
/// controllers plan them: inner points blend (`approx_mm > 0`).
fn spline_circle(v: f64, points: usize) -> (Pose, Vec<Motion>) {
    let (cx, cy, z, r) = (400.0, 0.0, 300.0, 100.0);
    let at = |k: usize| {
        let phi = 2.0 * PI * k as f64 / points as f64;
        Pose::new(cx + r * phi.cos(), cy + r * phi.sin(), z, 0.0, 180.0, 0.0)
    };
    let motions = (1..=points)
        .map(|k| Motion {
            kind: MotionKind::Spl {
                target: at(k),
                first: k == 1,
                prev: None,
                next: (k < points).then(|| at(k + 1)),
            },
            velocity: v,
            acceleration_pct: 100.0,
            approx_mm: if k < points { 1.0 } else { 0.0 },
        })
        .collect();
    (at(0), motions)
}

#[test]
fn a_spline_block_is_a_smooth_curve_through_its_points() {
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let v = 0.2;
    let (start_pose, block) = spline_circle(v, 8);
    let start = m
        .inverse(&start_pose, &NONE, &NONE, None, None, &HOME)
        .expect("reachable");
    let ex = plan(&m, &start, &NONE, &NONE, &block, &settings);
    assert_eq!(ex.error, None);
    check_samples(&m, &ex, &settings);
    // Eight points on a circle of 100 mm: the chords pass up to 7.6 mm
    // inside it, the curve (apart from its first and last segment, whose
    // outer tangent is mirrored) stays within 1.5 mm.
    let centre = Pose::new(400.0, 0.0, 300.0, 0.0, 180.0, 0.0).position();
    let mut worst: f64 = 0.0;
    for s in ex.samples.iter().filter(|s| s.motion >= 1 && s.motion <= 6) {
        let off = ((s.pose.position() - centre).length() - 100.0).abs();
        worst = worst.max(off);
        assert!((s.pose.z - 300.0).abs() < 1e-6);
    }
    assert!(worst < 1.5, "{worst} mm off the circle");
    // It passes through every point (the junctions) and ends at the last.
    for (j, mo) in block.iter().enumerate() {
        let MotionKind::Spl { target, .. } = mo.kind else {
            unreachable!()
        };
        if let Some(next) = ex.junctions.iter().find(|x| x.motion == j + 1) {
            let at = m.forward(&next.axes, &NONE, &NONE);
            assert!(at.distance_mm(&target) < 1e-3, "point {j}: {at:?}");
        }
    }
    let end = m.forward(&ex.end_axes, &NONE, &NONE);
    assert!(end.approx_eq(&start_pose, 1e-6, 1e-6), "{end:?}");
    // No stop at the points: the TCP keeps the programmed speed.
    let mid: Vec<_> = ex
        .samples
        .iter()
        .filter(|s| s.t > 0.2 && s.t < ex.duration_s - 0.2)
        .collect();
    for w in mid.windows(2) {
        let speed = w[0].pose.distance_mm(&w[1].pose) / (w[1].t - w[0].t);
        assert!(speed > 0.95 * v * 1000.0, "{speed} mm/s at {}", w[0].t);
    }
    // Without blending each point is an exact stop: much slower.
    let exact: Vec<Motion> = block
        .iter()
        .cloned()
        .map(|mut mo| {
            mo.approx_mm = 0.0;
            mo
        })
        .collect();
    let ex0 = plan(&m, &start, &NONE, &NONE, &exact, &settings);
    assert_eq!(ex0.error, None);
    // (each of the 7 inner stops costs about v/a = 87 ms)
    assert!(
        ex0.duration_s > ex.duration_s + 7.0 * 0.08,
        "{} vs {}",
        ex0.duration_s,
        ex.duration_s
    );
}

#[test]
fn a_spline_block_of_one_point_is_a_straight_line() {
    let m = RobotModel::kr6_r700_sixx();
    let settings = PlanSettings::default();
    let start_pose = Pose::new(450.0, -150.0, 400.0, 0.0, 180.0, 0.0);
    let target = Pose::new(350.0, 200.0, 250.0, 0.0, 180.0, 0.0);
    let spl = Motion {
        kind: MotionKind::Spl {
            target,
            first: true,
            prev: None,
            next: None,
        },
        velocity: 0.25,
        acceleration_pct: 100.0,
        approx_mm: 0.0,
    };
    let a = plan(&m, &HOME, &NONE, &NONE, &[ptp(start_pose), spl], &settings);
    let b = plan(
        &m,
        &HOME,
        &NONE,
        &NONE,
        &[ptp(start_pose), lin(target, 0.25, 0.0)],
        &settings,
    );
    assert_eq!(a.error, None);
    assert!((a.duration_s - b.duration_s).abs() < 1e-3);
    for (x, y) in a.samples.iter().zip(&b.samples) {
        assert!(
            x.pose.distance_mm(&y.pose) < 0.05,
            "{:?} {:?}",
            x.pose,
            y.pose
        );
    }
}

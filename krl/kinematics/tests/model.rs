//! Kinematics acceptance tests: KUKA conventions against the design brief's
//! numbers, FK∘IK round trips with Status/Turn, reachability and limits.

use kuka_kinematics::{Axes, IkError, Pose, RobotModel};

const HOME: Axes = [0.0, -90.0, 90.0, 0.0, 0.0, 0.0];
const NONE: Pose = Pose::IDENTITY;

/// Small deterministic PRNG (xorshift64*), so the tests need no dependency.
struct Rng(u64);
impl Rng {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

fn all_models() -> Vec<RobotModel> {
    RobotModel::builtin_names()
        .iter()
        .map(|n| RobotModel::by_name(n).expect("built-in model"))
        .collect()
}

#[test]
fn r700_home_matches_brief() {
    let m = RobotModel::kr6_r700_sixx();
    let p = m.forward(&HOME, &NONE, &NONE);
    let want = Pose::new(470.0, 0.0, 750.0, 0.0, 90.0, 0.0);
    assert!(p.approx_eq(&want, 1e-6, 1e-6), "{p:?}");
    assert!(
        p.a.abs() < 1e-6 && (p.b - 90.0).abs() < 1e-6 && p.c.abs() < 1e-6,
        "{p:?}"
    );
}

#[test]
fn positive_a1_turns_clockwise() {
    let m = RobotModel::kr6_r700_sixx();
    let p = m.forward(&[30.0, -90.0, 90.0, 0.0, 0.0, 0.0], &NONE, &NONE);
    assert!((p.y + 235.0).abs() < 1e-6, "{p:?}");
    assert!(
        (p.x - 470.0 * 30f64.to_radians().cos()).abs() < 1e-6,
        "{p:?}"
    );
    assert!((p.a + 30.0).abs() < 1e-6, "{p:?}");
}

#[test]
fn kr3_home_and_defaults() {
    let m = RobotModel::kr3_r540();
    assert_eq!(m.home, HOME);
    let p = m.flange(&m.home);
    // x = a1 + A3-to-wrist + wrist-to-flange, z = base + A2-A3 + A3-A4 offset.
    let want = Pose::new(
        20.0 + 260.0 + 75.0,
        0.0,
        345.0 + 260.0 + 20.0,
        0.0,
        90.0,
        0.0,
    );
    assert!(p.approx_eq(&want, 1e-6, 1e-6), "{p:?}");
    assert_eq!(RobotModel::by_name("nope"), None);
    for n in RobotModel::builtin_names() {
        assert_eq!(RobotModel::by_name(n).map(|m| m.name), Some(n.to_string()));
    }
}

#[test]
fn tool_and_base_frames() {
    let m = RobotModel::kr6_r700_sixx();
    // A 100 mm tool along the flange Z (out of the flange) at home points +X.
    let tool = Pose::new(0.0, 0.0, 100.0, 0.0, 0.0, 0.0);
    let p = m.forward(&HOME, &tool, &NONE);
    assert!(
        (p.x - 570.0).abs() < 1e-6 && (p.z - 750.0).abs() < 1e-6,
        "{p:?}"
    );
    // A base shifted by 100 mm in X reads 100 mm less.
    let base = Pose::new(100.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let q = m.forward(&HOME, &NONE, &base);
    assert!((q.x - 370.0).abs() < 1e-6, "{q:?}");
    // IK through tool and base lands back on the same axes.
    let ax = m
        .inverse(
            &m.forward(&HOME, &tool, &base),
            &tool,
            &base,
            None,
            None,
            &HOME,
        )
        .expect("reachable");
    assert!(
        ax.iter()
            .zip(HOME.iter())
            .all(|(a, b)| (a - b).abs() < 1e-6),
        "{ax:?}"
    );
}

#[test]
fn status_and_turn_bits() {
    let m = RobotModel::kr3_r540();
    assert_eq!(m.status(&HOME), 2);
    assert_eq!(RobotModel::turn(&HOME), 2);
    let phi = m.elbow_angle_deg();
    assert!((phi - 4.40).abs() < 0.01, "{phi}");
    for (name, phi) in [
        ("kr6_r700_sixx", 5.48),
        ("kr6_r900_sixx", 4.76),
        ("kr10_r1100_sixx", 3.89),
    ] {
        let got = RobotModel::by_name(name)
            .map(|m| m.elbow_angle_deg())
            .unwrap_or(0.0);
        assert!((got - phi).abs() < 0.01, "{name} {got}");
    }
    // Elbow below φ.
    assert_eq!(m.status(&[0.0, -90.0, 0.0, 0.0, 30.0, 0.0]), 0);
    // Wrist flip.
    assert_eq!(m.status(&[0.0, -90.0, 90.0, 0.0, -30.0, 0.0]), 6);
    // Overhead: A2 = −150 leans the arm backwards over the base.
    assert_eq!(m.status(&[0.0, -150.0, 90.0, 0.0, 30.0, 0.0]) & 1, 1);
    assert_eq!(m.status(&[0.0, -150.0, 90.0, 0.0, 30.0, 0.0]), 3);
    // Turn: every negative axis sets its bit; −0 and −1e−12 do not.
    assert_eq!(RobotModel::turn(&[-1.0, -1.0, -1.0, -1.0, -1.0, -1.0]), 63);
    assert_eq!(
        RobotModel::turn(&[1.0, -0.0, -1e-12, -5.0, 0.0, -10.0]),
        8 | 32
    );
    assert_eq!(m.status(&[0.0, -90.0, 90.0, 0.0, -1e-12, 0.0]), 2);
}

#[test]
fn fk_ik_round_trip_with_status_turn() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    for m in all_models() {
        let mut checked = 0;
        while checked < 300 {
            let mut ax = [0.0; 6];
            for (i, a) in ax.iter_mut().enumerate() {
                let (lo, hi) = m.limits_deg[i];
                *a = rng.range(lo + 1.0, hi - 1.0);
            }
            // Stay away from the singularities, where S/T is not unique.
            if ax[4].abs() < 2.0 || (ax[2] - m.elbow_angle_deg()).abs() < 2.0 {
                continue;
            }
            let (wx, _) = m.wrist_in_a1_frame(&ax);
            if wx.abs() < 20.0 {
                continue;
            }
            let tool = Pose::new(10.0, -20.0, 120.0, 10.0, 20.0, 30.0);
            let base = Pose::new(300.0, 50.0, 10.0, 45.0, 0.0, 0.0);
            let pose = m.forward(&ax, &tool, &base);
            let s = m.status(&ax);
            let t = RobotModel::turn(&ax);
            let sol = m
                .inverse(&pose, &tool, &base, Some(s), Some(t), &m.home)
                .unwrap_or_else(|e| panic!("{} {ax:?}: {e}", m.name));
            assert_eq!(m.status(&sol), s);
            assert_eq!(RobotModel::turn(&sol), t);
            let back = m.forward(&sol, &tool, &base);
            assert!(back.approx_eq(&pose, 1e-6, 1e-6), "{back:?} vs {pose:?}");
            assert!(
                sol.iter().zip(ax.iter()).all(|(a, b)| (a - b).abs() < 1e-6),
                "{}: {sol:?} vs {ax:?}",
                m.name
            );
            // All solutions within limits are valid FK solutions too.
            for (a, s2, t2) in m.solutions(&pose, &tool, &base, &m.home) {
                assert!(m.forward(&a, &tool, &base).approx_eq(&pose, 1e-6, 1e-6));
                assert_eq!((m.status(&a), RobotModel::turn(&a)), (s2, t2));
            }
            checked += 1;
        }
    }
}

#[test]
fn without_st_keeps_status_and_goes_shortest() {
    let m = RobotModel::kr6_r900_sixx();
    let start = [10.0, -80.0, 100.0, 20.0, 40.0, 170.0];
    let target_axes = [20.0, -70.0, 90.0, 10.0, 50.0, 200.0];
    let pose = m.forward(&target_axes, &NONE, &NONE);
    let sol = m
        .inverse(&pose, &NONE, &NONE, None, None, &start)
        .expect("reachable");
    // A6 200° (not −160°): the shortest path from 170°.
    assert!(
        sol.iter()
            .zip(target_axes.iter())
            .all(|(a, b)| (a - b).abs() < 1e-6),
        "{sol:?}"
    );
    assert_eq!(m.status(&sol), m.status(&start));
    // From a flipped wrist the Status is kept: A5 stays negative.
    let flipped = [10.0, -80.0, 100.0, -160.0, -40.0, -10.0];
    let sol = m
        .inverse(&pose, &NONE, &NONE, None, None, &flipped)
        .expect("reachable");
    assert!(sol[4] < 0.0, "{sol:?}");
    assert!(m.forward(&sol, &NONE, &NONE).approx_eq(&pose, 1e-6, 1e-6));
}

#[test]
fn home_pose_ik_is_robust_at_a5_zero() {
    for m in all_models() {
        let pose = m.forward(&HOME, &NONE, &NONE);
        let sol = m
            .inverse(&pose, &NONE, &NONE, None, None, &HOME)
            .expect("home");
        assert!(
            sol.iter()
                .zip(HOME.iter())
                .all(|(a, b)| (a - b).abs() < 1e-6),
            "{sol:?}"
        );
        let sol = m
            .inverse(&pose, &NONE, &NONE, Some(2), Some(2), &HOME)
            .expect("home");
        assert!(
            sol.iter()
                .zip(HOME.iter())
                .all(|(a, b)| (a - b).abs() < 1e-6),
            "{sol:?}"
        );
        // Close to home, with A4/A6 wound up, they stay where they are.
        let near = [0.0, -90.0, 90.0, 40.0, 0.0, -40.0];
        let sol = m
            .inverse(&pose, &NONE, &NONE, None, None, &near)
            .expect("home");
        assert!(m.forward(&sol, &NONE, &NONE).approx_eq(&pose, 1e-6, 1e-6));
        assert!(
            (sol[3] - 40.0).abs() < 1e-6 && (sol[5] + 40.0).abs() < 1e-6,
            "{sol:?}"
        );
    }
}

#[test]
fn kr3_thesis_points() {
    let m = RobotModel::kr3_r540();
    // The pen-down point: only with the wrist flipped (A5 ≈ −21°, S = 6).
    // From home (A5 = 0, wrist bit undefined) the planner may take it.
    let pen = Pose::new(200.0, 0.0, 70.0, 0.0, 180.0, 0.0);
    let sol = m
        .inverse(&pen, &NONE, &NONE, None, None, &m.home)
        .expect("reachable from home");
    assert!(m.check_limits(&sol).is_ok());
    assert!(m.forward(&sol, &NONE, &NONE).approx_eq(&pen, 1e-6, 1e-6));
    assert_eq!(m.status(&sol), 6, "{sol:?}");
    assert_eq!(
        m.inverse(&pen, &NONE, &NONE, Some(6), None, &m.home),
        Ok(sol)
    );
    // From a non-singular S = 2 pose the Status is kept, so it is refused:
    // the S = 2 twin needs A4 = ±180° (limit ±175°)...
    let s2 = [0.0, -90.0, 90.0, 0.0, 30.0, 0.0];
    let err = m.inverse(&pen, &NONE, &NONE, None, None, &s2);
    assert!(
        matches!(err, Err(IkError::SoftwareLimit { axis: 4, .. })),
        "{err:?}"
    );
    // ...unless the caller asks for S = 6.
    assert!(m.inverse(&pen, &NONE, &NONE, Some(6), None, &s2).is_ok());

    // {X 200, Y 0, Z 200, A 0, B 90, C 0} with the bare flange is NOT
    // reachable on a KR 3 R540: the wrist point is so close to the base that
    // A5 would have to be ±128° (limit ±120°). The thesis robot differs.
    let front = Pose::new(200.0, 0.0, 200.0, 0.0, 90.0, 0.0);
    let err = m.inverse(&front, &NONE, &NONE, None, None, &m.home);
    assert!(
        matches!(err, Err(IkError::SoftwareLimit { axis: 5, value, .. }) if (value + 128.15).abs() < 0.01),
        "{err:?}"
    );
    assert!(m.solutions(&front, &NONE, &NONE, &m.home).is_empty());
    // 100 mm further out it is reachable (again with the wrist flipped).
    let front = Pose::new(300.0, 0.0, 200.0, 0.0, 90.0, 0.0);
    let sol = m
        .inverse(&front, &NONE, &NONE, None, None, &m.home)
        .expect("reachable");
    assert!(m.forward(&sol, &NONE, &NONE).approx_eq(&front, 1e-6, 1e-6));
    assert_eq!(m.status(&sol), 6, "{sol:?}");
}

#[test]
fn far_target_is_unreachable() {
    let m = RobotModel::kr3_r540();
    let far = Pose::new(2000.0, 0.0, 300.0, 0.0, 90.0, 0.0);
    assert_eq!(
        m.inverse(&far, &NONE, &NONE, None, None, &m.home),
        Err(IkError::Unreachable)
    );
    assert_eq!(m.inverse_continuing(&far, &NONE, &NONE, &m.home), None);
    let nan = Pose::new(f64::NAN, 0.0, 300.0, 0.0, 90.0, 0.0);
    assert_eq!(
        m.inverse(&nan, &NONE, &NONE, None, None, &m.home),
        Err(IkError::Unreachable)
    );
}

#[test]
fn software_limit_names_the_axis() {
    let m = RobotModel::kr3_r540();
    let err = m.check_limits(&[0.0, -90.0, 160.0, 0.0, 0.0, 0.0]);
    assert!(
        matches!(err, Err(IkError::SoftwareLimit { axis: 3, min, max, .. }) if min == -110.0 && max == 155.0)
    );
    assert!(m.check_limits(&[0.0, -90.0, 90.0, 0.0, 0.0, 0.0]).is_ok());
    assert!(matches!(
        m.check_limits(&[0.0, -90.0, 90.0, 0.0, 0.0, f64::NAN]),
        Err(IkError::SoftwareLimit { axis: 6, .. })
    ));
    // Target straight behind the robot: only reachable with A1 = ±180
    // (beyond ±170) or overhead; with the base Status kept, A1 violates.
    let behind = Pose::new(-350.0, 0.0, 400.0, 180.0, 90.0, 0.0);
    let err = m.inverse(&behind, &NONE, &NONE, Some(2), None, &m.home);
    assert!(
        matches!(err, Err(IkError::SoftwareLimit { axis: 1, .. })),
        "{err:?}"
    );
    // A Status that cannot be matched at all.
    let home = m.flange(&m.home);
    let err = m.inverse(&home, &NONE, &NONE, Some(2), Some(0), &m.home);
    assert_eq!(err, Err(IkError::NoMatchingConfiguration { s: 2, t: 0 }));
}

/// IK within limits (issue 21): at the wrist singularity only A4 + A6 is
/// defined; the solver's split may put A4 beyond its limit (the KR 3 R540
/// at [0, -88, 0, 0, 0, 0] came back with A4 = 180°, limit ±175°), while
/// A4 = 0 reaches the same pose. Whatever the start, a split inside the
/// limits is found, and from where the robot stands it keeps A4.
#[test]
fn wrist_singular_targets_get_a_split_inside_the_limits() {
    let m = RobotModel::kr3_r540();
    let axes = [0.0, -88.0, 0.0, 0.0, 0.0, 0.0];
    // As the protocol carries it: 3 decimals.
    let p = m
        .forward(&axes, &NONE, &NONE)
        .to_array()
        .map(|v| (v * 1000.0).round() / 1000.0);
    let pose = Pose::new(p[0], p[1], p[2], p[3], p[4], p[5]);
    let (s, t) = (m.status(&axes), RobotModel::turn(&axes));
    for start in [m.home, axes, [30.0, -80.0, 80.0, 170.0, 20.0, -100.0]] {
        for (gs, gt) in [(Some(s), Some(t)), (Some(s), None), (None, None)] {
            let Ok(sol) = m.inverse(&pose, &NONE, &NONE, gs, gt, &start) else {
                // Without S the start's Status is kept, which may not reach.
                assert!(gs.is_none(), "from {start:?} with S {gs:?} T {gt:?}");
                continue;
            };
            m.check_limits(&sol).expect("inside the limits");
            assert!(
                m.forward(&sol, &NONE, &NONE).approx_eq(&pose, 0.01, 0.01),
                "{sol:?}"
            );
        }
    }
    let sol = m
        .inverse(&pose, &NONE, &NONE, Some(s), Some(t), &axes)
        .expect("reachable from there");
    assert!(
        sol.iter()
            .zip(axes.iter())
            .all(|(a, b)| (a - b).abs() < 0.01),
        "stays where it is: {sol:?}"
    );
    // A start with A4 at 170°: the split keeps A4 there (no A4/A6 spin).
    let start = [0.0, -88.0, 0.0, 170.0, 0.0, -170.0];
    let sol = m
        .inverse(&pose, &NONE, &NONE, None, None, &start)
        .expect("reachable");
    assert!(
        (sol[3] - 170.0).abs() < 0.01 && (sol[5] + 170.0).abs() < 0.01,
        "{sol:?}"
    );
}

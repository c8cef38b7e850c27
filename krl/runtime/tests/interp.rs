//! Interpreter tests: KRL programs run into the steps the simulated
//! controller plays, and programs outside the subset are refused with
//! their line.

use kuka_kinematics::plan::{PlanSettings, plan};
use kuka_kinematics::{IkError, Motion, MotionError, MotionKind, Pose, RobotModel};
use kuka_krl::Program;
use kuka_krl_runtime::interp::{RunError, Start, Step, Unsupported, check_subset, run};
use kuka_protocol::SpeedRecord;

const SPEED: SpeedRecord = SpeedRecord {
    override_pct: 100.0,
    ptp_velocity_pct: 40.0,
    ptp_acceleration_pct: 60.0,
    cp_velocity: 0.25,
    cp_acceleration_pct: 50.0,
};

fn start(model: &RobotModel) -> Start<'_> {
    Start {
        model,
        axes: model.home,
        tool: Pose::IDENTITY,
        base: Pose::IDENTITY,
        speed: SPEED,
    }
}

fn run_src(src: &str, dat: Option<&str>, entry: &str) -> Result<Vec<Step>, RunError> {
    let program = Program::parse(src, dat, Some(entry)).expect("parses");
    let model = RobotModel::kr3_r540();
    run(&program, entry, &start(&model))
}

fn steps(src: &str) -> Vec<Step> {
    let entry = src.split(['(', ' ']).nth(1).expect("DEF name(").to_string();
    match run_src(src, None, &entry) {
        Ok(s) => s,
        Err(e) => panic!("{e}\n{src}"),
    }
}

fn runtime_error(src: &str) -> (u32, String) {
    let entry = src.split(['(', ' ']).nth(1).expect("DEF name(").to_string();
    match run_src(src, None, &entry) {
        Err(RunError::Runtime { line, message } | RunError::TooLong { line, message, .. }) => {
            (line, message)
        }
        other => panic!("expected a runtime error, got {other:?}"),
    }
}

fn motions(steps: &[Step]) -> Vec<&Motion> {
    steps
        .iter()
        .filter_map(|s| match s {
            Step::Move { motion, .. } => Some(motion),
            Step::Dwell { .. } => None,
        })
        .collect()
}

/// The Cartesian target of a motion.
fn target(m: &Motion) -> Pose {
    match &m.kind {
        MotionKind::Ptp { target, .. }
        | MotionKind::Lin { target }
        | MotionKind::Circ { target, .. }
        | MotionKind::Spl { target, .. } => *target,
        MotionKind::PtpAxes { .. } => panic!("axis motion"),
        MotionKind::Hold { .. } | MotionKind::Mark => panic!("not a motion"),
    }
}

fn xyz(m: &Motion) -> [f64; 3] {
    let p = target(m);
    [p.x, p.y, p.z]
}

fn assert_close(a: [f64; 3], b: [f64; 3]) {
    let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    assert!(d < 1e-9, "{a:?} != {b:?}");
}

const THESIS: &str = "DEFFCT INT fuploaded()
    SPLINE
    SPL {X 200, Y 0, Z 200, A 0, B 90, C 0}
    SPL {X 200, Y -50, Z 150, A 0, B 90, C 0}
    SPL {X 200, Y 50, Z 100, A 0, B 90, C 0}
    ENDSPLINE
    RETURN 1
ENDFCT
";

fn check_thesis_spline(steps: &[Step], first_line: u32) {
    let model = RobotModel::kr3_r540();
    let home = model.forward(&model.home, &Pose::IDENTITY, &Pose::IDENTITY);
    let ms = motions(steps);
    // One spline segment per point: the curve from the programmed (home)
    // pose through the three points, each segment with its neighbours.
    let points = [
        Pose::new(200.0, 0.0, 200.0, 0.0, 90.0, 0.0),
        Pose::new(200.0, -50.0, 150.0, 0.0, 90.0, 0.0),
        Pose::new(200.0, 50.0, 100.0, 0.0, 90.0, 0.0),
    ];
    assert_eq!(ms.len(), 3, "{ms:?}");
    for (i, (m, p)) in ms.iter().zip(&points).enumerate() {
        let MotionKind::Spl {
            target,
            first,
            prev,
            next,
        } = &m.kind
        else {
            panic!("SPL gives spline segments: {m:?}");
        };
        assert!(target.approx_eq(p, 0.01, 1e-6), "{target:?}");
        assert_eq!(*first, i == 0);
        assert_eq!(next.is_some(), i < 2);
        // The point before each segment's start: home, then the points.
        let want_prev = match i {
            0 => None,
            1 => Some(home),
            _ => Some(points[i - 2]),
        };
        assert_eq!(prev.is_some(), want_prev.is_some());
        if let (Some(a), Some(b)) = (prev, want_prev) {
            assert!(a.approx_eq(&b, 0.01, 1e-6), "{a:?} vs {b:?}");
        }
        if let Some(n) = next {
            assert!(n.approx_eq(&points[i + 1], 0.01, 1e-6));
        }
    }
    let from = ms.len();
    assert_eq!(from, ms.len(), "the block ends at the last point");
    // Exact stop at the end (no C_SPL), blending inside.
    assert_eq!(ms.last().expect("moves").approx_mm, 0.0);
    assert!(ms[..ms.len() - 1].iter().all(|m| m.approx_mm > 0.0));
    // Speeds from the start record; lines of the points.
    assert!(ms.iter().all(|m| m.velocity == 0.25));
    let lines: Vec<u32> = steps
        .iter()
        .map(|s| match s {
            Step::Move { line, .. } | Step::Dwell { line, .. } => *line,
        })
        .collect();
    assert_eq!(lines.first(), Some(&first_line));
    assert_eq!(lines.last(), Some(&(first_line + 2)));
    assert!(lines.windows(2).all(|w| w[0] <= w[1]));
}

#[test]
fn the_thesis_spline_runs_through_its_points() {
    let s = run_src(THESIS, None, "fuploaded").expect("runs");
    check_thesis_spline(&s, 3);
}

#[test]
fn the_thesis_spline_runs_from_the_wrapper_but_is_out_of_the_kr3_limits() {
    let src = format!("DEF kbu7( )\n  DECL INT kb_ret\n  kb_ret = fuploaded( )\nEND\n\n{THESIS}");
    let s = run_src(&src, None, "kbu7").expect("runs");
    check_thesis_spline(&s, 8);
    // All moves share tool and base: one batch for the planner. The
    // thesis points (tool horizontal, pointing +X, at 100..200 mm height
    // and 200 mm out) need A5 beyond ±120° (or A4 at 180°) on the KR 3
    // R540 with the flange as TCP: the planner's look-ahead refuses the
    // block with a software limit before the robot reaches the first point.
    let model = RobotModel::kr3_r540();
    for p in [
        Pose::new(200.0, 0.0, 200.0, 0.0, 90.0, 0.0),
        Pose::new(200.0, -50.0, 150.0, 0.0, 90.0, 0.0),
        Pose::new(200.0, 50.0, 100.0, 0.0, 90.0, 0.0),
    ] {
        let r = model.check_reachable(&p, &Pose::IDENTITY, &Pose::IDENTITY);
        assert!(
            matches!(r, Err(IkError::SoftwareLimit { .. })),
            "{p:?}: {r:?}"
        );
    }
    let batch: Vec<Motion> = motions(&s).into_iter().cloned().collect();
    let e = plan(
        &model,
        &model.home,
        &Pose::IDENTITY,
        &Pose::IDENTITY,
        &batch,
        &PlanSettings::default(),
    );
    assert!(
        matches!(
            e.error,
            Some((_, MotionError::Ik(IkError::SoftwareLimit { .. })))
        ),
        "{:?}",
        e.error
    );
}

#[test]
fn the_thesis_spline_with_a_tilted_tool_is_executable_on_the_kr3() {
    // The same curve with the tool tilted 45° downwards (B 135) is
    // within the limits all the way from home, away from the wrist
    // singularity (B 180 crosses A5 = 0 on the way down).
    let src = THESIS.replace("B 90", "B 135");
    let s = run_src(&src, None, "fuploaded").expect("runs");
    let model = RobotModel::kr3_r540();
    let batch: Vec<Motion> = motions(&s).into_iter().cloned().collect();
    assert_eq!(batch.len(), 3);
    let e = plan(
        &model,
        &model.home,
        &Pose::IDENTITY,
        &Pose::IDENTITY,
        &batch,
        &PlanSettings::default(),
    );
    assert_eq!(e.error, None);
    let end = e.samples.last().expect("samples").pose;
    assert!(end.approx_eq(&Pose::new(200.0, 50.0, 100.0, 0.0, 135.0, 0.0), 0.01, 0.01));
    // The executed path passes the middle point too.
    let mid = Pose::new(200.0, -50.0, 150.0, 0.0, 135.0, 0.0);
    let closest = e
        .samples
        .iter()
        .map(|x| x.pose.distance_mm(&mid))
        .fold(f64::INFINITY, f64::min);
    assert!(closest < 5.0, "{closest}");
    // Constant speed along the curve: most of it at the programmed 0.25 m/s.
    let fast = e
        .samples
        .windows(2)
        .filter(|w| w[0].pose.distance_mm(&w[1].pose) / (w[1].t - w[0].t) > 0.2 * 1000.0)
        .count();
    assert!(fast * 2 > e.samples.len(), "{fast} of {}", e.samples.len());
}

#[test]
fn for_loops_produce_one_motion_per_iteration() {
    let s = steps(
        "DEF f()
  DECL INT i
  $APO.CDIS = 3
  FOR i = 1 TO 5
    LIN {X 300 + i * 10, Y 0, Z 400, A 0, B 90, C 0} C_DIS
  ENDFOR
  FOR i = 10 TO 4 STEP -3
    LIN {X 400, Y i, Z 400}
  ENDFOR
END
",
    );
    let ms = motions(&s);
    assert_eq!(ms.len(), 8);
    for (k, m) in ms[..5].iter().enumerate() {
        assert_close(xyz(m), [310.0 + 10.0 * k as f64, 0.0, 400.0]);
        assert_eq!(m.approx_mm, 3.0);
    }
    let ys: Vec<f64> = ms[5..].iter().map(|m| target(m).y).collect();
    assert_eq!(ys, [10.0, 7.0, 4.0]);
    assert_eq!(ms[5].approx_mm, 0.0);
}

#[test]
fn if_switch_and_while_pick_the_right_branch() {
    let s = steps(
        "DEF f()
  DECL INT n, k
  DECL REAL r
  n = 7
  IF (n > 5) AND NOT (n == 6) THEN
    LIN {X 301}
  ELSE
    LIN {X 302}
  ENDIF
  SWITCH n B_AND 3
  CASE 1, 2
    LIN {X 311}
  CASE 3
    LIN {X 312}
  DEFAULT
    LIN {X 313}
  ENDSWITCH
  k = 0
  WHILE k < 3
    k = k + 1
  ENDWHILE
  r = 7 / 2
  IF (k == 3) AND (r == 3.0) THEN
    LIN {X 321}
  ENDIF
  k = 2.5
  IF k == 3 THEN
    LIN {X 331}
  ENDIF
  REPEAT
    k = k - 1
  UNTIL k <= 0
  LOOP
    k = k + 1
    IF k >= 4 THEN
      EXIT
    ENDIF
  ENDLOOP
  LIN {X 340 + k}
END
",
    );
    let xs: Vec<f64> = motions(&s).iter().map(|m| target(m).x).collect();
    // 7 B_AND 3 = 3; 7 / 2 = 3 (INT); INT k = 2.5 rounds to 3.
    assert_eq!(xs, [301.0, 312.0, 321.0, 331.0, 344.0]);
}

#[test]
fn functions_with_out_parameters_and_return_values() {
    let s = steps(
        "DEF main()
  DECL INT a, b, res
  DECL REAL arr[3]
  a = 4
  res = twice(a, b)
  LIN {X 300 + res, Y b, Z 400}
  fill(arr[2])
  LIN {X arr[2]}
END

DEFFCT INT twice(x:IN, y:OUT)
  DECL INT x, y
  y = x * 3
  x = 0
  RETURN x + y * 2
ENDFCT

DEF fill(v:OUT)
  DECL REAL v
  v = 123.5
END
",
    );
    let ms = motions(&s);
    assert_close(xyz(ms[0]), [324.0, 12.0, 400.0]);
    assert_eq!(target(ms[1]).x, 123.5);
}

#[test]
fn tool_and_base_assignments_change_the_moves() {
    let s = steps(
        "DEF f()
  LIN {X 300, Y 0, Z 400, A 0, B 90, C 0}
  $TOOL = {X 0, Y 0, Z 100, A 0, B 0, C 0}
  $BASE = {X 10, Y 20, Z 30, A 0, B 0, C 0}
  LIN {Z 350}
  $BASE.X = 0
  $TOOL = $NULLFRAME
  LIN {Z 360}
END
",
    );
    let moves: Vec<(Pose, Pose, [f64; 3])> = s
        .iter()
        .map(|st| match st {
            Step::Move {
                tool, base, motion, ..
            } => (*tool, *base, xyz(motion)),
            Step::Dwell { .. } => panic!("no dwell"),
        })
        .collect();
    assert_eq!(moves[0].0, Pose::IDENTITY);
    assert_eq!(moves[1].0, Pose::new(0.0, 0.0, 100.0, 0.0, 0.0, 0.0));
    assert_eq!(moves[1].1, Pose::new(10.0, 20.0, 30.0, 0.0, 0.0, 0.0));
    // The programmed pose is re-expressed: the flange at X 300 with B 90
    // puts the 100 mm tool at X 400; in the base it is X 390, Y -20.
    let [x, y, _] = moves[1].2;
    assert!(
        (x - 390.0).abs() < 1e-9 && (y + 20.0).abs() < 1e-9,
        "{x} {y}"
    );
    assert_eq!(moves[2].0, Pose::IDENTITY);
    assert_eq!(moves[2].1, Pose::new(0.0, 20.0, 30.0, 0.0, 0.0, 0.0));
    // Tool removed again: the flange X 300 (Z 350+30 in the world) in base X 0.
    let [x, y, z] = moves[2].2;
    assert!((x - 300.0).abs() < 1e-9 && (y + 20.0).abs() < 1e-9 && z == 360.0);
}

#[test]
fn wait_sec_is_a_dwell_and_wait_for_false_is_refused_at_runtime() {
    let s = steps("DEF f()\n  LIN {X 300}\n  WAIT SEC 0.5\n  LIN {X 310}\nEND\n");
    assert_eq!(
        s[1],
        Step::Dwell {
            seconds: 0.5,
            line: 3
        }
    );
    assert_eq!(motions(&s).len(), 2);
    let s = steps("DEF f()\n  DECL BOOL ok\n  ok = TRUE\n  WAIT FOR ok\nEND\n");
    assert!(s.is_empty());
    let (line, msg) = runtime_error("DEF f()\n  DECL BOOL ok\n  ok = FALSE\n  WAIT FOR ok\nEND\n");
    assert_eq!(line, 4);
    assert!(msg.contains("wait forever"), "{msg}");
}

#[test]
fn partial_targets_keep_the_programmed_components() {
    let s = steps(
        "DEF f()
  LIN {X 300, Y 40, Z 400, A 10, B 80, C 5}
  LIN {X 310}
  LIN_REL {Z -20}
  CIRC {Y 60}, {X 330, Y 40}
END
",
    );
    let ms = motions(&s);
    let p = target(ms[1]);
    assert!(p.approx_eq(&Pose::new(310.0, 40.0, 400.0, 10.0, 80.0, 5.0), 1e-9, 1e-9));
    assert_close(xyz(ms[2]), [310.0, 40.0, 380.0]);
    let MotionKind::Circ { aux, target } = &ms[3].kind else {
        panic!("circ")
    };
    assert_close([aux.x, aux.y, aux.z], [310.0, 60.0, 380.0]);
    assert_close([target.x, target.y, target.z], [330.0, 40.0, 380.0]);
}

#[test]
fn ptp_xhome_after_initmov_is_an_axis_ptp_home() {
    let src = "DEF draw( )
;FOLD INI;%{PE}
  ;FOLD BASISTECH INI
    GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )
    INTERRUPT ON 3
    BAS (#INITMOV,0 )
  ;ENDFOLD (BASISTECH INI)
  ;FOLD USER INI
    ;Make your modifications here

  ;ENDFOLD (USER INI)
;ENDFOLD (INI)
  $VEL_AXIS[1] = 100
  $VEL_AXIS[3] = 20
  PTP {A1 10, A2 -80}
  BAS (#INITMOV,0 )
  PTP XHOME
  PTP {A1 5, A2 -90, A3 90, A4 0, A5 30, A6 0}
END
";
    let s = steps(src);
    let ms = motions(&s);
    let model = RobotModel::kr3_r540();
    assert_eq!(
        ms[0].kind,
        MotionKind::PtpAxes {
            axes: [10.0, -80.0, 90.0, 0.0, 0.0, 0.0]
        }
    );
    assert_eq!(ms[0].velocity, 20.0, "the smallest $VEL_AXIS");
    assert_eq!(ms[0].acceleration_pct, 60.0);
    assert_eq!(ms[1].kind, MotionKind::PtpAxes { axes: model.home });
    assert_eq!(ms[1].velocity, 40.0, "INITMOV resets to the start speed");
    assert_eq!(ms[1].approx_mm, 0.0);
    assert_eq!(
        ms[2].kind,
        MotionKind::PtpAxes {
            axes: [5.0, -90.0, 90.0, 0.0, 30.0, 0.0]
        }
    );
}

#[test]
fn cartesian_ptp_passes_status_and_turn() {
    let s = steps(
        "DEF f()\n  PTP {X 300, Y 0, Z 400, A 0, B 90, C 0, S 2, T 10}\n  PTP {Z 300}\nEND\n",
    );
    let ms = motions(&s);
    assert!(matches!(
        ms[0].kind,
        MotionKind::Ptp {
            s: Some(2),
            t: Some(10),
            ..
        }
    ));
    assert!(matches!(
        ms[1].kind,
        MotionKind::Ptp {
            s: None,
            t: None,
            ..
        }
    ));
    assert_close(xyz(ms[1]), [300.0, 0.0, 300.0]);
}

#[test]
fn pos_act_reads_the_programmed_pose_and_stops_the_advance_run() {
    let s = steps(
        "DEF f()
  DECL E6POS p
  DECL E6AXIS ax
  ax = $AXIS_ACT
  ax.A1 = 20
  PTP ax
  p = $POS_ACT
  p.Z = p.Z - 50
  LIN p C_DIS
  LIN {X 300} C_DIS
  p = $POS_ACT
  LIN {X 310} C_DIS
  CONTINUE
  p = $POS_ACT
  LIN {X 320}
END
",
    );
    let model = RobotModel::kr3_r540();
    let mut axes = model.home;
    axes[0] = 20.0;
    let home20 = model.forward(&axes, &Pose::IDENTITY, &Pose::IDENTITY);
    let ms = motions(&s);
    assert_eq!(ms[0].kind, MotionKind::PtpAxes { axes });
    let p = target(ms[1]);
    assert_close([p.x, p.y, p.z], [home20.x, home20.y, home20.z - 50.0]);
    // C_DIS with the default $APO.CDIS of 1 mm ...
    assert_eq!(ms[1].approx_mm, 1.0);
    // ... but reading $POS_ACT stops the advance run (exact stop) ...
    assert_eq!(ms[2].approx_mm, 0.0);
    // ... unless CONTINUE comes before.
    assert_eq!(ms[3].approx_mm, 1.0);
    // After a Cartesian motion the axes are not known in advance.
    let (line, msg) =
        runtime_error("DEF f()\n  DECL E6AXIS ax\n  LIN {X 300}\n  ax = $AXIS_ACT\nEND\n");
    assert_eq!(line, 4);
    assert!(msg.contains("line 3"), "{msg}");
}

#[test]
fn dat_globals_arrays_and_geometric_operator() {
    let src = "DEF prog()
  DECL INT i, j
  DECL REAL grid[2, 3]
  FOR i = 1 TO 2
    FOR j = 1 TO 3
      grid[i, j] = i * 10 + j
    ENDFOR
  ENDFOR
  count = count + 1
  LIN start_pt
  LIN shift : start_pt
  LIN {X grid[2, 3] + count, Y SQRT(16) + ABS(-2), Z ATAN2(1, 1) + 2 * SIN(30)}
END
";
    let dat = "DEFDAT prog
DECL INT count = 41
DECL E6POS start_pt = {X 300, Y 0, Z 400, A 0, B 90, C 0, S 2, T 0, E1 0, E2 0, E3 0, E4 0, E5 0, E6 0}
DECL FRAME shift
DECL FDAT FP1={TOOL_NO 1,BASE_NO 0,IPO_FRAME #BASE,POINT2[] \" \"}
shift = {X 5, Y 6, Z 7, A 0, B 0, C 0}
ENDDAT
";
    let s = run_src(src, Some(dat), "prog").expect("runs");
    let ms = motions(&s);
    assert_close(xyz(ms[0]), [300.0, 0.0, 400.0]);
    assert_close(xyz(ms[1]), [305.0, 6.0, 407.0]);
    let p = xyz(ms[2]);
    assert!((p[0] - 65.0).abs() < 1e-9 && (p[1] - 6.0).abs() < 1e-9 && (p[2] - 46.0).abs() < 1e-9);
}

#[test]
fn spline_with_velocity_slin_and_c_spl() {
    let s = steps(
        "DEF f()
  LIN {X 300, Y 0, Z 400, A 0, B 90, C 0}
  SPLINE
    SLIN {X 320} WITH $VEL = {CP 0.1}
    SPL {X 340, Y 10} WITH $VEL.CP = 0.05
    SCIRC {X 350, Y 20}, {X 340, Y 30}
  ENDSPLINE C_SPL
  SLIN {X 300}
END
",
    );
    let ms = motions(&s);
    assert_eq!(
        ms[1].kind,
        MotionKind::Lin {
            target: Pose::new(320.0, 0.0, 400.0, 0.0, 90.0, 0.0)
        }
    );
    assert_eq!(ms[1].velocity, 0.1);
    assert_eq!(ms[1].approx_mm, 1.0);
    let spl: Vec<&&Motion> = ms[2..ms.len() - 2].iter().collect();
    assert_eq!(spl.len(), 1);
    assert!(
        spl.iter()
            .all(|m| m.velocity == 0.05 && matches!(m.kind, MotionKind::Spl { .. }))
    );
    let circ = ms[ms.len() - 2];
    assert!(matches!(circ.kind, MotionKind::Circ { .. }));
    assert_eq!(circ.velocity, 0.25, "WITH applies to its own segment only");
    assert_eq!(
        circ.approx_mm, 1.0,
        "C_SPL: the block blends into the next spline motion"
    );
    assert_eq!(ms.last().unwrap().velocity, 0.25);
}

fn refused(src: &str) -> Unsupported {
    let p = Program::parse(src, None, None).expect("parses");
    check_subset(&p).expect_err("refused")
}

#[test]
fn statements_outside_the_subset_are_refused_with_their_line() {
    let u =
        refused("DEF f()\n  LIN {X 1}\n  INTERRUPT DECL 3 WHEN $IN[1] DO g()\nEND\nDEF g()\nEND\n");
    assert_eq!((u.line, u.what.as_str()), (3, "INTERRUPT"));
    let u = refused("DEF f()\n\n  $OUT[1] = TRUE\nEND\n");
    assert_eq!(u.line, 3);
    assert!(u.what.contains("$OUT"), "{}", u.what);
    let u = refused("DEF f()\n  DECL INT h\n  CWRITE($FCT_CALL, h, h, \"krl_fopen\")\nEND\n");
    assert_eq!(u.line, 3);
    assert!(u.what.contains("CWRITE"), "{}", u.what);
    let u = refused(
        "DEF f()\n  INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM()\n  INTERRUPT ON 4\nEND\n",
    );
    assert_eq!((u.line, u.what.as_str()), (3, "INTERRUPT"));
    let u = refused("DEF f()\n  LIN {X 1}\n  HALT\nEND\n");
    assert_eq!((u.line, u.what.as_str()), (3, "HALT"));
    // Also in a routine that is never called, and in the .dat.
    let u = refused("DEF f()\nEND\nDEF g()\n  WAIT FOR $IN[2]\nEND\n");
    assert_eq!(u.line, 4);
    assert!(u.what.contains("WAIT FOR"), "{}", u.what);
    let u = refused("DEF f()\n  CIRC {X 1}, {X 2}, CA 90\nEND\n");
    assert_eq!(u.line, 2);
    let u = refused("DEF f()\n  LIN_REL {X 10} C_DIS #TOOL\nEND\n");
    assert_eq!(u.line, 2);
    assert!(u.what.contains("#TOOL"), "{}", u.what);
    let u = refused("DEF f()\n  SPLINE\n    SCIRC {X 1}, {X 2}, CA 90\n  ENDSPLINE\nEND\n");
    assert_eq!(u.line, 3);
    let u = refused("DEF f()\n  SPLINE WITH $VEL = {CP 0.1}\n    SPL {X 1}\n  ENDSPLINE\nEND\n");
    assert_eq!(u.line, 2);
    let u = refused("DEF f()\n  BAS(#PTP_PARAMS, 100)\nEND\n");
    assert!(u.what.contains("PTP_PARAMS"), "{}", u.what);
    let u = refused("DEF f()\n  x = $TIMER[1]\nEND\n");
    assert!(u.what.contains("$TIMER"), "{}", u.what);
    // `run` refuses too, before producing anything.
    let err = run_src("DEF f()\n  LIN {X 1}\n  HALT\nEND\n", None, "f").expect_err("refused");
    assert!(matches!(
        err,
        RunError::Unsupported(Unsupported { line: 3, .. })
    ));
    // Real KSS 8.x syntax parses but is outside what the simulator runs.
    let u = refused("DEF f()\n  GOTO here\n  here:\nEND\n");
    assert_eq!((u.line, u.what.as_str()), (2, "GOTO and labels"));
    let u = refused("DEF f()\n  SPTP XHOME WITH $TOOL = STOOL2(FHOME)\nEND\n");
    assert_eq!(u.line, 2);
    assert!(u.what.contains("$TOOL"), "{}", u.what);
    let u = refused("DEF f()\n  SLIN_REL {X 10}\nEND\n");
    assert!(u.what.contains("relative spline"), "{}", u.what);
    let u = refused("DEF f()\n  $TOOL = TOOL_DATA[1]\nEND\n");
    assert!(u.what.contains("TOOL_DATA"), "{}", u.what);
    let u = refused(
        "DEF f()\n  DECL INT i\n  i = g(1, )\nEND\nDEFFCT INT g(a:IN, b:IN)\n  DECL INT a, b\n  RETURN a\nENDFCT\n",
    );
    assert!(u.what.contains("left-out"), "{}", u.what);
    let u = refused(
        "DEF f()\n  SPLINE\n    SPL {X 1}\n    TRIGGER WHEN PATH = 0 DELAY = 0 DO $OUT[1] = TRUE\n    SPL {X 2}\n  ENDSPLINE\nEND\n",
    );
    assert_eq!(u.line, 4);
}

#[test]
fn a_single_spline_motion_runs_like_a_block_of_one() {
    let single = run_src(
        "DEF f()\n  SLIN {X 300, Y 0, Z 300, A 0, B 90, C 0}\nEND\n",
        None,
        "f",
    )
    .expect("runs");
    let block = run_src(
        "DEF f()\n  SPLINE\n    SLIN {X 300, Y 0, Z 300, A 0, B 90, C 0}\n  ENDSPLINE\nEND\n",
        None,
        "f",
    )
    .expect("runs");
    let motions = |steps: Vec<Step>| {
        steps
            .into_iter()
            .map(|s| match s {
                Step::Move { motion, .. } => motion,
                other => panic!("a motion, not {other:?}"),
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(single.len(), 1);
    assert_eq!(motions(single), motions(block));
}

/// Conventional motions (PTP, LIN, CIRC) and spline motions (SPLINE
/// blocks, SLIN, SCIRC, SPTP) never blend into each other on a KRC (two
/// motion planners, docs/CONTROLLER.md 21): the last motion before a change
/// of family ends in an exact stop, whatever its approximation; within a
/// family the approximation stays.
#[test]
fn conventional_and_spline_motions_do_not_blend_into_each_other() {
    let approx = |src: &str| -> Vec<f64> {
        steps(src)
            .into_iter()
            .map(|s| match s {
                Step::Move { motion, .. } => motion.approx_mm,
                other => panic!("a motion, not {other:?}"),
            })
            .collect()
    };
    let head = "DEF f()\n  $APO.CDIS = 5\n  PTP {A1 0, A2 -80, A3 80, A4 0, A5 30, A6 0}\n";
    // LIN into LIN, SLIN into SLIN: blended.
    let same = approx(&format!(
        "{head}  LIN {{X 380}} C_DIS\n  LIN {{X 360}}\n  SLIN {{Y 20}} C_SPL\n  SLIN {{Y 40}}\nEND\n"
    ));
    assert_eq!(same[1..], [5.0, 0.0, 5.0, 0.0], "{same:?}");
    // LIN C_DIS into SLIN, and SLIN C_SPL into LIN: exact stops.
    let mixed = approx(&format!(
        "{head}  LIN {{X 380}} C_DIS\n  SLIN {{Y 20}} C_SPL\n  LIN {{X 360}} C_DIS\n  SPLINE\n    SPL {{Y 40}}\n  ENDSPLINE\nEND\n"
    ));
    assert_eq!(mixed[1..4], [0.0, 0.0, 0.0], "{mixed:?}");
}

#[test]
fn runtime_errors_name_their_line() {
    let (line, msg) = runtime_error("DEF f()\n  DECL INT i\n  LOOP\n    i = 1\n  ENDLOOP\nEND\n");
    assert!(msg.contains("endless loop"), "{msg}");
    assert!((3..=4).contains(&line));
    let (line, msg) = runtime_error("DEF f()\n  LOOP\n  ENDLOOP\nEND\n");
    assert!(msg.contains("endless loop") && line == 2, "{line} {msg}");
    let (line, msg) = runtime_error("DEF f()\n  DECL INT i\n  i = 0\n  i = 5 / i\nEND\n");
    assert_eq!(line, 4);
    assert!(msg.contains("division by zero"), "{msg}");
    let (line, msg) = runtime_error("DEF f()\n  DECL REAL r\n  r = 1.0 / (2 - 2)\nEND\n");
    assert_eq!(line, 3);
    assert!(msg.contains("division by zero"), "{msg}");
    let (line, msg) = runtime_error("DEF f()\n  DECL INT a[3]\n  a[4] = 1\nEND\n");
    assert_eq!(line, 3);
    assert!(msg.contains("out of range"), "{msg}");
    let (line, msg) = runtime_error("DEF f()\n  DECL INT a\n  LIN {X a}\nEND\n");
    assert_eq!(line, 3);
    assert!(msg.contains("no value"), "{msg}");
    let (line, msg) = runtime_error("DEF f()\n  nope = 1\nEND\n");
    assert_eq!(line, 2);
    assert!(msg.contains("not declared"), "{msg}");
    let (line, msg) = runtime_error("DEF f()\n  DECL BOOL b\n  b = 1.5\nEND\n");
    assert_eq!(line, 3);
    assert!(msg.contains("BOOL"), "{msg}");
    let (line, msg) = runtime_error("DEF f()\n  $VEL.CP = 3\nEND\n");
    assert_eq!(line, 2);
    assert!(msg.contains("$VEL.CP"), "{msg}");
    // Endless recursion ends with a limit error, not a stack overflow.
    match run_src("DEF f()\n  g()\nEND\nDEF g()\n  g()\nEND\n", None, "f") {
        Err(RunError::Limit { line, message }) => {
            assert_eq!(line, 5);
            assert!(message.contains("MAX_CALL_DEPTH"), "{message}");
        }
        other => panic!("expected the call depth limit, got {other:?}"),
    }
    // Endless motion loops stop at the step limit.
    let (line, msg) =
        runtime_error("DEF f()\n  LOOP\n    LIN {X 300}\n    LIN {X 310}\n  ENDLOOP\nEND\n");
    assert!(msg.contains("endless loop"), "{msg}");
    assert!((2..=4).contains(&line));
}

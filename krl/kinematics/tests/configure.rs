//! Configuration planning against a brute force (issue 21): for random
//! reachable targets from random start poses on every model, `auto` finds
//! a configuration whenever trying every Status (each with its best Turn
//! variant) finds one, and its choice is the brute force's optimum: the
//! least axis travel among the configurations clear of the singularity
//! margins (or among all, when none is clear). The margin rule is the only
//! reason `auto` ever moves more than the shortest solution.

use kuka_kinematics::configure::{self, ConfigMode, Context, Margins};
use kuka_kinematics::{Axes, Motion, MotionKind, PlanSettings, Pose, RobotModel};

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn random_axes(m: &RobotModel, rng: &mut Rng) -> Axes {
    let mut a = [0.0; 6];
    for (i, v) in a.iter_mut().enumerate() {
        let (lo, hi) = m.limits_deg[i];
        *v = lo + 1.0 + (hi - lo - 2.0) * rng.next();
    }
    a
}

#[test]
fn auto_finds_what_a_brute_force_finds_and_moves_no_more() {
    let zero = Pose::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let settings = PlanSettings::default();
    let margins = Margins::default();
    let mut checked = 0;
    for name in RobotModel::builtin_names() {
        let m = RobotModel::by_name(name).expect("model");
        let cx = Context {
            model: &m,
            tool: &zero,
            base: &zero,
            settings: &settings,
            margins: &margins,
            path_check: None,
        };
        let mut rng = Rng(0xC0FF_EE00 ^ name.len() as u64);
        for n in 0..1000 {
            let start = random_axes(&m, &mut rng);
            let target = m.forward(&random_axes(&m, &mut rng), &zero, &zero);
            let motion = Motion {
                kind: MotionKind::Ptp {
                    target,
                    s: None,
                    t: None,
                },
                velocity: 50.0,
                acceleration_pct: 100.0,
                approx_mm: 0.0,
            };
            let auto = configure::choose(&cx, &start, &[motion], &[ConfigMode::Auto]);
            // Brute force: every Status, each with its least-travel Turn
            // (exact solutions: not one taken at a limit it passes by a hair).
            let brute: Vec<Axes> = (0..8u8)
                .filter_map(|s| m.inverse(&target, &zero, &zero, Some(s), None, &start).ok())
                .filter(|a| m.forward(a, &zero, &zero).approx_eq(&target, 1e-6, 1e-6))
                .collect();
            let key = |a: &Axes| (margins.violations(&m, a), m.travel_time(&start, a));
            let best = brute
                .iter()
                .map(key)
                .min_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
            match (auto, best) {
                (Ok(chosen), Some(best)) => {
                    let c = chosen[0].expect("a configuration for the PTP");
                    let got = key(&c.axes);
                    assert!(
                        got.0 < best.0 || (got.0 == best.0 && got.1 <= best.1 + 1e-9),
                        "{name} #{n}: auto {got:?} ({:?}) vs brute force {best:?} {:?} from {start:?}",
                        c.axes,
                        brute.iter().map(|a| (a, key(a))).collect::<Vec<_>>()
                    );
                    checked += 1;
                }
                (Err(e), None) => {
                    // Neither finds one (the target needs an axis beyond its
                    // limit in every configuration).
                    assert!(e.to_string().contains("no arm configuration"), "{e}");
                }
                (auto, best) => panic!("{name} #{n}: auto {auto:?}, brute force {best:?}"),
            }
        }
    }
    assert!(checked > 3000, "{checked} targets with a configuration");
}

/// A path check (the service's workspace rules) drops configurations whose
/// PTP or following path breaks it: when it refuses every path, no
/// configuration is chosen and each one tried says why; when it refuses
/// only paths that pass below z = 300, the configuration chosen keeps its
/// whole PTP sweep above.
#[test]
fn a_path_check_drops_configurations() {
    use kuka_kinematics::configure::{ConfigError, Failure};
    let m = RobotModel::kr3_r540();
    let zero = Pose::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let settings = PlanSettings::for_model(&m);
    let margins = Margins::default();
    let target = Pose::new(250.0, 0.0, 350.0, 0.0, 180.0, 0.0);
    let ptp = Motion {
        kind: MotionKind::Ptp {
            target,
            s: None,
            t: None,
        },
        velocity: 50.0,
        acceleration_pct: 100.0,
        approx_mm: 0.0,
    };
    let never = |first: usize, _: &[kuka_kinematics::Sample]| Some((first, "refused".to_string()));
    let cx = Context {
        model: &m,
        tool: &zero,
        base: &zero,
        settings: &settings,
        margins: &margins,
        path_check: Some(&never),
    };
    match configure::choose(
        &cx,
        &m.home,
        std::slice::from_ref(&ptp),
        &[ConfigMode::Auto],
    ) {
        Err(ConfigError::NoConfiguration { tried, .. }) => {
            assert!(!tried.is_empty());
            assert!(
                tried
                    .iter()
                    .all(|c| matches!(&c.error, Failure::Path(w) if w == "refused"))
            );
        }
        other => panic!("{other:?}"),
    }
    let above = |first: usize, samples: &[kuka_kinematics::Sample]| {
        samples
            .iter()
            .find(|s| s.pose.z < 300.0)
            .map(|s| (first + s.motion, format!("z {:.1}", s.pose.z)))
    };
    let cx = Context {
        path_check: Some(&above),
        ..cx
    };
    let chosen = configure::choose(
        &cx,
        &m.home,
        std::slice::from_ref(&ptp),
        &[ConfigMode::Auto],
    )
    .expect("a configuration whose sweep stays above z = 300");
    let c = chosen[0].expect("chosen");
    let run = kuka_kinematics::plan::plan(
        &m,
        &m.home,
        &zero,
        &zero,
        &[Motion {
            kind: MotionKind::PtpAxes { axes: c.axes },
            ..ptp.clone()
        }],
        &settings,
    );
    assert!(run.samples.iter().all(|s| s.pose.z >= 300.0), "{c:?}");
}

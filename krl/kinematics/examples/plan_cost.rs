//! What planning costs (issue 21, docs/BENCHMARKS.md §9): a batch of 1000
//! motions through configuration planning (`auto`) and the dry run the
//! service does before it sends anything, on the KR 3 R540.
//!
//! ```sh
//! cargo run --release -p kuka-kinematics --example plan_cost
//! ```
//!
//! Prints, per case, the median and worst of 15 runs: configuration
//! planning, the dry run, their sum, and µs per motion.

use std::time::Instant;

use kuka_kinematics::configure::{self, ConfigMode, Context, Margins};
use kuka_kinematics::{Motion, MotionKind, PlanSettings, Pose, RobotModel, plan};

fn pose(x: f64, y: f64, z: f64) -> Pose {
    Pose::new(x, y, z, 0.0, 180.0, 0.0)
}

fn motion(kind: MotionKind, velocity: f64, approx_mm: f64) -> Motion {
    Motion {
        kind,
        velocity,
        acceleration_pct: 100.0,
        approx_mm,
    }
}

/// A PTP without S/T, then 999 LINs around a 50 mm circle at Z 70
/// (0.31 mm each, approximated).
fn circle() -> Vec<Motion> {
    let mut m = vec![motion(
        MotionKind::Ptp {
            target: pose(270.0, 0.0, 70.0),
            s: None,
            t: None,
        },
        50.0,
        0.0,
    )];
    for i in 1..1000 {
        let a = i as f64 / 999.0 * std::f64::consts::TAU;
        m.push(motion(
            MotionKind::Lin {
                target: pose(220.0 + 50.0 * a.cos(), 50.0 * a.sin(), 70.0),
            },
            0.2,
            if i < 999 { 1.0 } else { 0.0 },
        ));
    }
    m
}

/// 1000 PTPs without S/T between two points 40 mm apart: a configuration
/// to choose for every motion.
fn ptps() -> Vec<Motion> {
    (0..1000)
        .map(|i| {
            let x = if i % 2 == 0 { 200.0 } else { 240.0 };
            motion(
                MotionKind::Ptp {
                    target: pose(x, 0.0, 70.0),
                    s: None,
                    t: None,
                },
                50.0,
                0.0,
            )
        })
        .collect()
}

fn main() {
    let model = RobotModel::kr3_r540();
    let zero = Pose::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let settings = PlanSettings::for_model(&model);
    let margins = Margins::default();
    let cx = Context {
        model: &model,
        tool: &zero,
        base: &zero,
        settings: &settings,
        margins: &margins,
        path_check: None,
    };
    println!("| batch of 1000 | configuration planning | dry run | total | per motion |");
    println!("|---|---|---|---|---|");
    for (name, motions) in [
        ("PTP + 999 LIN (50 mm circle, 0.31 mm segments)", circle()),
        ("1000 PTP, each S/T chosen", ptps()),
    ] {
        let modes = vec![ConfigMode::Auto; motions.len()];
        let mut runs = Vec::new();
        for _ in 0..15 {
            let t0 = Instant::now();
            let chosen = configure::choose(&cx, &model.home, &motions, &modes)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let t1 = Instant::now();
            let resolved: Vec<Motion> = motions
                .iter()
                .zip(&chosen)
                .map(|(m, c)| match (&m.kind, c) {
                    (MotionKind::Ptp { target, .. }, Some(c)) => Motion {
                        kind: MotionKind::Ptp {
                            target: *target,
                            s: Some(c.s),
                            t: Some(c.t),
                        },
                        ..m.clone()
                    },
                    _ => m.clone(),
                })
                .collect();
            let run = plan::plan(&model, &model.home, &zero, &zero, &resolved, &settings);
            assert!(run.error.is_none(), "{name}: {:?}", run.error);
            let t2 = Instant::now();
            runs.push(((t1 - t0).as_secs_f64(), (t2 - t1).as_secs_f64()));
        }
        runs.sort_by(|a, b| (a.0 + a.1).total_cmp(&(b.0 + b.1)));
        let (c, d) = runs[runs.len() / 2];
        let worst = runs[runs.len() - 1];
        println!(
            "| {name} | {:.1} ms | {:.1} ms | {:.1} ms (worst {:.1}) | {:.0} µs |",
            c * 1e3,
            d * 1e3,
            (c + d) * 1e3,
            (worst.0 + worst.1) * 1e3,
            (c + d) * 1e6 / motions.len() as f64
        );
    }
}

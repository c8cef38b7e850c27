//! One motion model on both sides (issue 21): the accelerations and speeds
//! `kb_main.src` commands are the ones the planner (the service's dry run,
//! configuration planning and both simulated controllers) assumes. Reads the
//! KRL program's assignments, the simulated `$config.dat` defaults and the
//! planner's constants, and fails when they differ.

use kuka_kinematics::PlanSettings;
use kuka_kinematics::plan::{ORI_ACC_DEG_S2, ORI_SPEED_DEG_S};
use kuka_krc::{KRL_FILES, simulated_config_dat};

fn kb_main() -> &'static str {
    KRL_FILES
        .iter()
        .find(|(name, _)| *name == "kb_main.src")
        .map(|(_, text)| *text)
        .expect("kb_main.src is shipped")
}

/// The right-hand sides of every assignment to `var` in the text.
fn assignments(text: &str, var: &str) -> Vec<String> {
    text.lines()
        .map(|l| l.split(';').next().unwrap_or("").trim())
        .filter_map(|l| {
            let (lhs, rhs) = l.split_once('=')?;
            (lhs.trim().eq_ignore_ascii_case(var)).then(|| rhs.trim().to_string())
        })
        .collect()
}

/// A REAL of the simulated `$config.dat` (`DECL GLOBAL REAL NAME=value`).
fn config_value(name: &str) -> f64 {
    simulated_config_dat()
        .lines()
        .find_map(|l| {
            let rest = l.trim().strip_prefix("DECL GLOBAL REAL ")?;
            let (n, v) = rest.split_once('=')?;
            (n.trim() == name).then(|| v.trim().parse().ok())?
        })
        .unwrap_or_else(|| panic!("{name} in the simulated $config.dat"))
}

#[test]
fn the_krl_program_commands_what_the_planner_assumes() {
    let src = kb_main();
    let plan = PlanSettings::default();

    // Path acceleration: BAS(#ACC_CP) semantics, DEF_ACC_CP × pct / 100,
    // and DEF_ACC_CP (2.3 m/s² in real $config.dat files) is the planner's
    // 100 % and the interpreter's.
    assert_eq!(
        assignments(src, "$ACC.CP"),
        vec!["DEF_ACC_CP * m.ACC / 100.0".to_string()],
        "kb_main.src must command $ACC.CP as BAS(#ACC_CP) does"
    );
    assert_eq!(config_value("DEF_ACC_CP"), plan.max_acc_cp);
    assert_eq!(kuka_krl_runtime::interp::ACC_CP_MAX, plan.max_acc_cp);

    // Orientation speed: $VEL.ORI1/2 capped at 200 °/s, the planner's
    // ORI_SPEED_DEG_S.
    for var in ["$VEL.ORI1", "$VEL.ORI2"] {
        let rhs = assignments(src, var);
        assert!(!rhs.is_empty(), "{var} is set");
        for r in &rhs {
            let cap: f64 = r
                .trim_start_matches("KrMin(")
                .split(',')
                .next()
                .and_then(|v| v.trim().parse().ok())
                .unwrap_or_else(|| panic!("{var} = {r}: KrMin(<cap>, …)"));
            assert_eq!(cap, ORI_SPEED_DEG_S, "{var} = {r}");
        }
    }
    // Orientation acceleration: DEF_ACC_ORI1/2 × pct / 100 (BAS semantics),
    // DEF_ACC_ORI1/2 (100 °/s²) = the planner's ORI_ACC_DEG_S2.
    for (var, def) in [("$ACC.ORI1", "DEF_ACC_ORI1"), ("$ACC.ORI2", "DEF_ACC_ORI2")] {
        assert_eq!(
            assignments(src, var),
            vec![format!("{def} * m.ACC / 100.0")],
            "{var}"
        );
        assert_eq!(config_value(def), ORI_ACC_DEG_S2, "{def}");
    }

    // Axis speed and acceleration: percentages of the machine data, which
    // the planner takes from the model (max_speed_deg_s, max_acc_deg_s2).
    for var in ["$VEL_AXIS[k]", "$ACC_AXIS[k]"] {
        let rhs = assignments(src, var);
        assert!(!rhs.is_empty(), "{var} is set");
        for r in rhs {
            assert!(
                r.starts_with("KrPct(") || r == "v" || r == "a",
                "{var} = {r}: a percentage"
            );
        }
    }
}

//! The shipped KRL program running in the KRC-like runtime, spoken to
//! through the real channel files exactly as the service does: the
//! Submit side's heartbeat, a round trip (GETPOS), a MOVE batch executed
//! by `kb_main` with blending, and the cost figures.

use std::path::Path;
use std::time::Duration;

use kuka_krc::{KrcConfig, KrcController};
use kuka_protocol::files::{WriteError, atomic_write};
use kuka_protocol::{
    COMMAND_FILE, Command, CommandFile, Frame, MotionParams, MotionRecord, RESULT_FILE, ResultCode,
    ResultFile, ResultRecord, STATE_FILE, StateFile,
};

fn start(dir: &Path) -> KrcController {
    let mut c = KrcConfig::new(dir);
    c.time_scale = 0.0;
    KrcController::start(c).expect("the runtime starts")
}

fn state(dir: &Path) -> Option<StateFile> {
    let text = std::fs::read_to_string(dir.join(STATE_FILE)).ok()?;
    StateFile::decode(&text).ok()
}

/// Sends a command and waits (in simulated time) for its result.
fn round_trip(
    krc: &KrcController,
    dir: &Path,
    cid: i32,
    command: Command,
    limit_s: u64,
) -> ResultRecord {
    let text = CommandFile { cid, command }.encode().expect("encodes");
    // The KRL program holds the command file open while it reads it (an
    // open handle blocks replacing it, as on Windows): retry like the
    // service does, in simulated time.
    let mut error = None;
    let written = krc.wait_until(Duration::from_secs(1), |_| {
        match atomic_write(dir, COMMAND_FILE, "test", &text) {
            Ok(()) => true,
            Err(WriteError::Locked { .. }) => false,
            Err(e) => {
                error = Some(e.to_string());
                true
            }
        }
    });
    assert!(written && error.is_none(), "command not written: {error:?}");
    let mut found = None;
    let done = krc.wait_until(Duration::from_secs(limit_s), |_| {
        let Ok(text) = std::fs::read_to_string(dir.join(RESULT_FILE)) else {
            return false;
        };
        let Ok(f) = ResultFile::decode(&text) else {
            return false;
        };
        found = f.results.into_iter().find(|r| r.cid == cid);
        found.is_some()
    });
    assert!(
        done,
        "no result for CID {cid}: {:?}\n{:?}",
        krc.snapshot(),
        krc.stats()
    );
    found.expect("found")
}

#[test]
fn the_shipped_program_answers_through_the_channel_files() {
    let dir = tempfile::tempdir().expect("tempdir");
    let krc = start(dir.path());
    // The Submit side's heartbeat appears within a second of simulated time.
    assert!(
        krc.wait_until(Duration::from_secs(2), |_| state(dir.path()).is_some()),
        "no state file: {:?}",
        krc.snapshot()
    );
    let snap = krc.snapshot();
    assert_eq!(snap.pro_name, "KB_MAIN", "{snap:?}");
    assert!(
        snap.robot_errors.is_empty() && snap.submit_error.is_none(),
        "{snap:?}"
    );

    let r = round_trip(&krc, dir.path(), 1, Command::GetPosition, 2);
    assert_eq!(r.code, ResultCode::Ok, "{r:?}");
    let model = kuka_kinematics::RobotModel::kr3_r540();
    for (a, b) in r.axes.iter().zip(model.home) {
        assert!(
            (a - b).abs() < 1e-3,
            "{:?} vs home {:?}",
            r.axes,
            model.home
        );
    }

    // A blended square of LINs, 50 mm a side, from the home pose.
    let home = model.forward(
        &model.home,
        &kuka_kinematics::Pose::IDENTITY,
        &kuka_kinematics::Pose::IDENTITY,
    );
    let corner = |dx: f64, dy: f64| Frame {
        x: home.x + dx,
        y: home.y + dy,
        z: home.z,
        a: home.a,
        b: home.b,
        c: home.c,
    };
    let params = |apo: f64| MotionParams {
        velocity: 0.2,
        acceleration_pct: 100.0,
        approx_mm: apo,
    };
    let square: Vec<MotionRecord> = [(50.0, 0.0), (50.0, 50.0), (0.0, 50.0), (0.0, 0.0)]
        .iter()
        .enumerate()
        .map(|(i, (dx, dy))| MotionRecord::Lin {
            target: corner(*dx, *dy),
            params: params(if i < 3 { 5.0 } else { 0.0 }),
        })
        .collect();
    let before = krc.stats();
    let r = round_trip(&krc, dir.path(), 2, Command::Move(square), 20);
    assert_eq!(
        (r.code, r.completed),
        (ResultCode::Ok, 4),
        "{r:?}\n{:?}",
        krc.snapshot()
    );
    assert!(
        (r.position.x - home.x).abs() < 0.01 && (r.position.y - home.y).abs() < 0.01,
        "{r:?}"
    );
    let after = krc.stats();
    assert_eq!(after.motions_done - before.motions_done, 4, "{after:?}");
    assert_eq!(
        after.chains_started - before.chains_started,
        1,
        "the four blended LINs play as one chain (no exact stop): {after:?}"
    );
    assert!(after.motion_errors.is_empty(), "{after:?}");
    // The cost is measured, not yet within budget: a pass that handles a
    // command runs far more statements than an idle pass (the figures and
    // the goal are in docs/BENCHMARKS.md, `cargo run -p kuka-krc --example
    // submit_cost`).
    assert!(after.passes > before.passes, "{after:?}");
    assert!(
        after.pass_statements_max > after.pass_statements_p50,
        "a command pass costs more than an idle one: {after:?}"
    );
    krc.shutdown();
}

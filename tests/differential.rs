//! The two simulated controllers against each other: the same random
//! command sequences go to the native simulator (`krl/sim`, a Rust model
//! of the KRL program) and to the KRC-like runtime running the shipped
//! KRL program (`krl/krc`), through the channel files as the service
//! writes them. Their answers — result code, motions completed, reached
//! axes — must agree; every difference is a bug in one of
//! them or a documented difference (docs/CONTROLLER.md, "The KRC-like
//! runtime").
//!
//! The sequences come from a fixed seed (`KB_DIFF_SEED` to try another,
//! `KB_DIFF_COMMANDS` for more commands): a failure names the seed, the
//! sequence and the command.

use std::path::Path;
use std::time::{Duration, Instant};

use kuka_kinematics::{Pose, RobotModel};
use kuka_krc::{KrcConfig, KrcController};
use kuka_protocol::files::{WriteError, atomic_write};
use kuka_protocol::{
    COMMAND_FILE, Command, CommandFile, Frame, MotionParams, MotionRecord, RESULT_FILE, ResultCode,
    ResultFile, ResultRecord, STATE_FILE, SpeedRecord,
};
use kuka_sim::{SimConfig, SimController};

/// A small deterministic generator (xorshift64*): the sequences must be
/// the same on every machine, and a seed must reproduce a failure.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn pick(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

fn env_or(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn read_result(dir: &Path, cid: i32) -> Option<ResultRecord> {
    let text = std::fs::read_to_string(dir.join(RESULT_FILE)).ok()?;
    let f = ResultFile::decode(&text).ok()?;
    f.results.into_iter().find(|r| r.cid == cid)
}

fn try_write(dir: &Path, text: &str) -> Result<bool, String> {
    match atomic_write(dir, COMMAND_FILE, "diff", text) {
        Ok(()) => Ok(true),
        Err(WriteError::Locked { .. }) => Ok(false),
        Err(e) => Err(e.to_string()),
    }
}

/// The native simulator: instant at time scale 0; waited on in wall time.
fn native_round_trip(dir: &Path, cid: i32, text: &str) -> ResultRecord {
    let deadline = Instant::now() + Duration::from_secs(30);
    while !try_write(dir, text).expect("command written") {
        assert!(Instant::now() < deadline, "native: command file locked");
        std::thread::sleep(Duration::from_millis(1));
    }
    loop {
        if let Some(r) = read_result(dir, cid) {
            return r;
        }
        assert!(Instant::now() < deadline, "native: no result for CID {cid}");
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// The KRC-like runtime: waited on in simulated time. `None`: no answer
/// because the robot program is in an error stop (a motion failed on the
/// way: `$STOPMESS`).
fn krc_round_trip(krc: &KrcController, dir: &Path, cid: i32, text: &str) -> Option<ResultRecord> {
    krc_send(krc, dir, cid, text, true)
}

/// [`krc_round_trip`]; `give_up_on_error_stop` false: wait for the answer
/// even while a stop message is pending (STOP, RESET).
fn krc_send(
    krc: &KrcController,
    dir: &Path,
    cid: i32,
    text: &str,
    give_up_on_error_stop: bool,
) -> Option<ResultRecord> {
    let mut error = None;
    let written = krc.wait_until(Duration::from_secs(5), |_| match try_write(dir, text) {
        Ok(done) => done,
        Err(e) => {
            error = Some(e);
            true
        }
    });
    assert!(
        written && error.is_none(),
        "krc: command not written: {error:?}"
    );
    let mut found = None;
    let answered = krc.wait_until(Duration::from_secs(600), |_| {
        found = read_result(dir, cid);
        found.is_some() || (give_up_on_error_stop && krc.stop_message())
    });
    assert!(
        answered,
        "krc: no result for CID {cid}: {:?}",
        krc.snapshot()
    );
    found
}

/// After an error stop: what the service and the operator do. STOP ends
/// the job (CANCELLED), RESET leaves the bridge's error state, the operator
/// acknowledges the message and starts kb_main again.
fn krc_recover(krc: &KrcController, dir: &Path, cid: &mut i32) {
    for command in [Command::Stop, Command::Reset] {
        *cid += 1;
        let text = CommandFile { cid: *cid, command }
            .encode()
            .expect("encodes");
        let r = krc_send(krc, dir, *cid, &text, false).expect("STOP and RESET are answered");
        assert_eq!(r.code, ResultCode::Ok, "{r:?}");
    }
    krc.operator_restart();
    assert!(
        krc.wait_until(Duration::from_secs(10), |s| s.pro_state == "ACTIVE"
            && !s.moving
            && s.pro_name == "KB_MAIN"),
        "kb_main restarted: {:?}",
        krc.snapshot()
    );
}

/// Sends both controllers home with the next CID (a common pose after a
/// difference or an error stop); the KRL program's answer.
fn both_home(
    native_dir: &Path,
    krc: &KrcController,
    krc_dir: &Path,
    cid: &mut i32,
    rng: &mut Rng,
    model: &RobotModel,
) -> ResultRecord {
    *cid += 1;
    let reset = CommandFile {
        cid: *cid,
        command: Command::Move(vec![MotionRecord::PtpAxes {
            axes: model.home,
            params: params(rng, false, false),
        }]),
    }
    .encode()
    .expect("encodes");
    native_round_trip(native_dir, *cid, &reset);
    krc_round_trip(krc, krc_dir, *cid, &reset).expect("answered")
}

fn frame(p: &Pose) -> Frame {
    let [x, y, z, a, b, c] = p.to_array();
    Frame { x, y, z, a, b, c }
}

fn params(rng: &mut Rng, cart: bool, approx: bool) -> MotionParams {
    MotionParams {
        velocity: if cart {
            rng.range(0.05, 0.5)
        } else {
            rng.range(10.0, 100.0)
        },
        acceleration_pct: rng.range(20.0, 100.0),
        approx_mm: if approx { rng.range(0.0, 10.0) } else { 0.0 },
    }
}

/// Axes well inside the limits and away from the wrist singularity.
fn random_axes(rng: &mut Rng, model: &RobotModel) -> [f64; 6] {
    let mut axes = [0.0; 6];
    for (i, a) in axes.iter_mut().enumerate() {
        let (lo, hi) = model.limits_deg[i];
        *a = rng.range(lo * 0.6, hi * 0.6);
    }
    if axes[4].abs() < 10.0 {
        axes[4] = 30.0_f64.copysign(axes[4]);
    }
    axes
}

/// One random command from where the robot is (`axes`, `pose`).
fn command(rng: &mut Rng, model: &RobotModel, axes: &[f64; 6], pose: &Pose) -> Command {
    let offset = |rng: &mut Rng, p: &Pose, r: f64| {
        let mut f = frame(p);
        f.x += rng.range(-r, r);
        f.y += rng.range(-r, r);
        f.z += rng.range(-r, r);
        f
    };
    match rng.pick(23) {
        0 => Command::GetPosition,
        1 => Command::Home,
        2 => {
            // An axis PTP of either family (PTA, SPA), picked by A6's
            // sign (no draw of its own: the sequence after it is the one
            // the seed always gave).
            let (axes, params) = (random_axes(rng, model), params(rng, false, false));
            Command::Move(vec![if axes[5] >= 0.0 {
                MotionRecord::PtpAxes { axes, params }
            } else {
                MotionRecord::SptpAxes { axes, params }
            }])
        }
        3 => {
            // A Cartesian PTP to a pose reached by known axes, with its
            // Status and Turn: both must arrive at those axes.
            let target_axes = random_axes(rng, model);
            let p = model.forward(&target_axes, &Pose::IDENTITY, &Pose::IDENTITY);
            Command::Move(vec![MotionRecord::Ptp {
                target: frame(&p),
                s: Some(model.status(&target_axes)),
                t: Some(RobotModel::turn(&target_axes)),
                params: params(rng, false, false),
            }])
        }
        4 | 5 => Command::Move(vec![MotionRecord::Lin {
            target: offset(rng, pose, 60.0),
            params: params(rng, true, false),
        }]),
        6 => {
            let n = 2 + rng.pick(5);
            Command::Move(
                (0..n)
                    .map(|i| MotionRecord::Lin {
                        target: offset(rng, pose, 40.0),
                        params: params(rng, true, i + 1 < n),
                    })
                    .collect(),
            )
        }
        7 => {
            // A CIRC through a point beside the chord.
            let end = offset(rng, pose, 40.0);
            let f = frame(pose);
            let aux = [
                (f.x + end.x) / 2.0 + rng.range(-20.0, 20.0),
                (f.y + end.y) / 2.0 + rng.range(-20.0, 20.0),
                (f.z + end.z) / 2.0 + rng.range(-5.0, 5.0),
            ];
            Command::Move(vec![MotionRecord::Circ {
                aux,
                target: end,
                params: params(rng, true, false),
            }])
        }
        8 => Command::Move(vec![MotionRecord::Lin {
            // Far outside the arm's reach: both must refuse it.
            target: Frame {
                x: 5000.0,
                ..frame(pose)
            },
            params: params(rng, true, false),
        }]),
        9 => Command::SetSpeed(SpeedRecord {
            // The program override too (both scale motion time by it).
            override_pct: if rng.pick(3) == 0 {
                rng.range(10.0, 100.0)
            } else {
                100.0
            },
            ptp_velocity_pct: rng.range(10.0, 100.0),
            ptp_acceleration_pct: rng.range(20.0, 100.0),
            cp_velocity: rng.range(0.05, 1.0),
            cp_acceleration_pct: rng.range(20.0, 100.0),
        }),
        10 => Command::SetTool(Frame {
            x: rng.range(-20.0, 20.0),
            y: rng.range(-20.0, 20.0),
            z: rng.range(0.0, 120.0),
            a: rng.range(-30.0, 30.0),
            b: 0.0,
            c: 0.0,
        }),
        11 => Command::SetBase(Frame {
            x: rng.range(-50.0, 50.0),
            y: rng.range(-50.0, 50.0),
            z: rng.range(-20.0, 20.0),
            a: rng.range(-20.0, 20.0),
            b: 0.0,
            c: 0.0,
        }),
        12 => Command::GetBase,
        13 => Command::Reset,
        15 => {
            // An SPTP, as case 3's PTP.
            let target_axes = random_axes(rng, model);
            let p = model.forward(&target_axes, &Pose::IDENTITY, &Pose::IDENTITY);
            Command::Move(vec![MotionRecord::Sptp {
                target: frame(&p),
                s: Some(model.status(&target_axes)),
                t: Some(RobotModel::turn(&target_axes)),
                params: params(rng, false, false),
            }])
        }
        16 => {
            // Spline and conventional path motions mixed: they blend only
            // within their family.
            let f = frame(pose);
            let end = offset(rng, pose, 30.0);
            let aux = [
                (f.x + end.x) / 2.0 + rng.range(-15.0, 15.0),
                (f.y + end.y) / 2.0 + rng.range(-15.0, 15.0),
                (f.z + end.z) / 2.0,
            ];
            Command::Move(vec![
                MotionRecord::Slin {
                    target: offset(rng, pose, 30.0),
                    params: params(rng, true, true),
                },
                MotionRecord::Lin {
                    target: offset(rng, pose, 30.0),
                    params: params(rng, true, true),
                },
                MotionRecord::Scirc {
                    aux,
                    target: end,
                    params: params(rng, true, true),
                },
                MotionRecord::Slin {
                    target: offset(rng, pose, 30.0),
                    params: params(rng, true, false),
                },
            ])
        }
        17 | 18 => {
            // A spline block of 1..=8 points, then (17) an SLIN.
            let n = 1 + rng.pick(8);
            let p = params(rng, true, true);
            let mut motions: Vec<MotionRecord> = (0..n)
                .map(|i| MotionRecord::Spl {
                    target: offset(rng, pose, 40.0),
                    params: p,
                    left: (n - i) as u8,
                })
                .collect();
            if rng.pick(2) == 0 {
                motions.push(MotionRecord::Slin {
                    target: offset(rng, pose, 30.0),
                    params: params(rng, true, false),
                });
            }
            Command::Move(motions)
        }
        19 => Command::SetOutput(kuka_protocol::OutputRecord {
            // Inside the program's window of 31 outputs, or beyond it (the
            // service never sends that; both must answer alike anyway).
            index: if rng.pick(6) == 0 {
                40 + rng.pick(100) as u16
            } else {
                1 + rng.pick(31) as u16
            },
            value: rng.pick(2) == 0,
            pulse_ms: if rng.pick(3) == 0 {
                10 + rng.pick(200) as u32
            } else {
                0
            },
        }),
        20 => Command::SetAnalogOutput(kuka_protocol::AnalogOutputRecord {
            index: 1 + rng.pick(8) as u8,
            value: rng.range(-1.0, 1.0),
        }),
        21 => {
            // A closed path of LINs (a PATH command: the service's form of
            // a batch of more than 4 motions); its id is set by the caller.
            let n = 2 + rng.pick(6);
            Command::OpenPath(kuka_protocol::PathChunk {
                path: 0,
                first: 0,
                motions: (0..n)
                    .map(|i| MotionRecord::Lin {
                        target: offset(rng, pose, 40.0),
                        params: params(rng, true, i + 1 < n),
                    })
                    .collect(),
                close: true,
            })
        }
        22 => {
            // I/O actions between blended LINs: an output at the start of
            // the next motion, one at a point of the path, a wait for an
            // input (inputs are all off: either at once or a timeout) and
            // a dwell.
            let lin = |rng: &mut Rng, blend| MotionRecord::Lin {
                target: offset(rng, pose, 40.0),
                params: params(rng, true, blend),
            };
            let first = lin(rng, true);
            let index = 1 + rng.pick(31) as u16;
            let action = match rng.pick(4) {
                0 => MotionRecord::SetOutput {
                    index,
                    value: true,
                    pulse_ms: 0,
                    path_mm: None,
                },
                1 => MotionRecord::SetOutput {
                    index,
                    value: true,
                    pulse_ms: 0,
                    path_mm: Some(-rng.range(0.0, 5.0)),
                },
                2 => MotionRecord::WaitInput {
                    index,
                    value: rng.pick(2) == 0,
                    timeout_ms: 50,
                },
                _ => MotionRecord::Dwell {
                    ms: rng.pick(100) as u32,
                },
            };
            let last = lin(rng, false);
            Command::Move(vec![first, action, last])
        }
        _ => {
            let _ = axes;
            Command::GetTool
        }
    }
}

#[test]
fn native_simulator_and_shipped_krl_program_answer_alike() {
    let seed = env_or("KB_DIFF_SEED", 20_261_126);
    let commands = env_or("KB_DIFF_COMMANDS", 500) as usize;
    let model = RobotModel::kr3_r540();
    let native_dir = tempfile::tempdir().expect("tempdir");
    let krc_dir = tempfile::tempdir().expect("tempdir");
    let mut sc = SimConfig::new(native_dir.path());
    sc.time_scale = 0.0;
    sc.model = model.clone();
    let native = SimController::start(sc).expect("native simulator");
    let mut kc = KrcConfig::new(krc_dir.path());
    kc.time_scale = 0.0;
    kc.model = model.clone();
    // The budget changes when answers come, not what they say: a large
    // one makes the test fast.
    kc.submit_budget = 50_000;
    let krc = KrcController::start(kc).expect("KRC-like runtime");
    assert!(
        krc.wait_until(Duration::from_secs(5), |_| krc_dir
            .path()
            .join(STATE_FILE)
            .exists()),
        "the KRL program's heartbeat"
    );

    let mut rng = Rng(seed.max(1));
    let mut differences = Vec::new();
    let mut axes = model.home;
    let mut cid = 0;
    let mut per_code = std::collections::BTreeMap::<String, usize>::new();
    let mut error_stops = 0;
    let mut end_point_refusals = 0;
    for i in 0..commands {
        let pose = model.forward(&axes, &Pose::IDENTITY, &Pose::IDENTITY);
        // Every 10th command starts a sequence from a common random pose.
        let cmd = if i % 10 == 0 {
            Command::Move(vec![MotionRecord::PtpAxes {
                axes: random_axes(&mut rng, &model),
                params: params(&mut rng, false, false),
            }])
        } else {
            command(&mut rng, &model, &axes, &pose)
        };
        cid += 1;
        let cmd = match cmd {
            Command::OpenPath(chunk) => {
                Command::OpenPath(kuka_protocol::PathChunk { path: cid, ..chunk })
            }
            other => other,
        };
        let text = CommandFile {
            cid,
            command: cmd.clone(),
        }
        .encode()
        .expect("encodes");
        let a = native_round_trip(native_dir.path(), cid, &text);
        let b = krc_round_trip(&krc, krc_dir.path(), cid, &text);
        *per_code.entry(format!("{:?}", a.code)).or_default() += 1;
        // An error stop: no answer yet, or the program's ERROR answer
        // (code 30) for the job the robot could not finish.
        let b = b.filter(|_| !krc.stop_message());
        let Some(b) = b else {
            // The KRL program checks a motion's end point only; the native
            // simulator plans the whole path first. A path through a
            // singularity or a limit: the native one refuses it, the KRC
            // stops on the way (documented difference).
            let path_refusal = matches!(
                a.code,
                ResultCode::Singularity | ResultCode::SoftwareLimit | ResultCode::Unreachable
            );
            if !path_refusal {
                differences.push(format!(
                    "command {i} (CID {cid}) {} from {:?}: native {:?} {} {:?}, krc error stop ({})\n  sent: {}",
                    cmd.name(),
                    axes,
                    a.code,
                    a.completed,
                    a.axes,
                    krc.stats().motion_errors.last().map_or("no motion error", String::as_str),
                    text.lines().collect::<Vec<_>>().join("\n        ")
                ));
            }
            error_stops += 1;
            krc_recover(&krc, krc_dir.path(), &mut cid);
            let r = both_home(
                native_dir.path(),
                &krc,
                krc_dir.path(),
                &mut cid,
                &mut rng,
                &model,
            );
            assert_eq!(r.code, ResultCode::Ok, "{r:?}");
            axes = model.home;
            continue;
        };
        let same_axes = a.axes.iter().zip(b.axes).all(|(x, y)| (x - y).abs() < 0.01);
        let refused = |c: ResultCode| {
            matches!(
                c,
                ResultCode::Singularity
                    | ResultCode::SoftwareLimit
                    | ResultCode::Unreachable
                    | ResultCode::NoConfiguration
            )
        };
        // The KRL program checks the end point before it moves (INVERSE)
        // and refuses there; the native simulator plans the path and, when
        // a point on the way fails first, plays it up to that point
        // (documented: docs/CONTROLLER.md, the differential test).
        // The same, further into a batch: both refuse the same motion,
        // the native simulator after playing it up to the failing point.
        // And a command the KRL program refuses before anything moves (it
        // checks a spline block's points before the block starts, as a
        // KRC plans a block as a whole) where the native simulator
        // refuses it too: before moving, or at an earlier motion, where
        // its path fails first.
        let unmoved = |x: &[f64; 6]| x.iter().zip(axes).all(|(p, q)| (p - q).abs() < 0.01);
        let apart = a.code != b.code || a.completed != b.completed || !same_axes;
        let end_point_vs_path = apart
            && refused(a.code)
            && refused(b.code)
            && (a.completed == b.completed
                || (unmoved(&b.axes) && (unmoved(&a.axes) || a.completed <= b.completed)));
        if end_point_vs_path {
            end_point_refusals += 1;
        }
        let differs = apart && !end_point_vs_path;
        if differs {
            differences.push(format!(
                "command {i} (CID {cid}) {} from {:?}:\n  native {:?} {} {:?}\n  krc    {:?} {} {:?}\n  sent: {}",
                cmd.name(),
                axes,
                a.code,
                a.completed,
                a.axes,
                b.code,
                b.completed,
                b.axes,
                text.lines().collect::<Vec<_>>().join("\n        ")
            ));
        }
        if differs || end_point_vs_path {
            // Both go to a common pose again.
            both_home(
                native_dir.path(),
                &krc,
                krc_dir.path(),
                &mut cid,
                &mut rng,
                &model,
            );
            axes = model.home;
        } else {
            axes = a.axes;
        }
    }
    let snap = krc.snapshot();
    assert!(
        snap.robot_errors.is_empty() && snap.submit_error.is_none(),
        "{snap:?}"
    );
    eprintln!(
        "seed {seed}: {commands} commands, native codes {per_code:?}, {error_stops} error stops of the KRL program where the native simulator refused the path, {end_point_refusals} end points the KRL program refused where the native simulator stopped on the way, {} differences",
        differences.len()
    );
    assert!(
        differences.is_empty(),
        "seed {seed}: {} of {commands} commands answered differently:\n{}",
        differences.len(),
        differences.join("\n")
    );
    native.shutdown();
    krc.shutdown();
}

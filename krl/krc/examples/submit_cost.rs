//! What the shipped KRL program costs on the controller, measured in the
//! KRC-like runtime: statements per pass of the Submit loop, file
//! operations per motion, standstill before a MOVE (1 and 4 motions, the
//! most the service sends as a MOVE) starts to move, round trip per
//! command (GETPOS, SETANOUT), a MOVE with I/O actions (SOT, DWL). The figures go to
//! docs/BENCHMARKS.md §8.
//!
//! ```text
//! cargo run --release -p kuka-krc --example submit_cost [-- --cycle-ms 12 --budget 500]
//! ```
//!
//! Times are simulated controller time (`$ROB_TIMER`), sampled once a
//! cycle: they are exact to one cycle. The clock runs ten times faster
//! than real time.

use std::path::Path;
use std::time::Duration;

use anyhow::{Context, bail};
use kuka_krc::{KrcConfig, KrcController, KrcStats};
use kuka_protocol::files::{WriteError, atomic_write};
use kuka_protocol::{
    AnalogOutputRecord, COMMAND_FILE, Command, CommandFile, Frame, MotionParams, MotionRecord,
    RESULT_FILE, ResultCode, ResultFile,
};

fn arg(name: &str, default: u64) -> anyhow::Result<u64> {
    let args: Vec<String> = std::env::args().collect();
    match args.iter().position(|a| a == name) {
        Some(i) => args
            .get(i + 1)
            .context("a value after the option")?
            .parse()
            .with_context(|| format!("{name} takes a number")),
        None => Ok(default),
    }
}

/// Writes the command between two cycles (retrying while the KRL program
/// holds the file open); the controller time it appeared at.
fn send(krc: &KrcController, dir: &Path, cid: i32, command: Command) -> anyhow::Result<i64> {
    let text = CommandFile { cid, command }.encode()?;
    for _ in 0..100_000 {
        let written =
            krc.between_cycles(|t| match atomic_write(dir, COMMAND_FILE, "bench", &text) {
                Ok(()) => Ok(Some(t)),
                Err(WriteError::Locked { .. }) => Ok(None),
                Err(e) => Err(e),
            })?;
        if let Some(t) = written {
            return Ok(t);
        }
        std::thread::sleep(Duration::from_micros(100));
    }
    bail!("the command file stayed locked")
}

/// Waits for the result of `cid`; the controller time it was seen at.
fn result(krc: &KrcController, dir: &Path, cid: i32) -> anyhow::Result<(i64, ResultCode)> {
    for _ in 0..10_000_000 {
        let seen = krc.between_cycles(|t| {
            let text = std::fs::read_to_string(dir.join(RESULT_FILE)).ok()?;
            let f = ResultFile::decode(&text).ok()?;
            f.results
                .into_iter()
                .find(|r| r.cid == cid)
                .map(|r| (t, r.code))
        });
        if let Some(s) = seen {
            return Ok(s);
        }
        std::thread::sleep(Duration::from_micros(50));
    }
    bail!("no result for CID {cid}: {:?}", krc.snapshot())
}

fn file_ops(s: &KrcStats) -> u64 {
    s.file_calls.values().sum()
}

fn main() -> anyhow::Result<()> {
    let cycle_ms = arg("--cycle-ms", 12)?;
    let budget = arg("--budget", 500)?;
    let dir = tempfile::tempdir()?;
    let mut config = KrcConfig::new(dir.path());
    config.cycle = Duration::from_millis(cycle_ms);
    config.submit_budget = budget;
    config.time_scale = 10.0;
    let krc = KrcController::start(config)?;
    let model = kuka_kinematics::RobotModel::kr3_r540();
    let home = model.forward(
        &model.home,
        &kuka_kinematics::Pose::IDENTITY,
        &kuka_kinematics::Pose::IDENTITY,
    );
    println!(
        "KRC-like runtime, shipped KRL program, {cycle_ms} ms cycle, Submit budget {budget} statements/cycle"
    );

    // Idle: the Submit loop with nothing to do.
    let t0 = send(&krc, dir.path(), 1, Command::GetPosition)?;
    result(&krc, dir.path(), 1)?;
    let idle0 = krc.stats();
    krc.wait_until(Duration::from_secs(2), |s| s.time_ms > t0 + 2000);
    let idle1 = krc.stats();
    println!(
        "idle 2 s: {} passes, {} file operations/s, statements/pass max {}",
        idle1.passes - idle0.passes,
        (file_ops(&idle1) - file_ops(&idle0)) / 2,
        idle1.pass_statements_max,
    );

    // Round trip of a command without motion.
    let mut trips = Vec::new();
    for cid in 2..22 {
        let t = send(&krc, dir.path(), cid, Command::GetPosition)?;
        let (seen, code) = result(&krc, dir.path(), cid)?;
        if code != ResultCode::Ok {
            bail!("GETPOS answered {code:?}");
        }
        trips.push(seen - t);
    }
    trips.sort_unstable();
    println!(
        "GETPOS round trip (20): min {} ms, median {} ms, max {} ms",
        trips[0],
        trips[trips.len() / 2],
        trips[trips.len() - 1]
    );

    // SETANOUT (op 15): answered by the Submit side, which writes the
    // result and then the state file with its ANS line in the same pass.
    let before = krc.stats();
    let mut trips = Vec::new();
    for cid in 22..42 {
        let command = Command::SetAnalogOutput(AnalogOutputRecord {
            index: (cid % 8 + 1) as u8,
            value: f64::from(cid - 32) * 0.1,
        });
        let t = send(&krc, dir.path(), cid, command)?;
        let (seen, code) = result(&krc, dir.path(), cid)?;
        if code != ResultCode::Ok {
            bail!("SETANOUT answered {code:?}");
        }
        trips.push(seen - t);
    }
    trips.sort_unstable();
    let after = krc.stats();
    println!(
        "SETANOUT round trip (20): min {} ms, median {} ms, max {} ms; longest Submit pass {} statements (before {})",
        trips[0],
        trips[trips.len() / 2],
        trips[trips.len() - 1],
        after.pass_statements_max,
        before.pass_statements_max,
    );

    // Batches: LINs of 5 mm back and forth, approximated 2 mm, 0.2 m/s.
    // The service sends a MOVE of at most 4 motions; bigger batches go as a
    // path (PATH and APPENDs), measured through the service by the
    // streaming bench (`cargo bench -p kuka-bridge-tests --bench streaming
    // -- --sim krc --sections 2,6`, docs/BENCHMARKS.md §10).
    let mut cid = 100;
    for n in [1usize, 4] {
        let motions: Vec<MotionRecord> = (0..n)
            .map(|i| MotionRecord::Lin {
                target: Frame {
                    x: home.x + if i % 2 == 0 { 5.0 } else { 0.0 },
                    y: home.y,
                    z: home.z,
                    a: home.a,
                    b: home.b,
                    c: home.c,
                },
                params: MotionParams {
                    velocity: 0.2,
                    acceleration_pct: 100.0,
                    approx_mm: if i + 1 < n { 2.0 } else { 0.0 },
                },
            })
            .collect();
        cid += 1;
        let before = krc.stats();
        let t = send(&krc, dir.path(), cid, Command::Move(motions))?;
        let (seen, code) = result(&krc, dir.path(), cid)?;
        let after = krc.stats();
        if code != ResultCode::Ok {
            bail!("MOVE of {n} answered {code:?}: {:?}", krc.snapshot());
        }
        let start = after.last_chain_start_ms.unwrap_or(seen);
        println!(
            "MOVE of {n:>4}: standstill before the first motion {:>5} ms ({:.1} cycles), \
             whole round trip {:>6} ms, moving {:>6.0} ms, chains {}, \
             file operations/motion {:.2}",
            start - t,
            (start - t) as f64 / cycle_ms as f64,
            seen - t,
            (after.moving_s - before.moving_s) * 1000.0,
            after.chains_started - before.chains_started,
            (file_ops(&after) - file_ops(&before)) as f64 / n as f64,
        );
    }
    // A MOVE of 4 records with actions (PROTOCOL.md 5.6): LIN, SOT, DWL
    // 50 ms, LIN, 5 mm each, as in a pick: the Submit side parses the
    // action lines like motion lines (4 INT fields), kb_main stops for the
    // dwell. The longest pass before and after it tells whether a pass
    // reading actions costs more than one reading 4 LINs.
    let lin = |dx: f64, apo: f64| MotionRecord::Lin {
        target: Frame {
            x: home.x + dx,
            y: home.y,
            z: home.z,
            a: home.a,
            b: home.b,
            c: home.c,
        },
        params: MotionParams {
            velocity: 0.2,
            acceleration_pct: 100.0,
            approx_mm: apo,
        },
    };
    let actions = vec![
        lin(5.0, 2.0),
        MotionRecord::SetOutput {
            index: 1,
            value: true,
            pulse_ms: 0,
            path_mm: None,
        },
        MotionRecord::Dwell { ms: 50 },
        lin(0.0, 0.0),
    ];
    cid += 1;
    let before = krc.stats();
    let t = send(&krc, dir.path(), cid, Command::Move(actions))?;
    let (seen, code) = result(&krc, dir.path(), cid)?;
    let after = krc.stats();
    if code != ResultCode::Ok {
        bail!("MOVE with actions answered {code:?}: {:?}", krc.snapshot());
    }
    println!(
        "MOVE of LIN, SOT, DWL 50 ms, LIN: whole round trip {:>6} ms, moving {:>6.0} ms, \
         chains {}; longest Submit pass before {} statements, after {}",
        seen - t,
        (after.moving_s - before.moving_s) * 1000.0,
        after.chains_started - before.chains_started,
        before.pass_statements_max,
        after.pass_statements_max,
    );
    let s = krc.stats();
    println!(
        "Submit passes: {} (statements/pass p50 {}, p99 {}, max {}); passes over the budget: {}",
        s.passes,
        s.pass_statements_p50,
        s.pass_statements_p99,
        s.pass_statements_max,
        s.passes_overrun
    );
    println!("file functions: {:?}", s.file_calls);
    krc.shutdown();
    Ok(())
}

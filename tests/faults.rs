//! Faults on the controller side: a killed, hung or silent controller, a
//! locked command file, half-written results, a restarted service. Nothing
//! may hang, nothing may be executed twice, the service keeps answering.

use std::io::Write;
use std::path::Path;
#[cfg(unix)]
use std::process::Command;
use std::time::{Duration, Instant};

use kuka_bridge_tests::{Options, TestService, WAIT, assert_close, test_config, wait_for};
use kuka_protocol::{
    COMMAND_FILE, CommandFile, ControllerStatus, Frame, OperatingMode, RESULT_FILE, ResultCode,
    ResultFile, ResultRecord, STATE_FILE, StateFile,
};
use serde_json::{Value, json};

/// The CLI binary built in this crate.
fn cli() -> &'static str {
    env!("CARGO_BIN_EXE_kuka-bridge-cli")
}

/// A simulated controller in its own process (`kuka-bridge simulate`).
struct SimProcess(kuka_bridge_tests::SimProcess);

impl SimProcess {
    fn spawn(dir: &Path, time_scale: f64) -> SimProcess {
        SimProcess(kuka_bridge_tests::SimProcess::spawn(cli(), dir, time_scale))
    }

    fn kill(&mut self) {
        self.0.kill();
    }
}

fn slow_motion() -> Value {
    json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 160}, "velocity_pct": 5}], "wait": false})
}

/// Waits until the command file holds a STOP (the service superseded
/// what was there); that command.
async fn stop_in_command_file(dir: &Path) -> CommandFile {
    let path = dir.join(COMMAND_FILE);
    wait_for(WAIT, "a STOP in the command file", async || {
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        match CommandFile::decode(&text) {
            Ok(cmd) if cmd.command == kuka_protocol::Command::Stop => Ok(cmd),
            _ => Err(text),
        }
    })
    .await
}

async fn wait_job_state(
    t: &TestService,
    id: u64,
    terminal: bool,
    want: &str,
    within: Duration,
) -> Value {
    let deadline = Instant::now() + within;
    loop {
        let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
        let state = j["state"].as_str().unwrap_or("").to_string();
        let done = ["done", "failed", "cancelled"].contains(&state.as_str());
        if state == want || (terminal && done) || Instant::now() > deadline {
            return j;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

#[tokio::test]
async fn killed_controller_gives_timeout_and_service_recovers() {
    let root = tempfile::tempdir().expect("tempdir");
    let mut sim = SimProcess::spawn(&root.path().join("channel"), 1.0);
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let (s, job) = t.post_json("/api/v1/motions", &slow_motion()).await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    let j = wait_job_state(&t, id, false, "executing", Duration::from_secs(5)).await;
    assert_eq!(j["state"], "executing", "{j}");
    let killed_at = Instant::now();
    sim.kill();
    let j = wait_job_state(&t, id, true, "failed", Duration::from_secs(5)).await;
    let waited = killed_at.elapsed();
    assert_eq!(j["state"], "failed", "{j}");
    assert_eq!(j["error"]["code"], "timeout", "{j}");
    assert!(
        waited < Duration::from_secs(2),
        "failed within the offline threshold: {waited:?}"
    );
    // The service keeps serving and reports the controller offline (the
    // state is published just after the job's failure: wait for it).
    t.wait_connection("offline").await;
    let (s, h) = t.get("/health").await;
    assert_eq!((s, &h["connection"]), (200, &json!("offline")));
    let (s, v) = t.post("/krl/getpos").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("controller_offline")),
        "{v}"
    );
    assert_eq!(v["statuscode"], 50);
    // A restarted controller is picked up again and commands work.
    let _sim2 = SimProcess::spawn(&root.path().join("channel"), 0.0);
    t.wait_connection("online").await;
    let (s, v) = t.post("/krl/getpos").await;
    assert_eq!(s, 200, "{v}");
    t.service.shutdown().await.expect("shutdown");
}

#[cfg(unix)]
#[tokio::test]
async fn hung_controller_process_gives_timeout() {
    let root = tempfile::tempdir().expect("tempdir");
    let sim = SimProcess::spawn(&root.path().join("channel"), 1.0);
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let (_, job) = t.post_json("/api/v1/motions", &slow_motion()).await;
    let id = job["id"].as_u64().expect("id");
    wait_job_state(&t, id, false, "executing", Duration::from_secs(5)).await;
    let pid = sim.0.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-STOP", &pid])
            .status()
            .expect("kill")
            .success()
    );
    let j = wait_job_state(&t, id, true, "failed", Duration::from_secs(5)).await;
    assert_eq!(j["error"]["code"], "timeout", "{j}");
    let (s, _) = t.get("/api/v1/state").await;
    assert_eq!(s, 200, "service still answers");
    assert!(
        Command::new("kill")
            .args(["-CONT", &pid])
            .status()
            .expect("kill")
            .success()
    );
    t.wait_connection("online").await;
    // After the timeout the service sent STOP: the resumed controller brakes.
    let command_file = root.path().join("channel").join(COMMAND_FILE);
    wait_for(
        WAIT,
        "the resumed controller to brake to idle",
        async || {
            let (_, st) = t.get("/api/v1/state").await;
            if st["controller"]["status"] == "idle" {
                Ok(())
            } else {
                let cmd = std::fs::read_to_string(&command_file).unwrap_or_default();
                Err(format!("{st}\njob: {j}\ncommand file: {cmd}"))
            }
        },
    )
    .await;
    let (s, v) = t.post("/krl/getpos").await;
    assert_eq!(s, 200, "{v}");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn paused_embedded_controller_times_out_then_recovers() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let (_, job) = t.post_json("/api/v1/motions", &slow_motion()).await;
    let id = job["id"].as_u64().expect("id");
    wait_job_state(&t, id, false, "executing", Duration::from_secs(5)).await;
    t.pause_controller();
    let started = Instant::now();
    // A synchronous request queued behind it fails too, and does not hang.
    // (Not getpos: while a job runs it answers from the live state.)
    let (s, v) = t.post("/krl/gettcp").await;
    assert!(started.elapsed() < Duration::from_secs(3), "no hang");
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("controller_offline")),
        "{v}"
    );
    let j = wait_job_state(&t, id, true, "failed", Duration::from_secs(5)).await;
    assert_eq!(j["error"]["code"], "timeout", "{j}");
    t.resume_controller();
    t.wait_connection("online").await;
    // Recovered: a round trip through the program works again (on a
    // loaded machine the KRC-like runtime may need a heartbeat or two to
    // catch up after the pause).
    t.wait_getpos("getpos to work again").await;
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn locked_command_file_reports_channel_locked_and_recovers() {
    let t = TestService::start(Options::default()).await;
    let (s, _) = t.post("/krl/getpos").await;
    assert_eq!(s, 200);
    let path = t.channel_dir().join(COMMAND_FILE);
    let before = std::fs::read_to_string(&path).expect("command");
    let holder = std::fs::File::open(&path).expect("open");
    holder.lock().expect("lock");
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300}}]))
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("channel_locked")),
        "{v}"
    );
    assert!(
        v["detail"].as_str().expect("detail").contains("locked"),
        "{v}"
    );
    let (_, st) = t.get("/api/v1/state").await;
    assert_eq!(st["connection"], "locked", "{st}");
    assert_eq!(
        std::fs::read_to_string(&path).expect("command"),
        before,
        "nothing written"
    );
    drop(holder);
    // The locked state ends when the holder lets go, before anything is sent.
    t.wait_connection("online").await;
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300}}]))
        .await;
    assert_eq!(s, 200, "{v}");
    let (_, st) = t.get("/api/v1/state").await;
    assert_eq!(st["connection"], "online", "{st}");
    t.service.shutdown().await.expect("shutdown");
}

/// A hand-written controller: heartbeats, and (with `answer`) answers each
/// command with `code`, writing a half-written result file first and the
/// complete one 300 ms later.
fn scripted_controller(
    dir: &Path,
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    answer: bool,
    code: ResultCode,
) {
    let mut seq = 0;
    let mut last_cid = 0;
    let mut results: Vec<ResultRecord> = Vec::new();
    let mut pending: Option<(Instant, i32)> = None;
    while !stop.load(std::sync::atomic::Ordering::SeqCst) {
        seq += 1;
        let state = StateFile {
            seq,
            status: ControllerStatus::Idle,
            mode: OperatingMode::Ext,
            busy_cid: 0,
            busy_index: 0,
            last_cid: if answer { last_cid } else { 0 },
            error: None,
            error_axis: 0,
            override_pct: 100.0,
            simulated: true,
            room: 0,
            stored: 0,
            position: Frame {
                x: 1.0,
                y: 2.0,
                z: 3.0,
                a: 0.0,
                b: 90.0,
                c: 0.0,
            },
            s: 2,
            t: 0,
            axes: [0.0, -90.0, 90.0, 0.0, 0.0, 0.0],
            tool: Frame::default(),
            base: Frame::default(),
            io: None,
            safety: None,
            analog: None,
        };
        let text = state.encode().expect("state");
        kuka_protocol::files::atomic_write(dir, STATE_FILE, "fake", &text).expect("write state");
        if answer && let Ok(Some(cmd)) = kuka_protocol::files::read(dir, COMMAND_FILE) {
            if let Ok(cmd) = CommandFile::decode(&cmd)
                && cmd.cid > last_cid
            {
                last_cid = cmd.cid;
                results.push(ResultRecord {
                    cid: cmd.cid,
                    code,
                    completed: 0,
                    axis: 0,
                    position: Frame {
                        x: 123.456,
                        y: -7.5,
                        z: 42.0,
                        a: 0.0,
                        b: 90.0,
                        c: 0.0,
                    },
                    s: 2,
                    t: 0,
                    axes: [0.0; 6],
                });
                let full = ResultFile {
                    results: results.clone(),
                }
                .encode()
                .expect("encode");
                // Half-written, in place (not atomic): cut in the middle of a number.
                let cut = full.len() - 20;
                let mut f = std::fs::File::create(dir.join(RESULT_FILE)).expect("create");
                f.write_all(&full.as_bytes()[..cut]).expect("write");
                pending = Some((Instant::now() + Duration::from_millis(300), cmd.cid));
            }
            if let Some((at, _)) = pending
                && Instant::now() >= at
            {
                let full = ResultFile {
                    results: results.clone(),
                }
                .encode()
                .expect("encode");
                std::fs::write(dir.join(RESULT_FILE), full).expect("write");
                pending = None;
            }
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[tokio::test]
async fn half_written_result_is_never_misparsed() {
    let root = tempfile::tempdir().expect("tempdir");
    let dir = root.path().join("channel");
    std::fs::create_dir_all(&dir).expect("dir");
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let (d, s) = (dir.clone(), stop.clone());
    let fake = std::thread::spawn(move || scripted_controller(&d, s, true, ResultCode::Ok));
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let started = Instant::now();
    let (status, v) = t.post("/krl/getpos").await;
    assert_eq!(status, 200, "{v}");
    assert!(
        started.elapsed() >= Duration::from_millis(250),
        "answered only after the complete file"
    );
    assert_eq!(v["position"], json!([123.456, -7.5, 42.0, 0.0, 90.0, 0.0]));
    stop.store(true, std::sync::atomic::Ordering::SeqCst);
    fake.join().expect("fake controller");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn command_never_picked_up_times_out_and_is_superseded() {
    let root = tempfile::tempdir().expect("tempdir");
    let dir = root.path().join("channel");
    std::fs::create_dir_all(&dir).expect("dir");
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let (d, s) = (dir.clone(), stop.clone());
    // Heartbeats, but never reads commands (a KRL program stuck elsewhere).
    let fake = std::thread::spawn(move || scripted_controller(&d, s, false, ResultCode::Ok));
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let started = Instant::now();
    let (s, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 30}}]))
        .await;
    assert_eq!((s, v["code"].as_str()), (504, Some("timeout")), "{v}");
    assert!(
        started.elapsed() < Duration::from_secs(3),
        "bounded by the ack timeout"
    );
    // The service superseded the unread command with a STOP.
    let cmd = stop_in_command_file(&dir).await;
    stop.store(true, std::sync::atomic::Ordering::SeqCst);
    fake.join().expect("fake controller");
    // A real controller that now starts never executes the timed-out motion.
    let sim = kuka_sim::SimController::start({
        let mut c = kuka_sim::SimConfig::new(&dir);
        c.time_scale = 0.0;
        c.heartbeat = Duration::from_millis(10);
        c
    })
    .expect("sim");
    t.wait_connection("online").await;
    // Until it has taken the STOP that replaced the motion: the motion can
    // no longer reach it.
    wait_for(
        WAIT,
        "the started controller to take the STOP",
        async || {
            let seen = sim.snapshot();
            if seen.last_cid >= cmd.cid && !seen.busy {
                Ok(())
            } else {
                Err(format!(
                    "last cid {} (STOP {}), busy {}",
                    seen.last_cid, cmd.cid, seen.busy
                ))
            }
        },
    )
    .await;
    assert_close(sim.snapshot().axes[0], 0.0, 1e-9, "A1 never moved");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn offline_controller_rejects_at_once() {
    let root = tempfile::tempdir().expect("tempdir");
    let t = TestService::start_without_sim(root.path()).await;
    let started = Instant::now();
    let (s, v) = t.post("/krl/ptp?x=300").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("controller_offline")),
        "{v}"
    );
    assert!(started.elapsed() < Duration::from_secs(1));
    assert!(
        !root.path().join("channel").join(COMMAND_FILE).exists(),
        "nothing written"
    );
    // Stop still leaves a STOP on the channel for a controller that comes back.
    let (s, v) = t.post("/api/v1/stop").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("controller_offline")),
        "{v}"
    );
    let cmd = std::fs::read_to_string(root.path().join("channel").join(COMMAND_FILE))
        .expect("stop written");
    assert_eq!(
        CommandFile::decode(&cmd).expect("decode").command,
        kuka_protocol::Command::Stop
    );
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn restarted_service_never_reuses_a_command_id() {
    let root = tempfile::tempdir().expect("tempdir");
    let sim = kuka_sim::SimController::start({
        let mut c = kuka_sim::SimConfig::new(root.path().join("channel"));
        c.time_scale = 0.0;
        c.heartbeat = Duration::from_millis(10);
        c
    })
    .expect("sim");
    let mut last = 0;
    for round in 0..3 {
        let t = TestService::start_without_sim(root.path()).await;
        t.wait_connection("online").await;
        for _ in 0..3 {
            let (s, v) = t
                .motions(json!([{"type": "ptp", "target": {"x": 300 + round * 10}}]))
                .await;
            assert_eq!(s, 200, "{v}");
            let cid = v["cid"].as_i64().expect("cid");
            assert!(cid > last, "round {round}: cid {cid} after {last}");
            last = cid;
        }
        t.service.shutdown().await.expect("shutdown");
    }
    // Losing the counter file is survivable: the controller's ids are the floor.
    std::fs::remove_file(root.path().join("data").join("next_cid")).expect("counter exists");
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let (s, v) = t.post("/krl/getpos").await;
    assert_eq!(s, 200, "{v}");
    let (_, j) = t.get("/api/v1/jobs?limit=1").await;
    assert!(j[0]["cid"].as_i64().expect("cid") > last, "{j}");
    assert_eq!(
        sim.snapshot().last_cid as i64,
        j[0]["cid"].as_i64().expect("cid"),
        "the controller executed it"
    );
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn second_service_on_the_same_channel_is_refused() {
    let t = TestService::start(Options::default()).await;
    let mut c = test_config(t.dirs.path());
    c.simulator.enabled = false;
    match kuka_bridge::app::start(c).await {
        Err(e) => assert!(e.to_string().contains("already serves"), "{e}"),
        Ok(_) => panic!("two services on one channel"),
    }
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn unexpected_controller_answers_are_reported() {
    for (code, http, api) in [
        (ResultCode::Busy, 409, "controller_busy"),
        (ResultCode::Other(77), 502, "protocol_error"),
        (ResultCode::Unsupported, 502, "protocol_error"),
        (ResultCode::NotReady, 409, "controller_error"),
    ] {
        let root = tempfile::tempdir().expect("tempdir");
        let dir = root.path().join("channel");
        std::fs::create_dir_all(&dir).expect("dir");
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let (d, s) = (dir.clone(), stop.clone());
        let fake = std::thread::spawn(move || scripted_controller(&d, s, true, code));
        let t = TestService::start_without_sim(root.path()).await;
        t.wait_connection("online").await;
        let (s, v) = t.post("/api/v1/home").await;
        assert_eq!((s, v["code"].as_str()), (http, Some(api)), "{code:?}: {v}");
        assert!(
            v["motion"].is_null(),
            "no motion index for a non-motion job: {v}"
        );
        stop.store(true, std::sync::atomic::Ordering::SeqCst);
        fake.join().expect("fake controller");
        t.service.shutdown().await.expect("shutdown");
    }
}

#[tokio::test]
async fn full_queue_is_refused() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| c.motion.max_queue = 2),
        ..Options::default()
    })
    .await;
    let (s, first) = t.post_json("/api/v1/motions", &slow_motion()).await;
    assert_eq!(s, 202);
    let id = first["id"].as_u64().expect("id");
    wait_job_state(&t, id, false, "executing", Duration::from_secs(5)).await;
    let mut codes = vec![(s, None)];
    for _ in 0..3 {
        let (s, v) = t.post_json("/api/v1/motions", &slow_motion()).await;
        codes.push((s, v["code"].as_str().map(str::to_string)));
    }
    // One runs, two wait, the fourth is refused.
    assert_eq!(codes[3], (503, Some("queue_full".to_string())), "{codes:?}");
    assert!(codes[..3].iter().all(|c| c.0 == 202), "{codes:?}");
    // Stop is always accepted and empties the queue.
    let (s, _) = t.post("/api/v1/stop").await;
    assert_eq!(s, 200);
    let (s, _) = t.post_json("/api/v1/motions", &slow_motion()).await;
    assert_eq!(s, 202);
    t.service.shutdown().await.expect("shutdown");
}

/// CPU seconds (user + system) a process has used so far.
#[cfg(target_os = "linux")]
fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).expect("proc stat");
    // Fields after the command name (which ends with ')'): utime is the 12th, stime the 13th.
    let rest = &stat[stat.rfind(')').expect("comm") + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f[11].parse::<f64>().expect("utime") + f[12].parse::<f64>().expect("stime");
    ticks / 100.0
}

/// Reading the channel files must not wake the readers again (inotify
/// reports reads as access events): an idle service with its simulator
/// stays idle. Runs `kuka-bridge run --simulate` as its own process so the
/// measurement sees nothing else.
#[cfg(target_os = "linux")]
#[tokio::test]
async fn idle_service_does_not_spin() {
    use kuka_bridge_tests::CliService;
    let root = tempfile::tempdir().expect("tempdir");
    let mut service = CliService::spawn(
        cli(),
        "warn",
        [
            "--simulate",
            "--time-scale",
            "0",
            "--listen",
            "127.0.0.1:0",
            "--data-dir",
            root.path().to_str().expect("a UTF-8 temporary path"),
        ],
    );
    let url = service.url().to_string();
    let http = reqwest::Client::new();
    wait_for(WAIT, "the service to answer getpos", async || {
        match http.post(format!("{url}/krl/getpos")).send().await {
            Ok(r) if r.status() == 200 => Ok(()),
            Ok(r) => Err(format!("status {}", r.status())),
            Err(e) => Err(e.to_string()),
        }
    })
    .await;
    let pid = service.pid();
    let before = cpu_seconds(pid);
    // Let time pass on purpose: the CPU the idle service uses in 2 s is
    // the measurement.
    tokio::time::sleep(Duration::from_secs(2)).await;
    let used = cpu_seconds(pid) - before;
    service.kill();
    // A 50 ms heartbeat and poll cost well under 5 %; a read loop costs a core or two.
    assert!(used < 0.4, "idle service used {used:.2} CPU seconds in 2 s");
}

/// A STOP that replaces a command the controller never read cancels that
/// job at once (it never ran), and the queue moves on.
#[tokio::test]
async fn stop_superseding_an_unread_command_cancels_it() {
    let t = std::sync::Arc::new(TestService::start(Options::default()).await);
    t.pause_controller();
    let (s, job) = t.post_json("/api/v1/motions", &slow_motion()).await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    wait_job_state(&t, id, false, "sent", Duration::from_secs(2)).await;
    let t2 = t.clone();
    let stop = tokio::spawn(async move { t2.post("/api/v1/stop").await });
    // The STOP has replaced the unread motion before the controller resumes.
    stop_in_command_file(&t.channel_dir()).await;
    t.resume_controller();
    let (s, v) = stop.await.expect("stop task");
    assert_eq!(s, 200, "{v}");
    let j = wait_job_state(&t, id, true, "cancelled", Duration::from_secs(2)).await;
    assert_eq!(j["state"], "cancelled", "{j}");
    assert_close(
        t.controller_axes()[0],
        0.0,
        1e-9,
        "the superseded motion never ran",
    );
    let started = Instant::now();
    let (s, _) = t.post("/krl/getpos").await;
    assert_eq!(s, 200);
    assert!(
        started.elapsed() < Duration::from_secs(1),
        "the queue moved on at once"
    );
}

/// A locked command file never blocks the engine: stop is answered within
/// the lock budget and everything waiting fails with channel_locked.
#[tokio::test]
async fn locked_channel_does_not_block_stop_or_the_queue() {
    let t = TestService::start(Options::default()).await;
    let (s, _) = t.post("/krl/getpos").await;
    assert_eq!(s, 200);
    let path = t.channel_dir().join(COMMAND_FILE);
    let holder = std::fs::File::open(&path).expect("open");
    holder.lock().expect("lock");
    let mut ids = Vec::new();
    for _ in 0..10 {
        let (s, v) = t.post_json("/api/v1/motions", &slow_motion()).await;
        assert_eq!(s, 202, "{v}");
        ids.push(v["id"].as_u64().expect("id"));
    }
    let started = Instant::now();
    let (s, v) = t.post("/api/v1/stop").await;
    let took = started.elapsed();
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("channel_locked")),
        "{v}"
    );
    assert!(
        took < Duration::from_secs(2),
        "stop answered in {took:?} (lock budget 300 ms)"
    );
    let (s, st) = t.get("/api/v1/state").await;
    assert_eq!((s, &st["connection"]), (200, &json!("locked")));
    for id in ids {
        let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
        assert!(
            ["cancelled", "failed"].contains(&j["state"].as_str().unwrap_or("")),
            "{j}"
        );
    }
    drop(holder);
    let (s, v) = t.post("/api/v1/stop").await;
    assert_eq!(s, 200, "{v}");
    let (s, _) = t.post("/krl/getpos").await;
    assert_eq!(s, 200);
    t.service.shutdown().await.expect("shutdown");
}

/// A controller program of protocol version 1 (the KRL program shipped
/// before motion streams) is refused with its version named: the state
/// says which program to install, and nothing is sent to it.
#[tokio::test]
async fn a_version_1_controller_is_named_and_refused() {
    let root = tempfile::tempdir().expect("tmp");
    let t = TestService::start_without_sim(root.path()).await;
    let v1_state = "STA 1 294 0 4 0 0 22 0 0 100.000 1 31308\n\
        POS 355.000 0.000 625.000 0.000 90.000 0.000 2 2 49280\n\
        AXS 0.000 -90.000 90.000 0.000 0.000 0.000 63442\n\
        TOL 0.000 0.000 0.000 0.000 0.000 0.000 0\n\
        BAS 0.000 0.000 0.000 0.000 0.000 0.000 0\n\
        END 294 294\n";
    let dir = root.path().join("channel");
    std::fs::create_dir_all(&dir).expect("channel folder");
    std::fs::write(dir.join(STATE_FILE), v1_state).expect("state");
    let st = t
        .wait_state("the version to be named", |st| {
            st["degraded"].as_array().is_some_and(|d| {
                d.iter().any(|e| {
                    e["code"] == "protocol_error"
                        && e["detail"]
                            .as_str()
                            .is_some_and(|s| s.contains("protocol version 1"))
                })
            })
        })
        .await;
    assert_eq!(st["connection"], "offline", "{st}");
    let (s, v) = t.post("/krl/getpos").await;
    assert_eq!(s, 503, "{v}");
    assert!(
        !dir.join(COMMAND_FILE).exists(),
        "nothing was written for a version 1 controller"
    );
}

/// `controller.safety` of `GET /api/v1/state`.
/// Presses (`true`) or releases the simulated emergency stop.
async fn press_emergency_stop(t: &TestService, pressed: bool) {
    let (st, v) = t
        .put_json("/api/v1/sim/safety", &json!({"emergency_stop": pressed}))
        .await;
    assert_eq!(st, 204, "{v}");
}

async fn safety(t: &TestService) -> Value {
    let (_, s) = t.get("/api/v1/state").await;
    s["controller"]["safety"].clone()
}

/// A client that releases the emergency stop, acknowledges and resets at
/// once, without waiting for a state file in between, gets its reset: the
/// last state file read before the reset's result was written before it
/// and still shows the button pressed, so the service waits for one
/// written after it instead of refusing the reset on stale news (a KRL
/// program writes its state a pass after the result). Three rounds, the
/// window is a matter of milliseconds.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_reset_right_after_release_and_acknowledge_is_taken() {
    let t = TestService::start(Options::default()).await;
    t.wait_online().await;
    for round in 0..3 {
        press_emergency_stop(&t, true).await;
        t.wait_state("the emergency stop in the state", |s| {
            s["controller"]["safety"]["emergency_stop"] == true
        })
        .await;
        press_emergency_stop(&t, false).await;
        let (st, v) = t.post("/api/v1/sim/acknowledge").await;
        assert_eq!(st, 204, "{v}");
        let (st, v) = t.post("/api/v1/reset").await;
        assert_eq!(
            (st, &v["state"]),
            (200, &json!("done")),
            "round {round}: {v}"
        );
        let (st, v) = t
            .motions(json!([{"type": "ptp_axes", "axes": {"a1": round * 2 + 1}}]))
            .await;
        assert_eq!(
            (st, &v["state"]),
            (200, &json!("done")),
            "round {round}: {v}"
        );
    }
    // Still refused while the button is really pressed.
    press_emergency_stop(&t, true).await;
    t.wait_state("pressed again", |s| {
        s["controller"]["safety"]["emergency_stop"] == true
    })
    .await;
    let (st, v) = t.post("/api/v1/reset").await;
    assert_eq!(
        (st, v["code"].as_str()),
        (409, Some("controller_error")),
        "{v}"
    );
    t.service.shutdown().await.expect("shutdown");
}

/// A safety stop on the simulated cell (`PUT /api/v1/sim/safety`), as on a
/// KRC: an emergency stop pressed during a motion stops the robot on its
/// path and switches the drives off; the job fails `controller_error`
/// saying why; nothing moves and the acknowledgement is refused while the
/// button is pressed; released, acknowledged and reset, the robot moves
/// again. An operator safety opened while idle makes the controller not
/// ready until it is closed and acknowledged (no RESET needed).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_emergency_stop_stops_the_robot_until_released_and_acknowledged() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    t.wait_online().await;
    let (s, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 0, "a2": -80, "a3": 80, "a4": 0, "a5": 30, "a6": 0}}]))
        .await;
    assert_eq!((s, &v["state"]), (200, &json!("done")), "{v}");
    let from = t.controller_axes();
    // A slow axis motion (several seconds), not waited for.
    let (s, job) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 90}, "velocity_pct": 5}], "wait": false}),
        )
        .await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    wait_for(WAIT, "the robot moving", async || {
        let a1 = t.controller_axes()[0];
        if a1 > from[0] + 2.0 {
            Ok(a1)
        } else {
            Err(format!("A1 = {a1}"))
        }
    })
    .await;
    press_emergency_stop(&t, true).await;
    let job = t
        .wait_job(id, "the job ended by the emergency stop", |j| {
            j["state"] == "failed"
        })
        .await;
    assert_eq!(job["error"]["code"], "controller_error", "{job}");
    // The robot stands where it was stopped, short of its target.
    let stopped = t.controller_axes()[0];
    assert!(stopped > from[0] + 2.0 && stopped < 89.0, "A1 = {stopped}");
    let s = t
        .wait_state("the emergency stop in the state", |s| {
            s["controller"]["safety"]["emergency_stop"] == true
                && s["controller"]["safety"]["drives_ready"] == false
                && s["controller"]["status"] == "error"
        })
        .await;
    assert_eq!(s["controller"]["safety"]["stop_message"], true, "{s}");
    // Nothing moves: refused, with the reason.
    let (st, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 0}}]))
        .await;
    assert_eq!(
        (st, v["code"].as_str()),
        (409, Some("controller_error")),
        "{v}"
    );
    // (The simulator's teach pendant is its API: the detail says where.)
    assert!(
        v["detail"]
            .as_str()
            .is_some_and(|d| d.contains("emergency stop is pressed")
                && d.contains("POST /api/v1/sim/acknowledge")),
        "{v}"
    );
    assert_close(t.controller_axes()[0], stopped, 0.001, "A1 while stopped");
    // No path opens while the controller is in its error state.
    let (st, v) = t.post("/api/v1/paths").await;
    assert_eq!(
        (st, v["code"].as_str()),
        (409, Some("controller_error")),
        "{v}"
    );
    // The operator cannot acknowledge while the button is pressed.
    let (st, v) = t.post("/api/v1/sim/acknowledge").await;
    assert_eq!(
        (st, v["code"].as_str()),
        (409, Some("controller_error")),
        "{v}"
    );
    press_emergency_stop(&t, false).await;
    let s = t
        .wait_state("the emergency stop released", |s| {
            s["controller"]["safety"]["emergency_stop"] == false
        })
        .await;
    assert_eq!(
        s["controller"]["safety"]["drives_ready"], false,
        "released, the drives stay off until acknowledged: {s}"
    );
    let (st, v) = t.post("/api/v1/sim/acknowledge").await;
    assert_eq!(st, 204, "{v}");
    // Acknowledged: no stop message, drives on; the job the stop ended
    // leaves the error state RESET clears.
    t.wait_state("acknowledged, waiting for RESET", |s| {
        s["controller"]["safety"]["stop_message"] == false
            && s["controller"]["safety"]["drives_ready"] == true
            && s["controller"]["status"] == "error"
    })
    .await;
    let (st, v) = t.post("/api/v1/reset").await;
    assert_eq!(st, 200, "{v}");
    // Ready as soon as the reset is answered: the state says so and a
    // path opens at once (not only once the next state file is read).
    let (_, s) = t.get("/api/v1/state").await;
    assert_eq!(s["controller"]["status"], "idle", "{s}");
    let (st, v) = t.post("/api/v1/paths").await;
    assert_eq!(st, 201, "{v}");
    let id = v["id"].as_u64().expect("path id");
    let (st, v) = t.delete(&format!("/api/v1/paths/{id}")).await;
    assert!(st == 200 || st == 204, "{st} {v}");
    t.wait_state("ready again", |s| {
        s["controller"]["status"] == "idle"
            && s["controller"]["safety"]["drives_ready"] == true
            && s["controller"]["safety"]["stop_message"] == false
    })
    .await;
    let (st, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 5}}]))
        .await;
    assert_eq!((st, &v["state"]), (200, &json!("done")), "{v}");
    assert_close(t.controller_axes()[0], 5.0, 0.01, "A1 after the restart");

    // The operator safety opened while idle: not ready until closed and
    // acknowledged.
    let (st, v) = t
        .put_json("/api/v1/sim/safety", &json!({"user_safety": false}))
        .await;
    assert_eq!(st, 204, "{v}");
    t.wait_state("the operator safety open", |s| {
        s["controller"]["safety"]["user_safety"] == false && s["controller"]["status"] == "error"
    })
    .await;
    let (st, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 0}}]))
        .await;
    assert_eq!(
        (st, v["code"].as_str()),
        (409, Some("controller_error")),
        "{v}"
    );
    let (st, v) = t.post("/api/v1/sim/acknowledge").await;
    assert_eq!(
        (st, v["code"].as_str()),
        (409, Some("controller_error")),
        "{v}"
    );
    // Nor can a reset clear the error: it says why and what clears it.
    let (st, v) = t.post("/api/v1/reset").await;
    assert_eq!(
        (st, v["code"].as_str()),
        (409, Some("controller_error")),
        "{v}"
    );
    assert!(
        v["detail"].as_str().is_some_and(|d| d.contains("reset")
            && d.contains("operator safety")
            && d.contains("release it")),
        "{v}"
    );
    let (st, v) = t
        .put_json("/api/v1/sim/safety", &json!({"user_safety": true}))
        .await;
    assert_eq!(st, 204, "{v}");
    let (st, v) = t.post("/api/v1/sim/acknowledge").await;
    assert_eq!(st, 204, "{v}");
    t.wait_state("ready without RESET", |s| {
        s["controller"]["status"] == "idle" && s["controller"]["safety"]["drives_ready"] == true
    })
    .await;
    let (st, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 0}}]))
        .await;
    assert_eq!((st, &v["state"]), (200, &json!("done")), "{v}");
    assert!(
        safety(&t).await["emergency_stop"] == false,
        "{}",
        safety(&t).await
    );

    // Bodies that change nothing or are not the documented shape.
    for bad in [
        json!({}),
        json!({"emergency_stop": "yes"}),
        json!({"emergency_stop": 1}),
        json!({"e_stop": true}),
        json!({"user_safety": null, "emergency_stop": null}),
        json!(true),
        json!("emergency_stop"),
    ] {
        let (st, v) = t.put_json("/api/v1/sim/safety", &bad).await;
        assert_eq!(
            (st, v["code"].as_str()),
            (422, Some("invalid_input")),
            "{bad}: {v}"
        );
    }
    assert_eq!(safety(&t).await["drives_ready"], true);
    t.service.shutdown().await.expect("shutdown");
}

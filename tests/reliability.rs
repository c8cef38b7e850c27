//! What a client or the controller side sends must never take the bridge
//! down or silence Stop (issue 17): foreign and poisoned command ids in the
//! controller's files, a controller restarted in the middle of a batch, a
//! result file locked past the job's timeout, job ids across a service
//! restart, folders that cannot be written, junk files, a shutdown during
//! a motion, duplicate query tokens. Real files; the controller is a
//! separate simulator process where the fault is on its side.

use std::path::Path;
use std::time::{Duration, Instant};

use kuka_bridge_tests::{Options, SimProcess, TestService, initial_admin_secret};
use kuka_protocol::{
    RESULT_FILE, ResultCode, ResultFile, ResultRecord, STATE_FILE, StateFile, files,
};
use serde_json::{Value, json};

fn cli() -> &'static str {
    env!("CARGO_BIN_EXE_kuka-bridge-cli")
}

/// A motion that takes about a second at 100 % override.
fn slow_motion(a1: f64) -> Value {
    json!({"type": "ptp_axes", "axes": {"a1": a1}, "velocity_pct": 5})
}

/// Sends slow axis PTPs to these A1 values as one batch without waiting;
/// the job's id.
async fn start_slow_batch(t: &TestService, a1: &[f64]) -> u64 {
    let batch: Vec<Value> = a1.iter().map(|a| slow_motion(*a)).collect();
    let (s, job) = t
        .post_json("/api/v1/motions", &json!({"motions": batch, "wait": false}))
        .await;
    assert_eq!(s, 202, "{job}");
    job["id"].as_u64().expect("id")
}

fn terminal(j: &Value) -> bool {
    ["done", "failed", "cancelled"].contains(&j["state"].as_str().unwrap_or(""))
}

fn degraded_with(h: &Value, code: &str) -> bool {
    h["status"] == "degraded"
        && h["degraded"]
            .as_array()
            .is_some_and(|a| a.iter().any(|d| d["code"] == code))
}

/// A result line as a foreign writer would put it into the file.
fn foreign_result(cid: i32) -> ResultRecord {
    ResultRecord {
        cid,
        code: ResultCode::Ok,
        completed: 0,
        axis: 0,
        position: kuka_protocol::Frame::default(),
        s: 2,
        t: 0,
        axes: [0.0; 6],
    }
}

/// Adds `extra` to the result file in `dir` (atomically, as a controller writes it).
fn append_result(dir: &Path, extra: ResultRecord) {
    let mut results = files::read(dir, RESULT_FILE)
        .ok()
        .flatten()
        .and_then(|t| ResultFile::decode(&t).ok())
        .map(|r| r.results)
        .unwrap_or_default();
    results.push(extra);
    let text = ResultFile { results }.encode().expect("encode");
    files::atomic_write_bytes(dir, RESULT_FILE, "test", text.as_bytes()).expect("write");
}

async fn motion_and_stop_work(t: &TestService, what: &str) {
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300}}]))
        .await;
    assert_eq!(s, 200, "{what}: a motion works: {v}");
    let (s, v) = t.post("/api/v1/stop").await;
    assert_eq!(s, 200, "{what}: stop works: {v}");
}

/// A result line with the largest command id (or any id the service never
/// sent) is reported and ignored: commands and Stop go on, across a
/// restart of the service and of the controller; a state file that says
/// the controller accepted the largest id makes the ids wrap, not run out.
#[tokio::test]
async fn poisoned_command_ids_never_block_commands_or_stop() {
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    let mut sim = SimProcess::spawn(cli(), &channel, 0.0);
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    motion_and_stop_work(&t, "before").await;

    append_result(&channel, foreign_result(i32::MAX));
    // The line is read and reported; the next command is not hurt.
    let mut events = t
        .http
        .get(t.url("/api/v1/events"))
        .send()
        .await
        .expect("events");
    append_result(&channel, foreign_result(i32::MAX - 7));
    // The alarm of the first line may come on this stream too: wait for the second.
    let deadline = Instant::now() + Duration::from_secs(5);
    let mut seen = String::new();
    while !seen.contains("2147483640") && Instant::now() < deadline {
        match tokio::time::timeout(Duration::from_secs(1), events.chunk()).await {
            Ok(Ok(Some(chunk))) => seen.push_str(&String::from_utf8_lossy(&chunk)),
            _ => continue,
        }
    }
    assert!(seen.contains("2147483640"), "alarm names the foreign id");
    drop(events);
    motion_and_stop_work(&t, "after a foreign result line").await;
    let (_, h) = t.get("/health").await;
    assert_eq!(h["status"], "ok", "{h}");

    // A restarted service (same data folder) reads the line as old.
    t.service.shutdown().await.expect("shutdown");
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    motion_and_stop_work(&t, "after a service restart").await;

    // The controller restarts with the largest id in both of its files
    // (it recovers last_cid from them): ids wrap past it. The last command
    // file goes too (PROTOCOL.md §8: with its history gone, a controller
    // would take the stale command for a new one).
    sim.kill();
    std::fs::remove_file(channel.join(kuka_protocol::COMMAND_FILE)).expect("remove command");
    let only_max = ResultFile {
        results: vec![foreign_result(i32::MAX)],
    };
    let text = only_max.encode().expect("encode");
    files::atomic_write_bytes(&channel, RESULT_FILE, "test", text.as_bytes()).expect("write");
    let state = files::read(&channel, STATE_FILE)
        .expect("read")
        .expect("state file");
    let mut state = StateFile::decode(&state).expect("decode");
    state.last_cid = i32::MAX;
    let text = state.encode().expect("encode");
    files::atomic_write_bytes(&channel, STATE_FILE, "test", text.as_bytes()).expect("write");
    let _sim = SimProcess::spawn(cli(), &channel, 0.0);
    t.wait_state(
        "the restarted controller online with last_cid 2147483647",
        |st| st["controller"]["last_cid"] == i32::MAX && st["connection"] == "online",
    )
    .await;
    motion_and_stop_work(&t, "after the controller accepted the largest id").await;
    // The state file follows the result: wait for it.
    t.wait_state("the ids to wrap (last_cid below 2^30)", |st| {
        st["controller"]["last_cid"]
            .as_i64()
            .is_some_and(|last| last < 1 << 30)
    })
    .await;
    t.service.shutdown().await.expect("shutdown");
}

/// A result for a higher, foreign command id written while a job runs does
/// not hide the job's own result.
#[tokio::test]
async fn a_foreign_result_during_a_job_does_not_hide_its_own() {
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    let _sim = SimProcess::spawn(cli(), &channel, 1.0);
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let (s, job) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [slow_motion(30.0)], "wait": false}),
        )
        .await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    let j = t
        .wait_job(id, "the job", |j| j["state"] == "executing")
        .await;
    let cid = j["cid"].as_i64().expect("cid") as i32;
    append_result(&channel, foreign_result(cid + 1000));
    let j = t.wait_job(id, "the job", terminal).await;
    assert_eq!(j["state"], "done", "{j}");
    assert!(j.get("late_result").is_none(), "{j}");
    t.service.shutdown().await.expect("shutdown");
}

/// The controller is killed in the middle of a 4-motion batch and started
/// again at once: the job ends at once with how far it got, and the next
/// job runs (before: `executing` until its timeout, new jobs refused).
#[tokio::test]
async fn a_controller_restarted_mid_batch_resolves_the_job_at_once() {
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    let mut sim = SimProcess::spawn(cli(), &channel, 1.0);
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let id = start_slow_batch(&t, &[20.0, 0.0, 20.0, 0.0]).await;
    let j = t
        .wait_job(id, "the job", |j| {
            j["completed"].as_u64() >= Some(2) || terminal(j)
        })
        .await;
    assert_eq!(j["state"], "executing", "{j}");
    let completed = j["completed"].as_u64().expect("completed");
    sim.kill();
    let restarted = Instant::now();
    let _sim = SimProcess::spawn(cli(), &channel, 1.0);
    let j = t.wait_job(id, "the job", terminal).await;
    let took = restarted.elapsed();
    assert_eq!(j["state"], "failed", "{j}");
    assert_eq!(j["error"]["code"], "command_lost", "{j}");
    // The controller may have begun the next motion between the last poll
    // and the kill.
    let done = j["completed"].as_u64().expect("completed");
    assert!((completed..4).contains(&done), "{completed} then {j}");
    let detail = j["error"]["detail"].as_str().expect("detail");
    assert!(detail.contains(&format!("{done} of 4")), "{detail}");
    assert!(took < Duration::from_secs(3), "resolved in {took:?}");
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300}}]))
        .await;
    assert_eq!(s, 200, "the next job runs: {v}");
    t.service.shutdown().await.expect("shutdown");
}

/// The KRL program in the KRC-like runtime is killed in the middle of a path
/// (a batch of 8 motions) and started again at once, as after a reboot:
/// its Submit start ends the path (PROTOCOL.md §5.5 rule 9) and rewrites
/// its result file before the service sees it idle. The job ends at once
/// with `command_lost`, and the next job runs (before: `executing` for
/// good, because the result file was compared from the moment the
/// controller looked idle, after its rewrite).
#[tokio::test]
async fn the_krl_program_rebooted_mid_path_resolves_the_job_at_once() {
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    let mut sim = SimProcess::spawn_kind(cli(), &channel, 1.0, "krc");
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let id = start_slow_batch(&t, &[10.0, 0.0, 10.0, 0.0, 10.0, 0.0, 10.0, 0.0]).await;
    let j = t
        .wait_job(id, "the path running", |j| {
            j["completed"].as_u64() >= Some(1) || terminal(j)
        })
        .await;
    assert_eq!(j["state"], "executing", "{j}");
    sim.kill();
    let restarted = Instant::now();
    let _sim = SimProcess::spawn_kind(cli(), &channel, 1.0, "krc");
    let j = t.wait_job(id, "the job", terminal).await;
    let took = restarted.elapsed();
    assert_eq!(j["state"], "failed", "{j}");
    assert_eq!(j["error"]["code"], "command_lost", "{j}");
    assert!(took < Duration::from_secs(5), "resolved in {took:?}");
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300}}]))
        .await;
    assert_eq!(s, 200, "the next job runs: {v}");
    t.service.shutdown().await.expect("shutdown");
}

/// The controller cannot write its result (the file is locked) until after
/// the job's timeout: the job first fails with `timeout`, then takes the
/// controller's late OK (`late_result`), instead of staying failed although
/// the robot reached the target.
#[tokio::test]
async fn a_late_result_turns_a_timed_out_job_into_done() {
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    let _sim = SimProcess::spawn(cli(), &channel, 1.0);
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let (s, _) = t.post("/krl/getpos").await;
    assert_eq!(s, 200);
    let holder = std::fs::File::open(channel.join(RESULT_FILE)).expect("open");
    holder.lock().expect("lock");
    let (s, job) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [slow_motion(15.0)], "wait": false, "timeout_ms": 2500}),
        )
        .await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    let j = t.wait_job(id, "the job", terminal).await;
    assert_eq!(
        (j["state"].as_str(), j["error"]["code"].as_str()),
        (Some("failed"), Some("timeout")),
        "{j}"
    );
    // The robot stands at the target meanwhile.
    let (_, st) = t.get("/api/v1/state").await;
    assert!(
        (st["axes"]["a1"].as_f64().expect("a1") - 15.0).abs() < 0.01,
        "{st}"
    );
    drop(holder);
    let j = t.wait_job(id, "the job", |j| j["state"] == "done").await;
    assert_eq!(j["state"], "done", "{j}");
    assert_eq!(j["late_result"], true, "{j}");
    assert!(j["error"].is_null(), "{j}");
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300}}]))
        .await;
    assert_eq!(s, 200, "{v}");
    t.service.shutdown().await.expect("shutdown");
}

/// Job ids go on after a restart of the service: a client polling a
/// `wait: false` job across the restart learns with 410 that its job (the
/// one running, or one still queued) belonged to the earlier run, never
/// another job's outcome; an id never issued is 404.
#[tokio::test]
async fn job_ids_are_unique_across_service_restarts() {
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    let _sim = SimProcess::spawn(cli(), &channel, 1.0);
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let mut ids = Vec::new();
    for a1 in [10.0, 0.0] {
        let (s, job) = t
            .post_json(
                "/api/v1/motions",
                &json!({"motions": [slow_motion(a1)], "wait": false}),
            )
            .await;
        assert_eq!(s, 202, "{job}");
        ids.push(job["id"].as_u64().expect("id"));
    }
    let (_, queued) = t.get(&format!("/api/v1/jobs/{}", ids[1])).await;
    assert_eq!(queued["state"], "queued", "{queued}");
    // The running motion ends during the drain; the queued one never runs.
    t.service.shutdown().await.expect("shutdown");

    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    for id in &ids {
        let (s, v) = t.get(&format!("/api/v1/jobs/{id}")).await;
        assert_eq!((s, v["code"].as_str()), (410, Some("gone")), "{v}");
        assert!(
            v["detail"]
                .as_str()
                .expect("detail")
                .contains("earlier run"),
            "{v}"
        );
    }
    let (s, job) = t
        .motions(json!([{"type": "ptp", "target": {"x": 310}}]))
        .await;
    assert_eq!(s, 200, "{job}");
    let newest = job["id"].as_u64().expect("id");
    assert!(newest > ids[1], "{newest} after {ids:?}");
    for id in [0, newest + 10_000] {
        let (s, v) = t.get(&format!("/api/v1/jobs/{id}")).await;
        assert_eq!((s, v["code"].as_str()), (404, Some("not_found")), "{v}");
    }
    t.service.shutdown().await.expect("shutdown");
}

/// `/health` and `/api/v1/state` say `degraded`, with a code and the
/// reason, while commands cannot be sent, and `ok` again after.
#[tokio::test]
async fn health_says_degraded_while_commands_cannot_be_sent() {
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    let _sim = SimProcess::spawn(cli(), &channel, 0.0);
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let (_, h) = t.get("/health").await;
    assert_eq!(h["status"], "ok", "{h}");
    assert_eq!(h["degraded"], json!([]), "{h}");

    // The data folder's command id counter cannot be replaced.
    let counter = t.config.data_dir.join("next_cid");
    let _ = std::fs::remove_file(&counter);
    std::fs::create_dir(&counter).expect("block the counter");
    std::fs::write(counter.join("x"), b"x").expect("non-empty");
    let h = t
        .wait_health("the health", |h| degraded_with(h, "storage_unavailable"))
        .await;
    assert!(degraded_with(&h, "storage_unavailable"), "{h}");
    let (_, st) = t.get("/api/v1/state").await;
    assert!(
        st["degraded"]
            .as_array()
            .is_some_and(|a| a.iter().any(|d| d["code"] == "storage_unavailable")),
        "{st}"
    );
    let (s, v) = t.post("/api/v1/stop").await;
    assert_eq!(s, 200, "stop does not need the counter file: {v}");
    std::fs::remove_dir_all(&counter).expect("unblock");
    let h = t.wait_health("the health", |h| h["status"] == "ok").await;
    assert_eq!(h["status"], "ok", "{h}");

    // A junk result file far over any protocol file's size.
    let junk = vec![b'x'; 4 << 20];
    files::atomic_write_bytes(&channel, RESULT_FILE, "test", &junk).expect("junk");
    let h = t
        .wait_health("the health", |h| degraded_with(h, "protocol_error"))
        .await;
    assert!(degraded_with(&h, "protocol_error"), "{h}");
    // The controller's next result replaces it.
    let (s, v) = t.post("/krl/getpos").await;
    assert_eq!(s, 200, "{v}");
    let h = t.wait_health("the health", |h| h["status"] == "ok").await;
    assert_eq!(h["status"], "ok", "{h}");

    // The channel folder cannot take the atomic writes' temporary files.
    let tmp = channel.join(files::TEMP_DIR);
    let aside = channel.join("kb-tmp-aside");
    std::fs::rename(&tmp, &aside).expect("move aside");
    std::fs::write(&tmp, b"not a folder").expect("block");
    let h = t
        .wait_health("the health", |h| degraded_with(h, "storage_unavailable"))
        .await;
    assert!(degraded_with(&h, "storage_unavailable"), "{h}");
    // The simulator writes through the same folder: it is offline too.
    let h = t
        .wait_health("the health", |h| degraded_with(h, "controller_offline"))
        .await;
    assert!(degraded_with(&h, "controller_offline"), "{h}");
    let (s, v) = t.post("/api/v1/stop").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("storage_unavailable")),
        "a stop that cannot be written says so: {v}"
    );
    std::fs::remove_file(&tmp).expect("unblock");
    let h = t.wait_health("the health", |h| h["status"] == "ok").await;
    assert_eq!(h["status"], "ok", "{h}");
    let (s, _) = t.post("/krl/getpos").await;
    assert_eq!(s, 200);
    t.service.shutdown().await.expect("shutdown");
}

/// Two `access_token` parameters are refused like two `Authorization`
/// headers; one is accepted.
#[tokio::test]
async fn duplicate_query_tokens_are_refused() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.auth.require_on_loopback = true;
            c.auth.query_token = true;
        }),
        ..Options::default()
    })
    .await;
    let secret = initial_admin_secret(&t.config.data_dir);
    let (s, v) = t
        .post(&format!(
            "/krl/getpos?access_token={secret}&access_token=kb_other"
        ))
        .await;
    assert_eq!(s, 401, "{v}");
    assert!(v.to_string().contains("not several"), "{v}");
    let (s, v) = t
        .post(&format!(
            "/krl/getpos?access_token={secret}&access_token={secret}"
        ))
        .await;
    assert_eq!(s, 401, "even the same secret twice: {v}");
    let (s, v) = t.post(&format!("/krl/getpos?access_token={secret}")).await;
    assert_eq!(s, 200, "{v}");
    // A header and a query token: refused too, whichever is valid.
    let r = t
        .http
        .post(t.url("/krl/getpos?access_token=kb_other"))
        .bearer_auth(&secret)
        .send()
        .await
        .expect("request");
    let (s, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(s, 401, "header and query token: {v}");
    t.service.shutdown().await.expect("shutdown");
}

/// SIGTERM while a motion runs: the service drains. New jobs are refused
/// with 503 `shutting_down`, reads and Stop are still served, and it exits
/// once the motion has ended.
#[cfg(unix)]
#[tokio::test]
async fn sigterm_keeps_stop_working_until_the_motion_has_ended() {
    use kuka_bridge_tests::{CliService, WAIT, wait_for};
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    let data = root.path().join("data");
    let _sim = SimProcess::spawn(cli(), &channel, 1.0);
    let mut service = CliService::spawn(
        cli(),
        "warn",
        [
            "--listen",
            "127.0.0.1:0",
            "--channel-dir",
            channel.to_str().expect("a UTF-8 temporary path"),
            "--data-dir",
            data.to_str().expect("a UTF-8 temporary path"),
        ],
    );
    let url = service.url().to_string();
    assert!(url.starts_with("http://"), "{}", service.console());
    let http = reqwest::Client::new();
    let post = |path: &str, body: Value| {
        let req = http.post(format!("{url}{path}")).json(&body);
        async move {
            let r = req.send().await.expect("request");
            kuka_bridge_tests::decode(r).await
        }
    };
    let get = |path: String| {
        let req = http.get(format!("{url}{path}"));
        async move {
            let r = req.send().await.expect("request");
            kuka_bridge_tests::decode(r).await.1
        }
    };
    // Online first.
    wait_for(WAIT, "the controller online", async || {
        let h = get("/health".into()).await;
        if h["connection"] == "online" {
            Ok(())
        } else {
            Err(h.to_string())
        }
    })
    .await;
    let (s, job) = post(
        "/api/v1/motions",
        json!({"motions": [slow_motion(60.0)], "wait": false}),
    )
    .await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    wait_for(WAIT, "the motion executing", async || {
        let j = get(format!("/api/v1/jobs/{id}")).await;
        if j["state"] == "executing" {
            Ok(())
        } else {
            Err(j.to_string())
        }
    })
    .await;
    service.terminate();
    // Draining: a new job is refused, the health says why.
    // Until the signal arrives a job queues behind the motion (and is
    // cancelled when the drain starts).
    let refused = wait_for(WAIT, "a new job refused while draining", async || {
        let (s, v) = post(
            "/api/v1/motions",
            json!({"motions": [{"type": "ptp", "target": {"x": 300}}], "wait": false}),
        )
        .await;
        if s == 503 {
            Ok(v)
        } else {
            Err(format!("{s} {v}"))
        }
    })
    .await;
    assert_eq!(refused["code"].as_str(), Some("shutting_down"), "{refused}");
    let h: Value = http
        .get(format!("{url}/health"))
        .send()
        .await
        .expect("health")
        .json()
        .await
        .expect("json");
    assert!(degraded_with(&h, "shutting_down"), "{h}");
    // Stop still gets through and ends the motion.
    let r = http
        .post(format!("{url}/api/v1/stop"))
        .send()
        .await
        .expect("stop");
    let (s, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(s, 200, "stop during the drain: {v}");
    let code = service.wait_exit(Duration::from_secs(20), "after the stop");
    assert!(code.success(), "clean exit: {code:?}");
}

/// A state file the controller wrote before it accepted the session's
/// first command (`last_cid` 0), read only after that command's result,
/// does not set the position back to where the robot was before it: the
/// next motion would be planned from there (a CI run once planned a
/// blended LIN from the home pose after a PTP had answered done). The
/// test is the controller here, so the order of the two files is certain.
#[tokio::test]
async fn a_state_file_older_than_the_first_result_does_not_set_the_position_back() {
    use std::sync::{Arc, Mutex};
    let root = tempfile::tempdir().expect("tempdir");
    let channel = root.path().join("channel");
    std::fs::create_dir_all(&channel).expect("channel");
    let home = StateFile {
        seq: 1,
        status: kuka_protocol::ControllerStatus::Idle,
        mode: kuka_protocol::OperatingMode::T1,
        busy_cid: 0,
        busy_index: 0,
        last_cid: 0,
        error: None,
        error_axis: 0,
        override_pct: 100.0,
        simulated: true,
        room: 0,
        stored: 0,
        position: kuka_protocol::Frame::from_array([355.0, 0.0, 625.0, 0.0, 90.0, 0.0]),
        s: 2,
        t: 0,
        axes: [0.0, -90.0, 90.0, 0.0, 0.0, 0.0],
        tool: kuka_protocol::Frame::default(),
        base: kuka_protocol::Frame::default(),
        io: None,
        safety: None,
        analog: None,
    };
    // A heartbeat every 20 ms with the home state while `beat` holds true.
    let state = Arc::new(Mutex::new((home, true)));
    let heart = {
        let (state, channel) = (state.clone(), channel.clone());
        tokio::spawn(async move {
            loop {
                let text = {
                    let mut g = state.lock().expect("state");
                    if g.1 {
                        g.0.seq += 1;
                        Some(g.0.encode().expect("encode"))
                    } else {
                        None
                    }
                };
                if let Some(text) = text {
                    files::atomic_write_bytes(&channel, STATE_FILE, "test", text.as_bytes())
                        .expect("write state");
                }
                tokio::time::sleep(Duration::from_millis(20)).await;
            }
        })
    };
    let t = TestService::start_without_sim(root.path()).await;
    t.wait_connection("online").await;
    let target = [300.0, 50.0, 200.0, 0.0, 180.0, 0.0];
    let (s, job) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp", "target": {"x": target[0], "y": target[1], "z": target[2], "a": 0, "b": 180, "c": 0}}], "wait": false}),
        )
        .await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    let j = t
        .wait_job(id, "the PTP to be written", |j| j["cid"].as_i64().is_some())
        .await;
    let cid = i32::try_from(j["cid"].as_i64().expect("cid")).expect("cid fits");
    // The heartbeat stops; the controller answers the PTP.
    state.lock().expect("state").1 = false;
    let seq = state.lock().expect("state").0.seq;
    append_result(
        &channel,
        ResultRecord {
            cid,
            code: ResultCode::Ok,
            completed: 1,
            axis: 0,
            position: kuka_protocol::Frame::from_array(target),
            s: 6,
            t: 0,
            axes: [9.5, -60.0, 100.0, 0.0, 50.0, 9.5],
        },
    );
    let j = t.wait_job(id, "the PTP to end", terminal).await;
    assert_eq!(j["state"], "done", "{j}");
    // Then a state file the controller had written before it accepted the
    // PTP (last_cid 0, home pose) is read: a new number, old content.
    let stale = StateFile {
        seq: seq + 1,
        ..state.lock().expect("state").0
    };
    let text = stale.encode().expect("encode");
    files::atomic_write_bytes(&channel, STATE_FILE, "test", text.as_bytes()).expect("write");
    let st = t
        .wait_state("the stale state file read", |st| {
            st["controller"]["heartbeat_seq"].as_i64() == Some(i64::from(seq + 1))
        })
        .await;
    let p = &st["position"];
    assert_eq!(
        (p["x"].as_f64(), p["y"].as_f64(), p["z"].as_f64()),
        (Some(target[0]), Some(target[1]), Some(target[2])),
        "the position stays where the PTP's result put it: {st}"
    );
    heart.abort();
    t.service.shutdown().await.expect("shutdown");
}

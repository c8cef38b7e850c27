//! The versioned JSON API: state, motions and batches, jobs, stop, frames,
//! speeds, events and every validation error — over HTTP against the
//! running service with the simulated controller over real files.

use std::time::Duration;

use futures_util::StreamExt;
use kuka_bridge::config::WorkspaceBox;
use kuka_bridge_tests::{Options, TestService, assert_close};
use serde_json::{Value, json};

fn pen_down() -> Value {
    json!({"type": "ptp", "target": {"x": 200, "y": 0, "z": 70, "a": 0, "b": 180, "c": 0}})
}

#[tokio::test]
async fn state_health_and_docs() {
    let t = TestService::start(Options::default()).await;
    let (s, v) = t.get("/health").await;
    assert_eq!(s, 200);
    assert_eq!(v["status"], "ok");
    assert_eq!(v["simulated"], true);
    let (s, v) = t.get("/api/v1/state").await;
    assert_eq!(s, 200);
    assert_eq!(v["connection"], "online");
    assert_eq!(v["controller"]["status"], "idle");
    // Both simulated controllers say so in the state file (the shipped KRL
    // program reports kb_simulated, which the KRC-like runtime sets).
    assert_eq!(v["controller"]["simulated"], true, "{v}");
    assert_eq!(v["model"], "kr3_r540");
    assert_eq!(v["position"]["s"], 2, "home Status: elbow bit set");
    assert_close(
        v["axes"]["a2"].as_f64().expect("a2"),
        -90.0,
        1e-6,
        "home A2",
    );
    let (s, v) = t.get("/openapi.json").await;
    assert_eq!(s, 200);
    assert!(v["openapi"].as_str().expect("version").starts_with("3.1"));
    for path in [
        "/krl/ptp",
        "/krl/circ",
        "/api/v1/motions",
        "/api/v1/jobs/{id}",
        "/api/v1/events",
        "/api/v1/stop",
    ] {
        assert!(v["paths"][path].is_object(), "{path} documented");
    }
    let r = t.http.get(t.url("/docs/")).send().await.expect("docs");
    assert_eq!(r.status(), 200);
    let html = r.text().await.expect("html");
    assert!(
        html.contains("swagger"),
        "Swagger UI served from the binary"
    );
    let r = t
        .http
        .get(t.url("/docs/swagger-ui-bundle.js"))
        .send()
        .await
        .expect("bundle");
    assert_eq!(r.status(), 200, "Swagger UI assets are embedded (offline)");
    let (s, v) = t.get("/api/v1/nothing").await;
    assert_eq!((s, v["code"].as_str()), (404, Some("not_found")));
    for path in [
        "/api/v1/events?types=job,bogus",
        "/api/v1/events?type=job",
        "/api/v1/jobs?limt=3",
    ] {
        let (s, v) = t.get(path).await;
        assert_eq!(
            (s, v["code"].as_str()),
            (422, Some("invalid_input")),
            "{path}: {v}"
        );
    }
    // One simulated controller per channel.
    match kuka_sim::SimController::start(kuka_sim::SimConfig::new(t.channel_dir())) {
        Err(e) => assert!(e.to_string().contains("already serves"), "{e}"),
        Ok(_) => panic!("two simulated controllers on one channel"),
    }
    let (s, v) = t.delete("/api/v1/stop").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (405, Some("method_not_allowed")),
        "{v}"
    );
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn batch_runs_continuously_and_jobs_report_it() {
    let t = TestService::start(Options::default()).await;
    let before = t.moving_s();
    // A square drawn as one blended batch.
    let (s, v) = t
        .motions(json!([
            pen_down(),
            {"type": "lin", "target": {"x": 250}, "velocity_m_s": 0.1, "approx_mm": 2},
            {"type": "lin", "target": {"y": 50}, "velocity_m_s": 0.1, "approx_mm": 2},
            {"type": "lin", "target": {"x": 200}, "velocity_m_s": 0.1, "approx_mm": 2},
            {"type": "lin", "target": {"y": 0}, "velocity_m_s": 0.1}
        ]))
        .await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["state"], "done");
    assert_eq!(v["motions"], 5);
    assert_eq!(v["completed"], 5);
    assert_close(
        v["position"]["x"].as_f64().expect("x"),
        200.0,
        0.01,
        "end x",
    );
    assert_close(v["position"]["y"].as_f64().expect("y"), 0.0, 0.01, "end y");
    let id = v["id"].as_u64().expect("id");
    let (s, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
    assert_eq!(s, 200);
    assert_eq!(j["cid"], v["cid"]);
    let (_, list) = t.get("/api/v1/jobs?limit=5").await;
    assert_eq!(list[0]["id"], id, "newest first");
    assert!(t.moving_s() > before, "simulated time advanced");
    // Relative move.
    let (s, v) = t
        .motions(json!([{"type": "lin", "target": {"z": 30}, "relative": true}]))
        .await;
    assert_eq!(s, 200, "{v}");
    assert_close(
        v["position"]["z"].as_f64().expect("z"),
        100.0,
        0.01,
        "relative z",
    );
    // Position round trip and axis PTP.
    let (s, v) = t.get("/api/v1/position").await;
    assert_eq!(s, 200);
    assert_close(
        v["position"]["z"].as_f64().expect("z"),
        100.0,
        0.01,
        "position z",
    );
    let (s, v) = t.motions(json!([{"type": "ptp_axes", "axes": {"a1": 10, "a2": -90, "a3": 90, "a4": 0, "a5": 30, "a6": 0}}])).await;
    assert_eq!(s, 200, "{v}");
    assert_close(
        v["axes"]["a1"].as_f64().expect("a1"),
        10.0,
        1e-3,
        "axis ptp",
    );
    let (s, v) = t.post("/api/v1/home").await;
    assert_eq!(s, 200, "{v}");
    assert_close(v["axes"]["a1"].as_f64().expect("a1"), 0.0, 1e-3, "home");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn validation_errors_write_nothing() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.workspace = Some(WorkspaceBox {
                x: [0.0, 400.0],
                y: [-300.0, 300.0],
                z: [20.0, 700.0],
            })
        }),
        ..Options::default()
    })
    .await;
    let cmd = t.channel_dir().join(kuka_protocol::COMMAND_FILE);
    let (s, _) = t.post("/krl/getpos").await;
    assert_eq!(s, 200);
    let before = std::fs::read_to_string(&cmd).expect("command file");
    let cases: Vec<(Value, &str)> = vec![
        (json!({"motions": []}), "invalid_input"),
        (
            json!({"motions": [{"type": "ptp", "target": {"x": 200}, "s": 1}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "ptp", "target": {"x": 200, "s": 8}}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "ptp", "target": {"x": 200, "t": 64}}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"x": 200, "s": 2}}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "jump", "target": {}}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"x": 1e9}}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"x": 200}, "velocity_m_s": 5}]}),
            "speed_limit",
        ),
        (
            json!({"motions": [{"type": "ptp", "target": {"x": 200}, "velocity_pct": 0}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"x": 200}, "acceleration_pct": 101}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"x": 200}, "approx_mm": -1}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"x": 200, "z": 10}}]}),
            "workspace_violation",
        ),
        (
            json!({"motions": [{"type": "ptp", "target": {"x": 390, "y": 290, "z": 680}}]}),
            "unreachable",
        ),
        (
            json!({"motions": [pen_down(), {"type": "lin", "target": {"x": 390, "y": 290, "z": 680}}]}),
            "unreachable",
        ),
        (
            json!({"motions": [{"type": "ptp_axes", "axes": {"a5": 130}}]}),
            "software_limit",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"y": 100}}]}),
            "singularity",
        ),
        (
            json!({"motions": [{"type": "circ", "aux": {"x": 305, "y": 0, "z": 525}, "target": {"x": 255, "y": 0, "z": 425}}]}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"x": 200}}], "timeout_ms": 0}),
            "invalid_input",
        ),
        (
            json!({"motions": [{"type": "lin", "target": {"x": 200}}], "extra": 1}),
            "invalid_input",
        ),
    ];
    for (body, code) in cases {
        let (s, v) = t.post_json("/api/v1/motions", &body).await;
        assert_eq!(v["code"], code, "{body} → {v}");
        assert!(s == 422, "{body} → {s}");
        assert!(
            v["detail"].as_str().is_some_and(|d| !d.is_empty()),
            "human sentence: {v}"
        );
        if code == "software_limit" {
            assert_eq!(v["axis"], 5, "{v}");
        }
    }
    // Wrong media type, and a body above the 2 MB limit.
    let r = t
        .http
        .post(t.url("/api/v1/motions"))
        .header("content-type", "text/plain")
        .body("{}")
        .send()
        .await
        .expect("send");
    let (s, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(
        (s, v["code"].as_str()),
        (415, Some("unsupported_media_type")),
        "{v}"
    );
    let huge = format!("{{\"motions\": [], \"pad\": \"{}\"}}", "x".repeat(3 << 20));
    let r = t
        .http
        .post(t.url("/api/v1/motions"))
        .header("content-type", "application/json")
        .body(huge)
        .send()
        .await
        .expect("send");
    let (s, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(
        (s, v["code"].as_str()),
        (413, Some("payload_too_large")),
        "{v}"
    );
    // Malformed JSON.
    let r = t
        .http
        .post(t.url("/api/v1/motions"))
        .header("content-type", "application/json")
        .body("{")
        .send()
        .await
        .expect("send");
    let (s, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!((s, v["code"].as_str()), (422, Some("invalid_input")), "{v}");
    let (s, v) = t
        .put_json(
            "/api/v1/tool",
            &json!({"x": 0, "y": 0, "z": "high", "a": 0, "b": 0, "c": 0}),
        )
        .await;
    assert_eq!((s, v["code"].as_str()), (422, Some("invalid_input")), "{v}");
    let (s, v) = t
        .put_json("/api/v1/speed", &json!({"cp_velocity_m_s": 3}))
        .await;
    assert_eq!((s, v["code"].as_str()), (422, Some("speed_limit")), "{v}");
    let (s, v) = t
        .put_json("/api/v1/speed", &json!({"override_pct": 0}))
        .await;
    assert_eq!((s, v["code"].as_str()), (422, Some("invalid_input")), "{v}");
    // Found by schemathesis: positive, but 0.000 in the file (the
    // controller rejected the command as malformed: 502).
    let (s, v) = t
        .put_json("/api/v1/speed", &json!({"override_pct": 7.4e-214}))
        .await;
    assert_eq!((s, v["code"].as_str()), (422, Some("invalid_input")), "{v}");
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300}, "velocity_pct": 1e-9}]))
        .await;
    assert_eq!((s, v["code"].as_str()), (422, Some("invalid_input")), "{v}");
    assert_eq!(
        std::fs::read_to_string(&cmd).expect("command file"),
        before,
        "no rejected request reached the channel"
    );
    let (s, v) = t.get("/api/v1/jobs/999999").await;
    assert_eq!((s, v["code"].as_str()), (404, Some("not_found")));
    let (s, v) = t.get("/api/v1/jobs/abc").await;
    assert_eq!((s, v["code"].as_str()), (422, Some("invalid_input")));
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn controller_side_errors_are_structured() {
    // Without a model in the service, the controller itself rejects.
    let t = TestService::start(Options {
        tweak: Box::new(|c| c.robot.model = "none".into()),
        ..Options::default()
    })
    .await;
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 2000}}]))
        .await;
    assert_eq!((s, v["code"].as_str()), (422, Some("unreachable")), "{v}");
    assert!(v["job_id"].is_u64(), "{v}");
    let (s, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a3": 170}}]))
        .await;
    assert_eq!(
        (s, v["code"].as_str(), v["axis"].as_u64()),
        (422, Some("software_limit"), Some(3)),
        "{v}"
    );
    let (s, v) = t
        .motions(json!([{"type": "lin", "target": {"y": 100}}]))
        .await;
    if t.service.krc.is_some() {
        // The KRL program checks the end point only: the robot starts and
        // the controller stops it at the wrist singularity with a message;
        // the job ends with the controller's error at once (no timeout),
        // and the controller stays in its error state.
        assert_eq!(
            (s, v["code"].as_str()),
            (409, Some("controller_error")),
            "{v}"
        );
    } else {
        assert_eq!((s, v["code"].as_str()), (422, Some("singularity")), "{v}");
        // An error state on the controller: commands fail until reset. The
        // native simulator is told to enter it.
        t.provoke_controller_error().await;
    }
    let mut st = Value::Null;
    for _ in 0..200 {
        st = t.get("/api/v1/state").await.1;
        if st["controller"]["status"] == "error" {
            break;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    assert_eq!(st["controller"]["status"], "error", "{st}");
    assert_eq!(
        st["controller"]["error"]["code"], "controller_error",
        "{st}"
    );
    let (s, v) = t.post("/api/v1/home").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (409, Some("controller_error")),
        "{v}"
    );
    let (s, v) = t.post("/api/v1/reset").await;
    assert_eq!(s, 200, "{v}");
    if let Some(krc) = &t.service.krc {
        // After an error stop the operator acknowledges the message and
        // starts kb_main again (docs/CONTROLLER.md).
        krc.operator_restart();
    }
    let (s, v) = t.post("/api/v1/home").await;
    assert_eq!(s, 200, "{v}");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn frames_and_speeds() {
    let t = TestService::start(Options::default()).await;
    let tool = json!({"x": 0.0, "y": 0.0, "z": 120.5, "a": 0.0, "b": 0.0, "c": 0.0});
    let (s, v) = t.put_json("/api/v1/tool", &tool).await;
    assert_eq!((s, &v), (200, &tool));
    let (s, v) = t.get("/api/v1/tool").await;
    assert_eq!((s, &v), (200, &tool));
    let base = json!({"x": 100.0, "y": 0.0, "z": 0.0, "a": 90.0, "b": 0.0, "c": 0.0});
    let (s, v) = t.put_json("/api/v1/base", &base).await;
    assert_eq!((s, &v), (200, &base));
    let (s, v) = t.get("/api/v1/base").await;
    assert_eq!((s, &v), (200, &base));
    let (_, st) = t.get("/api/v1/state").await;
    assert_eq!(st["tool"], tool);
    let (s, v) = t
        .put_json(
            "/api/v1/speed",
            &json!({"override_pct": 50, "cp_velocity_m_s": 0.1}),
        )
        .await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["override_pct"], 50.0);
    assert_eq!(v["cp_velocity_m_s"], 0.1);
    let (_, v) = t.get("/api/v1/speed").await;
    assert_eq!(v["override_pct"], 50.0);
    // The controller reports the override in its next heartbeat.
    let mut applied = false;
    for _ in 0..100 {
        let (_, st) = t.get("/api/v1/state").await;
        if st["controller"]["override_pct"] == 50.0 {
            applied = true;
            break;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    assert!(applied, "the controller applied the override");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn async_jobs_cancel_stop_and_events() {
    // Real-time simulation so a motion takes a while.
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let events = t
        .http
        .get(t.url("/api/v1/events?types=job"))
        .send()
        .await
        .expect("events");
    assert_eq!(events.status(), 200);
    assert!(
        events.headers()["content-type"]
            .to_str()
            .expect("ct")
            .starts_with("text/event-stream")
    );
    let mut stream = events.bytes_stream();

    // A slow motion (several seconds) without waiting.
    let slow = json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 160}, "velocity_pct": 5}], "wait": false});
    let r = t
        .http
        .post(t.url("/api/v1/motions"))
        .json(&slow)
        .send()
        .await
        .expect("send");
    assert_eq!(r.status(), 202);
    let location = r.headers()["location"]
        .to_str()
        .expect("location")
        .to_string();
    let job: Value = r.json().await.expect("job");
    let id = job["id"].as_u64().expect("id");
    assert_eq!(location, format!("/api/v1/jobs/{id}"));
    // A second job queues behind it; cancelling it removes it.
    let second = json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 0}}], "wait": false});
    let (s, j2) = t.post_json("/api/v1/motions", &second).await;
    assert_eq!(s, 202);
    let id2 = j2["id"].as_u64().expect("id");
    let (s, c) = t.delete(&format!("/api/v1/jobs/{id2}")).await;
    assert_eq!((s, c["state"].as_str()), (200, Some("cancelled")), "{c}");
    // Wait until the first executes, then stop.
    let mut executing = false;
    for _ in 0..200 {
        let (_, j) = t.get(&location).await;
        if j["state"] == "executing" {
            executing = true;
            break;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    assert!(executing, "job reached executing");
    // Part way: A1 has left 0 (the job then says where it stopped).
    t.wait_state("A1 to move", |st| {
        st["axes"]["a1"].as_f64().is_some_and(|a1| a1 > 0.1)
    })
    .await;
    let (s, v) = t.post("/api/v1/stop").await;
    assert_eq!((s, &v), (200, &json!({"stopped": true})));
    let (_, j) = t.get(&location).await;
    assert_eq!(j["state"], "cancelled", "{j}");
    assert_eq!(j["error"]["code"], "cancelled");
    let a1 = j["axes"]["a1"].as_f64().expect("a1");
    assert!(a1 > 0.1 && a1 < 150.0, "stopped part way: A1 = {a1}");
    // The event stream told the story: queued → sent → executing → cancelled.
    let mut seen = Vec::new();
    let deadline = tokio::time::Instant::now() + Duration::from_secs(5);
    let mut buf = String::new();
    while tokio::time::Instant::now() < deadline && !seen.contains(&"cancelled".to_string()) {
        let Ok(Some(Ok(chunk))) = tokio::time::timeout(Duration::from_secs(2), stream.next()).await
        else {
            break;
        };
        buf.push_str(&String::from_utf8_lossy(&chunk));
        while let Some(end) = buf.find("\n\n") {
            let msg: String = buf.drain(..end + 2).collect();
            if let Some(data) = msg.lines().find_map(|l| l.strip_prefix("data:")) {
                let ev: Value = serde_json::from_str(data.trim()).expect("json event");
                if ev["id"] == id {
                    seen.push(ev["state"].as_str().unwrap_or("").to_string());
                }
            }
        }
    }
    for want in ["sent", "executing", "cancelled"] {
        assert!(seen.iter().any(|s| s == want), "event {want} in {seen:?}");
    }
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn concurrent_requests_run_in_arrival_order() {
    let t = std::sync::Arc::new(TestService::start(Options::default()).await);
    let mut ids = Vec::new();
    for i in 0..8 {
        let body = json!({"motions": [{"type": "ptp", "target": {"x": 200 + i * 10, "y": 0, "z": 70, "a": 0, "b": 180, "c": 0}}], "wait": false});
        let (s, v) = t.post_json("/api/v1/motions", &body).await;
        assert_eq!(s, 202);
        ids.push(v["id"].as_u64().expect("id"));
    }
    let mut cids = Vec::new();
    for id in &ids {
        let mut job = Value::Null;
        for _ in 0..200 {
            let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
            job = j;
            if job["state"] == "done" {
                break;
            }
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
        assert_eq!(job["state"], "done", "{job}");
        cids.push(job["cid"].as_i64().expect("cid"));
    }
    assert!(
        cids.windows(2).all(|w| w[0] < w[1]),
        "command ids follow arrival order: {cids:?}"
    );
    let (_, p) = t.get("/api/v1/position").await;
    assert_close(
        p["position"]["x"].as_f64().expect("x"),
        270.0,
        0.01,
        "last request ran last",
    );
}

/// The README's walk-through, step by step: the thesis endpoints, then the
/// smiley (docs/smiley.json) as one continuous batch — twice, since a
/// drawing must not depend on where the arm was — checked against the
/// simulator's executed trace.
#[tokio::test]
async fn readme_walk_through_draws_the_smiley() {
    let t = TestService::start(Options::default()).await;
    for step in [
        "/krl/getpos",
        "/krl/ptp?x=200&y=0&z=70&a=0&b=180&c=0",
        "/krl/linmov?x=250&y=100",
    ] {
        let (s, v) = t.post(step).await;
        assert_eq!((s, &v["statuscode"]), (200, &json!(1)), "{step}: {v}");
    }
    let body: Value = serde_json::from_str(include_str!("../docs/smiley.json"))
        .expect("docs/smiley.json is JSON");
    let n = body["motions"].as_array().expect("motions").len();
    for round in 0..2 {
        t.clear_trace();
        let (s, v) = t.post_json("/api/v1/motions", &body).await;
        assert_eq!(s, 200, "round {round}: {v}");
        assert_eq!(v["completed"], n);
        let trace = t.trace();
        let drawn: Vec<_> = trace
            .iter()
            .filter(|s| s.motion > 0 && (s.pose[2] - 70.0).abs() < 0.01) // motion 0 lifts the pen from wherever the arm was
            .collect();
        assert!(
            drawn.len() > 100,
            "pen on paper for {} samples",
            drawn.len()
        );
        let dist = |s: &&kuka_bridge_tests::Sample, cx: f64, cy: f64| {
            ((s.pose[0] - cx).powi(2) + (s.pose[1] - cy).powi(2)).sqrt()
        };
        // Every drawn point belongs to the face, an eye or the mouth.
        for s in &drawn {
            let face = (dist(s, 220.0, 0.0) - 55.0).abs() < 0.6;
            let eye = (dist(s, 238.0, 20.0) - 7.0).abs() < 0.6
                || (dist(s, 238.0, -20.0) - 7.0).abs() < 0.6;
            let mouth = dist(s, 220.0, 0.0) < 40.0 && s.pose[0] < 203.0;
            assert!(face || eye || mouth, "stray ink at {:?}", s.pose);
        }
        assert!(
            drawn
                .iter()
                .filter(|s| (dist(s, 220.0, 0.0) - 55.0).abs() < 0.6)
                .count()
                > 50,
            "face"
        );
        assert!(
            drawn
                .iter()
                .any(|s| (dist(s, 238.0, 20.0) - 7.0).abs() < 0.6),
            "left eye"
        );
        assert!(
            drawn
                .iter()
                .any(|s| (dist(s, 238.0, -20.0) - 7.0).abs() < 0.6),
            "right eye"
        );
        assert!(
            drawn
                .iter()
                .any(|s| (s.pose[0] - 185.0).abs() < 1.0 && s.pose[1].abs() < 2.0),
            "mouth through (185, 0)"
        );
    }
    // A flange-down PTP that would need another arm configuration says how to get it.
    let (s, v) = t.post("/krl/ptp?x=300&y=0&z=300&a=0&b=180&c=0").await;
    if s != 200 {
        assert!(
            v["detail"].as_str().unwrap_or("").contains("give `s`"),
            "{v}"
        );
    }
    t.service.shutdown().await.expect("shutdown");
}

/// The dashboard is served from the binary: the page at `/`, and every
/// file it loads — followed through the scripts' module imports — under
/// `/ui/` with its media type; unknown files 404.
#[tokio::test]
async fn dashboard_files_are_served_from_the_binary() {
    let t = TestService::start(Options::default()).await;
    let mut todo = vec!["/".to_string()];
    let mut seen = std::collections::BTreeSet::new();
    while let Some(path) = todo.pop() {
        if !seen.insert(path.clone()) {
            continue;
        }
        let r = t.http.get(t.url(&path)).send().await.expect("request");
        assert_eq!(r.status().as_u16(), 200, "{path}");
        let ct = r.headers()["content-type"]
            .to_str()
            .unwrap_or_default()
            .to_string();
        let body = r.text().await.expect("body");
        assert!(!body.is_empty(), "{path}");
        let dir = path.rsplit_once('/').map_or("", |(d, _)| d).to_string();
        let refs: Vec<String> = if path == "/" {
            assert!(ct.starts_with("text/html"), "{path}: {ct}");
            ["src=\"", "href=\""]
                .iter()
                .flat_map(|attr| body.split(attr).skip(1))
                .filter_map(|rest| rest.split('"').next())
                .filter(|r| r.starts_with("/ui/"))
                .map(str::to_string)
                .collect()
        } else if path.ends_with(".js") {
            assert!(ct.starts_with("text/javascript"), "{path}: {ct}");
            body.lines()
                .filter(|l| l.starts_with("import ") || l.starts_with("export * from"))
                .filter_map(|l| l.split(" from ").nth(1))
                .map(|m| m.trim_matches(|c| c == ' ' || c == ';' || c == '"' || c == '\''))
                .filter_map(|m| m.strip_prefix("./"))
                .map(|m| format!("{dir}/{m}"))
                .collect()
        } else {
            assert!(ct.starts_with("text/css"), "{path}: {ct}");
            Vec::new()
        };
        todo.extend(refs);
    }
    for want in [
        "/ui/app.js",
        "/ui/arm.js",
        "/ui/kinematics.js",
        "/ui/vendor/three.module.js",
        "/ui/vendor/three.core.js",
        "/ui/vendor/OrbitControls.js",
        "/ui/style.css",
    ] {
        assert!(seen.contains(want), "{want} in {seen:?}");
    }
    let (s, v) = t.get("/ui/nothing.js").await;
    assert_eq!((s, v["code"].as_str()), (404, Some("not_found")));
    t.service.shutdown().await.expect("shutdown");
}

/// `GET /api/v1/model` gives the geometry and limits the checks use, and
/// the `plan` event gives a batch's motions with relative and omitted
/// coordinates resolved, before they run.
#[tokio::test]
async fn model_and_planned_paths() {
    let t = TestService::start(Options::default()).await;
    let (s, m) = t.get("/api/v1/model").await;
    assert_eq!(s, 200, "{m}");
    assert_eq!(m["name"], "kr3_r540");
    assert_eq!(m["opw_mm"]["c1"], 345.0);
    assert_eq!(m["opw_mm"]["a2"], -20.0);
    assert_eq!(m["limits_deg"][1], json!([-170.0, 50.0]));
    assert_eq!(m["home"], json!([0.0, -90.0, 90.0, 0.0, 0.0, 0.0]));

    let events = t
        .http
        .get(t.url("/api/v1/events?types=plan"))
        .send()
        .await
        .expect("events");
    let mut stream = events.bytes_stream();
    let batch = json!({"motions": [
        {"type": "ptp", "target": {"x": 275, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}},
        {"type": "lin", "target": {"z": -30}, "relative": true},
        {"type": "circ", "aux": {"x": 220, "y": 55}, "target": {"x": 165}},
        {"type": "ptp_axes", "axes": {"a1": 5, "a2": -90, "a3": 90, "a4": 0, "a5": 0, "a6": 0}}
    ]});
    let (s, job) = t.post_json("/api/v1/motions", &batch).await;
    assert_eq!(s, 200, "{job}");
    let mut buf = String::new();
    let plan = loop {
        let chunk = tokio::time::timeout(Duration::from_secs(5), stream.next())
            .await
            .expect("a plan event within 5 s")
            .expect("stream open")
            .expect("chunk");
        buf.push_str(&String::from_utf8_lossy(&chunk));
        if let Some(end) = buf.find("\n\n") {
            let msg: String = buf.drain(..end + 2).collect();
            if msg.contains("event: plan") {
                let data = msg.lines().find_map(|l| l.strip_prefix("data:"));
                break serde_json::from_str::<Value>(data.expect("data").trim()).expect("json");
            }
        }
    };
    assert_eq!(plan["job"], job["id"]);
    assert_eq!(plan["cid"], job["cid"]);
    let m = &plan["motions"];
    assert_eq!(m[0]["type"], "ptp");
    assert_eq!(m[0]["target"], json!([275.0, 0.0, 100.0, 0.0, 180.0, 0.0]));
    assert_eq!(
        m[1]["target"],
        json!([275.0, 0.0, 70.0, 0.0, 180.0, 0.0]),
        "relative z"
    );
    assert_eq!(m[2]["aux"], json!([220.0, 55.0, 70.0]), "aux keeps z");
    assert_eq!(m[2]["target"], json!([165.0, 0.0, 70.0, 0.0, 180.0, 0.0]));
    assert_eq!(m[3]["type"], "ptp_axes");
    assert_eq!(m[3]["axes"], json!([5.0, -90.0, 90.0, 0.0, 0.0, 0.0]));
    assert!(m[3]["target"].is_null(), "{}", m[3]);
    // The unknown event type is named in the error.
    let (s, v) = t.get("/api/v1/events?types=plans").await;
    assert_eq!(s, 422);
    assert!(v["detail"].as_str().unwrap_or("").contains("plan"), "{v}");
    t.service.shutdown().await.expect("shutdown");
}

/// Every answer carries an `x-request-id`; an error body carries the same
/// id as `request_id`. An internal failure (the program folder cannot be
/// written) answers a code and a sentence: the path and the operating
/// system's error are in the log under that id, never in the answer.
#[tokio::test]
async fn errors_carry_the_request_id_and_no_internal_paths() {
    let t = TestService::start(Options::default()).await;
    let r = t.request(reqwest::Method::GET, "/api/v1/jobs/987654").await;
    let id = r
        .headers()
        .get("x-request-id")
        .expect("x-request-id")
        .to_str()
        .expect("ascii")
        .to_string();
    let (s, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(
        (s, v["request_id"].as_str()),
        (404, Some(id.as_str())),
        "{v}"
    );
    let r = t.request(reqwest::Method::GET, "/health").await;
    let other = r.headers().get("x-request-id").expect("x-request-id");
    assert_ne!(other.to_str().expect("ascii"), id, "one id per request");

    let folder = t.config.data_dir.join("programs");
    std::fs::remove_dir_all(&folder).expect("remove");
    std::fs::write(&folder, b"not a folder").expect("block");
    let src = "DEF p()\n  PTP {A1 10}\nEND\n";
    let (s, v) = t
        .post_json("/api/v1/programs", &json!({"name": "p", "src": src}))
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("storage_unavailable")),
        "{v}"
    );
    let root = t.dirs.path().display().to_string();
    assert!(!v.to_string().contains(&root), "no internal path: {v}");
    assert!(v["request_id"].is_string(), "{v}");
    t.service.shutdown().await.expect("shutdown");
}

/// A problem's `type` (`/errors#<code>`, relative to the request's URL)
/// leads to the service's own error catalogue, a 200 HTML page with the
/// code's section; so on every problem, the thesis format and the answers
/// the edge makes of bare errors included. Every code of the enum (the
/// document's `ErrorCode` list) has its section, and the JSON catalogue
/// lists each with its status.
#[tokio::test]
async fn problem_types_lead_to_the_served_error_catalogue() {
    let t = TestService::start(Options::default()).await;
    let cases = [
        ("GET", "/api/v1/jobs?limt=3", "invalid_input"),
        ("GET", "/api/v1/jobs/987654", "not_found"),
        ("GET", "/api/v1/nothing", "not_found"),
        ("DELETE", "/api/v1/stop", "method_not_allowed"),
        ("POST", "/krl/getpos?foo=1", "invalid_input"),
        ("POST", "/krl/ptp?x=99999", "invalid_input"),
    ];
    for (method, path, code) in cases {
        let method = reqwest::Method::from_bytes(method.as_bytes()).expect("method");
        let (status, v) = kuka_bridge_tests::decode(t.request(method, path).await).await;
        assert!(status >= 400, "{path}: {status} {v}");
        assert_eq!(v["code"], code, "{path}: {v}");
        let type_uri = v["type"].as_str().expect("a type");
        assert_eq!(type_uri, format!("/errors#{code}"), "{path}");
        let page = reqwest::Url::parse(&t.url(path))
            .expect("url")
            .join(type_uri)
            .expect("a URI reference");
        assert_eq!(page.fragment(), Some(code));
        let r = t.http.get(page.clone()).send().await.expect("catalogue");
        assert_eq!(r.status(), 200, "{page}");
        let media = r.headers()["content-type"].to_str().expect("ascii");
        assert!(media.starts_with("text/html"), "{media}");
        let html = r.text().await.expect("page");
        assert!(html.contains(&format!("id=\"{code}\"")), "{page}");
    }

    // Every code the service knows (the enum, as the document lists it).
    let (_, doc) = t.get("/openapi.json").await;
    let codes: Vec<String> = doc["components"]["schemas"]["ErrorCode"]["examples"]
        .as_array()
        .expect("the known codes")
        .iter()
        .map(|c| c.as_str().expect("a code").to_string())
        .collect();
    assert!(codes.len() >= 39, "{codes:?}");
    let html = t
        .http
        .get(t.url("/errors"))
        .send()
        .await
        .expect("page")
        .text()
        .await
        .expect("html");
    let r = t
        .http
        .get(t.url("/errors"))
        .header("accept", "application/json")
        .send()
        .await
        .expect("json");
    assert_eq!(r.status(), 200);
    let catalogue: Value = r.json().await.expect("JSON catalogue");
    for code in &codes {
        assert!(
            html.contains(&format!("id=\"{code}\"")),
            "no section {code}"
        );
        let entry = &catalogue[code];
        assert_eq!(entry["type"], format!("/errors#{code}"), "{entry}");
        assert!(
            entry["status"].as_u64().is_some_and(|s| s >= 400),
            "{entry}"
        );
        assert!(entry["title"].is_string() && entry["summary"].is_string());
    }
    assert_eq!(catalogue["software_limit"]["status"], 422);
    assert_eq!(catalogue["software_limit"]["thesis_statuscode"], 21);
    // Swagger UI links to it; the operation is documented and public.
    assert!(
        doc["info"]["description"]
            .as_str()
            .is_some_and(|d| d.contains("[/errors](/errors)")),
        "{}",
        doc["info"]
    );
    let op = &doc["paths"]["/errors"]["get"];
    assert_eq!(op["operationId"], "getErrorCatalogue");
    assert_eq!(op["x-required-role"], "none");
    t.service.shutdown().await.expect("shutdown");
}

/// Every documented operation refuses a query parameter it does not
/// declare: 422 `invalid_input` naming it (thesis format on `/krl/*`),
/// before anything runs; declared ones still pass.
#[tokio::test]
async fn every_operation_refuses_unknown_query_parameters() {
    let t = TestService::start(Options::default()).await;
    let (_, doc) = t.get("/openapi.json").await;
    let mut checked = 0;
    for (path, item) in doc["paths"].as_object().expect("paths") {
        let url = path
            .replace("{id}", "999999")
            .replace("{name}", "no-such-name");
        for method in item.as_object().expect("item").keys() {
            let what = format!("{} {path}", method.to_uppercase());
            let method =
                reqwest::Method::from_bytes(method.to_uppercase().as_bytes()).expect("method");
            let r = t.request(method, &format!("{url}?zz_unknown=1")).await;
            let (status, v) = kuka_bridge_tests::decode(r).await;
            assert_eq!(
                (status, v["code"].as_str()),
                (422, Some("invalid_input")),
                "{what}: {v}"
            );
            let detail = v["detail"].as_str().unwrap_or_default();
            assert!(detail.contains("\"zz_unknown\""), "{what}: {detail}");
            if path.starts_with("/krl/") {
                assert_eq!(v["statuscode"], 10, "{what}: {v}");
            }
            checked += 1;
        }
    }
    assert!(checked >= 45, "only {checked} operations");
    // The example, and the allowed parameters named.
    let (s, v) = t.get("/api/v1/tool?index=3").await;
    assert_eq!(s, 422, "{v}");
    let detail = v["detail"].as_str().unwrap_or_default();
    assert!(
        detail.contains("\"index\"") && detail.contains("takes no query parameters"),
        "{detail}"
    );
    let (s, v) = t.get("/api/v1/jobs?limit=2&limt=3").await;
    let detail = v["detail"].as_str().unwrap_or_default();
    assert!(
        s == 422 && detail.contains("\"limt\"") && detail.contains("takes limit"),
        "{s} {v}"
    );
    // Declared parameters (and the thesis's upper-case spelling) pass.
    let (s, v) = t.get("/api/v1/jobs?limit=2").await;
    assert_eq!(s, 200, "{v}");
    let (s, v) = t.post("/krl/getpos").await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    let (s, v) = t.post("/krl/tcp?X=0&z=0").await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    t.service.shutdown().await.expect("shutdown");
}

/// A request the router refuses before any handler (a path that is not
/// UTF-8 after percent-decoding) gets a problem whose `status` is the
/// status the client receives, with a sentence saying what was wrong.
#[tokio::test]
async fn bare_refusals_say_the_status_they_answer() {
    let t = TestService::start(Options::default()).await;
    for path in ["/api/v1/jobs/%FF", "/api/v1/programs/%FF"] {
        let (status, v) = t.get(path).await;
        assert_eq!(status, 400, "{path}: {v}");
        assert_eq!(v["status"], 400, "{path}: {v}");
        assert_eq!(v["code"], "invalid_input", "{path}: {v}");
        assert!(
            v["detail"]
                .as_str()
                .is_some_and(|d| d.contains("malformed")),
            "{path}: {v}"
        );
    }
}

/// The start of the 200 mm test line of the live-position tests, flange
/// down.
async fn to_line_start(t: &TestService) {
    let (s, j) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300, "y": -100, "z": 300, "a": 0, "b": 180, "c": 0}}]))
        .await;
    assert_eq!(s, 200, "{j}");
}

/// Starts the 200 mm LIN along y at `velocity` m/s without waiting and
/// returns its job id once it executes.
async fn run_line(t: &TestService, velocity: f64) -> u64 {
    let body = json!({"motions": [{"type": "lin", "target": {"y": 100}, "velocity_m_s": velocity}], "wait": false});
    let (s, job) = t.post_json("/api/v1/motions", &body).await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    t.wait_job(id, "the LIN to execute", |j| j["state"] == "executing")
        .await;
    id
}

/// Issue 22, live position: while a 2 s LIN runs, `GET /api/v1/position`
/// and the thesis `getpos` answer at once from the controller's live state
/// (`source: live`, with its age), with a position on the path — they no
/// longer queue behind the motion. At rest the answer is a GETPOS round trip.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn position_is_live_while_a_motion_runs() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    to_line_start(&t).await;
    let (s, at_rest) = t.get("/api/v1/position").await;
    assert_eq!(s, 200, "{at_rest}");
    assert_eq!(at_rest["source"], "controller", "{at_rest}");
    assert_eq!(at_rest["age_ms"], 0);
    // 200 mm at 0.1 m/s: about 2 s.
    let location = format!("/api/v1/jobs/{}", run_line(&t, 0.1).await);
    let mut mid_path = 0;
    let mut thesis_mid_path = 0;
    loop {
        let (s, p) = t.get("/api/v1/position").await;
        assert_eq!(s, 200, "{p}");
        let (_, j) = t.get(&location).await;
        let running = j["state"] == "executing";
        let y = p["position"]["y"].as_f64().expect("y");
        assert_close(
            p["position"]["x"].as_f64().expect("x"),
            300.0,
            0.01,
            "x on the line",
        );
        assert_close(
            p["position"]["z"].as_f64().expect("z"),
            300.0,
            0.01,
            "z on the line",
        );
        assert!((-100.001..=100.001).contains(&y), "y on the line: {p}");
        if running {
            // Answered while the motion still runs: from the live state.
            assert_eq!(p["source"], "live", "{p}");
            assert!(p["age_ms"].as_u64().expect("age") < 1000, "{p}");
            if y > -99.0 && y < 99.0 {
                mid_path += 1;
            }
            let (s, g) = t.post("/krl/getpos").await;
            assert_eq!((s, g["statuscode"].as_i64()), (200, Some(1)), "{g}");
            let gy = g["position"][1].as_f64().expect("y");
            assert_close(
                g["position"][0].as_f64().expect("x"),
                300.0,
                0.01,
                "getpos x",
            );
            if gy > -99.0 && gy < 99.0 && t.get(&location).await.1["state"] == "executing" {
                thesis_mid_path += 1;
                // From the live state, with its age.
                assert!(g["age_ms"].as_u64().expect("age_ms") < 1000, "{g}");
            }
        } else if j["state"] == "done" {
            break;
        } else {
            assert_eq!(j["state"], "sent", "{j}");
        }
        // Every 50 ms a new reading (the heartbeat moves the position on).
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert!(mid_path >= 5, "live positions along the path: {mid_path}");
    assert!(
        thesis_mid_path >= 5,
        "thesis getpos along the path: {thesis_mid_path}"
    );
}

/// Issue 22, live position when the heartbeat stalls: a sample older than
/// 500 ms is not answered; the read waits for the next one (up to 2 s)
/// instead of queueing behind the motion, and answers live as soon as the
/// controller reports again.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_late_heartbeat_delays_a_live_read_briefly() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    to_line_start(&t).await;
    // 200 mm at 0.02 m/s: about 10 s, far longer than the test.
    run_line(&t, 0.02).await;
    t.pause_controller();
    // Reads answer from the last sample until it is 500 ms old; then one
    // waits (it does not come back within 100 ms).
    let deadline = std::time::Instant::now() + Duration::from_secs(5);
    let waiting = loop {
        assert!(
            std::time::Instant::now() < deadline,
            "a read never waited for a fresh sample"
        );
        let http = t.http.clone();
        let url = t.url("/api/v1/position");
        let mut read = tokio::spawn(async move {
            let r = http.get(url).send().await.expect("position");
            let s = r.status().as_u16();
            (s, r.json::<Value>().await.expect("body"))
        });
        match tokio::time::timeout(Duration::from_millis(100), &mut read).await {
            Ok(done) => {
                let (s, p) = done.expect("read");
                assert_eq!((s, p["source"].as_str()), (200, Some("live")), "{p}");
                assert!(p["age_ms"].as_u64().expect("age") <= 500, "{p}");
            }
            Err(_) => break read,
        }
    };
    t.resume_controller();
    let (s, p) = tokio::time::timeout(Duration::from_secs(3), waiting)
        .await
        .expect("the waiting read answers once the controller reports")
        .expect("read");
    assert_eq!((s, p["source"].as_str()), (200, Some("live")), "{p}");
    assert!(p["age_ms"].as_u64().expect("age") < 500, "{p}");
    let (s, _) = t.post("/api/v1/stop").await;
    assert_eq!(s, 200);
}

/// Issue 20: the program override (`PUT /api/v1/speed`, written to `$OV_PRO`
/// by the KRL program's Submit side) scales the robot's speed on both
/// simulated controllers: the same LIN at 50 % takes twice as long.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_override_scales_the_motion_time() {
    let t = TestService::start(Options::default()).await;
    let (s, j) = t
        .motions(json!([{"type": "ptp", "target": {"x": 300, "y": -100, "z": 300, "a": 0, "b": 180, "c": 0}}]))
        .await;
    assert_eq!(s, 200, "{j}");
    let mut spans = Vec::new();
    for (pct, y) in [(100.0, 0.0), (50.0, -100.0)] {
        let (s, v) = t
            .put_json("/api/v1/speed", &json!({"override_pct": pct}))
            .await;
        assert_eq!(s, 200, "{v}");
        t.wait_state("the controller to report the override", |st| {
            st["controller"]["override_pct"] == pct
        })
        .await;
        // 100 mm at 0.1 m/s: about 1 s at 100 %.
        let (s, j) = t
            .motions(json!([{"type": "lin", "target": {"y": y}, "velocity_m_s": 0.1}]))
            .await;
        assert_eq!(s, 200, "{j}");
        let cid = j["cid"].as_i64().expect("cid");
        let trace: Vec<_> = t.trace().into_iter().filter(|s| s.cid == cid).collect();
        assert!(trace.len() > 2, "the LIN left a trace");
        spans.push(trace[trace.len() - 1].t - trace[0].t);
    }
    let ratio = spans[1] / spans[0];
    assert!(
        (1.8..=2.2).contains(&ratio),
        "at 50 % the LIN took {:.3} s, at 100 % {:.3} s (ratio {ratio:.2})",
        spans[1],
        spans[0]
    );
}

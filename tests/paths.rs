//! Paths (motion streams, issue 22) through HTTP against the simulated
//! controller (`KB_TEST_SIMULATOR=krc`: the shipped KRL program in the
//! KRC-like runtime): separately sent motions blend, ordering, JSON-lines
//! streams, back-pressure, a refused motion, cancel and stop mid-stream, a
//! client that disconnects, and the position while a path runs.

use std::time::Duration;

use kuka_bridge_tests::{Options, TestService, WAIT, assert_close, wait_for};
use serde_json::{Value, json};

/// The points of a circle (radius `r` mm around (190, 0), Z 100, flange
/// down; the KR 3 R540's A5 < 0 region, no singularity).
fn circle(n: usize, r: f64) -> Vec<[f64; 2]> {
    (0..=n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            [190.0 + r * a.cos(), r * a.sin()]
        })
        .collect()
}

fn lin(p: &[f64; 2], v: f64) -> Value {
    json!({"type": "lin", "target": {"x": p[0], "y": p[1]}, "velocity_m_s": v, "approx_mm": 2})
}

async fn to_start(t: &TestService, p: &[f64; 2]) {
    let start = json!([{"type": "ptp", "target": {"x": p[0], "y": p[1], "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]);
    let (s, v) = t.motions(start).await;
    assert_eq!(s, 200, "{v}");
}

async fn open_path(t: &TestService) -> u64 {
    let (s, job) = t.post_json("/api/v1/paths", &json!({})).await;
    assert_eq!(s, 201, "{job}");
    assert_eq!(job["operation"], "path");
    job["id"].as_u64().expect("id")
}

/// POSTs `body` as JSON lines (`application/x-ndjson`) to the path's
/// motions: the status and the JSON answer.
async fn post_lines(t: &TestService, id: u64, body: String) -> (u16, Value) {
    let r = t
        .http
        .post(t.url(&format!("/api/v1/paths/{id}/motions")))
        .header("content-type", "application/x-ndjson")
        .body(body)
        .send()
        .await
        .expect("stream");
    let status = r.status().as_u16();
    (status, r.json().await.expect("a JSON answer"))
}

/// Waits until the path has ended. On the KRL program in the KRC-like
/// runtime (a debug build interpreting every statement) a long path takes
/// a while: the bound is generous, the wait ends as soon as the path does.
async fn wait_path_end(t: &TestService, id: u64) -> Value {
    wait_for(Duration::from_secs(180), "the path to end", async || {
        let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
        let ended = j["state"]
            .as_str()
            .is_some_and(|s| ["done", "failed", "cancelled"].contains(&s));
        if ended { Ok(j) } else { Err(j.to_string()) }
    })
    .await
}

/// A path's job as it ended: state, motions completed, error code.
fn end_of(j: &Value) -> (Option<&str>, Option<u64>, Option<&str>) {
    (
        j["state"].as_str(),
        j["completed"].as_u64(),
        j["error"]["code"].as_str(),
    )
}

/// Seconds the path's trace spans, and how many stops it shows before its
/// end (the robot stood still between two of its motions).
fn path_trace(t: &TestService, cid: i64) -> (f64, usize, usize) {
    let trace: Vec<_> = t.trace().into_iter().filter(|s| s.cid == cid).collect();
    assert!(trace.len() > 2, "the path left a trace");
    let span = trace[trace.len() - 1].t - trace[0].t;
    let stops = trace[..trace.len() - 1].iter().filter(|s| s.stop).count();
    let last_motion = trace[trace.len() - 1].motion;
    (span, stops, last_motion)
}

/// The time scale of a test that asserts a path ran without a stop: the
/// KRC-like runtime in real time, as a controller runs (at the instant
/// scale its clock races ahead of the service's appends, and a loaded host
/// lets the robot run out of motions: stops no real controller would
/// make); the native simulator at once (it plans what it holds, whatever
/// the clock).
fn blend_time_scale() -> f64 {
    if kuka_bridge_tests::test_simulator() == kuka_bridge::config::SimulatorKind::Krc {
        1.0
    } else {
        0.0
    }
}

/// 200 LIN segments, each sent as its own request to one open path, run
/// as one blended path: no stop between them, in the time of the same
/// path planned as one batch, in order.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn separately_sent_motions_blend_into_one_path() {
    let t = TestService::start(Options {
        time_scale: blend_time_scale(),
        ..Options::default()
    })
    .await;
    let pts = circle(200, 50.0);
    to_start(&t, &pts[0]).await;
    // The same circle as one batch: the best the planner can do.
    let batch: Vec<Value> = pts[1..].iter().map(|p| lin(p, 0.2)).collect();
    let (s, b) = t
        .post_json("/api/v1/motions", &json!({"motions": batch}))
        .await;
    assert_eq!(s, 200, "{b}");
    let batch_cid = b["cid"].as_i64().expect("cid");
    let (batch_span, batch_stops, _) = path_trace(&t, batch_cid);
    assert_eq!(batch_stops, 0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    for (i, p) in pts[1..].iter().enumerate() {
        let (s, o) = t
            .post_json(
                &format!("/api/v1/paths/{id}/motions"),
                &json!({"motions": [lin(p, 0.2)]}),
            )
            .await;
        assert_eq!(s, 200, "{o}");
        assert_eq!(
            (o["first"].as_u64(), o["total"].as_u64()),
            (Some(i as u64), Some(i as u64 + 1)),
            "{o}"
        );
    }
    let (s, j) = t.delete(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(s, 200, "{j}");
    assert_eq!(j["path"]["closed"], true, "{j}");
    let j = wait_path_end(&t, id).await;
    assert_eq!(j["state"], "done", "{j}");
    assert_eq!(
        (j["completed"].as_u64(), j["motions"].as_u64()),
        (Some(200), Some(200)),
        "{j}"
    );
    assert_eq!(j["path"]["sent"], 200, "{j}");
    let cid = j["cid"].as_i64().expect("cid");
    let (span, stops, last) = path_trace(&t, cid);
    assert_eq!(stops, 0, "no stop between the separately sent motions");
    assert_eq!(last, 199, "every motion ran, the last one last");
    assert!(
        span <= batch_span * 1.02,
        "path {span:.3} s vs the same path as one batch {batch_span:.3} s"
    );
    // It ends where the circle closes.
    let end = &j["position"];
    assert_close(end["x"].as_f64().expect("x"), pts[200][0], 0.01, "x");
    assert_close(end["y"].as_f64().expect("y"), pts[200][1], 0.01, "y");
}

/// A JSON-lines stream of a long path: appended as the lines arrive,
/// closed at the end of the stream, every motion run once and in order.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_json_lines_stream_runs_a_long_path() {
    let t = TestService::start(Options::default()).await;
    // 10 turns of a 100-segment circle: segments of 3.8 mm, 12.6 ms each
    // at 0.3 m/s (a motion per interpolation cycle, as a KRC can follow).
    let turn = circle(100, 60.0);
    let pts: Vec<[f64; 2]> = (0..=1000).map(|i| turn[i % 100]).collect();
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let body: String = pts[1..]
        .iter()
        .map(|p| format!("{}\n", lin(p, 0.3)))
        .collect();
    let (status, o) = post_lines(&t, id, body).await;
    assert_eq!(status, 200, "{o}");
    assert_eq!(
        (
            o["appended"].as_u64(),
            o["total"].as_u64(),
            o["closed"].as_bool()
        ),
        (Some(1000), Some(1000), Some(true)),
        "{o}"
    );
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        (j["state"].as_str(), j["completed"].as_u64()),
        (Some("done"), Some(1000)),
        "{j}"
    );
    let (_, stops, last) = path_trace(&t, j["cid"].as_i64().expect("cid"));
    assert_eq!((stops, last), (0, 999));
    // Appending to a closed path is refused.
    let (s, e) = t
        .post_json(
            &format!("/api/v1/paths/{id}/motions"),
            &json!({"motions": [lin(&pts[0], 0.2)]}),
        )
        .await;
    assert_eq!((s, e["code"].as_str()), (409, Some("path_closed")), "{e}");
}

/// A refused motion changes nothing: the append is answered with the
/// reason and the path-wide index; the path goes on. In a JSON-lines
/// stream the path is closed at the motion before the refused one.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_refused_motion_mid_stream() {
    let t = TestService::start(Options::default()).await;
    let pts = circle(40, 40.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let url = format!("/api/v1/paths/{id}/motions");
    let first: Vec<Value> = pts[1..11].iter().map(|p| lin(p, 0.2)).collect();
    let (s, o) = t.post_json(&url, &json!({"motions": first})).await;
    assert_eq!(s, 200, "{o}");
    // Out of reach: 2 m away.
    let bad = json!({"motions": [lin(&pts[11], 0.2), {"type": "lin", "target": {"x": 2000}}]});
    let (s, e) = t.post_json(&url, &bad).await;
    assert_eq!(s, 422, "{e}");
    assert_eq!(
        e["motion"], 11,
        "path-wide index of the refused motion: {e}"
    );
    // The sentence numbers it in the append and in the path.
    assert!(
        e["detail"]
            .as_str()
            .is_some_and(|d| d.ends_with("(motion 11 of the path)")),
        "{e}"
    );
    let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(
        j["path"]["appended"], 10,
        "nothing of the refused append: {j}"
    );
    // The refusal closed the path at the last accepted motion: the robot
    // runs those 10 and stops; later appends are refused; the path's job
    // ends with the reason.
    let rest: Vec<Value> = pts[11..].iter().map(|p| lin(p, 0.2)).collect();
    let (s, e) = t.post_json(&url, &json!({"motions": rest})).await;
    assert_eq!((s, e["code"].as_str()), (409, Some("path_closed")), "{e}");
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        (j["state"].as_str(), j["completed"].as_u64()),
        (Some("failed"), Some(10)),
        "{j}"
    );
    assert_eq!(j["error"]["code"], "unreachable", "{j}");
    assert_eq!(j["error"]["motion"], 11, "{j}");
    let end = &j["position"];
    assert_close(
        end["x"].as_f64().expect("x"),
        pts[10][0],
        0.01,
        "stopped at motion 9's target x",
    );
    assert_close(end["y"].as_f64().expect("y"), pts[10][1], 0.01, "y");

    // In a JSON-lines stream the motions before a refused one run, however
    // the body is cut into batches; the path ends there.
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let mut body: String = pts[1..21]
        .iter()
        .map(|p| format!("{}\n", lin(p, 0.2)))
        .collect();
    body.push_str("{\"type\": \"lin\", \"target\": {\"x\": 2000}}\n");
    body.push_str(
        &pts[21..30]
            .iter()
            .map(|p| format!("{}\n", lin(p, 0.2)))
            .collect::<String>(),
    );
    let (status, e) = post_lines(&t, id, body).await;
    assert_eq!(
        (status, e["code"].as_str(), e["motion"].as_u64()),
        (422, Some("unreachable"), Some(20)),
        "{e}"
    );
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        end_of(&j),
        (Some("failed"), Some(20), Some("unreachable")),
        "{j}"
    );

    // A refused append and then a cancel while the accepted motions still
    // run: the path ends with the refusal on either simulator (the stop
    // only cut the accepted motions short).
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let url = format!("/api/v1/paths/{id}/motions");
    let slow: Vec<Value> = pts[1..6].iter().map(|p| lin(p, 0.02)).collect();
    let (s, o) = t.post_json(&url, &json!({"motions": slow})).await;
    assert_eq!(s, 200, "{o}");
    let (s, e) = t
        .post_json(
            &url,
            &json!({"motions": [{"type": "lin", "target": {"x": 2000}}]}),
        )
        .await;
    assert_eq!((s, e["code"].as_str()), (422, Some("unreachable")), "{e}");
    let (s, j) = t.delete(&format!("/api/v1/paths/{id}?cancel=true")).await;
    assert_eq!(s, 200, "{j}");
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        (j["state"].as_str(), j["error"]["code"].as_str()),
        (Some("failed"), Some("unreachable")),
        "{j}"
    );

    // A stream with a bad line: the lines before it run, then the path ends.
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let mut body: String = pts[1..6]
        .iter()
        .map(|p| format!("{}\n", lin(p, 0.2)))
        .collect();
    body.push_str("{\"type\": \"lin\", \"target\": {\"x\": \"far\"}}\n");
    body.push_str(&format!("{}\n", lin(&pts[6], 0.2)));
    let (status, e) = post_lines(&t, id, body).await;
    assert_eq!(
        (status, e["code"].as_str()),
        (422, Some("invalid_input")),
        "{e}"
    );
    assert!(
        e["detail"].as_str().is_some_and(|d| d.contains("line 6")),
        "{e}"
    );
    assert_eq!(e["motion"], 5, "the bad line's index in the path: {e}");
    // The path ends failed with the reason, as for a refused motion.
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        end_of(&j),
        (Some("failed"), Some(5), Some("invalid_input")),
        "{j}"
    );

    // A motion with a bad number (negative speed) after 3 good ones: refused
    // like an unreachable one, with its index in the path, and the path
    // closes there.
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let good: Vec<Value> = pts[1..4].iter().map(|p| lin(p, 0.2)).collect();
    let (s, o) = t.post_json(&url_of(id), &json!({"motions": good})).await;
    assert_eq!(s, 200, "{o}");
    let bad = json!({"motions": [lin(&pts[4], 0.2), lin(&pts[5], -1.0)]});
    let (s, e) = t.post_json(&url_of(id), &bad).await;
    assert_eq!(
        (s, e["code"].as_str(), e["motion"].as_u64()),
        (422, Some("invalid_input"), Some(4)),
        "{e}"
    );
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        end_of(&j),
        (Some("failed"), Some(3), Some("invalid_input")),
        "{j}"
    );
}

fn url_of(id: u64) -> String {
    format!("/api/v1/paths/{id}/motions")
}

/// Cancel and stop mid-stream: the robot stops at once, the path is
/// cancelled, later appends are refused.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn cancel_and_stop_mid_stream() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let pts = circle(40, 40.0);
    to_start(&t, &pts[0]).await;
    for how in ["cancel", "stop"] {
        let id = open_path(&t).await;
        let url = format!("/api/v1/paths/{id}/motions");
        // 40 × 6.3 mm at 0.05 m/s: about 5 s.
        let all: Vec<Value> = pts[1..].iter().map(|p| lin(p, 0.05)).collect();
        let (s, o) = t.post_json(&url, &json!({"motions": all})).await;
        assert_eq!(s, 200, "{o}");
        t.wait_job(id, "the path to run a few motions", |j| {
            j["completed"].as_u64().is_some_and(|c| c >= 2)
        })
        .await;
        let (s, v) = if how == "cancel" {
            t.delete(&format!("/api/v1/paths/{id}?cancel=true")).await
        } else {
            t.post("/api/v1/stop").await
        };
        assert_eq!(s, 200, "{v}");
        if how == "cancel" {
            // The answer is the path as it ended, not as it was.
            assert_eq!(v["state"], "cancelled", "{v}");
        }
        let j = wait_path_end(&t, id).await;
        assert_eq!(j["state"], "cancelled", "{how}: {j}");
        assert_eq!(j["path"]["closed"], true, "an ended path says so: {j}");
        let done = j["completed"].as_u64().expect("completed");
        assert!((2..40).contains(&done), "{how}: stopped part way: {j}");
        let (s, e) = t
            .post_json(&url, &json!({"motions": [lin(&pts[1], 0.05)]}))
            .await;
        assert_eq!(
            (s, e["code"].as_str()),
            (409, Some("path_closed")),
            "{how}: {e}"
        );
        // The robot stands where it stopped: the controller is idle, and
        // still there when a read comes back through it.
        t.wait_state("the controller idle", |st| {
            st["controller"]["status"] == "idle"
        })
        .await;
        let at = t.controller_axes();
        let (s, _) = t.get("/api/v1/position").await;
        assert_eq!(s, 200);
        assert_eq!(t.controller_axes(), at, "{how}: the robot stands");
        to_start(&t, &pts[0]).await;
    }
}

/// Back-pressure: a path holds at most 2000 motions in front of the
/// controller; an append beyond waits for room and, when none comes within
/// its `wait_ms`, is refused with `path_full` and a `Retry-After`, having
/// appended nothing. Live position answers while it runs.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_full_path_holds_the_client_back() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let pts = circle(2100, 50.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let url = format!("/api/v1/paths/{id}/motions");
    // Slow motions: the robot needs ~150 ms for each (0.15 mm at 1 mm/s).
    let slow = |p: &[f64; 2]| json!({"type": "lin", "target": {"x": p[0], "y": p[1]}, "velocity_m_s": 0.001});
    for chunk in pts[1..2201.min(pts.len())].chunks(500).take(5) {
        let m: Vec<Value> = chunk.iter().map(slow).collect();
        let (s, o) = t
            .post_json(&url, &json!({"motions": m, "wait_ms": 200}))
            .await;
        if s == 503 {
            assert_eq!(o["code"], "path_full", "{o}");
            break;
        }
        assert_eq!(s, 200, "{o}");
    }
    let more: Vec<Value> = pts[1..501].iter().map(slow).collect();
    let r = t
        .http
        .post(t.url(&url))
        .json(&json!({"motions": more, "wait_ms": 300}))
        .send()
        .await
        .expect("append");
    assert_eq!(r.status().as_u16(), 503);
    assert_eq!(r.headers()["retry-after"], "1");
    let e: Value = r.json().await.expect("problem");
    assert_eq!(e["code"], "path_full", "{e}");
    let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
    let appended = j["path"]["appended"].as_u64().expect("appended");
    assert!(appended <= 2000 + 200, "{j}");
    // The position is live while the path runs. (On a loaded machine the
    // heartbeat can be late beyond the 2 s a read waits for it: then that
    // read queues behind the path; the next one is live again.)
    let mut live = None;
    for _ in 0..5 {
        let r = t
            .http
            .get(t.url("/api/v1/position"))
            .timeout(Duration::from_secs(3))
            .send()
            .await;
        if let Ok(r) = r
            && r.status().as_u16() == 200
        {
            let p: Value = r.json().await.expect("position");
            if p["source"] == "live" {
                live = Some(p);
                break;
            }
        }
    }
    assert!(live.is_some(), "no live position while the path ran");
    // An append waiting for room does not hold up the end of the path: the
    // close is answered at once, and the waiting append hears that the
    // path was closed (nothing of it was appended).
    let waiting = {
        let http = t.http.clone();
        let url = t.url(&url);
        let more: Vec<Value> = pts[1..501].iter().map(slow).collect();
        tokio::spawn(async move {
            let r = http
                .post(url)
                .json(&json!({"motions": more, "wait_ms": 60000}))
                .send()
                .await
                .expect("append");
            let status = r.status().as_u16();
            (status, r.json::<Value>().await.expect("body"))
        })
    };
    wait_for(WAIT, "the append to wait for room", async || {
        let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
        // Parked appends are not counted; give it a moment on the engine.
        if j["state"] == "executing" {
            Ok(())
        } else {
            Err(j.to_string())
        }
    })
    .await;
    let closing = std::time::Instant::now();
    let (s, j) = t.delete(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(s, 200, "{j}");
    assert!(
        closing.elapsed() < Duration::from_secs(5),
        "the close waited behind the append"
    );
    assert_eq!(j["path"]["closed"], true, "{j}");
    let (s, e) = waiting.await.expect("append task");
    assert_eq!((s, e["code"].as_str()), (409, Some("path_closed")), "{e}");
    let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(j["path"]["appended"].as_u64(), Some(appended), "{j}");
    let (s, j) = t.delete(&format!("/api/v1/paths/{id}?cancel=true")).await;
    assert_eq!(s, 200, "{j}");
    wait_path_end(&t, id).await;
}

/// A path opened behind another job takes appends once it runs: the
/// append waits for it (within its `wait_ms`). An open path that gets no
/// more motions ends by itself after 5 s once the robot has run what it
/// has (its client is gone), on either simulator, instant or not.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_queued_path_takes_appends_and_an_idle_one_ends() {
    let t = TestService::start(Options::default()).await;
    let pts = circle(40, 40.0);
    to_start(&t, &pts[0]).await;
    let a = open_path(&t).await;
    let (s, o) = t
        .post_json(
            &format!("/api/v1/paths/{a}/motions"),
            &json!({"motions": [lin(&pts[1], 0.2), lin(&pts[2], 0.2)]}),
        )
        .await;
    assert_eq!(s, 200, "{o}");
    // Path b waits behind path a, which nobody closes: it ends when idle.
    let b = open_path(&t).await;
    let (s, o) = t
        .post_json(
            &format!("/api/v1/paths/{b}/motions"),
            &json!({"motions": [lin(&pts[3], 0.2)], "close": true, "wait_ms": 30000}),
        )
        .await;
    assert_eq!(s, 200, "appended once b ran: {o}");
    // b ran only after a had ended (idle: 5 s of controller time).
    let (_, ja) = t.get(&format!("/api/v1/paths/{a}")).await;
    assert_eq!(
        ja["state"], "done",
        "a ended before b took the append: {ja}"
    );
    let ja = wait_path_end(&t, a).await;
    assert_eq!(
        (ja["state"].as_str(), ja["completed"].as_u64()),
        (Some("done"), Some(2)),
        "{ja}"
    );
    let jb = wait_path_end(&t, b).await;
    assert_eq!(
        (jb["state"].as_str(), jb["completed"].as_u64()),
        (Some("done"), Some(1)),
        "{jb}"
    );

    // Ending a path that is still queued (behind a LIN the paused
    // controller holds) answers at once: it has no motions, so it is
    // cancelled, and closed; the LIN ahead is not touched.
    t.pause_controller();
    let (s, ahead) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [lin(&pts[10], 0.2)], "wait": false}),
        )
        .await;
    assert_eq!(s, 202, "{ahead}");
    let c = open_path(&t).await;
    let (_, jc) = t.get(&format!("/api/v1/paths/{c}")).await;
    assert_eq!(jc["state"], "queued", "{jc}");
    let (s, jc) = t.delete(&format!("/api/v1/paths/{c}")).await;
    assert_eq!(s, 200, "{jc}");
    assert_eq!(
        (jc["state"].as_str(), jc["path"]["closed"].as_bool()),
        (Some("cancelled"), Some(true)),
        "{jc}"
    );
    t.resume_controller();
    let id = ahead["id"].as_u64().expect("id");
    let j = t
        .wait_job(id, "the LIN ahead", |j| {
            ["done", "failed", "cancelled"].contains(&j["state"].as_str().unwrap_or(""))
        })
        .await;
    assert_eq!(j["state"], "done", "the LIN ahead ran: {j}");
}

/// A client that disconnects in the middle of a JSON-lines stream: the
/// path ends at the last motion appended (documented), nothing hangs.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_disconnect_ends_the_path() {
    let t = TestService::start(Options::default()).await;
    let pts = circle(60, 40.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let lines: Vec<Result<String, std::io::Error>> = pts[1..21]
        .iter()
        .map(|p| Ok(format!("{}\n", lin(p, 0.2))))
        .chain(std::iter::once(Err(std::io::Error::other("client gone"))))
        .collect();
    let body = reqwest::Body::wrap_stream(futures_util::stream::iter(lines));
    let _ = t
        .http
        .post(t.url(&format!("/api/v1/paths/{id}/motions")))
        .header("content-type", "application/x-ndjson")
        .body(body)
        .send()
        .await;
    let j = wait_for(WAIT, "the path to end after the disconnect", async || {
        let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
        if j["state"] == "done" {
            Ok(j)
        } else {
            Err(j.to_string())
        }
    })
    .await;
    let done = j["completed"].as_u64().expect("completed");
    assert!(done <= 20, "{j}");
    assert_eq!(
        j["completed"], j["path"]["appended"],
        "every appended motion ran: {j}"
    );
}

/// The KRL program's robot side restarted mid-stream (the operator resets
/// and starts `kb_main` again, `POST /api/v1/sim/acknowledge`): the path
/// goes on with the motion that was running. No motion runs twice, none
/// is lost: the trace's motion index never goes back, every motion is
/// done, the path ends at its last target. Always on the KRC-like runtime
/// (the native simulator has no robot program to restart).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_robot_program_restart_mid_stream_loses_and_repeats_nothing() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| c.simulator.kind = kuka_bridge::config::SimulatorKind::Krc),
        ..Options::default()
    })
    .await;
    let pts = circle(30, 40.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let url = format!("/api/v1/paths/{id}/motions");
    // 30 × 8.4 mm at 0.05 m/s: about 5 s.
    let all: Vec<Value> = pts[1..].iter().map(|p| lin(p, 0.05)).collect();
    let (s, o) = t
        .post_json(&url, &json!({"motions": all, "close": true}))
        .await;
    assert_eq!(s, 200, "{o}");
    t.wait_job(id, "a few motions to run", |j| {
        j["completed"].as_u64().is_some_and(|c| c >= 4)
    })
    .await;
    let (s, v) = t.post("/api/v1/sim/acknowledge").await;
    assert_eq!(s, 204, "{v}");
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        (j["state"].as_str(), j["completed"].as_u64()),
        (Some("done"), Some(30)),
        "{j}"
    );
    // No motion twice: the TCP goes round the circle once, never back
    // (its angle about the centre only grows), and reaches the end.
    let cid = j["cid"].as_i64().expect("cid");
    let mut angles: Vec<f64> = Vec::new();
    for s in t.trace().iter().filter(|s| s.cid == cid) {
        let mut a = s.pose[1].atan2(s.pose[0] - 190.0);
        if let Some(&prev) = angles.last() {
            while a < prev - std::f64::consts::PI {
                a += std::f64::consts::TAU;
            }
        }
        angles.push(a);
    }
    assert!(
        angles.windows(2).all(|w| w[1] >= w[0] - 1e-6),
        "the TCP never goes back along the path: {angles:?}"
    );
    let turned = angles.last().expect("trace") - angles.first().expect("trace");
    assert!(
        turned > 5.0,
        "it went (most of) the way round: {turned} rad"
    );
    let end = &j["position"];
    assert_close(end["x"].as_f64().expect("x"), pts[30][0], 0.01, "x");
    assert_close(end["y"].as_f64().expect("y"), pts[30][1], 0.01, "y");
}

/// Thesis clients (`motion.thesis_blend_ms` > 0): consecutive `/krl/linmov`
/// calls sent faster than the robot runs them blend into one path: each is
/// answered when it is checked and queued (with the position it will
/// reach), the robot does not stop between them, and another kind of call
/// (here `/krl/ptp`) ends the path and runs after its last motion.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn thesis_linmov_calls_blend_when_the_site_enables_it() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.motion.thesis_blend_ms = 300;
            c.simulator.kind = kuka_bridge_tests::test_simulator();
        }),
        ..Options::default()
    })
    .await;
    let pts = circle(40, 40.0);
    to_start(&t, &pts[0]).await;
    for p in &pts[1..] {
        let (s, v) = t.post(&format!("/krl/linmov?x={}&y={}", p[0], p[1])).await;
        assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
        assert_close(
            v["position"][0].as_f64().expect("x"),
            p[0],
            0.001,
            "planned x",
        );
        assert_close(
            v["position"][1].as_f64().expect("y"),
            p[1],
            0.001,
            "planned y",
        );
        // As the controller reports positions: in thousandths (a planned
        // end read 200.00000000000003 before).
        let exact = v["position"].as_array().expect("position").iter().all(|c| {
            let c = c.as_f64().expect("number");
            (c * 1000.0).round() / 1000.0 == c
        });
        assert!(exact, "{v}");
    }
    // A PTP ends the blending path: it runs after the circle's last motion.
    let (s, v) = t.post("/krl/ptp?z=120").await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    let (_, jobs) = t.get("/api/v1/jobs?limit=10").await;
    let path = jobs
        .as_array()
        .expect("jobs")
        .iter()
        .find(|j| j["operation"] == "path")
        .expect("a path job")
        .clone();
    let j = wait_path_end(&t, path["id"].as_u64().expect("id")).await;
    assert_eq!(
        (j["state"].as_str(), j["completed"].as_u64()),
        (Some("done"), Some(40)),
        "{j}"
    );
    let (_, stops, last) = path_trace(&t, j["cid"].as_i64().expect("cid"));
    assert_eq!(
        (stops, last),
        (0, 39),
        "no stop between the 40 linmov calls"
    );
}

/// A path's progress comes as a job event per motion, in order, although
/// a heartbeat reports several short motions at once (a review saw
/// `completed` go 0, 2, 3, 4, 6, …).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_motion_of_a_path_has_its_progress_event() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| c.simulator.kind = kuka_bridge_tests::test_simulator()),
        ..Options::default()
    })
    .await;
    let pts = circle(30, 20.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let body: String = pts[1..]
        .iter()
        .map(|p| format!("{}\n", lin(p, 0.2)))
        .collect();
    let (status, o) = post_lines(&t, id, body).await;
    assert_eq!(status, 200, "{o}");
    let (s, _) = t.delete(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(s, 200);
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        (j["state"].as_str(), j["completed"].as_u64()),
        (Some("done"), Some(30)),
        "{j}"
    );
    let (_, recent) = t.get("/api/v1/events/recent?types=job&limit=1000").await;
    let seen: Vec<u64> = recent
        .as_array()
        .expect("recent")
        .iter()
        .filter(|e| e["data"]["id"].as_u64() == Some(id))
        .filter(|e| ["executing", "done"].contains(&e["data"]["state"].as_str().unwrap_or("")))
        .filter_map(|e| e["data"]["completed"].as_u64())
        .collect();
    let mut steps = seen.clone();
    steps.dedup();
    assert_eq!(
        steps,
        (0..=30).collect::<Vec<u64>>(),
        "completed as published: {seen:?}"
    );
}

/// With blending on, a refused thesis call ends its client's path at once
/// (the robot stops at the last accepted call): it does not leave an
/// open, empty path holding the robot — and every client behind it — until
/// the controller's idle end (5 s each, found by a review).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_refused_blended_thesis_call_leaves_no_path_open() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.motion.thesis_blend_ms = 300;
            c.simulator.kind = kuka_bridge_tests::test_simulator();
        }),
        ..Options::default()
    })
    .await;
    to_start(&t, &[200.0, 0.0]).await;
    let (s, v) = t.post("/krl/linmov?x=210").await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    for _ in 0..3 {
        let (s, v) = t.post("/krl/linmov?x=NaN").await;
        assert_eq!(s, 422, "{v}");
    }
    // Refused by the plan: the sentence is about the call, not about a
    // path the thesis client does not know of.
    let (s, v) = t.post("/krl/linmov?x=2000").await;
    assert_eq!(s, 422, "{v}");
    let detail = v["detail"].as_str().expect("detail");
    assert!(
        !detail.contains("path") && !detail.starts_with("motion") && v.get("motion").is_none(),
        "{v}"
    );
    // Every path has ended (the first with its one call), well before
    // the controller's idle end of an open path (5 s).
    wait_for(Duration::from_secs(3), "every path to end", async || {
        let (_, jobs) = t.get("/api/v1/jobs?limit=20").await;
        let open: Vec<_> = jobs
            .as_array()
            .expect("jobs")
            .iter()
            .filter(|j| j["operation"] == "path")
            .filter(|j| {
                !["done", "failed", "cancelled"].contains(&j["state"].as_str().unwrap_or(""))
            })
            .cloned()
            .collect();
        if open.is_empty() {
            Ok(())
        } else {
            Err(format!("{open:?}"))
        }
    })
    .await;
    let (s, v) = t.post("/krl/linmov?x=220").await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
}

/// With blending on, a thesis client learns through its next call that
/// the calls answered before did not all run: after a Stop the next call
/// is refused `cancelled` (and runs nothing; the one after starts anew),
/// and while the controller is in its error state (an emergency stop) a
/// call is refused `controller_error` instead of being queued and
/// answered 1 (found by a review).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stop_or_an_emergency_stop_reaches_the_next_blended_thesis_call() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| {
            c.motion.thesis_blend_ms = 500;
            c.simulator.kind = kuka_bridge_tests::test_simulator();
        }),
        ..Options::default()
    })
    .await;
    to_start(&t, &[200.0, 0.0]).await;
    for y in [40, -40] {
        let (s, v) = t.post(&format!("/krl/linmov?y={y}")).await;
        assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    }
    let (s, v) = t.post("/api/v1/stop").await;
    assert_eq!(s, 200, "{v}");
    wait_for(Duration::from_secs(5), "the path cancelled", async || {
        let (_, jobs) = t.get("/api/v1/jobs?limit=5").await;
        let path = jobs
            .as_array()
            .and_then(|a| a.iter().find(|j| j["operation"] == "path").cloned());
        match path {
            Some(j) if j["state"] == "cancelled" => Ok(()),
            other => Err(format!("{other:?}")),
        }
    })
    .await;
    let jobs = async || {
        let (_, jobs) = t.get("/api/v1/jobs?limit=50").await;
        jobs.as_array().map_or(0, Vec::len)
    };
    let before = jobs().await;
    let (s, v) = t.post("/krl/linmov?y=10").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (409, Some("cancelled")),
        "the stop reaches the next call: {v}"
    );
    assert_ne!(v["statuscode"], 1, "{v}");
    assert_eq!(jobs().await, before, "the refused call ran nothing");
    let (s, v) = t.post("/krl/linmov?y=20").await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    // The same when the next call comes after the blend window: the path
    // has been closed meanwhile, and the Stop still reaches the client.
    let (s, v) = t.post("/krl/linmov?y=-30").await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    let (s, v) = t.post("/api/v1/stop").await;
    assert_eq!(s, 200, "{v}");
    wait_for(
        Duration::from_secs(5),
        "the second path cancelled",
        async || {
            let (_, jobs) = t.get("/api/v1/jobs?limit=5").await;
            let path = jobs
                .as_array()
                .and_then(|a| a.iter().find(|j| j["operation"] == "path").cloned());
            match path {
                Some(j) if j["state"] == "cancelled" => Ok(()),
                other => Err(format!("{other:?}")),
            }
        },
    )
    .await;
    // On purpose: the 500 ms blend window runs out (its end is what is
    // tested; nothing to wait on).
    tokio::time::sleep(Duration::from_millis(800)).await;
    let before = jobs().await;
    let (s, v) = t.post("/krl/linmov?y=10").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (409, Some("cancelled")),
        "the stop reaches the next call after the window: {v}"
    );
    assert_eq!(jobs().await, before, "the refused call ran nothing");
    let (s, v) = t.post("/krl/linmov?y=20").await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    // An emergency stop: calls are refused while the controller is in error.
    let (s, v) = t
        .put_json("/api/v1/sim/safety", &json!({"emergency_stop": true}))
        .await;
    assert_eq!(s, 204, "{v}");
    t.wait_state("the controller in error", |s| {
        s["controller"]["status"] == "error"
    })
    .await;
    for _ in 0..2 {
        let (s, v) = t.post("/krl/linmov?y=30").await;
        assert_eq!(
            (s, v["code"].as_str()),
            (409, Some("controller_error")),
            "{v}"
        );
    }
}

/// An append that waits for room is withdrawn when its client stops
/// waiting (a client that times out and retries must not get its motions
/// twice): when room frees up later, it is not appended.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_append_its_client_gave_up_on_is_never_appended() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let pts = circle(40, 40.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let url = format!("/api/v1/paths/{id}/motions");
    // 2000 short motions back and forth (1 mm at 0.05 m/s, a few tens of
    // ms each): the path's queue in the service is full.
    let zigzag: Vec<Value> = (0..1000)
        .map(|i| {
            let y = if i % 2 == 0 { 1.0 } else { 0.0 };
            json!({"type": "lin", "target": {"y": y}, "velocity_m_s": 0.05})
        })
        .collect();
    for _ in 0..2 {
        let (s, o) = t.post_json(&url, &json!({"motions": zigzag})).await;
        assert_eq!(s, 200, "{o}");
    }
    // 300 more cannot fit now; the client gives up after 300 ms.
    let more: Vec<Value> = zigzag[..300].to_vec();
    let gave_up = t
        .http
        .post(t.url(&url))
        .timeout(Duration::from_millis(300))
        .json(&json!({"motions": more, "wait_ms": 60000}))
        .send()
        .await;
    assert!(gave_up.is_err(), "the client gave up waiting: {gave_up:?}");
    // Room frees up as the robot runs: enough for the 300 once 300 more are
    // on the controller.
    let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
    let sent = j["path"]["sent"].as_u64().expect("sent");
    wait_for(Duration::from_secs(60), "room for 300 more", async || {
        let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
        if j["path"]["sent"].as_u64().is_some_and(|s| s >= sent + 310) {
            Ok(j)
        } else {
            Err(j.to_string())
        }
    })
    .await;
    let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(
        j["path"]["appended"], 2000,
        "the withdrawn append was not appended: {j}"
    );
    let (s, j) = t.delete(&format!("/api/v1/paths/{id}?cancel=true")).await;
    assert_eq!(s, 200, "{j}");
}

/// A batch of more than 4 motions goes to the controller as a closed path
/// (each line read once, the robot starting on the first ones): it runs
/// whole and blended, in order, its job reports like any batch (no path
/// progress), and it takes no appends from clients.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_big_batch_streams_to_the_controller() {
    let t = TestService::start(Options {
        time_scale: blend_time_scale(),
        ..Options::default()
    })
    .await;
    let pts = circle(300, 50.0);
    to_start(&t, &pts[0]).await;
    let batch: Vec<Value> = pts[1..].iter().map(|p| lin(p, 0.2)).collect();
    let body = json!({"motions": batch, "wait": false});
    let (s, job) = t.post_json("/api/v1/motions", &body).await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("id");
    // Not a path for clients.
    let (s, e) = t
        .post_json(
            &format!("/api/v1/paths/{id}/motions"),
            &json!({"motions": [lin(&pts[0], 0.2)]}),
        )
        .await;
    assert_eq!((s, e["code"].as_str()), (404, Some("not_found")), "{e}");
    let j = t
        .wait_job(id, "the batch to end", |j| {
            ["done", "failed", "cancelled"].contains(&j["state"].as_str().unwrap_or(""))
        })
        .await;
    assert_eq!(j["state"], "done", "{j}");
    assert_eq!(j["completed"], 300, "{j}");
    assert!(j.get("path").is_none_or(Value::is_null), "{j}");
    let cid = j["cid"].as_i64().expect("cid");
    let (_, stops, last) = path_trace(&t, cid);
    assert_eq!(stops, 0, "the batch ran blended");
    assert_eq!(last, 299, "every motion ran, in order");
    // It ended where the batch ends.
    let (_, p) = t.get("/api/v1/position").await;
    let end = pts[300];
    assert!(
        (p["position"]["x"].as_f64().expect("x") - end[0]).abs() < 0.01
            && (p["position"]["y"].as_f64().expect("y") - end[1]).abs() < 0.01,
        "{p}"
    );
}

/// A small batch sent as a path (5 to 40 motions: the PATH carries them
/// all) ends with its own result, also when the controller answers it
/// before any state file showed it running (instant time scale).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_small_streamed_batch_ends_with_its_result() {
    let t = TestService::start(Options::default()).await;
    let pts = circle(12, 30.0);
    to_start(&t, &pts[0]).await;
    for n in [5usize, 12] {
        let batch: Vec<Value> = pts[1..=n].iter().map(|p| lin(p, 0.2)).collect();
        let (s, j) = t
            .post_json("/api/v1/motions", &json!({"motions": batch}))
            .await;
        assert_eq!(s, 200, "{j}");
        assert_eq!(
            (j["state"].as_str(), j["completed"].as_u64()),
            (Some("done"), Some(n as u64)),
            "{j}"
        );
        to_start(&t, &pts[0]).await;
    }
}

// ---------------------------------------------------------------------
// JSON splines (issue 22, point 3): SPL points in spline blocks, SLIN,
// SCIRC and SPTP, on both simulated controllers.
// ---------------------------------------------------------------------

fn spl(p: &[f64; 2], v: f64) -> Value {
    json!({"type": "spl", "target": {"x": p[0], "y": p[1]}, "velocity_m_s": v})
}

/// Where the robot slowed below a quarter of `v` m/s between the first and
/// the last sample of the job's trace (an exact stop; a blended junction
/// keeps its speed): the number of such slow stretches. Found from the
/// TCP's speed, so it reads the same on both simulators.
fn slowdowns(t: &TestService, cid: i64, v: f64) -> usize {
    let trace: Vec<_> = t.trace().into_iter().filter(|s| s.cid == cid).collect();
    assert!(trace.len() > 10, "the job left a trace");
    let speed = |a: &kuka_bridge_tests::Sample, b: &kuka_bridge_tests::Sample| {
        let d = ((a.pose[0] - b.pose[0]).powi(2)
            + (a.pose[1] - b.pose[1]).powi(2)
            + (a.pose[2] - b.pose[2]).powi(2))
        .sqrt();
        d / (b.t - a.t).max(1e-9)
    };
    // Over 48 ms (four samples): the KRC-like runtime's samples come
    // from its interpolation cycle, which may record one pose twice and
    // then move two steps at once.
    let speeds: Vec<f64> = trace.windows(5).map(|w| speed(&w[0], &w[4])).collect();
    // From the first sample at speed to the last one at speed.
    let fast = |s: &f64| *s >= 0.25 * v * 1000.0;
    let (Some(from), Some(to)) = (speeds.iter().position(fast), speeds.iter().rposition(fast))
    else {
        return 0;
    };
    let mut slow = 0;
    let mut in_slow = false;
    for s in &speeds[from..=to] {
        if !fast(s) && !in_slow {
            slow += 1;
        }
        in_slow = !fast(s);
    }
    slow
}

/// Eight SPL points on a circle of 50 mm (one spline block) and back with
/// an SLIN: the TCP follows a smooth curve through the points, not the
/// chords between them (3.8 mm inside the circle at their middle), and
/// never stops on the way.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_spline_block_is_a_smooth_curve_without_stops() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let pts = circle(8, 50.0);
    to_start(&t, &pts[0]).await;
    let mut batch: Vec<Value> = pts[1..].iter().map(|p| spl(p, 0.2)).collect();
    // The block's end blends (C_SPL, 10 mm) into the SLIN's 90° turn.
    batch[7]["approx_mm"] = json!(10);
    batch.push(json!({"type": "slin", "target": {"x": 190.0, "y": 0.0}, "velocity_m_s": 0.2}));
    let (s, b) = t.motions(json!(batch)).await;
    assert_eq!(s, 200, "{b}");
    assert_eq!(b["state"], "done", "{b}");
    assert_eq!(b["completed"], 9, "{b}");
    let cid = b["cid"].as_i64().expect("cid");
    let trace: Vec<_> = t.trace().into_iter().filter(|s| s.cid == cid).collect();
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for s in &trace {
        let (dx, dy) = (s.pose[0] - 190.0, s.pose[1]);
        let r = dx.hypot(dy);
        let angle = dy.atan2(dx).rem_euclid(std::f64::consts::TAU).to_degrees();
        // Away from the block's first and last segment (their outer
        // tangent is mirrored) and from the SLIN to the centre.
        if (50.0..=305.0).contains(&angle) && r > 40.0 {
            worst = worst.max((r - 50.0).abs());
            checked += 1;
            assert_close(s.pose[2], 100.0, 0.01, "z on the spline");
        }
    }
    assert!(checked > 30, "{checked} samples on the curve");
    assert!(
        worst < 1.5,
        "the TCP is {worst:.2} mm off the circle through the points"
    );
    assert_eq!(
        slowdowns(&t, cid, 0.2),
        0,
        "no stop in the block, none between the block and the SLIN"
    );
    let (_, pos) = t.get("/api/v1/position").await;
    let pos = &pos["position"];
    assert_close(pos["x"].as_f64().expect("x"), 190.0, 0.01, "x at the end");
    assert_close(pos["y"].as_f64().expect("y"), 0.0, 0.01, "y at the end");
}

/// A KRC's two motion planners never blend into each other: LIN → SLIN
/// and SLIN → LIN stop exactly even with an approximation distance, SLIN →
/// SCIRC → SLIN blend.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn spline_motions_blend_only_into_spline_motions() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let pts = circle(8, 50.0);
    to_start(&t, &pts[0]).await;
    let m = |ty: &str, p: &[f64; 2]| json!({"type": ty, "target": {"x": p[0], "y": p[1]}, "velocity_m_s": 0.2, "approx_mm": 5});
    let batch = json!([
        m("lin", &pts[1]),
        m("slin", &pts[2]),
        {"type": "scirc", "aux": {"x": pts[3][0], "y": pts[3][1]}, "target": {"x": pts[4][0], "y": pts[4][1]},
         "velocity_m_s": 0.2, "approx_mm": 5},
        m("slin", &pts[5]),
        m("lin", &pts[6]),
        m("lin", &pts[7]),
    ]);
    let (s, b) = t.motions(batch).await;
    assert_eq!(s, 200, "{b}");
    assert_eq!(b["state"], "done", "{b}");
    let cid = b["cid"].as_i64().expect("cid");
    assert_eq!(
        slowdowns(&t, cid, 0.2),
        2,
        "stops at LIN → SLIN and SLIN → LIN only"
    );
}

/// An SPTP without Status chooses the arm configuration like a PTP, and
/// reports it.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_sptp_reaches_its_target_with_a_chosen_configuration() {
    let t = TestService::start(Options::default()).await;
    let (s, b) = t
        .motions(json!([{"type": "sptp", "target": {"x": 250, "y": 50, "z": 150, "a": 0, "b": 180, "c": 0}}]))
        .await;
    assert_eq!(s, 200, "{b}");
    assert_eq!(b["state"], "done", "{b}");
    let c = &b["configurations"][0];
    assert_eq!(c["motion"], 0, "{b}");
    assert!(c["s"].is_u64() && c["t"].is_u64(), "{b}");
    let (_, pos) = t.get("/api/v1/position").await;
    let pos = &pos["position"];
    for (k, want) in [("x", 250.0), ("y", 50.0), ("z", 150.0)] {
        assert_close(pos[k].as_f64().expect(k), want, 0.01, k);
    }
}

/// An SPTP to axis angles (KRL `SPTP` to an E6AXIS, as `SPTP XHOME`):
/// the robot reaches the angles, absolute and relative; the plan names it;
/// a Cartesian motion after it in the same batch is refused, as after a
/// `ptp_axes` (its Cartesian end is the controller's to compute).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_sptp_to_axis_angles_reaches_them() {
    let t = TestService::start(Options::default()).await;
    let want = [10.0, -80.0, 100.0, 5.0, 45.0, -20.0];
    let (s, b) = t
        .motions(json!([{"type": "sptp_axes", "axes": {"a1": 10, "a2": -80, "a3": 100, "a4": 5, "a5": 45, "a6": -20}, "velocity_pct": 50}]))
        .await;
    assert_eq!((s, &b["state"]), (200, &json!("done")), "{b}");
    let axes = |s: &Value| {
        ["a1", "a2", "a3", "a4", "a5", "a6"].map(|k| s["axes"][k].as_f64().unwrap_or(f64::NAN))
    };
    let (_, st) = t.get("/api/v1/state").await;
    for (k, (got, want)) in axes(&st).into_iter().zip(want).enumerate() {
        assert_close(got, want, 0.01, &format!("A{}", k + 1));
    }
    let (_, plans) = t.get("/api/v1/events/recent?types=plan&limit=1").await;
    assert_eq!(
        plans[0]["data"]["motions"][0]["type"], "sptp_axes",
        "{plans}"
    );
    let (s, b) = t
        .motions(json!([{"type": "sptp_axes", "axes": {"a1": -15}, "relative": true}]))
        .await;
    assert_eq!((s, &b["state"]), (200, &json!("done")), "{b}");
    let (_, st) = t.get("/api/v1/state").await;
    assert_close(axes(&st)[0], -5.0, 0.01, "A1 after -15 relative");
    let (s, e) = t
        .motions(json!([
            {"type": "sptp_axes", "axes": {"a1": 0, "a2": -80, "a3": 100, "a4": 0, "a5": 45, "a6": 0}},
            {"type": "slin", "target": {"x": 10}, "relative": true}
        ]))
        .await;
    assert_eq!(
        (s, e["code"].as_str(), e["motion"].as_u64()),
        (422, Some("invalid_input"), Some(0)),
        "{e}"
    );
}

/// Spline points streamed into a path: each append's run of SPL points is
/// played as blocks (8 points at most), every point once, in order, and
/// the blocks blend into each other.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn spline_points_stream_into_a_path_as_whole_blocks() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let pts = circle(36, 50.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    // Appends of 12 points: a block of 8 and one of 4 each.
    for chunk in pts[1..].chunks(12) {
        let motions: Vec<Value> = chunk.iter().map(|p| spl(p, 0.2)).collect();
        let (s, o) = t
            .post_json(
                &format!("/api/v1/paths/{id}/motions"),
                &json!({"motions": motions}),
            )
            .await;
        assert_eq!(s, 200, "{o}");
    }
    let (s, j) = t.delete(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(s, 200, "{j}");
    let j = wait_path_end(&t, id).await;
    assert_eq!(end_of(&j), (Some("done"), Some(36), None), "{j}");
    let cid = j["cid"].as_i64().expect("cid");
    let trace: Vec<_> = t.trace().into_iter().filter(|s| s.cid == cid).collect();
    let motions: Vec<usize> = trace.iter().map(|s| s.motion).collect();
    assert!(
        motions.windows(2).all(|w| w[0] <= w[1]),
        "in order: {motions:?}"
    );
    assert_eq!(motions.last(), Some(&35), "every point ran");
    assert_eq!(slowdowns(&t, cid, 0.2), 0, "the blocks blend");
    let end = &j["position"];
    assert_close(end["x"].as_f64().expect("x"), pts[36][0], 0.01, "x");
    assert_close(end["y"].as_f64().expect("y"), pts[36][1], 0.01, "y");
}

/// Spline motions are checked like the others before anything is sent.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_spline_motions_are_refused_with_their_index() {
    let t = TestService::start(Options::default()).await;
    let pts = circle(8, 50.0);
    to_start(&t, &pts[0]).await;
    let cases = [
        (json!([spl(&pts[1], 0.2), {"type": "spl"}]), 422, None),
        (
            json!([spl(&pts[1], 0.2), {"type": "spl", "target": {"x": 2000}}]),
            422,
            Some(1),
        ),
        (json!([spl(&pts[1], -1.0)]), 422, Some(0)),
        (
            json!([spl(&pts[1], 0.2), {"type": "scirc", "aux": {"x": 1.0}, "target": {"x": 1.0}}]),
            422,
            Some(1),
        ),
        (
            json!([{"type": "spl", "target": {"x": 200, "c": "x"}}]),
            422,
            None,
        ),
        (
            json!([{"type": "sptp", "target": {"x": 200, "s": 9}}]),
            422,
            Some(0),
        ),
    ];
    for (body, status, motion) in cases {
        let (s, e) = t.motions(body.clone()).await;
        assert_eq!(s, status, "{body} → {e}");
        assert!(e["code"].is_string() && e["detail"].is_string(), "{e}");
        if let Some(m) = motion {
            assert_eq!(e["motion"], m, "{body} → {e}");
        }
    }
    // Nothing moved.
    let (_, pos) = t.get("/api/v1/position").await;
    let pos = &pos["position"];
    assert_close(pos["x"].as_f64().expect("x"), pts[0][0], 0.01, "x");
}

/// Bodies of the wrong kind get an answer that says what to send.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn path_requests_with_the_wrong_body_say_what_to_send() {
    let t = TestService::start(Options::default()).await;
    let send = async |path: &str, ct: &str, body: &str| {
        let r = t
            .http
            .post(t.url(path))
            .header("content-type", ct)
            .body(body.to_string())
            .send()
            .await
            .expect("request");
        let status = r.status().as_u16();
        let v: Value = r.json().await.expect("a JSON answer");
        (status, v)
    };
    let (s, v) = send("/api/v1/paths", "text/plain", "{}").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (415, Some("unsupported_media_type")),
        "{v}"
    );
    let (s, v) = send("/api/v1/paths", "application/json", "[1]").await;
    assert_eq!(s, 422, "{v}");
    assert!(
        v["detail"]
            .as_str()
            .is_some_and(|d| d.contains("JSON object")),
        "{v}"
    );
    let id = open_path(&t).await;
    let url = format!("/api/v1/paths/{id}/motions");
    let (s, v) = send(&url, "text/plain", "{}").await;
    assert_eq!(s, 415, "{v}");
    let d = v["detail"].as_str().expect("detail");
    assert!(
        d.contains("application/json") && d.contains("application/x-ndjson"),
        "{v}"
    );
    // A huge number is shown as the client wrote it, not in 301 digits.
    let (s, v) = send(
        &url,
        "application/json",
        r#"{"motions": [{"type": "lin", "target": {"x": 1e300}}]}"#,
    )
    .await;
    assert_eq!(s, 422, "{v}");
    let d = v["detail"].as_str().expect("detail");
    assert!(d.contains("1e300") && d.len() < 200, "{d}");
}

/// Opens a JSON-lines stream to the path's motions whose lines the test
/// sends when it wants (dropping the sender ends the stream); the answer
/// comes when the stream ends.
fn open_stream(
    t: &TestService,
    id: u64,
) -> (
    tokio::sync::mpsc::UnboundedSender<Result<String, std::io::Error>>,
    tokio::task::JoinHandle<reqwest::Result<reqwest::Response>>,
) {
    let (tx, rx) = tokio::sync::mpsc::unbounded_channel::<Result<String, std::io::Error>>();
    let body = reqwest::Body::wrap_stream(futures_util::stream::unfold(rx, async |mut rx| {
        rx.recv().await.map(|item| (item, rx))
    }));
    let request = t
        .http
        .post(t.url(&format!("/api/v1/paths/{id}/motions")))
        .header("content-type", "application/x-ndjson")
        .body(body)
        .send();
    (tx, tokio::spawn(request))
}

/// A JSON-lines stream that pauses longer than the controller's idle end
/// of a path (5 s) keeps its path while its connection stays open: the
/// lines after the pause run in the same path.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_paused_stream_keeps_its_path() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let pts = circle(40, 40.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let (tx, answer) = open_stream(&t, id);
    for p in &pts[1..4] {
        tx.send(Ok(format!("{}\n", lin(p, 0.2))))
            .expect("stream open");
    }
    // (An open path may show its last stored motion as the running one.)
    t.wait_job(id, "the first motions to run", |j| {
        j["completed"].as_u64() >= Some(2)
    })
    .await;
    // The pause under test, longer than the controller's kb_path_idle_ms
    // (5 s): three keep-alives (one per 2 s of silence) have reached it.
    let cid = async || {
        let (_, st) = t.get("/api/v1/state").await;
        st["controller"]["last_cid"].as_i64().unwrap_or(0)
    };
    let before = cid().await;
    wait_for(Duration::from_secs(20), "three keep-alives", async || {
        let now = cid().await;
        if now >= before + 3 {
            Ok(())
        } else {
            Err(format!("last_cid {now}, {before} before the pause"))
        }
    })
    .await;
    let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(
        j["path"]["closed"], false,
        "still open after the pause: {j}"
    );
    for p in &pts[4..7] {
        tx.send(Ok(format!("{}\n", lin(p, 0.2))))
            .expect("stream open");
    }
    drop(tx);
    let r = answer.await.expect("request task").expect("answer");
    assert_eq!(r.status().as_u16(), 200);
    let o: Value = r.json().await.expect("JSON");
    assert_eq!(
        (o["appended"].as_u64(), o["closed"].as_bool()),
        (Some(6), Some(true)),
        "{o}"
    );
    let j = wait_path_end(&t, id).await;
    assert_eq!(end_of(&j), (Some("done"), Some(6), None), "{j}");
}

/// A JSON-lines stream that pauses after spline points sends the block it
/// held back for more points: the robot runs every point it was sent.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_paused_stream_sends_its_held_back_spline_points() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let pts = circle(40, 40.0);
    to_start(&t, &pts[0]).await;
    let id = open_path(&t).await;
    let (tx, answer) = open_stream(&t, id);
    // 20 points: two blocks of 8 and 4 held back for more.
    for p in &pts[1..21] {
        tx.send(Ok(format!("{}\n", spl(p, 0.2))))
            .expect("stream open");
    }
    let j = wait_for(
        WAIT,
        "all 20 points appended during the pause",
        async || {
            let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
            if j["path"]["appended"] == 20 {
                Ok(j)
            } else {
                Err(j.to_string())
            }
        },
    )
    .await;
    assert_eq!(j["path"]["closed"], false, "{j}");
    drop(tx);
    let r = answer.await.expect("request task").expect("answer");
    assert_eq!(r.status().as_u16(), 200);
    let j = wait_path_end(&t, id).await;
    assert_eq!(end_of(&j), (Some("done"), Some(20), None), "{j}");
    assert_close(
        j["position"]["x"].as_f64().expect("x"),
        pts[20][0],
        0.01,
        "x",
    );
}

/// A bad line for a path still queued behind another job: the path ends
/// failed with the reason once it reaches the controller, instead of
/// holding it open.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_bad_line_for_a_queued_path_fails_the_path() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    // A job of about a second ahead of the path.
    let slow = json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 30}, "velocity_pct": 30}], "wait": false});
    let (s, job) = t.post_json("/api/v1/motions", &slow).await;
    assert_eq!(s, 202, "{job}");
    let id = open_path(&t).await;
    let (_, j) = t.get(&format!("/api/v1/paths/{id}")).await;
    assert_eq!(j["state"], "queued", "{j}");
    let (s, e) = post_lines(&t, id, "{\"target\": {\"x\": 230}}\n".into()).await;
    assert_eq!(s, 422, "{e}");
    let j = wait_path_end(&t, id).await;
    assert_eq!(
        (j["state"].as_str(), j["error"]["code"].as_str()),
        (Some("failed"), Some("invalid_input")),
        "{j}"
    );
}

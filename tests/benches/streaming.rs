//! Benchmark of motion streams (issue 22; results in docs/BENCHMARKS.md §10):
//!
//! 1. a 50 mm circle as 200 LIN segments at 0.2 m/s, each segment sent as
//!    its own request: appended to one path, versus 200 separate
//!    `POST /api/v1/motions`, versus one batch; exact stops and path time
//!    against the ideal (length / speed) — real time, as a client sees it;
//! 2. a 10,000-point path streamed as JSON lines: stops, time against the
//!    ideal (native simulator: instant time scale; the KRL program: twice
//!    real time — at the instant scale its clock races ahead of the
//!    client's stream and of the service's reactions, which a controller
//!    never does, and the stops it shows are the host's);
//! 3. a long path (default 100,000 points) streamed as JSON lines
//!    generated on the fly: it completes, and the process's memory
//!    (service and simulated controller in one process) stays flat;
//! 4. the position read while a 2 s LIN runs: latency of
//!    `GET /api/v1/position` and `POST /krl/getpos`;
//! 5. with `--sim krc` (the shipped KRL program in the KRC-like runtime,
//!    12 ms Submit cycle): the Submit side's statements per pass and file
//!    operations per motion over the 10,000-point path;
//! 6. batches of 1, 100 and 1000 LINs: real time from the request to the
//!    robot moving (batches over 40 motions stream as a path), and on the
//!    KRL program the file operations per motion;
//! 7. splines: a 50 mm circle as 8 blended LINs, 8 and 24 SPL points in one
//!    batch, and 200 SPL points appended one per request: time against the
//!    circle at 0.2 m/s, stops, and how far the TCP leaves the circle.
//!
//! Run: `cargo bench -p kuka-bridge-tests --bench streaming -- [--sim native|krc]
//! [--long 100000] [--sections 2,6]` (`--sections`: only the numbered sections; 5 comes
//! with 2).

use std::time::{Duration, Instant};

use kuka_bridge::config::SimulatorKind;
use kuka_bridge_tests::bench::{percentile, rss_mib};
use kuka_bridge_tests::{Options, TestService};
use serde_json::{Value, json};

fn arg(name: &str) -> Option<String> {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

/// A circle of `n` segments (radius `r` around (190, 0), Z 100).
fn circle(n: usize, r: f64) -> Vec<[f64; 2]> {
    (0..=n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            [190.0 + r * a.cos(), r * a.sin()]
        })
        .collect()
}

/// Milliseconds of a duration.
fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn length(pts: &[[f64; 2]]) -> f64 {
    pts.windows(2)
        .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
        .sum()
}

fn lin(p: &[f64; 2], v: f64) -> Value {
    json!({"type": "lin", "target": {"x": p[0], "y": p[1]}, "velocity_m_s": v, "approx_mm": 2})
}

async fn service(kind: SimulatorKind, time_scale: f64) -> TestService {
    TestService::start(Options {
        time_scale,
        tweak: Box::new(move |c| {
            c.simulator.kind = kind;
            c.channel.offline_after_ms = 3000;
        }),
        ..Options::default()
    })
    .await
}

async fn to_start(t: &TestService, p: &[f64; 2]) {
    let start = json!([{"type": "ptp", "target": {"x": p[0], "y": p[1], "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]);
    let (s, v) = t.motions(start).await;
    assert_eq!(s, 200, "{v}");
}

async fn open_path(t: &TestService) -> u64 {
    let (s, job) = t.post_json("/api/v1/paths", &json!({})).await;
    assert_eq!(s, 201, "{job}");
    job["id"].as_u64().expect("id")
}

async fn wait_end(t: &TestService, id: u64) -> Value {
    loop {
        let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
        if j["state"]
            .as_str()
            .is_some_and(|s| ["done", "failed", "cancelled"].contains(&s))
        {
            return j;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

/// Span (s) of the trace samples of the given command ids and the stops
/// in it before its last sample.
fn span_and_stops(t: &TestService, cids: &[i64]) -> (f64, usize) {
    let trace: Vec<_> = t
        .trace()
        .into_iter()
        .filter(|s| cids.contains(&s.cid))
        .collect();
    if trace.len() < 2 {
        return (0.0, 0);
    }
    let span = trace[trace.len() - 1].t - trace[0].t;
    let stops: Vec<_> = trace[..trace.len() - 1].iter().filter(|s| s.stop).collect();
    // KB_BENCH_STOPS=1: where the robot stood still (motion index, time).
    if std::env::var_os("KB_BENCH_STOPS").is_some() {
        for s in &stops {
            println!(
                "  stop after motion {} at {:.3} s",
                s.motion,
                s.t - trace[0].t
            );
        }
    }
    (span, stops.len())
}

async fn stream_lines(t: &TestService, id: u64, lines: String) -> Value {
    // No client timeout: the stream lasts as long as the robot needs.
    let r = reqwest::Client::new()
        .post(t.url(&format!("/api/v1/paths/{id}/motions")))
        .header("content-type", "application/x-ndjson")
        .body(lines)
        .send()
        .await
        .expect("stream");
    let v: Value = r.json().await.expect("outcome");
    assert_eq!(v["closed"], true, "{v}");
    v
}

fn main() {
    let kind = match arg("--sim").as_deref() {
        Some("krc") => SimulatorKind::Krc,
        _ => SimulatorKind::Native,
    };
    let long: usize = arg("--long")
        .and_then(|v| v.parse().ok())
        .unwrap_or(100_000);
    let sections: Option<Vec<u32>> =
        arg("--sections").map(|v| v.split(',').filter_map(|n| n.trim().parse().ok()).collect());
    let want = move |n: u32| sections.as_ref().is_none_or(|s| s.contains(&n));
    // KB_BENCH_LOG=<filter> (e.g. kuka_engine=debug): the service's log on stderr.
    if let Ok(filter) = std::env::var("KB_BENCH_LOG") {
        tracing_subscriber::fmt()
            .with_env_filter(tracing_subscriber::EnvFilter::new(filter))
            .with_writer(std::io::stderr)
            .init();
    }
    let rt = kuka_bridge_tests::bench::runtime();
    rt.block_on(async move {
        println!("kuka-bridge streaming benchmark, simulator {kind:?}");

        if want(1) {
            // 1. 200 separately sent segments, real time.
            let t = service(kind, 1.0).await;
            let pts = circle(200, 50.0);
            let ideal = length(&pts) / 1000.0 / 0.2;
            to_start(&t, &pts[0]).await;
            let batch: Vec<Value> = pts[1..].iter().map(|p| lin(p, 0.2)).collect();
            let (s, b) = t.post_json("/api/v1/motions", &json!({"motions": batch})).await;
            assert_eq!(s, 200, "{b}");
            let (batch_span, batch_stops) = span_and_stops(&t, &[b["cid"].as_i64().expect("cid")]);
            to_start(&t, &pts[0]).await;
            let wall = Instant::now();
            let mut cids = Vec::new();
            for p in &pts[1..] {
                let (s, v) = t.post_json("/api/v1/motions", &json!({"motions": [lin(p, 0.2)]})).await;
                assert_eq!(s, 200, "{v}");
                cids.push(v["cid"].as_i64().expect("cid"));
            }
            let separate_wall = wall.elapsed().as_secs_f64();
            let (separate_span, separate_stops) = span_and_stops(&t, &cids);
            to_start(&t, &pts[0]).await;
            let wall = Instant::now();
            let id = open_path(&t).await;
            for p in &pts[1..] {
                let (s, v) = t
                    .post_json(&format!("/api/v1/paths/{id}/motions"), &json!({"motions": [lin(p, 0.2)]}))
                    .await;
                assert_eq!(s, 200, "{v}");
            }
            let (s, _) = t.delete(&format!("/api/v1/paths/{id}")).await;
            assert_eq!(s, 200);
            let j = wait_end(&t, id).await;
            let path_wall = wall.elapsed().as_secs_f64();
            assert_eq!(j["state"], "done", "{j}");
            let (path_span, path_stops) = span_and_stops(&t, &[j["cid"].as_i64().expect("cid")]);
            println!("-- 1. 50 mm circle, 200 LIN segments at 0.2 m/s (ideal {ideal:.3} s), real time");
            println!("one batch:                    {batch_span:.3} s = {:.3}× ideal, {batch_stops} stops", batch_span / ideal);
            println!("200 separate motion requests: {separate_span:.3} s = {:.3}× ideal, {separate_stops} stops (wall {separate_wall:.2} s)", separate_span / ideal);
            println!("200 appends to one path:      {path_span:.3} s = {:.3}× ideal, {:.3}× the batch, {path_stops} stops (wall {path_wall:.2} s)", path_span / ideal, path_span / batch_span);
            t.service.shutdown().await.expect("shutdown");
        }

        let turn = circle(100, 60.0);
        if want(2) {
            // 2. and 5. 10,000 points as JSON lines.
            let scale = if kind == SimulatorKind::Krc { 2.0 } else { 0.0 };
            let t = service(kind, scale).await;
            let pts: Vec<[f64; 2]> = (0..=10_000).map(|i| turn[i % 100]).collect();
            let ideal = length(&pts) / 1000.0 / 0.3;
            to_start(&t, &pts[0]).await;
            let before = t.service.krc.as_ref().map(|k| k.stats());
            let id = open_path(&t).await;
            let lines: String = pts[1..].iter().map(|p| format!("{}\n", lin(p, 0.3))).collect();
            let wall = Instant::now();
            stream_lines(&t, id, lines).await;
            let j = wait_end(&t, id).await;
            assert_eq!(j["state"], "done", "{j}");
            let (span, stops) = span_and_stops(&t, &[j["cid"].as_i64().expect("cid")]);
            println!("-- 2. 10,000-point path (3.8 mm segments at 0.3 m/s, ideal {ideal:.3} s) as JSON lines");
            println!("path time {span:.3} s = {:.4}× ideal, {stops} stops, {} motions done (wall {:.1} s)", span / ideal, j["completed"], wall.elapsed().as_secs_f64());
            if let (Some(k), Some(before)) = (t.service.krc.as_ref(), before) {
                let after = k.stats();
                let ops = |s: &kuka_krc::KrcStats| s.file_calls.values().sum::<u64>();
                let reads = |s: &kuka_krc::KrcStats| s.file_calls.get("krl_fgets").copied().unwrap_or(0);
                println!("-- 5. the Submit side over that path (KRL program, 12 ms cycle, budget {})", t.config.simulator.submit_budget);
                println!(
                    "file operations per motion: {:.3} (krl_fgets {:.3}); Submit passes {}, over the budget {}; statements per pass p50/p99/max (whole run) {}/{}/{}",
                    (ops(&after) - ops(&before)) as f64 / 10_000.0,
                    (reads(&after) - reads(&before)) as f64 / 10_000.0,
                    after.passes - before.passes,
                    after.passes_overrun - before.passes_overrun,
                    after.pass_statements_p50,
                    after.pass_statements_p99,
                    after.pass_statements_max
                );
            }
            t.service.shutdown().await.expect("shutdown");
        }

        if want(3) {
            // 3. A long path streamed from a client, generated on the fly; twice:
            // the first run warms up (allocator, the simulator's bounded trace
            // buffer), the second shows whether memory grows with the path.
            let t = service(kind, 0.0).await;
            to_start(&t, &turn[0]).await;
            println!("-- 3. {long}-point path streamed as JSON lines, twice (the second after clearing the trace)");
            for run in 1..=2 {
                let (s, _) = t.delete("/api/v1/sim/trace").await;
                assert!(s == 200 || s == 204, "clear the trace: {s}");
                let rss0 = rss_mib(None).unwrap_or(0.0);
                let peak = std::sync::Arc::new(std::sync::Mutex::new(rss0));
                let watch = {
                    let peak = peak.clone();
                    tokio::spawn(async move {
                        loop {
                            if let Some(r) = rss_mib(None) {
                                let mut p = peak.lock().expect("peak");
                                *p = p.max(r);
                            }
                            tokio::time::sleep(Duration::from_millis(100)).await;
                        }
                    })
                };
                let chunks = (0..long).collect::<Vec<_>>();
                let lines = futures_util::stream::iter(
                    chunks
                        .chunks(500)
                        .map(|c| {
                            let text: String = c
                                .iter()
                                .map(|i| format!("{}\n", lin(&turn[(i + 1) % 100], 0.3)))
                                .collect();
                            Ok::<_, std::io::Error>(text)
                        })
                        .collect::<Vec<_>>(),
                );
                // Opened once the body is ready: at time scale 0 the simulated
                // clock races ahead, and a path idle for 5 s (simulated) ends.
                let id = open_path(&t).await;
                let wall = Instant::now();
                // No client timeout: the stream lasts as long as the robot needs.
                let client = reqwest::Client::new();
                let r = client
                    .post(t.url(&format!("/api/v1/paths/{id}/motions")))
                    .header("content-type", "application/x-ndjson")
                    .body(reqwest::Body::wrap_stream(lines))
                    .send()
                    .await
                    .expect("stream");
                let status = r.status();
                let v: Value = r.json().await.expect("outcome");
                assert!(
                    status.is_success() && v["total"].as_u64() == Some(long as u64),
                    "the stream was not taken whole: {status} {v}"
                );
                let j = wait_end(&t, id).await;
                watch.abort();
                let rss1 = rss_mib(None).unwrap_or(0.0);
                let peak = *peak.lock().expect("peak");
                println!(
                    "run {run}: {} ({} motions done, appended {}), wall {:.1} s; RSS before {rss0:.1} MiB, peak {peak:.1} MiB (+{:.1}), after {rss1:.1} MiB",
                    j["state"],
                    j["completed"],
                    v["total"],
                    wall.elapsed().as_secs_f64(),
                    peak - rss0
                );
            }
            t.service.shutdown().await.expect("shutdown");
        }

        if want(4) {
            // 4. Position reads while a 2 s LIN runs.
            let t = service(kind, 1.0).await;
            to_start(&t, &[190.0, -100.0]).await;
            let body = json!({"motions": [{"type": "lin", "target": {"y": 100}, "velocity_m_s": 0.1}], "wait": false});
            let (s, job) = t.post_json("/api/v1/motions", &body).await;
            assert_eq!(s, 202, "{job}");
            let id = job["id"].as_u64().expect("id");
            t.wait_job(id, "the LIN to execute", |j| j["state"] == "executing")
                .await;
            let mut v1 = Vec::new();
            let mut thesis = Vec::new();
            let mut live = 0;
            for _ in 0..200 {
                let t0 = Instant::now();
                let (_, p) = t.get("/api/v1/position").await;
                v1.push(t0.elapsed());
                live += usize::from(p["source"] == "live");
                let t0 = Instant::now();
                let (_, _) = t.post("/krl/getpos").await;
                thesis.push(t0.elapsed());
            }
            let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
            v1.sort();
            thesis.sort();
            println!("-- 4. position reads during a 2 s LIN ({live} of 200 live; the LIN was still {} after them)", j["state"]);
            println!("GET /api/v1/position  p50 {:.2} ms  p99 {:.2} ms  max {:.2} ms", ms(percentile(&v1, 0.5)), ms(percentile(&v1, 0.99)), ms(*v1.last().expect("samples")));
            println!("POST /krl/getpos      p50 {:.2} ms  p99 {:.2} ms  max {:.2} ms", ms(percentile(&thesis, 0.5)), ms(percentile(&thesis, 0.99)), ms(*thesis.last().expect("samples")));
            t.service.shutdown().await.expect("shutdown");
        }

        if want(6) {
            // 6. Batches of 1, 100 and 1000 LINs (5 mm, 0.2 m/s, approximated):
            // real time from the request to the controller reporting it
            // executing (the robot moving), and on the KRL program the file
            // operations per motion over the whole batch.
            let t = service(kind, 1.0).await;
            println!("-- 6. batches: from the request to the robot moving (real time)");
            for n in [1usize, 100, 1000] {
                to_start(&t, &[190.0, -100.0]).await;
                let motions: Vec<Value> = (1..=n)
                    .map(|i| {
                        let y = -100.0 + 200.0 * i as f64 / n as f64;
                        json!({"type": "lin", "target": {"y": y}, "velocity_m_s": 0.2, "approx_mm": 2})
                    })
                    .collect();
                let before = t.service.krc.as_ref().map(|k| k.stats());
                let krc_t0 = t.service.krc.as_ref().map(|k| k.snapshot().time_ms);
                if let Some(k) = t.service.krc.as_ref() {
                    k.clear_trace();
                }
                // The controller's time when the command file changes (the
                // batch's command appears): a thread reads the file every
                // 0.2 ms until then.
                let appeared = t.service.krc.clone().map(|k| {
                    let dir = t.channel_dir();
                    let read = move || std::fs::read(dir.join(kuka_protocol::COMMAND_FILE)).ok();
                    let old = read();
                    std::thread::spawn(move || {
                        let deadline = Instant::now() + Duration::from_secs(10);
                        while read() == old && Instant::now() < deadline {
                            std::thread::sleep(Duration::from_micros(200));
                        }
                        k.snapshot().time_ms
                    })
                });
                let t0 = Instant::now();
                let (s, job) = t
                    .post_json("/api/v1/motions", &json!({"motions": motions, "wait": false}))
                    .await;
                assert_eq!(s, 202, "{job}");
                let id = job["id"].as_u64().expect("id");
                t.wait_job(id, "the batch to execute", |j| {
                    j["state"] == "executing" || j["state"] == "done"
                })
                .await;
                let started = t0.elapsed();
                let j = wait_end(&t, id).await;
                assert_eq!(j["state"], "done", "{j}");
                let ops = match (t.service.krc.as_ref(), before) {
                    (Some(k), Some(b)) => {
                        // Controller time from the request to the batch's first
                        // moving sample (the trace marks the command's CID).
                        let cid = j["cid"].as_i64().expect("cid");
                        let first = k
                            .trace()
                            .iter()
                            .find(|s| s.cid == cid && !s.stop)
                            .map(|s| (s.t * 1000.0).round() as i64);
                        let cycle = t.config.simulator.cycle_ms as f64;
                        let appeared = appeared.and_then(|h| h.join().ok());
                        let standstill = match (first, krc_t0, appeared) {
                            (Some(f), Some(t0), Some(a)) => format!(
                                ", first moving sample {} ms of controller time after the request ({:.1} cycles), {} ms after the command file appeared ({:.1} cycles)",
                                f - t0,
                                (f - t0) as f64 / cycle,
                                f - a,
                                (f - a) as f64 / cycle
                            ),
                            _ => String::new(),
                        };
                        let a = k.stats();
                        let sum = |s: &kuka_krc::KrcStats| s.file_calls.values().sum::<u64>();
                        let fgets = |s: &kuka_krc::KrcStats| s.file_calls.get("krl_fgets").copied().unwrap_or(0);
                        format!(
                            "{standstill}, file operations per motion {:.2} (krl_fgets {:.2})",
                            (sum(&a) - sum(&b)) as f64 / n as f64,
                            (fgets(&a) - fgets(&b)) as f64 / n as f64
                        )
                    }
                    _ => String::new(),
                };
                println!("batch of {n:>4}: reported executing after {:.0} ms{ops}", ms(started));
            }
            t.service.shutdown().await.expect("shutdown");
        }

        if want(7) {
            // 7. Splines (issue 22 point 3): a 50 mm circle at 0.2 m/s, real time.
            let t = service(kind, 1.0).await;
            let v = 0.2;
            for (name, n, how) in [
                ("8 LIN (approx 2 mm), one batch", 8, "lin"),
                ("8 SPL (one block), one batch", 8, "spl"),
                ("24 SPL (3 blocks), one batch", 24, "spl"),
                ("200 SPL, one per append to a path", 200, "path"),
            ] {
                let pts = circle(n, 50.0);
                let ideal = std::f64::consts::TAU * 50.0 / 1000.0 / v;
                to_start(&t, &pts[0]).await;
                let motion = |p: &[f64; 2]| {
                    if how == "lin" {
                        lin(p, v)
                    } else {
                        json!({"type": "spl", "target": {"x": p[0], "y": p[1]}, "velocity_m_s": v})
                    }
                };
                let cid = if how == "path" {
                    let id = open_path(&t).await;
                    for p in &pts[1..] {
                        let (s, o) = t
                            .post_json(&format!("/api/v1/paths/{id}/motions"), &json!({"motions": [motion(p)]}))
                            .await;
                        assert_eq!(s, 200, "{o}");
                    }
                    let (s, _) = t.delete(&format!("/api/v1/paths/{id}")).await;
                    assert_eq!(s, 200);
                    let j = wait_end(&t, id).await;
                    assert_eq!(j["state"], "done", "{j}");
                    j["cid"].as_i64().expect("cid")
                } else {
                    let batch: Vec<Value> = pts[1..].iter().map(motion).collect();
                    let (s, b) = t.post_json("/api/v1/motions", &json!({"motions": batch})).await;
                    assert_eq!(s, 200, "{b}");
                    b["cid"].as_i64().expect("cid")
                };
                let trace: Vec<_> = t.trace().into_iter().filter(|x| x.cid == cid).collect();
                let span = trace.last().map_or(0.0, |l| l.t) - trace.first().map_or(0.0, |f| f.t);
                // Slow stretches (below a quarter of the speed over 48 ms)
                // between the first and the last sample at speed.
                let speeds: Vec<f64> = trace
                    .windows(5)
                    .map(|w| {
                        let d = ((w[4].pose[0] - w[0].pose[0]).powi(2) + (w[4].pose[1] - w[0].pose[1]).powi(2)).sqrt();
                        d / (w[4].t - w[0].t).max(1e-9)
                    })
                    .collect();
                let fast = |x: &f64| *x >= 0.25 * v * 1000.0;
                let stops = match (speeds.iter().position(fast), speeds.iter().rposition(fast)) {
                    (Some(a), Some(b)) => speeds[a..=b]
                        .windows(2)
                        .filter(|w| fast(&w[0]) && !fast(&w[1]))
                        .count(),
                    _ => 0,
                };
                // Off the circle, away from the first and last 45° (a
                // block's outer tangents are mirrored).
                let off = trace
                    .iter()
                    .filter(|x| {
                        let a = x.pose[1].atan2(x.pose[0] - 190.0).rem_euclid(std::f64::consts::TAU).to_degrees();
                        (45.0..=315.0).contains(&a)
                    })
                    .map(|x| ((x.pose[0] - 190.0).hypot(x.pose[1]) - 50.0).abs())
                    .fold(0.0, f64::max);
                println!(
                    "{name}: {span:.3} s ({:.3}× the circle at 0.2 m/s), {stops} stops, up to {off:.2} mm off the circle",
                    span / ideal
                );
            }
            t.service.shutdown().await.expect("shutdown");
        }
    });
}

//! Benchmark of the whole bridge (results in docs/BENCHMARKS.md):
//!
//! 1. command round trip through HTTP with the instant simulator: the
//!    thesis `POST /krl/getpos` (HTTP → engine → command file → simulated
//!    controller → result file → engine → HTTP) and a small `POST
//!    /api/v1/motions`; p50/p90/p99/max over many sequential requests.
//! 2. a 200-segment polyline (an 80 mm-radius circle, 0.2 m/s): one
//!    blended batch versus one request per segment, in simulated seconds
//!    against the ideal path time (length / speed).
//!
//! Run: `cargo bench -p kuka-bridge-tests --bench bridge` (optionally
//! `-- N` for the number of round trips, default 5000). The channel
//! directory lives in the system temp directory; set `KB_BENCH_DIR` to put
//! it elsewhere (e.g. `/dev/shm` to take the disk out of the measurement).

use std::time::{Duration, Instant};

use kuka_bridge_tests::bench::{raw_round_trips, report};
use kuka_bridge_tests::{Options, TestService};
use serde_json::{Value, json};

async fn round_trips(
    t: &TestService,
    n: usize,
    request: impl Fn() -> reqwest::RequestBuilder,
) -> Vec<Duration> {
    // Warm up connections and caches.
    for _ in 0..200 {
        let r = request().send().await.expect("request");
        assert!(
            r.status().is_success(),
            "{}",
            r.text().await.unwrap_or_default()
        );
    }
    let _ = t;
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let start = Instant::now();
        let r = request().send().await.expect("request");
        let ok = r.status().is_success();
        let _ = r.bytes().await;
        out.push(start.elapsed());
        assert!(ok);
    }
    out
}

fn circle_polyline(segments: usize, radius: f64) -> Vec<[f64; 2]> {
    (0..=segments)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / segments as f64;
            [190.0 + radius * a.cos(), radius * a.sin()]
        })
        .collect()
}

async fn sim_time(t: &TestService) -> f64 {
    let (_, v) = t.get("/api/v1/sim").await;
    v["sim_time_s"].as_f64().expect("sim time")
}

fn main() {
    let n: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(5000);
    let rt = kuka_bridge_tests::bench::runtime();
    // Removed when the bench ends (it is not inside the service's data dir).
    let channel_dir =
        std::env::var_os("KB_BENCH_DIR").map(|dir| tempfile::tempdir_in(dir).expect("bench dir"));
    let channel_path = channel_dir.as_ref().map(|d| d.path().to_path_buf());
    rt.block_on(async move {
        let t = TestService::start(Options {
            time_scale: 0.0,
            tweak: Box::new(move |c| {
                if let Some(dir) = &channel_path {
                    c.channel.dir = Some(dir.clone());
                }
                c.channel.poll_interval_ms = 50;
                c.simulator.heartbeat_ms = 50;
                c.channel.offline_after_ms = 2000;
            }),
            ..Options::default()
        })
        .await;
        println!("kuka-bridge benchmark ({} CPUs)", std::thread::available_parallelism().map_or(0, |n| n.get()));
        println!("channel directory: {}", t.service.sim.as_ref().expect("sim").channel_dir().display());
        println!("-- command round trip without HTTP (engine API), instant simulator");
        let engine = t.service.engine.clone();
        let mut samples = Vec::with_capacity(n);
        for i in 0..n + 200 {
            let start = Instant::now();
            engine
                .execute(
                    kuka_bridge::engine::Operation::GetPosition,
                    None,
                    Duration::from_secs(5),
                    kuka_bridge::engine::Caller::default(),
                )
                .await
                .expect("get position");
            if i >= 200 {
                samples.push(start.elapsed());
            }
        }
        report("engine.execute(GetPosition)", samples);
        println!("-- command round trip through HTTP, instant simulator, sequential requests");
        let url = t.url("/krl/getpos");
        let http = t.http.clone();
        report("POST /krl/getpos", round_trips(&t, n, || http.post(&url)).await);
        let addr = t.service.addr;
        let raw = tokio::task::spawn_blocking(move || {
            raw_round_trips(addr, "POST /krl/getpos HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\n\r\n", n)
        })
        .await
        .expect("raw client");
        report("POST /krl/getpos (plain TCP client)", raw);
        let addr = t.service.addr;
        let raw = tokio::task::spawn_blocking(move || {
            raw_round_trips(addr, "GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n", n)
        })
        .await
        .expect("raw client");
        report("GET /health (plain TCP client)", raw);
        let url = t.url("/api/v1/motions");
        let http = t.http.clone();
        let small = json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 1}, "relative": true}]});
        let back = json!({"motions": [{"type": "ptp_axes", "axes": {"a1": -1}, "relative": true}]});
        let flip = std::sync::atomic::AtomicBool::new(false);
        let samples = round_trips(&t, n, || {
            let b = if flip.fetch_xor(true, std::sync::atomic::Ordering::Relaxed) { &back } else { &small };
            http.post(&url).json(b)
        })
        .await;
        report("POST /api/v1/motions (1 axis PTP)", samples);

        // Pen down on the KR 3 R540: the circle stays inside the region where
        // A5 < 0 (A5 passes 0 about 290 mm from the base), so no singularity.
        println!("-- 200-segment polyline (circle r = 80 mm, 0.2 m/s), simulated seconds");
        let segments = 200;
        let radius = 80.0;
        let speed = 0.2;
        let pts = circle_polyline(segments, radius);
        let length_mm: f64 = pts.windows(2).map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt()).sum();
        let ideal = length_mm / 1000.0 / speed;
        let start = json!({"motions": [{"type": "ptp", "target": {"x": pts[0][0], "y": pts[0][1], "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]});
        let (s, v) = t.post_json("/api/v1/motions", &start).await;
        assert_eq!(s, 200, "{v}");
        let lin = |p: &[f64; 2]| json!({"type": "lin", "target": {"x": p[0], "y": p[1]}, "velocity_m_s": speed, "approx_mm": 2});
        let batch: Vec<Value> = pts[1..].iter().map(lin).collect();
        let t0 = sim_time(&t).await;
        let wall = Instant::now();
        let (s, v) = t.post_json("/api/v1/motions", &json!({ "motions": batch })).await;
        let batch_wall = wall.elapsed();
        assert_eq!(s, 200, "{v}");
        let batch_time = sim_time(&t).await - t0;
        let t1 = sim_time(&t).await;
        let wall = Instant::now();
        for p in &pts[1..] {
            let (s, v) = t.post_json("/api/v1/motions", &json!({ "motions": [lin(p)] })).await;
            assert_eq!(s, 200, "{v}");
        }
        let single_wall = wall.elapsed();
        let single_time = sim_time(&t).await - t1;
        println!("path length {length_mm:.1} mm, ideal time (length / speed) {ideal:.3} s");
        println!(
            "one batch of {segments}:        {batch_time:>7.3} s simulated = {:.3}× ideal   (HTTP wall time {:.1} ms)",
            batch_time / ideal,
            batch_wall.as_secs_f64() * 1e3
        );
        println!(
            "{segments} requests of one:  {single_time:>7.3} s simulated = {:.3}× ideal   (HTTP wall time {:.1} ms)",
            single_time / ideal,
            single_wall.as_secs_f64() * 1e3
        );
        t.service.shutdown().await.expect("shutdown");
    });
}

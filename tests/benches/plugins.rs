//! Benchmark of the WASM plugin host through the running service (results
//! in docs/BENCHMARKS.md):
//!
//! 1. overhead of a plugin endpoint over a native one: `GET
//!    /api/v1/plugins/misbehave/ping` (fresh instance, `handle`, JSON
//!    answer, identified like a native read) against `GET /api/v1/state`,
//!    and the POST route `/ok` (JSON body, audited) against `POST
//!    /api/v1/control` (the same: renews the bench's lease), both also
//!    against the bare `GET /health`;
//!    keep-alive requests from a plain TCP client, one of each kind in turn;
//!    p50/p90/p99/max of each and the median of the paired differences;
//! 2. install of a plugin compiled from scratch (`PUT`, new bytes each time),
//!    for the Rust draw-circle (and the Python py-square with `--python`);
//! 3. reinstall of the same bytes, which loads the compiled artifact from
//!    the cache (the path of a restart or a reload);
//! 4. resident memory of the process before and after installing 10
//!    plugins (Linux: VmRSS from /proc/self/status);
//! 5. with `--memory` (only this part; Linux, needs Python): the memory of
//!    the service in a process of its own (`kuka-bridge run`, VmRSS, RssAnon
//!    and RssFile from /proc/<pid>/status) before installing the Python
//!    example py-square, installed, after 3 calls and after its removal,
//!    for 3 install/remove cycles (the first compiles, the others load the
//!    compiled cache).
//!
//! Run: `cargo bench -p kuka-bridge-tests --bench plugins [-- N] [-- --python]`
//! (N round trips, default 5000), or `... -- --memory`. The ten plugins are
//! copies of draw-circle whose 11-byte name string is replaced in place
//! (`bench-pl-00` ...), so each is a distinct component with its own
//! compiled code.

use std::path::Path;
use std::time::{Duration, Instant};

use kuka_bridge_tests::bench::{interleaved_round_trips, paired_median_us, report};
use kuka_bridge_tests::{Options, TestService};
use serde_json::Value;

/// `wasm` with every occurrence of `from` replaced by `to` (same length).
fn renamed(wasm: &[u8], from: &str, to: &str) -> Vec<u8> {
    assert_eq!(from.len(), to.len());
    let mut out = wasm.to_vec();
    let mut i = 0;
    while let Some(pos) = out[i..]
        .windows(from.len())
        .position(|w| w == from.as_bytes())
    {
        out[i + pos..i + pos + from.len()].copy_from_slice(to.as_bytes());
        i += pos + from.len();
    }
    out
}

async fn put(t: &TestService, name: &str, wasm: Vec<u8>) -> (Duration, Value) {
    let start = Instant::now();
    let (status, v) = t.put_bytes(&format!("/api/v1/plugins/{name}"), wasm).await;
    let took = start.elapsed();
    assert!(
        status == 200 || status == 201,
        "install {name}: {status} {v}"
    );
    (took, v)
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1000.0
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// `VmRSS`, `RssAnon` and `RssFile` of a process, MiB (Linux).
fn rss_parts(pid: u32) -> [f64; 3] {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    ["VmRSS:", "RssAnon:", "RssFile:"].map(|key| {
        status
            .lines()
            .find_map(|l| l.strip_prefix(key))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
            .map_or(f64::NAN, |kb| kb / 1024.0)
    })
}

fn show(what: &str, [rss, anon, file]: [f64; 3]) {
    println!("  {what:<38} VmRSS {rss:6.1} MiB  (anonymous {anon:6.1}, file {file:5.1})");
}

/// Part 5: install, call and remove py-square in a service of its own,
/// three times; the memory it holds at each step.
fn memory(py: Vec<u8>) {
    let root = tempfile::tempdir().expect("tempdir");
    let dir = |d: &str| root.path().join(d).to_string_lossy().into_owned();
    let service = kuka_bridge_tests::CliService::spawn(
        env!("CARGO_BIN_EXE_kuka-bridge-cli"),
        "warn",
        [
            "--simulate",
            "--time-scale",
            "0",
            "--listen",
            "127.0.0.1:0",
            "--data-dir",
            &dir("data"),
            "--channel-dir",
            &dir("channel"),
        ],
    );
    let pid = service.pid();
    let rt = kuka_bridge_tests::bench::runtime();
    let http = reqwest::Client::new();
    let url = |p: &str| format!("{}{p}", service.url());
    rt.block_on(async {
        let wait_online = Instant::now() + Duration::from_secs(30);
        loop {
            let r = http.get(url("/health")).send().await.expect("health");
            let (_, h) = kuka_bridge_tests::decode(r).await;
            if h["connection"] == "online" {
                break;
            }
            assert!(Instant::now() < wait_online, "never online: {h}");
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
        tokio::time::sleep(Duration::from_secs(1)).await;
        println!(
            "-- memory of the service process (pid {pid}) with py-square ({:.1} MB)",
            py.len() as f64 / 1e6
        );
        let start = rss_parts(pid);
        show("started", start);
        for cycle in 1..=3 {
            let took = Instant::now();
            let r = http
                .put(url("/api/v1/plugins/py-square"))
                .body(py.clone())
                .send()
                .await
                .expect("install");
            let (status, v) = kuka_bridge_tests::decode(r).await;
            assert_eq!(status, 201, "{v}");
            let how = if v["from_cache"] == true {
                "from the cache"
            } else {
                "compiled"
            };
            show(
                &format!(
                    "{cycle}: installed ({how}, {:.1} s)",
                    took.elapsed().as_secs_f64()
                ),
                rss_parts(pid),
            );
            for _ in 0..3 {
                let body = serde_json::json!({"x": 300, "y": 0, "z": 100, "side": 20});
                let r = http
                    .post(url("/api/v1/plugins/py-square/square"))
                    .json(&body)
                    .send()
                    .await
                    .expect("call");
                let (status, v) = kuka_bridge_tests::decode(r).await;
                assert_eq!(status, 200, "{v}");
            }
            show(&format!("{cycle}: after 3 calls"), rss_parts(pid));
            let r = http
                .delete(url("/api/v1/plugins/py-square"))
                .send()
                .await
                .expect("remove");
            assert_eq!(r.status().as_u16(), 204);
            // The memory goes back on a blocking thread, just after the answer.
            tokio::time::sleep(Duration::from_secs(2)).await;
            let after = rss_parts(pid);
            show(&format!("{cycle}: removed (+2 s)"), after);
            println!(
                "  {cycle}: removed - started: {:+.1} MiB",
                after[0] - start[0]
            );
        }
    });
    drop(service);
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.iter().find_map(|a| a.parse().ok()).unwrap_or(5000);
    let python = args.iter().any(|a| a == "--python");
    if args.iter().any(|a| a == "--memory") {
        let examples =
            kuka_bridge_tests::example_plugins(Path::new(env!("CARGO_TARGET_TMPDIR")), true);
        memory(std::fs::read(examples.join("py-square.wasm")).expect("py-square.wasm"));
        return;
    }
    let examples =
        kuka_bridge_tests::example_plugins(Path::new(env!("CARGO_TARGET_TMPDIR")), python);
    let read =
        |name: &str| std::fs::read(examples.join(format!("{name}.wasm"))).expect("built plugin");
    let rt = kuka_bridge_tests::bench::runtime();
    rt.block_on(async move {
        let t = TestService::start(Options {
            time_scale: 0.0,
            tweak: Box::new(|c| {
                c.simulator.heartbeat_ms = 50;
                c.channel.offline_after_ms = 2000;
            }),
            ..Options::default()
        })
        .await;
        println!(
            "kuka-bridge plugin benchmark ({} CPUs)",
            std::thread::available_parallelism().map_or(0, |n| n.get())
        );
        let rss_start = kuka_bridge_tests::bench::rss_mib(None);

        println!("-- install compiled from scratch (PUT, new bytes each time), then 10 plugins resident");
        let circle = read("draw-circle");
        let (mut http_ms, mut load_ms) = (Vec::new(), Vec::new());
        for i in 0..10 {
            let name = format!("bench-pl-{i:02}");
            let (took, v) = put(&t, &name, renamed(&circle, "draw-circle", &name)).await;
            assert_eq!(v["from_cache"], false, "{v}");
            http_ms.push(ms(took));
            load_ms.push(v["load_ms"].as_f64().expect("load_ms"));
        }
        println!(
            "draw-circle ({} KB)  install p50 {:.1} ms (HTTP), load p50 {:.1} ms (compile + link + describe), n=10",
            circle.len() / 1024,
            median(http_ms),
            median(load_ms)
        );
        // Every plugin serves once, so their code is really resident.
        for i in 0..10 {
            let body = serde_json::json!({"x": 300, "y": 20, "z": 100, "radius": 10});
            let (status, v) = t.post_json(&format!("/api/v1/plugins/bench-pl-{i:02}/circle"), &body).await;
            assert_eq!(status, 200, "{v}");
        }
        let rss_10 = kuka_bridge_tests::bench::rss_mib(None);
        match (rss_start, rss_10) {
            (Some(a), Some(b)) => println!(
                "RSS: {a:.1} MiB with no plugin, {b:.1} MiB with 10 installed and called once ({:.2} MiB per plugin)",
                (b - a) / 10.0
            ),
            _ => println!("RSS: not measured on this OS"),
        }

        println!("-- reinstall of the same bytes: compiled code from the cache");
        let (mut http_ms, mut load_ms) = (Vec::new(), Vec::new());
        for _ in 0..20 {
            let (took, v) = put(&t, "bench-pl-00", renamed(&circle, "draw-circle", "bench-pl-00")).await;
            assert_eq!(v["from_cache"], true, "{v}");
            http_ms.push(ms(took));
            load_ms.push(v["load_ms"].as_f64().expect("load_ms"));
        }
        println!(
            "draw-circle reload  p50 {:.2} ms (HTTP, 165 KB upload), load p50 {:.2} ms (deserialize + link + describe), n=20",
            median(http_ms),
            median(load_ms)
        );

        if python {
            let py = read("py-square");
            let (took, v) = put(&t, "py-square", py.clone()).await;
            println!(
                "py-square ({:.1} MB) install {:.0} ms (HTTP), load {:.0} ms, from_cache {}",
                py.len() as f64 / 1e6,
                ms(took),
                v["load_ms"].as_f64().unwrap_or(f64::NAN),
                v["from_cache"]
            );
            let (took, v) = put(&t, "py-square", py).await;
            println!(
                "py-square reload {:.0} ms (HTTP), load {:.1} ms, from_cache {}",
                ms(took),
                v["load_ms"].as_f64().unwrap_or(f64::NAN),
                v["from_cache"]
            );
            let body = serde_json::json!({"x": 300, "y": 0, "z": 100, "side": 20});
            let start = Instant::now();
            let (status, v) = t.post_json("/api/v1/plugins/py-square/square", &body).await;
            assert_eq!(status, 200, "{v}");
            println!("py-square call (5 motions, instant simulator) {:.1} ms", ms(start.elapsed()));
        }

        println!("-- plugin endpoint vs native endpoint, plain TCP client, sequential");
        let (status, v) = t.put_bytes("/api/v1/plugins/misbehave", read("misbehave")).await;
        assert_eq!(status, 201, "{v}");
        // One request of each kind in turn, so machine noise hits all alike;
        // the overhead is the median of the paired differences.
        let addr = t.service.addr;
        let kinds = [
            ("GET /health (native)", "GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"),
            ("GET /api/v1/state (native)", "GET /api/v1/state HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"),
            (
                "POST /api/v1/control (native)",
                "POST /api/v1/control HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: 2\r\n\r\n{}",
            ),
            ("GET /api/v1/plugins/misbehave/ping", "GET /api/v1/plugins/misbehave/ping HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"),
            (
                "POST /api/v1/plugins/misbehave/ok",
                "POST /api/v1/plugins/misbehave/ok HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: 2\r\n\r\n{}",
            ),
        ];
        let requests: Vec<&'static str> = kinds.iter().map(|k| k.1).collect();
        let times = tokio::task::spawn_blocking(move || interleaved_round_trips(addr, &requests, n))
            .await
            .expect("raw client");
        for ((name, _), t) in kinds.iter().zip(&times) {
            report(name, t.clone());
        }
        // Like for like first: GET identified vs GET identified, POST audited
        // with a JSON body vs the same; then against the bare /health.
        for (k, base) in [(3, 1), (4, 2), (3, 0), (4, 0)] {
            println!(
                "{} - {}: median of {n} paired differences {:.1} µs",
                kinds[k].0,
                kinds[base].0,
                paired_median_us(&times[base], &times[k])
            );
        }
        let rss_end = kuka_bridge_tests::bench::rss_mib(None);
        if let Some(r) = rss_end {
            println!("RSS at the end: {r:.1} MiB");
        }
        let TestService { service, .. } = t;
        service.shutdown().await.expect("shutdown");
    });
}

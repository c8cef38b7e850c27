//! Soak benchmark (docs/SECURITY.md): many concurrent clients against the
//! service with access control on, for minutes, checking that nothing goes
//! wrong under sustained load:
//!
//! - the service runs as its own process (`kuka-bridge run --simulate
//!   --require-auth`, simulator at `--time-scale 0`), so its memory is its
//!   own; every client has its own operator token;
//! - each client loops over a mix: a motion batch of 1–4 PTP/LIN motions
//!   between two poses (`wait: true`, 50 %), `GET /api/v1/state` (25 %),
//!   `GET /api/v1/jobs/{its last job}` (15 %), thesis `POST /krl/getpos`
//!   (10 %);
//! - any answer other than 200 is an unexpected error;
//! - no lost or duplicated motion: every motion request gives exactly one
//!   done job with all its motions completed and its own command id (CIDs
//!   never repeat), every such CID shows all its motion indices in the
//!   simulator's executed trace, and the audit trail holds exactly one
//!   record per motion request with that job;
//! - memory flat: the service's RSS (Linux `/proc/<pid>/status`) sampled
//!   every 10 s; the first and last minute are compared.
//!
//! Run: `cargo bench -p kuka-bridge-tests --bench soak -- [--clients 64]
//! [--minutes 10]`. Not part of CI (it takes the given minutes).

use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use tokio::sync::Mutex;

fn arg(name: &str, default: u64) -> u64 {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// What the clients saw.
#[derive(Default)]
struct Seen {
    /// Motion requests sent and answered 200.
    motion_requests: u64,
    /// job id → (cid, motions).
    jobs: BTreeMap<u64, (i64, u64)>,
    /// Unexpected answers: "status path detail".
    errors: Vec<String>,
    /// Requests per kind.
    counts: BTreeMap<&'static str, u64>,
}

fn batch(n: usize, flip: bool) -> Value {
    // Two poses the KR 3 R540 reaches with the flange down; alternate so
    // every motion really moves.
    let (a, b) = ((300.0, -40.0, 120.0), (300.0, 40.0, 160.0));
    let motions: Vec<Value> = (0..n)
        .map(|i| {
            let (x, y, z) = if (i % 2 == 0) ^ flip { a } else { b };
            let kind = if i % 2 == 0 { "ptp" } else { "lin" };
            json!({"type": kind, "target": {"x": x, "y": y, "z": z, "a": 0, "b": 180, "c": 0}})
        })
        .collect();
    json!({"motions": motions})
}

fn main() {
    let clients = arg("--clients", 64) as usize;
    let minutes = arg("--minutes", 10);
    let data = tempfile::tempdir().expect("tempdir");
    let data_dir = data.path().join("data");
    let mut service = kuka_bridge_tests::CliService::spawn(
        env!("CARGO_BIN_EXE_kuka-bridge-cli"),
        "warn",
        [
            "--simulate",
            "--require-auth",
            "--listen",
            "127.0.0.1:0",
            "--time-scale",
            "0",
            "--data-dir",
            data_dir.to_str().expect("a UTF-8 temporary path"),
        ],
    );
    let pid = service.pid();
    let url = service.url().to_string();
    let admin = kuka_bridge_tests::initial_admin_secret(&data_dir);
    println!("soak: {clients} clients for {minutes} min against {url} (pid {pid})");

    let rt = kuka_bridge_tests::bench::runtime();
    let seen = Arc::new(Mutex::new(Seen::default()));
    let trace_gaps = Arc::new(AtomicU64::new(0));
    let total = Arc::new(AtomicU64::new(0));
    let (rss, trace) = rt.block_on(async {
        let http = reqwest::Client::builder()
            .timeout(Duration::from_secs(60))
            .pool_max_idle_per_host(clients)
            .build()
            .expect("client");
        // One operator token per client.
        let mut tokens = Vec::new();
        for i in 0..clients {
            let v: Value = http
                .post(format!("{url}/api/v1/tokens"))
                .bearer_auth(&admin)
                .json(&json!({"name": format!("soak-{i:02}"), "role": "operator"}))
                .send()
                .await
                .expect("create token")
                .json()
                .await
                .expect("json");
            tokens.push(v["secret"].as_str().expect("secret").to_string());
        }
        let _ = http
            .post(format!("{url}/api/v1/home"))
            .bearer_auth(&admin)
            .send()
            .await;
        let _ = http
            .delete(format!("{url}/api/v1/sim/trace"))
            .bearer_auth(&admin)
            .send()
            .await;
        let end = Instant::now() + Duration::from_secs(minutes * 60);

        // The executed trace: command id → motion indices seen.
        let trace: Arc<Mutex<BTreeMap<i64, BTreeSet<u64>>>> = Arc::default();
        let poller = {
            let (http, url, admin, trace) =
                (http.clone(), url.clone(), admin.clone(), trace.clone());
            let gaps = trace_gaps.clone();
            tokio::spawn(async move {
                // `since` is exclusive: ask from just before the last time
                // seen, as a zero-length motion (a target the robot is at)
                // adds a sample with the same time after the poll.
                let mut since = f64::NEG_INFINITY;
                loop {
                    let done = Instant::now() > end + Duration::from_secs(5);
                    let q = if since.is_finite() {
                        format!("?since={}", since - 1e-6)
                    } else {
                        String::new()
                    };
                    if let Ok(r) = http
                        .get(format!("{url}/api/v1/sim/trace{q}"))
                        .bearer_auth(&admin)
                        .send()
                        .await
                        && let Ok(samples) = r.json::<Vec<Value>>().await
                    {
                        // The simulator keeps 200,000 samples: a poll that
                        // comes back with a gap of simulated time means the
                        // buffer overflowed in between (the trace lost
                        // samples, not the robot motions).
                        if let Some(first) = samples.first().and_then(|s| s["t"].as_f64())
                            && since.is_finite()
                            && first - since > 0.5
                        {
                            gaps.fetch_add(1, Ordering::Relaxed);
                        }
                        let mut t = trace.lock().await;
                        for s in &samples {
                            let cid = s["cid"].as_i64().unwrap_or(-1);
                            let m = s["motion"].as_u64().unwrap_or(u64::MAX);
                            t.entry(cid).or_default().insert(m);
                            since = since.max(s["t"].as_f64().unwrap_or(since));
                        }
                        drop(t);
                        // Keep the simulator's trace buffer from filling.
                        if samples.len() > 20_000 {
                            continue;
                        }
                    }
                    if done {
                        return;
                    }
                    tokio::time::sleep(Duration::from_millis(50)).await;
                }
            })
        };
        let sampler = tokio::spawn(async move {
            let mut samples = Vec::new();
            while Instant::now() < end {
                if let Some(m) = kuka_bridge_tests::bench::rss_mib(Some(pid)) {
                    samples.push(m);
                }
                tokio::time::sleep(Duration::from_secs(10)).await;
            }
            samples
        });
        let mut tasks = Vec::new();
        for (i, token) in tokens.into_iter().enumerate() {
            let (http, url, seen, total) = (http.clone(), url.clone(), seen.clone(), total.clone());
            tasks.push(tokio::spawn(async move {
                let mut n: u64 = i as u64;
                let mut last_job: Option<u64> = None;
                while Instant::now() < end {
                    n = n
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    let pick = (n >> 33) % 100;
                    let (kind, req) = if pick < 50 {
                        let count = 1 + ((n >> 40) % 4) as usize;
                        (
                            "motions",
                            http.post(format!("{url}/api/v1/motions"))
                                .json(&batch(count, (n >> 45).is_multiple_of(2))),
                        )
                    } else if pick < 75 {
                        ("state", http.get(format!("{url}/api/v1/state")))
                    } else if pick < 90 && last_job.is_some() {
                        (
                            "job",
                            http.get(format!("{url}/api/v1/jobs/{}", last_job.unwrap_or(0))),
                        )
                    } else {
                        ("getpos", http.post(format!("{url}/krl/getpos")))
                    };
                    let answer = req.bearer_auth(&token).send().await;
                    total.fetch_add(1, Ordering::Relaxed);
                    let (status, body) = match answer {
                        Ok(r) => {
                            let s = r.status().as_u16();
                            (s, r.json::<Value>().await.unwrap_or(Value::Null))
                        }
                        Err(e) => (0, json!({"detail": e.to_string()})),
                    };
                    let mut s = seen.lock().await;
                    *s.counts.entry(kind).or_default() += 1;
                    if status != 200 {
                        s.errors.push(format!("{status} {kind} {}", body["detail"]));
                        continue;
                    }
                    if kind == "motions" {
                        s.motion_requests += 1;
                        let id = body["id"].as_u64().unwrap_or(0);
                        let cid = body["cid"].as_i64().unwrap_or(-1);
                        let motions = body["motions"].as_u64().unwrap_or(0);
                        if body["state"] != "done" || body["completed"].as_u64() != Some(motions) {
                            s.errors.push(format!("job {id} not complete: {body}"));
                        }
                        if s.jobs.insert(id, (cid, motions)).is_some() {
                            s.errors.push(format!("job {id} answered twice"));
                        }
                        last_job = Some(id);
                    }
                }
            }));
        }
        for t in tasks {
            let _ = t.await;
        }
        let rss = sampler.await.unwrap_or_default();
        let _ = poller.await;
        let trace = Arc::try_unwrap(trace)
            .map(Mutex::into_inner)
            .unwrap_or_default();
        // The audit trail: one record per motion request, each with its job.
        let audit: Vec<Value> = http
            .get(format!(
                "{url}/api/v1/audit?path=/api/v1/motions&limit=1000"
            ))
            .bearer_auth(&admin)
            .send()
            .await
            .expect("audit")
            .json()
            .await
            .unwrap_or_default();
        println!(
            "audit sample: {} newest motion records read back",
            audit.len()
        );
        (rss, trace)
    });
    service.terminate();
    service.wait_exit(Duration::from_secs(60), "after SIGTERM");

    let seen = Arc::try_unwrap(seen)
        .map(Mutex::into_inner)
        .unwrap_or_default();
    let mut problems = seen.errors.clone();
    // Command ids never repeat; every motion of every job was executed.
    let mut cids = HashSet::new();
    let mut motions_total = 0;
    for (id, (cid, motions)) in &seen.jobs {
        motions_total += motions;
        if !cids.insert(*cid) {
            problems.push(format!("cid {cid} used by two jobs (job {id})"));
        }
        let want: BTreeSet<u64> = (0..*motions).collect();
        match trace.get(cid) {
            Some(got) if *got == want => {}
            Some(got) => problems.push(format!(
                "job {id} cid {cid}: trace motions {got:?}, want {want:?}"
            )),
            None => problems.push(format!("job {id} cid {cid}: not in the executed trace")),
        }
    }
    // Every audited motion record (whole trail, from the files).
    let mut audited = 0u64;
    let mut audited_jobs = HashSet::new();
    if let Ok(dir) = std::fs::read_dir(data_dir.join("logs/audit")) {
        for f in dir.flatten() {
            let name = f.file_name().to_string_lossy().into_owned();
            if !name.starts_with("audit.") {
                continue;
            }
            for line in std::fs::read_to_string(f.path())
                .unwrap_or_default()
                .lines()
            {
                let Ok(r) = serde_json::from_str::<Value>(line) else {
                    continue;
                };
                if r["path"] == "/api/v1/motions" && r["status"] == 200 {
                    audited += 1;
                    for j in r["jobs"].as_array().into_iter().flatten() {
                        if !audited_jobs.insert(j.as_u64().unwrap_or(0)) {
                            problems.push(format!("job {j} audited twice"));
                        }
                    }
                }
            }
        }
    }
    if audited != seen.motion_requests {
        problems.push(format!(
            "{audited} audited motion requests, {} answered",
            seen.motion_requests
        ));
    }
    let mins = rss.len().min(6);
    let first = rss.iter().take(mins).copied().fold(0.0, f64::max);
    let last = rss.iter().rev().take(mins).copied().fold(0.0, f64::max);
    println!(
        "requests: {} total ({:?}); motion jobs: {} with {} motions; unique cids: {}",
        total.load(Ordering::Relaxed),
        seen.counts,
        seen.jobs.len(),
        motions_total,
        cids.len()
    );
    println!(
        "throughput: {:.0} requests/s, {:.1} motion jobs/s",
        total.load(Ordering::Relaxed) as f64 / (minutes * 60) as f64,
        seen.jobs.len() as f64 / (minutes * 60) as f64
    );
    println!("RSS MiB (every 10 s): {rss:.1?}");
    println!("RSS: first minute max {first:.1} MiB, last minute max {last:.1} MiB");
    println!("unexpected errors / lost / duplicated: {}", problems.len());
    // By kind: numbers replaced, so that one line stands for many.
    let mut kinds: BTreeMap<String, usize> = BTreeMap::new();
    for p in &problems {
        let kind: String = p
            .chars()
            .map(|c| if c.is_ascii_digit() { '#' } else { c })
            .collect();
        *kinds.entry(kind).or_default() += 1;
    }
    for (kind, n) in &kinds {
        println!("  {n:>7} × {kind}");
    }
    for p in problems.iter().take(5) {
        println!("  e.g. {p}");
    }
    println!(
        "trace polls that found a gap (simulator trace buffer overflowed): {}",
        trace_gaps.load(Ordering::Relaxed)
    );
    if !problems.is_empty() {
        std::process::exit(1);
    }
}

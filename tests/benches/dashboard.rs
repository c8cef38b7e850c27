//! Benchmark of the dashboard in headless Chromium (results in
//! docs/BENCHMARKS.md): is the page responsive with a 10,000-point trace
//! at the controller's state rate?
//!
//! 1. a batch of slow LIN strokes (≥ 10,000 simulator samples, time scale
//!    0) is drawn; measured: the time from the motion's answer until the
//!    page holds every sample (trace fetched on events, not polled);
//! 2. with that path on the page: the cost of one redraw of both 2D
//!    projections and of one 3D frame (median of 30, synchronous);
//! 3. while the robot moves in real time with a 10 ms heartbeat (state
//!    events at up to 100 Hz) and the path keeps growing: the frame
//!    intervals of the page (requestAnimationFrame) over 5 s — p50, p95,
//!    max — and the long tasks (> 50 ms) the browser reported;
//! 4. the page's JavaScript heap (Chrome's `performance.memory`).
//!
//! Run: `cargo bench -p kuka-bridge-tests --bench dashboard` (needs
//! `chromium` and `chromedriver`; software WebGL). Prints one line per figure.

use std::time::{Duration, Instant};

use kuka_bridge_tests::browser::Browser;
use kuka_bridge_tests::{Options, TestService};
use serde_json::{Value, json};

const WAIT: Duration = Duration::from_secs(120);

/// Back-and-forth LIN strokes at 10 mm/s on the drawing plane: `n` strokes
/// of 100 mm (≈ 833 samples of 12 ms each).
fn strokes(n: usize, velocity_m_s: f64) -> Value {
    let mut motions = vec![
        json!({"type": "ptp", "target": {"x": 220, "y": -50, "z": 70, "a": 0, "b": 180, "c": 0, "s": 6}}),
    ];
    for i in 0..n {
        let y = if i % 2 == 0 { 50 } else { -50 };
        motions.push(json!({"type": "lin", "target": {"y": y, "x": 220 + (i % 5) as i64 * 5}, "velocity_m_s": velocity_m_s, "approx_mm": 0}));
    }
    json!({ "motions": motions })
}

fn main() {
    let rt = kuka_bridge_tests::bench::runtime();
    rt.block_on(run());
}

async fn run() {
    let Some(browser) = Browser::start().await else {
        eprintln!("chromium and chromedriver are needed for this benchmark");
        return;
    };
    browser.resize(1400, 1000).await;
    browser.goto("about:blank").await;
    let blank = browser
        .eval_async(
            "const gaps = []; await new Promise((done) => { let last = performance.now(); const end = last + 3000;
               const tick = (now) => { gaps.push(now - last); last = now; if (now < end) requestAnimationFrame(tick); else done(); };
               requestAnimationFrame(tick); });
             gaps.sort((a, b) => a - b); return [gaps.length, gaps[gaps.length >> 1]];",
        )
        .await;
    println!(
        "browser baseline (blank page)       {} frames in 3 s, median interval {:.1} ms",
        blank[0],
        blank[1].as_f64().unwrap_or(f64::NAN)
    );

    // 1. ingest of a ≥ 10,000-sample drawing
    let t = TestService::start(Options::default()).await;
    open_page(&browser, &t).await;
    let (s, v) = t.post_json("/api/v1/motions", &strokes(13, 0.01)).await;
    assert_eq!(s, 200, "{v}");
    let answered = Instant::now();
    let (_, trace) = t.get("/api/v1/sim/trace").await;
    let n = trace.as_array().map_or(0, Vec::len);
    assert!(n >= 10_000, "only {n} samples");
    browser
        .wait_js(
            &format!("window.dashboard.path.length >= {n}"),
            WAIT,
            "every sample on the page",
        )
        .await;
    let ingest = answered.elapsed();
    println!("trace samples on the page          {n}");
    println!(
        "motion answer → all on the page     {:.0} ms (includes the HTTP fetch of the trace)",
        ingest.as_secs_f64() * 1e3
    );

    // 2. redraw costs with that path
    let costs = browser
        .eval(
            "const d = window.dashboard; const t2 = [], t3 = [];
             for (let i = 0; i < 30; i++) {
               let t0 = performance.now(); d.drawPathNow(); t2.push(performance.now() - t0);
               t0 = performance.now(); d.view.renderNow(); d.view.renderer.getContext().finish(); t3.push(performance.now() - t0);
             }
             const med = (a) => a.sort((x, y) => x - y)[a.length >> 1];
             return [med(t2), med(t3)];",
        )
        .await;
    println!(
        "redraw both projections ({n} pts)  {:.2} ms (median of 30)",
        costs[0].as_f64().unwrap_or(f64::NAN)
    );
    println!(
        "render the 3D view ({n} pts)       {:.2} ms (median of 30, software WebGL)",
        costs[1].as_f64().unwrap_or(f64::NAN)
    );
    t.service.shutdown().await.expect("shutdown");

    // 3. frame pacing during real-time motion at a 10 ms heartbeat with a 10k path
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    open_page(&browser, &t).await;
    // Preload the page with a 10,000-point path (as if drawn earlier).
    browser
        .eval(
            "const d = window.dashboard; const pts = [];
             for (let i = 0; i < 10000; i++) pts.push({t: i * 0.012, cid: 0, motion: 0,
               pose: [220 + 40 * Math.cos(i / 300), 40 * Math.sin(i / 200), 70, 0, 180, 0]});
             d.path.push(...pts); d.view.addExecuted(pts.map((p) => p.pose)); d.drawPathNow();",
        )
        .await;
    let idle = pacing(&browser).await;
    println!(
        "frame interval, robot idle          p50={:.1} ms  p95={:.1} ms  max={:.1} ms  ({} frames)",
        idle["p50"].as_f64().unwrap_or(f64::NAN),
        idle["p95"].as_f64().unwrap_or(f64::NAN),
        idle["max"].as_f64().unwrap_or(f64::NAN),
        idle["frames"]
    );
    let mut body = strokes(4, 0.05);
    body["wait"] = json!(false);
    let (s, v) = t.post_json("/api/v1/motions", &body).await;
    assert_eq!(s, 202, "{v}");
    browser
        .wait_js(
            "window.dashboard.robot.busy === true",
            WAIT,
            "the robot moving",
        )
        .await;
    let moving = pacing(&browser).await;
    let g = |k: &str| moving[k].as_f64().unwrap_or(f64::NAN);
    println!(
        "state events received in 5 s        {:.0} ({:.0}/s)",
        g("events"),
        g("events") / 5.0
    );
    println!("path samples added in 5 s           {:.0}", g("added"));
    println!(
        "frame interval while moving         p50={:.1} ms  p95={:.1} ms  max={:.1} ms  ({:.0} frames)",
        g("p50"),
        g("p95"),
        g("max"),
        g("frames")
    );
    println!(
        "event-loop delay while moving       p95={:.1} ms  max={:.1} ms (a click waits at most this)",
        g("lag_p95"),
        g("lag_max")
    );
    println!(
        "long tasks (> 50 ms)                {:.0} (longest {:.0} ms)",
        g("long"),
        g("longest")
    );
    println!(
        "JS heap                             {:.1} MiB",
        g("heap_mib")
    );
    // The same with the 3D view frozen: what the 2D views and the DOM cost.
    browser
        .eval("window.dashboard.view.render = () => {};")
        .await;
    let flat = pacing(&browser).await;
    println!(
        "frame interval, 3D view frozen      p50={:.1} ms  p95={:.1} ms  max={:.1} ms  ({} frames)",
        flat["p50"].as_f64().unwrap_or(f64::NAN),
        flat["p95"].as_f64().unwrap_or(f64::NAN),
        flat["max"].as_f64().unwrap_or(f64::NAN),
        flat["frames"]
    );
    let _ = t.post("/api/v1/stop").await;
    t.service.shutdown().await.expect("shutdown");
    browser.close().await;
}

/// Frame intervals (requestAnimationFrame), long tasks, state events and
/// path growth of the page over 5 s.
async fn pacing(browser: &Browser) -> Value {
    browser
        .eval_async(
            "const gaps = []; let long = 0, longest = 0, events = 0;
             const obs = new PerformanceObserver((l) => { for (const e of l.getEntries()) { long++; longest = Math.max(longest, e.duration); } });
             try { obs.observe({ type: 'longtask', buffered: false }); } catch (e) {}
             const count = () => events++;
             window.dashboard.stream.addEventListener('state', count);
             const before = window.dashboard.path.length;
             const lags = []; let stop = false;
             const probe = () => { const at = performance.now(); setTimeout(() => { lags.push(performance.now() - at); if (!stop) probe(); }, 0); };
             probe();
             await new Promise((done) => {
               let last = performance.now(); const end = last + 5000;
               const tick = (now) => { gaps.push(now - last); last = now; if (now < end) requestAnimationFrame(tick); else done(); };
               requestAnimationFrame(tick);
             });
             stop = true;
             obs.disconnect();
             lags.sort((a, b) => a - b);
             window.dashboard.stream.removeEventListener('state', count);
             gaps.sort((a, b) => a - b);
             const q = (p) => gaps[Math.min(gaps.length - 1, Math.floor(p * gaps.length))];
             return { frames: gaps.length, p50: q(0.5), p95: q(0.95), max: gaps[gaps.length - 1],
                      lag_p95: lags[Math.floor(0.95 * lags.length)], lag_max: lags[lags.length - 1],
                      long, longest, events, added: window.dashboard.path.length - before,
                      heap_mib: performance.memory ? performance.memory.usedJSHeapSize / 1048576 : null };",
        )
        .await
}

/// Opens the dashboard of `t` and waits until its script has started.
async fn open_page(browser: &Browser, t: &TestService) {
    browser.goto(&t.url("/")).await;
    browser
        .wait_js(
            "window.dashboard && window.dashboard.ready === true",
            WAIT,
            "page ready",
        )
        .await;
}

//! The dashboard page at `/` in headless Chromium, against the service
//! with the simulated controller: the page's path and pose against the
//! simulator's trace, Stop, jogging, and what a viewer may do. Without
//! Chromium and chromedriver they fail at once with the command that
//! installs them (`sudo apt-get install chromium chromium-driver` on
//! Debian), never skipped and counted as passed (see
//! `kuka_bridge_tests::browser`); screenshots go to `<target>/artifacts/dashboard/`.

use std::time::Duration;

use kuka_bridge::config::SimulatorKind;
use kuka_bridge_tests::browser::Browser;
use kuka_bridge_tests::{Options, TestService, initial_admin_secret, test_simulator};
use serde_json::{Value, json};

/// Generous for a loaded CI machine running a debug build and a software-rendered browser.
const WAIT: Duration = Duration::from_secs(20);

/// Opens the dashboard and waits until it has started and shows the controller online.
async fn open(browser: &Browser, t: &TestService) {
    browser.goto(&t.url("/")).await;
    browser
        .wait_js(
            "window.dashboard && window.dashboard.ready === true && window.dashboard.robot && window.dashboard.robot.connection === 'online'",
            WAIT,
            "the dashboard to start and show the controller online",
        )
        .await;
}

/// Starts a slow motion (A1 to 160° at 5 %, time scale 1) without waiting
/// and waits until the page shows it executing; its job id.
async fn slow_job_on_page(browser: &Browser, t: &TestService) -> u64 {
    let slow = json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 160}, "velocity_pct": 5}], "wait": false});
    let (s, job) = t.post_json("/api/v1/motions", &slow).await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("job id");
    browser
        .wait_js(
            &format!("window.dashboard.jobs.get({id})?.state === 'executing'"),
            WAIT,
            "the page to show the slow job executing",
        )
        .await;
    id
}

fn smiley() -> Value {
    serde_json::from_str(include_str!("../docs/smiley.json")).expect("docs/smiley.json is JSON")
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// The smiley drawn through the API appears on the page as the simulator
/// drew it: the page's path equals the trace sample for sample, the plan
/// came before the motion and lies on the drawn path, the arm drawn by
/// the page's own kinematics ends at the reported TCP, and the 3D and 2D
/// views hold every point.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_draws_what_the_robot_draws() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    // Twice real time: the drawing takes a few seconds, so the page sees it happen.
    let t = TestService::start(Options {
        time_scale: 2.0,
        ..Options::default()
    })
    .await;
    browser.resize(1400, 1900).await;
    open(&browser, &t).await;
    assert_eq!(browser.title().await, "kuka-bridge");

    let mut body = smiley();
    body["wait"] = json!(false);
    let (s, job) = t.post_json("/api/v1/motions", &body).await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("job id");
    browser
        .wait_js(
            &format!("window.dashboard.lastPlan && window.dashboard.lastPlan.job === {id}"),
            WAIT,
            "the plan of the smiley",
        )
        .await;
    browser
        .wait_js(
            &format!("window.dashboard.jobs.get({id})?.state === 'executing'"),
            WAIT,
            "the page to show the job executing",
        )
        .await;
    browser.screenshot("drawing").await;
    browser
        .wait_js(
            &format!("window.dashboard.jobs.get({id})?.state === 'done'"),
            WAIT,
            "the page to show the job done",
        )
        .await;
    let (_, job) = t.get(&format!("/api/v1/jobs/{id}")).await;
    assert_eq!(job["state"], "done", "{job}");
    let cid = job["cid"].as_i64().expect("cid");

    // The plan came before the motion ran (event order on the page).
    let order = browser
        .eval(&format!(
            "const e = window.dashboard.events.map((x) => x.type + ' ' + x.text);
             return [e.findIndex((x) => x.startsWith('plan #{id} ')),
                     e.findIndex((x) => x.startsWith('job #{id} move executing'))];"
        ))
        .await;
    let (plan_at, exec_at) = (order[0].as_i64(), order[1].as_i64());
    assert!(
        matches!((plan_at, exec_at), (Some(p), Some(e)) if p >= 0 && e > p),
        "plan before execution in the event log: {order}"
    );

    // The page's path is the simulator's trace, sample for sample.
    let (_, trace) = t.get("/api/v1/sim/trace").await;
    let trace: Vec<&Value> = trace
        .as_array()
        .expect("trace")
        .iter()
        .filter(|s| s["cid"].as_i64() == Some(cid))
        .collect();
    assert!(trace.len() > 200, "{} samples", trace.len());
    browser
        .wait_js(
            &format!(
                "window.dashboard.path.filter((s) => s.cid === {cid}).length >= {}",
                trace.len()
            ),
            WAIT,
            "every trace sample on the page",
        )
        .await;
    let page = browser
        .eval(&format!(
            "return window.dashboard.path.filter((s) => s.cid === {cid}).map((s) => [s.t, s.motion, ...s.pose]);"
        ))
        .await;
    let page = page.as_array().expect("page path");
    assert_eq!(page.len(), trace.len(), "samples on the page vs the trace");
    for (i, (p, s)) in page.iter().zip(&trace).enumerate() {
        assert_eq!(f(&p[0]), f(&s["t"]), "sample {i} time");
        assert_eq!(p[1], s["motion"], "sample {i} motion index");
        for k in 0..6 {
            assert!(
                (f(&p[k + 2]) - f(&s["pose"][k])).abs() < 1e-9,
                "sample {i}: page {p} vs trace {}",
                s["pose"]
            );
        }
    }

    // The plan lies on the drawn path: every planned point with the pen
    // down (z = 70) is within 1.5 mm of a drawn sample (samples are
    // 12 ms apart; corners are rounded by 1 mm approximation).
    let planned = browser
        .eval("return window.dashboard.lastPlan.points;")
        .await;
    let planned = planned.as_array().expect("planned points");
    let drawn: Vec<[f64; 3]> = trace
        .iter()
        .map(|s| [f(&s["pose"][0]), f(&s["pose"][1]), f(&s["pose"][2])])
        .filter(|p| (p[2] - 70.0).abs() < 0.01)
        .collect();
    let mut checked = 0;
    for p in planned {
        let q = [f(&p[0]), f(&p[1]), f(&p[2])];
        if (q[2] - 70.0).abs() > 0.01 {
            continue;
        }
        let nearest = drawn
            .iter()
            .map(|d| ((d[0] - q[0]).powi(2) + (d[1] - q[1]).powi(2)).sqrt())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1.5,
            "planned point {q:?} is {nearest:.2} mm off the drawing"
        );
        checked += 1;
    }
    assert!(checked > 100, "{checked} planned points with the pen down");
    // Once the job is done its plan is no longer shown.
    browser
        .wait_js(
            &format!("!window.dashboard.plans.has({id})"),
            WAIT,
            "the finished job's plan to be removed",
        )
        .await;

    // The page's state is the service's, and the arm drawn by the page's
    // own kinematics ends at the reported TCP.
    let (_, state) = t.get("/api/v1/state").await;
    let shown = browser
        .eval("return [window.dashboard.robot.position, window.dashboard.drawnTcp()];")
        .await;
    for k in ["x", "y", "z", "a", "b", "c", "s", "t"] {
        assert_eq!(
            f(&shown[0][k]),
            f(&state["position"][k]),
            "page position {k} vs /api/v1/state"
        );
    }
    let tip = shown[1].as_array().expect("drawn TCP");
    let pose = |v: [f64; 6]| kuka_kinematics::Pose::new(v[0], v[1], v[2], v[3], v[4], v[5]);
    let drawn = pose(std::array::from_fn(|k| f(&tip[k])));
    let p = &state["position"];
    let reported = pose(["x", "y", "z", "a", "b", "c"].map(|k| f(&p[k])));
    assert!(
        drawn.distance_mm(&reported) < 0.01 && drawn.angle_deg(&reported) < 0.01,
        "arm tip drawn at {tip:?}, TCP reported at {p}"
    );
    // The pose table (drawn at the next animation frame) shows the same Z.
    browser
        .wait_js(
            &format!(
                "document.querySelector('#pose tbody tr:nth-child(3) td').textContent === '{:.3}'",
                f(&state["position"]["z"])
            ),
            WAIT,
            "Z in the pose table",
        )
        .await;

    // The 3D view holds every sample; the projections drew something; the CSV has a row per sample.
    let counts = browser
        .eval(
            "const d = window.dashboard;
             const ink = (id) => { const c = document.getElementById(id);
               const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
               let n = 0; for (let i = 3; i < px.length; i += 4) if (px[i] > 0) n++; return n; };
             return [d.path.length, d.view.executedCount, ink('top'), ink('side'),
                     d.pathCsv().trim().split('\\n').length - 1];",
        )
        .await;
    assert_eq!(
        counts[0], counts[1],
        "3D path points vs page path: {counts}"
    );
    assert_eq!(counts[0], counts[4], "CSV rows vs page path: {counts}");
    // The SVG export is a valid SVG document with one vertex per sample
    // (its strokes and travel runs join: each starts where the one before ends).
    let svg = browser
        .eval(
            "const doc = new DOMParser().parseFromString(window.dashboard.pathSvg(), 'image/svg+xml');
             const err = doc.querySelector('parsererror');
             const lines = [...doc.querySelectorAll('polyline.executed')];
             const vertices = lines.map((l) => l.getAttribute('points').trim().split(/\\s+/).length);
             return [err ? err.textContent : null, doc.documentElement.nodeName,
                     vertices.reduce((a, b) => a + b, 0) - (lines.length - 1)];",
        )
        .await;
    assert!(svg[0].is_null(), "SVG parse error: {svg}");
    assert_eq!(svg[1], "svg");
    assert_eq!(svg[2], counts[0], "SVG vertices vs page path: {svg}");
    // The event list filters by text.
    browser.set_value("#event-text", "plan #").await;
    let listed = browser
        .wait_js(
            "(() => { const li = [...document.querySelectorAll('#events li')]; return li.length > 0 && li.every((l) => l.textContent.includes('plan #')) && li.length; })()",
            WAIT,
            "only plan events listed",
        )
        .await;
    assert_eq!(listed, 1, "one plan in this run");
    browser.set_value("#event-text", "").await;
    assert_eq!(browser.text("#simulated").await, "simulated");
    assert!(
        f(&counts[2]) > 500.0 && f(&counts[3]) > 200.0,
        "ink in the projections: {counts}"
    );

    let errors = browser.page_errors().await;
    assert!(errors.is_empty(), "console errors: {errors:#?}");
    browser.screenshot("smiley").await;

    // Tablet and phone sizes: nothing wider than the screen, and Stop stays
    // on screen when scrolled to the bottom.
    for (name, w, h) in [("tablet", 820, 1180), ("phone", 390, 844)] {
        browser.resize(w, h).await;
        let fit = browser
            .eval_async(
                "await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
                 window.scrollTo(0, document.body.scrollHeight);
                 await new Promise((r) => requestAnimationFrame(r));
                 const stop = document.getElementById('stop').getBoundingClientRect();
                 return [document.documentElement.scrollWidth, window.innerWidth, stop.top, stop.bottom, window.innerHeight];",
            )
            .await;
        let v: Vec<f64> = fit.as_array().expect("sizes").iter().map(f).collect();
        assert!(
            v[0] <= v[1],
            "{name}: page {} px wide in a {} px window",
            v[0],
            v[1]
        );
        assert!(
            v[2] >= 0.0 && v[3] <= v[4],
            "{name}: Stop off screen at the bottom: {fit}"
        );
        browser.eval("window.scrollTo(0, 0);").await;
        browser.screenshot(name).await;
    }
    browser.close().await;
}

/// Pressing the page's Stop during a long motion cancels the job.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn stop_on_the_page_cancels_the_running_job() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    open(&browser, &t).await;
    let id = slow_job_on_page(&browser, &t).await;
    browser
        .wait_js(
            &format!(
                "document.getElementById('running').textContent.includes('#{id} move — executing')"
            ),
            WAIT,
            "the running-job panel to show it",
        )
        .await;
    browser.click("#stop").await;
    browser
        .wait_js(
            &format!("window.dashboard.jobs.get({id})?.state === 'cancelled'"),
            WAIT,
            "the page to show the job cancelled",
        )
        .await;
    let (_, job) = t.get(&format!("/api/v1/jobs/{id}")).await;
    assert_eq!(job["state"], "cancelled", "{job}");
    assert_eq!(job["error"]["code"], "cancelled", "{job}");
    let a1 = f(&job["axes"]["a1"]);
    assert!(a1 > 0.0 && a1 < 150.0, "stopped part way: A1 = {a1}");
    browser
        .wait_js(
            &format!(
                "document.getElementById('jobs').textContent.includes('#{id} move (1) cancelled')"
            ),
            WAIT,
            "the jobs panel to show the job cancelled",
        )
        .await;
    browser.screenshot("stopped").await;
    browser.close().await;
}

/// The jog panel moves the robot through the API: typed LIN target,
/// relative steps, override; a KRL program is uploaded and run.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_jog_panel_drives_the_robot() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options::default()).await;
    open(&browser, &t).await;
    // A pose away from the home singularity, typed in with LIN.
    let (s, v) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp", "target": {"x": 275, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]}),
        )
        .await;
    assert_eq!(s, 200, "{v}");
    browser
        .wait_js(
            "Math.abs(window.dashboard.robot.position.z - 100) < 1e-6",
            WAIT,
            "the page to show z = 100",
        )
        .await;
    browser.click("#fill-current").await;
    browser
        .wait_js(
            "document.querySelector('#goto [name=x]').value === '275.000'",
            WAIT,
            "Current to fill in the pose",
        )
        .await;
    browser
        .eval("document.getElementById('jog-type').value = 'lin';")
        .await;
    browser.set_value("#goto [name=y]", "40").await;
    browser.set_value("#goto [name=z]", "80").await;
    browser.click("#go").await;
    browser
        .wait_js(
            "(() => { const p = window.dashboard.robot.position; return Math.abs(p.y - 40) < 1e-6 && Math.abs(p.z - 80) < 1e-6; })()",
            WAIT,
            "the typed LIN target reached",
        )
        .await;
    let (_, st) = t.get("/api/v1/state").await;
    assert_eq!(st["position"]["x"], 275.0);
    assert_eq!(st["position"]["y"], 40.0);
    assert_eq!(st["position"]["z"], 80.0);
    let (_, jobs) = t.get("/api/v1/jobs?limit=1").await;
    assert_eq!(jobs[0]["operation"], "move");
    let (_, trace) = t.get("/api/v1/sim/trace").await;
    let last_cid = jobs[0]["cid"].clone();
    let line: Vec<&Value> = trace
        .as_array()
        .expect("trace")
        .iter()
        .filter(|s| s["cid"] == last_cid)
        .collect();
    // LIN: every sample on the straight segment (x stays 275).
    assert!(
        line.iter().all(|s| (f(&s["pose"][0]) - 275.0).abs() < 0.01),
        "LIN stayed on x = 275"
    );

    // A target out of reach: the page says why its own job failed.
    browser.set_value("#goto [name=x]", "2000").await;
    browser.click("#go").await;
    browser
        .wait_js(
            "!document.getElementById('alarm-bar').hidden && document.getElementById('alarm').textContent.includes('unreachable')",
            WAIT,
            "the failure of the page's own job in the red bar",
        )
        .await;
    browser.set_value("#goto [name=x]", "275").await;

    // Relative steps: 50 mm along −X, then 1 mm along −Z.
    browser
        .eval("document.getElementById('step').value = '50';")
        .await;
    browser.click("[data-step='x,-1']").await;
    browser
        .wait_js(
            "Math.abs(window.dashboard.robot.position.x - 225) < 1e-6",
            WAIT,
            "X− 50 mm",
        )
        .await;
    browser
        .eval("document.getElementById('step').value = '1';")
        .await;
    browser.click("[data-step='z,-1']").await;
    browser
        .wait_js(
            "Math.abs(window.dashboard.robot.position.z - 79) < 1e-6",
            WAIT,
            "Z− 1 mm",
        )
        .await;

    // Override.
    browser
        .eval(
            "const o = document.getElementById('override-input'); o.value = '35';
             o.dispatchEvent(new Event('change'));",
        )
        .await;
    browser
        .wait_js(
            "window.dashboard.robot.speed.override_pct === 35",
            WAIT,
            "the override at 35 %",
        )
        .await;
    let (_, speed) = t.get("/api/v1/speed").await;
    assert_eq!(speed["override_pct"], 35.0);
    browser
        .wait_js(
            "document.getElementById('override').textContent === '35 %'",
            WAIT,
            "the header to show 35 %",
        )
        .await;

    // A KRL program uploaded from a file and run from the page.
    let dir = tempfile::tempdir().expect("tempdir");
    let src = dir.path().join("wave.src");
    std::fs::write(&src, "DEF wave()\n  PTP {A1 20}\n  PTP {A1 0}\nEND\n").expect("write .src");
    browser.set_value("#upload [name=name]", "wave").await;
    browser
        .client()
        .find(fantoccini::Locator::Css("#upload [name=src]"))
        .await
        .expect("file input")
        .send_keys(&src.to_string_lossy())
        .await
        .expect("choose the file");
    browser.click("#upload button").await;
    browser
        .wait_js(
            "document.getElementById('programs').textContent.includes('wave')",
            WAIT,
            "the uploaded program in the list",
        )
        .await;
    browser.click("#programs li button").await;
    let run = browser
        .wait_js(
            "[...window.dashboard.jobs.values()].find((j) => j.operation === 'run_program' && j.state === 'done')",
            WAIT,
            "the program run done",
        )
        .await;
    let (_, trace) = t.get("/api/v1/sim/trace").await;
    let a1_max = trace
        .as_array()
        .expect("trace")
        .iter()
        .filter(|s| s["cid"] == run["cid"])
        .map(|s| f(&s["axes"][0]))
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(
        (a1_max - 20.0).abs() < 0.01,
        "the program turned A1 to 20°: {a1_max}"
    );
    browser.close().await;
}

/// With tokens required, the page asks for one; a viewer sees the robot
/// live but the driving controls are disabled and a motion is refused;
/// an operator may drive but not upload programs.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_viewer_sees_the_page_but_cannot_drive() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options {
        tweak: Box::new(|c| c.auth.require_on_loopback = true),
        ..Options::default()
    })
    .await;
    let admin = initial_admin_secret(&t.config.data_dir);
    let viewer = t.create_token(&admin, "wall-screen", "viewer").await;
    let operator = t.create_token(&admin, "tablet-1", "operator").await;

    browser.goto(&t.url("/")).await;
    browser
        .wait_js(
            "!document.getElementById('auth').hidden",
            WAIT,
            "the page to ask for a token",
        )
        .await;
    browser.set_value("#token", &viewer).await;
    browser.click("#token-form button").await;
    browser
        .wait_js(
            "window.dashboard.ready && window.dashboard.you?.role === 'viewer' && window.dashboard.robot?.connection === 'online'",
            WAIT,
            "the page to load as viewer",
        )
        .await;
    assert_eq!(browser.text("#role").await, "wall-screen · viewer");
    browser
        .wait_js(
            "document.getElementById('connection').textContent === 'online'",
            WAIT,
            "the connection pill to show online",
        )
        .await;
    let disabled =
        |css: &str| format!("[...document.querySelectorAll(\"{css}\")].map((e) => e.disabled)");
    for css in [
        "#go",
        "[data-step]",
        "[data-joint]",
        "#step",
        "#rot-step",
        "#goto [name=s]",
        "#home",
        "#override-input",
        "#take-control",
        "#goto input",
        "#upload button",
        "#stop",
    ] {
        let states = browser.eval(&format!("return {};", disabled(css))).await;
        let states = states.as_array().expect("elements");
        assert!(
            !states.is_empty() && states.iter().all(|d| d == true),
            "{css} disabled for a viewer: {states:?}"
        );
    }
    // Stop stays on screen but says that a viewer cannot stop (the
    // server requires the operator role for it).
    let stop = browser
        .eval("const b = document.getElementById('stop'); return [b.getBoundingClientRect().height, b.title];")
        .await;
    assert!(stop[0].as_f64().unwrap_or(0.0) > 30.0, "{stop}");
    assert!(
        stop[1].as_str().unwrap_or("").contains("operator"),
        "{stop}"
    );
    let why = browser
        .eval("return document.getElementById('go').title;")
        .await;
    assert!(
        why.as_str()
            .unwrap_or("")
            .contains("needs the operator role"),
        "{why}"
    );

    // A motion from the page anyway (as a script could) is refused by the server.
    let (_, before) = t.get_as("/api/v1/state", &viewer).await;
    let answer = browser
        .eval_async("return await window.dashboard.move({type: 'ptp', target: {z: 400}});")
        .await;
    assert_eq!(answer["status"], 403, "{answer}");
    assert_eq!(answer["body"]["code"], "forbidden", "{answer}");
    let message = browser.text("#message").await;
    assert!(
        message.contains("forbidden"),
        "the page says why: {message}"
    );
    let (_, after) = t.get_as("/api/v1/state", &viewer).await;
    assert_eq!(
        before["position"], after["position"],
        "the robot did not move"
    );
    // On the page, not only in tooltips (touch screens show none).
    let notes = browser
        .eval("return [document.getElementById('jog-note').textContent, document.getElementById('stop-note').textContent];")
        .await;
    assert!(
        notes[0]
            .as_str()
            .unwrap_or("")
            .contains("needs the operator role"),
        "{notes}"
    );
    assert!(
        notes[1]
            .as_str()
            .unwrap_or("")
            .contains("needs the operator role"),
        "{notes}"
    );
    browser.screenshot("viewer").await;

    // Revoking the token: the page asks for another (it does not pretend the service is gone).
    let r = t
        .http
        .delete(t.url("/api/v1/tokens/wall-screen"))
        .bearer_auth(&admin)
        .send()
        .await
        .expect("revoke");
    assert_eq!(r.status().as_u16(), 200);
    browser
        .wait_js(
            "!document.getElementById('auth').hidden && document.getElementById('role').textContent === 'no access' && document.getElementById('alarm').textContent.includes('rejected or revoked')",
            WAIT,
            "the page to ask for another token",
        )
        .await;

    // An operator in a fresh tab may drive but not upload programs.
    browser
        .eval(&format!(
            "sessionStorage.setItem('kb-token', {});",
            json!(operator)
        ))
        .await;
    open(&browser, &t).await;
    browser
        .wait_js(
            "window.dashboard.you?.role === 'operator'",
            WAIT,
            "the page to load as operator",
        )
        .await;
    assert_eq!(
        browser
            .eval("return document.getElementById('go').disabled;")
            .await,
        false
    );
    assert_eq!(
        browser
            .eval("return document.querySelector('#upload button').disabled;")
            .await,
        true
    );
    assert_eq!(
        browser
            .eval("return document.getElementById('stop').disabled;")
            .await,
        false,
        "an operator may stop"
    );
    browser.close().await;
}

/// An installed plugin's route gets a form generated from its JSON schema;
/// calling it from the page draws the circle.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn plugin_routes_are_callable_from_generated_forms() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let wasm = kuka_bridge_tests::example_plugins(
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")),
        false,
    )
    .join("draw-circle.wasm");
    let t = TestService::start(Options::default()).await;
    let bytes = std::fs::read(&wasm).expect("draw-circle.wasm");
    // The route summary carries markup (same length, replaced in the
    // component's data): the page must show it as text, never run it.
    let from = "Draw a horizontal circle (PTP to its start,";
    let to = "<img src=x onerror=window.pwned=1>XXXXXXXXX";
    assert_eq!(from.len(), to.len());
    let at = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .expect("the summary in the component");
    let mut bytes = bytes;
    bytes[at..at + to.len()].copy_from_slice(to.as_bytes());
    let (s, v) = t.put_bytes("/api/v1/plugins/draw-circle", bytes).await;
    assert!(s == 200 || s == 201, "install: {s} {v}");
    // Swagger UI renders Markdown/HTML: the plugin's text is escaped in /openapi.json.
    let (_, doc) = t.get("/openapi.json").await;
    let summary = doc["paths"]["/api/v1/plugins/draw-circle/circle"]["post"]["summary"]
        .as_str()
        .unwrap_or_default();
    assert!(summary.starts_with("&lt;img src=x"), "{summary}");
    // Pen-down orientation in the configuration the drawings use.
    let (s, v) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp", "target": {"x": 275, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]}),
        )
        .await;
    assert_eq!(s, 200, "{v}");
    open(&browser, &t).await;
    let form = "form[data-url='/api/v1/plugins/draw-circle/circle']";
    browser
        .wait_js(
            &format!("document.querySelector(\"{form}\") !== null"),
            WAIT,
            "the plugin's form",
        )
        .await;
    let summary = browser
        .eval(&format!(
            "return [document.querySelector(\"{form} p\").textContent, document.querySelectorAll('#plugins img').length, window.pwned === undefined];"
        ))
        .await;
    assert!(
        summary[0].as_str().unwrap_or("").starts_with("<img src=x"),
        "summary shown as text: {summary}"
    );
    assert_eq!(summary[1], 0, "no element made from plugin text: {summary}");
    assert_eq!(summary[2], true, "no plugin script ran: {summary}");
    // The inputs follow the schema: names, required marks, types, enum, default, example.
    let inputs = browser
        .eval(&format!(
            "return [...document.querySelectorAll(\"{form} input, {form} select\")].map((i) =>
               [i.name, i.tagName, i.type, i.required, i.value, i.placeholder]);"
        ))
        .await;
    let by_name = |n: &str| {
        inputs
            .as_array()
            .expect("inputs")
            .iter()
            .find(|i| i[0] == n)
            .cloned()
            .unwrap_or_else(|| panic!("no input {n} in {inputs}"))
    };
    assert_eq!(
        by_name("radius"),
        json!(["radius", "INPUT", "number", true, "", "40"])
    );
    assert_eq!(by_name("speed_m_s")[3], false, "optional");
    assert_eq!(by_name("speed_m_s")[4], "0.1", "default");
    assert_eq!(by_name("mode")[1], "SELECT");
    assert_eq!(by_name("mode")[4], "\"circ\"");
    for (name, value) in [("x", "220"), ("y", "0"), ("z", "70"), ("radius", "30")] {
        browser
            .set_value(&format!("{form} input[name={name}]"), value)
            .await;
    }
    browser.click(&format!("{form} button")).await;
    browser
        .wait_js(
            &format!("document.querySelector(\"{form} pre\").textContent.startsWith('200')"),
            WAIT,
            "the plugin's answer",
        )
        .await;
    let (_, jobs) = t.get("/api/v1/jobs?limit=1").await;
    let job = &jobs[0];
    assert_eq!(job["origin"], "plugin:draw-circle@0.1.0", "{job}");
    assert_eq!(job["state"], "done", "{job}");
    let (_, trace) = t.get("/api/v1/sim/trace").await;
    let on_paper: Vec<&Value> = trace
        .as_array()
        .expect("trace")
        .iter()
        .filter(|s| s["cid"] == job["cid"] && (f(&s["pose"][2]) - 70.0).abs() < 0.01)
        .collect();
    assert!(on_paper.len() > 50, "{} samples on paper", on_paper.len());
    for s in on_paper {
        let r = (f(&s["pose"][0]) - 220.0).hypot(f(&s["pose"][1]));
        assert!((r - 30.0).abs() < 0.5, "sample off the circle: r = {r}");
    }
    browser.screenshot("plugin").await;
    browser.close().await;
}

/// A controller error and a lost heartbeat are shown with their code and
/// sentence; Acknowledge on the page resets the error; a lost service is
/// shown as such.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn controller_errors_and_offline_are_shown() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    // The shipped KRL program (`KB_TEST_SIMULATOR=krc`) enters its error
    // state only through a real error stop, which the dry run prevents.
    let krc = test_simulator() == SimulatorKind::Krc;
    let t = TestService::start(Options {
        tweak: Box::new(move |c| {
            if krc {
                c.robot.model = "none".into();
            }
        }),
        // The KRL program in real time: at the instant time scale its two
        // interpreters take a core each, and a loaded CI machine then keeps
        // the page from seeing the heartbeat in time.
        time_scale: if krc { 1.0 } else { 0.0 },
        ..Options::default()
    })
    .await;
    open(&browser, &t).await;
    assert_eq!(
        browser
            .eval("return document.getElementById('alarm-bar').hidden;")
            .await,
        true
    );
    t.provoke_controller_error().await;
    let (_, state) = {
        let mut last = (0, Value::Null);
        for _ in 0..200 {
            last = t.get("/api/v1/state").await;
            if !last.1["controller"]["error"].is_null() {
                break;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        last
    };
    let code = state["controller"]["error"]["code"]
        .as_str()
        .expect("error code")
        .to_string();
    browser
        .wait_js(
            &format!(
                "!document.getElementById('alarm-bar').hidden && document.getElementById('alarm').textContent.includes('{code}') && !document.getElementById('reset').hidden"
            ),
            WAIT,
            "the error bar with the code and Acknowledge",
        )
        .await;
    assert_eq!(browser.text("#status").await, "error");
    browser.screenshot("controller-error").await;
    browser.click("#reset").await;
    if krc {
        // A KRC's stop message waits for the operator, whatever RESET does:
        // the page keeps showing the error until it is acknowledged.
        browser
            .wait_js(
                "window.dashboard.jobs.size >= 0 && !document.getElementById('alarm-bar').hidden",
                WAIT,
                "the error still shown after RESET",
            )
            .await;
        let (s, v) = t.post("/api/v1/sim/acknowledge").await;
        assert_eq!(s, 204, "{v}");
    }
    browser
        .wait_js(
            "document.getElementById('alarm-bar').hidden && window.dashboard.robot.controller.error === null",
            WAIT,
            "the error acknowledged",
        )
        .await;
    let (_, state) = t.get("/api/v1/state").await;
    assert!(state["controller"]["error"].is_null(), "{state}");

    t.pause_controller();
    browser
        .wait_js(
            "document.getElementById('connection').textContent === 'offline' && document.getElementById('alarm').textContent.includes('controller_offline')",
            WAIT,
            "offline shown",
        )
        .await;
    t.resume_controller();
    // A resumed controller first catches up with its clock; on a loaded CI
    // machine running the KRL program's two interpreters that can take a
    // while (the wait ends as soon as the page shows it online).
    browser
        .wait_js(
            "document.getElementById('connection').textContent === 'online' && document.getElementById('alarm-bar').hidden",
            if krc { WAIT * 3 } else { WAIT },
            "online again",
        )
        .await;
    // The service itself gone (a tablet losing the network looks the same).
    t.service.shutdown().await.expect("shutdown");
    browser
        .wait_js(
            "document.getElementById('connection').textContent === 'no service' && document.getElementById('alarm').textContent.includes('No connection to the kuka-bridge service') && document.body.classList.contains('stale')",
            WAIT,
            "the lost service shown",
        )
        .await;
    browser.close().await;
}

/// After the service restarts (same port, same data), the open page
/// reconnects and starts again from the service's jobs and trace: no job
/// left "executing", new jobs listed, the path keeps growing.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_resyncs_after_a_service_restart() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("free port")
        .port();
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(move |c| c.server.listen = ([127, 0, 0, 1], port).into()),
        ..Options::default()
    })
    .await;
    open(&browser, &t).await;
    // A slow job running when the service goes away.
    slow_job_on_page(&browser, &t).await;
    let TestService {
        service,
        dirs,
        config,
        ..
    } = t;
    service.shutdown().await.expect("shutdown");
    browser
        .wait_js(
            "document.getElementById('connection').textContent === 'no service'",
            WAIT,
            "the page to notice",
        )
        .await;
    let mut config = config;
    config.simulator.time_scale = 0.0;
    let t = TestService::start_with(config, dirs).await;
    browser
        .wait_js(
            "window.dashboard.streamDown === null && document.getElementById('connection').textContent === 'online'",
            WAIT,
            "the page to reconnect",
        )
        .await;
    // The interrupted job is no longer shown as executing; a new one appears.
    // (A motion, so that it leaves a trace whichever simulator runs.)
    let (s, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 20}}]))
        .await;
    assert_eq!(s, 200, "{v}");
    let new_id = v["id"].as_u64().expect("id");
    browser
        .wait_js(
            &format!(
                "window.dashboard.jobs.get({new_id})?.operation === 'move' && window.dashboard.jobs.get({new_id})?.state === 'done' && ![...window.dashboard.jobs.values()].some((j) => j.state === 'executing')"
            ),
            WAIT,
            "the page's jobs to come from the restarted service",
        )
        .await;
    // The page shows the restarted simulator's samples of that motion, as
    // many as its trace holds (the simulator may still add the standstill
    // sample after the job is done: compare against the trace as it is).
    let cid = v["cid"].as_i64().expect("cid");
    kuka_bridge_tests::wait_for(
        WAIT,
        "the restarted simulator's samples on the page",
        async || {
            let (_, trace) = t.get("/api/v1/sim/trace").await;
            let n = trace.as_array().map_or(0, |a| {
                a.iter().filter(|s| s["cid"].as_i64() == Some(cid)).count()
            });
            let page = browser
                .eval(&format!(
                    "return window.dashboard.path.filter((s) => s.cid === {cid}).length;"
                ))
                .await;
            if n > 0 && page.as_u64() == Some(n as u64) {
                Ok(())
            } else {
                Err(format!("trace {n}, page {page}"))
            }
        },
    )
    .await;
    browser.close().await;
}

/// Waits until the page shows a job newer than `after` done; its id.
async fn job_done_after(browser: &Browser, after: u64, what: &str) -> u64 {
    let id = browser
        .wait_js(
            &format!(
                "[...window.dashboard.jobs.values()].find((j) => j.id > {after} && j.state === 'done')?.id"
            ),
            WAIT,
            what,
        )
        .await;
    id.as_u64().expect("job id")
}

/// The newest job id the service knows (0 before any).
async fn last_job(t: &TestService) -> u64 {
    let (_, jobs) = t.get("/api/v1/jobs?limit=1").await;
    jobs[0]["id"].as_u64().unwrap_or(0)
}

/// The jog panel names the arm configuration of S and T in words, sends
/// them with a PTP, shows the API's sentences as text (no backticks),
/// steps A/B/C by the rotation step and each axis A1–A6 by an axis PTP,
/// with the axes on bars between their software limits and the steps
/// that would pass a limit switched off.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn jog_with_status_turn_rotations_and_axis_steps() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options::default()).await;
    // Pen-down orientation with the wrist flipped: S 6 (A5 < 0), T 18 (A2 and A5 negative).
    let (s, v) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp", "target": {"x": 275, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]}),
        )
        .await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(
        (v["position"]["s"].as_i64(), v["position"]["t"].as_i64()),
        (Some(6), Some(18)),
        "{v}"
    );
    browser.resize(1400, 1900).await;
    open(&browser, &t).await;
    // The pose table and the S field name the configuration (φ = atan(20/260) = 4.4° on a KR 3 R540).
    browser
        .wait_js(
            "document.querySelector('#pose tbody tr:nth-child(7) td:nth-child(3)').textContent === 'basic · elbow up · wrist flipped'
             && document.querySelector('#pose tbody tr:nth-child(8) td:nth-child(3)').textContent === 'A2, A5 < 0, the others ≥ 0'",
            WAIT,
            "S 6 and T 18 in words in the pose table",
        )
        .await;
    let words = browser
        .eval("return [document.getElementById('s-words').textContent, document.getElementById('t-words').textContent];")
        .await;
    assert_eq!(
        words,
        json!([
            "empty: the bridge chooses (reachable, clear of singularities, least axis travel)",
            "empty: chosen with the Status"
        ])
    );
    // With `keep` (KUKA's rule) the empty S keeps the current Status.
    browser
        .eval("const s = document.getElementById('config-mode'); s.value = 'keep'; s.dispatchEvent(new Event('change'));")
        .await;
    let words = browser
        .eval("return [document.getElementById('s-words').textContent, document.getElementById('t-words').textContent];")
        .await;
    assert_eq!(
        words,
        json!([
            "empty: keeps S 6 (basic area · elbow up (A3 ≥ 4.4°) · wrist flipped (A5 < 0))",
            "empty: the shortest axis motion"
        ])
    );

    // A flange-down target the flipped wrist cannot reach with `keep`: the
    // red bar says how to choose another configuration, as text with code,
    // no backticks.
    for (name, value) in [
        ("x", "300"),
        ("y", "0"),
        ("z", "300"),
        ("a", "0"),
        ("b", "180"),
        ("c", "0"),
    ] {
        browser
            .set_value(&format!("#goto [name={name}]"), value)
            .await;
    }
    browser.click("#go").await;
    let alarm = browser
        .wait_js(
            "(() => { const a = document.getElementById('alarm');
               return !document.getElementById('alarm-bar').hidden && a.textContent.includes('give s, 0..7, to choose another arm configuration')
                 && [a.textContent, [...a.querySelectorAll('code')].map((c) => c.textContent)]; })()",
            WAIT,
            "the refused PTP in the red bar",
        )
        .await;
    assert!(
        !alarm[0].as_str().unwrap_or("`").contains('`'),
        "no backticks shown: {alarm}"
    );
    assert_eq!(alarm[1], json!(["s", "s"]), "code spans: {alarm}");
    browser.screenshot("jog-refused").await;

    // The same target with `auto`: the bridge picks a configuration that
    // reaches it, and the job says which.
    browser
        .eval("const s = document.getElementById('config-mode'); s.value = 'auto'; s.dispatchEvent(new Event('change'));")
        .await;
    let before = last_job(&t).await;
    browser.click("#go").await;
    let id = job_done_after(&browser, before, "the PTP with auto done").await;
    let (_, job) = t.get(&format!("/api/v1/jobs/{id}")).await;
    assert_eq!(job["configurations"][0]["chosen"], "auto", "{job}");
    let (_, st) = t.get("/api/v1/state").await;
    assert_eq!(
        (f(&st["position"]["x"]), f(&st["position"]["z"])),
        (300.0, 300.0),
        "{st}"
    );

    // S 2 (wrist not flipped) and T 2, named as typed, reach it.
    browser.set_value("#goto [name=s]", "9").await;
    browser
        .wait_js(
            "document.getElementById('s-words').classList.contains('bad') && document.getElementById('s-words').textContent === 'must be a whole number from 0 to 7'",
            WAIT,
            "an S out of range said next to the field",
        )
        .await;
    browser.set_value("#goto [name=s]", "2").await;
    browser.set_value("#goto [name=t]", "2").await;
    let words = browser
        .eval("return [document.getElementById('s-words').textContent, document.getElementById('t-words').textContent];")
        .await;
    assert_eq!(
        words,
        json!([
            "S 2: basic area · elbow up (A3 ≥ 4.4°) · wrist not flipped (A5 ≥ 0)",
            "T 2: A2 < 0, the others ≥ 0"
        ])
    );
    let before = last_job(&t).await;
    browser.click("#go").await;
    job_done_after(&browser, before, "the PTP with S 2 and T 2 done").await;
    let (_, st) = t.get("/api/v1/state").await;
    let p = &st["position"];
    assert_eq!(
        (f(&p["x"]), f(&p["z"]), p["s"].as_i64(), p["t"].as_i64()),
        (300.0, 300.0, Some(2), Some(2)),
        "{p}"
    );

    // S and T are for PTP only: with LIN they are off, and said so.
    browser
        .eval("const s = document.getElementById('jog-type'); s.value = 'lin'; s.dispatchEvent(new Event('change'));")
        .await;
    let lin = browser
        .eval("const f = document.getElementById('goto').elements; return [f.s.disabled, f.t.disabled, f.x.disabled, document.getElementById('s-words').textContent];")
        .await;
    assert_eq!(
        lin,
        json!([
            true,
            true,
            false,
            "S and T apply to PTP only (a LIN keeps the configuration)"
        ])
    );
    browser
        .eval("const s = document.getElementById('jog-type'); s.value = 'ptp'; s.dispatchEvent(new Event('change'));")
        .await;

    // A− by the rotation step: the tool turns 10° about Z in place.
    browser
        .eval("const s = document.getElementById('rot-step'); s.value = '10'; s.dispatchEvent(new Event('change'));")
        .await;
    let pose = |p: &Value| {
        kuka_kinematics::Pose::new(
            f(&p["x"]),
            f(&p["y"]),
            f(&p["z"]),
            f(&p["a"]),
            f(&p["b"]),
            f(&p["c"]),
        )
    };
    let (_, st) = t.get("/api/v1/state").await;
    let start = pose(&st["position"]);
    let before = last_job(&t).await;
    browser.click("[data-step='a,-1']").await;
    job_done_after(&browser, before, "A− done").await;
    let (_, st) = t.get("/api/v1/state").await;
    let turned = pose(&st["position"]);
    assert!(
        turned.distance_mm(&start) < 1e-3,
        "in place: {}",
        st["position"]
    );
    assert!(
        (turned.angle_deg(&start) - 10.0).abs() < 1e-3,
        "turned 10°: {}",
        st["position"]
    );

    // A1+ by the same step: an axis PTP; the bar follows.
    let a1 = f(&st["axes"]["a1"]);
    let before = last_job(&t).await;
    browser.click("[data-joint='a1,1']").await;
    job_done_after(&browser, before, "A1+ done").await;
    let (_, jobs) = t.get("/api/v1/jobs?limit=1").await;
    assert_eq!(jobs[0]["operation"], "move", "{jobs}");
    let (_, st) = t.get("/api/v1/state").await;
    assert!(
        (f(&st["axes"]["a1"]) - (a1 + 10.0)).abs() < 1e-6,
        "A1 {a1} + 10: {}",
        st["axes"]
    );
    let mark = browser
        .wait_js(
            &format!(
                "(() => {{ const row = document.querySelector('#joints [data-axis=a1]');
                   return row.querySelector('.value').textContent === '{:.2}°' && parseFloat(row.querySelector('.mark').style.left); }})()",
                a1 + 10.0
            ),
            WAIT,
            "the A1 bar at its new angle",
        )
        .await;
    assert!(
        (f(&mark) - (a1 + 10.0 + 170.0) / 340.0 * 100.0).abs() < 0.01,
        "A1 marker at {mark}%"
    );

    // Near a limit a step that would pass it is off and says why; a smaller one is on.
    let (s, v) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 165}}]}),
        )
        .await;
    assert_eq!(s, 200, "{v}");
    let plus = browser
        .wait_js(
            "(() => { const b = document.querySelector(\"[data-joint='a1,1']\");
               return b.disabled && [b.title, document.querySelector(\"[data-joint='a1,-1']\").disabled,
                 document.querySelector('#joints [data-axis=a1]').classList.contains('near')]; })()",
            WAIT,
            "A1+ off at 165° with a 10° step",
        )
        .await;
    assert_eq!(
        plus,
        json!(["A1 + 10° would pass the software limit 170°", false, true])
    );
    browser
        .eval("const s = document.getElementById('rot-step'); s.value = '1'; s.dispatchEvent(new Event('change'));")
        .await;
    assert_eq!(
        browser
            .eval("return document.querySelector(\"[data-joint='a1,1']\").disabled;")
            .await,
        false,
        "a 1° step stays within the limit"
    );
    browser.screenshot("jog").await;
    let errors = browser.page_errors().await;
    assert!(errors.is_empty(), "console errors: {errors:#?}");
    browser.close().await;
}

/// The motions of the smiley that only travel (docs/smiley.json): the PTP
/// to the start, and the LINs that lower, lift or move the pen at
/// Z 100 (the drawing plane is Z 70, the lowest Z of its LINs and CIRCs).
const SMILEY_TRAVEL: [usize; 12] = [0, 1, 4, 5, 6, 9, 10, 11, 14, 15, 16, 18];

/// Pen-up travel is drawn faint and dashed in the top view and the 3D view
/// (and the SVG export): PTPs and the LINs above the drawing plane, by the
/// rule of docs/DASHBOARD.md computed here from the plan the service
/// published; after a reload the page classifies the path the same way
/// from the event history.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pen_up_travel_is_drawn_faint_and_dashed() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options::default()).await;
    browser.resize(1400, 1900).await;
    open(&browser, &t).await;
    let (s, job) = t.post_json("/api/v1/motions", &smiley()).await;
    assert_eq!(s, 200, "{job}");
    let cid = job["cid"].as_i64().expect("cid");

    // The rule, from the plan as published (targets resolved).
    let (_, plans) = t.get("/api/v1/events/recent?types=plan&limit=1").await;
    let motions = plans[0]["data"]["motions"]
        .as_array()
        .expect("planned motions")
        .clone();
    assert_eq!(plans[0]["data"]["cid"].as_i64(), Some(cid));
    let z = |v: &Value| f(&v[2]);
    let cp = |m: &Value| m["type"] == "lin" || m["type"] == "circ";
    let mut plane = f64::INFINITY;
    for (i, m) in motions.iter().enumerate() {
        if cp(m) {
            plane = plane.min(z(&m["target"])).min(z(&motions[i - 1]["target"]));
        }
    }
    assert_eq!(plane, 70.0);
    let travel: Vec<bool> = motions
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let above = |p: &Value| !p.is_null() && z(p) > plane + 0.5;
            !cp(m) || above(&motions[i - 1]["target"]) || above(&m["target"]) || above(&m["aux"])
        })
        .collect();
    let expected: Vec<bool> = (0..motions.len())
        .map(|i| SMILEY_TRAVEL.contains(&i))
        .collect();
    assert_eq!(travel, expected, "the rule on the smiley");

    let (_, trace) = t.get("/api/v1/sim/trace").await;
    let samples: Vec<&Value> = trace
        .as_array()
        .expect("trace")
        .iter()
        .filter(|s| s["cid"].as_i64() == Some(cid))
        .collect();
    let want: Vec<bool> = samples
        .iter()
        .map(|s| travel[s["motion"].as_u64().expect("motion") as usize])
        .collect();
    let page_kinds = format!(
        "(() => {{ const p = window.dashboard.path.filter((s) => s.cid === {cid});
           return p.length === {} && p.map((s) => !!s.travel); }})()",
        samples.len()
    );
    let shown = browser
        .wait_js(&page_kinds, WAIT, "every sample on the page, classified")
        .await;
    assert_eq!(shown, json!(want), "travel per sample on the page");
    let plan = browser
        .eval("return [window.dashboard.lastPlan.kinds.plane, window.dashboard.lastPlan.kinds.travel];")
        .await;
    assert_eq!(
        (f(&plan[0]), &plan[1]),
        (70.0, &json!(travel)),
        "the page's plan"
    );

    // 3D: strokes solid, travel dashed and faint, every segment in one of them.
    let view = browser
        .eval(
            "const v = window.dashboard.view;
             return [v.ink.count, v.travel.count, v.executedCount, v.ink.line.material.type,
                     v.travel.line.material.type, v.travel.line.material.opacity, v.travel.line.material.transparent];",
        )
        .await;
    assert!(f(&view[0]) > 100.0 && f(&view[1]) > 100.0, "{view}");
    assert_eq!(f(&view[0]) + f(&view[1]), f(&view[2]) - 1.0, "{view}");
    assert_eq!(view[3], "LineBasicMaterial", "{view}");
    assert_eq!(view[4], "LineDashedMaterial", "{view}");
    assert!(f(&view[5]) < 0.5 && view[6] == true, "faint: {view}");
    // Planned travel is fainter than planned strokes in 3D too.
    let planned = browser
        .eval(
            "const d = window.dashboard; d.view.setPlanned([d.lastPlan]);
             const ch = d.view.planned.children;
             const out = [ch.length, ch.filter((c) => c.userData.travel && c.material.opacity < 0.5).length,
                          ch.filter((c) => !c.userData.travel && c.material.opacity === 1).length];
             d.view.setPlanned([]); return out;",
        )
        .await;
    assert!(
        f(&planned[0]) > 2.0
            && f(&planned[0]) == f(&planned[1]) + f(&planned[2])
            && f(&planned[1]) > 0.0,
        "planned runs: {planned}"
    );

    // Top view, pixels: away from the strokes the travel lines are faint and
    // have gaps (dashes); away from travel the strokes are solid.
    let pixels = browser
        .eval_async(
            "const d = window.dashboard; d.drawPathNow();
             await new Promise((r) => requestAnimationFrame(r));
             const c = document.getElementById('top');
             const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
             const alpha = ([x, y]) => { let m = 0;
               for (let dx = -1; dx <= 1; dx++) for (let dy = -1; dy <= 1; dy++) {
                 const X = Math.round(x) + dx, Y = Math.round(y) + dy;
                 if (X >= 0 && Y >= 0 && X < c.width && Y < c.height) m = Math.max(m, px[(Y * c.width + X) * 4 + 3]); }
               return m; };
             const ink = d.path.filter((s) => !s.travel), trav = d.path.filter((s) => s.travel);
             const far = (s, others) => others.every((o) => Math.hypot(o.pose[0] - s.pose[0], o.pose[1] - s.pose[1]) > 3);
             const t = trav.filter((s) => far(s, ink)).map((s) => alpha(d.top.toCanvas(s.pose)));
             const i = ink.filter((s) => far(s, trav)).map((s) => alpha(d.top.toCanvas(s.pose)));
             return [t.length, Math.max(...t), t.filter((a) => a < 20).length, i.length, Math.min(...i)];",
        )
        .await;
    println!(
        "top view: [travel samples, their max alpha, in gaps, stroke samples, their min alpha] = {pixels}"
    );
    let p: Vec<f64> = pixels.as_array().expect("pixels").iter().map(f).collect();
    assert!(
        p[0] > 30.0,
        "travel samples away from the strokes: {pixels}"
    );
    assert!(p[1] < 200.0, "travel is faint: {pixels}");
    assert!(p[2] > 0.0, "travel is dashed: {pixels}");
    assert!(p[3] > 100.0 && p[4] >= 200.0, "strokes are solid: {pixels}");
    // The SVG export draws travel dashed and faint too.
    let svg = browser
        .eval(
            "const doc = new DOMParser().parseFromString(window.dashboard.pathSvg(), 'image/svg+xml');
             const t = [...doc.querySelectorAll('polyline.executed.travel')];
             return [t.length, t.every((l) => l.getAttribute('stroke-dasharray') && Number(l.getAttribute('stroke-opacity')) < 0.5),
                     doc.querySelectorAll('polyline.executed:not(.travel)').length];",
        )
        .await;
    assert!(
        f(&svg[0]) >= 4.0 && svg[1] == true && f(&svg[2]) >= 4.0,
        "{svg}"
    );
    browser.screenshot("travel").await;

    // After a reload the trace comes back and the plan from the event history: same kinds.
    browser.goto(&t.url("/")).await;
    open(&browser, &t).await;
    let shown = browser
        .wait_js(
            &page_kinds,
            WAIT,
            "the path classified again after a reload",
        )
        .await;
    assert_eq!(shown, json!(want), "travel per sample after a reload");
    let errors = browser.page_errors().await;
    assert!(errors.is_empty(), "console errors: {errors:#?}");
    browser.close().await;
}

/// The Events panel shows what happened before the page was (re)loaded,
/// from `GET /api/v1/events/recent`, at the times it happened, once; the
/// stream continues from the last id without a gap, and a stream that
/// reconnects gets the events it missed (and none twice).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_events_panel_keeps_its_history_across_a_reload() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options::default()).await;
    let (s, home) = t.post("/api/v1/home").await;
    assert_eq!(s, 200, "{home}");
    let (s, mv) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 10}}]}),
        )
        .await;
    assert_eq!(s, 200, "{mv}");
    let id = mv["id"].as_u64().expect("id");
    // Opened after the fact: the history is there.
    open(&browser, &t).await;
    let lines = |text: String| {
        format!(
            "[...document.querySelectorAll('#events li')].filter((l) => l.textContent.includes({})).length",
            json!(text)
        )
    };
    let done = format!("job #{id} move done");
    let plan = format!("plan #{id} cid {}: ptp_axes", mv["cid"]);
    let home_done = format!("job #{} home done", home["id"]);
    for reload in [false, true] {
        if reload {
            browser.eval("location.reload();").await;
            open(&browser, &t).await;
        }
        browser
            .wait_js(
                &format!(
                    "{} === 1 && {} === 1 && {} === 1",
                    lines(done.clone()),
                    lines(plan.clone()),
                    lines(home_done.clone())
                ),
                WAIT,
                "the earlier jobs and plan listed once",
            )
            .await;
    }
    // At the time the service published them.
    let (_, recent) = t.get("/api/v1/events/recent?types=job").await;
    let published = recent
        .as_array()
        .expect("recent")
        .iter()
        .rev()
        .find(|e| e["data"]["id"].as_u64() == Some(id) && e["data"]["state"] == "done")
        .expect("the done event")
        .clone();
    let shown = browser
        .eval(&format!(
            "return window.dashboard.events.find((e) => e.type === 'job' && e.text.startsWith('#{id} move done')).at.getTime();"
        ))
        .await;
    assert_eq!(shown, published["at_ms"], "the time it happened");
    let (_, newest) = t.get("/api/v1/events/recent?limit=1").await;
    browser
        .wait_js(
            &format!("window.dashboard.lastEventId >= {}", newest[0]["id"]),
            WAIT,
            "the page at the newest event id",
        )
        .await;

    // A job after the reload is listed once (live, not also replayed).
    let (s, again) = t.post("/api/v1/home").await;
    assert_eq!(s, 200, "{again}");
    let again_done = format!("job #{} home done", again["id"]);
    browser
        .wait_js(
            &format!("{} === 1", lines(again_done.clone())),
            WAIT,
            "the new job listed",
        )
        .await;
    // The stream drops; a job runs meanwhile; the page reconnects from its last id and gets it, once.
    browser.eval("window.dashboard.stream.close();").await;
    let (s, missed) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp_axes", "axes": {"a1": -10}}]}),
        )
        .await;
    assert_eq!(s, 200, "{missed}");
    let missed_done = format!("job #{} move done", missed["id"]);
    assert_eq!(
        browser
            .eval(&format!("return {};", lines(missed_done.clone())))
            .await,
        0
    );
    browser.eval("window.dashboard.reconnect();").await;
    browser
        .wait_js(
            &format!("{} === 1", lines(missed_done.clone())),
            WAIT,
            "the missed job replayed",
        )
        .await;
    browser
        .wait_js(
            &format!(
                "window.dashboard.jobs.get({})?.state === 'done'",
                missed["id"]
            ),
            WAIT,
            "the missed job in the jobs panel",
        )
        .await;
    for line in [done, plan, home_done, again_done, missed_done] {
        assert_eq!(
            browser
                .eval(&format!("return {};", lines(line.clone())))
                .await,
            1,
            "{line} once"
        );
    }
    browser.screenshot("events-history").await;
    let errors = browser.page_errors().await;
    assert!(errors.is_empty(), "console errors: {errors:#?}");
    browser.close().await;
}

/// A plugin's form lists its fields in the order of its schema as
/// `/openapi.json` gives it (not sorted, required ones not moved first).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn plugin_form_fields_follow_the_schema_order() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options::default()).await;
    open(&browser, &t).await;
    let names = browser
        .eval_async(
            "const { renderPlugins } = await import('/ui/plugins.js');
             // As the page parses /openapi.json: JSON.parse keeps the document's order.
             const schema = {type: 'object', required: ['zeta', 'alpha'], properties: {
               zeta: {type: 'number'}, mid: {type: 'string'}, alpha: {type: 'number'}, beta: {type: 'boolean'}}};
             const text = JSON.stringify({paths: {'/api/v1/plugins/p/go': {post: {requestBody: {content: {'application/json': {schema}}}}}}});
             const doc = JSON.parse(text);
             const box = document.createElement('div');
             renderPlugins(box, [{name: 'p', version: '1', status: 'active', routes: [{method: 'POST', url: '/api/v1/plugins/p/go', summary: 'go'}]}],
                           doc, async () => ({status: 200, body: {}}));
             return [...box.querySelectorAll('input, select')].map((i) => [i.name, i.required]);",
        )
        .await;
    assert_eq!(
        names,
        json!([
            ["zeta", true],
            ["mid", false],
            ["alpha", true],
            ["beta", false]
        ])
    );
    browser.close().await;
}

/// The draw-smiley plugin's form in the order its schema lists the
/// fields: the order survives the plugin, the host and `/openapi.json`
/// because both workspaces build `serde_json` with `preserve_order`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn smiley_plugin_form_in_its_schema_order() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let wasm = kuka_bridge_tests::example_plugins(
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")),
        false,
    )
    .join("draw-smiley.wasm");
    let t = TestService::start(Options::default()).await;
    let (s, v) = t
        .put_bytes(
            "/api/v1/plugins/draw-smiley",
            std::fs::read(&wasm).expect("draw-smiley.wasm"),
        )
        .await;
    assert!(s == 200 || s == 201, "install: {s} {v}");
    open(&browser, &t).await;
    let form = "form[data-url='/api/v1/plugins/draw-smiley/smiley']";
    let names = browser
        .wait_js(
            &format!(
                "(() => {{ const f = document.querySelector(\"{form}\"); return f && [...f.querySelectorAll('input, select')].map((i) => i.name); }})()"
            ),
            WAIT,
            "the smiley's form",
        )
        .await;
    assert_eq!(
        names,
        json!(["x", "y", "z", "size", "lift_mm", "speed_m_s"])
    );
    browser.close().await;
}

/// One SSE message: its `event:`, `id:` (if any) and `data:` as JSON.
#[derive(Debug)]
struct Sse {
    event: String,
    id: Option<u64>,
    data: Value,
}

/// Reads SSE messages from `r` until one with `event: <until>` (included).
async fn read_sse(r: reqwest::Response, until: &str) -> Vec<Sse> {
    use futures_util::StreamExt;
    let mut stream = r.bytes_stream();
    let mut buf = String::new();
    let mut out = Vec::new();
    loop {
        while let Some(end) = buf.find("\n\n") {
            let msg: String = buf.drain(..end + 2).collect();
            let field = |name: &str| {
                msg.lines()
                    .find_map(|l| l.strip_prefix(name).map(|v| v.trim().to_string()))
            };
            let Some(event) = field("event:") else {
                continue; // a keep-alive comment
            };
            out.push(Sse {
                id: field("id:").map(|i| i.parse().expect("numeric id")),
                data: serde_json::from_str(&field("data:").unwrap_or_default())
                    .unwrap_or(Value::Null),
                event: event.clone(),
            });
            if event == until {
                return out;
            }
        }
        let chunk = tokio::time::timeout(WAIT, stream.next())
            .await
            .expect("an SSE message in time")
            .expect("stream open")
            .expect("chunk");
        buf.push_str(&String::from_utf8_lossy(&chunk));
    }
}

/// `GET /api/v1/events/recent` lists the held job, plan and alarm events
/// with consecutive ids, newest last, filtered by type, limit and id; the
/// event stream replays what came after `Last-Event-ID` (or
/// `?last_event_id=`, the header winning) before the current state, then
/// continues with the next id.
#[tokio::test]
async fn the_event_history_is_listed_and_replayed() {
    let t = TestService::start(Options::default()).await;
    let (s, home) = t.post("/api/v1/home").await;
    assert_eq!(s, 200, "{home}");
    let (s, mv) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 10}}]}),
        )
        .await;
    assert_eq!(s, 200, "{mv}");
    // The job's last event is published as its answer goes out: wait for it
    // rather than read the history once.
    let all = kuka_bridge_tests::wait_for(WAIT, "the move's done event", async || {
        let (s, all) = t.get("/api/v1/events/recent").await;
        let list = all.as_array().cloned().unwrap_or_default();
        let done = list.iter().any(|e| {
            e["type"] == "job" && e["data"]["id"] == mv["id"] && e["data"]["state"] == "done"
        });
        if s == 200 && done {
            Ok(list)
        } else {
            Err(format!("{s} {all}"))
        }
    })
    .await;
    let ids: Vec<u64> = all.iter().map(|e| e["id"].as_u64().expect("id")).collect();
    assert!(
        ids.windows(2).all(|w| w[1] == w[0] + 1),
        "consecutive ids: {ids:?}"
    );
    assert!(
        all.windows(2)
            .all(|w| w[0]["at_ms"].as_u64() <= w[1]["at_ms"].as_u64()),
        "oldest first"
    );
    assert!(
        all.iter()
            .all(|e| ["job", "plan", "alarm"].contains(&e["type"].as_str().unwrap_or("")))
    );
    let find = |kind: &str, ok: &dyn Fn(&Value) -> bool| {
        all.iter()
            .position(|e| e["type"] == kind && ok(&e["data"]))
            .unwrap_or_else(|| panic!("no {kind} event like that in {all:#?}"))
    };
    let home_done = find("job", &|d| d["id"] == home["id"] && d["state"] == "done");
    let plan = find("plan", &|d| {
        d["job"] == mv["id"] && d["motions"][0]["type"] == "ptp_axes"
    });
    let mv_done = find("job", &|d| d["id"] == mv["id"] && d["state"] == "done");
    assert!(home_done < plan && plan < mv_done, "in order");
    assert_eq!(all[mv_done]["data"]["position"], mv["position"]);

    // Limit (the newest), types, after.
    let (_, two) = t.get("/api/v1/events/recent?limit=2").await;
    assert_eq!(two, json!(all[all.len() - 2..]));
    let (_, plans) = t.get("/api/v1/events/recent?types=plan").await;
    let plans = plans.as_array().expect("plans");
    assert!(
        !plans.is_empty() && plans.iter().all(|e| e["type"] == "plan"),
        "{plans:?}"
    );
    let plan_id = ids[plan];
    let (_, after) = t
        .get(&format!(
            "/api/v1/events/recent?after={plan_id}&types=job,alarm"
        ))
        .await;
    let want: Vec<&Value> = all[plan + 1..]
        .iter()
        .filter(|e| e["type"] != "plan")
        .collect();
    assert_eq!(after, json!(want));
    for bad in [
        "limit=0",
        "limit=1001",
        "types=state",
        "types=job,bogus",
        "after=abc",
        "since=3",
    ] {
        let (s, v) = t.get(&format!("/api/v1/events/recent?{bad}")).await;
        assert_eq!(
            (s, v["code"].as_str()),
            (422, Some("invalid_input")),
            "{bad}: {v}"
        );
    }

    // The stream after Last-Event-ID: the held events after it with their
    // ids, then the state (no id); the query parameter does the same; the
    // header wins over it.
    let replayed: Vec<(String, Option<u64>)> = all[plan + 1..]
        .iter()
        .map(|e| {
            (
                e["type"].as_str().unwrap_or("").to_string(),
                e["id"].as_u64(),
            )
        })
        .chain([("state".to_string(), None)])
        .collect();
    for (header, query) in [
        (Some(plan_id), None),
        (None, Some(plan_id)),
        (Some(plan_id), Some(ids[0])),
    ] {
        let mut req = t.http.get(t.url(&format!(
            "/api/v1/events{}",
            query.map_or(String::new(), |q| format!("?last_event_id={q}"))
        )));
        if let Some(h) = header {
            req = req.header("Last-Event-ID", h.to_string());
        }
        let r = req.send().await.expect("events");
        assert_eq!(r.status(), 200);
        let got: Vec<(String, Option<u64>)> = read_sse(r, "state")
            .await
            .into_iter()
            .map(|m| (m.event, m.id))
            .collect();
        assert_eq!(got, replayed, "header {header:?}, query {query:?}");
    }
    // Without a position the stream starts with the state; live events continue the ids.
    let r = t
        .http
        .get(t.url("/api/v1/events?types=state,job"))
        .send()
        .await
        .expect("events");
    let first = read_sse(r, "state").await;
    assert_eq!(first.len(), 1, "{first:?}");
    let r = t
        .http
        .get(t.url(&format!(
            "/api/v1/events?types=job&last_event_id={}",
            ids[ids.len() - 1]
        )))
        .send()
        .await
        .expect("events");
    let (s, next) = t.post("/api/v1/home").await;
    assert_eq!(s, 200, "{next}");
    let live = read_sse(r, "job").await;
    let job = live.last().expect("a job event");
    assert_eq!(job.id, Some(ids[ids.len() - 1] + 1), "{live:?}");
    assert_eq!(job.data["id"], next["id"]);
    let (s, v) = t
        .http
        .get(t.url("/api/v1/events"))
        .header("Last-Event-ID", "abc")
        .send()
        .await
        .map(|r| (r.status().as_u16(), r))
        .expect("events");
    assert_eq!(s, 422, "{:?}", v.text().await);

    // Documented for clients, with the role it needs.
    let (_, doc) = t.get("/openapi.json").await;
    let op = &doc["paths"]["/api/v1/events/recent"]["get"];
    assert_eq!(op["operationId"], "listRecentEvents", "{op}");
    assert_eq!(op["x-required-role"], "viewer", "{op}");
    let responses = op["responses"].as_object().expect("responses");
    for (status, r) in responses {
        assert!(
            r["description"].as_str().is_some_and(|d| !d.is_empty()),
            "{status} without a description"
        );
    }
    t.service.shutdown().await.expect("shutdown");
}

/// The workspace box, a keep-out zone and the floor are drawn in the
/// projections where the configuration puts them (`GET /api/v1/workspace`).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_workspace_and_keep_out_zones_are_drawn() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.workspace = Some(kuka_bridge::config::WorkspaceBox {
                x: [0.0, 600.0],
                y: [-300.0, 300.0],
                z: [0.0, 700.0],
            });
            c.zones.floor_z = Some(10.0);
            c.zones.keep_out = vec![kuka_bridge::config::KeepOut {
                name: "fixture".into(),
                x: [200.0, 260.0],
                y: [-30.0, 30.0],
                z: [0.0, 60.0],
            }];
        }),
        ..Options::default()
    })
    .await;
    let (s, ws) = t.get("/api/v1/workspace").await;
    assert_eq!(s, 200, "{ws}");
    assert_eq!(ws["keep_out"][0]["name"], "fixture", "{ws}");
    assert_eq!(ws["floor_z"], 10.0, "{ws}");
    browser.resize(1400, 1900).await;
    open(&browser, &t).await;
    let shapes = browser
        .wait_js(
            "(() => { const d = window.dashboard;
               const kinds = (p) => (p.zoneShapes || []).map((z) => z.kind).join(',');
               return kinds(d.top) === 'box,keep_out' && kinds(d.side) === 'box,keep_out,floor'
                 && [d.top.zoneShapes, d.side.zoneShapes]; })()",
            WAIT,
            "the box, the zone and the floor drawn",
        )
        .await;
    // The zone is filled red where it lies: read the pixel at its centre.
    let zone = &shapes[0][1];
    assert_eq!(zone["name"], "fixture", "{shapes}");
    let (cx, cy) = (
        (f(&zone["x0"]) + f(&zone["x1"])) / 2.0,
        (f(&zone["y0"]) + f(&zone["y1"])) / 2.0,
    );
    let px = browser
        .eval(&format!(
            "return [...document.getElementById('top').getContext('2d').getImageData({}, {}, 1, 1).data];",
            cx.round(),
            cy.round()
        ))
        .await;
    let rgba: Vec<f64> = px.as_array().expect("pixel").iter().map(f).collect();
    assert!(
        rgba[3] > 0.0 && rgba[0] > rgba[1] && rgba[0] > rgba[2],
        "reddish at the zone's centre: {rgba:?}"
    );
    browser.screenshot("zones").await;
    browser.close().await;
}

/// A path (issue 22) publishes a plan per append; the page joins the
/// pieces into one planned path while it runs.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_joins_a_paths_appends_into_one_plan() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    open(&browser, &t).await;
    let start = json!({"motions": [{"type": "ptp", "target": {"x": 250, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]});
    let (s, v) = t.post_json("/api/v1/motions", &start).await;
    assert_eq!(s, 200, "{v}");
    let (s, path) = t.post_json("/api/v1/paths", &json!({})).await;
    assert_eq!(s, 201, "{path}");
    let id = path["id"].as_u64().expect("id");
    // Two appends of 10 LINs each, slow enough that the path still runs.
    let lins = |from: usize| -> Vec<Value> {
        (from..from + 10)
            .map(|i| json!({"type": "lin", "target": {"y": 5.0 * (i + 1) as f64}, "velocity_m_s": 0.02}))
            .collect()
    };
    for from in [0, 10] {
        let (s, o) = t
            .post_json(
                &format!("/api/v1/paths/{id}/motions"),
                &json!({"motions": lins(from)}),
            )
            .await;
        assert_eq!(s, 200, "{o}");
    }
    browser
        .wait_js(
            &format!(
                "window.dashboard.lastPlan && window.dashboard.lastPlan.job === {id} && window.dashboard.lastPlan.points.length >= 21"
            ),
            WAIT,
            "both appends in one planned path",
        )
        .await;
    let ys = browser
        .eval("return window.dashboard.lastPlan.points.map((p) => p[1]);")
        .await;
    let ys: Vec<f64> = ys
        .as_array()
        .expect("points")
        .iter()
        .map(|v| v.as_f64().unwrap_or(f64::NAN))
        .collect();
    let want: Vec<f64> = (0..=20).map(|i| 5.0 * i as f64).collect();
    assert_eq!(ys.len(), want.len(), "{ys:?}");
    for (y, w) in ys.iter().zip(&want) {
        assert!((y - w).abs() < 1e-6, "planned {ys:?}");
    }
    let (s, _) = t.delete(&format!("/api/v1/paths/{id}?cancel=true")).await;
    assert_eq!(s, 200);
}

/// A spline block on the page: the plan is drawn as the curve through the
/// points (not the chords between them) and lies on what the robot drew.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_draws_a_spline_block_as_its_curve() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    open(&browser, &t).await;
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 240, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]))
        .await;
    assert_eq!(s, 200, "{v}");
    // Eight points on a circle of 50 mm around (190, 0): one block.
    let points: Vec<Value> = (1..=8)
        .map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / 8.0;
            json!({"type": "spl", "target": {"x": 190.0 + 50.0 * a.cos(), "y": 50.0 * a.sin()}, "velocity_m_s": 0.2})
        })
        .collect();
    let (s, job) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": points, "wait": false}),
        )
        .await;
    assert_eq!(s, 202, "{job}");
    let id = job["id"].as_u64().expect("job id");
    browser
        .wait_js(
            &format!("window.dashboard.lastPlan && window.dashboard.lastPlan.job === {id}"),
            WAIT,
            "the plan of the spline block",
        )
        .await;
    let planned = browser
        .eval("return window.dashboard.lastPlan.points;")
        .await;
    let planned: Vec<[f64; 3]> = planned
        .as_array()
        .expect("planned points")
        .iter()
        .map(|p| [f(&p[0]), f(&p[1]), f(&p[2])])
        .collect();
    assert!(planned.len() > 8 * 8, "{} points: a curve", planned.len());
    // Away from the block's mirrored first and last segment, the drawn
    // plan keeps to the circle (chords would pass 3.8 mm inside it).
    let mut checked = 0;
    for q in &planned {
        let (dx, dy) = (q[0] - 190.0, q[1]);
        let angle = dy.atan2(dx).rem_euclid(std::f64::consts::TAU).to_degrees();
        if (50.0..=305.0).contains(&angle) {
            let r = dx.hypot(dy);
            assert!(
                (r - 50.0).abs() < 1.5,
                "planned {q:?} is {r:.2} mm from the centre"
            );
            checked += 1;
        }
    }
    assert!(checked > 30, "{checked} planned points checked");
    let j = t
        .wait_job(id, "the block to run", |j| j["state"] == "done")
        .await;
    let cid = j["cid"].as_i64().expect("cid");
    let drawn: Vec<[f64; 3]> = t
        .trace()
        .into_iter()
        .filter(|s| s.cid == cid)
        .map(|s| [s.pose[0], s.pose[1], s.pose[2]])
        .collect();
    // Distance to the drawn polyline (the KRC-like runtime's samples may
    // be two interpolation steps apart).
    let to_segment = |q: &[f64; 3], a: &[f64; 3], b: &[f64; 3]| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let u = if len2 > 0.0 {
            (((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (a[0] + u * dx - q[0]).hypot(a[1] + u * dy - q[1])
    };
    for q in &planned {
        let nearest = drawn
            .windows(2)
            .map(|w| to_segment(q, &w[0], &w[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1.0,
            "planned point {q:?} is {nearest:.2} mm off the drawing"
        );
    }
}

/// The I/O panel: a lamp per reported signal; a click on an output the site
/// allows switches it on the controller, and a simulated input lights its
/// lamp; the changes of watched signals appear in the event log.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_io_panel_switches_an_allowed_output_and_shows_inputs() {
    let Some(browser) = Browser::start().await else {
        return;
    };
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| {
            let signal = |name: &str, index: u16| kuka_bridge::io::SignalConfig {
                name: name.into(),
                index,
                pulse_ms: 0,
                watch: true,
            };
            c.io.inputs = vec![signal("part_present", 3)];
            c.io.outputs = vec![signal("gripper_close", 1)];
            let analog = |name: &str, index: u8| kuka_bridge::io::AnalogConfig {
                name: name.into(),
                index,
                watch: false,
                deadband: 0.01,
            };
            c.io.analog_inputs = vec![analog("force", 2)];
            c.io.analog_outputs = vec![analog("spindle_speed", 1)];
        }),
        ..Options::default()
    })
    .await;
    open(&browser, &t).await;
    browser
        .wait_js(
            "document.querySelectorAll('#io-outputs .lamp').length === 31 && document.querySelectorAll('#io-inputs .lamp').length === 31",
            WAIT,
            "31 output and 31 input lamps",
        )
        .await;
    // Only the allowed output is a button; the others are lamps.
    let kinds = browser
        .eval("return [...document.querySelectorAll('#io-outputs .lamp')].slice(0, 3).map((l) => [l.tagName, l.textContent, l.disabled === true]);")
        .await;
    assert_eq!(
        kinds,
        json!([
            ["BUTTON", "1 gripper_close", false],
            ["SPAN", "2", false],
            ["SPAN", "3", false]
        ]),
        "{kinds}"
    );
    browser.click("#io-outputs button[data-index='1']").await;
    wait_for_value(&t, "/api/v1/io/outputs/1", true).await;
    browser
        .wait_js(
            "document.querySelector(\"#io-outputs [data-index='1']\").classList.contains('on')",
            WAIT,
            "the gripper's lamp on",
        )
        .await;
    let (s, v) = t
        .put_json("/api/v1/sim/inputs/3", &json!({"value": true}))
        .await;
    assert_eq!(s, 204, "{v}");
    browser
        .wait_js(
            "document.querySelector(\"#io-inputs [data-index='3']\").classList.contains('on')",
            WAIT,
            "the part-present lamp on",
        )
        .await;
    browser
        .wait_js(
            "window.dashboard.events.some((e) => e.type === 'io' && e.text === '$OUT[1] gripper_close on') && window.dashboard.events.some((e) => e.type === 'io' && e.text === '$IN[3] part_present on')",
            WAIT,
            "both changes in the event log",
        )
        .await;
    // The controller's safety state in the header.
    browser
        .wait_js(
            "!document.getElementById('safety').hidden && document.getElementById('safety').textContent === 'drives on · program active'",
            WAIT,
            "the safety pill",
        )
        .await;
    // A second click switches it off again.
    browser.click("#io-outputs button[data-index='1']").await;
    wait_for_value(&t, "/api/v1/io/outputs/1", false).await;
    // Analog channels: the allowed output is set from its field, a
    // simulated sensor's value shows in its cell.
    browser
        .wait_js(
            "document.querySelectorAll('#io-analog .analog').length === 16 && document.querySelectorAll('#io-analog .analog-set').length === 1 && document.querySelector(\"#io-analog [data-kind='output'][data-index='1']\").textContent.includes('spindle_speed')",
            WAIT,
            "16 analog cells, one settable",
        )
        .await;
    browser
        .eval("document.querySelector('#io-analog .analog-field').value = '0.5'; document.querySelector('#io-analog .analog-set').click(); return true;")
        .await;
    kuka_bridge_tests::wait_for(WAIT, "$ANOUT[1] at 0.5", async || {
        let (_, v) = t.get("/api/v1/io/analog").await;
        if v["outputs"][0]["value"] == 0.5 {
            Ok(())
        } else {
            Err(v.to_string())
        }
    })
    .await;
    let (s, v) = t
        .put_json("/api/v1/sim/analog-inputs/2", &json!({"value": -0.25}))
        .await;
    assert_eq!(s, 204, "{v}");
    browser
        .wait_js(
            "document.querySelector(\"#io-analog [data-kind='output'][data-index='1'] .analog-value\").textContent === '0.500' && document.querySelector(\"#io-analog [data-kind='input'][data-index='2'] .analog-value\").textContent === '-0.250' && document.querySelector(\"#io-analog [data-kind='input'][data-index='2']\").textContent.includes('force')",
            WAIT,
            "the analog values in their cells",
        )
        .await;
    // An emergency stop on the simulated cell: the pill says so, in red.
    let (s, v) = t
        .put_json("/api/v1/sim/safety", &json!({"emergency_stop": true}))
        .await;
    assert_eq!(s, 204, "{v}");
    browser
        .wait_js(
            "document.getElementById('safety').textContent.startsWith('EMERGENCY STOP · drives off') && document.getElementById('safety').classList.contains('error')",
            WAIT,
            "the emergency stop in the safety pill",
        )
        .await;
    browser.screenshot("emergency-stop").await;
    let (s, v) = t
        .put_json("/api/v1/sim/safety", &json!({"emergency_stop": false}))
        .await;
    assert_eq!(s, 204, "{v}");
    let (s, v) = t.post("/api/v1/sim/acknowledge").await;
    assert_eq!(s, 204, "{v}");
    browser
        .wait_js(
            "document.getElementById('safety').textContent === 'drives on · program active'",
            WAIT,
            "the pill back to normal after the acknowledgement",
        )
        .await;
    assert!(browser.page_errors().await.is_empty());
}

async fn wait_for_value(t: &TestService, path: &str, want: bool) {
    kuka_bridge_tests::wait_for(WAIT, &format!("{path} to read {want}"), async || {
        let (s, v) = t.get(path).await;
        if s == 200 && v["value"] == want {
            Ok(())
        } else {
            Err(format!("{s} {v}"))
        }
    })
    .await;
}

//! The dashboard page at `/` in headless Chromium, against the service
//! with the simulated controller: the page's path and pose against the
//! simulator's trace, Stop, jogging, and what a viewer may do. Without
//! Chromium and chromedriver they fail at once with the command that
//! installs them (`sudo apt-get install chromium chromium-driver` on
//! Debian); they are skipped only with `KUKA_BRIDGE_SKIP_BROWSER=1` set (and
//! `CI` not), with a loud SKIPPED line (see `kuka_bridge_tests::browser`);
//! screenshots go to `<target>/artifacts/dashboard/`.

use std::time::Duration;

use kuka_bridge_tests::browser::Browser;
use kuka_bridge_tests::{Options, TestService, initial_admin_secret};
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
             return [d.path.length, d.view.executed.count, ink('top'), ink('side'),
                     d.pathCsv().trim().split('\\n').length - 1];",
        )
        .await;
    assert_eq!(
        counts[0], counts[1],
        "3D path points vs page path: {counts}"
    );
    assert_eq!(counts[0], counts[4], "CSV rows vs page path: {counts}");
    // The SVG export is a valid SVG document with one vertex per sample.
    let svg = browser
        .eval(
            "const doc = new DOMParser().parseFromString(window.dashboard.pathSvg(), 'image/svg+xml');
             const err = doc.querySelector('parsererror');
             const lines = [...doc.querySelectorAll('polyline')];
             return [err ? err.textContent : null, doc.documentElement.nodeName,
                     lines.at(-1).getAttribute('points').trim().split(/\\s+/).length];",
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
    let t = TestService::start(Options::default()).await;
    open(&browser, &t).await;
    let sim = t.service.sim.as_ref().expect("simulator");
    assert_eq!(
        browser
            .eval("return document.getElementById('alarm-bar').hidden;")
            .await,
        true
    );
    sim.inject_error(kuka_protocol::ResultCode::ControllerError, 0);
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
    browser
        .wait_js(
            "document.getElementById('alarm-bar').hidden && window.dashboard.robot.controller.error === null",
            WAIT,
            "the error acknowledged",
        )
        .await;
    let (_, state) = t.get("/api/v1/state").await;
    assert!(state["controller"]["error"].is_null(), "{state}");

    sim.pause();
    browser
        .wait_js(
            "document.getElementById('connection').textContent === 'offline' && document.getElementById('alarm').textContent.includes('controller_offline')",
            WAIT,
            "offline shown",
        )
        .await;
    sim.resume();
    browser
        .wait_js(
            "document.getElementById('connection').textContent === 'online' && document.getElementById('alarm-bar').hidden",
            WAIT,
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
    let (s, v) = t.post("/api/v1/home").await;
    assert_eq!(s, 200, "{v}");
    let new_id = v["id"].as_u64().expect("id");
    browser
        .wait_js(
            &format!(
                "window.dashboard.jobs.get({new_id})?.operation === 'home' && window.dashboard.jobs.get({new_id})?.state === 'done' && ![...window.dashboard.jobs.values()].some((j) => j.state === 'executing')"
            ),
            WAIT,
            "the page's jobs to come from the restarted service",
        )
        .await;
    let (_, trace) = t.get("/api/v1/sim/trace").await;
    let n = trace.as_array().map_or(0, Vec::len);
    assert!(n > 0, "the home run left a trace");
    browser
        .wait_js(
            &format!(
                "window.dashboard.path.filter((s) => s.cid === {}).length === {n}",
                v["cid"]
            ),
            WAIT,
            "the restarted simulator's samples on the page",
        )
        .await;
    browser.close().await;
}

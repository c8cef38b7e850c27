//! Access control through HTTP against the running service: every
//! documented operation with no token, a viewer, an operator and an admin
//! (generated from `/openapi.json`, so a new endpoint cannot be forgotten),
//! the first-start admin token file, control conflicts and lease expiry,
//! the audit trail, live revocation from the CLI, the failed-attempt
//! limiter, the HTTP edge limits, CORS, HTTPS, and that no secret ever
//! shows up in a log, the audit trail or an error.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

#[cfg(unix)]
use kuka_bridge_tests::CliService;
use kuka_bridge_tests::{
    Options, TestService, WAIT, example_plugins, initial_admin_secret, wait_for,
};
use serde_json::{Value, json};

fn cli() -> &'static str {
    env!("CARGO_BIN_EXE_kuka-bridge-cli")
}

/// Waits until two requests hold the service's two request slots: two
/// motion jobs that have not ended (asked of the engine in this process: a
/// request to the service would take a slot itself).
async fn both_in_flight(t: &TestService) {
    wait_for(WAIT, "two slow motion requests in flight", async || {
        let jobs = t.service.engine.jobs(16);
        let open = jobs.iter().filter(|j| !j.state.is_terminal()).count();
        if open >= 2 {
            Ok(())
        } else {
            let states: Vec<&str> = jobs.iter().map(|j| j.state.as_str()).collect();
            Err(format!("{open} unfinished jobs; states {states:?}"))
        }
    })
    .await;
}

/// Starts a simulated service that requires tokens on loopback.
async fn secured(tweak: impl FnOnce(&mut kuka_bridge::config::Config) + 'static) -> TestService {
    TestService::start(Options {
        tweak: Box::new(move |c| {
            c.auth.require_on_loopback = true;
            tweak(c);
        }),
        ..Options::default()
    })
    .await
}

/// A request as `token` (None: no Authorization header).
async fn call(
    t: &TestService,
    method: &str,
    path: &str,
    token: Option<&str>,
    body: Option<&Value>,
) -> (u16, Value, reqwest::header::HeaderMap) {
    let method = reqwest::Method::from_bytes(method.as_bytes()).expect("method");
    let mut req = t.http.request(method, t.url(path));
    if let Some(tok) = token {
        req = req.bearer_auth(tok);
    }
    if let Some(b) = body {
        req = req.json(b);
    }
    let r = req.send().await.expect("request");
    let headers = r.headers().clone();
    let is_stream = headers
        .get("content-type")
        .is_some_and(|v| v.as_bytes().starts_with(b"text/event-stream"));
    if is_stream {
        // The event stream never ends: its status is the answer.
        return (r.status().as_u16(), Value::Null, headers);
    }
    let (status, v) = kuka_bridge_tests::decode(r).await;
    (status, v, headers)
}

fn rank(role: &str) -> u8 {
    match role {
        "none" => 0,
        "viewer" => 1,
        "operator" => 2,
        "admin" => 3,
        other => panic!("unknown role {other:?} in the document"),
    }
}

/// Every operation of the OpenAPI document, called with no token and with
/// each role, answers as its declared `x-required-role` says.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_documented_operation_answers_as_its_role_says() {
    let t = secured(|_| {}).await;
    let admin = initial_admin_secret(&t.dirs.path().join("data"));
    let viewer = t.create_token(&admin, "view", "viewer").await;
    let operator = t.create_token(&admin, "op", "operator").await;
    // A plugin, so that plugin routes are in the document too.
    let wasm = std::fs::read(
        example_plugins(Path::new(env!("CARGO_TARGET_TMPDIR")), false).join("draw-circle.wasm"),
    )
    .expect("draw-circle.wasm");
    let r = t
        .http
        .put(t.url("/api/v1/plugins/draw-circle"))
        .bearer_auth(&admin)
        .header("content-type", "application/wasm")
        .body(wasm)
        .send()
        .await
        .expect("install");
    assert!(r.status().is_success(), "{}", r.status());

    let (s, doc, _) = call(&t, "GET", "/openapi.json", None, None).await;
    assert_eq!(s, 200);
    assert_eq!(
        doc["components"]["securitySchemes"]["bearer"]["scheme"],
        "bearer"
    );
    let callers = [
        ("none", None),
        ("viewer", Some(viewer.as_str())),
        ("operator", Some(operator.as_str())),
        ("admin", Some(admin.as_str())),
    ];
    let mut checked = 0;
    let mut plugin_routes = 0;
    for (path, item) in doc["paths"].as_object().expect("paths") {
        // Harmless values: unknown names and ids (404s) rather than real ones.
        let url = path
            .replace("{id}", "999999")
            .replace("{name}", "no-such-name");
        if path.starts_with("/api/v1/plugins/draw-circle/") {
            plugin_routes += 1;
        }
        for (method, op) in item.as_object().expect("item") {
            let needed = op["x-required-role"]
                .as_str()
                .unwrap_or_else(|| panic!("{method} {path} declares no role"));
            let body = op.get("requestBody").map(|_| json!({}));
            for (role, token) in callers {
                let (status, v, headers) =
                    call(&t, &method.to_uppercase(), &url, token, body.as_ref()).await;
                let what = format!("{} {path} as {role}: {status} {v}", method.to_uppercase());
                if needed == "none" {
                    assert!(status != 401 && status != 403, "{what}");
                } else if role == "none" {
                    assert_eq!(status, 401, "{what}");
                    assert_eq!(v["code"], "unauthenticated", "{what}");
                    assert!(headers.contains_key("www-authenticate"), "{what}");
                } else if rank(role) < rank(needed) {
                    assert_eq!(status, 403, "{what}");
                    assert_eq!(v["code"], "forbidden", "{what}");
                } else {
                    assert!(status != 401 && status != 403, "{what}");
                }
                checked += 1;
            }
        }
        // Someone may have taken control on the way (POST /api/v1/control).
        let _ = call(&t, "DELETE", "/api/v1/control", Some(&admin), None).await;
    }
    assert!(plugin_routes >= 1, "the plugin's routes are documented");
    assert!(checked >= 4 * 45, "only {checked} calls");

    // Thesis clients: the same rules, their answer format, and the token
    // in the query string for clients that cannot set headers.
    let (s, v, h) = call(&t, "POST", "/krl/getpos", None, None).await;
    assert_eq!((s, v["statuscode"].as_i64()), (401, Some(70)), "{v}");
    assert!(h.contains_key("www-authenticate"));
    let (s, v, _) = call(
        &t,
        "POST",
        &format!("/krl/getpos?access_token={viewer}"),
        None,
        None,
    )
    .await;
    assert_eq!((s, v["statuscode"].as_i64()), (200, Some(1)), "{v}");
    let (s, v, _) = call(
        &t,
        "POST",
        &format!("/krl/ptp?x=200&access_token={viewer}"),
        None,
        None,
    )
    .await;
    assert_eq!((s, v["statuscode"].as_i64()), (403, Some(71)), "{v}");
    // Elsewhere the query string is not a way in.
    let (s, _, _) = call(
        &t,
        "GET",
        &format!("/api/v1/state?access_token={viewer}"),
        None,
        None,
    )
    .await;
    assert_eq!(s, 401);
    // Tokens are listed without secrets.
    let (s, list, _) = call(&t, "GET", "/api/v1/tokens", Some(&admin), None).await;
    assert_eq!(s, 200);
    let text = list.to_string();
    assert!(text.contains("\"op\"") && !text.contains(&operator) && !text.contains(&operator[3..]));
    t.service.shutdown().await.expect("shutdown");
}

/// The first start with auth on writes one admin token to a private file;
/// the next start does not replace it.
#[tokio::test]
async fn first_start_creates_one_admin_token_in_a_private_file() {
    let t = secured(|_| {}).await;
    let data = t.dirs.path().join("data");
    let file = t
        .service
        .admin_token_file
        .clone()
        .expect("created this start");
    assert_eq!(file, data.join("initial-admin-token.txt"));
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&file).expect("file").permissions().mode();
        assert_eq!(mode & 0o777, 0o600, "readable by the service account only");
        let mode = std::fs::metadata(data.join("tokens.json"))
            .expect("tokens.json")
            .permissions()
            .mode();
        assert_eq!(mode & 0o777, 0o600);
    }
    let admin = initial_admin_secret(&data);
    let (s, v, _) = call(&t, "GET", "/api/v1/tokens", Some(&admin), None).await;
    assert_eq!(s, 200);
    assert_eq!(v.as_array().map(Vec::len), Some(1), "{v}");
    assert_eq!(v[0]["name"], "admin");
    assert_eq!(v[0]["role"], "admin");
    let tokens = std::fs::read_to_string(data.join("tokens.json")).expect("tokens");
    assert!(!tokens.contains(&admin[3..]), "stored as a hash only");
    // Restart on the same data: the admin exists, nothing new is created.
    let config = t.config.clone();
    t.service.shutdown().await.expect("shutdown");
    let again = kuka_bridge::app::start(config).await.expect("restart");
    assert!(again.admin_token_file.is_none());
    again.shutdown().await.expect("shutdown");
    assert_eq!(initial_admin_secret(&data), admin);
}

/// Auth is on whenever the service listens beyond loopback, even without
/// `--require-auth`; on loopback without it the demo stays token-free.
#[tokio::test]
async fn auth_is_on_beyond_loopback_and_off_on_plain_loopback() {
    let open = TestService::start(Options::default()).await;
    let (s, _, _) = call(&open, "GET", "/api/v1/state", None, None).await;
    assert_eq!(s, 200);
    assert!(!open.service.auth && open.service.admin_token_file.is_none());
    open.service.shutdown().await.expect("shutdown");

    let t = TestService::start(Options {
        tweak: Box::new(|c| c.server.listen = "0.0.0.0:0".parse().expect("addr")),
        ..Options::default()
    })
    .await;
    assert!(t.service.auth);
    let url = format!("http://127.0.0.1:{}/api/v1/state", t.service.addr.port());
    let r = t.http.get(url).send().await.expect("request");
    assert_eq!(r.status().as_u16(), 401);
    let r = t
        .http
        .get(format!("http://127.0.0.1:{}/health", t.service.addr.port()))
        .send()
        .await
        .expect("health");
    assert_eq!(r.status().as_u16(), 200, "health stays public");
    t.service.shutdown().await.expect("shutdown");
}

fn ptp_to(z: f64) -> Value {
    json!({"motions": [{"type": "ptp", "target": {"x": 250, "y": 0, "z": z, "a": 0, "b": 180, "c": 0}}]})
}

/// One writer at a time: a second operator is refused while the first
/// holds control, reads and stop are not; an admin takes over; a silent
/// holder's lease lapses; plugin routes act under the caller's lease; the
/// audit trail records who did what.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn control_lease_conflicts_expiry_and_audit() {
    let t = secured(|c| c.auth.lease_ms = 1000).await;
    let admin = initial_admin_secret(&t.dirs.path().join("data"));
    let one = t.create_token(&admin, "op-one", "operator").await;
    let two = t.create_token(&admin, "op-two", "operator").await;
    let (s, v, _) = call(
        &t,
        "POST",
        "/api/v1/motions",
        Some(&one),
        Some(&ptp_to(120.0)),
    )
    .await;
    assert_eq!(s, 200, "no one holds control: any operator may move: {v}");

    let (s, v, _) = call(&t, "POST", "/api/v1/control", Some(&one), None).await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["lease"]["holder"], "op-one");
    let jobs_before = t.get("/api/v1/jobs").await;
    let (s, v, _) = call(
        &t,
        "POST",
        "/api/v1/motions",
        Some(&two),
        Some(&ptp_to(100.0)),
    )
    .await;
    assert_eq!(s, 409, "{v}");
    assert_eq!(v["code"], "control_held");
    assert!(
        v["detail"].as_str().unwrap_or_default().contains("op-one"),
        "{v}"
    );
    let _ = jobs_before;
    let (s, _, _) = call(&t, "GET", "/api/v1/state", Some(&two), None).await;
    assert_eq!(s, 200, "reads never need control");
    let (s, v, _) = call(
        &t,
        "POST",
        "/api/v1/control",
        Some(&two),
        Some(&json!({"take_over": true})),
    )
    .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (409, Some("control_held")),
        "operators cannot take over"
    );
    let (s, v, _) = call(&t, "POST", "/api/v1/stop", Some(&two), None).await;
    assert_eq!(s, 200, "stop is always allowed: {v}");
    let (s, v, _) = call(
        &t,
        "POST",
        "/api/v1/motions",
        Some(&one),
        Some(&ptp_to(100.0)),
    )
    .await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["requested_by"], "op-one");
    let job_one = v["id"].as_u64().expect("job id");

    // Plugin routes act under the caller's identity and lease.
    let wasm = std::fs::read(
        example_plugins(Path::new(env!("CARGO_TARGET_TMPDIR")), false).join("draw-circle.wasm"),
    )
    .expect("draw-circle.wasm");
    let r = t
        .http
        .put(t.url("/api/v1/plugins/draw-circle"))
        .bearer_auth(&admin)
        .header("content-type", "application/wasm")
        .body(wasm)
        .send()
        .await
        .expect("install");
    assert!(r.status().is_success());
    let circle = json!({"x": 300, "y": 20, "z": 100, "radius": 40});
    // The 1 s lease may have lapsed during the install: take it again.
    let (s, _, _) = call(&t, "POST", "/api/v1/control", Some(&one), None).await;
    assert_eq!(s, 200);
    // From home, where the plugin's orientation is reachable.
    let (s, v, _) = call(&t, "POST", "/api/v1/home", Some(&one), None).await;
    assert_eq!(s, 200, "{v}");
    let (s, v, _) = call(
        &t,
        "POST",
        "/api/v1/plugins/draw-circle/circle",
        Some(&two),
        Some(&circle),
    )
    .await;
    assert_eq!((s, v["code"].as_str()), (409, Some("control_held")), "{v}");
    let (s, v, _) = call(
        &t,
        "POST",
        "/api/v1/plugins/draw-circle/circle",
        Some(&one),
        Some(&circle),
    )
    .await;
    assert_eq!(s, 200, "{v}");
    let (_, jobs, _) = call(&t, "GET", "/api/v1/jobs?limit=1", Some(&one), None).await;
    assert_eq!(jobs[0]["requested_by"], "op-one", "{jobs}");
    assert!(
        jobs[0]["origin"]
            .as_str()
            .unwrap_or_default()
            .starts_with("plugin:draw-circle")
    );
    // The plugin's batch is on the audit record of the HTTP call that ran it.
    let (_, records, _) = call(
        &t,
        "GET",
        "/api/v1/audit?who=op-one&path=/api/v1/plugins/draw-circle/circle&failed=false",
        Some(&admin),
        None,
    )
    .await;
    assert_eq!(records[0]["jobs"], json!([jobs[0]["id"]]), "{records}");

    // An admin takes over; the former holder is now refused.
    let (s, v, _) = call(
        &t,
        "POST",
        "/api/v1/control",
        Some(&admin),
        Some(&json!({"take_over": true})),
    )
    .await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["lease"]["holder"], "admin");
    let (s, _, _) = call(
        &t,
        "POST",
        "/api/v1/motions",
        Some(&one),
        Some(&ptp_to(110.0)),
    )
    .await;
    assert_eq!(s, 409);
    // The admin goes silent: the lease (1 s) lapses and others may write again.
    wait_for(WAIT, "the admin's silent lease to lapse", async || {
        let (s, v, _) = call(&t, "GET", "/api/v1/control", Some(&two), None).await;
        assert_eq!(s, 200, "{v}");
        if v["lease"].is_null() {
            Ok(())
        } else {
            Err(v.to_string())
        }
    })
    .await;
    let (s, _, _) = call(
        &t,
        "POST",
        "/api/v1/motions",
        Some(&two),
        Some(&ptp_to(120.0)),
    )
    .await;
    assert_eq!(s, 200);

    // The audit trail: who, what, parameters, job, result.
    let (s, v, _) = call(
        &t,
        "GET",
        "/api/v1/audit?who=op-two&failed=true",
        Some(&one),
        None,
    )
    .await;
    assert_eq!(s, 403, "the audit trail is for admins: {v}");
    let (s, records, _) = call(
        &t,
        "GET",
        "/api/v1/audit?who=op-two&failed=true",
        Some(&admin),
        None,
    )
    .await;
    assert_eq!(s, 200);
    let refused = records
        .as_array()
        .expect("records")
        .iter()
        .find(|r| r["path"] == "/api/v1/motions" && r["code"] == "control_held")
        .unwrap_or_else(|| panic!("the refused motion is on record: {records}"));
    assert_eq!(refused["status"], 409);
    assert_eq!(refused["role"], "operator");
    let (_, records, _) = call(
        &t,
        "GET",
        "/api/v1/audit?who=op-one&path=motions&failed=false",
        Some(&admin),
        None,
    )
    .await;
    let done = records
        .as_array()
        .expect("records")
        .iter()
        .find(|r| r["jobs"] == json!([job_one]))
        .unwrap_or_else(|| panic!("op-one's motion with its job: {records}"));
    assert_eq!(done["params"]["body"]["motions"][0]["target"]["z"], 100.0);
    assert_eq!(done["status"], 200);
    assert!(done["duration_ms"].as_f64().unwrap_or(-1.0) >= 0.0);
    let (_, stops, _) = call(
        &t,
        "GET",
        "/api/v1/audit?path=/api/v1/stop",
        Some(&admin),
        None,
    )
    .await;
    assert_eq!(stops[0]["who"], "op-two", "{stops}");
    // Reads are not audited.
    let (_, reads, _) = call(&t, "GET", "/api/v1/audit?method=GET", Some(&admin), None).await;
    assert_eq!(reads, json!([]));
    t.service.shutdown().await.expect("shutdown");
}

fn run_cli(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(cli()).args(args).output().expect("cli runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `kuka-bridge token create/list/revoke` work on the data folder of a
/// running service, and revocation takes effect without a restart.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn cli_tokens_and_live_revocation() {
    let t = secured(|_| {}).await;
    let data = t.dirs.path().join("data");
    let data_arg = data.to_str().expect("utf-8 path");
    let (ok, secret, err) = run_cli(&[
        "token",
        "create",
        "--data-dir",
        data_arg,
        "--name",
        "cell-pc",
        "--role",
        "operator",
    ]);
    assert!(ok, "{err}");
    let secret = secret.trim().to_string();
    assert!(
        secret.starts_with("kb_") && secret.len() >= 3 + 32,
        "{secret}"
    );
    // Picked up by the running service.
    let mut status = 0;
    for _ in 0..50 {
        status = call(&t, "GET", "/api/v1/state", Some(&secret), None)
            .await
            .0;
        if status == 200 {
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert_eq!(
        status, 200,
        "a token created by the CLI works on the running service"
    );
    let (ok, list, _) = run_cli(&["token", "list", "--data-dir", data_arg]);
    assert!(
        ok && list.contains("cell-pc") && list.contains("operator") && !list.contains(&secret[3..]),
        "{list}"
    );
    let (ok, _, err) = run_cli(&[
        "token",
        "create",
        "--data-dir",
        data_arg,
        "--name",
        "cell-pc",
        "--role",
        "viewer",
    ]);
    assert!(!ok && err.contains("already exists"), "{err}");
    let (ok, _, err) = run_cli(&["token", "revoke", "--data-dir", data_arg, "cell-pc"]);
    assert!(ok, "{err}");
    let started = std::time::Instant::now();
    loop {
        let (s, v, _) = call(&t, "GET", "/api/v1/state", Some(&secret), None).await;
        if s == 401 {
            assert_eq!(v["code"], "unauthenticated");
            break;
        }
        assert!(
            started.elapsed() < Duration::from_secs(2),
            "revocation not in effect after 2 s"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let (ok, _, err) = run_cli(&["token", "revoke", "--data-dir", data_arg, "cell-pc"]);
    assert!(!ok && err.contains("no token named"), "{err}");
    t.service.shutdown().await.expect("shutdown");
}

/// Failed attempts are limited per address: after `max_failures` wrong
/// tokens the address gets 429 with Retry-After, even with a good token.
#[tokio::test]
async fn failed_attempts_are_rate_limited() {
    let t = secured(|c| c.auth.max_failures = 3).await;
    let admin = initial_admin_secret(&t.dirs.path().join("data"));
    for i in 0..3 {
        let (s, v, h) = call(
            &t,
            "GET",
            "/api/v1/state",
            Some(&format!("kb_wrong{i}")),
            None,
        )
        .await;
        assert_eq!(s, 401, "{v}");
        assert!(
            h["www-authenticate"]
                .to_str()
                .unwrap_or_default()
                .contains("invalid_token")
        );
    }
    let (s, v, h) = call(&t, "GET", "/api/v1/state", Some("kb_wrong"), None).await;
    assert_eq!(
        (s, v["code"].as_str()),
        (429, Some("too_many_attempts")),
        "{v}"
    );
    assert!(h.contains_key("retry-after"));
    let (s, _, _) = call(&t, "GET", "/api/v1/state", Some(&admin), None).await;
    assert_eq!(s, 429, "the address waits out its window");
    let (s, _, _) = call(&t, "GET", "/health", None, None).await;
    assert_eq!(s, 200);
    t.service.shutdown().await.expect("shutdown");
}

/// The HTTP edge: body limit, load shedding with Retry-After, CORS only for
/// configured origins, and the head size limit.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn edge_limits_and_cors() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| {
            c.server.max_body_bytes = 64 * 1024;
            c.server.max_concurrent_requests = 2;
            c.server.cors_origins = vec!["http://cell-hmi:3000".into()];
        }),
        ..Options::default()
    })
    .await;
    let big = json!({"motions": [], "pad": "x".repeat(100 * 1024)});
    let (s, v) = t.post_json("/api/v1/motions", &big).await;
    assert_eq!(
        (s, v["code"].as_str()),
        (413, Some("payload_too_large")),
        "{v}"
    );

    // Two slow requests fill the service; a third is shed at once.
    let slow = |z: f64| {
        let http = t.http.clone();
        let url = t.url("/api/v1/motions");
        async move {
            http.post(url)
                .json(&json!({"motions": [{"type": "ptp", "target": {"x": 250, "y": 0, "z": z, "a": 0, "b": 180, "c": 0}, "velocity_pct": 1}]}))
                .send()
                .await
                .map(|r| r.status().as_u16())
        }
    };
    let a = tokio::spawn(slow(150.0));
    let b = tokio::spawn(slow(90.0));
    both_in_flight(&t).await;
    let r = t
        .http
        .get(t.url("/api/v1/state"))
        .send()
        .await
        .expect("request");
    assert_eq!(r.status().as_u16(), 503);
    assert_eq!(r.headers()["retry-after"], "1");
    let (_, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(v["code"], "overloaded");
    let _ = t.post("/api/v1/stop").await;
    let _ = (a.await, b.await);

    // CORS: the configured origin only.
    let r = t
        .http
        .get(t.url("/api/v1/state"))
        .header("origin", "http://cell-hmi:3000")
        .send()
        .await
        .expect("request");
    assert_eq!(
        r.headers()["access-control-allow-origin"],
        "http://cell-hmi:3000"
    );
    let r = t
        .http
        .get(t.url("/api/v1/state"))
        .header("origin", "http://evil.example")
        .send()
        .await
        .expect("request");
    assert!(!r.headers().contains_key("access-control-allow-origin"));
    // An oversized request head is refused before any handler runs.
    let r = t
        .http
        .get(t.url("/api/v1/state"))
        .header("x-filler", "y".repeat(128 * 1024))
        .send()
        .await;
    match r {
        Ok(r) => assert_eq!(r.status().as_u16(), 431),
        Err(e) => assert!(e.is_request() || e.is_connect() || e.is_body(), "{e}"),
    }
    t.service.shutdown().await.expect("shutdown");
}

/// Without CORS origins configured, no CORS headers at all.
#[tokio::test]
async fn cors_is_off_by_default() {
    let t = TestService::start(Options::default()).await;
    let r = t
        .http
        .get(t.url("/api/v1/state"))
        .header("origin", "http://anywhere.example")
        .send()
        .await
        .expect("request");
    assert!(
        !r.headers()
            .keys()
            .any(|k| k.as_str().starts_with("access-control-"))
    );
    t.service.shutdown().await.expect("shutdown");
}

/// HTTPS with the certificate and key from the config.
#[tokio::test]
async fn serves_https_with_the_configured_certificate() {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/tls");
    let cert = fixtures.join("cert.pem");
    let key = fixtures.join("key.pem");
    let t = TestService::start(Options {
        // No simulator: the test client here speaks plain HTTP only.
        simulate: false,
        tweak: Box::new(move |c| {
            c.server.tls = Some(kuka_bridge::config::TlsConfig { cert, key });
        }),
        ..Options::default()
    })
    .await;
    assert!(t.service.base_url().starts_with("https://"));
    let answer =
        kuka_bridge_tests::https_get(t.service.addr, &fixtures.join("cert.pem"), "/health").await;
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
    // No controller here: the service answers, and says it cannot send commands.
    assert!(answer.contains("\"status\":\"degraded\""), "{answer}");
    assert!(answer.contains("controller_offline"), "{answer}");
    // Plain HTTP on the TLS port gets no answer.
    let plain = reqwest::Client::new()
        .get(format!("http://{}/health", t.service.addr))
        .timeout(Duration::from_secs(5))
        .send()
        .await;
    assert!(plain.is_err() || !plain.expect("r").status().is_success());
    t.service.shutdown().await.expect("shutdown");
}

/// Secrets never reach the log files, the audit trail or an error answer,
/// whether sent as a header, in the query string, or wrong.
#[cfg(unix)]
#[test]
fn no_secret_in_logs_audit_or_errors() {
    let root = tempfile::tempdir().expect("tempdir");
    let data = root.path().join("data");
    let mut service = CliService::spawn(
        cli(),
        "debug",
        [
            "--simulate",
            "--require-auth",
            "--listen",
            "127.0.0.1:0",
            "--time-scale",
            "0",
            "--data-dir",
            data.to_str().expect("a UTF-8 temporary path"),
        ],
    );
    let url = service.url().to_string();
    let console = service.console();
    assert!(
        console.contains("initial-admin-token.txt"),
        "the console says where: {console}"
    );
    let admin = initial_admin_secret(&data);
    assert!(
        !console.contains(&admin),
        "the console shows the file, not the secret"
    );
    let rt = tokio::runtime::Runtime::new().expect("runtime");
    let wrong = "kb_0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef";
    let bodies = rt.block_on(async {
        let http = reqwest::Client::new();
        let mut bodies = String::new();
        let created = http
            .post(format!("{url}/api/v1/tokens"))
            .bearer_auth(&admin)
            .json(&json!({"name": "op", "role": "operator"}))
            .send()
            .await
            .expect("create");
        let op: Value = created.json().await.expect("json");
        let op = op["secret"].as_str().expect("secret").to_string();
        for (path, token) in [
            ("/api/v1/motions", Some(op.as_str())),
            ("/api/v1/motions", Some(wrong)),
            ("/api/v1/stop", Some(op.as_str())),
        ] {
            let mut req = http
                .post(format!("{url}{path}"))
                .json(&json!({"motions": [{"type": "ptp", "target": {"x": 250, "z": 100}}]}));
            if let Some(tok) = token {
                req = req.bearer_auth(tok);
            }
            bodies.push_str(&req.send().await.expect("send").text().await.expect("text"));
        }
        for q in [
            format!("access_token={op}"),
            format!("access_token={wrong}"),
            format!("x=250&access_token={op}"),
        ] {
            let r = http
                .post(format!("{url}/krl/ptp?{q}"))
                .send()
                .await
                .expect("send");
            bodies.push_str(&r.text().await.expect("text"));
        }
        (bodies, op)
    });
    let (bodies, op) = bodies;
    service.terminate();
    service.wait_exit(Duration::from_secs(20), "after SIGTERM");
    let mut everything = format!("{}\n{}\n{bodies}", service.console(), service.log());
    for entry in std::fs::read_dir(data.join("logs"))
        .expect("logs")
        .chain(std::fs::read_dir(data.join("logs/audit")).expect("audit"))
    {
        let p = entry.expect("entry").path();
        if p.is_file() {
            everything.push_str(&std::fs::read_to_string(&p).expect("log"));
        }
    }
    assert!(
        everything.contains("/krl/ptp"),
        "the logs and audit were read"
    );
    for secret in [&admin, &op, &wrong.to_string()] {
        assert!(!everything.contains(&secret[3..]), "a secret leaked");
    }
}

/// Stop gets through a full service and from an address locked out by the
/// failed-attempt limiter; `/health` is never shed either.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn stop_gets_through_overload_and_lockout() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| {
            c.auth.require_on_loopback = true;
            c.auth.max_failures = 2;
            c.server.max_concurrent_requests = 2;
        }),
        ..Options::default()
    })
    .await;
    let admin = initial_admin_secret(&t.dirs.path().join("data"));
    let op = t.create_token(&admin, "op", "operator").await;
    let slow = |z: f64| {
        let (http, url, op) = (t.http.clone(), t.url("/api/v1/motions"), op.clone());
        async move {
            http.post(url)
                .bearer_auth(op)
                .json(&json!({"motions": [{"type": "ptp", "target": {"x": 250, "y": 0, "z": z, "a": 0, "b": 180, "c": 0}, "velocity_pct": 1}]}))
                .send()
                .await
                .map(|r| r.status().as_u16())
        }
    };
    let a = tokio::spawn(slow(150.0));
    let b = tokio::spawn(slow(90.0));
    both_in_flight(&t).await;
    let (s, v, h) = call(&t, "GET", "/api/v1/state", Some(&op), None).await;
    assert_eq!((s, v["code"].as_str()), (503, Some("overloaded")), "{v}");
    assert_eq!(h["retry-after"], "1");
    let (s, _, _) = call(&t, "GET", "/health", None, None).await;
    assert_eq!(s, 200, "/health is never shed");
    let (s, v, _) = call(&t, "POST", "/api/v1/stop", Some(&op), None).await;
    assert_eq!(s, 200, "stop gets through a full service: {v}");
    let (a, b) = (a.await.expect("task"), b.await.expect("task"));
    assert_eq!(
        (a.ok(), b.ok()),
        (Some(409), Some(409)),
        "both stopped (cancelled)"
    );

    for _ in 0..2 {
        let (s, _, _) = call(&t, "GET", "/api/v1/state", Some("kb_guess"), None).await;
        assert_eq!(s, 401);
    }
    let (s, _, _) = call(&t, "GET", "/api/v1/state", Some(&op), None).await;
    assert_eq!(s, 429, "locked out");
    let (s, v, _) = call(&t, "POST", "/api/v1/stop", Some(&op), None).await;
    assert_eq!(
        s, 200,
        "a valid token stops the robot from a locked-out address: {v}"
    );
    let (s, _, _) = call(&t, "POST", "/api/v1/stop", Some("kb_guess"), None).await;
    assert_eq!(
        s, 429,
        "a wrong one is refused like any other guess from there"
    );
    t.service.shutdown().await.expect("shutdown");
}

/// The holder's own long call keeps its lease; revoking the holder's token
/// ends it; unidentified callers see no position; HEAD is GET.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn lease_outlives_a_long_call_and_ends_with_its_token() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| {
            c.auth.require_on_loopback = true;
            c.auth.lease_ms = 1000;
        }),
        ..Options::default()
    })
    .await;
    let admin = initial_admin_secret(&t.dirs.path().join("data"));
    let one = t.create_token(&admin, "op-one", "operator").await;
    let two = t.create_token(&admin, "op-two", "operator").await;
    let (s, _, _) = call(&t, "POST", "/api/v1/control", Some(&one), None).await;
    assert_eq!(s, 200);
    // A motion of about 3 s, longer than the 1 s lease.
    let long = {
        let (http, url, one) = (t.http.clone(), t.url("/api/v1/motions"), one.clone());
        tokio::spawn(async move {
            http.post(url)
                .bearer_auth(one)
                .json(&json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 60}, "velocity_pct": 10}]}))
                .send()
                .await
                .map(|r| r.status().as_u16())
        })
    };
    // Let time pass on purpose: the test is that the lease does NOT lapse
    // during the call, so wait past its 1 s (no state shows "not yet").
    tokio::time::sleep(Duration::from_millis(1600)).await;
    let (s, v, _) = call(&t, "POST", "/api/v1/control", Some(&two), None).await;
    assert_eq!(
        (s, v["code"].as_str()),
        (409, Some("control_held")),
        "lease kept during the call: {v}"
    );
    assert_eq!(long.await.expect("task").ok(), Some(200));
    let (_, v, _) = call(&t, "GET", "/api/v1/control", Some(&two), None).await;
    assert_eq!(
        v["lease"]["holder"], "op-one",
        "renewed when the call ended: {v}"
    );

    let (s, _, _) = call(&t, "DELETE", "/api/v1/tokens/op-one", Some(&admin), None).await;
    assert_eq!(s, 200);
    let (_, v, _) = call(&t, "GET", "/api/v1/control", Some(&two), None).await;
    assert_eq!(
        v["lease"],
        Value::Null,
        "a revoked token holds no control: {v}"
    );

    // The robot moved (A1 = 60): an unidentified thesis client does not
    // learn where it is.
    let (s, v, _) = call(&t, "POST", "/krl/getpos", None, None).await;
    assert_eq!(s, 401);
    assert_eq!(v["position"], json!([0.0, 0.0, 0.0, 0.0, 0.0, 0.0]), "{v}");
    let (s, v, _) = call(&t, "POST", "/krl/getpos", Some(&two), None).await;
    assert_eq!(s, 200);
    assert_ne!(v["position"], json!([0.0, 0.0, 0.0, 0.0, 0.0, 0.0]));

    // HEAD follows GET's rule and is not audited.
    let r = t.http.head(t.url("/health")).send().await.expect("head");
    assert_eq!(r.status().as_u16(), 200);
    let r = t
        .http
        .head(t.url("/api/v1/state"))
        .bearer_auth(&two)
        .send()
        .await
        .expect("head");
    assert_eq!(r.status().as_u16(), 200);
    let (_, heads, _) = call(&t, "GET", "/api/v1/audit?method=HEAD", Some(&admin), None).await;
    assert_eq!(heads, json!([]));
    t.service.shutdown().await.expect("shutdown");
}

/// Connections that send nothing are closed after `header_timeout_ms`, and
/// one address cannot open more than `max_connections_per_client`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn idle_and_excess_connections_are_closed() {
    use tokio::io::AsyncReadExt;
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.server.header_timeout_ms = 500;
            c.server.max_connections_per_client = 3;
        }),
        ..Options::default()
    })
    .await;
    // (The test client's pooled connection may count as one of the three
    // too; either way the fourth is over the limit.)
    let addr = t.service.addr;
    let quiet = || async move { tokio::net::TcpStream::connect(addr).await.expect("connect") };
    let closed_within = |mut s: tokio::net::TcpStream, d: Duration| async move {
        let mut buf = [0u8; 64];
        matches!(
            tokio::time::timeout(d, s.read(&mut buf)).await,
            Ok(Ok(0) | Err(_))
        )
    };
    let mut idle = Vec::new();
    for _ in 0..3 {
        idle.push(quiet().await);
    }
    // No wait needed: the server admits connections in its accept loop, in
    // the order the kernel queued them (the order of the connects above),
    // so the three are counted before the fourth.
    let fourth = quiet().await;
    assert!(
        closed_within(fourth, Duration::from_millis(300)).await,
        "over the per-client limit: closed at once"
    );
    let started = std::time::Instant::now();
    for s in idle {
        assert!(
            closed_within(s, Duration::from_secs(3)).await,
            "an idle connection is closed"
        );
    }
    assert!(
        started.elapsed() < Duration::from_secs(2),
        "closed after about 0.5 s"
    );
    let r = reqwest::Client::new()
        .get(t.url("/health"))
        .send()
        .await
        .expect("health");
    assert_eq!(
        r.status().as_u16(),
        200,
        "new connections are welcome again"
    );
    t.service.shutdown().await.expect("shutdown");
}

/// When all connections are taken, the idlest is closed to make room; a
/// client that stops reading its answers is dropped.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn full_service_makes_room_and_drops_clients_that_do_not_read() {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.server.header_timeout_ms = 500;
            c.server.max_connections = 2;
        }),
        ..Options::default()
    })
    .await;
    let addr = t.service.addr;
    let mut quiet = Vec::new();
    for _ in 0..2 {
        quiet.push(tokio::net::TcpStream::connect(addr).await.expect("connect"));
    }
    // No wait needed: the server admits connections in its accept loop in
    // the order they were made, so both quiet ones hold a place before the
    // client below arrives.
    let r = reqwest::Client::new()
        .get(t.url("/health"))
        .timeout(Duration::from_secs(2))
        .send()
        .await
        .expect("a new client gets in: an idle connection made room");
    assert_eq!(r.status().as_u16(), 200);

    // A client that asks for a large answer many times and never reads.
    let socket = tokio::net::TcpSocket::new_v4().expect("socket");
    socket.set_recv_buffer_size(4096).expect("small buffer");
    let mut s = socket.connect(addr).await.expect("connect");
    let one = "GET /openapi.json HTTP/1.1\r\nHost: x\r\n\r\n".repeat(200);
    s.write_all(one.as_bytes()).await.expect("send");
    // Let time pass on purpose: this client does not read for 2.5 s (the
    // server drops a connection whose writes are stuck for 0.5 s). Waiting
    // on anything here would mean reading, and the server's connection
    // table is not visible from outside.
    tokio::time::sleep(Duration::from_millis(2500)).await;
    let mut total = 0usize;
    let mut buf = vec![0u8; 64 * 1024];
    let ended = tokio::time::timeout(Duration::from_secs(10), async {
        loop {
            match s.read(&mut buf).await {
                Ok(0) | Err(_) => return,
                Ok(n) => total += n,
            }
        }
    })
    .await;
    assert!(ended.is_ok(), "the server dropped the stuck connection");
    let (_, doc) = t.get("/openapi.json").await;
    let doc_len = doc.to_string().len();
    assert!(
        total < 200 * doc_len,
        "not every answer was delivered: {total} bytes"
    );
    t.service.shutdown().await.expect("shutdown");
}

/// An event stream ends when its token is revoked (it does not keep
/// pushing positions to a client that lost its access).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn event_streams_end_with_their_token() {
    use futures_util::StreamExt;
    let t = secured(|_| {}).await;
    let admin = initial_admin_secret(&t.config.data_dir);
    let viewer = t.create_token(&admin, "wall", "viewer").await;
    let other = t.create_token(&admin, "wall-2", "viewer").await;
    let open = |secret: String| {
        let url = t.url(&format!("/api/v1/events?access_token={secret}"));
        let http = t.http.clone();
        async move {
            let r = http.get(url).send().await.expect("events");
            assert_eq!(r.status(), 200);
            r.bytes_stream()
        }
    };
    let mut stream = open(viewer.clone()).await;
    let mut kept = open(other).await;
    assert!(stream.next().await.is_some(), "first event");
    let (s, v, _) = call(&t, "DELETE", "/api/v1/tokens/wall", Some(&admin), None).await;
    assert_eq!(s, 200, "{v}");
    let ended = tokio::time::timeout(Duration::from_secs(3), async {
        while let Some(Ok(_)) = stream.next().await {}
    })
    .await;
    assert!(ended.is_ok(), "the revoked token's stream ended within 3 s");
    // Another token's stream goes on.
    let (s, _, _) = call(&t, "POST", "/api/v1/home", Some(&admin), None).await;
    assert_eq!(s, 200);
    let next = tokio::time::timeout(Duration::from_secs(3), kept.next()).await;
    assert!(
        matches!(next, Ok(Some(Ok(_)))),
        "the other stream still delivers"
    );
    // And the revoked secret opens no new one.
    let r = t
        .http
        .get(t.url(&format!("/api/v1/events?access_token={viewer}")))
        .send()
        .await
        .expect("events");
    assert_eq!(r.status(), 401);
    t.service.shutdown().await.expect("shutdown");
}

/// Without tokens (loopback), a foreign web page cannot drive the robot
/// through the operator's browser: cross-site state-changing requests and
/// non-loopback Host names (DNS rebinding) are refused; the service's own
/// pages, configured CORS origins and clients without `Origin` still work.
#[tokio::test]
async fn cross_site_requests_are_refused_without_tokens() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| c.server.cors_origins = vec!["http://trusted.example".into()]),
        ..Options::default()
    })
    .await;
    let own = t.service.base_url();
    let send = |method: reqwest::Method, path: &str, headers: &[(&str, &str)]| {
        let mut req = t.http.request(method, t.url(path));
        for (k, v) in headers {
            req = req.header(*k, *v);
        }
        async move { kuka_bridge_tests::decode(req.send().await.expect("request")).await }
    };
    use reqwest::Method;
    // A foreign page's POST (form or no-cors fetch): refused, nothing moves.
    let (s, v) = send(
        Method::POST,
        "/api/v1/home",
        &[("origin", "http://evil.example")],
    )
    .await;
    assert_eq!((s, v["code"].as_str()), (403, Some("forbidden")), "{v}");
    assert!(
        v["detail"].as_str().unwrap_or("").contains("cross-site"),
        "{v}"
    );
    let (s, v) = send(Method::POST, "/krl/ptp?x=300", &[("origin", "null")]).await;
    assert_eq!(s, 403, "{v}");
    assert_eq!(v["statuscode"], 71, "thesis format: {v}");
    let (_, jobs) = t.get("/api/v1/jobs").await;
    assert_eq!(jobs, json!([]), "no job was created");
    // DNS rebinding: a foreign name resolving to 127.0.0.1 reads nothing either.
    let (s, v) = send(
        Method::GET,
        "/api/v1/state",
        &[("host", "rebind.evil.example")],
    )
    .await;
    assert_eq!(s, 403, "{v}");
    // The service's own pages, a configured origin, and curl-like clients work.
    let (s, v) = send(Method::POST, "/api/v1/home", &[("origin", own.as_str())]).await;
    assert_eq!(s, 200, "{v}");
    let (s, v) = send(
        Method::POST,
        "/api/v1/home",
        &[("origin", "http://trusted.example")],
    )
    .await;
    assert_eq!(s, 200, "{v}");
    let (s, v) = t.post("/api/v1/home").await;
    assert_eq!(s, 200, "{v}");
    let (s, _) = send(Method::GET, "/api/v1/state", &[("host", "localhost")]).await;
    assert_eq!(s, 200);
    t.service.shutdown().await.expect("shutdown");
}

/// A client that gives up before the answer does not take its request off
/// the record: the motion it started runs on and its audit line says so
/// (status 499, `client_disconnected`, the job). And a body sent without a
/// JSON content type (`curl -d` sends a form) is recorded with its content.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn requests_are_on_record_when_the_client_leaves_or_sends_a_form() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    // A PTP of A1 by 60° takes about a second on the KR 3.
    let motion = json!({"motions": [{"type": "ptp_axes", "axes": {"a1": 60}}]});
    let gave_up = t
        .http
        .post(t.url("/api/v1/motions"))
        .json(&motion)
        .timeout(Duration::from_millis(300))
        .send()
        .await;
    assert!(gave_up.is_err(), "the motion answered within 0.3 s");
    let deadline = Instant::now() + Duration::from_secs(10);
    let record = loop {
        let (_, records) = t.get("/api/v1/audit?path=/api/v1/motions").await;
        if let Some(r) = records.as_array().and_then(|r| r.first()).cloned() {
            break r;
        }
        assert!(Instant::now() < deadline, "no audit record: {records}");
        tokio::time::sleep(Duration::from_millis(20)).await;
    };
    assert_eq!(record["status"], 499, "{record}");
    assert_eq!(record["code"], "client_disconnected", "{record}");
    assert_eq!(record["params"]["body"], motion, "{record}");
    let job = record["jobs"][0].as_u64().expect("the job is on record");
    let (_, j) = t.get(&format!("/api/v1/jobs/{job}")).await;
    assert!(
        ["sent", "executing", "done"].contains(&j["state"].as_str().unwrap_or_default()),
        "the motion runs on: {j}"
    );

    // A body of some content type, and the newest audit record of it.
    let put_speed = |content_type: &'static str, body: &'static str| {
        let t = &t;
        async move {
            let r = t
                .http
                .put(t.url("/api/v1/speed"))
                .header("content-type", content_type)
                .body(body)
                .send()
                .await
                .expect("request");
            let (_, records) = t.get("/api/v1/audit?path=/api/v1/speed").await;
            (r.status().as_u16(), records[0].clone())
        }
    };
    // `curl -d '{"override_percent": 50}'` (a form, by curl's default).
    let form = r#"{"override_percent": 50}"#;
    let (status, record) = put_speed("application/x-www-form-urlencoded", form).await;
    assert_eq!(status, 415);
    assert_eq!(
        record["params"]["body"],
        json!({"override_percent": 50}),
        "{record}"
    );
    let (status, record) = put_speed("text/plain", "not json").await;
    assert_eq!(status, 415);
    assert_eq!(record["params"]["body_text"], "not json", "{record}");
    // Broken JSON is kept as text: the record shows what was sent.
    let broken = r#"{"override_percent":"#;
    let (status, record) = put_speed("application/json", broken).await;
    assert_eq!(status, 422);
    assert_eq!(record["params"]["body_text"], broken, "{record}");
    assert_eq!(record["code"], "invalid_input", "{record}");
    t.service.shutdown().await.expect("shutdown");
}

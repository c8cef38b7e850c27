//! WASM plugins end to end, over HTTP against the running service with the
//! simulated controller: install the example plugins, call them and check
//! the simulator's trace draws what they say; validation before activation;
//! misbehaving plugins get their error and leave the service healthy;
//! reinstall while requests run; the plugins folder (drop-in install, hot
//! reload, broken files, removal); persistence across restarts; the
//! OpenAPI document follows the installed plugins.
//!
//! The Python example needs `python3` with its `venv` module: without it
//! its tests fail with the command that installs it (leave them out on
//! purpose with `cargo test -- --skip python`).

use std::time::{Duration, Instant};

use std::path::{Path, PathBuf};

use kuka_bridge_tests::{Options, TestService};
use serde_json::{Value, json};

/// The folder of the built example plugins.
fn example_plugins(python: bool) -> PathBuf {
    kuka_bridge_tests::example_plugins(Path::new(env!("CARGO_TARGET_TMPDIR")), python)
}

/// The bytes of one built example plugin.
fn example_plugin(name: &str) -> Vec<u8> {
    let path = example_plugins(false).join(format!("{name}.wasm"));
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A point of the trace `[x, y, z]`.
type P3 = [f64; 3];

/// The trace of the motions since the last clear, with the motion index.
async fn trace(t: &TestService) -> Vec<(usize, P3)> {
    let (status, v) = t.get("/api/v1/sim/trace").await;
    assert_eq!(status, 200, "{v}");
    v.as_array()
        .expect("trace array")
        .iter()
        .map(|s| {
            let p = &s["pose"];
            let f = |i: usize| p[i].as_f64().expect("number");
            (
                s["motion"].as_u64().expect("motion") as usize,
                [f(0), f(1), f(2)],
            )
        })
        .collect()
}

async fn clear_trace(t: &TestService) {
    let (status, v) = t.delete("/api/v1/sim/trace").await;
    assert_eq!(status, 204, "{v}");
}

async fn install(t: &TestService, name: &str, wasm: Vec<u8>) -> (u16, Value) {
    t.put_bytes(&format!("/api/v1/plugins/{name}"), wasm).await
}

/// The draw-circle plugin's route.
async fn draw_circle(t: &TestService, body: Value) -> (u16, Value) {
    t.post_json("/api/v1/plugins/draw-circle/circle", &body)
        .await
}

/// A circle the KR 3 R540 reaches from its home orientation.
fn circle_body() -> Value {
    json!({"x": 300, "y": 20, "z": 100, "radius": 40})
}

/// Distance of a point (in the XY plane at height `z`) from a circle arc.
fn arc_distance(p: P3, center: [f64; 2], radius: f64, z: f64, from_to: Option<(f64, f64)>) -> f64 {
    let (dx, dy) = (p[0] - center[0], p[1] - center[1]);
    let angle = dy.atan2(dx).to_degrees().rem_euclid(360.0);
    let on_arc = match from_to {
        None => true,
        Some((a0, a1)) => {
            let (a0, a1) = (a0.rem_euclid(360.0), a1.rem_euclid(360.0));
            if a0 <= a1 {
                (a0..=a1).contains(&angle)
            } else {
                angle >= a0 || angle <= a1
            }
        }
    };
    let radial = ((dx * dx + dy * dy).sqrt() - radius).abs();
    let planar = if on_arc {
        radial
    } else {
        // Nearest end point of the arc.
        let (a0, a1) = from_to.unwrap_or((0.0, 0.0));
        [a0, a1]
            .iter()
            .map(|a| {
                let (ex, ey) = (
                    center[0] + radius * a.to_radians().cos(),
                    center[1] + radius * a.to_radians().sin(),
                );
                ((p[0] - ex).powi(2) + (p[1] - ey).powi(2)).sqrt()
            })
            .fold(f64::INFINITY, f64::min)
    };
    (planar.powi(2) + (p[2] - z).powi(2)).sqrt()
}

/// Share of check points along a circle (or arc), every 5°, that have a
/// trace point within 2 mm (the trace is sampled every 12 ms: 1.2 mm at
/// 0.1 m/s).
fn coverage(points: &[P3], center: [f64; 2], radius: f64, from_to: Option<(f64, f64)>) -> f64 {
    let (a0, span) = match from_to {
        None => (0.0, 360.0),
        Some((a0, a1)) => (a0, (a1 - a0).rem_euclid(360.0)),
    };
    let checks = (span / 5.0).ceil().max(1.0) as usize;
    let hit = (0..=checks)
        .filter(|i| {
            let a = (a0 + span * *i as f64 / checks as f64).to_radians();
            let (x, y) = (center[0] + radius * a.cos(), center[1] + radius * a.sin());
            points
                .iter()
                .any(|p| ((p[0] - x).powi(2) + (p[1] - y).powi(2)).sqrt() <= 2.0)
        })
        .count();
    hit as f64 / (checks + 1) as f64
}

#[tokio::test]
async fn draw_circle_plugin_draws_a_circle_in_both_modes() {
    let t = TestService::start(Options::default()).await;
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201, "{v}");
    assert_eq!(v["version"], "0.1.0");
    assert_eq!(v["routes"][0]["url"], "/api/v1/plugins/draw-circle/circle");

    for mode in ["circ", "lin"] {
        clear_trace(&t).await;
        let (cx, cy, z, r) = (300.0, 20.0, 100.0, 40.0);
        let body = json!({"x": cx, "y": cy, "z": z, "radius": r, "mode": mode});
        let (status, v) = draw_circle(&t, body).await;
        assert_eq!(status, 200, "{mode}: {v}");
        let motions = v["motions"].as_u64().expect("motions");
        assert_eq!(v["completed"], motions, "{v}");
        // Everything after the approach (motion 0) is on the circle.
        let drawn: Vec<P3> = trace(&t)
            .await
            .into_iter()
            .filter(|(m, _)| *m >= 1)
            .map(|(_, p)| p)
            .collect();
        assert!(drawn.len() > 20, "{mode}: only {} samples", drawn.len());
        let worst = drawn
            .iter()
            .map(|p| arc_distance(*p, [cx, cy], r, z, None))
            .fold(0.0, f64::max);
        // LIN mode: 36 chords of a 40 mm circle sag by r(1-cos 5°) = 0.15 mm.
        assert!(
            worst <= 0.5,
            "{mode}: a point is {worst:.3} mm off the circle"
        );
        let covered = coverage(&drawn, [cx, cy], r, None);
        // The batch is a job like any other, marked with the plugin that asked.
        let (_, jobs) = t.get("/api/v1/jobs?limit=1").await;
        assert_eq!(jobs[0]["origin"], "plugin:draw-circle@0.1.0", "{jobs}");
        assert_eq!(jobs[0]["state"], "done", "{jobs}");
        assert!(
            covered >= 0.99,
            "{mode}: only {:.0} % of the circle drawn",
            covered * 100.0
        );
    }
}

/// Issue 22, point 5: a plugin streams a path through the WIT's `paths`
/// interface (draw-circle with `turns`: one turn per append, never the
/// whole path in memory). The turns run as one path that never stops; the
/// path is the plugin's job; a plugin cannot touch another caller's path.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_plugin_streams_a_path_that_never_stops() {
    let t = TestService::start(Options::default()).await;
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201, "{v}");
    clear_trace(&t).await;
    let body = json!({"x": 300, "y": 20, "z": 100, "radius": 40, "mode": "lin", "segments": 36, "turns": 5});
    let (status, v) = draw_circle(&t, body).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(
        (v["motions"].as_u64(), v["completed"].as_u64()),
        (Some(181), Some(181)),
        "{v}"
    );
    let path = v["path"].as_u64().expect("path id");
    let (_, j) = t.get(&format!("/api/v1/paths/{path}")).await;
    assert_eq!(j["state"], "done", "{j}");
    assert_eq!(j["origin"], "plugin:draw-circle@0.1.0", "{j}");
    assert_eq!(j["path"]["appended"], 181, "{j}");
    // After the approach (a PTP, which stops exactly) the robot does not
    // stop until the end of the fifth turn.
    let samples = t.trace();
    let cid = j["cid"].as_i64().expect("cid");
    let circle: Vec<_> = samples
        .iter()
        .filter(|s| s.cid == cid && s.motion >= 1)
        .collect();
    assert!(circle.len() > 50, "{} samples", circle.len());
    let stops = circle[..circle.len() - 1].iter().filter(|s| s.stop).count();
    assert_eq!(stops, 0, "no stop between the turns");
    // A bad turn count is the plugin's own 400.
    let (status, v) = draw_circle(
        &t,
        json!({"x": 300, "y": 20, "z": 100, "radius": 40, "turns": 3}),
    )
    .await;
    assert_eq!(status, 400, "turns need lin mode: {v}");
}

#[tokio::test]
async fn draw_smiley_plugin_draws_the_thesis_smiley_as_one_batch() {
    let t = TestService::start(Options::default()).await;
    let (status, v) = install(&t, "draw-smiley", example_plugin("draw-smiley")).await;
    assert_eq!(status, 201, "{v}");
    clear_trace(&t).await;
    let (cx, cy, z, size) = (300.0, 0.0, 100.0, 40.0);
    let (status, v) = t
        .post_json(
            "/api/v1/plugins/draw-smiley/smiley",
            &json!({"x": cx, "y": cy, "z": z, "size": size}),
        )
        .await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["completed"], v["motions"], "{v}");
    let shapes = v["shapes"].as_array().expect("shapes");
    assert!(shapes.len() >= 4, "face, two eyes and a mouth: {shapes:?}");
    let face = &shapes[0];
    assert_eq!(face["kind"], "circle");
    assert_eq!(face["center"], json!([cx, cy]));
    assert_eq!(face["radius"], size);

    let samples = trace(&t).await;
    // One batch: a single command drew everything.
    let on_paper: Vec<P3> = samples
        .iter()
        .map(|(_, p)| *p)
        .filter(|p| (p[2] - z).abs() < 0.05)
        .collect();
    assert!(
        on_paper.len() > 50,
        "only {} samples on the paper",
        on_paper.len()
    );
    let shape = |s: &Value| {
        let c = [
            s["center"][0].as_f64().expect("cx"),
            s["center"][1].as_f64().expect("cy"),
        ];
        let r = s["radius"].as_f64().expect("radius");
        let arc = (s["kind"] == "arc").then(|| {
            (
                s["from_deg"].as_f64().expect("from"),
                s["to_deg"].as_f64().expect("to"),
            )
        });
        (c, r, arc)
    };
    // Every pen-down point lies on one of the shapes...
    for p in &on_paper {
        let best = shapes
            .iter()
            .map(|s| {
                let (c, r, arc) = shape(s);
                arc_distance(*p, c, r, z, arc)
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            best <= 0.5,
            "pen-down point {p:?} is {best:.3} mm from every shape"
        );
    }
    // ...and every shape is drawn.
    for s in shapes {
        let (c, r, arc) = shape(s);
        let near: Vec<P3> = on_paper
            .iter()
            .copied()
            .filter(|p| arc_distance(*p, c, r, z, arc) <= 0.5)
            .collect();
        let covered = coverage(&near, c, r, arc);
        assert!(
            covered >= 0.99,
            "shape {s} only {:.0} % drawn",
            covered * 100.0
        );
    }
}

#[tokio::test]
async fn install_list_openapi_and_remove() {
    let t = TestService::start(Options::default()).await;
    let (_, doc) = t.get("/openapi.json").await;
    assert!(
        doc["paths"]
            .get("/api/v1/plugins/draw-circle/circle")
            .is_none()
    );

    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201, "{v}");
    let (status, list) = t.get("/api/v1/plugins").await;
    assert_eq!(status, 200);
    assert_eq!(list[0]["name"], "draw-circle");
    assert_eq!(list[0]["status"], "active");
    assert_eq!(list[0]["routes"][0]["method"], "POST");

    // The route is documented with the plugin's own schemas.
    let (_, doc) = t.get("/openapi.json").await;
    let op = &doc["paths"]["/api/v1/plugins/draw-circle/circle"]["post"];
    assert!(op.is_object(), "plugin route missing from /openapi.json");
    let schema = &op["requestBody"]["content"]["application/json"]["schema"];
    assert!(schema["properties"]["radius"].is_object(), "{schema}");
    assert_eq!(op["tags"][0], "plugin: draw-circle");

    // Same bytes again: a replacement, 200.
    let (status, _) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 200);
    // Wrong method and unknown route.
    let (status, v) = t.get("/api/v1/plugins/draw-circle/circle").await;
    assert_eq!(
        (status, v["code"].as_str()),
        (405, Some("method_not_allowed")),
        "{v}"
    );
    let r = t
        .request(
            reqwest::Method::DELETE,
            "/api/v1/plugins/draw-circle/circle",
        )
        .await;
    assert_eq!(r.status().as_u16(), 405);
    assert_eq!(r.headers()["allow"], "POST", "as for native routes");
    let (status, v) = t
        .post_json("/api/v1/plugins/draw-circle/square", &json!({}))
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (404, Some("not_found")),
        "{v}"
    );
    // Bad input is refused by the bridge, against the plugin's schema.
    let (status, v) = draw_circle(&t, json!({"x": "far"})).await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );

    let (status, _) = t.delete("/api/v1/plugins/draw-circle").await;
    assert_eq!(status, 204);
    let (_, doc) = t.get("/openapi.json").await;
    assert!(
        doc["paths"]
            .get("/api/v1/plugins/draw-circle/circle")
            .is_none(),
        "route still documented"
    );
    let (status, v) = draw_circle(&t, json!({})).await;
    assert_eq!(
        (status, v["code"].as_str()),
        (404, Some("not_found")),
        "{v}"
    );
    let (status, _) = t.delete("/api/v1/plugins/draw-circle").await;
    assert_eq!(status, 404);
    let (_, list) = t.get("/api/v1/plugins").await;
    assert_eq!(list, json!([]));

    // A name is never a path: nothing outside the plugins folder is touched.
    let outside = t.dirs.path().join("data/keep.wasm");
    std::fs::write(&outside, b"not a plugin").expect("write");
    for name in ["..%2Fkeep", "%2E%2E%2Fkeep", "..%5Ckeep"] {
        let (status, v) = t.delete(&format!("/api/v1/plugins/{name}")).await;
        assert_eq!(
            (status, v["code"].as_str()),
            (422, Some("invalid_input")),
            "{name}: {v}"
        );
    }
    let abs =
        format!("/api/v1/plugins/{}", outside.with_extension("").display()).replace('/', "%2F");
    let (status, _) = t
        .delete(&abs.replacen("%2Fapi%2Fv1%2Fplugins%2F", "/api/v1/plugins/", 1))
        .await;
    assert_eq!(status, 422);
    assert!(
        outside.exists(),
        "a file outside the plugins folder was deleted"
    );
}

#[tokio::test]
async fn operation_ids_are_unique_with_plugins_installed() {
    let t = TestService::start(Options::default()).await;
    for name in ["draw-circle", "draw-smiley", "misbehave"] {
        let (status, v) = install(&t, name, example_plugin(name)).await;
        assert_eq!(status, 201, "{v}");
    }
    let (_, doc) = t.get("/openapi.json").await;
    let mut ids = Vec::new();
    for (path, item) in doc["paths"].as_object().expect("paths") {
        for (method, op) in item.as_object().expect("path item") {
            let id = op["operationId"]
                .as_str()
                .unwrap_or_else(|| panic!("{method} {path} has no operationId"));
            ids.push(id.to_string());
        }
    }
    let count = ids.len();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), count, "duplicate operationIds in /openapi.json");
}

#[tokio::test]
async fn invalid_plugins_are_refused_with_precise_errors_and_change_nothing() {
    let t = TestService::start(Options::default()).await;
    let (status, installed) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201);
    let refused = |v: &Value, needle: &str| {
        assert_eq!(v["code"], "plugin_invalid", "{v}");
        let detail = v["detail"].as_str().expect("detail");
        assert!(detail.contains(needle), "{needle:?} not in {detail:?}");
    };
    // Not WebAssembly at all.
    let (status, v) = install(&t, "junk", b"MZ this is not wasm".to_vec()).await;
    assert_eq!(status, 422);
    refused(&v, "not a WebAssembly component");
    // A component of another world.
    let (status, v) = install(&t, "other-world", example_plugin("other-world")).await;
    assert_eq!(status, 422);
    refused(&v, "not a kuka-bridge plugin");
    // Invalid routes and schemas: every problem listed.
    let (status, v) = install(&t, "bad-describe", example_plugin("bad-describe")).await;
    assert_eq!(status, 422);
    for needle in [
        "declared twice",
        "method must be GET or POST",
        "must start with '/'",
        "schema is not JSON",
        "POST /no-schema: the request schema does not compile as a JSON Schema",
        "nmber",
    ] {
        refused(&v, needle);
    }
    // A plugin under a name that is not its own; over an installed one.
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-smiley")).await;
    assert_eq!(status, 422);
    refused(&v, "installed as \"draw-circle\"");
    // Bad names.
    let (status, v) = install(&t, "Draw_Circle", example_plugin("draw-circle")).await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );
    // The old version still serves; nothing else was installed or written.
    let (_, list) = t.get("/api/v1/plugins").await;
    assert_eq!(list.as_array().map(Vec::len), Some(1), "{list}");
    assert_eq!(list[0]["sha256"], installed["sha256"]);
    let files: Vec<String> = std::fs::read_dir(t.dirs.path().join("data/plugins"))
        .expect("plugins dir")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    assert_eq!(files, vec!["draw-circle.wasm".to_string()]);
}

/// The jobs the service lists (`GET /api/v1/jobs`), for "nothing moved".
async fn jobs(t: &TestService) -> Value {
    let (status, v) = t.get("/api/v1/jobs").await;
    assert_eq!(status, 200, "{v}");
    v
}

/// A 422 `invalid_input` refusal of the plugin's schema: `detail` holds
/// `needle`, and `errors` an entry with this pointer and keyword.
fn schema_refused(status: u16, v: &Value, pointer: &str, keyword: &str, needle: &str) {
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );
    let detail = v["detail"].as_str().unwrap_or_default();
    assert!(detail.contains(needle), "{needle:?} not in {detail:?}");
    assert!(v["plugin"].is_string(), "{v}");
    let errors = v["errors"].as_array().expect("errors");
    assert!(
        errors
            .iter()
            .any(|e| e["pointer"] == pointer && e["keyword"] == keyword),
        "no error at {pointer:?} for {keyword}: {v}"
    );
}

#[tokio::test]
async fn request_schemas_are_enforced_before_the_plugin_runs() {
    let t = TestService::start(Options::default()).await;
    for name in ["draw-circle", "misbehave"] {
        let (status, v) = install(&t, name, example_plugin(name)).await;
        assert_eq!(status, 201, "{v}");
    }
    clear_trace(&t).await;
    let before = jobs(&t).await;

    // draw-circle's schema says `additionalProperties: false`.
    let mut extra = circle_body();
    extra["pen"] = json!("red");
    let (status, v) = draw_circle(&t, extra).await;
    schema_refused(status, &v, "/pen", "additionalProperties", "/pen: ");
    // The problem of any other invalid_input of the API.
    let (_, native) = t.post_json("/api/v1/motions", &json!({"motions": 7})).await;
    assert_eq!(native["code"], "invalid_input", "{native}");
    assert_eq!(
        (&v["type"], &v["title"]),
        (&native["type"], &native["title"]),
        "{v}"
    );
    // A query parameter on a POST route (its input is the body).
    let (status, v) = t
        .post_json(
            "/api/v1/plugins/draw-circle/circle?radius=9999",
            &circle_body(),
        )
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );
    assert!(
        v["detail"].as_str().is_some_and(|d| d.contains("radius")),
        "{v}"
    );
    // A string for a number.
    let mut text = circle_body();
    text["x"] = json!("220");
    let (status, v) = draw_circle(&t, text).await;
    schema_refused(
        status,
        &v,
        "/x",
        "type",
        r#"/x: "220" is not of type "number""#,
    );
    // Out of range, missing, several at once, not JSON at all.
    let mut big = circle_body();
    big["radius"] = json!(600);
    let (status, v) = draw_circle(&t, big).await;
    schema_refused(status, &v, "/radius", "maximum", "/radius: 600");
    let (status, v) = draw_circle(&t, json!({"x": 300, "y": 20, "z": 100})).await;
    schema_refused(
        status,
        &v,
        "",
        "required",
        "\"radius\" is a required property",
    );
    let (status, v) = draw_circle(
        &t,
        json!({"x": true, "y": 20, "z": 100, "radius": "4", "mode": "oval"}),
    )
    .await;
    for (pointer, keyword) in [("/x", "type"), ("/radius", "type"), ("/mode", "enum")] {
        schema_refused(
            status,
            &v,
            pointer,
            keyword,
            "does not match the plugin's request schema",
        );
    }
    // A body declared as something else than JSON.
    let (status, v) = t
        .post_text("/api/v1/plugins/draw-circle/circle", "x=300".into())
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (415, Some("unsupported_media_type")),
        "{v}"
    );
    // A body that says it is JSON and is not.
    let r = t
        .http
        .post(t.url("/api/v1/plugins/draw-circle/circle"))
        .header("content-type", "application/json")
        .body("x=300")
        .send()
        .await
        .expect("request");
    let (status, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );
    assert!(
        v["detail"]
            .as_str()
            .unwrap_or_default()
            .contains("is not JSON"),
        "{v}"
    );
    // A GET route's query is checked too, typed as its schema says.
    let (status, v) = t.get("/api/v1/plugins/misbehave/echo?n=abc").await;
    schema_refused(
        status,
        &v,
        "/n",
        "type",
        r#"/n: "abc" is not of type "integer""#,
    );
    let (status, v) = t.get("/api/v1/plugins/misbehave/echo?n=3&color=red").await;
    schema_refused(status, &v, "/color", "additionalProperties", "/color");
    let (status, v) = t.get("/api/v1/plugins/misbehave/echo?label=a").await;
    schema_refused(status, &v, "", "required", "\"n\" is a required property");
    let (status, v) = t
        .get("/api/v1/plugins/misbehave/echo?n=3&label=a%20b")
        .await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(
        v,
        json!({"n": "3", "label": "a b"}),
        "the plugin gets the query as sent"
    );

    // Nothing reached the robot.
    assert_eq!(jobs(&t).await, before, "a refused request created a job");
    assert!(
        trace(&t).await.is_empty(),
        "a refused request moved the robot"
    );

    // A valid body still draws.
    let (status, v) = draw_circle(&t, circle_body()).await;
    assert_eq!(status, 200, "{v}");
    assert!(!trace(&t).await.is_empty());
}

#[tokio::test]
async fn plugin_error_codes_reach_the_client_unchanged() {
    let t = TestService::start(Options::default()).await;
    let (status, v) = install(&t, "misbehave", example_plugin("misbehave")).await;
    assert_eq!(status, 201, "{v}");
    for (http, code) in [
        (400, "bad_request"),
        (409, "pen_is_up"),
        (422, "invalid_input"),
        (503, "paper_missing"),
    ] {
        let detail = format!("the plugin says {code}");
        let r = t
            .http
            .post(t.url("/api/v1/plugins/misbehave/refuse"))
            .json(&json!({"status": http, "code": code, "detail": detail}))
            .send()
            .await
            .expect("request");
        assert_eq!(r.headers()["content-type"], "application/problem+json");
        let (status, v) = kuka_bridge_tests::decode(r).await;
        assert_eq!(status, http, "{v}");
        assert_eq!(v["code"], code, "{v}");
        assert_eq!(v["detail"], detail.as_str(), "{v}");
        assert_eq!(
            v["field"], "from the plugin",
            "its own members are kept: {v}"
        );
        assert_eq!(
            (&v["status"], &v["plugin"]),
            (&json!(http), &json!("misbehave")),
            "{v}"
        );
        assert!(v.get("errors").is_none(), "not a schema refusal: {v}");
        // A relayed bridge code links to its catalogue section; the plugin's own does not.
        let expected_type = if code == "invalid_input" {
            "/errors#invalid_input"
        } else {
            "about:blank"
        };
        assert_eq!(v["type"], expected_type, "{v}");
    }
    // A status HTTP does not register (clients cannot type it) is the plugin's fault.
    let (status, v) = t
        .post_json(
            "/api/v1/plugins/misbehave/refuse",
            &json!({"status": 599, "code": "odd"}),
        )
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (502, Some("plugin_bad_response")),
        "{v}"
    );
}

#[tokio::test]
async fn misbehaving_plugins_get_their_error_and_the_service_keeps_running() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.plugins.cpu_time_ms = 300;
            c.plugins.memory_mib = 16;
            c.plugins.max_motions = 100;
        }),
        ..Options::default()
    })
    .await;
    let (status, v) = install(&t, "misbehave", example_plugin("misbehave")).await;
    assert_eq!(status, 201, "{v}");
    let (status, _) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201);

    let call = |route: &'static str| {
        let t = &t;
        async move {
            t.post_json(&format!("/api/v1/plugins/misbehave/{route}"), &json!({}))
                .await
        }
    };
    let (status, v) = call("ok").await;
    assert_eq!((status, v["ok"].as_bool()), (200, Some(true)), "{v}");
    // HEAD on a GET route is the GET without its body, as for native routes.
    let r = t
        .request(reqwest::Method::HEAD, "/api/v1/plugins/misbehave/ping")
        .await;
    assert_eq!(r.status().as_u16(), 200);
    assert_eq!(r.headers()["content-type"], "application/json");
    assert_eq!(r.bytes().await.expect("body").len(), 0);
    let r = t
        .request(reqwest::Method::PUT, "/api/v1/plugins/misbehave/ping")
        .await;
    assert_eq!(r.status().as_u16(), 405);
    assert_eq!(r.headers()["allow"], "GET,HEAD");
    // The state a plugin reads is the REST API's.
    let (status, state) = call("state").await;
    assert_eq!(status, 200, "{state}");
    let (_, rest) = t.get("/api/v1/state").await;
    assert_eq!(state["connection"], "online", "{state}");
    assert_eq!(state["speed"], rest["speed"], "{state}");
    assert_eq!(state["model"], rest["model"], "{state}");
    for (route, http, code, needle) in [
        ("loop", 504, "plugin_timeout", "300 ms"),
        ("alloc", 502, "plugin_memory", "16 MiB"),
        ("panic", 502, "plugin_trap", "plugin bug"),
        ("recurse", 502, "plugin_trap", ""),
        ("garbage", 502, "plugin_bad_response", "not JSON"),
        ("bad-status", 502, "plugin_bad_response", "status 42"),
    ] {
        let started = Instant::now();
        let (status, v) = call(route).await;
        assert_eq!(
            (status, v["code"].as_str()),
            (http, Some(code)),
            "/{route}: {v}"
        );
        let detail = v["detail"].as_str().unwrap_or_default();
        assert!(
            detail.contains(needle),
            "/{route}: {needle:?} not in {detail:?}"
        );
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "/{route} took {:?}",
            started.elapsed()
        );
        // The service, the same plugin and the other plugins keep working.
        let (status, _) = t.get("/health").await;
        assert_eq!(status, 200);
        let (status, v) = call("ok").await;
        assert_eq!(status, 200, "after /{route}: {v}");
    }
    // More motions than a request may run: the host refuses, the plugin reports it.
    let (status, v) = call("many").await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "plugin_motion_limit", "{v}");
    // A plugin's motions go through the same safety checks as a client's.
    let (status, v) = draw_circle(&t, json!({"x": 2000, "y": 0, "z": 100, "radius": 40})).await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "unreachable", "{v}");
    // With the title that code has everywhere in the API.
    let (_, native) = t
        .motions(json!([{"type": "lin", "target": {"x": 2000, "y": 0, "z": 100}}]))
        .await;
    assert_eq!(native["code"], "unreachable", "{native}");
    assert_eq!(
        (&v["type"], &v["title"]),
        (&native["type"], &native["title"]),
        "{v}"
    );
    let (status, v) = draw_circle(
        &t,
        json!({"x": 300, "y": 0, "z": 100, "radius": 40, "speed_m_s": 50}),
    )
    .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("speed_limit")),
        "{v}"
    );
    let (status, v) = draw_circle(&t, circle_body()).await;
    assert_eq!(status, 200, "{v}");
}

/// As many requests at once as the host runs (64): 32 that keep their
/// instance for a while (`/loop` until its CPU budget ends) and 32 clients
/// calling `/ping` again as soon as they are answered: every ping is served
/// (finished instances are released after their answer; the pool keeps
/// room for those still being released). Then 70 at once: exactly 64 run,
/// 6 are refused with 503 `queue_full` and `Retry-After`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sixty_four_requests_run_at_once_and_no_more() {
    let t = TestService::start(Options {
        // Long enough that no loop ends before all 70 requests of the
        // second part are in, even on a loaded CI machine (at 1.5 s two
        // loops once ended first and let two more in).
        tweak: Box::new(|c| c.plugins.cpu_time_ms = 4000),
        ..Options::default()
    })
    .await;
    let (status, v) = install(&t, "misbehave", example_plugin("misbehave")).await;
    assert_eq!(status, 201, "{v}");
    let t = std::sync::Arc::new(t);
    let post_loop = |t: std::sync::Arc<TestService>| async move {
        let r = t
            .http
            .post(t.url("/api/v1/plugins/misbehave/loop"))
            .json(&json!({}))
            .send()
            .await
            .expect("request");
        let retry_after = r.headers().get("retry-after").is_some();
        let (status, v) = kuka_bridge_tests::decode(r).await;
        (
            status,
            v["code"].as_str().unwrap_or_default().to_string(),
            retry_after,
        )
    };
    let loops_left = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(32));
    let mut loops = Vec::new();
    let mut pingers = Vec::new();
    for _ in 0..32 {
        let (t2, left) = (t.clone(), loops_left.clone());
        loops.push(tokio::spawn(async move {
            let answer = post_loop(t2).await;
            left.fetch_sub(1, std::sync::atomic::Ordering::SeqCst);
            answer
        }));
        let (t2, left) = (t.clone(), loops_left.clone());
        pingers.push(tokio::spawn(async move {
            let mut answers = Vec::new();
            while left.load(std::sync::atomic::Ordering::SeqCst) > 0 {
                let (status, v) = t2.get("/api/v1/plugins/misbehave/ping").await;
                answers.push(format!("{status} {v}"));
            }
            answers
        }));
    }
    for l in loops {
        let (status, code, _) = l.await.expect("loop");
        assert_eq!((status, code.as_str()), (504, "plugin_timeout"));
    }
    let mut pings = Vec::new();
    for p in pingers {
        pings.extend(p.await.expect("pinger"));
    }
    let failed: Vec<_> = pings.iter().filter(|p| !p.starts_with("200 ")).collect();
    assert!(
        failed.is_empty(),
        "{} of {} pings failed: {:?}",
        failed.len(),
        pings.len(),
        &failed[..failed.len().min(3)]
    );
    assert!(
        pings.len() > 32,
        "only {} pings ran while the loops did",
        pings.len()
    );

    let seventy: Vec<_> = (0..70)
        .map(|_| tokio::spawn(post_loop(t.clone())))
        .collect();
    let mut answers = Vec::new();
    for a in seventy {
        answers.push(a.await.expect("loop"));
    }
    let ran = answers
        .iter()
        .filter(|a| a.0 == 504 && a.1 == "plugin_timeout")
        .count();
    let busy = answers
        .iter()
        .filter(|a| a.0 == 503 && a.1 == "queue_full" && a.2)
        .count();
    assert_eq!((ran, busy), (64, 6), "{answers:?}");
}

#[tokio::test]
async fn limits_can_be_set_per_plugin() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.plugins.cpu_time_ms = 5000;
            c.plugins.limits.insert(
                "misbehave".into(),
                kuka_bridge::config::PluginLimitsConfig {
                    cpu_time_ms: Some(100),
                    memory_mib: Some(8),
                    ..Default::default()
                },
            );
        }),
        ..Options::default()
    })
    .await;
    for name in ["misbehave", "draw-circle"] {
        let (status, v) = install(&t, name, example_plugin(name)).await;
        assert_eq!(status, 201, "{v}");
    }
    let (_, v) = t.get("/api/v1/plugins/misbehave").await;
    assert_eq!(v["limits"]["cpu_time_ms"], 100, "{v}");
    assert_eq!(v["limits"]["memory_mib"], 8, "{v}");
    let (_, v) = t.get("/api/v1/plugins/draw-circle").await;
    assert_eq!(v["limits"]["cpu_time_ms"], 5000, "{v}");
    assert_eq!(v["limits"]["memory_mib"], 64, "{v}");
    let started = Instant::now();
    let (status, v) = t
        .post_json("/api/v1/plugins/misbehave/loop", &json!({}))
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (504, Some("plugin_timeout")),
        "{v}"
    );
    assert!(
        v["detail"].as_str().unwrap_or_default().contains("100 ms"),
        "{v}"
    );
    assert!(
        started.elapsed() < Duration::from_secs(3),
        "{:?}",
        started.elapsed()
    );
    let (status, v) = t
        .post_json("/api/v1/plugins/misbehave/alloc", &json!({}))
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (502, Some("plugin_memory")),
        "{v}"
    );
    assert!(
        v["detail"].as_str().unwrap_or_default().contains("8 MiB"),
        "{v}"
    );
}

#[tokio::test]
async fn a_request_that_outlives_its_time_limit_is_answered_and_the_plugin_keeps_serving() {
    // Real time: the circle takes seconds; the request may take 300 ms.
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| c.plugins.request_timeout_ms = 300),
        ..Options::default()
    })
    .await;
    let (status, _) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201);
    let started = Instant::now();
    let (status, v) = draw_circle(&t, circle_body()).await;
    assert_eq!(
        (status, v["code"].as_str()),
        (504, Some("plugin_timeout")),
        "{v}"
    );
    assert!(
        started.elapsed() < Duration::from_secs(3),
        "{:?}",
        started.elapsed()
    );
    // The motions it queued are jobs like any other: visible and cancellable.
    let (status, _) = t.post("/api/v1/stop").await;
    assert_eq!(status, 200);
}

#[tokio::test]
async fn reinstalling_while_requests_run_lets_them_finish_on_the_old_version() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let (status, _) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201);
    let url = t.url("/api/v1/plugins/draw-circle/circle");
    let http = t.http.clone();
    let running = tokio::spawn(async move {
        let r = http
            .post(url)
            .json(&json!({"x": 300, "y": 20, "z": 100, "radius": 20, "speed_m_s": 0.2}))
            .send()
            .await
            .expect("request");
        kuka_bridge_tests::decode(r).await
    });
    // Reinstall while its motion runs on the controller.
    t.wait_state("the circle's motion on the controller", |st| {
        st["busy"] == true
    })
    .await;
    assert!(
        !running.is_finished(),
        "the circle request ended before its motion could be caught running"
    );
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle-0.2.0")).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["version"], "0.2.0");
    let (status, v) = running.await.expect("task");
    assert_eq!(status, 200, "the request in flight failed: {v}");
    let (_, info) = t.get("/api/v1/plugins/draw-circle").await;
    assert_eq!(info["version"], "0.2.0");
    // Back to the first version: its compiled code is still in the cache.
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(
        (&v["version"], &v["from_cache"]),
        (&json!("0.1.0"), &json!(true)),
        "{v}"
    );
}

/// Waits until `GET /api/v1/plugins/{name}` satisfies `ok` (10 s).
async fn wait_plugin(t: &TestService, name: &str, ok: impl Fn(u16, &Value) -> bool) -> Value {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let (status, v) = t.get(&format!("/api/v1/plugins/{name}")).await;
        if ok(status, &v) {
            return v;
        }
        assert!(
            Instant::now() < deadline,
            "plugin {name} never got there: {status} {v}"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

#[tokio::test]
async fn the_plugins_folder_installs_reloads_and_removes() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| c.plugins.poll_interval_ms = 200),
        ..Options::default()
    })
    .await;
    let dir = t.dirs.path().join("data/plugins");
    let file = dir.join("draw-circle.wasm");
    // Drop-in install.
    std::fs::write(&file, example_plugin("draw-circle")).expect("write");
    wait_plugin(&t, "draw-circle", |s, v| {
        s == 200 && v["version"] == "0.1.0"
    })
    .await;
    let (_, doc) = t.get("/openapi.json").await;
    assert!(doc["paths"]["/api/v1/plugins/draw-circle/circle"].is_object());
    // A broken file never takes the working version down.
    std::fs::write(&file, b"\0asm broken").expect("write");
    let v = wait_plugin(&t, "draw-circle", |_, v| v["file_error"].is_object()).await;
    assert_eq!(v["status"], "active", "{v}");
    assert_eq!(v["version"], "0.1.0");
    assert_eq!(v["file_error"]["code"], "plugin_invalid", "{v}");
    let (status, v) = draw_circle(&t, circle_body()).await;
    assert_eq!(status, 200, "{v}");
    // Hot reload of a new version.
    std::fs::write(&file, example_plugin("draw-circle-0.2.0")).expect("write");
    let v = wait_plugin(&t, "draw-circle", |_, v| v["version"] == "0.2.0").await;
    assert!(v.get("file_error").is_none(), "{v}");
    // A broken file for a new name is listed as failed.
    std::fs::write(dir.join("broken.wasm"), b"nope").expect("write");
    let v = wait_plugin(&t, "broken", |s, _| s == 200).await;
    assert_eq!(v["status"], "failed", "{v}");
    let (status, _) = t.post_json("/api/v1/plugins/broken/x", &json!({})).await;
    assert_eq!(status, 404);
    // Deleting the file unloads the plugin.
    std::fs::remove_file(&file).expect("remove");
    wait_plugin(&t, "draw-circle", |s, _| s == 404).await;
    let (_, doc) = t.get("/openapi.json").await;
    assert!(
        doc["paths"]
            .get("/api/v1/plugins/draw-circle/circle")
            .is_none()
    );
}

#[tokio::test]
async fn installed_plugins_load_at_start_from_the_compiled_cache() {
    let t = TestService::start(Options::default()).await;
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201, "{v}");
    assert_eq!(v["from_cache"], false);
    let TestService { service, dirs, .. } = t;
    let mut config = kuka_bridge_tests::test_config(dirs.path());
    config.simulator.enabled = true;
    config.simulator.time_scale = 0.0;
    service.shutdown().await.expect("shutdown");
    let t = TestService::start_with(config, dirs).await;
    let (status, v) = t.get("/api/v1/plugins/draw-circle").await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["from_cache"], true, "{v}");
    let (status, v) = draw_circle(&t, circle_body()).await;
    assert_eq!(status, 200, "{v}");
}

/// The Python example `py-square.wasm` (built once with componentize-py
/// from PyPI into a venv). Without python3 and its venv module the test
/// fails with the command that installs them ([`kuka_bridge_tests::missing_tool`]:
/// it never returns `None`).
fn python_plugin() -> Option<Vec<u8>> {
    let python = if cfg!(windows) { "python" } else { "python3" };
    let have_python = std::process::Command::new(python)
        .args(["-c", "import venv, ensurepip"])
        .status()
        .is_ok_and(|s| s.success());
    if !have_python {
        kuka_bridge_tests::missing_tool(
            &format!(
                "{python} with venv/ensurepip is not installed (the Python plugin example needs it)"
            ),
            if cfg!(windows) {
                "winget install Python.Python.3.12"
            } else if cfg!(target_os = "macos") {
                "brew install python3"
            } else {
                "sudo apt-get install python3 python3-venv"
            },
            "python",
        );
        return None;
    }
    Some(std::fs::read(example_plugins(true).join("py-square.wasm")).expect("py-square.wasm"))
}

#[tokio::test]
async fn python_plugin_built_with_componentize_py_draws_a_square() {
    let Some(wasm) = python_plugin() else { return };
    let t = TestService::start(Options::default()).await;
    let (status, v) = install(&t, "py-square", wasm).await;
    assert_eq!(status, 201, "{v}");
    clear_trace(&t).await;
    // The reported contract breaches: a string for a number and an extra
    // field are refused against the plugin's schema; nothing moves.
    let before = jobs(&t).await;
    for (body, pointer, keyword) in [
        (
            json!({"x": "220", "y": 0, "z": 100, "side": 40}),
            "/x",
            "type",
        ),
        (
            json!({"x": 220, "y": 0, "z": 100, "side": 40, "colour": "red"}),
            "/colour",
            "additionalProperties",
        ),
    ] {
        let (status, v) = t.post_json("/api/v1/plugins/py-square/square", &body).await;
        schema_refused(status, &v, pointer, keyword, pointer);
    }
    assert_eq!(jobs(&t).await, before);
    assert!(trace(&t).await.is_empty());
    let (x, y, z, side) = (300.0, 0.0, 100.0, 40.0);
    let (status, v) = t
        .post_json(
            "/api/v1/plugins/py-square/square",
            &json!({"x": x, "y": y, "z": z, "side": side}),
        )
        .await;
    assert_eq!(status, 200, "{v}");
    let corners: Vec<[f64; 2]> = v["corners"]
        .as_array()
        .expect("corners")
        .iter()
        .map(|c| [c[0].as_f64().expect("x"), c[1].as_f64().expect("y")])
        .collect();
    assert_eq!(corners.len(), 4, "{v}");
    // Every drawn point (after the approach) is on an edge of the square.
    let drawn: Vec<P3> = trace(&t)
        .await
        .into_iter()
        .filter(|(m, _)| *m >= 1)
        .map(|(_, p)| p)
        .collect();
    assert!(drawn.len() > 20);
    for p in &drawn {
        let d = (0..4)
            .map(|i| segment_distance(*p, corners[i], corners[(i + 1) % 4], z))
            .fold(f64::INFINITY, f64::min);
        assert!(d <= 0.5, "{p:?} is {d:.3} mm off the square");
    }
}

fn segment_distance(p: P3, a: [f64; 2], b: [f64; 2], z: f64) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let u = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0);
    let (qx, qy) = (a[0] + u * dx, a[1] + u * dy);
    ((p[0] - qx).powi(2) + (p[1] - qy).powi(2) + (p[2] - z).powi(2)).sqrt()
}

/// Removing a plugin gives its memory back: the service, in a process of
/// its own, measured through `/proc/<pid>/status` (VmRSS), compiles the
/// Python example (hundreds of MiB of compiler memory at its peak), runs it
/// and removes it; within 10 s its resident memory is back within 20 MiB of
/// what it was before the install (docs/BENCHMARKS.md §3 has the figures).
#[cfg(target_os = "linux")]
#[tokio::test]
async fn removing_the_python_plugin_gives_its_memory_back() {
    use kuka_bridge_tests::bench::rss_mib;
    let Some(wasm) = python_plugin() else { return };
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
    let rss = || rss_mib(Some(pid)).expect("VmRSS of the service");
    let http = reqwest::Client::new();
    let url = |p: &str| format!("{}{p}", service.url());
    // Settled: the simulator is online, and the resident memory no longer
    // grows (two readings 200 ms apart within 0.5 MiB).
    kuka_bridge_tests::wait_for(
        Duration::from_secs(30),
        "the simulator online",
        async || {
            let r = http
                .get(url("/health"))
                .send()
                .await
                .map_err(|e| e.to_string())?;
            let (_, h) = kuka_bridge_tests::decode(r).await;
            (h["connection"] == "online")
                .then_some(())
                .ok_or_else(|| h.to_string())
        },
    )
    .await;
    let mut last = (Instant::now(), rss());
    let before = kuka_bridge_tests::wait_for(
        kuka_bridge_tests::WAIT,
        "the memory to settle",
        async || {
            let now = rss();
            if last.0.elapsed() < Duration::from_millis(200) {
                return Err(format!("{now:.1} MiB"));
            }
            let (_, prev) = std::mem::replace(&mut last, (Instant::now(), now));
            if (now - prev).abs() < 0.5 {
                Ok(now)
            } else {
                Err(format!("{prev:.1} -> {now:.1} MiB"))
            }
        },
    )
    .await;

    let r = http
        .put(url("/api/v1/plugins/py-square"))
        .body(wasm)
        .send()
        .await
        .expect("install");
    let (status, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(status, 201, "{v}");
    let installed = rss();
    for _ in 0..3 {
        let r = http
            .post(url("/api/v1/plugins/py-square/square"))
            .json(&json!({"x": 300, "y": 0, "z": 100, "side": 20}))
            .send()
            .await
            .expect("square");
        let (status, v) = kuka_bridge_tests::decode(r).await;
        assert_eq!(status, 200, "{v}");
    }
    let called = rss();
    let r = http
        .delete(url("/api/v1/plugins/py-square"))
        .send()
        .await
        .expect("remove");
    assert_eq!(r.status().as_u16(), 204);
    let figures = |after: f64| {
        format!(
            "VmRSS {before:.1} MiB before the install, {installed:.1} installed, {called:.1} after 3 calls, {after:.1} after the removal"
        )
    };
    // This measures the right process: the plugin did take memory.
    assert!(installed - before > 10.0, "{}", figures(rss()));
    // The memory goes back off the request's path (a blocking thread).
    kuka_bridge_tests::wait_for(
        kuka_bridge_tests::WAIT,
        "the memory of the removed plugin",
        async || {
            let after = rss();
            (after <= before + 20.0)
                .then_some(())
                .ok_or_else(|| figures(after))
        },
    )
    .await;
}

// ---------------------------------------------------------------------
// Spline motions from plugins (issue 22, point 5): the WIT's `splines`
// interface, draw-circle's spl mode, and a plugin built against the
// contract as it was before `splines`.
// ---------------------------------------------------------------------

/// One sample of `GET /api/v1/sim/trace` with what the spline tests need.
struct TraceSample {
    /// Simulated seconds.
    t: f64,
    cid: i64,
    motion: usize,
    p: P3,
}

/// The trace since the last clear, from `GET /api/v1/sim/trace`.
async fn trace_samples(t: &TestService) -> Vec<TraceSample> {
    let (status, v) = t.get("/api/v1/sim/trace").await;
    assert_eq!(status, 200, "{v}");
    v.as_array()
        .expect("trace array")
        .iter()
        .map(|s| {
            let f = |i: usize| s["pose"][i].as_f64().expect("number");
            TraceSample {
                t: s["t"].as_f64().expect("t"),
                cid: s["cid"].as_i64().expect("cid"),
                motion: s["motion"].as_u64().expect("motion") as usize,
                p: [f(0), f(1), f(2)],
            }
        })
        .collect()
}

/// The pen-down pose of docs/BENCHMARKS.md §7 (B 180, Status 6), from
/// where the KR 3 R540 draws a 50 mm circle around (190, 0) at z 100.
async fn pen_down(t: &TestService) {
    let (status, v) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": [{"type": "ptp", "target": {"x": 240, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0, "s": 6}}]}),
        )
        .await;
    assert_eq!(status, 200, "{v}");
}

/// The centre, height and radius of the circle of docs/BENCHMARKS.md §7.
const SPLINE_CIRCLE: ([f64; 2], f64, f64) = ([190.0, 0.0], 100.0, 50.0);

/// The largest distance from the circle of [`SPLINE_CIRCLE`] of the
/// samples that `keep`, and how many were measured. Only samples between
/// 50° and 310° count (a spline block's first and last segment follow
/// mirrored outer tangents, as in docs/BENCHMARKS.md §7).
fn off_circle(samples: &[&TraceSample]) -> (f64, usize) {
    let ([cx, cy], z, r) = SPLINE_CIRCLE;
    let on: Vec<f64> = samples
        .iter()
        .filter(|s| {
            let angle = (s.p[1] - cy)
                .atan2(s.p[0] - cx)
                .to_degrees()
                .rem_euclid(360.0);
            (50.0..=310.0).contains(&angle)
        })
        .map(|s| arc_distance(s.p, [cx, cy], r, z, None))
        .collect();
    (on.iter().copied().fold(0.0, f64::max), on.len())
}

/// How often the TCP slowed below a quarter of `v` m/s between the first
/// and the last sample at speed (an exact stop; a blended junction keeps
/// its speed). Speeds over 48 ms: the KRC-like runtime may record a pose
/// twice and then move two steps at once.
fn slowdowns(samples: &[&TraceSample], v: f64) -> usize {
    let speeds: Vec<f64> = samples
        .windows(5)
        .map(|w| {
            let (a, b) = (w[0], w[4]);
            let d =
                ((a.p[0] - b.p[0]).powi(2) + (a.p[1] - b.p[1]).powi(2) + (a.p[2] - b.p[2]).powi(2))
                    .sqrt();
            d / (b.t - a.t).max(1e-9)
        })
        .collect();
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

/// The circle of [`SPLINE_CIRCLE`] as draw-circle's request body.
fn spline_circle_body(mode: &str, extra: Value) -> Value {
    let ([x, y], z, radius) = SPLINE_CIRCLE;
    let mut body = json!({"x": x, "y": y, "z": z, "radius": radius, "mode": mode,
                          "segments": 8, "speed_m_s": 0.2});
    if let (Some(b), Some(e)) = (body.as_object_mut(), extra.as_object()) {
        b.extend(e.clone());
    }
    body
}

/// The job of the plugin's last batch or path, from `GET /api/v1/jobs`.
async fn last_job(t: &TestService) -> Value {
    let (status, jobs) = t.get("/api/v1/jobs?limit=1").await;
    assert_eq!(status, 200, "{jobs}");
    jobs[0].clone()
}

/// draw-circle's spl mode sends the PTP and 8 SPL points in ONE
/// `run-spline-motions` batch: the TCP follows the smooth curve through
/// the points (docs/BENCHMARKS.md §7: 0.42 mm off the circle), not the
/// chords, which 8 LINs of the same plugin cut 3.8 mm inside, and it keeps
/// its speed through the points.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn draw_circle_plugin_draws_a_circle_through_eight_spline_points() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201, "{v}");
    pen_down(&t).await;

    // The control: 8 LINs cut the corners of the circle.
    clear_trace(&t).await;
    let (status, v) = draw_circle(&t, spline_circle_body("lin", json!({}))).await;
    assert_eq!(status, 200, "lin: {v}");
    let samples = trace_samples(&t).await;
    let chords: Vec<&TraceSample> = samples.iter().filter(|s| s.motion >= 1).collect();
    let (lin_off, _) = off_circle(&chords);
    assert!(
        lin_off > 3.0,
        "8 LINs should cut ~3.8 mm inside the circle, not {lin_off:.2} mm"
    );

    clear_trace(&t).await;
    let (status, v) = draw_circle(&t, spline_circle_body("spl", json!({}))).await;
    assert_eq!(status, 200, "spl: {v}");
    assert_eq!(
        (v["motions"].as_u64(), v["completed"].as_u64()),
        (Some(9), Some(9)),
        "{v}"
    );
    let job = last_job(&t).await;
    assert_eq!(job["origin"], "plugin:draw-circle@0.1.0", "{job}");
    assert_eq!(job["state"], "done", "{job}");
    let cid = job["cid"].as_i64().expect("cid");
    let samples = trace_samples(&t).await;
    let curve: Vec<&TraceSample> = samples
        .iter()
        .filter(|s| s.cid == cid && s.motion >= 1)
        .collect();
    let (off, measured) = off_circle(&curve);
    assert!(measured > 30, "only {measured} samples on the circle");
    assert!(
        off <= 0.5,
        "the TCP is {off:.3} mm off the circle through the 8 spline points"
    );
    assert_eq!(slowdowns(&curve, 0.2), 0, "no stop within the spline block");
    // It ends exactly on the start point (the last point has approx_mm 0).
    let end = &v["position"];
    let ([cx, cy], _, r) = SPLINE_CIRCLE;
    assert!(
        (end["x"].as_f64().expect("x") - (cx + r)).abs() < 0.01,
        "{v}"
    );
    assert!((end["y"].as_f64().expect("y") - cy).abs() < 0.01, "{v}");
}

/// draw-circle's spl mode with `turns`: the PTP is appended with
/// `paths.append`, each turn's 8 SPL points with
/// `splines.append-spline-motions`; the blocks blend into each other, so
/// three turns run on the circle without a stop.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn draw_circle_plugin_appends_spline_turns_to_a_path() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201, "{v}");
    pen_down(&t).await;
    clear_trace(&t).await;
    let (status, v) = draw_circle(&t, spline_circle_body("spl", json!({"turns": 3}))).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(
        (v["motions"].as_u64(), v["completed"].as_u64()),
        (Some(25), Some(25)),
        "{v}"
    );
    let path = v["path"].as_u64().expect("path id");
    let (_, j) = t.get(&format!("/api/v1/paths/{path}")).await;
    assert_eq!(j["state"], "done", "{j}");
    assert_eq!(j["origin"], "plugin:draw-circle@0.1.0", "{j}");
    assert_eq!(j["path"]["appended"], 25, "{j}");
    let cid = j["cid"].as_i64().expect("cid");
    let samples = trace_samples(&t).await;
    let turns: Vec<&TraceSample> = samples
        .iter()
        .filter(|s| s.cid == cid && s.motion >= 1)
        .collect();
    let motions: Vec<usize> = turns.iter().map(|s| s.motion).collect();
    assert!(
        motions.windows(2).all(|w| w[0] <= w[1]),
        "in order: {motions:?}"
    );
    assert_eq!(motions.last(), Some(&24), "every point ran");
    // Away from the path's first and last segment (their outer tangents),
    // block joins included.
    let inner: Vec<&TraceSample> = turns
        .iter()
        .copied()
        .filter(|s| (2..=23).contains(&s.motion))
        .collect();
    let (off, measured) = off_circle(&inner);
    assert!(measured > 100, "only {measured} samples on the circle");
    assert!(off <= 0.5, "the TCP is {off:.3} mm off the circle");
    assert_eq!(slowdowns(&turns, 0.2), 0, "the turns' blocks blend");
}

/// A spline motion the robot cannot reach is refused like any motion: the
/// plugin gets the host-error with the REST API's code and the index of
/// the point (the same as `POST /api/v1/motions` answers for the same
/// batch), in a batch and in a path, and nothing of a refused batch runs.
/// Spline motions count against `max_motions` like the others.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_refused_spline_motion_reaches_the_plugin_with_its_code_and_index() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.plugins.limits.insert(
                "draw-circle".into(),
                kuka_bridge::config::PluginLimitsConfig {
                    max_motions: Some(16),
                    ..Default::default()
                },
            );
        }),
        ..Options::default()
    })
    .await;
    let (status, v) = install(&t, "draw-circle", example_plugin("draw-circle")).await;
    assert_eq!(status, 201, "{v}");
    pen_down(&t).await;
    // Starts at the pen (240, 0); the 90° point (-200, 440) is out of reach.
    let (cx, r) = (-200.0, 440.0);
    let circle = |extra: Value| {
        let mut b = json!({"x": cx, "y": 0, "z": 100, "radius": r, "mode": "spl", "segments": 8});
        if let (Some(b), Some(e)) = (b.as_object_mut(), extra.as_object()) {
            b.extend(e.clone());
        }
        b
    };
    clear_trace(&t).await;
    let (status, v) = draw_circle(&t, circle(json!({}))).await;
    assert_eq!(
        (status, v["code"].as_str(), v["motion"].as_u64()),
        (422, Some("unreachable"), Some(3)),
        "{v}"
    );
    assert!(
        trace_samples(&t).await.is_empty(),
        "nothing of a refused batch moves"
    );
    // The REST API refuses the same batch with the same code and index.
    let pose = |deg: f64, spl: bool| {
        let a = f64::to_radians(deg);
        let target =
            json!({"x": cx + r * a.cos(), "y": r * a.sin(), "z": 100, "a": 180, "b": 0, "c": 180});
        if spl {
            json!({"type": "spl", "target": target, "velocity_m_s": 0.1, "approx_mm": 1})
        } else {
            json!({"type": "ptp", "target": target, "approx_mm": 0})
        }
    };
    let mut batch = vec![pose(0.0, false)];
    batch.extend((1..=8).map(|i| pose(45.0 * f64::from(i % 8), true)));
    let (status, rest) = t
        .post_json("/api/v1/motions", &json!({"motions": batch}))
        .await;
    assert_eq!(
        (status, rest["code"].as_str(), rest["motion"].as_u64()),
        (422, Some("unreachable"), Some(3)),
        "{rest}"
    );
    // Appended to a path: the index in the path (the PTP is motion 0).
    let (status, v) = draw_circle(&t, circle(json!({"turns": 2}))).await;
    assert_eq!(
        (status, v["code"].as_str(), v["motion"].as_u64()),
        (422, Some("unreachable"), Some(3)),
        "{v}"
    );
    // 1 PTP + 16 points > max_motions 16: refused before anything is checked.
    let (status, v) = draw_circle(&t, spline_circle_body("spl", json!({"segments": 16}))).await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("plugin_motion_limit")),
        "{v}"
    );
    // 1 PTP + 8 points fit.
    let (status, v) = draw_circle(&t, spline_circle_body("spl", json!({}))).await;
    assert_eq!(status, 200, "{v}");
}

/// The compatibility promise of the WIT: a plugin built against the
/// contract as it was before the `splines` interface (the old-contract
/// fixture, with a frozen copy of that WIT) loads in this bridge and its
/// `host`, `paths` and `io` calls work as before.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_plugin_built_against_the_older_contract_loads_and_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../plugins");
    let old = std::fs::read_to_string(root.join("examples/fixtures/old-contract/wit/plugin.wit"))
        .expect("the frozen WIT");
    let now = std::fs::read_to_string(root.join("wit/plugin.wit")).expect("the WIT");
    assert!(
        now.contains("interface splines") && !old.contains("interface splines"),
        "the fixture is built against the contract before splines"
    );
    let wasm = example_plugin("old-contract");
    let imports = |name: &str| {
        let needle = format!("kuka-bridge:plugin/{name}@0.1.0");
        wasm.windows(needle.len()).any(|w| w == needle.as_bytes())
    };
    assert!(
        imports("host") && imports("paths") && imports("io") && !imports("splines"),
        "old-contract imports host, paths and io, not splines"
    );
    let t = TestService::start(Options::default()).await;
    let (status, v) = install(&t, "old-contract", wasm).await;
    assert_eq!(status, 201, "{v}");
    pen_down(&t).await;
    let (status, v) = t
        .post_json("/api/v1/plugins/old-contract/run", &json!({}))
        .await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v, json!({"run_motions": 2, "path": 2, "run_steps": 2}));
}

/// A cell for the pick-and-place plugin: the gripper on `$OUT[1]` (true =
/// closed, the only writable output), the part-present sensor on `$IN[3]`,
/// both watched.
async fn pick_and_place_cell() -> TestService {
    pick_and_place_cell_with(Vec::new()).await
}

/// [`pick_and_place_cell`] with the simulated plant's `links`.
async fn pick_and_place_cell_with(links: Vec<kuka_bridge::sim_plant::InputLink>) -> TestService {
    use kuka_bridge::io::{IoConfig, SignalConfig};
    let signal = |name: &str, index| SignalConfig {
        name: name.into(),
        index,
        pulse_ms: 0,
        watch: true,
    };
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(move |c| {
            c.io = IoConfig {
                inputs: vec![signal("part_present", 3)],
                outputs: vec![signal("gripper_close", 1)],
                ..IoConfig::default()
            };
            c.simulator.links = links;
        }),
        ..Options::default()
    })
    .await;
    let (status, v) = install(&t, "pick-and-place", example_plugin("pick-and-place")).await;
    assert_eq!(status, 201, "{v}");
    t
}

/// The part-present sensor reports the part 150 ms after the gripper
/// closes, and loses it 150 ms after it opens (a plant wired to the
/// simulated controller).
fn sensor_follows_gripper() -> kuka_bridge::sim_plant::InputLink {
    kuka_bridge::sim_plant::InputLink {
        output: 1,
        input: 3,
        delay_ms: 150,
        invert: false,
    }
}

/// Pick at (300, -60, 100), place at (300, 60, 100), approach 50 mm.
fn cycle_body(timeout_ms: u32) -> Value {
    json!({
        "pick": {"x": 300, "y": -60, "z": 100},
        "place": {"x": 300, "y": 60, "z": 100},
        "part_timeout_ms": timeout_ms,
        "speed_m_s": 0.3,
        "approach_speed_m_s": 0.1
    })
}

/// The gripper's `io` events, oldest first.
async fn gripper_events(t: &TestService) -> Vec<bool> {
    let (_, ev) = t.get("/api/v1/events/recent?types=io&limit=1000").await;
    ev.as_array()
        .expect("events")
        .iter()
        .filter(|e| e["data"]["name"] == "gripper_close")
        .filter_map(|e| e["data"]["value"].as_bool())
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pick_and_place_plugin_runs_a_cycle_as_one_job() {
    let t = pick_and_place_cell().await;
    let call = {
        let http = t.http.clone();
        let url = t.url("/api/v1/plugins/pick-and-place/cycle");
        tokio::spawn(async move {
            let r = http
                .post(url)
                .json(&cycle_body(20_000))
                .send()
                .await
                .expect("plugin call");
            let status = r.status().as_u16();
            (status, r.json::<Value>().await.expect("JSON"))
        })
    };
    // The robot waits at the pick point with the gripper closed: one state
    // file shows both (it closed at the bottom, before the wait).
    let job = kuka_bridge_tests::wait_for(
        Duration::from_secs(30),
        "the cycle waiting for the part",
        async || {
            let (_, jobs) = t.get("/api/v1/jobs").await;
            let j = jobs
                .as_array()
                .and_then(|a| a.iter().find(|j| j["operation"] == "move").cloned())
                .ok_or("no job")?;
            let (_, s) = t.get("/api/v1/state").await;
            let z = s["position"]["z"].as_f64().unwrap_or(f64::NAN);
            let closed = s["io"]["outputs"][0].as_bool();
            if j["completed"] == 4
                && j["state"] == "executing"
                && (z - 100.0).abs() < 0.5
                && closed == Some(true)
            {
                Ok(j)
            } else {
                Err(format!("{j} z={z} closed={closed:?}"))
            }
        },
    )
    .await;
    assert_eq!(job["motions"], 11, "one job for the whole cycle: {job}");
    assert_eq!(
        job["origin"]
            .as_str()
            .map(|o| o.starts_with("plugin:pick-and-place")),
        Some(true),
        "{job}"
    );
    // The part arrives.
    let (s, v) = t
        .put_json("/api/v1/sim/inputs/3", &json!({"value": true}))
        .await;
    assert_eq!(s, 204, "{v}");
    let (status, v) = call.await.expect("task");
    assert_eq!(status, 200, "{v}");
    assert_eq!(
        (v["completed"].as_u64(), v["steps"].as_u64()),
        (Some(11), Some(11)),
        "{v}"
    );
    let (x, y, z) = (
        v["position"]["x"].as_f64().expect("x"),
        v["position"]["y"].as_f64().expect("y"),
        v["position"]["z"].as_f64().expect("z"),
    );
    assert!(
        (x - 300.0).abs() < 0.5 && (y - 60.0).abs() < 0.5 && (z - 150.0).abs() < 0.5,
        "above the place point: {v}"
    );
    // Closed at the pick, opened at the place; the state agrees.
    let events =
        kuka_bridge_tests::wait_for(Duration::from_secs(5), "both gripper events", async || {
            let e = gripper_events(&t).await;
            if e.len() >= 2 {
                Ok(e)
            } else {
                Err(format!("{e:?}"))
            }
        })
        .await;
    assert_eq!(events, [true, false]);
    let (_, io) = t.get("/api/v1/io/outputs/gripper_close").await;
    assert_eq!(io["value"], false, "{io}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pick_and_place_plugin_stops_cleanly_when_the_part_never_comes() {
    let t = pick_and_place_cell().await;
    let (status, v) = t
        .post_json("/api/v1/plugins/pick-and-place/cycle", &cycle_body(300))
        .await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(
        (v["code"].as_str(), v["step"].as_u64()),
        (Some("input_timeout"), Some(4)),
        "{v}"
    );
    // The robot stands at the pick point, the gripper closed; nothing
    // after the wait ran and the controller takes the next command.
    // (The state file may still show the job for a heartbeat.)
    let s = t
        .wait_state("the controller idle", |s| {
            s["controller"]["status"] == "idle"
        })
        .await;
    let p = &s["position"];
    assert!(
        (p["y"].as_f64().unwrap_or(0.0) + 60.0).abs() < 0.5
            && (p["z"].as_f64().unwrap_or(0.0) - 100.0).abs() < 0.5,
        "at the pick point: {s}"
    );
    assert_eq!(s["io"]["outputs"][0], true, "{s}");
    let (_, jobs) = t.get("/api/v1/jobs").await;
    let j = jobs
        .as_array()
        .and_then(|a| a.iter().find(|j| j["operation"] == "move").cloned())
        .expect("the cycle's job");
    assert_eq!(
        (
            j["state"].as_str(),
            j["error"]["code"].as_str(),
            j["completed"].as_u64()
        ),
        (Some("failed"), Some("input_timeout"), Some(4)),
        "{j}"
    );
    let (status, v) = t
        .motions(json!([{"type": "lin", "target": {"z": 150}}]))
        .await;
    assert_eq!(status, 200, "{v}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pick_and_place_plugin_runs_unattended_with_a_simulated_sensor() {
    let t = pick_and_place_cell_with(vec![sensor_follows_gripper()]).await;
    let (status, v) = t
        .post_json("/api/v1/plugins/pick-and-place/cycle", &cycle_body(5000))
        .await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["completed"], 11, "{v}");
    // The sensor followed the gripper: on, then off again.
    let seen =
        kuka_bridge_tests::wait_for(Duration::from_secs(5), "the sensor to follow", async || {
            let (_, ev) = t.get("/api/v1/events/recent?types=io&limit=1000").await;
            let e: Vec<bool> = ev
                .as_array()
                .expect("events")
                .iter()
                .filter(|e| e["data"]["name"] == "part_present")
                .filter_map(|e| e["data"]["value"].as_bool())
                .collect();
            if e.len() >= 2 {
                Ok(e)
            } else {
                Err(format!("{e:?}"))
            }
        })
        .await;
    assert_eq!(seen, [true, false]);
}

/// The `steps` interface: the cycle's straight motions as SLINs (spline
/// family), and the gripper opened 20 mm before the place point while the
/// robot descends (a `set-output` with `path-mm` after a spline motion).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pick_and_place_with_splines_releases_at_a_distance_before_the_place_point() {
    let t = pick_and_place_cell_with(vec![sensor_follows_gripper()]).await;
    let mut body = cycle_body(5000);
    body["spline"] = json!(true);
    body["release_before_mm"] = json!(20);
    let call = {
        let http = t.http.clone();
        let url = t.url("/api/v1/plugins/pick-and-place/cycle");
        tokio::spawn(async move {
            let r = http
                .post(url)
                .json(&body)
                .send()
                .await
                .expect("plugin call");
            let status = r.status().as_u16();
            (status, r.json::<Value>().await.expect("JSON"))
        })
    };
    // Where the gripper opened: the last state at the place (y = 60) with
    // it closed and the first with it open, polled back to back.
    let mut closed_z: Option<f64> = None;
    let open_z = kuka_bridge_tests::wait_for(
        Duration::from_secs(60),
        "the gripper to open at the place",
        async || {
            let (_, s) = t.get("/api/v1/state").await;
            let (y, z) = (
                s["position"]["y"].as_f64().unwrap_or(f64::NAN),
                s["position"]["z"].as_f64().unwrap_or(f64::NAN),
            );
            let at_place = (y - 60.0).abs() < 0.5;
            match s["io"]["outputs"][0].as_bool() {
                Some(true) if at_place => {
                    closed_z = Some(z);
                    Err(format!("closed at z={z}"))
                }
                Some(false) if at_place && closed_z.is_some() => Ok(z),
                other => Err(format!("y={y} z={z} gripper closed: {other:?}")),
            }
        },
    )
    .await;
    let closed_z = closed_z.expect("a state with the gripper closed at the place");
    // Descending from z 150 to 100 at 0.1 m/s: it opens at z 120, within
    // one 12 ms step (1.2 mm) either way (the KRC-like runtime's trigger
    // fires at the sample nearest its point, before or after; seen: the
    // first state with it open at z 121.15). The first state with it open
    // is written at once by the native simulator, within the 100 ms
    // heartbeat by the KRL program (10 mm): either way well before the
    // bottom, where it would open without `path-mm`.
    assert!(
        closed_z >= 118.0 && open_z <= 122.0 && open_z > 104.0,
        "opened between z {closed_z} and {open_z}, not at 120"
    );
    let (status, v) = call.await.expect("task");
    assert_eq!((status, v["completed"].as_u64()), (200, Some(11)), "{v}");
    // The plan as published: a PTP, then spline straight lines only.
    let (_, plans) = t.get("/api/v1/events/recent?types=plan&limit=1").await;
    let kinds: Vec<&str> = plans[0]["data"]["motions"]
        .as_array()
        .expect("planned motions")
        .iter()
        .filter_map(|m| m["type"].as_str())
        .filter(|k| !["set_output", "wait_input", "dwell"].contains(k))
        .collect();
    assert_eq!(
        kinds,
        ["ptp", "slin", "slin", "slin", "slin", "slin"],
        "{plans}"
    );
    // A distance too long for the descent is refused before anything runs.
    let mut too_far = cycle_body(5000);
    too_far["spline"] = json!(true);
    too_far["release_before_mm"] = json!(80);
    let (status, v) = t
        .post_json("/api/v1/plugins/pick-and-place/cycle", &too_far)
        .await;
    assert_eq!(
        (status, v["code"].as_str(), v["step"].as_u64()),
        (422, Some("invalid_input"), Some(8)),
        "{v}"
    );
}

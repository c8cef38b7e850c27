//! KRL variables through HTTP (issue 23, points 3 and 4) against the
//! simulated controller and its KUKAVARPROXY stand-in (`KB_TEST_SIMULATOR
//! =krc`: every variable of the shipped KRL program in the KRC-like
//! runtime): `$OV_PRO` follows an override change, `$POS_ACT` as a typed
//! E6POS, an allow-listed write, a refused one, a tool selected by number
//! changes the reported TCP, an absent proxy, and hostile names and values
//! refused before anything reaches the proxy.

use kuka_bridge_tests::{Options, TestService, WAIT, wait_for};
use serde_json::{Value, json};

async fn service() -> TestService {
    TestService::start(Options {
        tweak: Box::new(|c| {
            c.variables.writable = vec!["TOOL_DATA[3]".into(), "TOOL_NAME[3,]".into()];
        }),
        ..Options::default()
    })
    .await
}

/// `GET /api/v1/variables/{name}` with the name percent-encoded.
async fn read(t: &TestService, name: &str) -> (u16, Value) {
    t.get(&format!("/api/v1/variables/{}", encode(name))).await
}

fn encode(name: &str) -> String {
    name.bytes()
        .map(|b| {
            if b.is_ascii_alphanumeric() || b"$_.-".contains(&b) {
                char::from(b).to_string()
            } else {
                format!("%{b:02X}")
            }
        })
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_override_variable_follows_an_override_change() {
    let t = service().await;
    let (s, v) = read(&t, "$OV_PRO").await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(
        (v["type"].as_str(), v["value"].as_i64()),
        (Some("INT"), Some(100)),
        "{v}"
    );
    let (s, v) = t
        .put_json("/api/v1/speed", &json!({"override_pct": 35}))
        .await;
    assert_eq!(s, 200, "{v}");
    wait_for(WAIT, "$OV_PRO to read 35", async || {
        let (_, v) = read(&t, "$OV_PRO").await;
        if v["value"] == 35 {
            Ok(())
        } else {
            Err(v.to_string())
        }
    })
    .await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_actual_position_is_a_typed_structure() {
    let t = service().await;
    let (_, state) = t.get("/api/v1/state").await;
    let (s, v) = read(&t, "$POS_ACT").await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["type"], "E6POS", "{v}");
    for k in ["x", "y", "z"] {
        let a = v["value"][k.to_uppercase()].as_f64().expect("a component");
        let b = state["position"][k].as_f64().expect("the state's position");
        assert!((a - b).abs() < 0.01, "{k}: {a} vs {b}");
    }
    // A component alone.
    let (s, x) = read(&t, "$POS_ACT.X").await;
    assert_eq!((s, x["type"].as_str()), (200, Some("REAL")), "{x}");
    let (s, m) = read(&t, "$MODE_OP").await;
    assert_eq!(s, 200, "{m}");
    assert_eq!(m["type"], "ENUM", "{m}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_tool_written_and_selected_by_number_changes_the_tcp() {
    let t = service().await;
    let xyz = |s: &Value| ["x", "y", "z"].map(|k| s["position"][k].as_f64().unwrap_or(f64::NAN));
    let before = xyz(&t.get("/api/v1/state").await.1);
    let url = format!("/api/v1/variables/{}", encode("TOOL_DATA[3]"));
    let (s, v) = t
        .put_json(
            &url,
            &json!({"value": {"X": 0, "Y": 0, "Z": 120.5, "A": 0, "B": 0, "C": 0}}),
        )
        .await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["value"]["Z"], 120.5, "{v}");
    let (s, e) = t.get("/api/v1/tools/3").await;
    assert_eq!(s, 200, "{e}");
    assert_eq!(e["frame"]["z"], 120.5, "{e}");
    assert_eq!(e["name"], Value::Null, "unnamed at first: {e}");
    // Its name, as the teach pendant shows it (TOOL_NAME[3,], a row of a
    // CHAR array).
    let (s, v) = t
        .put_json(
            &format!("/api/v1/variables/{}", encode("TOOL_NAME[3,]")),
            &json!({"value": "gripper"}),
        )
        .await;
    assert_eq!((s, v["value"].as_str()), (200, Some("gripper")), "{v}");
    let (s, v) = t
        .put_json(
            &format!("/api/v1/variables/{}", encode("TOOL_NAME[3,]")),
            &json!({"value": "a name longer than twenty-four characters"}),
        )
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("invalid_input")),
        "too long for CHAR[24]: {v}"
    );
    let (s, e) = t.get("/api/v1/tools/3").await;
    assert_eq!((s, e["name"].as_str()), (200, Some("gripper")), "{e}");
    let (s, e) = t.get("/api/v1/tools/4").await;
    assert_eq!((s, &e["name"]), (200, &Value::Null), "{e}");
    // Selecting takes no options: a body that looks like one is refused,
    // not ignored (and nothing is selected).
    let (s, v) = t
        .post_json("/api/v1/tools/3/select", &json!({"number": 4}))
        .await;
    assert_eq!((s, v["code"].as_str()), (422, Some("invalid_input")), "{v}");
    let (_, tool) = t.get("/api/v1/tool").await;
    assert_eq!(tool["z"], 0.0, "nothing selected: {tool}");
    let (s, e) = t.post_json("/api/v1/tools/3/select", &json!({})).await;
    assert_eq!(s, 200, "{e}");
    let (_, tool) = t.get("/api/v1/tool").await;
    assert_eq!(tool["z"], 120.5, "{tool}");
    // The TCP moved 120.5 mm along the flange's axis: the reported
    // position is another point now (the robot did not move).
    let state = t
        .wait_state("the position for the new tool", |s| {
            let p = xyz(s);
            let d = (0..3)
                .map(|k| (p[k] - before[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            (d - 120.5).abs() < 0.05
        })
        .await;
    assert!(state["tool"]["z"] == 120.5, "{state}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn writes_outside_the_list_and_hostile_names_are_refused() {
    let t = service().await;
    let (s, v) = t
        .put_json(
            &format!("/api/v1/variables/{}", encode("$OV_PRO")),
            &json!({"value": 10}),
        )
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (403, Some("variable_not_allowed")),
        "{v}"
    );
    let (_, ov) = read(&t, "$OV_PRO").await;
    assert_eq!(ov["value"], 100, "unchanged: {ov}");
    let (s, v) = t
        .put_json(
            &format!("/api/v1/variables/{}", encode("TOOL_DATA[4]")),
            &json!({"value": {"X": 1}}),
        )
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (403, Some("variable_not_allowed")),
        "{v}"
    );
    // Names that are not names: 422 before anything reaches the proxy.
    for name in [
        "$OUT[1]=TRUE;",
        "$OV_PRO;$OUT[1]=TRUE",
        "$OV_PRO\nHALT",
        "A B",
        "$OUT[i]",
        "$OUT[-1]",
        "RUN /R1/X()",
        "\"X\"",
        "X..Y",
        &"A".repeat(101),
    ] {
        let (s, v) = read(&t, name).await;
        assert_eq!(
            (s, v["code"].as_str()),
            (422, Some("invalid_input")),
            "{name:?}: {v}"
        );
    }
    // Variables the controller does not have.
    let (s, v) = read(&t, "NO_SUCH_VARIABLE").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (404, Some("unknown_variable")),
        "{v}"
    );
    // Values that are not values, on a writable name.
    let url = format!("/api/v1/variables/{}", encode("TOOL_DATA[3]"));
    for bad in [
        json!({"value": "1}; $OUT[1]=TRUE; {"}),
        json!({"value": {"X 1}, Y": 2}}),
        json!({"value": {"enum": "T1;HALT"}}),
        json!({"value": [1, 2]}),
        json!({"value": null}),
        json!({"value": 1e300}),
        json!({"krl": "{X 1}"}),
    ] {
        let (s, v) = t.put_json(&url, &bad).await;
        assert_eq!(s, 422, "{bad}: {v}");
    }
    let (s, e) = t.get("/api/v1/tools/17").await;
    assert_eq!(s, 422, "{e}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_absent_proxy_answers_variables_unavailable_at_once() {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let t = TestService::start(Options {
        tweak: Box::new(move |c| {
            c.variables.proxy = format!("127.0.0.1:{port}");
            c.variables.timeout_ms = 500;
        }),
        ..Options::default()
    })
    .await;
    let started = std::time::Instant::now();
    let (s, v) = read(&t, "$OV_PRO").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (503, Some("variables_unavailable")),
        "{v}"
    );
    assert!(started.elapsed() < std::time::Duration::from_secs(3));
    assert!(
        !v["detail"].as_str().unwrap_or("").contains("os error"),
        "no internals in the sentence... {v}"
    );
}

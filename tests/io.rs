//! Digital I/O through HTTP against the simulated controller (issue 23;
//! `KB_TEST_SIMULATOR=krc`: the shipped KRL program in the KRC-like
//! runtime): outputs set and read back by name and number, the allow-list
//! (nothing reaches the channel for another output), pulses, simulated
//! inputs pushed as `io` events, and hostile signal names and bodies.

use kuka_bridge::io::{AnalogConfig, IoConfig, SignalConfig};
use kuka_bridge_tests::{Options, TestService, WAIT, initial_admin_secret, wait_for};
use serde_json::{Value, json};

fn signal(name: &str, index: u16, pulse_ms: u32, watch: bool) -> SignalConfig {
    SignalConfig {
        name: name.into(),
        index,
        pulse_ms,
        watch,
    }
}

/// A site with a gripper on `$OUT[1]`, a blow-off pulse on `$OUT[2]` and a
/// part-present sensor on `$IN[3]`; only those two outputs are writable.
async fn plant() -> TestService {
    TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| {
            c.io = IoConfig {
                inputs: vec![signal("part_present", 3, 0, true)],
                outputs: vec![
                    signal("gripper_close", 1, 0, true),
                    signal("blow_off", 2, 300, true),
                ],
                analog_inputs: vec![AnalogConfig {
                    name: "force".into(),
                    index: 2,
                    watch: true,
                    deadband: 0.05,
                }],
                analog_outputs: vec![AnalogConfig {
                    name: "spindle_speed".into(),
                    index: 1,
                    watch: false,
                    deadband: 0.01,
                }],
            };
        }),
        ..Options::default()
    })
    .await
}

async fn put(t: &TestService, path: &str, body: &Value) -> (u16, Value) {
    t.put_json(path, body).await
}

/// Waits until `GET path` answers a signal whose value is `want`.
async fn wait_value(t: &TestService, path: &str, want: bool) -> Value {
    wait_for(WAIT, &format!("{path} to read {want}"), async || {
        let (s, v) = t.get(path).await;
        if s == 200 && v["value"] == want {
            Ok(v)
        } else {
            Err(format!("{s} {v}"))
        }
    })
    .await
}

/// The controller's newest accepted command id.
async fn last_cid(t: &TestService) -> i64 {
    let (_, s) = t.get("/api/v1/state").await;
    s["controller"]["last_cid"].as_i64().unwrap_or(0)
}

/// `io` events held by the service, oldest first.
async fn io_events(t: &TestService) -> Vec<Value> {
    let (s, v) = t.get("/api/v1/events/recent?types=io&limit=1000").await;
    assert_eq!(s, 200, "{v}");
    v.as_array()
        .expect("events")
        .iter()
        .map(|e| e["data"].clone())
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn outputs_are_set_and_read_back_by_name_and_number() {
    let t = plant().await;
    let (s, v) = t.get("/api/v1/io").await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["base"], 1, "{v}");
    assert_eq!(v["outputs"].as_array().map(Vec::len), Some(31), "{v}");
    assert_eq!(v["outputs"][0]["name"], "gripper_close", "{v}");
    assert_eq!(v["outputs"][0]["writable"], true, "{v}");
    assert_eq!(v["outputs"][4]["writable"], false, "{v}");
    assert_eq!(v["inputs"][2]["name"], "part_present", "{v}");

    let (s, v) = put(
        &t,
        "/api/v1/io/outputs/gripper_close",
        &json!({"value": true}),
    )
    .await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(
        (v["index"].as_u64(), v["value"].as_bool()),
        (Some(1), Some(true)),
        "{v}"
    );
    wait_value(&t, "/api/v1/io/outputs/1", true).await;
    let v = wait_value(&t, "/api/v1/io/outputs/gripper_close", true).await;
    assert_eq!(v["name"], "gripper_close", "{v}");
    // By number, back to false.
    let (s, v) = put(&t, "/api/v1/io/outputs/1", &json!({"value": false})).await;
    assert_eq!(s, 200, "{v}");
    wait_value(&t, "/api/v1/io/outputs/gripper_close", false).await;
    // The watched output's changes were pushed, in order.
    let events = wait_for(WAIT, "two io events of the gripper", async || {
        let e: Vec<Value> = io_events(&t)
            .await
            .into_iter()
            .filter(|e| e["name"] == "gripper_close")
            .collect();
        if e.len() >= 2 {
            Ok(e)
        } else {
            Err(format!("{e:?}"))
        }
    })
    .await;
    let values: Vec<bool> = events.iter().filter_map(|e| e["value"].as_bool()).collect();
    assert_eq!(values, [true, false], "{events:?}");
    assert_eq!(events[0]["kind"], "output");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_pulse_returns_the_output_to_its_other_value() {
    let t = plant().await;
    // The configured pulse (300 ms).
    let (s, v) = put(&t, "/api/v1/io/outputs/blow_off", &json!({"value": true})).await;
    assert_eq!(s, 200, "{v}");
    let events = wait_for(WAIT, "the pulse to end", async || {
        let e: Vec<Value> = io_events(&t)
            .await
            .into_iter()
            .filter(|e| e["name"] == "blow_off")
            .collect();
        if e.len() >= 2 {
            Ok(e)
        } else {
            Err(format!("{e:?}"))
        }
    })
    .await;
    let values: Vec<bool> = events.iter().filter_map(|e| e["value"].as_bool()).collect();
    assert_eq!(values, [true, false], "{events:?}");
    let (_, v) = t.get("/api/v1/io/outputs/2").await;
    assert_eq!(v["value"], false, "{v}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_simulated_input_is_read_by_name_and_pushed() {
    let t = plant().await;
    let (s, v) = t.get("/api/v1/io/inputs/part_present").await;
    assert_eq!((s, v["value"].as_bool()), (200, Some(false)), "{v}");
    let (s, v) = put(&t, "/api/v1/sim/inputs/3", &json!({"value": true})).await;
    assert_eq!(s, 204, "{v}");
    wait_value(&t, "/api/v1/io/inputs/part_present", true).await;
    let e = wait_for(WAIT, "the io event of the input", async || {
        let e: Vec<Value> = io_events(&t)
            .await
            .into_iter()
            .filter(|e| e["name"] == "part_present")
            .collect();
        if e.is_empty() {
            Err("none".to_string())
        } else {
            Ok(e)
        }
    })
    .await;
    assert_eq!(
        (
            e[0]["kind"].as_str(),
            e[0]["index"].as_u64(),
            e[0]["value"].as_bool()
        ),
        (Some("input"), Some(3), Some(true)),
        "{e:?}"
    );
    // An input nobody watches changes without an event.
    let (s, _) = put(&t, "/api/v1/sim/inputs/4", &json!({"value": true})).await;
    assert_eq!(s, 204);
    wait_value(&t, "/api/v1/io/inputs/4", true).await;
    assert!(io_events(&t).await.iter().all(|e| e["index"] != 4));
}

/// Hostile signal names, numbers and bodies: each refused with a code and
/// a sentence, and none reaches the controller (its newest command id
/// stays where it was, no output changes).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hostile_io_requests_are_refused_before_the_channel() {
    let t = plant().await;
    let before = last_cid(&t).await;
    let long = "x".repeat(5000);
    let cases: Vec<(String, Value, u16, &str)> = vec![
        // Not on the allow-list.
        (
            "/api/v1/io/outputs/5".into(),
            json!({"value": true}),
            403,
            "output_not_allowed",
        ),
        (
            "/api/v1/io/outputs/4096".into(),
            json!({"value": true}),
            403,
            "output_not_allowed",
        ),
        (
            "/api/v1/io/outputs/3".into(),
            json!({"value": false}),
            403,
            "output_not_allowed",
        ),
        // An input's name is not an output.
        (
            "/api/v1/io/outputs/part_present".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        // Numbers out of range, and things that are not numbers or names.
        (
            "/api/v1/io/outputs/0".into(),
            json!({"value": true}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/4097".into(),
            json!({"value": true}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/99999".into(),
            json!({"value": true}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/-1".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/1.0".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/1e3".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/0x01".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/1%3B".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/%24OUT%5B1%5D%3DTRUE%3B".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/gripper_close%3B%24OUT%5B5%5D%3DTRUE".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/GRIPPER_CLOSE".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/gripper_close%20".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/outputs/gr%C3%BCn".into(),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        (
            format!("/api/v1/io/outputs/{long}"),
            json!({"value": true}),
            404,
            "unknown_signal",
        ),
        // Bodies of the wrong shape.
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": "yes"}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": 1}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": null}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!([true]),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!(true),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": true, "index": 5}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": true, "pulse_ms": -1}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": true, "pulse_ms": 60001}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": true, "pulse_ms": 1e10}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": true, "pulse_ms": "300"}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/outputs/1".into(),
            json!({"value": "$OUT[5]=TRUE;"}),
            422,
            "invalid_input",
        ),
        // Inputs cannot be written through the API (only the simulator's plant).
        (
            "/api/v1/io/inputs/3".into(),
            json!({"value": true}),
            405,
            "method_not_allowed",
        ),
        (
            "/api/v1/io/bogus/1".into(),
            json!({"value": true}),
            404,
            "not_found",
        ),
    ];
    assert!(cases.len() >= 30);
    for (path, body, status, code) in &cases {
        let (s, v) = put(&t, path, body).await;
        let shown: String = path.chars().take(60).collect();
        assert_eq!(
            (s, v["code"].as_str()),
            (*status, Some(*code)),
            "PUT {shown} {body} → {v}"
        );
        let detail = v["detail"].as_str().unwrap_or("");
        assert!(
            !detail.is_empty() && detail.len() < 400,
            "PUT {shown} → {v}"
        );
    }
    // Reads of what does not exist or is not reported.
    for (path, status, code) in [
        ("/api/v1/io/inputs/0", 422, "invalid_input"),
        ("/api/v1/io/inputs/100", 422, "signal_not_reported"),
        ("/api/v1/io/inputs/gripper_close", 404, "unknown_signal"),
        ("/api/v1/io/outputs/%24OUT%5B1%5D", 404, "unknown_signal"),
    ] {
        let (s, v) = t.get(path).await;
        assert_eq!(
            (s, v["code"].as_str()),
            (status, Some(code)),
            "GET {path} → {v}"
        );
    }
    // Nothing reached the controller: a write that is allowed still goes
    // through afterwards, with the next command id.
    assert_eq!(
        last_cid(&t).await,
        before,
        "a refused write reached the channel"
    );
    let (_, io) = t.get("/api/v1/io").await;
    assert!(
        io["outputs"]
            .as_array()
            .expect("outputs")
            .iter()
            .all(|o| o["value"] == false),
        "{io}"
    );
    let (s, v) = put(
        &t,
        "/api/v1/io/outputs/gripper_close",
        &json!({"value": true}),
    )
    .await;
    assert_eq!(s, 200, "{v}");
    wait_for(
        WAIT,
        "the allowed write's command id in the state",
        async || {
            let now = last_cid(&t).await;
            if now > before {
                Ok(())
            } else {
                Err(now.to_string())
            }
        },
    )
    .await;
}

/// What a teach pendant shows: drives, operator safety, emergency stop,
/// stop message and the robot program's state, in `GET /api/v1/state`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_state_reports_the_controllers_safety_and_program() {
    let t = plant().await;
    let s = t
        .wait_state("the controller's safety state", |s| {
            !s["controller"]["safety"].is_null()
        })
        .await;
    let saf = &s["controller"]["safety"];
    assert_eq!(
        (
            saf["drives_ready"].as_bool(),
            saf["user_safety"].as_bool(),
            saf["emergency_stop"].as_bool(),
            saf["stop_message"].as_bool(),
            saf["program"].as_str()
        ),
        (
            Some(true),
            Some(true),
            Some(false),
            Some(false),
            Some("active")
        ),
        "{s}"
    );
}

/// The analog channel `k` (0-based) of `GET /api/v1/io/analog`.
async fn analog(t: &TestService, output: bool, k: usize) -> Value {
    let (s, v) = t.get("/api/v1/io/analog").await;
    assert_eq!(s, 200, "{v}");
    v[if output { "outputs" } else { "inputs" }][k].clone()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn analog_values_round_trip_within_the_protocols_resolution() {
    let t = plant().await;
    let out = analog(&t, true, 0).await;
    assert_eq!(
        (
            out["name"].as_str(),
            out["writable"].as_bool(),
            out["value"].as_f64()
        ),
        (Some("spindle_speed"), Some(true), Some(0.0)),
        "{out}"
    );
    for (sent, want) in [(0.5, 0.5), (-0.12345, -0.123), (1.0, 1.0), (0.0004, 0.0)] {
        let (s, v) = put(
            &t,
            "/api/v1/io/analog-outputs/spindle_speed",
            &json!({"value": sent}),
        )
        .await;
        assert_eq!(s, 200, "{v}");
        wait_for(WAIT, &format!("$ANOUT[1] to read {want}"), async || {
            let o = analog(&t, true, 0).await;
            match o["value"].as_f64() {
                Some(v) if (v - want).abs() <= 0.0005 => Ok(()),
                _ => Err(o.to_string()),
            }
        })
        .await;
    }
    // A simulated sensor on $ANIN[2] ("force"), set by its name.
    let (s, v) = put(
        &t,
        "/api/v1/sim/analog-inputs/force",
        &json!({"value": -0.25}),
    )
    .await;
    assert_eq!(s, 204, "{v}");
    wait_for(WAIT, "$ANIN[2] to read -0.25", async || {
        let i = analog(&t, false, 1).await;
        if i["value"] == -0.25 && i["name"] == "force" {
            Ok(())
        } else {
            Err(i.to_string())
        }
    })
    .await;
    // A value out of range is shown as sent, in the words of the docs.
    let (s, v) = put(&t, "/api/v1/io/analog-outputs/1", &json!({"value": 1.0001})).await;
    assert_eq!(s, 422, "{v}");
    assert!(
        v["detail"]
            .as_str()
            .is_some_and(|d| d.contains("value = 1.0001 is not between -1 and 1")),
        "{v}"
    );
    // Refused before the channel: not on the list, out of range, not a
    // name, not a value.
    let before = last_cid(&t).await;
    for (path, body, status, code) in [
        (
            "/api/v1/io/analog-outputs/2",
            json!({"value": 0.5}),
            403,
            "output_not_allowed",
        ),
        (
            "/api/v1/io/analog-outputs/33",
            json!({"value": 0.5}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/analog-outputs/0",
            json!({"value": 0.5}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/analog-outputs/force",
            json!({"value": 0.5}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/analog-outputs/%24ANOUT%5B1%5D",
            json!({"value": 0.5}),
            404,
            "unknown_signal",
        ),
        (
            "/api/v1/io/analog-outputs/1",
            json!({"value": 1.5}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/analog-outputs/1",
            json!({"value": -1.001}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/analog-outputs/1",
            json!({"value": "0.5"}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/analog-outputs/1",
            json!({"value": 1e308}),
            422,
            "invalid_input",
        ),
        (
            "/api/v1/io/analog-outputs/1",
            json!({"value": 0.5, "volts": 5}),
            422,
            "invalid_input",
        ),
    ] {
        let (s, v) = put(&t, path, &body).await;
        assert_eq!(
            (s, v["code"].as_str()),
            (status, Some(code)),
            "{path} {body}: {v}"
        );
    }
    assert_eq!(last_cid(&t).await, before, "nothing reached the channel");
}

/// `analog` events held by the service, oldest first.
async fn analog_events(t: &TestService) -> Vec<Value> {
    let (s, v) = t.get("/api/v1/events/recent?types=analog&limit=1000").await;
    assert_eq!(s, 200, "{v}");
    v.as_array()
        .expect("events")
        .iter()
        .map(|e| e["data"].clone())
        .collect()
}

/// Sets the simulated `$ANIN[2]` and waits until the service reports it.
async fn set_force(t: &TestService, value: f64) {
    let (s, v) = put(t, "/api/v1/sim/analog-inputs/2", &json!({"value": value})).await;
    assert_eq!(s, 204, "{v}");
    wait_for(WAIT, &format!("$ANIN[2] to read {value}"), async || {
        let i = analog(t, false, 1).await;
        if i["value"].as_f64() == Some(value) {
            Ok(())
        } else {
            Err(i.to_string())
        }
    })
    .await;
}

/// A watched analog channel (`force`, deadband 0.05) publishes an
/// `analog` event when it moves by its deadband from the value it last
/// published, and only then; an unwatched one (`spindle_speed`) never.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn watched_analog_channels_publish_events_beyond_their_deadband() {
    let t = plant().await;
    set_force(&t, 0.0).await;
    let values = |events: &[Value]| -> Vec<f64> {
        events.iter().filter_map(|e| e["value"].as_f64()).collect()
    };
    set_force(&t, 0.2).await;
    let events = analog_events(&t).await;
    assert_eq!(values(&events), [0.2], "{events:?}");
    assert_eq!(
        events[0],
        json!({"kind": "input", "index": 2, "name": "force", "value": 0.2})
    );
    // 0.03 from the last published value: below the deadband.
    set_force(&t, 0.23).await;
    assert_eq!(values(&analog_events(&t).await), [0.2]);
    // 0.06 from it: published (the deadband counts from 0.2, not 0.23).
    set_force(&t, 0.26).await;
    set_force(&t, -0.5).await;
    assert_eq!(values(&analog_events(&t).await), [0.2, 0.26, -0.5]);
    // An output that is not watched.
    let (s, v) = put(
        &t,
        "/api/v1/io/analog-outputs/spindle_speed",
        &json!({"value": 0.75}),
    )
    .await;
    assert_eq!(s, 200, "{v}");
    wait_for(WAIT, "$ANOUT[1] to read 0.75", async || {
        let o = analog(&t, true, 0).await;
        if o["value"].as_f64() == Some(0.75) {
            Ok(())
        } else {
            Err(o.to_string())
        }
    })
    .await;
    let events = analog_events(&t).await;
    assert!(events.iter().all(|e| e["name"] == "force"), "{events:?}");
    assert_eq!(events.len(), 3, "{events:?}");
    // Single channels, by name or number.
    let (s, v) = t.get("/api/v1/io/analog-inputs/force").await;
    assert_eq!(
        (s, v["index"].as_u64(), v["value"].as_f64()),
        (200, Some(2), Some(-0.5)),
        "{v}"
    );
    let (s, v) = t.get("/api/v1/io/analog-outputs/1").await;
    assert_eq!(
        (
            s,
            v["name"].as_str(),
            v["value"].as_f64(),
            v["writable"].as_bool()
        ),
        (200, Some("spindle_speed"), Some(0.75), Some(true)),
        "{v}"
    );
    let (s, v) = t.get("/api/v1/io/analog-inputs/12").await;
    assert_eq!(v["code"], "signal_not_reported", "{s} {v}");
    for bad in ["0", "33", "gripper_close", "%24ANIN%5B1%5D"] {
        let (s, v) = t.get(&format!("/api/v1/io/analog-inputs/{bad}")).await;
        assert!(s == 404 || s == 422, "{bad}: {s} {v}");
    }
}

/// A request with a bearer token.
async fn call_as(
    t: &TestService,
    method: reqwest::Method,
    path: &str,
    token: &str,
    body: Option<&Value>,
) -> (u16, Value) {
    let mut req = t.http.request(method, t.url(path)).bearer_auth(token);
    if let Some(b) = body {
        req = req.json(b);
    }
    kuka_bridge_tests::decode(req.send().await.expect("request")).await
}

/// An admin edits the allow-list over HTTP (`PUT /api/v1/io/config`): an
/// operator may read it but not change it; the new list applies to the
/// next request at once (a removed output is refused before the channel),
/// invalid lists are refused whole, the change is audited, survives a
/// restart (`<data_dir>/io.json`), and `DELETE` goes back to the
/// configuration file's `[io]`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_admin_edits_the_allow_list_and_it_applies_at_once_and_after_a_restart() {
    use reqwest::Method;
    let t = TestService::start(Options {
        time_scale: 1.0,
        tweak: Box::new(|c| {
            c.auth.require_on_loopback = true;
            c.io = IoConfig {
                inputs: vec![signal("part_present", 3, 0, true)],
                outputs: vec![
                    signal("gripper_close", 1, 0, true),
                    signal("blow_off", 2, 300, true),
                ],
                ..IoConfig::default()
            };
        }),
        ..Options::default()
    })
    .await;
    let admin = initial_admin_secret(&t.config.data_dir);
    let operator = t.create_token(&admin, "cell-operator", "operator").await;
    let (s, cfg) = call_as(&t, Method::GET, "/api/v1/io/config", &operator, None).await;
    assert_eq!(s, 200, "{cfg}");
    assert_eq!(cfg["outputs"][1]["name"], "blow_off", "{cfg}");
    let mut edited = cfg.clone();
    edited["outputs"] = json!([
        {"name": "gripper_close", "index": 1, "watch": true},
        {"name": "lamp", "index": 5}
    ]);
    let (s, v) = call_as(
        &t,
        Method::PUT,
        "/api/v1/io/config",
        &operator,
        Some(&edited),
    )
    .await;
    assert_eq!((s, v["code"].as_str()), (403, Some("forbidden")), "{v}");
    // Refused whole, nothing changed: duplicates, out of range, unknown
    // fields, not a list.
    for bad in [
        json!({"outputs": [{"name": "a", "index": 1}, {"name": "a", "index": 2}]}),
        json!({"outputs": [{"name": "a", "index": 0}]}),
        json!({"outputs": [{"name": "a", "index": 4097}]}),
        json!({"outputs": [{"name": "A-1", "index": 1}]}),
        json!({"outputs": [{"name": "a", "index": 1, "pulse_ms": 60001}]}),
        json!({"analog_inputs": [{"name": "f", "index": 12, "watch": true}]}),
        json!({"outputs": [{"name": "a", "index": 1, "colour": "red"}]}),
        json!({"outputs": "all"}),
        json!({"secret_outputs": []}),
    ] {
        let (s, v) = call_as(&t, Method::PUT, "/api/v1/io/config", &admin, Some(&bad)).await;
        assert_eq!(
            (s, v["code"].as_str()),
            (422, Some("invalid_input")),
            "{bad}: {v}"
        );
    }
    // A list with several mistakes names each of them at once.
    let bad = json!({
        "inputs": [{"name": "Part", "index": 3}],
        "outputs": [{"name": "lamp", "index": 5000}, {"name": "horn", "index": 2, "pulse_ms": 70000}],
        "analog_outputs": [{"name": "lamp", "index": 1}]
    });
    let (s, v) = call_as(&t, Method::PUT, "/api/v1/io/config", &admin, Some(&bad)).await;
    assert_eq!(s, 422, "{v}");
    let detail = v["detail"].as_str().unwrap_or_default();
    for problem in [
        "io.inputs: name \"Part\"",
        "io.outputs: \"lamp\" has index 5000",
        "io.outputs: \"horn\" has pulse_ms 70000",
        "io.analog_outputs: the name \"lamp\" is used twice",
    ] {
        assert!(detail.contains(problem), "{problem} missing in {v}");
    }
    let (_, now) = call_as(&t, Method::GET, "/api/v1/io/config", &operator, None).await;
    assert_eq!(now, cfg, "unchanged after refused edits");
    let (s, v) = call_as(&t, Method::PUT, "/api/v1/io/config", &admin, Some(&edited)).await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["outputs"][1]["name"], "lamp", "{v}");
    // In force for the next request: blow_off is gone (by name and by
    // number), the lamp is writable; nothing refused reached the channel.
    let before = last_cid(&t).await;
    let on = json!({"value": true});
    let (s, v) = call_as(
        &t,
        Method::PUT,
        "/api/v1/io/outputs/blow_off",
        &operator,
        Some(&on),
    )
    .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (404, Some("unknown_signal")),
        "{v}"
    );
    let (s, v) = call_as(
        &t,
        Method::PUT,
        "/api/v1/io/outputs/2",
        &operator,
        Some(&on),
    )
    .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (403, Some("output_not_allowed")),
        "{v}"
    );
    assert_eq!(
        last_cid(&t).await,
        before,
        "a refused write reached the controller"
    );
    let (s, v) = call_as(
        &t,
        Method::PUT,
        "/api/v1/io/outputs/lamp",
        &operator,
        Some(&on),
    )
    .await;
    assert_eq!(s, 200, "{v}");
    // Audited.
    let (s, audit) = call_as(
        &t,
        Method::GET,
        "/api/v1/audit?path=/api/v1/io/config&method=PUT",
        &admin,
        None,
    )
    .await;
    assert_eq!(s, 200, "{audit}");
    let records = audit.as_array().map_or(0, Vec::len);
    assert!(records >= 3, "the edits in the audit trail: {audit}");
    // Kept over a restart.
    let TestService {
        service,
        dirs,
        config,
        ..
    } = t;
    service.shutdown().await.expect("shutdown");
    let t = TestService::start_with(config, dirs).await;
    let (s, v) = call_as(&t, Method::GET, "/api/v1/io/config", &admin, None).await;
    assert_eq!((s, &v["outputs"][1]["name"]), (200, &json!("lamp")), "{v}");
    // Back to the configuration file's.
    let (s, v) = call_as(&t, Method::DELETE, "/api/v1/io/config", &operator, None).await;
    assert_eq!(s, 403, "{v}");
    let (s, v) = call_as(&t, Method::DELETE, "/api/v1/io/config", &admin, None).await;
    assert_eq!(
        (s, &v["outputs"][1]["name"]),
        (200, &json!("blow_off")),
        "{v}"
    );
    assert!(!t.config.data_dir.join("io.json").exists());
    t.service.shutdown().await.expect("shutdown");
}

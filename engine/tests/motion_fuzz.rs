//! Property tests (fuzzing) of what a client's motion body goes through
//! before anything reaches the controller: JSON → `MotionRequest`s, the
//! request check, resolution against the robot's pose, and the kinematic
//! check of the resolved motions. Whatever the body, each step answers
//! `Ok` or a `BridgeError`; none panics, hangs or overflows.
//! `PROPTEST_CASES=20000 cargo test -p kuka-engine --test motion_fuzz` runs longer.

use kuka_engine::motion::{MotionRequest, SpeedSettings, StartPoint, resolve};
use kuka_engine::safety::Safety;
use kuka_engine::settings::MotionConfig;
use kuka_kinematics::RobotModel;
use kuka_protocol::Frame;
use proptest::prelude::*;
use serde_json::{Value, json};

/// Keys and words the motion bodies use, so generated JSON reaches past
/// the first `unknown field` refusal.
const WORDS: &[&str] = &[
    "type",
    "ptp",
    "lin",
    "circ",
    "ptp_axes",
    "spl",
    "slin",
    "scirc",
    "sptp",
    "target",
    "aux",
    "axes",
    "x",
    "y",
    "z",
    "a",
    "b",
    "c",
    "s",
    "t",
    "a1",
    "a2",
    "a3",
    "a4",
    "a5",
    "a6",
    "velocity_pct",
    "velocity_m_s",
    "acceleration_pct",
    "approx_mm",
    "relative",
    "frame",
    "tool",
    "base",
];

fn number() -> impl Strategy<Value = Value> {
    prop_oneof![
        (-1000.0f64..1000.0).prop_map(|v| json!(v)),
        (-10i64..100).prop_map(|v| json!(v)),
        prop::sample::select(vec![
            json!(0),
            json!(-0.0),
            json!(1e308),
            json!(-1e308),
            json!(5e-324),
            json!(u64::MAX),
            json!(i64::MIN),
            json!(9999.9995),
        ]),
    ]
}

fn leaf() -> impl Strategy<Value = Value> {
    prop_oneof![
        4 => number(),
        1 => prop::sample::select(WORDS).prop_map(|w| json!(w)),
        1 => any::<bool>().prop_map(|b| json!(b)),
        1 => Just(Value::Null),
        1 => ".{0,12}".prop_map(|s| json!(s)),
    ]
}

fn json_value() -> impl Strategy<Value = Value> {
    leaf().prop_recursive(5, 64, 8, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
            prop::collection::btree_map(
                prop_oneof![4 => prop::sample::select(WORDS).prop_map(str::to_string), 1 => ".{0,6}"],
                inner,
                0..6
            )
            .prop_map(|m| Value::Object(m.into_iter().collect())),
        ]
    })
}

fn pose() -> impl Strategy<Value = std::collections::BTreeMap<String, Value>> {
    prop::collection::btree_map(
        prop::sample::select(&["x", "y", "z", "a", "b", "c"][..]).prop_map(str::to_string),
        number(),
        0..6,
    )
}

/// A motion of a real kind with arbitrary numbers (often out of range).
fn motion() -> impl Strategy<Value = Value> {
    let axes = prop::collection::btree_map(
        prop::sample::select(&["a1", "a2", "a3", "a4", "a5", "a6"][..]).prop_map(str::to_string),
        number(),
        0..6,
    );
    prop_oneof![
        (pose(), number(), number())
            .prop_map(|(t, v, s)| json!({"type": "ptp", "target": t, "velocity_pct": v, "s": s})),
        (pose(), number(), number()).prop_map(
            |(t, v, a)| json!({"type": "lin", "target": t, "velocity_m_s": v, "approx_mm": a})
        ),
        (pose(), pose()).prop_map(|(a, t)| json!({"type": "circ", "aux": a, "target": t})),
        (axes, number())
            .prop_map(|(a, v)| json!({"type": "ptp_axes", "axes": a, "velocity_pct": v})),
    ]
}

fn check(body: Value) {
    let Ok(requests) = serde_json::from_value::<Vec<MotionRequest>>(body) else {
        return;
    };
    let config = MotionConfig::default();
    let speeds = SpeedSettings::from_config(&config);
    let safety = Safety::new(
        config,
        None,
        Default::default(),
        Some(RobotModel::kr3_r540()),
    );
    if safety.check_request(&requests).is_err() {
        return;
    }
    let home = Frame::from_array([355.0, 0.0, 625.0, 0.0, 90.0, 0.0]);
    let start = StartPoint {
        pose: home,
        axes: [0.0, -90.0, 90.0, 0.0, 0.0, 0.0],
    };
    let Ok(records) = resolve(&requests, &start, &speeds, 0.0) else {
        return;
    };
    let _ = safety.check_resolved(&records, &start, &Frame::default(), &Frame::default());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2048, ..ProptestConfig::default() })]

    #[test]
    fn any_json_body_is_answered(body in json_value()) {
        check(json!([body.clone()]));
        check(body);
    }

    #[test]
    fn motions_with_any_numbers_are_answered(batch in prop::collection::vec(motion(), 1..8)) {
        check(Value::Array(batch));
    }
}

/// Nested 10 000 levels deep: serde_json's recursion limit refuses it
/// before anything recurses further.
#[test]
fn deeply_nested_json_is_refused() {
    let text = format!("{}{}", "[".repeat(10_000), "]".repeat(10_000));
    assert!(serde_json::from_str::<Vec<MotionRequest>>(&text).is_err());
}

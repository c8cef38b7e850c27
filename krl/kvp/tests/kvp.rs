//! The KUKAVARPROXY protocol through real TCP: the client against the
//! server over a map of variables, byte layouts as the public OpenShowVar
//! clients send them, KRL value text, and the name check against KRL
//! injected into names.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use kuka_kvp::codec::{Answer, Function, Request};
use kuka_kvp::{KrlValue, KvpClient, KvpError, KvpServer, VarStore, check_name};
use proptest::prelude::*;
use serde_json::json;

struct Map(Mutex<HashMap<String, String>>);

impl VarStore for Map {
    fn read(&self, name: &str) -> Option<String> {
        self.0.lock().ok()?.get(name).cloned()
    }
    fn write(&self, name: &str, value: &str) -> Option<String> {
        let mut m = self.0.lock().ok()?;
        let slot = m.get_mut(name)?;
        *slot = value.to_string();
        Some(value.to_string())
    }
}

fn server() -> KvpServer {
    let vars = HashMap::from([
        ("$OV_PRO".to_string(), "100".to_string()),
        (
            "$POS_ACT".to_string(),
            "{E6POS: X 355.0, Y 0.0, Z 625.0, A 0.0, B 90.0, C 0.0, S 2, T 10}".to_string(),
        ),
    ]);
    KvpServer::start("127.0.0.1:0", Arc::new(Map(Mutex::new(vars)))).expect("server")
}

#[test]
fn a_read_request_is_the_bytes_openshowvar_sends() {
    // py_openshowvar: struct.pack('!HHBH7s', id, 7 + 3, 0, 7, b'$OV_PRO')
    let r = Request {
        id: 5,
        function: Function::Read,
        name: "$OV_PRO".into(),
        value: None,
    };
    let mut want = vec![0, 5, 0, 10, 0, 0, 7];
    want.extend_from_slice(b"$OV_PRO");
    assert_eq!(r.encode().expect("encodes"), want);
    // A write adds the value's length and the value.
    let w = Request {
        function: Function::Write,
        value: Some("50".into()),
        ..r
    };
    let mut want = vec![0, 5, 0, 14, 1, 0, 7];
    want.extend_from_slice(b"$OV_PRO");
    want.extend_from_slice(&[0, 2]);
    want.extend_from_slice(b"50");
    assert_eq!(w.encode().expect("encodes"), want);
}

proptest! {
    #[test]
    fn messages_round_trip(id in 1u16.., name in "[A-Z$_][A-Z0-9_]{0,20}", value in proptest::option::of("[ -~]{0,200}"), ok: bool) {
        let function = if value.is_some() { Function::Write } else { Function::Read };
        let r = Request { id, function, name: name.clone(), value: value.clone() };
        let bytes = r.encode().expect("encodes");
        prop_assert_eq!(Request::decode(id, &bytes[4..]).expect("decodes"), r);
        let a = Answer { id, function, value: value.unwrap_or_default(), ok };
        let bytes = a.encode().expect("encodes");
        prop_assert_eq!(Answer::decode(id, &bytes[4..]).expect("decodes"), a);
    }

    #[test]
    fn decoding_any_bytes_never_panics(id: u16, body in proptest::collection::vec(any::<u8>(), 0..300)) {
        let _ = Request::decode(id, &body);
        let _ = Answer::decode(id, &body);
    }

    #[test]
    fn parsing_any_text_never_panics(text in "\\PC{0,200}") {
        let _ = KrlValue::parse(&text);
    }
}

#[tokio::test]
async fn the_client_reads_and_writes_through_the_server() {
    let s = server();
    let c = KvpClient::new(s.addr().to_string(), Duration::from_secs(2));
    assert_eq!(c.read("$OV_PRO").await.expect("read"), "100");
    assert_eq!(c.write("$OV_PRO", "42").await.expect("write"), "42");
    assert_eq!(c.read("$OV_PRO").await.expect("read"), "42");
    let pos = KrlValue::parse(&c.read("$POS_ACT").await.expect("read")).expect("parses");
    assert_eq!(pos.type_name(), "E6POS");
    assert_eq!(pos.to_json()["X"], json!(355.0));
    assert_eq!(pos.to_json()["S"], json!(2));
    assert!(matches!(c.read("NOPE").await, Err(KvpError::Refused(_))));
    // After a refusal the connection still serves.
    assert_eq!(c.read("$OV_PRO").await.expect("read"), "42");
}

#[tokio::test]
async fn an_absent_proxy_is_unreachable_not_a_hang() {
    // A port nothing listens on.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let c = KvpClient::new(format!("127.0.0.1:{port}"), Duration::from_millis(500));
    let started = std::time::Instant::now();
    assert!(matches!(
        c.read("$OV_PRO").await,
        Err(KvpError::Unreachable { .. })
    ));
    assert!(started.elapsed() < Duration::from_secs(2));
}

#[test]
fn krl_values_parse_into_types() {
    let cases = [
        ("100", "INT", json!(100)),
        ("-3", "INT", json!(-3)),
        ("1.5", "REAL", json!(1.5)),
        ("1.0E-03", "REAL", json!(0.001)),
        ("TRUE", "BOOL", json!(true)),
        ("FALSE", "BOOL", json!(false)),
        ("\"gripper 1\"", "CHAR", json!("gripper 1")),
        ("#T1", "ENUM", json!({"enum": "T1"})),
        ("{X 1.0, Y -2.5}", "STRUC", json!({"X": 1.0, "Y": -2.5})),
        (
            "{FRAME: X 10.0, Y 0.0, Z 100.0, A 0.0, B 0.0, C 0.0}",
            "FRAME",
            json!({"X": 10.0, "Y": 0.0, "Z": 100.0, "A": 0.0, "B": 0.0, "C": 0.0}),
        ),
        (
            "{LOAD: M 1.5, CM {X 0.0, Y 0.0, Z 50.0, A 0.0, B 0.0, C 0.0}}",
            "LOAD",
            json!({"M": 1.5, "CM": {"X": 0.0, "Y": 0.0, "Z": 50.0, "A": 0.0, "B": 0.0, "C": 0.0}}),
        ),
    ];
    for (text, ty, want) in cases {
        let v = KrlValue::parse(text).unwrap_or_else(|| panic!("{text} parses"));
        assert_eq!(
            (v.type_name().as_str(), v.to_json()),
            (ty, want.clone()),
            "{text}"
        );
        // Back to KRL text and again: the same value.
        assert_eq!(
            KrlValue::parse(&v.to_krl()).map(|w| w.to_json()),
            Some(want),
            "{text}"
        );
    }
    for bad in [
        "", "{X 1.0", "\"open", "1 2", "X 1", "{1 X}", "#", "nan", "inf",
    ] {
        assert_eq!(KrlValue::parse(bad), None, "{bad:?}");
    }
}

#[test]
fn json_values_become_krl_text_or_are_refused() {
    let ok = [
        (json!(50), "50"),
        (json!(12.5), "12.5"),
        (json!(true), "TRUE"),
        (json!("part A"), "\"part A\""),
        (json!({"enum": "T1"}), "#T1"),
        (json!({"x": 1.0, "y": 2}), "{X 1.0, Y 2}"),
    ];
    for (v, krl) in ok {
        assert_eq!(
            KrlValue::from_json(&v).expect("accepted").to_krl(),
            krl,
            "{v}"
        );
    }
    let refused = [
        json!(null),
        json!([1, 2]),
        json!("say \"hi\""),
        json!("line\nbreak"),
        json!("x".repeat(129)),
        json!(1e300),
        json!(3_000_000_000i64),
        json!({"enum": "T1; $OUT[1]=TRUE"}),
        json!({"X 1.0}, Y": 2}),
        json!({}),
        json!({"a": {"b": {"c": {"d": {"e": {"f": 1}}}}}}),
    ];
    for v in refused {
        assert!(KrlValue::from_json(&v).is_err(), "{v} was accepted");
    }
}

#[test]
fn names_are_names_and_nothing_else() {
    for ok in [
        "$OV_PRO",
        "$POS_ACT",
        "$POS_ACT.X",
        "$OUT[1]",
        "TOOL_DATA[3]",
        "BASE_DATA[32].X",
        "kb_last_cid",
        "$TIMER[16]",
        "M[1,2,3]",
        "S.A.B",
        "TOOL_NAME[3,]",
        "M[1,2,]",
    ] {
        assert_eq!(check_name(ok), Ok(()), "{ok}");
    }
    for bad in [
        "",
        "$OUT[1]=TRUE",
        "$OUT[1]=TRUE;",
        "$OV_PRO;$OUT[1]=TRUE",
        "$OV_PRO\nHALT",
        "$OUT[ 1]",
        "$OUT[i]",
        "$OUT[1",
        "$OUT[-1]",
        "$OUT[1][2]x",
        "1ABC",
        "A B",
        "$$X",
        "\"X\"",
        "X.",
        "X..Y",
        "X[1,2,3,4]",
        "X[123456]",
        "ABCDEFGHIJKLMNOPQRSTUVWXYZ",
        "$OV_PRO)",
        "RUN /R1/X()",
        "X{1}",
        "X[]",
        "X[,]",
        "X[,1]",
        "X[1,,]",
        "X[1,,2]",
        "X[1,]=\"A\"",
    ] {
        assert!(check_name(bad).is_err(), "{bad:?} was accepted");
    }
    assert!(check_name(&"A".repeat(101)).is_err());
}

//! The thesis-compatible `/krl/*` endpoints, over HTTP against the running
//! service with the simulated controller over real files.

use kuka_bridge_tests::{Options, TestService, assert_close, thesis_position};

#[tokio::test]
async fn thesis_motions_move_the_simulated_robot() {
    let t = TestService::start(Options::default()).await;

    // getpos answers the home position (KR 3 R540: flange at X 355, Z 625, B 90).
    let (status, v) = t.post("/krl/getpos").await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["statuscode"], 1);
    let p = thesis_position(&v);
    assert_close(p[0], 355.0, 0.01, "home x");
    assert_close(p[2], 625.0, 0.01, "home z");

    // The thesis's pen position.
    let (status, v) = t.post("/krl/ptp?x=200&y=0&z=70&a=0&b=180&c=0").await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["statuscode"], 1);
    let p = thesis_position(&v);
    assert_close(p[0], 200.0, 0.01, "x");
    assert_close(p[1], 0.0, 0.01, "y");
    assert_close(p[2], 70.0, 0.01, "z");

    // Omitted coordinates keep their value: only X and Y change.
    let (status, v) = t.post("/krl/linmov?x=250&y=100").await;
    assert_eq!(status, 200, "{v}");
    let q = thesis_position(&v);
    assert_close(q[0], 250.0, 0.01, "x");
    assert_close(q[1], 100.0, 0.01, "y");
    assert_close(q[2], 70.0, 0.01, "z kept");
    for i in 3..6 {
        assert_close(q[i], p[i], 0.01, "orientation kept");
    }

    // The simulator really drew a straight line between the two points.
    let trace = t.trace();
    let last_lin: Vec<_> = trace
        .iter()
        .filter(|s| s.cid == trace.last().expect("samples").cid)
        .collect();
    assert!(last_lin.len() > 3, "LIN sampled");
    for s in &last_lin {
        // On the segment (200,0)→(250,100): y = 2 (x − 200).
        assert_close(s.pose[1], 2.0 * (s.pose[0] - 200.0), 0.5, "on the line");
        assert_close(s.pose[2], 70.0, 0.5, "z constant");
    }

    // The thesis's CIRC example: from (200, 50) through (250, 0) to (200, −50).
    let (status, _) = t.post("/krl/linmov?x=200&y=50&z=80").await;
    assert_eq!(status, 200);
    let (status, v) = t.post("/krl/circ?ax=250&ay=0&az=80&x=200&y=-50&z=80").await;
    assert_eq!(status, 200, "{v}");
    let p = thesis_position(&v);
    assert_close(p[1], -50.0, 0.01, "circ end y");
    let trace = t.trace();
    let circ_cid = trace.last().expect("samples").cid;
    let arc: Vec<_> = trace.iter().filter(|s| s.cid == circ_cid).collect();
    let max_x = arc.iter().map(|s| s.pose[0]).fold(f64::MIN, f64::max);
    assert_close(max_x, 250.0, 1.5, "arc passes through the auxiliary point");
    for s in &arc {
        let r = ((s.pose[0] - 200.0).powi(2) + s.pose[1].powi(2)).sqrt();
        assert_close(r, 50.0, 0.5, "on the circle");
    }

    // Home ("base").
    let (status, v) = t.post("/krl/base").await;
    assert_eq!(status, 200, "{v}");
    assert_close(thesis_position(&v)[0], 355.0, 0.01, "home again");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn thesis_tool_frame_round_trip() {
    let t = TestService::start(Options::default()).await;
    let (status, v) = t.post("/krl/tcp?z=100").await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(thesis_position(&v), [0.0, 0.0, 100.0, 0.0, 0.0, 0.0]);
    // Omitted values keep the current tool's.
    let (status, v) = t.post("/krl/tcp?x=5").await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(thesis_position(&v), [5.0, 0.0, 100.0, 0.0, 0.0, 0.0]);
    let (status, v) = t.post("/krl/gettcp").await;
    assert_eq!(status, 200);
    assert_eq!(thesis_position(&v), [5.0, 0.0, 100.0, 0.0, 0.0, 0.0]);
    // The position now refers to the tool tip: 100 mm further along the
    // flange's Z axis, which points along base X at home (B = 90°).
    let (_, v) = t.post("/krl/getpos").await;
    let p = thesis_position(&v);
    assert_close(p[0], 455.0, 0.01, "tcp x at home with a 100 mm tool");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn thesis_failures_keep_statuscode_and_position() {
    let t = TestService::start(Options::default()).await;
    // Far out of reach.
    let (status, v) = t.post("/krl/ptp?x=2000").await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "unreachable");
    assert_ne!(v["statuscode"], 1);
    assert_eq!(v["statuscode"], 20);
    let p = thesis_position(&v);
    assert_close(p[0], 355.0, 0.01, "position still reported");
    // Not a number.
    let (status, v) = t.post("/krl/ptp?x=abc").await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "invalid_input");
    assert_eq!(v["statuscode"], 10);
    // Unknown parameters are refused, never ignored; KUKA's upper-case names work.
    let (status, v) = t.post("/krl/ptp?x=300&foo=1").await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );
    let (status, v) = t.post("/krl/ptp?X=300&Y=0&Z=300&A=0&B=90&C=0").await;
    assert_eq!(status, 200, "{v}");
    assert_close(thesis_position(&v)[0], 300.0, 0.01, "upper-case X");
    for path in ["/krl/getpos?foo=1", "/krl/base?x=1", "/krl/gettcp?bogus=1"] {
        let (status, v) = t.post(path).await;
        assert_eq!(
            (status, v["code"].as_str()),
            (422, Some("invalid_input")),
            "{path}: {v}"
        );
    }
    // Routing errors keep the thesis format.
    let (status, v) = t.post("/krl/nothing").await;
    assert_eq!((status, v["statuscode"].as_i64()), (404, Some(54)), "{v}");
    let (status, v) = t.get("/krl/ptp").await;
    assert_eq!(
        (status, v["statuscode"].as_i64(), v["code"].as_str()),
        (405, Some(55), Some("method_not_allowed")),
        "{v}"
    );
    assert!(v["position"].is_array(), "{v}");
    // A CIRC back to its own start is refused before anything is sent.
    let (status, _) = t.post("/krl/linmov?x=300&y=20&z=300").await;
    assert_eq!(status, 200);
    let (status, v) = t.post("/krl/circ?ax=330&ay=20&x=300&y=20").await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );
    assert!(
        v["detail"].as_str().unwrap_or("").contains("coincides"),
        "{v}"
    );
    // Status out of range.
    let (status, v) = t.post("/krl/ptp?x=300&s=9").await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "invalid_input");
    assert!(
        v["detail"].as_str().expect("detail").contains("Status"),
        "{v}"
    );
    t.service.shutdown().await.expect("shutdown");
}

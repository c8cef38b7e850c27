//! Configuration planning through HTTP (issue 21, docs/CONFIGURATION.md):
//! a client that never sends S/T gets a configuration that works, a pose
//! the bridge reports is accepted back with its S/T and reaches the same
//! axes, and `keep` is KUKA's rule. And whole-path safety: the workspace
//! box, the floor and keep-out zones hold along the swept path, not only at
//! the targets.

use kuka_bridge_tests::{Options, TestService, assert_close};
use serde_json::{Value, json};

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

async fn start(model: &'static str) -> TestService {
    TestService::start(Options {
        tweak: Box::new(move |c| c.robot.model = model.into()),
        ..Options::default()
    })
    .await
}

/// The thesis's own coordinates (its figures 4.2, 4.5 and 4.6: the flange
/// pointing down at Z 70), sent as a thesis client sends them, without
/// S/T, from the home pose of each model.
#[tokio::test]
async fn thesis_coordinates_run_from_home_on_every_model() {
    for model in [
        "kr3_r540",
        "kr6_r700_sixx",
        "kr6_r900_sixx",
        "kr10_r1100_sixx",
    ] {
        let t = start(model).await;
        for (what, path) in [
            ("ptp", "/krl/ptp?x=200&y=0&z=70&a=0&b=180&c=0"),
            ("linmov", "/krl/linmov?x=250&y=100"),
            (
                "circ",
                "/krl/circ?ax=250&ay=0&az=70&x=200&y=-50&z=80&a=0&b=180&c=0",
            ),
            ("ptp back", "/krl/ptp?x=200&y=0&z=70&a=0&b=180&c=0"),
        ] {
            let (s, v) = t.post(path).await;
            assert_eq!(
                (s, &v["statuscode"]),
                (200, &json!(1)),
                "{model} {what}: {v}"
            );
        }
        // The first PTP's configuration was chosen by the bridge, and says so.
        let (_, jobs) = t.get("/api/v1/jobs?limit=10").await;
        let first = jobs
            .as_array()
            .and_then(|j| j.last())
            .expect("the first job");
        assert_eq!(
            first["configurations"][0]["chosen"], "auto",
            "{model}: {first}"
        );
        t.service.shutdown().await.expect("shutdown");
    }
}

/// A target no configuration reaches within the limits is refused with
/// what each Status would need, not with KUKA's "keeps the current Status".
#[tokio::test]
async fn an_unreachable_ptp_names_every_configuration() {
    let t = start("kr3_r540").await;
    let (s, v) = t.post("/krl/ptp?x=200&y=0&z=200&a=0&b=90&c=0").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("software_limit")),
        "{v}"
    );
    let detail = v["detail"].as_str().unwrap_or_default();
    for st in 0..8 {
        assert!(
            detail.contains(&format!("S {st}: ")),
            "S {st} missing: {detail}"
        );
    }
    t.service.shutdown().await.expect("shutdown");
}

/// The thesis's failing case: the smiley followed by a circle as its
/// mouth, in one batch, without any S/T. `auto` chooses the start
/// configuration for the whole path; with `keep` the first PTP keeps the
/// home Status and the same batch is refused before anything moves.
#[tokio::test]
async fn the_smiley_with_a_mouth_draws_in_one_batch_without_st() {
    let t = start("kr3_r540").await;
    let smiley: Value =
        serde_json::from_str(include_str!("../docs/smiley.json")).expect("docs/smiley.json");
    let mut motions: Vec<Value> = smiley["motions"].as_array().expect("motions").clone();
    for m in &mut motions {
        if let Some(target) = m["target"].as_object_mut() {
            target.remove("s");
            target.remove("t");
        }
    }
    let mouth = json!([
        {"type": "lin", "target": {"x": 250, "y": 0}, "velocity_m_s": 0.1, "approx_mm": 1},
        {"type": "lin", "target": {"z": 70}, "velocity_m_s": 0.1, "approx_mm": 1},
        {"type": "circ", "aux": {"x": 220, "y": 30}, "target": {"x": 190, "y": 0}, "velocity_m_s": 0.1, "approx_mm": 1},
        {"type": "circ", "aux": {"x": 220, "y": -30}, "target": {"x": 250, "y": 0}, "velocity_m_s": 0.1, "approx_mm": 1},
        {"type": "lin", "target": {"z": 100}, "velocity_m_s": 0.1}
    ]);
    motions.extend(mouth.as_array().expect("mouth").iter().cloned());
    let n = motions.len();

    let (s, keep) = t
        .post_json(
            "/api/v1/motions",
            &json!({"motions": motions, "config": "keep"}),
        )
        .await;
    let (s2, job) = t
        .post_json("/api/v1/motions", &json!({"motions": motions}))
        .await;
    assert_eq!(s2, 200, "{job}");
    assert_eq!(job["state"], "done", "{job}");
    assert_eq!(job["completed"].as_u64(), Some(n as u64), "{job}");
    let chosen = &job["configurations"][0];
    assert_eq!(chosen["chosen"], "auto", "{job}");
    assert!(chosen["s"].is_u64() && chosen["t"].is_u64(), "{job}");
    // `keep` from home: the home Status (A5 bit free at A5 = 0) is kept.
    // Whether that works depends on the path; either way nothing moved
    // when it was refused, and a refusal names a motion.
    if s != 200 {
        assert_eq!(s, 422, "{keep}");
        assert!(keep["motion"].is_u64(), "{keep}");
    }
    t.service.shutdown().await.expect("shutdown");
}

/// Every pose the bridge reports is accepted back with its S/T and reaches
/// the same axes: random axes (A1/A4/A6 at exactly 0 half of the time, A5
/// at 0 sometimes), read through `GET /api/v1/position`, sent back as a PTP
/// from elsewhere, on every model.
#[tokio::test]
async fn reported_positions_are_accepted_back_and_reach_the_same_axes() {
    let mut seed: u64 = 0x2026_1126;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % 10_000) as f64 / 10_000.0
    };
    let mut refused = Vec::new();
    let mut tried = 0;
    for model in [
        "kr3_r540",
        "kr6_r700_sixx",
        "kr6_r900_sixx",
        "kr10_r1100_sixx",
    ] {
        let t = start(model).await;
        let (_, info) = t.get("/api/v1/model").await;
        let limits: Vec<(f64, f64)> = info["limits_deg"]
            .as_array()
            .expect("limits")
            .iter()
            .map(|l| (f(&l[0]), f(&l[1])))
            .collect();
        for _ in 0..25 {
            let mut axes = [0.0; 6];
            for (i, a) in axes.iter_mut().enumerate() {
                // Inside the limits by a margin, so the PTP there is legal.
                let (lo, hi) = (limits[i].0 + 5.0, limits[i].1 - 5.0);
                *a = ((lo + (hi - lo) * rnd()) * 1000.0).round() / 1000.0;
            }
            for i in [0, 3, 5] {
                if rnd() < 0.5 {
                    axes[i] = 0.0;
                }
            }
            if rnd() < 0.2 {
                axes[4] = 0.0;
            }
            let names = ["a1", "a2", "a3", "a4", "a5", "a6"];
            let spec: serde_json::Map<String, Value> = names
                .iter()
                .zip(axes)
                .map(|(n, v)| ((*n).into(), json!(v)))
                .collect();
            let (s, v) = t.motions(json!([{"type": "ptp_axes", "axes": spec}])).await;
            assert_eq!(s, 200, "{model} to {axes:?}: {v}");
            let (_, pos) = t.get("/api/v1/position").await;
            let p = &pos["position"];
            // Away first, then back to the reported pose with its S/T.
            let (s, v) = t.post("/api/v1/home").await;
            assert_eq!(s, 200, "{v}");
            tried += 1;
            let (s, v) = t
                .motions(json!([{"type": "ptp", "target": p.clone()}]))
                .await;
            if s != 200 {
                refused.push(format!("{model} {axes:?} {p}: {v}"));
                continue;
            }
            let (_, back) = t.get("/api/v1/position").await;
            for (i, n) in names.iter().enumerate() {
                let (want, got) = (axes[i], f(&back["axes"][n]));
                // A4/A6 are only defined as a sum at A5 = 0.
                if axes[4] == 0.0 && (i == 3 || i == 5) {
                    continue;
                }
                assert_close(got, want, 0.05, &format!("{model} {n} after replaying {p}"));
            }
            if axes[4] == 0.0 {
                // The same wrist rotation (A4 + A6, modulo a turn) in the
                // same Turn: the same configuration.
                let sum = f(&back["axes"]["a4"]) + f(&back["axes"]["a6"]);
                let off = (sum - (axes[3] + axes[5]) + 180.0).rem_euclid(360.0) - 180.0;
                assert_close(off, 0.0, 0.05, &format!("{model} A4 + A6 at A5 = 0"));
                // ... and A4, A6 on the same side of 0 where they were clear of it.
                for (i, n) in [(3, "a4"), (5, "a6")] {
                    if axes[i].abs() > 0.5 {
                        assert_eq!(
                            f(&back["axes"][n]) < 0.0,
                            axes[i] < 0.0,
                            "{model} {n} sign after replaying {p}: {back}"
                        );
                    }
                }
            }
        }
        t.service.shutdown().await.expect("shutdown");
    }
    assert!(
        refused.is_empty(),
        "{} of {tried} replays refused:\n{}",
        refused.len(),
        refused.join("\n")
    );
}

/// A CIRC whose targets and auxiliary point lie inside the box but whose
/// arc dips out of it between them is refused before anything moves, with
/// the motion and the first point outside; a LIN through a keep-out zone
/// likewise; the same motions pass without the zones.
#[tokio::test]
async fn the_swept_path_must_stay_in_the_workspace_and_out_of_keep_out_zones() {
    use kuka_bridge::config::{KeepOut, WorkspaceBox};
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.workspace = Some(WorkspaceBox {
                x: [0.0, 600.0],
                y: [-70.0, 400.0],
                z: [0.0, 700.0],
            });
            c.zones.floor_z = Some(20.0);
            c.zones.keep_out = vec![KeepOut {
                name: "fixture".into(),
                x: [190.0, 210.0],
                y: [40.0, 60.0],
                z: [0.0, 100.0],
            }];
        }),
        ..Options::default()
    })
    .await;
    let down = json!({"x": 250, "y": 0, "z": 70, "a": 0, "b": 180, "c": 0});
    // The arc through (240, -60) to (150, -60) around (195, -21.7), r 59.1,
    // passes y = -80.8 between its points; every point given is at y ≥ -60.
    let (s, v) = t
        .motions(json!([
            {"type": "ptp", "target": down},
            {"type": "circ", "aux": {"x": 240, "y": -60}, "target": {"x": 150, "y": -60}}
        ]))
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("workspace_violation")),
        "{v}"
    );
    assert_eq!(v["motion"], 1, "{v}");
    let detail = v["detail"].as_str().unwrap_or_default();
    assert!(detail.contains("the path passes"), "{detail}");
    let y: f64 = detail
        .split(", ")
        .nth(1)
        .and_then(|y| y.parse().ok())
        .unwrap_or(0.0);
    assert!(y < -70.0, "the first point outside: {detail}");
    // A LIN whose ends are clear of the fixture but whose line crosses it.
    let (s, v) = t
        .motions(json!([
            {"type": "ptp", "target": {"x": 250, "y": 50, "z": 70, "a": 0, "b": 180, "c": 0}},
            {"type": "lin", "target": {"x": 150}}
        ]))
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("workspace_violation")),
        "{v}"
    );
    assert!(
        v["detail"]
            .as_str()
            .unwrap_or_default()
            .contains("`fixture`"),
        "{v}"
    );
    // Below the floor.
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 250, "y": 0, "z": 10, "a": 0, "b": 180, "c": 0}}]))
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("workspace_violation")),
        "{v}"
    );
    // Nothing of the refused requests moved the robot; a path that keeps
    // clear runs.
    let (s, v) = t
        .motions(json!([
            {"type": "ptp", "target": down},
            {"type": "circ", "aux": {"x": 220, "y": -30}, "target": {"x": 190, "y": 0}}
        ]))
        .await;
    assert_eq!((s, &v["state"]), (200, &json!("done")), "{v}");
    t.service.shutdown().await.expect("shutdown");

    // The same refused motions without any zones: the dry run alone accepts them.
    let t = TestService::start(Options::default()).await;
    let (s, v) = t
        .motions(json!([
            {"type": "ptp", "target": down},
            {"type": "circ", "aux": {"x": 240, "y": -60}, "target": {"x": 150, "y": -60}},
            {"type": "ptp", "target": {"x": 250, "y": 50, "z": 70, "a": 0, "b": 180, "c": 0}},
            {"type": "lin", "target": {"x": 150}}
        ]))
        .await;
    assert_eq!((s, &v["state"]), (200, &json!("done")), "{v}");
    t.service.shutdown().await.expect("shutdown");
}

/// The way home and uploaded programs are held to the same zones as the
/// motions: HOME whose joint path passes through a keep-out zone and a
/// program whose LIN crosses it are refused, naming the program's line.
#[tokio::test]
async fn home_and_programs_keep_out_of_the_zones() {
    use kuka_bridge::config::KeepOut;
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.zones.keep_out = vec![KeepOut {
                name: "fixture".into(),
                x: [200.0, 230.0],
                y: [-20.0, 20.0],
                z: [0.0, 120.0],
            }];
        }),
        ..Options::default()
    })
    .await;
    // Beside the fixture, reached from the side (a PTP straight there
    // would sweep through it and is refused).
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 180, "y": 0, "z": 100, "a": 0, "b": 180, "c": 0}}]))
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("workspace_violation")),
        "{v}"
    );
    let (s, v) = t
        .motions(json!([
            {"type": "ptp", "target": {"x": 180, "y": 100, "z": 100, "a": 0, "b": 180, "c": 0}},
            {"type": "lin", "target": {"y": 0}}
        ]))
        .await;
    assert_eq!((s, &v["state"]), (200, &json!("done")), "{v}");
    let (s, v) = t.post("/api/v1/home").await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("workspace_violation")),
        "{v}"
    );
    assert!(
        v["detail"]
            .as_str()
            .unwrap_or_default()
            .contains("the way home"),
        "{v}"
    );
    let src = "DEF cross()\n  LIN {X 180, Y 0, Z 100, A 0, B 180, C 0}\n  LIN {X 260, Y 0, Z 100, A 0, B 180, C 0}\nEND\n";
    let (s, v) = t
        .post_json("/api/v1/programs", &json!({"name": "cross", "src": src}))
        .await;
    assert_eq!(s, 201, "{v}");
    let (s, v) = t.post_json("/api/v1/programs/cross/run", &json!({})).await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("workspace_violation")),
        "{v}"
    );
    assert_eq!(v["line"], 3, "{v}");
    t.service.shutdown().await.expect("shutdown");
}

/// A fast PTP samples its path several mm apart: a thin zone between two
/// samples is still found (the pieces between samples are checked too).
#[tokio::test]
async fn a_thin_zone_between_two_samples_is_found() {
    use kuka_bridge::config::KeepOut;
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.zones.keep_out = vec![KeepOut {
                name: "sheet".into(),
                x: [300.0, 300.5],
                y: [-20.0, 20.0],
                z: [600.0, 720.0],
            }];
        }),
        ..Options::default()
    })
    .await;
    let (s, v) = t
        .motions(json!([{"type": "ptp", "target": {"x": 250}, "velocity_pct": 100}]))
        .await;
    assert_eq!(
        (s, v["code"].as_str()),
        (422, Some("workspace_violation")),
        "{v}"
    );
    assert!(
        v["detail"].as_str().unwrap_or_default().contains("`sheet`"),
        "{v}"
    );
    t.service.shutdown().await.expect("shutdown");
}

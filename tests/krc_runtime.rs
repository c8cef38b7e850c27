//! The service over HTTP against the shipped KRL program: `--simulate krc`
//! embeds the KRC-like runtime (`krl/krc`), which runs `krl/KRC/` itself —
//! the Submit side reads the command file, `kb_main` moves the robot — on
//! a simulated controller clock. The thesis endpoints, a v1 batch and an
//! uploaded program, as a user would send them.

use std::time::Duration;

use kuka_bridge::config::SimulatorKind;
use kuka_bridge_tests::{Options, TestService, assert_close, thesis_position, wait_for};
use serde_json::json;

async fn start() -> TestService {
    TestService::start(Options {
        tweak: Box::new(|c| {
            c.simulator.kind = SimulatorKind::Krc;
            // The KRL program's own heartbeat (kb_hb_ms = 100 ms of
            // controller time): well inside offline_after_ms.
        }),
        ..Options::default()
    })
    .await
}

#[tokio::test]
async fn thesis_endpoints_drive_the_shipped_krl_program() {
    let t = start().await;
    assert!(t.service.sim.is_none() && t.service.krc.is_some());
    let (status, health) = t.get("/health").await;
    assert_eq!(
        (status, health["simulated"].as_bool()),
        (200, Some(true)),
        "{health}"
    );

    let (status, v) = t.post("/krl/getpos").await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["statuscode"], 1, "{v}");
    let p = thesis_position(&v);
    assert_close(p[0], 355.0, 0.01, "home x");
    assert_close(p[2], 625.0, 0.01, "home z");

    // The thesis's pen-down pose without Status: from home (A5 = 0 exactly,
    // Status bit 2 undefined) it needs A5 < 0 (docs/CONTROLLER.md
    // changelog, 2026-11-26).
    let (status, v) = t.post("/krl/ptp?x=200&y=0&z=70&a=0&b=180&c=0").await;
    assert_eq!((status, &v["statuscode"]), (200, &json!(1)), "{v}");
    let p = thesis_position(&v);
    assert_close(p[0], 200.0, 0.01, "x");
    assert_close(p[2], 70.0, 0.01, "z");

    let (status, v) = t.post("/krl/linmov?x=250&y=100").await;
    assert_eq!((status, &v["statuscode"]), (200, &json!(1)), "{v}");
    let q = thesis_position(&v);
    assert_close(q[0], 250.0, 0.01, "x");
    assert_close(q[1], 100.0, 0.01, "y");
    assert_close(q[2], 70.0, 0.01, "z kept");

    // The runtime really moved: its axes are where the answer says.
    let krc = t.service.krc.as_ref().expect("krc");
    let snap = krc.snapshot();
    assert!(
        snap.robot_errors.is_empty() && snap.submit_error.is_none(),
        "{snap:?}"
    );
    assert_close(snap.pose[0], 250.0, 0.01, "runtime x");
    assert_close(snap.pose[1], 100.0, 0.01, "runtime y");
    assert!(krc.stats().motions_done >= 2, "{:?}", krc.stats());
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn a_v1_batch_plays_as_one_blended_chain_on_the_krl_program() {
    let t = start().await;
    let krc = t.service.krc.clone().expect("krc");
    let (s, v) = t
        .motions(json!([
            {"type": "ptp", "target": {"x": 200, "y": 0, "z": 70, "a": 0, "b": 180, "c": 0}}
        ]))
        .await;
    assert_eq!(s, 200, "{v}");
    let before = krc.stats();
    let (s, v) = t
        .motions(json!([
            {"type": "lin", "target": {"x": 250}, "velocity_m_s": 0.1, "approx_mm": 2},
            {"type": "lin", "target": {"y": 50}, "velocity_m_s": 0.1, "approx_mm": 2},
            {"type": "lin", "target": {"x": 200}, "velocity_m_s": 0.1, "approx_mm": 2},
            {"type": "lin", "target": {"y": 0}, "velocity_m_s": 0.1}
        ]))
        .await;
    assert_eq!(s, 200, "{v}");
    assert_eq!(v["state"], "done", "{v}");
    assert_eq!(v["completed"], 4, "{v}");
    assert_close(v["position"]["x"].as_f64().expect("x"), 200.0, 0.01, "x");
    assert_close(v["position"]["y"].as_f64().expect("y"), 0.0, 0.01, "y");
    let after = krc.stats();
    assert_eq!(after.motions_done - before.motions_done, 4, "{after:?}");
    assert_eq!(
        after.chains_started - before.chains_started,
        1,
        "the approximated square plays without exact stops: {after:?}"
    );
    // 4 × 50 mm at 0.1 m/s: at least 2 s of simulated motion.
    assert!(after.moving_s - before.moving_s >= 2.0, "{after:?}");
    // The trace over HTTP marks the one stop: where the square ends.
    let cid = v["cid"].as_i64().expect("cid");
    let (s, trace) = t.get("/api/v1/sim/trace").await;
    assert_eq!(s, 200, "{trace}");
    let samples: Vec<&serde_json::Value> = trace
        .as_array()
        .expect("samples")
        .iter()
        .filter(|x| x["cid"].as_i64() == Some(cid))
        .collect();
    let stops: Vec<usize> = samples
        .iter()
        .enumerate()
        .filter(|(_, x)| x["stop"] == true)
        .map(|(i, _)| i)
        .collect();
    assert_eq!(stops, vec![samples.len() - 1], "one stop, at the end");
    t.service.shutdown().await.expect("shutdown");
}

#[tokio::test]
async fn an_uploaded_program_runs_through_the_krl_program_and_its_run_command() {
    let t = start().await;
    let src = "&ACCESS RVP\nDEF wave()\n  DECL INT i\n  FOR i = 1 TO 3\n    PTP {A1 amp * i}\n  ENDFOR\n  PTP {A1 0}\nEND\n";
    let dat = "DEFDAT wave\n  DECL REAL amp = 10.0\nENDDAT\n";
    let (status, v) = t
        .post_json(
            "/api/v1/programs",
            &json!({"name": "wave", "src": src, "dat": dat}),
        )
        .await;
    assert_eq!(status, 201, "{v}");
    let krc = t.service.krc.clone().expect("krc");
    let (status, job) = t.post_json("/api/v1/programs/wave/run", &json!({})).await;
    assert_eq!(status, 200, "{job}");
    assert_eq!(job["state"], "done", "{job}\n{:?}", krc.snapshot());
    // The Submit side selected the module through $CMD with the public
    // RUN path, and the robot interpreter ran it to A1 = 0 again.
    let snap = krc.snapshot();
    assert!(
        snap.commands.iter().any(|c| c.starts_with("RUN /R1/kbu")),
        "{snap:?}"
    );
    assert!(snap.axes[0].abs() < 0.01, "{snap:?}");
    // kb_main is selected again afterwards, ready for the next command.
    let (status, v) = wait_for(
        Duration::from_secs(10),
        "getpos after the program",
        async || {
            let (s, v) = t.post("/krl/getpos").await;
            if s == 200 {
                Ok((s, v))
            } else {
                Err(format!("{s} {v}"))
            }
        },
    )
    .await;
    assert_eq!((status, &v["statuscode"]), (200, &json!(1)), "{v}");

    // KRL beyond the native simulator's subset (an output) is accepted and
    // runs: the upload is checked against what the runtime runs.
    let src = "DEF io()\n  $OUT[5] = TRUE\n  PTP {A1 5}\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "io", "src": src}))
        .await;
    assert_eq!(
        (status, &v["simulator_checked"]),
        (201, &json!(true)),
        "{v}"
    );
    let (status, job) = t.post_json("/api/v1/programs/io/run", &json!({})).await;
    assert_eq!((status, &job["state"]), (200, &json!("done")), "{job}");
    assert!((krc.snapshot().axes[0] - 5.0).abs() < 0.01);
    t.service.shutdown().await.expect("shutdown");
}

/// The other KSS variant of the two facts public sources leave open
/// (docs/CONTROLLER.md A1, A2): file functions answer `#CMD_OK` and RUN
/// wants the folder in the path. With `kb_run_pfx` set as a site would,
/// the shipped program reads commands and runs uploaded modules as before.
#[tokio::test]
async fn the_program_works_on_the_other_kss_variant() {
    let t = TestService::start(Options {
        tweak: Box::new(|c| {
            c.simulator.kind = SimulatorKind::Krc;
            c.simulator.file_success = kuka_bridge::config::FileSuccess::CmdOk;
            c.simulator.run_prefix = "/R1/Program/kbridge/".into();
        }),
        ..Options::default()
    })
    .await;
    let krc = t.service.krc.clone().expect("krc");
    let (status, v) = t.post("/krl/getpos").await;
    assert_eq!((status, &v["statuscode"]), (200, &json!(1)), "{v}");
    let src = "DEF hop()\n  PTP {A1 12}\n  PTP {A1 0}\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "hop", "src": src}))
        .await;
    assert_eq!(status, 201, "{v}");
    let (status, job) = t.post_json("/api/v1/programs/hop/run", &json!({})).await;
    assert_eq!(
        (status, &job["state"]),
        (200, &json!("done")),
        "{job}\n{:?}",
        krc.snapshot()
    );
    let snap = krc.snapshot();
    assert!(
        snap.commands
            .iter()
            .any(|c| c.starts_with("RUN /R1/Program/kbridge/kbu")),
        "{snap:?}"
    );
    assert!(
        snap.commands.iter().all(|c| !c.starts_with("RUN /R1/kb")),
        "only the site's RUN form: {snap:?}"
    );
    // The file functions answered #CMD_OK all along and the program took
    // them as success: the results file is read back over HTTP.
    assert!(
        krc.stats()
            .file_calls
            .get("krl_fgets")
            .copied()
            .unwrap_or(0)
            > 0,
        "{:?}",
        krc.stats().file_calls
    );
    let (status, job) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 7}}]))
        .await;
    assert_eq!((status, &job["state"]), (200, &json!("done")), "{job}");
    assert_close(t.controller_axes()[0], 7.0, 0.01, "A1 after the motion");
    t.service.shutdown().await.expect("shutdown");
}

/// A program that stops with an error leaves the controller waiting for
/// the operator, as a KRC does: the state says so (not idle), RESET does
/// not clear it, motions are refused; acknowledging the stop message
/// (`POST /api/v1/sim/acknowledge`, what the operator does at the
/// pendant) makes it ready again. Programs may use the tool and base
/// tables every KRC has.
#[tokio::test]
async fn an_error_stop_waits_for_the_operator_and_acknowledge_ends_it() {
    let t = start().await;
    let src = "DEF usetool()\n  $TOOL = TOOL_DATA[1]\n  $BASE = BASE_DATA[2]\n  PTP {A1 5}\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "usetool", "src": src}))
        .await;
    assert_eq!(status, 201, "{v}");
    let (status, job) = t
        .post_json("/api/v1/programs/usetool/run", &json!({}))
        .await;
    assert_eq!((status, &job["state"]), (200, &json!("done")), "{job}");

    // (The output makes it KRL the service's dry run does not run, so the
    // division by zero is found by the controller.)
    let src =
        "DEF fails()\n  DECL INT i\n  i = 0\n  $OUT[5] = TRUE\n  PTP {A1 10}\n  i = 10 / i\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "fails", "src": src}))
        .await;
    assert_eq!(status, 201, "{v}");
    let (status, job) = t.post_json("/api/v1/programs/fails/run", &json!({})).await;
    assert_eq!(
        (status, job["code"].as_str()),
        (409, Some("program_failed")),
        "{job}"
    );
    let (_, state) = wait_for(Duration::from_secs(10), "the error state", async || {
        let (s, v) = t.get("/api/v1/state").await;
        if v["controller"]["status"] == "error" {
            Ok((s, v))
        } else {
            Err(v.to_string())
        }
    })
    .await;
    assert_eq!(
        state["controller"]["error"]["code"], "controller_error",
        "{state}"
    );
    let (status, v) = t.post("/api/v1/reset").await;
    assert_eq!(status, 200, "{v}");
    let (status, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 3}}]))
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (409, Some("controller_error")),
        "RESET does not acknowledge a stop message: {v}"
    );
    let (status, v) = t.post("/api/v1/sim/acknowledge").await;
    assert_eq!(status, 204, "{v}");
    // kb_main runs again; once the state is idle, motions work.
    wait_for(Duration::from_secs(10), "ready again", async || {
        let (s, v) = t.get("/api/v1/state").await;
        if v["controller"]["status"] == "idle" {
            Ok((s, v))
        } else {
            Err(v.to_string())
        }
    })
    .await;
    let (status, v) = t
        .motions(json!([{"type": "ptp_axes", "axes": {"a1": 3}}]))
        .await;
    assert_eq!((status, &v["state"]), (200, &json!("done")), "{v}");
    t.service.shutdown().await.expect("shutdown");
}

/// While a path runs, the service removes each command the controller has
/// read (`channel.remove_read_command`, PROTOCOL.md §9.2 step 4): the
/// program's polls between APPENDs open nothing and read no line, where
/// they used to read the same header at every poll (docs/BENCHMARKS.md
/// §10.5). A batch of 16 slow LINs (sent as a path, 200 ms each, ~10 polls
/// per motion) in real time: with the removal, `krl_fgets` stay within 1.5
/// per motion (the command lines and each command's header and APD line);
/// with the key off, every poll reads the header again.
#[tokio::test]
async fn polls_during_a_path_read_no_line_twice() {
    let mut per_motion = Vec::new();
    for remove in [true, false] {
        let t = TestService::start(Options {
            time_scale: 1.0,
            tweak: Box::new(move |c| {
                c.simulator.kind = SimulatorKind::Krc;
                c.channel.remove_read_command = remove;
            }),
            ..Options::default()
        })
        .await;
        let krc = t.service.krc.clone().expect("krc");
        // Away from home's wrist singularity.
        let (status, job) = t
            .motions(json!([{"type": "ptp", "target": {"x": 300, "z": 500}}]))
            .await;
        assert_eq!((status, &job["state"]), (200, &json!("done")), "{job}");
        let fgets = || {
            krc.stats()
                .file_calls
                .get("krl_fgets")
                .copied()
                .unwrap_or(0)
        };
        let before = fgets();
        let motions: Vec<_> = (0..16)
            .map(|i| {
                let y = if i % 2 == 0 { 10.0 } else { 0.0 };
                json!({"type": "lin", "target": {"y": y}, "velocity_m_s": 0.05, "approx_mm": 0})
            })
            .collect();
        let (status, job) = t.motions(json!(motions)).await;
        assert_eq!((status, &job["state"]), (200, &json!("done")), "{job}");
        let read = (fgets() - before) as f64 / 16.0;
        per_motion.push(read);
        let cmd = t.channel_dir().join(kuka_protocol::COMMAND_FILE);
        if remove {
            assert!(
                read <= 1.5,
                "krl_fgets per motion {read:.2} with the removal"
            );
        } else {
            assert!(
                cmd.exists(),
                "the command file was removed with the key off"
            );
        }
    }
    assert!(
        per_motion[1] >= 3.0 * per_motion[0],
        "the polls read the kept command again and again: {per_motion:?} (with, without the removal)"
    );
    eprintln!("krl_fgets per motion with / without the removal: {per_motion:?}");
}

//! KRL programs end to end: upload, validation before anything reaches the
//! controller, runs on the simulated controller through the file protocol
//! (a fresh module per run), and the thesis's `/krl/uploadfile`.

use kuka_bridge_tests::{Options, TestService, assert_close, thesis_position};
use serde_json::json;

/// The thesis's upload example (listing 4.11) with the middle point's Y
/// and the end point's Z as parameters. Its points are in the base frame;
/// the thesis's small LEGO arm reached them from its base, a KR 3 R540
/// (flange pointing forward, B 90) needs the base 150 mm in front of it
/// ([`thesis_base`]), as on a table-top setup.
fn thesis_spline(y_mid: f64, z_end: f64) -> String {
    format!(
        "DEFFCT INT fuploaded()
    SPLINE
    SPL {{X 200, Y 0, Z 200, A 0, B 90, C 0}}
    SPL {{X 200, Y {y_mid}, Z 150, A 0, B 90, C 0}}
    SPL {{X 200, Y 50, Z {z_end}, A 0, B 90, C 0}}
    ENDSPLINE
    RETURN 1
ENDFCT
"
    )
}

/// Puts the base frame 150 mm in front of the robot.
async fn thesis_base(t: &TestService) {
    let base = json!({"x": 150.0, "y": 0.0, "z": 0.0, "a": 0.0, "b": 0.0, "c": 0.0});
    let (status, v) = t.put_json("/api/v1/base", &base).await;
    assert_eq!(status, 200, "{v}");
}

fn cmd_file(t: &TestService) -> Option<String> {
    std::fs::read_to_string(t.channel_dir().join("kb_cmd.txt")).ok()
}

/// The trace points of the last run, as (x, y, z).
fn trace_xyz(t: &TestService) -> Vec<[f64; 3]> {
    t.trace()
        .iter()
        .map(|s| [s.pose[0], s.pose[1], s.pose[2]])
        .collect()
}

/// Whether the trace polyline passes within `tol` mm of `p` (samples are
/// 12 ms apart, so compare against the segments between them).
fn passes_near(trace: &[[f64; 3]], p: [f64; 3], tol: f64) -> bool {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    trace.windows(2).any(|w| {
        let (a, b) = (w[0], w[1]);
        let ab = sub(b, a);
        let len2 = dot(ab, ab);
        let u = if len2 > 0.0 {
            (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + u * ab[0], a[1] + u * ab[1], a[2] + u * ab[2]];
        dot(sub(p, q), sub(p, q)).sqrt() <= tol
    })
}

#[tokio::test]
async fn the_thesis_upload_runs_every_time_with_the_new_code() {
    let t = TestService::start(Options::default()).await;
    thesis_base(&t).await;

    let mut ends = Vec::new();
    for (y_mid, z_end) in [(-50.0, 100.0), (60.0, 120.0)] {
        t.clear_trace();
        let (status, v) = t
            .post_text("/krl/uploadfile", thesis_spline(y_mid, z_end))
            .await;
        assert_eq!(status, 200, "{v}");
        assert_eq!(v["statuscode"], 1, "{v}");
        let p = thesis_position(&v);
        assert_close(p[0], 200.0, 0.01, "end x");
        assert_close(p[1], 50.0, 0.01, "end y");
        assert_close(p[2], z_end, 0.01, "end z");
        let trace = trace_xyz(&t);
        assert!(trace.len() > 10, "the program moved the robot");
        // The spline's segments blend (approximation), so it passes its
        // points within a few millimetres.
        assert!(
            passes_near(&trace, [200.0, y_mid, 150.0], 2.0),
            "the spline passes its middle point (y {y_mid})"
        );
        assert!(
            passes_near(&trace, [200.0, 0.0, 200.0], 2.0),
            "and its first point"
        );
        ends.push((y_mid, trace));
    }
    // The second run drew the second program, not the first one again.
    assert!(
        !passes_near(&ends[1].1, [200.0, -50.0, 150.0], 5.0),
        "second run must not replay the first upload"
    );

    // Each run wrote its own module: two kbu files, different numbers.
    let modules: Vec<String> = std::fs::read_dir(t.channel_dir().join("programs"))
        .expect("program folder")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".src"))
        .collect();
    assert_eq!(modules.len(), 2, "{modules:?}");
}

#[tokio::test]
async fn the_thesis_upload_accepts_a_multipart_form() {
    let t = TestService::start(Options::default()).await;
    thesis_base(&t).await;
    let boundary = "kbtestboundary";
    let body = format!(
        "--{boundary}\r\nContent-Disposition: form-data; name=\"file\"; filename=\"up.src\"\r\nContent-Type: application/octet-stream\r\n\r\n{}\r\n--{boundary}--\r\n",
        thesis_spline(-20.0, 100.0)
    );
    let (status, v) = t.post_form(boundary, body).await;
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["statuscode"], 1);
}

#[tokio::test]
async fn bad_programs_are_refused_with_their_line_before_reaching_the_controller() {
    let t = TestService::start(Options::default()).await;
    t.wait_online().await;
    let before = cmd_file(&t);

    // Syntax error: IF without ENDIF.
    let src = "DEF bad()\n  DECL INT i\n  IF i > 0 THEN\n    i = 1\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "bad", "src": src}))
        .await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "invalid_program");
    assert_eq!(v["line"], 5, "{v}");
    assert_eq!(v["file"], "src");

    // A program that opens a channel file would lock the channel: refused
    // whatever runs it.
    let src = "DEF peek()\n  DECL STATE_T st\n  DECL MODUS_T md\n  DECL INT h\n  md = #SYNC\n  IF TRUE THEN\n    CWRITE($FCT_CALL, st, md, \"krl_fopen\", \"KB_CMD.TXT\", \"r\", h)\n  ENDIF\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "peek", "src": src}))
        .await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(
        (&v["code"], &v["line"]),
        (&json!("invalid_program"), &json!(7)),
        "{v}"
    );
    assert!(
        v["detail"].as_str().is_some_and(|d| d.contains("channel")),
        "{v}"
    );

    // Outside the simulator's subset: an interrupt on line 3.
    let src = "DEF irq()\n  PTP {A1 0}\n  INTERRUPT ON 3\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "irq", "src": src}))
        .await;
    if t.service.krc.is_some() {
        // The KRC-like runtime runs interrupts: accepted, checked against
        // what the runtime runs.
        assert_eq!(
            (status, &v["simulator_checked"]),
            (201, &json!(true)),
            "{v}"
        );
        let (status, _) = t.delete("/api/v1/programs/irq").await;
        assert_eq!(status, 204);
        // It cannot run a GOTO nor a $config.dat global it lacks: refused
        // with the line rather than stopping the program there.
        for (src, line) in [
            ("DEF jump()\n  PTP {A1 0}\n  GOTO over\n  over:\nEND\n", 3),
            ("DEF jump()\n  PTP {A1 0}\n  PDAT_ACT = PDEFAULT\nEND\n", 3),
        ] {
            let (status, v) = t
                .post_json("/api/v1/programs", &json!({"name": "jump", "src": src}))
                .await;
            assert_eq!(status, 422, "{v}");
            assert_eq!(
                (&v["code"], &v["line"]),
                (&json!("program_unsupported"), &json!(line)),
                "{v}"
            );
        }
    } else {
        assert_eq!(status, 422, "{v}");
        assert_eq!(v["code"], "program_unsupported");
        assert_eq!(v["line"], 3, "{v}");
        assert!(
            v["detail"]
                .as_str()
                .is_some_and(|d| d.contains("not supported by the simulator")),
            "{v}"
        );
    }

    // The thesis endpoint answers in its format, with the line.
    let (status, v) = t
        .post_text(
            "/krl/uploadfile",
            "DEFFCT INT fuploaded()\n  x = = 1\nENDFCT\n".into(),
        )
        .await;
    assert_eq!(status, 422, "{v}");
    assert_ne!(v["statuscode"], 1);
    assert_eq!(v["line"], 2, "{v}");

    // Bad names, missing entry points, a .dat of another module.
    let (status, v) = t
        .post_json(
            "/api/v1/programs",
            &json!({"name": "9lives", "src": "DEF a()\nEND\n"}),
        )
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );
    let (status, v) = t
        .post_json(
            "/api/v1/programs",
            &json!({"name": "a", "src": "DEF a()\nEND\n", "entry": "main"}),
        )
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_program")),
        "{v}"
    );
    let (status, v) = t
        .post_json(
            "/api/v1/programs",
            &json!({"name": "a", "src": "DEF a()\nEND\n", "dat": "DEFDAT b\nENDDAT\n"}),
        )
        .await;
    assert_eq!(
        (status, v["code"].as_str(), v["file"].as_str()),
        (422, Some("invalid_program"), Some("dat")),
        "{v}"
    );

    // Nothing reached the channel or the program folder.
    assert_eq!(cmd_file(&t), before, "no command was written");
    assert!(
        !t.channel_dir().join("programs").exists(),
        "no module was written"
    );
    let (_, list) = t.get("/api/v1/programs").await;
    assert_eq!(list, json!([]), "nothing was stored");
}

#[tokio::test]
async fn programs_are_stored_run_listed_and_deleted() {
    let t = TestService::start(Options::default()).await;
    let src = "&ACCESS RVP\nDEF wave()\n  DECL INT i\n  FOR i = 1 TO 3\n    PTP {A1 amp * i}\n    WAIT SEC 0.1\n  ENDFOR\n  PTP {A1 0}\nEND\n";
    let dat = "DEFDAT wave\n  DECL REAL amp = 10.0\nENDDAT\n";
    let (status, v) = t
        .post_json(
            "/api/v1/programs",
            &json!({"name": "Wave", "src": src, "dat": dat}),
        )
        .await;
    assert_eq!(status, 201, "{v}");
    assert_eq!(v["entry"], "wave");
    assert_eq!(v["src_lines"], 9);

    let (status, job) = t.post_json("/api/v1/programs/wave/run", &json!({})).await;
    assert_eq!(status, 200, "{job}");
    assert_eq!(job["state"], "done");
    // The native simulator counts the steps; the KRL program cannot count
    // the statements of an arbitrary program and answers 0 (PROTOCOL.md 6:
    // 0 if unknown): a program that ended ran all of them either way.
    assert_eq!(
        job["completed"], 8,
        "BCO run + 3 PTP + 3 dwells + 1 PTP: {job}"
    );
    assert_eq!(job["motions"], 8, "the dry run counted them: {job}");
    // The trace visited A1 = 30 (amp from the .dat times 3).
    assert!(
        t.trace().iter().any(|s| (s.axes[0] - 30.0).abs() < 0.01),
        "A1 reached 30"
    );

    // Replacing keeps one program; listing and reading show it.
    let (status, _) = t
        .post_json(
            "/api/v1/programs",
            &json!({"name": "wave", "src": src, "dat": dat}),
        )
        .await;
    assert_eq!(status, 200);
    let (_, list) = t.get("/api/v1/programs").await;
    assert_eq!(list.as_array().map(Vec::len), Some(1), "{list}");
    let (status, one) = t.get("/api/v1/programs/WAVE").await;
    assert_eq!(status, 200);
    assert_eq!(one["src"], src);

    // Not waiting gives a job to poll.
    let r = reqwest::Client::new()
        .post(t.url("/api/v1/programs/wave/run"))
        .json(&json!({"wait": false}))
        .send()
        .await
        .expect("run");
    assert_eq!(r.status().as_u16(), 202);

    let (status, _) = t.delete("/api/v1/programs/wave").await;
    assert_eq!(status, 204);
    let (status, v) = t.get("/api/v1/programs/wave").await;
    assert_eq!((status, v["code"].as_str()), (404, Some("not_found")));
    let (status, v) = t.post_json("/api/v1/programs/wave/run", &json!({})).await;
    assert_eq!(status, 404, "{v}");
}

/// Line 4 is out of reach of a KR 3 R540 (541 mm).
const FAR: &str = "DEF far()\n  PTP {A1 0, A2 -90, A3 90, A4 0, A5 0, A6 0}\n  LIN {X 360, Y 0, Z 600}\n  LIN {X 2000, Y 0, Z 600}\nEND\n";
/// Division by zero on line 3.
const DIV: &str = "DEF div()\n  DECL INT i\n  i = 1 / 0\nEND\n";

#[tokio::test]
async fn the_safety_gate_dry_runs_a_program_and_writes_nothing_when_it_fails() {
    let t = TestService::start(Options::default()).await;
    t.wait_online().await;
    for (name, src) in [("far", FAR), ("div", DIV)] {
        let (status, v) = t
            .post_json("/api/v1/programs", &json!({"name": name, "src": src}))
            .await;
        assert_eq!(status, 201, "{v}");
    }
    let before = cmd_file(&t);
    let (status, v) = t.post_json("/api/v1/programs/far/run", &json!({})).await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "unreachable");
    assert_eq!(v["line"], 4, "{v}");
    let (status, v) = t.post_json("/api/v1/programs/div/run", &json!({})).await;
    assert_eq!(status, 409, "{v}");
    assert_eq!(v["code"], "program_failed");
    assert_eq!(v["line"], 3, "{v}");
    assert_eq!(cmd_file(&t), before, "nothing was sent");
    assert!(
        !t.channel_dir().join("programs").exists(),
        "no module was written"
    );

    // Speed caps hold inside programs too.
    let fast = "DEF fast()\n  PTP {A1 0, A2 -90, A3 90, A4 0, A5 0, A6 0}\n  $VEL.CP = 1.5\n  LIN {X 360, Y 0, Z 600}\nEND\n";
    t.post_json("/api/v1/programs", &json!({"name": "fast", "src": fast}))
        .await;
    let (status, v) = t.post_json("/api/v1/programs/fast/run", &json!({})).await;
    assert_eq!(
        (status, v["code"].as_str(), v["line"].as_u64()),
        (422, Some("speed_limit"), Some(4)),
        "{v}"
    );
}

#[tokio::test]
async fn without_a_robot_model_the_controller_reports_the_failing_line() {
    // No model in the service: no dry run; the simulated controller (a
    // KR 3 R540) finds the errors while running.
    let t = TestService::start(Options {
        tweak: Box::new(|c| c.robot.model = "none".into()),
        ..Options::default()
    })
    .await;
    for (name, src) in [("far", FAR), ("div", DIV)] {
        t.post_json("/api/v1/programs", &json!({"name": name, "src": src}))
            .await;
    }
    if let Some(krc) = t.service.krc.clone() {
        // The KRL program learns only that the module stopped with a
        // message ($STOPMESS): both fail as program_failed, without a line;
        // the operator acknowledges and starts kb_main again.
        for name in ["far", "div"] {
            let (status, v) = t
                .post_json(&format!("/api/v1/programs/{name}/run"), &json!({}))
                .await;
            assert_eq!(
                (status, v["code"].as_str()),
                (409, Some("program_failed")),
                "{name}: {v}\n{:?}",
                krc.snapshot()
            );
            krc.operator_restart();
            t.wait_getpos("kb_main back").await;
        }
        let (status, v) = t.post("/krl/getpos").await;
        assert_eq!(status, 200, "{v}");
        return;
    }
    let (status, v) = t.post_json("/api/v1/programs/far/run", &json!({})).await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "unreachable");
    assert_eq!(v["line"], 4, "{v}");
    assert!(
        v["detail"]
            .as_str()
            .is_some_and(|d| d.contains("controller")),
        "{v}"
    );
    let (status, v) = t.post_json("/api/v1/programs/div/run", &json!({})).await;
    assert_eq!(status, 409, "{v}");
    assert_eq!(v["code"], "program_failed");
    assert_eq!(v["line"], 3, "{v}");
    // The service keeps working afterwards.
    let (status, v) = t.post("/krl/getpos").await;
    assert_eq!(status, 200, "{v}");
}

#[tokio::test]
async fn stop_ends_a_running_program_and_skips_the_rest() {
    let t = TestService::start(Options {
        time_scale: 1.0,
        ..Options::default()
    })
    .await;
    t.wait_online().await;
    // A dwell of 3 s, then a PTP that must never run.
    let src = "DEF slow()\n  WAIT SEC 3\n  PTP {A1 45}\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "slow", "src": src}))
        .await;
    assert_eq!(status, 201, "{v}");
    let (status, job) = t
        .post_json("/api/v1/programs/slow/run", &json!({"wait": false}))
        .await;
    assert_eq!(status, 202, "{job}");
    // Wait until the controller runs it, then stop.
    let id = job["id"].as_u64().expect("job id");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(5);
    loop {
        let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
        if j["state"] == "executing" {
            break;
        }
        assert!(std::time::Instant::now() < deadline, "never executing: {j}");
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    let (status, v) = t.post("/api/v1/stop").await;
    assert_eq!(status, 200, "{v}");
    let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
    assert_eq!(j["state"], "cancelled", "{j}");
    assert_eq!(j["error"]["code"], "cancelled", "{j}");
    // The PTP after the dwell never ran: the controller is idle (a program
    // still dwelling would be busy, and then run the PTP) with A1 at 0.
    let state = t
        .wait_state("the controller idle after the stop", |st| {
            st["controller"]["status"] == "idle"
        })
        .await;
    let a1 = state["axes"]["a1"].as_f64().expect("a1");
    assert!(a1.abs() < 0.01, "A1 stayed at 0: {state}");
}

#[tokio::test]
async fn uploads_as_old_clients_and_editors_make_them_are_handled() {
    let t = TestService::start(Options::default()).await;
    thesis_base(&t).await;
    // A form field before the file (Python requests with data= and files=).
    let boundary = "kbb";
    let body = format!(
        "--{boundary}\r\nContent-Disposition: form-data; name=\"robot\"\r\n\r\nkr3\r\n--{boundary}\r\nContent-Disposition: form-data; name=\"upload\"; filename=\"up.src\"\r\n\r\n{}\r\n--{boundary}--\r\n",
        thesis_spline(-20.0, 100.0)
    );
    let (status, v) = t.post_form(boundary, body).await;
    assert_eq!((status, &v["statuscode"]), (200, &json!(1)), "{v}");

    // A byte-order mark, CR LF line ends and a Windows-1252 comment (ü = 0xFC).
    let mut bytes = b"\xef\xbb\xbfDEF bom()\r\n  ; Gr\xfc\xdfe\r\n  PTP {A1 5}\r\nEND\r\n".to_vec();
    let r = reqwest::Client::new()
        .post(t.url("/krl/uploadfile"))
        .header("content-type", "text/plain")
        .body(std::mem::take(&mut bytes))
        .send()
        .await
        .expect("request");
    let (status, v) = kuka_bridge_tests::decode(r).await;
    assert_eq!(status, 200, "{v}");
    let modules = t.channel_dir().join("programs");
    let newest = std::fs::read_dir(&modules)
        .expect("modules")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "src"))
        .max_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok())
        .expect("a module");
    let written = std::fs::read(&newest).expect("module");
    assert!(
        !written.windows(3).any(|w| w == b"\xef\xbb\xbf"),
        "no BOM inside the module"
    );
    assert!(
        written.windows(4).any(|w| w == b"Gr\xfc\xdf"),
        "comment kept in the 8-bit code page"
    );
    assert!(
        written.starts_with(b"&ACCESS RVP\nDEF kbu"),
        "module header"
    );

    // Names Windows reserves, and variables nobody declared.
    let (status, v) = t
        .post_json(
            "/api/v1/programs",
            &json!({"name": "con", "src": "DEF con()\nEND\n"}),
        )
        .await;
    assert_eq!(
        (status, v["code"].as_str()),
        (422, Some("invalid_input")),
        "{v}"
    );
    let (status, v) = t
        .post_json(
            "/api/v1/programs",
            &json!({"name": "dm3", "src": "DEF dm3()\n\n  PTP p1\nEND\n"}),
        )
        .await;
    assert_eq!(
        (status, v["code"].as_str(), v["line"].as_u64()),
        (422, Some("invalid_program"), Some(3)),
        "{v}"
    );
}

#[tokio::test]
async fn a_program_that_never_ends_is_refused_by_the_simulator_with_its_line() {
    let t = TestService::start(Options::default()).await;
    let src = "DEF cyc()\n  LOOP\n    PTP {A1 10}\n    PTP {A1 -10}\n  ENDLOOP\nEND\n";
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": "cyc", "src": src}))
        .await;
    assert_eq!(status, 201, "{v}");
    if t.service.krc.is_some() {
        // A KRC runs it until it is stopped, as the shipped KRL program does.
        let (status, job) = t
            .post_json("/api/v1/programs/cyc/run", &json!({"wait": false}))
            .await;
        assert_eq!(status, 202, "{job}");
        let id = job["id"].as_u64().expect("id");
        let krc = t.service.krc.clone().expect("krc");
        t.wait_job(id, "the program running", |j| j["state"] == "executing")
            .await;
        kuka_bridge_tests::wait_for(
            kuka_bridge_tests::WAIT,
            "two motions of the loop",
            async || {
                let n = krc.stats().motions_done;
                if n >= 4 {
                    Ok(())
                } else {
                    Err(format!("{n} motions"))
                }
            },
        )
        .await;
        let (status, v) = t.post("/api/v1/stop").await;
        assert_eq!(status, 200, "{v}");
        let j = t
            .wait_job(id, "the program cancelled", |j| j["state"] != "executing")
            .await;
        assert_eq!(j["state"], "cancelled", "{j}");
        return;
    }
    let (status, v) = t.post_json("/api/v1/programs/cyc/run", &json!({})).await;
    assert_eq!(
        (status, v["code"].as_str()),
        (409, Some("program_failed")),
        "{v}"
    );
    assert!(
        v["line"].as_u64().is_some_and(|l| (3..=4).contains(&l)),
        "{v}"
    );
}

#[tokio::test]
async fn stop_is_answered_while_a_long_program_is_being_dry_run() {
    let t = TestService::start(Options::default()).await;
    t.wait_online().await;
    // Never ends: the dry run goes to the interpreter's limit (seconds in a
    // debug build), on its own thread.
    let src = "DEF cyc2()\n  LOOP\n    PTP {A1 10}\n    PTP {A1 -10}\n  ENDLOOP\nEND\n";
    t.post_json("/api/v1/programs", &json!({"name": "cyc2", "src": src}))
        .await;
    let (status, job) = t
        .post_json("/api/v1/programs/cyc2/run", &json!({"wait": false}))
        .await;
    assert_eq!(status, 202, "{job}");
    let started = std::time::Instant::now();
    let (status, v) = t.post("/api/v1/stop").await;
    assert_eq!(status, 200, "{v}");
    assert!(
        started.elapsed() < std::time::Duration::from_millis(500),
        "STOP waited {:?}",
        started.elapsed()
    );
    let id = job["id"].as_u64().expect("id");
    let (_, j) = t.get(&format!("/api/v1/jobs/{id}")).await;
    assert_eq!(j["state"], "cancelled", "{j}");
    // The controller stays online and serves the next request.
    let (status, v) = t.post("/krl/getpos").await;
    assert_eq!(status, 200, "{v}");
}

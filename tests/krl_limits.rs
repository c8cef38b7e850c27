//! Issue 17 over HTTP: KRL programs that crashed the service with a stack
//! overflow (deep parentheses, deep blocks, long unary and operator
//! chains) are refused at upload — through `POST /api/v1/programs` and the
//! thesis's `POST /krl/uploadfile`, raw and as a form — with
//! `invalid_program`, the line and the limit's name, and the service keeps
//! answering. Programs within the upload limits but too deep to run are
//! refused by the dry run (or, without a robot model, by the simulated
//! controller) with their line; the service survives them too.

use kuka_bridge_tests::{Options, TestService};
use serde_json::{Value, json};

/// Wraps statements in a routine: the first statement is on line 3.
fn wrap(name: &str, body: &str) -> String {
    format!("DEF {name}()\n  DECL INT i\n{body}\nEND\n")
}

/// The crash inputs of issue 17: (what, src, line of the refusal, limit).
fn crash_inputs() -> Vec<(&'static str, String, u64, &'static str)> {
    let nest = |n: usize, open: &str, close: &str| {
        format!(
            "{}  i = 1\n{}",
            format!("{open}\n").repeat(n),
            format!("{close}\n").repeat(n)
        )
    };
    vec![
        (
            "parentheses nested 726 levels (1.6 KB)",
            wrap(
                "deep",
                &format!("  i = {}1{}", "(".repeat(726), ")".repeat(726)),
            ),
            3,
            "MAX_EXPR_DEPTH",
        ),
        (
            "1000 nested IF blocks",
            wrap("deep", &nest(1000, "IF TRUE THEN", "ENDIF")),
            3 + kuka_krl::MAX_BLOCK_DEPTH as u64,
            "MAX_BLOCK_DEPTH",
        ),
        (
            "1000 nested FOR blocks",
            wrap("deep", &nest(1000, "FOR i = 1 TO 2", "ENDFOR")),
            3 + kuka_krl::MAX_BLOCK_DEPTH as u64,
            "MAX_BLOCK_DEPTH",
        ),
        (
            "10,000 unary minus",
            wrap("deep", &format!("  i = {}1", "-".repeat(10_000))),
            3,
            "MAX_EXPR_DEPTH",
        ),
        (
            "10,000 NOT",
            wrap("deep", &format!("  i = {}TRUE", "NOT ".repeat(10_000))),
            3,
            "MAX_EXPR_DEPTH",
        ),
        (
            "a sum of 3000 terms (12 KB)",
            wrap("deep", &format!("  i = {}", vec!["1"; 3000].join(" + "))),
            3,
            "MAX_EXPR_DEPTH",
        ),
    ]
}

fn assert_refused(what: &str, status: u16, v: &Value, line: u64, limit: &str) {
    assert_eq!(status, 422, "{what}: {v}");
    assert_eq!(v["code"], "invalid_program", "{what}: {v}");
    assert_eq!(v["line"], line, "{what}: {v}");
    let detail = v["detail"].as_str().unwrap_or_default();
    assert!(
        detail.contains(limit) && detail.contains(&format!("line {line}")),
        "{what}: {v}"
    );
}

async fn post_form(t: &TestService, src: &str) -> (u16, Value) {
    let boundary = "kbLimitsBoundary";
    let body = format!(
        "--{boundary}\r\nContent-Disposition: form-data; name=\"file\"; filename=\"deep.src\"\r\nContent-Type: application/octet-stream\r\n\r\n{src}\r\n--{boundary}--\r\n"
    );
    t.post_form(boundary, body).await
}

async fn assert_alive(t: &TestService) {
    let (status, v) = t.get("/health").await;
    assert_eq!(status, 200, "{v}");
}

async fn uploads_are_refused(t: &TestService) {
    for (what, src, line, limit) in crash_inputs() {
        let (status, v) = t
            .post_json("/api/v1/programs", &json!({"name": "deep", "src": src}))
            .await;
        assert_refused(what, status, &v, line, limit);
        let (status, v) = t.post_text("/krl/uploadfile", src.clone()).await;
        assert_refused(what, status, &v, line, limit);
        let (status, v) = post_form(t, &src).await;
        assert_refused(what, status, &v, line, limit);
        assert_alive(t).await;
    }
    // Nothing was stored.
    let (status, v) = t.get("/api/v1/programs/deep").await;
    assert_eq!(status, 404, "{v}");
}

#[tokio::test]
async fn crash_inputs_are_refused_at_upload_and_the_service_keeps_answering() {
    let t = TestService::start(Options::default()).await;
    uploads_are_refused(&t).await;
}

#[tokio::test]
async fn crash_inputs_are_refused_without_a_simulator_too() {
    let t = TestService::start(Options {
        simulate: false,
        ..Options::default()
    })
    .await;
    uploads_are_refused(&t).await;
}

/// Blocks nested to the limit around a recursive call, and the deepest
/// expressions the parser allows: within the upload limits, too deep to
/// run (the interpreter stops at MAX_NESTING).
fn too_deep_to_run() -> String {
    let n = kuka_krl::MAX_BLOCK_DEPTH;
    let d = kuka_krl::MAX_EXPR_DEPTH - 1;
    let mut body = String::new();
    for k in 0..n {
        body.push_str(if k % 2 == 0 {
            "  FOR i = 1 TO 2\n"
        } else {
            "  IF TRUE THEN\n"
        });
    }
    body.push_str(&format!("  i = {}1{}\n", "(".repeat(d), ")".repeat(d)));
    body.push_str(&format!("  i = {}\n", vec!["1"; d].join(" + ")));
    body.push_str("  r()\n");
    for k in (0..n).rev() {
        body.push_str(if k % 2 == 0 {
            "  ENDFOR\n"
        } else {
            "  ENDIF\n"
        });
    }
    format!("DEF heavy()\n  r()\nEND\nDEF r()\n  DECL INT i\n{body}END\n")
}

async fn store(t: &TestService, name: &str, src: &str) {
    let (status, v) = t
        .post_json("/api/v1/programs", &json!({"name": name, "src": src}))
        .await;
    assert_eq!(status, 201, "{v}");
}

#[tokio::test]
async fn a_program_too_deep_to_run_is_refused_by_the_dry_run() {
    let t = TestService::start(Options::default()).await;
    store(&t, "heavy", &too_deep_to_run()).await;
    let (status, v) = t.post_json("/api/v1/programs/heavy/run", &json!({})).await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "invalid_program", "{v}");
    assert!(v["line"].as_u64().is_some_and(|l| l > 5), "{v}");
    assert!(
        v["detail"]
            .as_str()
            .is_some_and(|d| d.contains("MAX_NESTING")),
        "{v}"
    );
    assert_alive(&t).await;
    // The same through the thesis endpoint (upload and run in one).
    let (status, v) = t.post_text("/krl/uploadfile", too_deep_to_run()).await;
    assert_eq!(status, 422, "{v}");
    assert_eq!(v["code"], "invalid_program", "{v}");
    assert_alive(&t).await;
    // The service still runs programs.
    store(&t, "fine", "DEF fine()\n  PTP {A1 10}\nEND\n").await;
    let (status, v) = t.post_json("/api/v1/programs/fine/run", &json!({})).await;
    assert_eq!(status, 200, "{v}");
}

#[tokio::test]
async fn without_a_robot_model_the_simulated_controller_refuses_it() {
    // No model: no dry run; the simulated controller's program thread
    // interprets the module and answers with the line.
    let t = TestService::start(Options {
        tweak: Box::new(|c| c.robot.model = "none".into()),
        ..Options::default()
    })
    .await;
    store(&t, "heavy", &too_deep_to_run()).await;
    let (status, v) = t.post_json("/api/v1/programs/heavy/run", &json!({})).await;
    assert!((400..500).contains(&status), "{v}");
    assert!(v["line"].as_u64().is_some_and(|l| l > 5), "{v}");
    assert_alive(&t).await;
    let (status, v) = t.post("/krl/getpos").await;
    assert_eq!(status, 200, "{v}");
}

#[tokio::test]
async fn the_deepest_program_within_the_limits_is_accepted() {
    // Parsing, the name check and the subset check of the deepest program
    // the parser accepts run on the HTTP handler's thread (a tokio worker,
    // 2 MiB of stack).
    let openers = [
        ("IF i > 0 THEN", "ENDIF"),
        ("WHILE i < 0", "ENDWHILE"),
        ("FOR i = 1 TO 2", "ENDFOR"),
        ("LOOP", "ENDLOOP"),
        ("REPEAT", "UNTIL TRUE"),
        ("SWITCH i\nCASE 1", "ENDSWITCH"),
    ];
    let d = kuka_krl::MAX_EXPR_DEPTH - 1;
    let mut body = String::new();
    for k in 0..kuka_krl::MAX_BLOCK_DEPTH {
        body.push_str(openers[k % openers.len()].0);
        body.push('\n');
    }
    for inner in [
        format!("i = {}1{}", "(".repeat(d), ")".repeat(d)),
        format!("i = {}1", "-".repeat(d)),
        format!("i = {}1{}", "ABS(".repeat(d), ")".repeat(d)),
        format!("i = {}1{}", "a[".repeat(d), "]".repeat(d)),
        format!("i = {}", vec!["1"; d].join(" + ")),
        "EXIT".to_string(),
    ] {
        body.push_str(&inner);
        body.push('\n');
    }
    for k in (0..kuka_krl::MAX_BLOCK_DEPTH).rev() {
        body.push_str(openers[k % openers.len()].1);
        body.push('\n');
    }
    let src = format!("DEF deepest()\n  DECL INT i, a[2]\n  i = 0\n{body}END\n");
    let t = TestService::start(Options::default()).await;
    store(&t, "deepest", &src).await;
    // It runs too (i = 0: the first IF skips the rest).
    let (status, v) = t
        .post_json("/api/v1/programs/deepest/run", &json!({}))
        .await;
    assert_eq!(status, 200, "{v}");
}

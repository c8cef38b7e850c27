//! The interpreter's limits (issue 17): programs that parse but are too
//! deep or too heavy to run end with [`RunError::Limit`] or
//! [`RunError::TooLong`] naming the line and the limit, on a 2 MiB stack
//! in a debug build (the default stack of a spawned thread, such as the
//! service's dry run and the simulated controller's program thread) —
//! never with a stack overflow or an out-of-memory abort. Property tests
//! run random programs through the whole front end: parse, name check,
//! subset check and interpreter.
//!
//! The property tests run a modest number of cases so that `cargo test`
//! stays quick; run more with
//! `PROPTEST_CASES=5000 cargo test -p kuka-krl-runtime --test limits`.

use kuka_kinematics::{Pose, RobotModel};
use kuka_krl::{MAX_BLOCK_DEPTH, MAX_EXPR_DEPTH, Program};
use kuka_krl_runtime::interp::{
    MAX_CALL_DEPTH, MAX_NESTING, RunError, Start, Step, check_subset, run,
};
use kuka_krl_runtime::names::check_names;
use kuka_protocol::SpeedRecord;
use proptest::prelude::*;

const SPEED: SpeedRecord = SpeedRecord {
    override_pct: 100.0,
    ptp_velocity_pct: 40.0,
    ptp_acceleration_pct: 60.0,
    cp_velocity: 0.25,
    cp_acceleration_pct: 50.0,
};

/// The default stack of a spawned thread.
const STACK: usize = 2 * 1024 * 1024;

/// Parses `src` (entry `t`) and runs it on a thread with a 2 MiB stack.
fn run_small(src: String) -> Result<Vec<Step>, RunError> {
    std::thread::Builder::new()
        .stack_size(STACK)
        .spawn(move || {
            let program = match Program::parse(&src, None, Some("t")) {
                Ok(p) => p,
                Err(e) => panic!("{e}\n{src}"),
            };
            let model = RobotModel::kr3_r540();
            let start = Start {
                model: &model,
                axes: model.home,
                tool: Pose::IDENTITY,
                base: Pose::IDENTITY,
                speed: SPEED,
            };
            run(&program, "t", &start)
        })
        .expect("spawn")
        .join()
        .expect("no panic")
}

/// The limit error of a run, as (line, message).
fn limit(src: String) -> (u32, String) {
    match run_small(src) {
        Err(RunError::Limit { line, message }) => (line, message),
        other => panic!("expected a limit error, got {other:?}"),
    }
}

fn nest(n: usize, open: &str, close: &str, inner: &str) -> String {
    format!(
        "{}{inner}\n{}",
        format!("{open}\n").repeat(n),
        format!("{close}\n").repeat(n)
    )
}

/// A recursive routine `r` whose body nests `n` blocks around the call.
fn recursive_blocks(open: &str, close: &str) -> String {
    format!(
        "DEF t()\n  r()\nEND\nDEF r()\n  DECL INT i\n{}END\n",
        nest(MAX_BLOCK_DEPTH, open, close, "r()")
    )
}

#[test]
fn deep_recursion_through_blocks_ends_at_the_nesting_limit() {
    for (open, close) in [
        ("FOR i = 1 TO 2", "ENDFOR"),
        ("IF TRUE THEN", "ENDIF"),
        ("WHILE TRUE", "ENDWHILE"),
        ("LOOP", "ENDLOOP"),
        ("REPEAT", "UNTIL TRUE"),
        ("SWITCH 1\nCASE 1", "ENDSWITCH"),
    ] {
        let (line, msg) = limit(recursive_blocks(open, close));
        assert!(line > 5, "{open}: line {line}");
        assert!(
            msg.contains("MAX_NESTING") && msg.contains(&MAX_NESTING.to_string()),
            "{open}: {msg}"
        );
    }
}

#[test]
fn deep_recursion_through_expressions_ends_at_a_limit() {
    let d = MAX_EXPR_DEPTH - 1;
    let fct = |body: &str| {
        format!(
            "DEF t()\n  DECL INT i\n  i = f(1)\nEND\nDEFFCT INT f(n:IN)\n  DECL INT n\n{body}\nENDFCT\n"
        )
    };
    for body in [
        // The call at the bottom of the deepest chain, of a unary chain,
        // of nested arguments.
        format!("  RETURN f(1){}", " + 1".repeat(d - 1)),
        format!("  RETURN {}f(1)", "B_NOT ".repeat(d - 1)),
        format!("  RETURN {}1{}", "f(".repeat(d - 1), ")".repeat(d - 1)),
        // Calls in every place an expression is evaluated.
        "  DECL INT a[2]\n  a[f(1)] = 1\n  RETURN 1".to_string(),
        "  DECL INT i\n  FOR i = f(1) TO 2\n  ENDFOR\n  RETURN 1".to_string(),
        "  DECL INT i = f(1)\n  RETURN 1".to_string(),
        "  WAIT SEC f(1)\n  RETURN 1".to_string(),
        "  SWITCH f(1)\n  CASE 1\n  ENDSWITCH\n  RETURN 1".to_string(),
        "  WHILE f(1) > 0\n  ENDWHILE\n  RETURN 1".to_string(),
        "  IF f(1) > 0 THEN\n  ENDIF\n  RETURN 1".to_string(),
    ] {
        let (line, msg) = limit(fct(&body));
        assert!(line >= 5, "{body}: line {line}");
        assert!(
            msg.contains("MAX_NESTING") || msg.contains("MAX_CALL_DEPTH"),
            "{body}: {msg}"
        );
    }
}

#[test]
fn deep_recursion_through_motions_ends_at_the_call_limit() {
    let g = |stmt: &str| {
        format!("DEF t()\n  LIN g()\nEND\nDEFFCT E6POS g()\n{stmt}\n  RETURN $POS_ACT\nENDFCT\n")
    };
    for stmt in [
        "  LIN g()",
        "  PTP g()",
        "  CIRC g(), {X 1}",
        "  CIRC {X 1}, g()",
        "  SPLINE\n    SLIN g()\n  ENDSPLINE",
        "  SPLINE\n    SPL g()\n  ENDSPLINE",
        "  SPLINE\n    SCIRC g(), {X 1}\n  ENDSPLINE",
    ] {
        let (_, msg) = limit(g(stmt));
        assert!(
            msg.contains("MAX_CALL_DEPTH") || msg.contains("MAX_NESTING"),
            "{stmt}: {msg}"
        );
    }
}

#[test]
fn a_recursion_of_the_full_call_depth_runs() {
    // A plain recursive function reaches MAX_CALL_DEPTH within MAX_NESTING.
    let src = format!(
        "DEF t()\n  DECL INT i\n  i = f({})\nEND\nDEFFCT INT f(n:IN)\n  DECL INT n\n  IF n <= 1 THEN\n    RETURN 1\n  ENDIF\n  RETURN n + f(n - 1)\nENDFCT\n",
        MAX_CALL_DEPTH - 1
    );
    run_small(src).expect("runs");
}

#[test]
fn large_variables_end_at_the_value_limit() {
    let (line, msg) = limit("DEF t()\n  DECL E6POS p[1000000]\nEND\n".into());
    assert_eq!(line, 2);
    assert!(msg.contains("MAX_VALUE_CELLS"), "{msg}");
    // Local arrays of a recursion are counted while their frames live…
    let (_, msg) = limit("DEF t()\n  r()\nEND\nDEF r()\n  DECL INT a[200000]\n  r()\nEND\n".into());
    assert!(msg.contains("MAX_VALUE_CELLS"), "{msg}");
    // … and released with them.
    run_small(
        "DEF t()\n  DECL INT i\n  FOR i = 1 TO 100\n    r()\n  ENDFOR\nEND\nDEF r()\n  DECL INT a[100000]\nEND\n"
            .into(),
    )
    .expect("runs");
}

#[test]
fn heavy_expressions_end_at_the_evaluation_limit() {
    // Within the parser's limits, but each statement evaluates 4000 nodes:
    // the evaluation limit ends the loop long before the statement limit.
    let mut e = "i".to_string();
    for _ in 0..10 {
        e = format!("({e} + {e})");
    }
    let t0 = std::time::Instant::now();
    let r = run_small(format!(
        "DEF t()\n  DECL INT i\n  i = 0\n  LOOP\n    i = {e} - {e}\n  ENDLOOP\nEND\n"
    ));
    match r {
        Err(RunError::TooLong { message, line, .. }) => {
            assert!(message.contains("evaluations"), "{message}");
            assert!((4..=5).contains(&line), "{line}");
        }
        other => panic!("expected TooLong, got {other:?}"),
    }
    eprintln!("evaluation limit reached in {:?}", t0.elapsed());
}

#[test]
fn the_issue_17_sum_is_refused_before_it_runs() {
    // `i = 1 + 1 + …` with 3000 terms crashed the dry run; it no longer
    // parses. Within the limits the same shape runs.
    let terms = |n: usize| vec!["1"; n].join(" + ");
    let src = format!("DEF t()\n  DECL INT i\n  i = {}\nEND\n", terms(3000));
    let e = Program::parse(&src, None, None).expect_err("too deep");
    assert!(e.to_string().contains("MAX_EXPR_DEPTH"), "{e}");
    let src = format!(
        "DEF t()\n  DECL INT i\n  i = {}\nEND\n",
        terms(MAX_EXPR_DEPTH)
    );
    run_small(src).expect("runs");
}

// ---- property tests

fn config(default_cases: u32) -> ProptestConfig {
    let mut c = ProptestConfig::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = default_cases;
    }
    c.failure_persistence = None;
    c
}

/// Random expressions over the program's variables and functions.
fn expr() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        (-5i64..50).prop_map(|v| v.to_string()),
        Just("i".to_string()),
        Just("j".to_string()),
        Just("a[i]".to_string()),
        Just("p.X".to_string()),
        Just("TRUE".to_string()),
        Just("f(i)".to_string()),
        Just("g()".to_string()),
        Just("2.5".to_string()),
    ];
    leaf.prop_recursive(6, 64, 4, |inner| {
        prop_oneof![
            (
                inner.clone(),
                prop::sample::select(vec![
                    "+", "-", "*", "/", "==", "<>", "<", ">=", " AND ", " OR ", " B_AND "
                ]),
                inner.clone()
            )
                .prop_map(|(a, op, b)| format!("({a}{op}{b})")),
            (
                prop::sample::select(vec!["-", "NOT ", "B_NOT "]),
                inner.clone()
            )
                .prop_map(|(op, a)| format!("{op}{a}")),
            inner.clone().prop_map(|a| format!("f({a})")),
            inner.clone().prop_map(|a| format!("ABS({a})")),
            inner.prop_map(|a| format!("a[{a}]")),
        ]
    })
}

/// Random statements, blocks nested a few levels.
fn stmt() -> impl Strategy<Value = String> {
    let simple = prop_oneof![
        expr().prop_map(|e| format!("i = {e}")),
        expr().prop_map(|e| format!("a[2] = {e}")),
        expr().prop_map(|e| format!("p.X = {e}")),
        expr().prop_map(|e| format!("LIN {{X {e}, Y 0, Z 300}}")),
        expr().prop_map(|e| format!("PTP {{A1 {e}}}")),
        expr().prop_map(|e| format!("WAIT SEC {e}")),
        Just("h()".to_string()),
        Just("EXIT".to_string()),
        Just("RETURN".to_string()),
    ];
    simple.prop_recursive(4, 32, 4, |inner| {
        let body = prop::collection::vec(inner, 0..4).prop_map(|v| v.join("\n"));
        prop_oneof![
            (expr(), body.clone()).prop_map(|(c, b)| format!("IF {c} THEN\n{b}\nENDIF")),
            (expr(), body.clone()).prop_map(|(c, b)| format!("WHILE {c}\n{b}\nENDWHILE")),
            (expr(), body.clone()).prop_map(|(e, b)| format!("FOR j = 1 TO {e}\n{b}\nENDFOR")),
            body.clone().prop_map(|b| format!("LOOP\n{b}\nENDLOOP")),
            (body.clone(), expr()).prop_map(|(b, c)| format!("REPEAT\n{b}\nUNTIL {c}")),
            (expr(), body)
                .prop_map(|(s, b)| format!("SWITCH {s}\nCASE 1\n{b}\nDEFAULT\nENDSWITCH")),
        ]
    })
}

/// A module: an entry, a recursive function, a function and a procedure,
/// with random bodies.
fn program() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(stmt(), 0..6),
        prop::collection::vec(stmt(), 0..3),
        expr(),
        expr(),
    )
        .prop_map(|(main, h, fe, ge)| {
            format!(
                "DEF t()\n  DECL INT i, j, a[5]\n  DECL E6POS p\n  i = 1\n  j = 1\n  p = {{X 300, Y 0, Z 300, A 0, B 90, C 0}}\n{}\nEND\n\
                 DEFFCT INT f(n:IN)\n  DECL INT n, i, j, a[5]\n  DECL E6POS p\n  i = n\n  j = 1\n  IF n > 3 THEN\n    RETURN n\n  ENDIF\n  RETURN {fe}\nENDFCT\n\
                 DEFFCT INT g()\n  DECL INT i, j, a[5]\n  DECL E6POS p\n  i = 2\n  j = 1\n  RETURN {ge}\nENDFCT\n\
                 DEF h()\n  DECL INT i, j, a[5]\n  DECL E6POS p\n  i = 3\n  j = 1\n{}\nEND\n",
                main.join("\n"),
                h.join("\n")
            )
        })
}

proptest! {
    #![proptest_config(config(256))]

    /// Random programs go through the whole front end and the interpreter
    /// on a 2 MiB stack: a result or an error, never a panic or overflow.
    #[test]
    fn random_programs_run_or_fail_cleanly(src in program()) {
        let done = std::thread::Builder::new()
            .stack_size(STACK)
            .spawn(move || {
                let Ok(program) = Program::parse(&src, None, Some("t")) else {
                    return;
                };
                let _ = check_names(&program);
                let _ = check_subset(&program);
                let model = RobotModel::kr3_r540();
                let start = Start {
                    model: &model,
                    axes: model.home,
                    tool: Pose::IDENTITY,
                    base: Pose::IDENTITY,
                    speed: SPEED,
                };
                let _ = run(&program, "t", &start);
            })
            .expect("spawn")
            .join();
        prop_assert!(done.is_ok(), "the interpreter panicked");
    }
}

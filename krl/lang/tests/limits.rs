//! The front end's limits (`kuka_krl::limits`): the inputs that crashed
//! the service (issue 17: a stack overflow in the parser) are refused with
//! their line and the limit's name, the deepest program within the limits
//! parses on a 2 MiB stack (a debug build's tokio worker), and property
//! tests feed the lexer and parser random text and random programs.
//!
//! The property tests run a modest number of cases so that `cargo test`
//! stays quick; run more with
//! `PROPTEST_CASES=20000 cargo test -p kuka-krl --test limits`.

use kuka_krl::{
    MAX_BLOCK_DEPTH, MAX_EXPR_DEPTH, MAX_EXPR_NODES, Program, ProgramError, parse_dat, parse_src,
};
use proptest::prelude::*;

/// The stack of a tokio worker and of a spawned std thread.
const STACK: usize = 2 * 1024 * 1024;

/// Runs `f` on a thread with a 2 MiB stack (a stack overflow aborts the
/// whole test binary, which fails the test run).
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(STACK)
        .spawn(f)
        .expect("spawn")
        .join()
        .expect("no panic")
}

/// Parses on a 2 MiB stack; the refusal's line and message.
fn refusal(src: String) -> (u32, String) {
    on_small_stack(move || match Program::parse(&src, None, None) {
        Err(ProgramError::Src(e)) => (e.line, e.message),
        other => panic!("expected a syntax error, got {other:?}"),
    })
}

fn parses(src: String) {
    on_small_stack(move || {
        if let Err(e) = Program::parse(&src, None, None) {
            panic!("{e}");
        }
    });
}

fn wrap(body: &str) -> String {
    format!("DEF t()\n  DECL INT i\n{body}\nEND\n")
}

// ---- the crash inputs of issue 17, kept as regression cases

/// `i = ((((…1…))))` nested 726 levels (1.6 KB) overflowed the parser.
fn parens(n: usize) -> String {
    wrap(&format!("  i = {}1{}", "(".repeat(n), ")".repeat(n)))
}

/// `n` nested IF blocks.
fn nested_ifs(n: usize) -> String {
    let mut s = String::new();
    for _ in 0..n {
        s.push_str("IF TRUE THEN\n");
    }
    s.push_str("i = 1\n");
    for _ in 0..n {
        s.push_str("ENDIF\n");
    }
    wrap(&s)
}

/// `n` nested FOR blocks.
fn nested_fors(n: usize) -> String {
    let mut s = String::new();
    for _ in 0..n {
        s.push_str("FOR i = 1 TO 2\n");
    }
    for _ in 0..n {
        s.push_str("ENDFOR\n");
    }
    wrap(&s)
}

#[test]
fn deep_parentheses_are_refused_with_line_and_limit() {
    for n in [MAX_EXPR_DEPTH, 726, 100_000] {
        let (line, msg) = refusal(parens(n));
        assert_eq!(line, 3, "{msg}");
        assert!(
            msg.contains("MAX_EXPR_DEPTH") && msg.contains(&MAX_EXPR_DEPTH.to_string()),
            "{msg}"
        );
    }
    parses(parens(MAX_EXPR_DEPTH - 1));
}

#[test]
fn deep_blocks_are_refused_with_line_and_limit() {
    for src in [nested_ifs(1000), nested_fors(1000), nested_ifs(100_000)] {
        let (line, msg) = refusal(src);
        // The first block beyond the limit: DEF is line 1, DECL line 2.
        assert_eq!(line, 3 + MAX_BLOCK_DEPTH as u32, "{msg}");
        assert!(msg.contains("MAX_BLOCK_DEPTH"), "{msg}");
    }
    parses(nested_ifs(MAX_BLOCK_DEPTH));
    parses(nested_fors(MAX_BLOCK_DEPTH));
    refusal(nested_ifs(MAX_BLOCK_DEPTH + 1));
}

#[test]
fn long_unary_chains_are_refused() {
    for op in ["-", "NOT ", "B_NOT ", "+"] {
        let (line, msg) = refusal(wrap(&format!("  i = {}1", op.repeat(10_000))));
        assert_eq!(line, 3, "{op}: {msg}");
        assert!(msg.contains("MAX_EXPR_DEPTH"), "{op}: {msg}");
    }
}

#[test]
fn long_operator_chains_are_refused() {
    // `i = 1 + 1 + …` with 3000 terms (12 KB) was accepted and crashed the
    // interpreter: the tree nests one level per `+`.
    for op in ["+", "*", " AND ", " OR ", ":", "=="] {
        let terms = vec!["1"; 3000].join(op);
        let (line, msg) = refusal(wrap(&format!("  i = {terms}")));
        assert_eq!(line, 3, "{op}: {msg}");
        assert!(msg.contains("MAX_EXPR_DEPTH"), "{op}: {msg}");
    }
    // Postfix chains nest too.
    let (_, msg) = refusal(wrap(&format!("  i = a{}", "[1]".repeat(3000))));
    assert!(msg.contains("MAX_EXPR_DEPTH"), "{msg}");
    let (_, msg) = refusal(wrap(&format!("  i = a{}", ".b".repeat(3000))));
    assert!(msg.contains("MAX_EXPR_DEPTH"), "{msg}");
    // Within the depth a chain is fine.
    let terms = vec!["1"; MAX_EXPR_DEPTH].join(" + ");
    parses(wrap(&format!("  i = {terms}")));
}

#[test]
fn huge_expressions_are_refused() {
    // Flat but large: a call with many arguments, a wide balanced tree.
    let args = vec!["1"; MAX_EXPR_NODES + 1].join(", ");
    let (line, msg) = refusal(wrap(&format!("  f({args})")));
    assert_eq!(line, 3, "{msg}");
    assert!(msg.contains("MAX_EXPR_NODES"), "{msg}");
    let mut e = "1".to_string();
    for _ in 0..13 {
        e = format!("({e} + {e})");
    }
    let (_, msg) = refusal(wrap(&format!("  i = {e}")));
    assert!(msg.contains("MAX_EXPR_NODES"), "{msg}");
    // Many statements and spline points of normal size are fine.
    let stmt = format!("  i = {}\n", vec!["1"; 30].join(" + "));
    parses(wrap(&stmt.repeat(1000)));
    let pts = "  SPL {X 1, Y 2, Z 3, A 0, B 0, C 0}\n".repeat(2000);
    parses(wrap(&format!("SPLINE\n{pts}ENDSPLINE")));
}

#[test]
fn the_dat_file_has_the_same_limits() {
    let dat = format!(
        "DEFDAT t\nDECL INT i = {}1{}\nENDDAT\n",
        "(".repeat(500),
        ")".repeat(500)
    );
    let e = on_small_stack(move || parse_dat(&dat)).expect_err("too deep");
    assert_eq!(e.line, 2);
    assert!(e.message.contains("MAX_EXPR_DEPTH"), "{}", e.message);
}

/// The most stack-hungry program within the limits: blocks nested to the
/// limit, each kind of block, and at the innermost level every kind of
/// expression nesting up to the limit.
fn deepest_within_limits() -> String {
    let openers = [
        ("IF i > 0 THEN", "ENDIF"),
        ("WHILE i < 0", "ENDWHILE"),
        ("FOR i = 1 TO 2", "ENDFOR"),
        ("LOOP", "ENDLOOP"),
        ("REPEAT", "UNTIL TRUE"),
        ("SWITCH i\nCASE 1", "ENDSWITCH"),
    ];
    let d = MAX_EXPR_DEPTH - 1;
    let mut s = String::new();
    for k in 0..MAX_BLOCK_DEPTH {
        s.push_str(openers[k % openers.len()].0);
        s.push('\n');
    }
    for inner in [
        format!("i = {}1{}", "(".repeat(d), ")".repeat(d)),
        format!("i = {}1", "-".repeat(d)),
        format!("i = {}1{}", "f(".repeat(d), ")".repeat(d)),
        format!("i = {}1{}", "a[".repeat(d), "]".repeat(d)),
        format!("i = {}1{}", "{X ".repeat(d), "}".repeat(d)),
        format!("i = {}", vec!["1"; d].join(" + ")),
    ] {
        s.push_str(&inner);
        s.push('\n');
    }
    for k in (0..MAX_BLOCK_DEPTH).rev() {
        s.push_str(openers[k % openers.len()].1);
        s.push('\n');
    }
    wrap(&s)
}

#[test]
fn the_deepest_program_within_the_limits_parses_on_a_small_stack() {
    parses(deepest_within_limits());
}

// ---- property tests

/// Fewer cases by default (each test a few seconds in a debug build);
/// `PROPTEST_CASES` raises it.
fn config(default_cases: u32) -> ProptestConfig {
    let mut c = ProptestConfig::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = default_cases;
    }
    c.failure_persistence = None;
    c
}

/// KRL-ish tokens, so that random text gets past the lexer and deep into
/// the parser.
fn token() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "DEF ",
        "END",
        "DEFFCT INT ",
        "ENDFCT",
        "DEFDAT ",
        "ENDDAT",
        "t",
        "f",
        "(",
        ")",
        "[",
        "]",
        "{",
        "}",
        ",",
        ".",
        ":",
        "=",
        "==",
        "<>",
        "+",
        "-",
        "*",
        "/",
        " AND ",
        " OR ",
        " NOT ",
        " B_NOT ",
        "IF ",
        " THEN",
        "ELSE",
        "ENDIF",
        "WHILE ",
        "ENDWHILE",
        "FOR ",
        " TO ",
        " STEP ",
        "ENDFOR",
        "LOOP",
        "ENDLOOP",
        "REPEAT",
        "UNTIL ",
        "SWITCH ",
        "CASE ",
        "DEFAULT",
        "ENDSWITCH",
        "RETURN ",
        "PTP ",
        "LIN ",
        "CIRC ",
        "SPLINE",
        "SPL ",
        "ENDSPLINE",
        "DECL ",
        "INT ",
        "E6POS ",
        "X ",
        "1",
        "2.5",
        "1E3",
        "'B101'",
        "#BASE",
        "\"s\"",
        "$VEL",
        " ",
        "\n",
        ";c\n",
        "&ACCESS\n",
        "GLOBAL ",
        "INTERRUPT DECL 3 WHEN ",
        " DO ",
        "TRIGGER WHEN ",
        "WAIT SEC ",
        "WAIT FOR ",
        "C_DIS",
        "EXIT",
        "i",
    ])
}

proptest! {
    #![proptest_config(config(512))]

    /// Any text: the front end answers (a tree or a refusal with a line in
    /// the text), never panics or overflows.
    #[test]
    fn any_text_is_parsed_or_refused(text in "\\PC{0,400}") {
        for r in [parse_src(&text).err(), parse_dat(&text).err()].into_iter().flatten() {
            prop_assert!(r.line >= 1 && r.line as usize <= text.lines().count() + 1);
        }
    }

    /// Token soups: deep nesting of every kind.
    #[test]
    fn token_soups_are_parsed_or_refused(toks in prop::collection::vec(token(), 0..600)) {
        let text = toks.concat();
        let _ = Program::parse(&text, None, None);
        let _ = Program::parse(&format!("DEF t()\n{text}\nEND\n"), None, None);
        let _ = parse_dat(&format!("DEFDAT t\n{text}\nENDDAT\n"));
    }

    /// Opening tokens repeated far beyond the limits (the crash shapes of
    /// issue 17, in random mixes): answered on a 2 MiB stack. A single
    /// kind repeated 100 times or more is always refused.
    #[test]
    fn deep_repetitions_are_refused(
        open in prop::collection::vec(
            prop::sample::select(vec!["(", "-", "NOT ", "a[", "f(", "{X ", "1+", "a.", "1:"]),
            1..8,
        ),
        n in 100usize..3000,
    ) {
        let mut e = String::new();
        for k in 0..n {
            e.push_str(open[k % open.len()]);
        }
        let src = wrap(&format!("  i = {e}1"));
        let r = on_small_stack(move || Program::parse(&src, None, None));
        if open.iter().all(|o| *o == open[0]) {
            prop_assert!(r.is_err());
        }
    }
}

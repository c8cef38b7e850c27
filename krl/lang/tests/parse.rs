//! Parser tests: real KRL shapes parse into the expected tree, and
//! mistakes are refused with the right line.

use kuka_krl::{
    Expr, MotionKind, Program, ProgramError, SplinePointKind, StmtKind, parse_dat, parse_src,
};

const THESIS_UPLOAD: &str = "DEFFCT INT fuploaded()
    SPLINE
    SPL {X 200, Y 0, Z 200, A 0, B 90, C 0}
    SPL {X 200, Y -50, Z 150, A 0, B 90, C 0}
    SPL {X 200, Y 50, Z 100, A 0, B 90, C 0}
    ENDSPLINE
    RETURN 1
ENDFCT
";

#[test]
fn the_thesis_upload_example_parses() {
    let p = Program::parse(THESIS_UPLOAD, None, Some("fuploaded")).expect("parses");
    let r = &p.src.routines[0];
    assert_eq!(r.name, "fuploaded");
    assert_eq!(r.body.len(), 2);
    let StmtKind::Spline { points, .. } = &r.body[0].kind else {
        panic!("spline")
    };
    assert_eq!(points.len(), 3);
    assert_eq!(points[1].kind, SplinePointKind::Spl);
    assert_eq!(points[1].line, 4);
    let Expr::Struct { fields, .. } = &points[1].target else {
        panic!("struct")
    };
    assert_eq!(fields[1], ("Y".to_string(), Expr::Int(-50)));
    assert_eq!(r.body[1].kind, StmtKind::Return(Some(Expr::Int(1))));
}

const BIG: &str = r#"&ACCESS RVP
&REL 1
DEF draw(  )
;FOLD INI
  BAS (#INITMOV,0 )
;ENDFOLD (INI)
DECL E6POS p
DECL INT i, n[4]
REAL r
DECL GLOBAL CONST INT kMax = 3
INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )
INTERRUPT ON 3
$ADVANCE = 3
$VEL.CP = 0.2
$APO.CDIS = 2.0
$TOOL = {X 0, Y 0, Z 100, A 0, B 0, C 0}
p = $POS_ACT
p.Z = p.Z - 50
PTP {A1 0, A2 -90, A3 90, A4 0, A5 0, A6 0}
PTP p C_PTP
LIN {X 300, Y 0, Z 100, A 0, B 180, C 0} C_DIS
CIRC {X 320, Y 20, Z 100}, {X 300, Y 40, Z 100}, CA 180 C_DIS
LIN_REL {Z 10} C_DIS #TOOL
FOR i = 1 TO 10 STEP 2
  IF (i > 3) AND NOT (i == 7) THEN
    r = r + i * 1.5E1
  ELSE
    WAIT SEC 0.1
  ENDIF
ENDFOR
WHILE $IN[1] == FALSE
  WAIT FOR $IN[2]
ENDWHILE
SWITCH i
CASE 1, 2
  n[1] = 'B0101'
DEFAULT
  n[2] = 'H1F' B_AND 3
ENDSWITCH
REPEAT
  i = i - 1
UNTIL i <= 0
LOOP
  EXIT
ENDLOOP
TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[1]=TRUE PRIO=-1
ON_ERROR_PROCEED
CWRITE($FCT_CALL, st, mode, "krl_fopen", name[], "r", handle)
p = $NULLFRAME : p
SPLINE WITH $VEL = {CP 0.1}
  SLIN {X 310} WITH $VEL = {CP 0.05}
  SCIRC {X 320, Y 10}, {X 330, Y 0}
  SPL {X 340} C_SPL
ENDSPLINE
BRAKE F
RESUME
END

DEFFCT INT helper(a:IN, b:OUT)
  DECL INT a, b
  b = a * 2
  RETURN b
ENDFCT
"#;

#[test]
fn a_program_with_most_of_krl_parses() {
    let f = parse_src(BIG).expect("parses");
    assert_eq!(f.routines.len(), 2);
    assert!(f.routines[1].params[1].out);
    let body = &f.routines[0].body;
    let motions: Vec<_> = body
        .iter()
        .filter_map(|s| match &s.kind {
            StmtKind::Motion { kind, approx, .. } => Some((*kind, approx.clone(), s.line)),
            _ => None,
        })
        .collect();
    assert_eq!(motions.len(), 5);
    assert_eq!(motions[3], (MotionKind::Circ, Some("C_DIS".into()), 22));
    assert_eq!(motions[4].0, MotionKind::LinRel);
}

#[test]
fn dat_files_parse() {
    let d = parse_dat(
        "&ACCESS RVP\nDEFDAT draw PUBLIC\nDECL E6POS XP1={X 1.0,Y 2,Z 3,A 0,B 0,C 0,S 2,T 35,E1 0.0}\nDECL FDAT FP1={TOOL_NO 1,BASE_NO 0,IPO_FRAME #BASE,POINT2[] \" \"}\nDECL INT counts[3]\ncounts[1]=5\nENDDAT\n",
    )
    .expect("parses");
    assert_eq!(d.name, "draw");
    assert!(d.public);
    assert_eq!(d.items.len(), 4);
}

fn src_error(text: &str) -> (u32, String) {
    match parse_src(text) {
        Err(e) => (e.line, e.message),
        Ok(_) => panic!("should not parse:\n{text}"),
    }
}

#[test]
fn mistakes_are_refused_with_their_line() {
    let (line, msg) = src_error("DEF a()\n  IF x THEN\n    y = 1\nEND\n");
    assert_eq!(line, 4, "{msg}");
    assert!(msg.contains("IF on line 2"), "{msg}");
    let (line, msg) = src_error("DEF a()\n  x = \nEND\n");
    assert_eq!(line, 2, "{msg}");
    let (line, msg) = src_error("DEF a()\n  PTP {X 1, Y}\nEND\n");
    assert_eq!(line, 2, "{msg}");
    let (line, msg) = src_error("DEF a()\n\n  SPL {X 1}\nEND\n");
    assert_eq!(line, 3, "{msg}");
    assert!(msg.contains("SPLINE"), "{msg}");
    let (line, msg) = src_error("DEF a()\n  DECL INT this_name_is_longer_than_24\nEND\n");
    assert_eq!(line, 2);
    assert!(msg.contains("24"), "{msg}");
    let (line, _) = src_error("DEF a()\n  x = 1\n");
    assert_eq!(line, 3);
    let (line, msg) = src_error("DEF a()\n  foo\nEND\n");
    assert_eq!(line, 2);
    assert!(msg.contains("parentheses"), "{msg}");
    let (line, msg) = src_error("DEF a()\nENDIF\nEND\n");
    assert_eq!(line, 2);
    assert!(msg.contains("ENDIF"), "{msg}");
    let (line, _) = src_error("x = 1\n");
    assert_eq!(line, 1);
    let (line, _) = src_error("DEF a()\n  GOTO lbl\nEND\n");
    assert_eq!(line, 2);
}

#[test]
fn program_checks_name_the_problem() {
    assert!(matches!(
        Program::parse(THESIS_UPLOAD, None, Some("main")),
        Err(ProgramError::NoEntry { .. })
    ));
    let e = Program::parse("DEF a(x:IN)\nEND\n", None, None).expect_err("params");
    assert_eq!(e.line(), Some(1));
    let e = Program::parse("DEF a()\nEND\nDEF A()\nEND\n", None, None).expect_err("dup");
    assert_eq!(e.line(), Some(3));
    let e =
        Program::parse("DEF a()\nEND\n", Some("DEFDAT b\nENDDAT\n"), None).expect_err("dat name");
    assert!(matches!(e, ProgramError::DatName { .. }));
    let e = Program::parse(
        "DEF a()\nEND\n",
        Some("DEFDAT a\nPTP {X 1}\nENDDAT\n"),
        None,
    )
    .expect_err("dat stmt");
    assert_eq!(e.line(), Some(2));
}

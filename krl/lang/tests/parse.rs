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
DECL E6POS p
DECL INT i, n[4]
REAL r
DECL GLOBAL CONST INT kMax = 3
;FOLD INI
  BAS (#INITMOV,0 )
;ENDFOLD (INI)
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
    let (line, _) = src_error("DEF a()\n  GOTO\nEND\n");
    assert_eq!(line, 2);
    // What a KRC refuses although it reads like KRL.
    let (line, msg) = src_error("DEF a()\n  DECL INT i\n  i = 1\n  DECL REAL r\nEND\n");
    assert_eq!(line, 4, "{msg}");
    assert!(msg.contains("first statement (line 3)"), "{msg}");
    let (line, msg) = src_error("DEF a()\n  IF TRUE THEN\n    DECL INT i\n  ENDIF\nEND\n");
    assert_eq!(line, 3, "{msg}");
    let (line, msg) = src_error("DEF a(this_parameter_name_is_too_long[]:OUT)\nEND\n");
    assert_eq!(line, 1, "{msg}");
    assert!(msg.contains("24"), "{msg}");
    let (line, msg) = src_error("DEF a()\n  SPTP XHOME C_VEL\nEND\n");
    assert_eq!(line, 2, "{msg}");
    let (line, _) = src_error("DEF a()\n  SCIRC {X 1}\nEND\n");
    assert_eq!(line, 2);
}

/// The KSS 8.x constructs real programs use that the first front end
/// refused (issue 20): each as written in public KUKA code.
#[test]
fn real_kss8_constructs_parse() {
    let src = r#"DEF demo( )
DECL INT i, answer
DECL CHAR msg[128]
DECL REAL grid[3,4]
EXT MsgNotify(CHAR[]:IN, INT:IN, INT:IN)
;FOLD SPTP HOME Vel=100 % DEFAULT ;%{PE}
SPTP XHOME WITH $VEL_AXIS[1] = SVEL_JOINT(100.0), $TOOL = STOOL2(FHOME), $BASE = SBASE(FHOME.BASE_NO), $APO = SAPO_PTP(PDEFAULT)
;ENDFOLD
SLIN XP1 WITH $VEL = SVEL_CP(2.0, , LCPDAT1), $ORI_TYPE = SORI_TYP(LCPDAT1) C_SPL
SCIRC XP2, XP3, CA 90.0 C_SPL
SLIN_REL {Z 10} C_SPL #TOOL
SPTP {A1 0}
answer = MsgNotify(msg[], , 26)
grid[1,] = grid[2,]
GOTO done
i = 1
done:
ANOUT ON A1 = 0.5 * $VEL_ACT DELAY = -0.2
ANOUT OFF A1
SPLINE
  SPL XP1
  TRIGGER WHEN PATH = -20 ONSTART DELAY = 0 DO $OUT[1] = TRUE
  SLIN XP2
ENDSPLINE
END

DEF sub(t[]:OUT, m[,]:IN)
  DECL INT t[]
END

DEFFCT CHAR[128] name_of(x:IN)
  DECL INT x
  RETURN "x"
ENDFCT
"#;
    let f = parse_src(src).expect("parses");
    let body = &f.routines[0].body;
    let kinds: Vec<&StmtKind> = body.iter().map(|s| &s.kind).collect();
    let single: Vec<(SplinePointKind, bool, usize)> = kinds
        .iter()
        .filter_map(|k| match k {
            StmtKind::SplineMotion { point, rel, .. } => Some((point.kind, *rel, point.with.len())),
            _ => None,
        })
        .collect();
    assert_eq!(
        single,
        [
            (SplinePointKind::Sptp, false, 4),
            (SplinePointKind::Slin, false, 2),
            (SplinePointKind::Scirc, false, 0),
            (SplinePointKind::Slin, true, 0),
            (SplinePointKind::Sptp, false, 0),
        ]
    );
    assert!(body.iter().any(|s| s.kind == StmtKind::Goto("done".into())));
    assert!(
        body.iter()
            .any(|s| s.kind == StmtKind::Label("done".into()) && s.line == 17)
    );
    let call = body
        .iter()
        .find_map(|s| match &s.kind {
            StmtKind::Assign {
                value: Expr::Call(n, args),
                ..
            } if n == "MsgNotify" => Some(args.clone()),
            _ => None,
        })
        .expect("the call");
    assert_eq!(call[1], Expr::Omitted);
    assert!(body.iter().any(|s| matches!(&s.kind,
        StmtKind::Assign { target: Expr::Index(_, idx), .. } if idx.len() == 2 && idx[1] == Expr::Omitted)));
    assert!(body.iter().any(
        |s| matches!(&s.kind, StmtKind::Spline { triggers, points, .. } if triggers.len() == 1 && points.len() == 2)
    ));
    let sub = &f.routines[1];
    assert_eq!((sub.params[0].array_dims, sub.params[0].out), (1, true));
    assert_eq!(sub.params[1].array_dims, 2);
    assert_eq!(
        f.routines[2].kind,
        kuka_krl::RoutineKind::DefFct("CHAR[]".into())
    );
}

/// `.dat` globals as KUKA's own files write them: without `DECL`.
#[test]
fn dat_globals_without_decl_parse() {
    let d = parse_dat(
        "DEFDAT  $CUSTOM PUBLIC
GLOBAL INT counter=0
GLOBAL CONST REAL k=1.5
DECL CONST GLOBAL INT m=2
GLOBAL SIGNAL gripper $OUT[3]
GLOBAL E6POS xp={X 1}
CHANNEL :SER_3 SER_3 3
GLOBAL STRUC pair INT a, b
ENDDAT
",
    )
    .expect("parses");
    let globals = d
        .items
        .iter()
        .filter(|s| matches!(s.kind, StmtKind::Decl { global: true, .. }))
        .count();
    assert_eq!(globals, 4);
    assert!(d.items.iter().any(|s| s.kind
        == StmtKind::Channel {
            name: "SER_3".into()
        }));
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

/// Constructs found in the public corpus (tests/corpus): `CONFIRM`, a
/// parameter's array type with omitted sizes in its declaration, and a
/// STRUC whose members of a new type follow without a comma.
#[test]
fn corpus_constructs_parse() {
    let src = r#"DEF matrix(t[,]:OUT)
  REAL t[,]
  STRUC PAIR INT a, b REAL c
  CONFIRM 0
  t[1,1] = 0
END
"#;
    let f = parse_src(src).expect("parses");
    let body = &f.routines[0].body;
    assert!(body.iter().any(|s| matches!(&s.kind,
        StmtKind::Decl { vars, .. } if vars[0].dims == [Expr::Omitted, Expr::Omitted])));
    assert!(body.iter().any(|s| matches!(&s.kind,
        StmtKind::Struc { fields, .. } if fields.len() == 3 && fields[2].0 == "REAL")));
    assert!(
        body.iter()
            .any(|s| s.kind == StmtKind::Confirm(Expr::Int(0)))
    );
    // A comma alone still needs a member after it.
    assert!(parse_src("DEF a()\nSTRUC P INT x,\nEND\n").is_err());
}

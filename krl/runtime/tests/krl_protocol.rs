//! The file protocol pinned from both directions by **executing the shipped
//! KRL controller program** (`krl/KRC/R1/Program/kbridge`) with the
//! simulator's KRL interpreter in its test harness
//! ([`kuka_krl_runtime::interp::run_with_files`], in-memory files):
//!
//! - service → KRL: every line the Rust encoder writes into a command file
//!   is parsed by the program's own line parser `KbLine` with the format
//!   (tag, field count, REAL mask) that `kb_submit.src` passes for that
//!   record, and the values must be the Rust field values; corrupted and
//!   truncated lines must be refused. Then whole command files go through
//!   the Submit side's own cycle (`kb_submit_init`, `kb_submit_cycle`:
//!   `KsPoll` → `KsNewCmd` → `KsBody` → `KsStoreMot` → motion buffer / job
//!   mailbox / answers).
//! - KRL → service: the result and state files the program writes
//!   (`KsHistPush` + `KsWriteRes`, `KsWriteState`) must decode with
//!   `ResultFile::decode` / `StateFile::decode` to exactly the records put
//!   in, byte for byte as the Rust encoder writes them.
//!
//! Nothing of the KRL is copied here: the program is read from disk and
//! only small driver routines (and the driver's result variables) are
//! added to it. The KRL modules are combined into one program: the routines
//! of `kb_submit.src` and `kb_io.src`, and one data list of `kb_main.dat` and
//! `kb_io.dat`.
//!
//! Limits of the harness: KRL REALs are 32-bit floats on a KRC, the
//! interpreter computes in 64 bits, so the exactness of `KbMilli` in 32-bit
//! arithmetic is not tested here (PROTOCOL.md 12 reports an exhaustive test
//! of it); `krl_fgets`/`krl_fwriteln` behave as the harness documents
//! (unconfirmed on a KRC).

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::sync::OnceLock;

use kuka_kinematics::{Pose, RobotModel};
use kuka_krl::{DatFile, Expr, Program, SrcFile, Stmt, StmtKind, parse_dat, parse_src};
use kuka_krl_runtime::interp::{Globals, Start, run_with_files};
use kuka_protocol::{
    AnalogOutputRecord, AnalogState, COMMAND_FILE, Command, CommandFile, ControllerStatus, Frame,
    IoState, MotionParams, MotionRecord, OperatingMode, OutputRecord, PathChunk, RESULT_FILE,
    ResultCode, ResultFile, ResultRecord, STATE_FILE, SafetyState, SpeedRecord, StateFile,
    checksum,
};

// ---------------------------------------------------------------- the program

fn krl_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../KRC/R1/Program/kbridge")
}

fn read_krl(name: &str) -> String {
    let path = krl_dir().join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn parse_src_file(name: &str) -> SrcFile {
    parse_src(&read_krl(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn parse_dat_file(name: &str) -> DatFile {
    parse_dat(&read_krl(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// `kb_submit.src` as parsed (the KRL-side format description).
fn submit_src() -> &'static SrcFile {
    static SRC: OnceLock<SrcFile> = OnceLock::new();
    SRC.get_or_init(|| parse_src_file("kb_submit.src"))
}

/// The Submit side as one program: the routines of kb_submit.src and
/// kb_io.src, one data list from kb_main.dat and kb_io.dat.
fn controller() -> &'static Program {
    static PROGRAM: OnceLock<Program> = OnceLock::new();
    PROGRAM.get_or_init(|| {
        let mut routines = submit_src().routines.clone();
        routines.extend(parse_src_file("kb_io.src").routines);
        let mut items = parse_dat_file("kb_main.dat").items;
        items.extend(parse_dat_file("kb_io.dat").items);
        Program {
            src: SrcFile { routines },
            dat: Some(DatFile {
                name: "kb_submit".into(),
                public: true,
                items,
                line: 1,
            }),
        }
    })
}

/// Runs the driver routine `t_main` (KRL text, may define more routines)
/// with the extra data declarations `dat` on the in-memory `files`. Every
/// run must close every file it opened.
fn run_driver(driver: &str, dat: &str, files: &mut BTreeMap<String, String>) -> Globals {
    let mut program = controller().clone();
    let drv = parse_src(driver).unwrap_or_else(|e| panic!("driver: {e}\n{driver}"));
    program.src.routines.extend(drv.routines);
    let extra = parse_dat(&format!("DEFDAT t_drv\n{dat}\nENDDAT\n"))
        .unwrap_or_else(|e| panic!("driver data: {e}\n{dat}"));
    if let Some(d) = program.dat.as_mut() {
        d.items.extend(extra.items);
    }
    let model = RobotModel::kr3_r540();
    let start = Start {
        model: &model,
        axes: model.home,
        tool: Pose::IDENTITY,
        base: Pose::IDENTITY,
        speed: SpeedRecord {
            override_pct: 100.0,
            ptp_velocity_pct: 20.0,
            ptp_acceleration_pct: 100.0,
            cp_velocity: 0.25,
            cp_acceleration_pct: 100.0,
        },
    };
    let g = match run_with_files(&program, "t_main", &start, files) {
        Ok(g) => g,
        Err(e) => panic!("the KRL program failed: {e}\ndriver:\n{driver}"),
    };
    assert!(
        g.open_files().is_empty(),
        "the KRL program left files open: {:?}",
        g.open_files()
    );
    g
}

/// A REAL literal for a driver routine.
fn krl_real(v: f64) -> String {
    format!("{v:.3}")
}

fn krl_frame(f: &Frame) -> String {
    format!(
        "{{X {}, Y {}, Z {}, A {}, B {}, C {}}}",
        krl_real(f.x),
        krl_real(f.y),
        krl_real(f.z),
        krl_real(f.a),
        krl_real(f.b),
        krl_real(f.c)
    )
}

fn krl_axes(a: &[f64; 6]) -> String {
    format!(
        "{{A1 {}, A2 {}, A3 {}, A4 {}, A5 {}, A6 {}}}",
        krl_real(a[0]),
        krl_real(a[1]),
        krl_real(a[2]),
        krl_real(a[3]),
        krl_real(a[4]),
        krl_real(a[5])
    )
}

/// A REAL as the thousandths it travels as.
fn milli(v: f64) -> i64 {
    (v * 1000.0).round() as i64
}

/// The value the KRL side gets back from thousandths (`KsR`).
fn from_milli(v: f64) -> f64 {
    milli(v) as f64 / 1000.0
}

// ---------------------------------------------------------------- formats

/// How `KbLine` is told to parse a record: field count and REAL mask
/// (bit f-1 set = field f is a REAL).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Format {
    nf: usize,
    rmask: u32,
}

/// One field value as the Rust side holds it.
#[derive(Debug, Clone, Copy)]
enum Val {
    I(i64),
    R(f64),
}

impl Val {
    fn wire(self) -> i64 {
        match self {
            Val::I(v) => v,
            Val::R(r) => milli(r),
        }
    }
}

fn shape(vals: &[Val]) -> Format {
    let rmask = vals
        .iter()
        .enumerate()
        .filter(|(_, v)| matches!(v, Val::R(_)))
        .fold(0, |m, (i, _)| m | (1 << i));
    Format {
        nf: vals.len(),
        rmask,
    }
}

/// Every `KbLine(c1, c2, c3, nf, rmask)` call in the routines, by tag:
/// the KRL side's description of the records it reads.
fn krl_formats(src: &SrcFile) -> BTreeMap<String, BTreeSet<Format>> {
    fn expr(e: &Expr, out: &mut BTreeMap<String, BTreeSet<Format>>) {
        match e {
            Expr::Call(name, args) if name.eq_ignore_ascii_case("KbLine") => {
                let ints: Vec<i64> = args
                    .iter()
                    .map(|a| match a {
                        Expr::Int(i) => *i,
                        other => panic!("KbLine with a non-constant argument {other:?}"),
                    })
                    .collect();
                let [c1, c2, c3, nf, rmask] = ints[..] else {
                    panic!("KbLine takes 5 arguments, got {ints:?}");
                };
                let tag: String = [c1, c2, c3]
                    .iter()
                    .map(|&c| char::from(u8::try_from(c).expect("ASCII code")))
                    .collect();
                out.entry(tag).or_default().insert(Format {
                    nf: usize::try_from(nf).expect("field count"),
                    rmask: u32::try_from(rmask).expect("REAL mask"),
                });
            }
            Expr::Call(_, args) => args.iter().for_each(|a| expr(a, out)),
            Expr::Index(b, idx) => {
                expr(b, out);
                idx.iter().for_each(|a| expr(a, out));
            }
            Expr::Field(b, _) | Expr::Unary(_, b) => expr(b, out),
            Expr::Binary(_, a, b) => {
                expr(a, out);
                expr(b, out);
            }
            Expr::Struct { fields, .. } => fields.iter().for_each(|(_, v)| expr(v, out)),
            Expr::Int(_)
            | Expr::Real(_)
            | Expr::Bool(_)
            | Expr::Str(_)
            | Expr::Enum(_)
            | Expr::Var(_)
            | Expr::Omitted => {}
        }
    }
    fn block(b: &[Stmt], out: &mut BTreeMap<String, BTreeSet<Format>>) {
        for s in b {
            match &s.kind {
                StmtKind::Decl { vars, .. } => {
                    for v in vars {
                        v.init.iter().for_each(|e| expr(e, out));
                    }
                }
                StmtKind::Assign { target, value } => {
                    expr(target, out);
                    expr(value, out);
                }
                StmtKind::Call { args, .. } => args.iter().for_each(|a| expr(a, out)),
                StmtKind::If {
                    cond,
                    then_body,
                    else_body,
                } => {
                    expr(cond, out);
                    block(then_body, out);
                    block(else_body, out);
                }
                StmtKind::While { cond, body } => {
                    expr(cond, out);
                    block(body, out);
                }
                StmtKind::For {
                    from,
                    to,
                    step,
                    body,
                    ..
                } => {
                    expr(from, out);
                    expr(to, out);
                    step.iter().for_each(|e| expr(e, out));
                    block(body, out);
                }
                StmtKind::Loop { body } => block(body, out),
                StmtKind::Repeat { body, until } => {
                    block(body, out);
                    expr(until, out);
                }
                StmtKind::Switch {
                    selector,
                    cases,
                    default,
                } => {
                    expr(selector, out);
                    for (vals, body) in cases {
                        vals.iter().for_each(|e| expr(e, out));
                        block(body, out);
                    }
                    if let Some(d) = default {
                        block(d, out);
                    }
                }
                StmtKind::Return(Some(e)) | StmtKind::WaitFor(e) | StmtKind::WaitSec(e) => {
                    expr(e, out);
                }
                _ => {}
            }
        }
    }
    let mut out = BTreeMap::new();
    for r in &src.routines {
        block(&r.body, &mut out);
    }
    out
}

// ---------------------------------------------------------------- samples

fn frame(x: f64, y: f64, z: f64, a: f64, b: f64, c: f64) -> Frame {
    Frame { x, y, z, a, b, c }
}

fn params(velocity: f64, acceleration_pct: f64, approx_mm: f64) -> MotionParams {
    MotionParams {
        velocity,
        acceleration_pct,
        approx_mm,
    }
}

/// The MOVE batch of PROTOCOL.md 5.3.
fn doc_batch() -> CommandFile {
    let down = frame(180.0, 0.0, 180.0, 0.0, 0.0, 0.0);
    let pose = |x, y, z| frame(x, y, z, down.x, down.y, down.z);
    CommandFile {
        cid: 19,
        command: Command::Move(vec![
            MotionRecord::Ptp {
                target: pose(350.0, 0.0, 150.0),
                s: Some(2),
                t: None,
                params: params(50.0, 100.0, 0.0),
            },
            MotionRecord::Lin {
                target: pose(350.0, 0.0, 100.0),
                params: params(0.2, 100.0, 2.0),
            },
            MotionRecord::Circ {
                aux: [400.0, 50.0, 100.0],
                target: pose(350.0, 100.0, 100.0),
                params: params(0.2, 100.0, 2.0),
            },
            MotionRecord::Lin {
                target: pose(350.0, 100.0, 150.0),
                params: params(0.25, 100.0, 0.0),
            },
        ]),
    }
}

/// A batch with extreme values: the largest CID, ±9999.999, ±0.001,
/// Status/Turn set and not set, and the actions SOT/WIN/DWL at the ends
/// of their ranges.
fn edge_batch() -> CommandFile {
    CommandFile {
        cid: 2_147_483_647,
        command: Command::Move(vec![
            MotionRecord::Ptp {
                target: frame(-9999.999, 9999.999, -0.001, -179.999, 0.001, 180.0),
                s: None,
                t: Some(63),
                params: params(100.0, 1.0, 9999.999),
            },
            MotionRecord::Ptp {
                target: frame(0.0, -12.345, 7.5, -90.0, -45.25, 0.125),
                s: Some(7),
                t: Some(0),
                params: params(0.001, 100.0, 0.0),
            },
            MotionRecord::Ptp {
                target: frame(1.0, 2.0, 3.0, 4.0, 5.0, 6.0),
                s: Some(0),
                t: None,
                params: params(12.5, 50.0, 1.5),
            },
            MotionRecord::PtpAxes {
                axes: [-170.0, -9999.999, 9999.999, -0.001, 120.0, -350.5],
                params: params(100.0, 100.0, 0.0),
            },
            MotionRecord::SptpAxes {
                axes: [185.0, -0.001, 9999.999, 350.5, -120.0, 0.0],
                params: params(0.001, 1.0, 0.0),
            },
            MotionRecord::Lin {
                target: frame(-1.0, -2.0, -3.0, -4.0, -5.0, -6.0),
                params: params(2.0, 1.0, 9999.999),
            },
            MotionRecord::Circ {
                aux: [-9999.999, 0.0, 9999.999],
                target: frame(8192.021, -8388.607, 0.5, -0.5, 179.999, -180.0),
                params: params(0.001, 0.001, 0.001),
            },
            MotionRecord::Sptp {
                target: frame(-0.001, 9999.999, 1.0, 180.0, -89.999, 0.0),
                s: Some(7),
                t: Some(63),
                params: params(100.0, 1.0, 0.0),
            },
            MotionRecord::Slin {
                target: frame(9999.999, -9999.999, 0.001, 0.0, 0.0, -179.999),
                params: params(2.0, 100.0, 9999.999),
            },
            MotionRecord::Scirc {
                aux: [0.001, -0.001, 5000.5],
                target: frame(-5.5, 6.25, -7.125, 45.0, -45.0, 90.0),
                params: params(0.001, 50.0, 0.5),
            },
            // The actions (PROTOCOL.md 5.6) at the ends of their ranges,
            // between two motions and after the last one.
            MotionRecord::SetOutput {
                index: 4096,
                value: true,
                pulse_ms: 60_000,
                path_mm: Some(-5000.0),
            },
            MotionRecord::SetOutput {
                index: 1,
                value: false,
                pulse_ms: 0,
                path_mm: Some(4999.999),
            },
            MotionRecord::SetOutput {
                index: 4096,
                value: true,
                pulse_ms: 60_000,
                path_mm: None,
            },
            MotionRecord::SetOutput {
                index: 1,
                value: false,
                pulse_ms: 0,
                path_mm: None,
            },
            MotionRecord::WaitInput {
                index: 4096,
                value: false,
                timeout_ms: 600_000,
            },
            MotionRecord::WaitInput {
                index: 1,
                value: true,
                timeout_ms: 1,
            },
            MotionRecord::Dwell { ms: 0 },
            MotionRecord::Spl {
                target: frame(-9999.999, 1.0, 2.0, 3.0, 4.0, 5.0),
                params: params(1.5, 75.0, 3.0),
                left: 2,
            },
            MotionRecord::Spl {
                target: frame(9999.999, -1.0, -2.0, -3.0, -4.0, -5.0),
                params: params(1.5, 75.0, 9999.999),
                left: 1,
            },
            MotionRecord::Dwell { ms: 600_000 },
        ]),
    }
}

fn tool_frame() -> Frame {
    frame(0.0, 0.0, 100.0, 0.0, 0.0, 0.0)
}

fn base_frame() -> Frame {
    frame(500.0, -250.0, 0.0, 90.0, 0.0, 0.0)
}

/// One command file of every op (PROTOCOL.md 5.4) and the two batches.
fn sample_commands() -> Vec<CommandFile> {
    let c = |cid, command| CommandFile { cid, command };
    vec![
        doc_batch(),
        edge_batch(),
        c(17, Command::GetPosition),
        c(18, Command::SetTool(tool_frame())),
        c(25, Command::SetBase(base_frame())),
        c(
            27,
            Command::SetSpeed(SpeedRecord {
                override_pct: 50.0,
                ptp_velocity_pct: 20.0,
                ptp_acceleration_pct: 100.0,
                cp_velocity: 0.25,
                cp_acceleration_pct: 100.0,
            }),
        ),
        c(30, Command::Run(30)),
        c(1_000_000, Command::Run(2_147_483_647)),
        c(
            32,
            Command::SetOutput(OutputRecord {
                index: 4096,
                value: true,
                pulse_ms: 60_000,
            }),
        ),
        c(
            33,
            Command::SetOutput(OutputRecord {
                index: 1,
                value: false,
                pulse_ms: 0,
            }),
        ),
        c(
            34,
            Command::SetAnalogOutput(AnalogOutputRecord {
                index: 32,
                value: -1.0,
            }),
        ),
        c(
            35,
            Command::SetAnalogOutput(AnalogOutputRecord {
                index: 1,
                value: 0.001,
            }),
        ),
        c(23, Command::Home),
        c(24, Command::GetTool),
        c(26, Command::GetBase),
        c(21, Command::Stop),
        c(28, Command::Reset),
        c(
            31,
            Command::OpenPath(PathChunk {
                path: 31,
                first: 0,
                motions: match doc_batch().command {
                    Command::Move(m) => m,
                    _ => Vec::new(),
                },
                close: false,
            }),
        ),
        c(
            32,
            Command::Append(PathChunk {
                path: 31,
                first: 1_000_000,
                motions: match edge_batch().command {
                    Command::Move(m) => m,
                    _ => Vec::new(),
                },
                close: true,
            }),
        ),
        c(
            33,
            Command::Append(PathChunk {
                path: 31,
                first: 7,
                motions: Vec::new(),
                close: true,
            }),
        ),
    ]
}

fn frame_vals(f: &Frame) -> Vec<Val> {
    f.to_array().into_iter().map(Val::R).collect()
}

fn params_vals(p: &MotionParams) -> [Val; 3] {
    [
        Val::R(p.velocity),
        Val::R(p.acceleration_pct),
        Val::R(p.approx_mm),
    ]
}

/// The records of a command file with the Rust-side field values, in file
/// order (not read from the text).
fn command_records(cmd: &CommandFile) -> Vec<(&'static str, Vec<Val>)> {
    let mut body: Vec<(&'static str, Vec<Val>)> = Vec::new();
    let (motions, first): (&[MotionRecord], i64) = match &cmd.command {
        Command::Move(m) => (m, 0),
        Command::OpenPath(c) | Command::Append(c) => {
            body.push((
                "APD",
                vec![
                    Val::I(i64::from(c.path)),
                    Val::I(i64::from(c.first)),
                    Val::I(i64::from(c.close)),
                ],
            ));
            (&c.motions, i64::from(c.first))
        }
        _ => (&[], 0),
    };
    match &cmd.command {
        Command::Move(_) | Command::OpenPath(_) | Command::Append(_) => {
            for (i, m) in motions.iter().enumerate() {
                let mut v = vec![Val::I(first + i as i64)];
                let tag = match m {
                    MotionRecord::Ptp {
                        target,
                        s,
                        t,
                        params,
                    } => {
                        v.extend(frame_vals(target));
                        v.push(Val::I(s.map_or(-1, i64::from)));
                        v.push(Val::I(t.map_or(-1, i64::from)));
                        v.extend(params_vals(params));
                        "PTP"
                    }
                    MotionRecord::PtpAxes { axes, params } => {
                        v.extend(axes.iter().copied().map(Val::R));
                        v.extend(params_vals(params));
                        "PTA"
                    }
                    MotionRecord::SptpAxes { axes, params } => {
                        v.extend(axes.iter().copied().map(Val::R));
                        v.extend(params_vals(params));
                        "SPA"
                    }
                    MotionRecord::Lin { target, params } => {
                        v.extend(frame_vals(target));
                        v.extend(params_vals(params));
                        "LIN"
                    }
                    MotionRecord::Circ {
                        aux,
                        target,
                        params,
                    } => {
                        v.extend(aux.iter().copied().map(Val::R));
                        v.extend(frame_vals(target));
                        v.extend(params_vals(params));
                        "CIR"
                    }
                    MotionRecord::Sptp {
                        target,
                        s,
                        t,
                        params,
                    } => {
                        v.extend(frame_vals(target));
                        v.push(Val::I(s.map_or(-1, i64::from)));
                        v.push(Val::I(t.map_or(-1, i64::from)));
                        v.extend(params_vals(params));
                        "SPT"
                    }
                    MotionRecord::Slin { target, params } => {
                        v.extend(frame_vals(target));
                        v.extend(params_vals(params));
                        "SLN"
                    }
                    MotionRecord::Scirc {
                        aux,
                        target,
                        params,
                    } => {
                        v.extend(aux.iter().copied().map(Val::R));
                        v.extend(frame_vals(target));
                        v.extend(params_vals(params));
                        "SCI"
                    }
                    MotionRecord::Spl {
                        target,
                        params,
                        left,
                    } => {
                        v.extend(frame_vals(target));
                        v.extend(params_vals(params));
                        v.push(Val::I(i64::from(*left)));
                        "SPL"
                    }
                    MotionRecord::SetOutput {
                        index,
                        value,
                        pulse_ms,
                        path_mm,
                    } => {
                        v.push(Val::I(i64::from(*index)));
                        v.push(Val::I(i64::from(*value)));
                        v.push(Val::I(i64::from(*pulse_ms)));
                        match path_mm {
                            None => "SOT",
                            Some(p) => {
                                v.push(Val::R(*p));
                                "SOP"
                            }
                        }
                    }
                    MotionRecord::WaitInput {
                        index,
                        value,
                        timeout_ms,
                    } => {
                        v.push(Val::I(i64::from(*index)));
                        v.push(Val::I(i64::from(*value)));
                        v.push(Val::I(i64::from(*timeout_ms)));
                        "WIN"
                    }
                    MotionRecord::Dwell { ms } => {
                        v.push(Val::I(i64::from(*ms)));
                        "DWL"
                    }
                };
                body.push((tag, v));
            }
        }
        Command::SetTool(f) | Command::SetBase(f) => body.push(("FRM", frame_vals(f))),
        Command::SetSpeed(s) => body.push((
            "SPD",
            vec![
                Val::R(s.override_pct),
                Val::R(s.ptp_velocity_pct),
                Val::R(s.ptp_acceleration_pct),
                Val::R(s.cp_velocity),
                Val::R(s.cp_acceleration_pct),
            ],
        )),
        Command::Run(n) => body.push(("PRG", vec![Val::I(i64::from(*n))])),
        Command::SetAnalogOutput(a) => {
            body.push(("ANO", vec![Val::I(i64::from(a.index)), Val::R(a.value)]))
        }
        Command::SetOutput(o) => body.push((
            "OUT",
            vec![
                Val::I(i64::from(o.index)),
                Val::I(i64::from(o.value)),
                Val::I(i64::from(o.pulse_ms)),
            ],
        )),
        _ => {}
    }
    let n = body.len() as i64;
    let cid = i64::from(cmd.cid);
    let mut out = vec![(
        "CMD",
        vec![
            Val::I(2),
            Val::I(cid),
            Val::I(i64::from(cmd.command.op())),
            Val::I(n),
        ],
    )];
    out.extend(body);
    out.push(("END", vec![Val::I(cid), Val::I(n)]));
    out
}

/// A well-formed line with its checksum, for contents the Rust encoder
/// would never write.
fn line(tag: &str, vals: &[Val]) -> String {
    let mut out = tag.to_string();
    for v in vals {
        match v {
            Val::I(i) => out.push_str(&format!(" {i}")),
            Val::R(r) => out.push_str(&format!(" {r:.3}")),
        }
    }
    let ck = checksum(vals.iter().map(|v| v.wire()));
    format!("{out} {ck}\n")
}

fn encode(cmd: &CommandFile) -> String {
    cmd.encode()
        .unwrap_or_else(|e| panic!("{}: {e}", cmd.command.name()))
}

// ---------------------------------------------------------------- KbLine driver

/// One line for `KbLine`: its text (plus extra character codes after it,
/// e.g. a CR) and the tag and format to parse it with.
struct LineCase {
    text: String,
    extra: Vec<u8>,
    tag: String,
    format: Format,
}

impl LineCase {
    fn new(text: &str, tag: &str, format: Format) -> Self {
        LineCase {
            text: text.to_string(),
            extra: Vec::new(),
            tag: tag.to_string(),
            format,
        }
    }
}

/// How the KRL program parses and formats lines (kb_io.src): by
/// characters, or with SREAD/SWRITE after `KbTxtInit`'s self-test.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Text {
    Chars,
    Native,
}

/// The start of a driver that puts the program into `mode`, checking that
/// the self-test chose SREAD/SWRITE in the runtime.
/// Characters: `kb_txt_native = FALSE`, as a site may set it.
fn text_setup(mode: Text) -> &'static str {
    match mode {
        Text::Chars => "  kb_txt_native = FALSE\n  KbTxtInit()\n",
        // A WAIT FOR that is FALSE fails the run (it would wait forever).
        Text::Native => "  KbTxtInit()\n  WAIT FOR kb_txt_mode == 1\n",
    }
}

/// `driver` with [`text_setup`] after its declarations.
fn in_mode(driver: &str, mode: Text) -> String {
    let mut out = String::new();
    let mut placed = false;
    for (i, line) in driver.lines().enumerate() {
        if !placed && i > 0 && !line.trim_start().starts_with("DECL") {
            out.push_str(text_setup(mode));
            placed = true;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// Runs `KbLine` over every case in one KRL run: `Some(kb_v[1..nf+1])`
/// (the values and the checksum) when it returns TRUE, `None` when FALSE.
fn krl_parse(cases: &[LineCase], mode: Text) -> Vec<Option<Vec<i64>>> {
    let mut d = String::from("DEF t_main( )\n  DECL INT k\n");
    d.push_str(text_setup(mode));
    for (i, c) in cases.iter().enumerate() {
        let i = i + 1;
        assert!(
            c.text.is_ascii() && !c.text.contains('"'),
            "{:?} cannot be a KRL string literal",
            c.text
        );
        let t = c.tag.as_bytes();
        d.push_str(&format!(
            "  kb_ln[] = \"{}\"\n  kb_lc = {}\n",
            c.text,
            c.text.len() + c.extra.len()
        ));
        for (k, b) in c.extra.iter().enumerate() {
            d.push_str(&format!("  kb_ln[{}] = {b}\n", c.text.len() + k + 1));
        }
        // The 0 after the line, as KbFGets puts it (KbLineC reads up to it).
        let lc = c.text.len() + c.extra.len();
        if lc < 256 {
            d.push_str(&format!("  kb_ln[{}] = 0\n", lc + 1));
        }
        d.push_str(&format!(
            "  t_ok[{i}] = KbLine({}, {}, {}, {}, {})\n  IF t_ok[{i}] THEN\n    FOR k = 1 TO {}\n      t_v[{i}, k] = kb_v[k]\n    ENDFOR\n  ENDIF\n",
            t[0],
            t[1],
            t[2],
            c.format.nf,
            c.format.rmask,
            c.format.nf + 1
        ));
    }
    d.push_str("END\n");
    let n = cases.len().max(1);
    let dat = format!("DECL GLOBAL BOOL t_ok[{n}]\nDECL GLOBAL INT t_v[{n},24]\n");
    let g = run_driver(&d, &dat, &mut BTreeMap::new());
    cases
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let i = i as i64 + 1;
            let ok = g.bool("t_ok", &[i]).expect("t_ok set");
            ok.then(|| {
                (1..=c.format.nf as i64 + 1)
                    .map(|k| g.int("t_v", &[i, k]).expect("kb_v copied"))
                    .collect()
            })
        })
        .collect()
}

/// Every command line the Rust encoder writes, with the KRL format for its
/// shape and the values (and checksum) the Rust side holds.
fn service_lines() -> Vec<(String, String, Format, Vec<i64>)> {
    let formats = krl_formats(submit_src());
    let mut out = Vec::new();
    for cmd in sample_commands() {
        let text = encode(&cmd);
        let records = command_records(&cmd);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), records.len(), "{text}");
        for (line, (tag, vals)) in lines.iter().zip(&records) {
            assert!(line.starts_with(&format!("{tag} ")), "{line}: tag {tag}");
            let f = shape(vals);
            assert!(
                formats.get(*tag).is_some_and(|s| s.contains(&f)),
                "{line}: kb_submit.src has no KbLine format for {tag} with {} fields, REAL mask {:#b} (it has {:?})",
                f.nf,
                f.rmask,
                formats.get(*tag)
            );
            let mut want: Vec<i64> = vals.iter().map(|v| v.wire()).collect();
            want.push(checksum(want.clone()));
            out.push((line.to_string(), tag.to_string(), f, want));
        }
    }
    out
}

// ---------------------------------------------------------------- a. service → KRL, lines

#[test]
fn krl_formats_cover_every_record_of_the_protocol() {
    let formats = krl_formats(submit_src());
    // What the Rust encoder writes into command files, by shape.
    let mut written: BTreeMap<&str, BTreeSet<Format>> = BTreeMap::new();
    for cmd in sample_commands() {
        for (tag, vals) in command_records(&cmd) {
            written.entry(tag).or_default().insert(shape(&vals));
        }
    }
    let tags: Vec<&str> = written.keys().copied().collect();
    assert_eq!(
        tags,
        [
            "ANO", "APD", "CIR", "CMD", "DWL", "END", "FRM", "LIN", "OUT", "PRG", "PTA", "PTP",
            "SCI", "SLN", "SOP", "SOT", "SPA", "SPD", "SPL", "SPT", "WIN"
        ],
        "the samples cover every command record"
    );
    for (tag, shapes) in &written {
        let krl = formats
            .get(*tag)
            .unwrap_or_else(|| panic!("kb_submit.src never parses {tag} ({formats:?})"));
        for s in shapes {
            assert!(krl.contains(s), "{tag}: {s:?} not among {krl:?}");
        }
    }
    // Exactly the documented shapes (PROTOCOL.md 5.2; bit f-1 = field f REAL).
    let one = |nf, rmask| BTreeSet::from([Format { nf, rmask }]);
    assert_eq!(formats["CMD"], one(4, 0));
    assert_eq!(formats["PTP"], one(12, 0b1110_0111_1110));
    assert_eq!(formats["PTA"], one(10, 0b11_1111_1110));
    assert_eq!(formats["SPA"], one(10, 0b11_1111_1110));
    assert_eq!(formats["LIN"], one(10, 0b11_1111_1110));
    assert_eq!(formats["CIR"], one(13, 0b1_1111_1111_1110));
    assert_eq!(formats["FRM"], one(6, 0b11_1111));
    assert_eq!(formats["SPD"], one(5, 0b1_1111));
    assert_eq!(formats["PRG"], one(1, 0));
    assert_eq!(formats["APD"], one(3, 0));
    assert_eq!(formats["SOT"], one(4, 0));
    assert_eq!(formats["SOP"], one(5, 0b1_0000));
    assert_eq!(formats["WIN"], one(4, 0));
    assert_eq!(formats["DWL"], one(2, 0));
    assert_eq!(formats["ANO"], one(2, 0b10));
    // The files the KRL program reads back at start (KsRecover) in the
    // shapes the Rust encoder writes them.
    let results = sample_results(3).encode().expect("encodes");
    let state = sample_state().encode().expect("encodes");
    for line in results.lines().chain(state.lines().take(1)) {
        let tag = &line[..3];
        let fields: Vec<&str> = line.split(' ').skip(1).collect();
        let vals = &fields[..fields.len() - 1];
        let f = Format {
            nf: vals.len(),
            rmask: vals
                .iter()
                .enumerate()
                .filter(|(_, v)| v.contains('.'))
                .fold(0, |m, (i, _)| m | (1 << i)),
        };
        assert!(
            formats.get(tag).is_some_and(|s| s.contains(&f)),
            "{line}: no KbLine format {f:?} for {tag}"
        );
    }
    let tags: BTreeSet<&str> = formats.keys().map(String::as_str).collect();
    assert_eq!(
        tags,
        BTreeSet::from([
            "ANO", "APD", "CIR", "CMD", "DWL", "END", "FRM", "LIN", "OUT", "PRG", "PTA", "PTP",
            "RES", "RSL", "SCI", "SLN", "SOP", "SOT", "SPA", "SPD", "SPL", "SPT", "STA", "WIN"
        ]),
        "kb_submit.src parses exactly the protocol's records"
    );
}

#[test]
fn krl_parses_every_line_the_service_writes() {
    for mode in [Text::Chars, Text::Native] {
        parses_every_line(mode);
    }
}

fn parses_every_line(mode: Text) {
    let formats = krl_formats(submit_src());
    let lines = service_lines();
    let mut cases: Vec<LineCase> = Vec::new();
    let mut expect: Vec<Option<Vec<i64>>> = Vec::new();
    for (text, tag, f, want) in &lines {
        cases.push(LineCase::new(text, tag, *f));
        expect.push(Some(want.clone()));
        // The other formats of the same tag (END of a command vs. END of
        // a result file) refuse the line.
        for other in formats[tag].iter().filter(|o| *o != f) {
            cases.push(LineCase::new(text, tag, *other));
            expect.push(None);
        }
        // A line end that krl_fgets may leave in the buffer (CR, LF, CR LF).
        for extra in [vec![13], vec![10], vec![13, 10]] {
            cases.push(LineCase {
                extra,
                ..LineCase::new(text, tag, *f)
            });
            expect.push(Some(want.clone()));
        }
    }
    let got = krl_parse(&cases, mode);
    for ((c, g), e) in cases.iter().zip(&got).zip(&expect) {
        assert_eq!(
            g, e,
            "{mode:?}: KbLine({}, {:?}) on {:?} + {:?}",
            c.tag, c.format, c.text, c.extra
        );
    }
}

/// Every damaged line is refused. With SREAD (native mode) a form error
/// that keeps every value (a double space, a missing trailing zero) may
/// pass, as the checksum allows: then the values must be the original's.
#[test]
fn krl_refuses_corrupted_and_truncated_lines() {
    for mode in [Text::Chars, Text::Native] {
        refuses_damaged_lines(mode);
    }
}

fn refuses_damaged_lines(mode: Text) {
    let lines = service_lines();
    let mut cases: Vec<LineCase> = Vec::new();
    let mut originals: Vec<&Vec<i64>> = Vec::new();
    for (k, (text, tag, f, want)) in lines.iter().enumerate() {
        let before = cases.len();
        let bytes = text.as_bytes();
        // Every digit changed: to every other digit in the first lines of
        // each kind, else to the next digit (keeps the run short).
        let all = k < 5;
        for i in (0..bytes.len()).filter(|&i| bytes[i].is_ascii_digit()) {
            let alternatives: Vec<u8> = if all {
                (b'0'..=b'9').filter(|&d| d != bytes[i]).collect()
            } else {
                vec![b'0' + (bytes[i] - b'0' + 1) % 10]
            };
            for d in alternatives {
                let mut b = bytes.to_vec();
                b[i] = d;
                let t = String::from_utf8(b).expect("ASCII");
                cases.push(LineCase::new(&t, tag, *f));
            }
        }
        // Every proper prefix: a writer cut off inside the line.
        for n in 1..text.len() {
            cases.push(LineCase::new(&text[..n], tag, *f));
        }
        // Form errors: a trailing space, a double space, a '+', 2 decimals.
        cases.push(LineCase::new(&format!("{text} "), tag, *f));
        cases.push(LineCase::new(&text.replacen(' ', "  ", 2), tag, *f));
        if let Some(p) = text.find(" -") {
            let mut t = text.clone();
            t.replace_range(p..p + 2, " +");
            cases.push(LineCase::new(&t, tag, *f));
        }
        if let Some(p) = text.find('.') {
            let mut t = text.clone();
            t.remove(p + 3);
            cases.push(LineCase::new(&t, tag, *f));
        }
        originals.resize(cases.len().max(before), want);
    }
    let got = krl_parse(&cases, mode);
    let accepted: Vec<&str> = cases
        .iter()
        .zip(&got)
        .zip(&originals)
        .filter(|((_, g), want)| match g {
            None => false,
            Some(v) => mode == Text::Chars || v != **want,
        })
        .map(|((c, _), _)| c.text.as_str())
        .collect();
    assert!(
        accepted.is_empty(),
        "{mode:?}: KbLine accepted {} damaged lines, e.g. {:?}",
        accepted.len(),
        &accepted[..accepted.len().min(5)]
    );
    assert!(cases.len() > 2000, "{} cases", cases.len());
}

// ---------------------------------------------------------------- d. checksum examples

#[test]
fn protocol_checksum_examples_computed_by_krl() {
    let driver = "DEF t_main( )
  t_c1 = KbMix(KbMix(KbMix(KbMix(0, 2), 17), 3), 0)
  t_c2 = KbMix(0, KbMilli(500.0))
  t_c2 = KbMix(t_c2, KbMilli(-250.0))
  t_c2 = KbMix(t_c2, KbMilli(0.0))
  t_c2 = KbMix(t_c2, KbMilli(90.0))
  t_c2 = KbMix(t_c2, KbMilli(0.0))
  t_c2 = KbMix(t_c2, KbMilli(0.0))
  KbOBeg(67, 77, 68)
  KbOI(2)
  KbOI(17)
  KbOI(3)
  KbOI(0)
  KbOEnd()
  t_l1[] = kb_ob[]
  t_n1 = kb_ol
  KbOBeg(70, 82, 77)
  KbOR(500.0)
  KbOR(-250.0)
  KbOR(0.0)
  KbOR(90.0)
  KbOR(0.0)
  KbOR(0.0)
  KbOEnd()
  t_l2[] = kb_ob[]
  t_n2 = kb_ol
END
";
    let dat = "DECL GLOBAL INT t_c1\nDECL GLOBAL INT t_c2\nDECL GLOBAL CHAR t_l1[256]\nDECL GLOBAL CHAR t_l2[256]\nDECL GLOBAL INT t_n1\nDECL GLOBAL INT t_n2";
    let g = run_driver(driver, dat, &mut BTreeMap::new());
    assert_eq!(g.int("t_c1", &[]), Some(10491));
    assert_eq!(g.int("t_c2", &[]), Some(4787));
    let line = |arr: &str, n: &str| {
        let n = usize::try_from(g.int(n, &[]).expect("length")).expect("length");
        g.chars(arr, n).expect("characters")
    };
    assert_eq!(line("t_l1", "t_n1"), "CMD 2 17 3 0 10491");
    assert_eq!(
        line("t_l2", "t_n2"),
        "FRM 500.000 -250.000 0.000 90.000 0.000 0.000 4787"
    );
    // The lines are 0-terminated for krl_fwriteln.
    assert_eq!(g.int("t_l1", &[19]), Some(0));
}

#[test]
fn krl_thousandths_match_the_rust_encoder() {
    let values: [f64; 20] = [
        0.0, 0.001, -0.001, 0.5, -0.5, 1.25, 12.345, -12.345, 120.5, 179.999, -180.0, 8192.021,
        -8192.021, 8388.607, -8388.607, 9999.999, -9999.999, 12345.678, -12345.678, 0.0004,
    ];
    let mut d = String::from("DEF t_main( )\n");
    for (i, v) in values.iter().enumerate() {
        d.push_str(&format!("  t_m[{}] = KbMilli({v:?})\n", i + 1));
    }
    d.push_str("END\n");
    let g = run_driver(
        &d,
        &format!("DECL GLOBAL INT t_m[{}]", values.len()),
        &mut BTreeMap::new(),
    );
    for (i, v) in values.iter().enumerate() {
        // Clamped to +-9999.999 so that the line stays well-formed.
        let want = milli(v.clamp(-9999.999, 9999.999));
        assert_eq!(g.int("t_m", &[i as i64 + 1]), Some(want), "KbMilli({v})");
    }
}

// ---------------------------------------------------------------- c. KRL → service, files

/// The pose the Submit side reads in the channel tests ($POS_ACT,
/// $AXIS_ACT): the stopped pose of PROTOCOL.md 6.2.
const POSE: [f64; 6] = [300.0, 32.174, 150.0, 180.0, 0.0, 180.0];
const POSE_S: u8 = 2;
const POSE_T: u8 = 35;
const AXES: [f64; 6] = [-6.121, -53.228, 118.714, 0.0, 24.514, -6.121];

fn sample_results(n: i32) -> ResultFile {
    let codes = [
        ResultCode::Ok,
        ResultCode::Cancelled,
        ResultCode::SoftwareLimit,
        ResultCode::BadCommand,
        ResultCode::Other(99),
        ResultCode::RuntimeError,
    ];
    ResultFile {
        results: (1..=n)
            .map(|i| {
                let f = f64::from(i);
                // Exact thousandths, as a decoded file holds them.
                let th = |m: i32| f64::from(m) / 1000.0;
                ResultRecord {
                    cid: 100 * i + 7,
                    code: codes[i as usize % codes.len()],
                    completed: (i * 3) as u32,
                    axis: (i % 7) as u8,
                    position: frame(
                        th(-9_999_999 + 1000 * i),
                        f * 0.125,
                        th(-i),
                        180.0 - f,
                        -90.0 + f,
                        th(9_999_999 - 1000 * i),
                    ),
                    s: (i % 8) as u8,
                    t: (i * 9 % 64) as u8,
                    axes: [f, -f, th(99), th(-10 * i), th(100 * i + 56), -170.0 + f],
                }
            })
            .collect(),
    }
}

fn sample_state() -> StateFile {
    StateFile {
        seq: 290,
        status: ControllerStatus::Busy,
        mode: OperatingMode::Ext,
        busy_cid: 20,
        busy_index: 1,
        last_cid: 20,
        error: None,
        error_axis: 0,
        override_pct: 100.0,
        simulated: false,
        room: 200,
        stored: 0,
        position: Frame::from_array(POSE),
        s: POSE_S,
        t: POSE_T,
        axes: AXES,
        tool: tool_frame(),
        base: Frame::default(),
        // Nothing set: the KRL program's $IN/$OUT start FALSE.
        io: Some(IoState {
            base: 1,
            inputs: 0,
            outputs: 0,
        }),
        // Drives on, fence closed, no emergency stop; the state driver
        // leaves the robot program free ($PRO_STATE1 #P_FREE).
        safety: Some(SafetyState {
            drives_ready: true,
            user_safety: true,
            alarm_stop: true,
            stop_message: false,
            program_state: 0,
        }),
        // Full scale both ways, the smallest steps, values between.
        analog: Some(AnalogState {
            inputs: [1.0, -1.0, 0.0, 0.001, -0.001, 0.5, -0.25, 0.999],
            outputs: [-0.999, 0.123, -0.456, 0.0, 1.0, -1.0, 0.002, 0.75],
        }),
    }
}

#[test]
fn result_files_written_by_krl_decode_in_rust() {
    // Ten results through KsHistPush (only the newest 8 stay), then
    // KsWriteRes; the result file must be what the Rust encoder writes.
    let all = sample_results(10);
    let mut d = String::from("DEF t_main( )\n");
    for r in &all.results {
        d.push_str(&format!(
            "  kb_sp.S = {}\n  kb_sp.T = {}\n  kb_sa = {}\n  KsHistPush({}, {}, {}, {}, {})\n",
            r.s,
            r.t,
            krl_axes(&r.axes),
            r.cid,
            r.code.code(),
            r.completed,
            r.axis,
            krl_frame(&r.position)
        ));
    }
    d.push_str("  KsWriteRes()\nEND\n");
    let want = ResultFile {
        results: all.results[2..].to_vec(),
    };
    // The file is the same whether SWRITE or the characters format it.
    let mut g = None;
    for mode in [Text::Native, Text::Chars] {
        let mut files = BTreeMap::new();
        g = Some(run_driver(&in_mode(&d, mode), "", &mut files));
        let text = files.get(RESULT_FILE).expect("kb_res.txt written");
        assert_eq!(
            ResultFile::decode(text),
            Ok(want.clone()),
            "{mode:?}: {text}"
        );
        assert_eq!(text, &all.encode().expect("encodes"), "{mode:?}");
    }
    let g = g.expect("ran");
    assert_eq!(g.int("kb_hn", &[]), Some(8));
    assert_eq!(g.bool("kb_res_due", &[]), Some(false));

    // No result yet (PROTOCOL.md 6.2).
    let mut files = BTreeMap::new();
    run_driver("DEF t_main( )\n  KsWriteRes()\nEND\n", "", &mut files);
    assert_eq!(files[RESULT_FILE], "RES 2 0 62\nEND 0 0\n");
    assert_eq!(
        ResultFile::decode(&files[RESULT_FILE]),
        Ok(ResultFile::default())
    );
}

/// A driver that sets the Submit side's state from `s` and calls
/// KsWriteState (which increments kb_seq first).
fn state_driver(s: &StateFile, mode: &str, ov_pro: i64) -> String {
    let status = match s.status {
        ControllerStatus::Idle => 0,
        ControllerStatus::Busy => 1,
        ControllerStatus::Error => 2,
    };
    let (run_cid, err) = match status {
        1 => (s.busy_cid, 0),
        2 => (17, s.error.map_or(0, ResultCode::code)),
        _ => (0, 0),
    };
    format!(
        "DEF t_main( )
  kb_seq = {seq}
  kb_err = {err}
  kb_err_axis = {axis}
  kb_run_cid = {run_cid}
  kb_run_stg = 2
  kb_busy_idx = {idx}
  kb_last_cid = {last}
  $MODE_OP = #{mode}
  $OV_PRO = {ov_pro}
  $POS_ACT = {pos}
  $POS_ACT.S = {ps}
  $POS_ACT.T = {pt}
  $AXIS_ACT = {axes}
  kb_tool_act = {tool}
  kb_base_act = {base}
{analog}  KsWriteState(4711)
END
",
        seq = i64::from(s.seq) - 1,
        axis = s.error_axis,
        idx = s.busy_index,
        last = s.last_cid,
        pos = krl_frame(&s.position),
        ps = s.s,
        pt = s.t,
        axes = krl_axes(&s.axes),
        tool = krl_frame(&s.tool),
        base = krl_frame(&s.base),
        analog = analog_setup(s.analog.as_ref()),
    )
}

/// KRL statements that set `$ANIN[1..8]` and `$ANOUT[1..8]` to `a`'s
/// values (nothing for `None`: they stay 0.0).
fn analog_setup(a: Option<&AnalogState>) -> String {
    let mut out = String::new();
    if let Some(a) = a {
        for (k, v) in a.inputs.iter().enumerate() {
            out.push_str(&format!("  $ANIN[{}] = {}\n", k + 1, krl_real(*v)));
        }
        for (k, v) in a.outputs.iter().enumerate() {
            out.push_str(&format!("  $ANOUT[{}] = {}\n", k + 1, krl_real(*v)));
        }
    }
    out
}

#[test]
fn state_files_written_by_krl_decode_in_rust() {
    let busy = sample_state();
    let idle = StateFile {
        seq: 294,
        status: ControllerStatus::Idle,
        mode: OperatingMode::T1,
        busy_cid: 0,
        busy_index: 0,
        last_cid: 22,
        override_pct: 30.0,
        base: base_frame(),
        ..busy
    };
    let error = StateFile {
        seq: 2_147_483_647,
        status: ControllerStatus::Error,
        mode: OperatingMode::Aut,
        busy_cid: 0,
        busy_index: 0,
        last_cid: 2_147_483_000,
        error: Some(ResultCode::SoftwareLimit),
        error_axis: 5,
        override_pct: 1.0,
        position: frame(-9999.999, 9999.999, -0.001, 0.001, -90.0, 90.0),
        s: 7,
        t: 63,
        axes: [-170.0, -9999.999, 9999.999, 0.0, -120.0, 350.0],
        ..busy
    };
    let t2 = StateFile {
        seq: 1,
        mode: OperatingMode::T2,
        ..idle
    };
    for (s, mode, ov) in [
        (busy, "EX", 100),
        (idle, "T1", 30),
        (error, "AUT", 1),
        (t2, "T2", 30),
    ] {
        for text_mode in [Text::Native, Text::Chars] {
            let mut files = BTreeMap::new();
            let d = in_mode(&state_driver(&s, mode, ov), text_mode);
            let g = run_driver(&d, "", &mut files);
            let text = files.get(STATE_FILE).expect("kb_state.txt written");
            assert_eq!(StateFile::decode(text), Ok(s), "{text_mode:?}: {text}");
            assert_eq!(text, &s.encode().expect("encodes"), "{text_mode:?}");
            assert_eq!(g.int("kb_seq", &[]), Some(i64::from(s.seq)));
        }
        let mut files = BTreeMap::new();
        let g = run_driver(&state_driver(&s, mode, ov), "", &mut files);
        let text = files.get(STATE_FILE).expect("kb_state.txt written");
        assert_eq!(text, &s.encode().expect("encodes"));
        assert_eq!(g.int("kb_seq", &[]), Some(i64::from(s.seq)));
        assert_eq!(g.int("kb_hb_t", &[]), Some(4711));
        assert_eq!(g.bool("kb_hb_due", &[]), Some(false));
    }

    // seq wraps from 2147483647 to 1; an unknown mode is 0.
    let wrapped = StateFile {
        seq: 1,
        mode: OperatingMode::Unknown,
        ..idle
    };
    let mut d = state_driver(&wrapped, "T1", 30);
    d = d
        .replace("kb_seq = 0", "kb_seq = 2147483647")
        .replace("$MODE_OP = #T1", "$MODE_OP = #INVALID");
    let mut files = BTreeMap::new();
    run_driver(&d, "", &mut files);
    assert_eq!(StateFile::decode(&files[STATE_FILE]), Ok(wrapped));

    // Analog readings past full scale are reported as +-1.000 (the
    // decoder refuses anything beyond, which would make the whole state
    // file invalid), others rounded to the nearest thousandth.
    let d = state_driver(&idle, "T1", 30)
        .replace("$ANIN[1] = 1.000", "$ANIN[1] = 1.5")
        .replace("$ANIN[2] = -1.000", "$ANIN[2] = -1.0004")
        .replace("$ANIN[8] = 0.999", "$ANIN[8] = 0.9994")
        .replace("$ANOUT[2] = 0.123", "$ANOUT[2] = 0.1225001");
    assert_eq!(
        ["$ANIN[1] = 1.5", "-1.0004", "0.9994", "0.1225001"].map(|t| d.contains(t)),
        [true; 4],
        "{d}"
    );
    for text_mode in [Text::Native, Text::Chars] {
        let mut files = BTreeMap::new();
        run_driver(&in_mode(&d, text_mode), "", &mut files);
        assert_eq!(
            StateFile::decode(&files[STATE_FILE]),
            Ok(idle),
            "{text_mode:?}: {}",
            files[STATE_FILE]
        );
    }
    // kb_an_on = FALSE (a controller whose Submit interpreter may not
    // read the analog channels): no ANS line, the file still decodes.
    let d = state_driver(&idle, "T1", 30).replace(
        "  KsWriteState(4711)",
        "  kb_an_on = FALSE\n  KsWriteState(4711)",
    );
    let mut files = BTreeMap::new();
    run_driver(&d, "", &mut files);
    assert!(!files[STATE_FILE].contains("ANS "), "{}", files[STATE_FILE]);
    assert_eq!(
        StateFile::decode(&files[STATE_FILE]),
        Ok(StateFile {
            analog: None,
            ..idle
        })
    );
}

// ---------------------------------------------------------------- b. the Submit side's own cycle

/// The controller as the channel tests set it up: kb_main selected,
/// running and ready, EXT mode (or `mode`), the pose of POSE/AXES.
fn env_setup(mode: &str) -> String {
    format!(
        "  kb_rob_ready = TRUE
  $PRO_STATE1 = #P_ACTIVE
  $PRO_NAME1[] = \"KB_MAIN \"
  $MODE_OP = #{mode}
  $POS_ACT = {pos}
  $POS_ACT.S = {POSE_S}
  $POS_ACT.T = {POSE_T}
  $AXIS_ACT = {axes}
  kb_tool_act = {tool}
  kb_base_act = {base}
",
        pos = krl_frame(&Frame::from_array(POSE)),
        axes = krl_axes(&AXES),
        tool = krl_frame(&tool_frame()),
        base = krl_frame(&base_frame()),
    )
}

/// Starts the Submit side (kb_submit_init: recovery, result and state
/// file) and runs `cycles` cycles 100 ms apart, after `setup`.
fn submit(files: &mut BTreeMap<String, String>, setup: &str, cycles: u32) -> Globals {
    let d = format!(
        "DEF t_main( )
  DECL INT k
{setup}  kb_submit_init()
  FOR k = 1 TO {cycles}
    $ROB_TIMER = $ROB_TIMER + 100
    kb_submit_cycle()
  ENDFOR
END
"
    );
    run_driver(&d, "", files)
}

fn channel(cmd: &str) -> BTreeMap<String, String> {
    BTreeMap::from([(COMMAND_FILE.to_string(), cmd.to_string())])
}

fn results(files: &BTreeMap<String, String>) -> Vec<ResultRecord> {
    let text = files.get(RESULT_FILE).expect("kb_res.txt written");
    match ResultFile::decode(text) {
        Ok(r) => r.results,
        Err(e) => panic!("kb_res.txt does not decode: {e}\n{text}"),
    }
}

fn state(files: &BTreeMap<String, String>) -> StateFile {
    let text = files.get(STATE_FILE).expect("kb_state.txt written");
    match StateFile::decode(text) {
        Ok(s) => s,
        Err(e) => panic!("kb_state.txt does not decode: {e}\n{text}"),
    }
}

/// The motion buffer entry `i` (1-based) holds `m`.
fn assert_motion(g: &Globals, i: usize, m: &MotionRecord) {
    let int = |f: &str| g.int_at(&format!("kb_mot[{i}].{f}"));
    let real = |f: &str| g.real_at(&format!("kb_mot[{i}].{f}"));
    // The actions: K 9 SOT, 10 WIN, 11 DWL, 12 SOP; S = index, T =
    // value, N = ms; an SOP's distance in X.
    let action = match m {
        MotionRecord::SetOutput {
            index,
            value,
            pulse_ms,
            path_mm,
        } => {
            if let Some(p) = path_mm {
                assert_eq!(real("X"), Some(from_milli(*p)), "kb_mot[{i}].X for {m:?}");
            }
            let k = if path_mm.is_some() { 12 } else { 9 };
            Some((k, i64::from(*index), i64::from(*value), *pulse_ms))
        }
        MotionRecord::WaitInput {
            index,
            value,
            timeout_ms,
        } => Some((10, i64::from(*index), i64::from(*value), *timeout_ms)),
        MotionRecord::Dwell { ms } => Some((11, 0, 0, *ms)),
        _ => None,
    };
    if let Some((k, s, t, n)) = action {
        let ctx = format!("kb_mot[{i}] for {m:?}");
        assert_eq!(int("K"), Some(k), "{ctx}");
        assert_eq!(int("S"), Some(s), "{ctx}");
        assert_eq!(int("T"), Some(t), "{ctx}");
        assert_eq!(int("N"), Some(i64::from(n)), "{ctx}");
        return;
    }
    let (k, s, t, six, aux, p) = match m {
        MotionRecord::Ptp {
            target,
            s,
            t,
            params,
        } => (
            1,
            s.map_or(-1, i64::from),
            t.map_or(-1, i64::from),
            target.to_array(),
            [0.0; 3],
            params,
        ),
        MotionRecord::PtpAxes { axes, params } => (2, -1, -1, *axes, [0.0; 3], params),
        // An SPA is stored as a PTA with S = 1 (kb_main plays it as SPTP).
        MotionRecord::SptpAxes { axes, params } => (2, 1, -1, *axes, [0.0; 3], params),
        MotionRecord::Lin { target, params } => (3, -1, -1, target.to_array(), [0.0; 3], params),
        MotionRecord::Circ {
            aux,
            target,
            params,
        } => (4, -1, -1, target.to_array(), *aux, params),
        MotionRecord::Slin { target, params } => (5, -1, -1, target.to_array(), [0.0; 3], params),
        MotionRecord::Scirc {
            aux,
            target,
            params,
        } => (6, -1, -1, target.to_array(), *aux, params),
        MotionRecord::Sptp {
            target,
            s,
            t,
            params,
        } => (
            7,
            s.map_or(-1, i64::from),
            t.map_or(-1, i64::from),
            target.to_array(),
            [0.0; 3],
            params,
        ),
        MotionRecord::Spl { target, params, .. } => {
            (8, -1, -1, target.to_array(), [0.0; 3], params)
        }
        MotionRecord::SetOutput { .. }
        | MotionRecord::WaitInput { .. }
        | MotionRecord::Dwell { .. } => unreachable!("actions are checked above"),
    };
    assert_eq!(
        int("N"),
        Some(m.block_left() as i64),
        "kb_mot[{i}].N for {m:?}"
    );
    let ctx = format!("kb_mot[{i}] for {m:?}");
    assert_eq!(int("K"), Some(k), "{ctx}");
    assert_eq!(int("S"), Some(s), "{ctx}");
    assert_eq!(int("T"), Some(t), "{ctx}");
    for (name, v) in ["X", "Y", "Z", "A", "B", "C"].into_iter().zip(six) {
        assert_eq!(real(name), Some(from_milli(v)), "{ctx}: {name}");
    }
    for (name, v) in ["AX", "AY", "AZ"].into_iter().zip(aux) {
        assert_eq!(real(name), Some(from_milli(v)), "{ctx}: {name}");
    }
    assert_eq!(real("VEL"), Some(from_milli(p.velocity)), "{ctx}");
    assert_eq!(real("ACC"), Some(from_milli(p.acceleration_pct)), "{ctx}");
    assert_eq!(real("APO"), Some(from_milli(p.approx_mm)), "{ctx}");
}

fn assert_frame(g: &Globals, var: &str, f: &Frame) {
    for (name, v) in ["X", "Y", "Z", "A", "B", "C"].into_iter().zip(f.to_array()) {
        assert_eq!(
            g.real_at(&format!("{var}.{name}")),
            Some(from_milli(v)),
            "{var}.{name}"
        );
    }
}

/// The busy state right after a command was handed to kb_main.
fn assert_busy(files: &BTreeMap<String, String>, cid: i32, seq: i32) {
    let s = state(files);
    assert_eq!(
        (s.status, s.busy_cid, s.busy_index, s.last_cid, s.seq),
        (ControllerStatus::Busy, cid, 0, cid, seq),
        "{s:?}"
    );
}

#[test]
fn service_commands_reach_the_motion_buffer() {
    let setup = env_setup("EX");
    let cmds = [
        doc_batch(),
        edge_batch(),
        CommandFile {
            cid: 18,
            command: Command::SetTool(tool_frame()),
        },
        CommandFile {
            cid: 25,
            command: Command::SetBase(base_frame()),
        },
        CommandFile {
            cid: 23,
            command: Command::Home,
        },
    ];
    for cmd in cmds {
        let mut files = channel(&encode(&cmd));
        let g = submit(&mut files, &setup, 1);
        let cid = i64::from(cmd.cid);
        let ctx = cmd.command.name();
        assert_eq!(g.int("kb_last_cid", &[]), Some(cid), "{ctx}");
        assert_eq!(g.int("kb_job_cid", &[]), Some(cid), "{ctx}");
        assert_eq!(g.int("kb_run_cid", &[]), Some(cid), "{ctx}");
        assert_eq!(
            g.int("kb_job_op", &[]),
            Some(i64::from(cmd.command.op())),
            "{ctx}"
        );
        match &cmd.command {
            Command::Move(motions) => {
                assert_eq!(g.int("kb_job_n", &[]), Some(motions.len() as i64));
                for (i, m) in motions.iter().enumerate() {
                    assert_motion(&g, i + 1, m);
                }
            }
            Command::SetTool(f) | Command::SetBase(f) => {
                assert_eq!(g.int("kb_job_n", &[]), Some(1));
                assert_frame(&g, "kb_job_frm", f);
            }
            _ => assert_eq!(g.int("kb_job_n", &[]), Some(0)),
        }
        // No result yet (kb_main answers); the state shows the pick-up:
        // seq 1 from kb_submit_init, 2 after the command.
        assert_eq!(results(&files), [], "{ctx}");
        assert_busy(&files, cmd.cid, 2);
    }
}

#[test]
fn big_batches_are_read_over_several_cycles() {
    let motions: Vec<MotionRecord> = (0..100)
        .map(|i| {
            let f = f64::from(i);
            match i % 4 {
                0 => MotionRecord::Ptp {
                    target: frame(300.0 + f, -f, 150.5, 180.0, 0.0, -180.0),
                    s: (i % 8 == 0).then_some(2),
                    t: (i % 3 == 0).then_some((i % 64) as u8),
                    params: params(50.0, 100.0, 0.0),
                },
                1 => MotionRecord::Lin {
                    target: frame(300.0, f, 100.0, 180.0, 0.0, 180.0),
                    params: params(0.2, 100.0, f / 10.0),
                },
                2 => MotionRecord::Circ {
                    aux: [f, 1.0, -1.0],
                    target: frame(310.0, f, 100.0, 180.0, 0.0, 180.0),
                    params: params(0.1, 50.0, 2.0),
                },
                _ => MotionRecord::PtpAxes {
                    axes: [f, -90.0, 90.0, 0.0, -f / 2.0, 0.0],
                    params: params(20.0, 100.0, 0.0),
                },
            }
        })
        .collect();
    let cmd = CommandFile {
        cid: 40,
        command: Command::Move(motions.clone()),
    };
    let setup = env_setup("EX");
    // One cycle: accepted (busy at once), 40 lines read, nothing posted.
    let mut files = channel(&encode(&cmd));
    let g = submit(&mut files, &setup, 1);
    assert_eq!(g.int("kb_last_cid", &[]), Some(40));
    assert_eq!(g.bool("kb_ld_on", &[]), Some(true));
    assert_eq!(g.int("kb_ld_next", &[]), Some(41));
    assert_eq!(g.int("kb_job_cid", &[]), Some(0));
    assert_busy(&files, 40, 2);
    // Three cycles: the whole batch is in the buffer and posted.
    let mut files = channel(&encode(&cmd));
    let g = submit(&mut files, &setup, 3);
    assert_eq!(g.bool("kb_ld_on", &[]), Some(false));
    assert_eq!(g.int("kb_job_cid", &[]), Some(40));
    assert_eq!(g.int("kb_job_n", &[]), Some(100));
    for (i, m) in motions.iter().enumerate() {
        assert_motion(&g, i + 1, m);
    }
    assert_eq!(results(&files), []);
    assert_eq!(state(&files).busy_cid, 40);
}

/// The record the Submit side writes for `cid` with the test pose.
fn answer(cid: i32, code: ResultCode, position: Frame) -> ResultRecord {
    ResultRecord {
        cid,
        code,
        completed: 0,
        axis: 0,
        position,
        s: POSE_S,
        t: POSE_T,
        axes: AXES,
    }
}

#[test]
fn commands_answered_by_the_submit_side_decode_in_rust() {
    let pose = Frame::from_array(POSE);
    let speed = SpeedRecord {
        override_pct: 50.0,
        ptp_velocity_pct: 20.0,
        ptp_acceleration_pct: 90.0,
        cp_velocity: 0.25,
        cp_acceleration_pct: 75.5,
    };
    let cases = [
        (Command::GetPosition, "EX", answer(17, ResultCode::Ok, pose)),
        (
            Command::GetTool,
            "EX",
            answer(24, ResultCode::Ok, tool_frame()),
        ),
        (
            Command::GetBase,
            "EX",
            answer(26, ResultCode::Ok, base_frame()),
        ),
        (
            Command::SetSpeed(speed),
            "EX",
            answer(27, ResultCode::Ok, pose),
        ),
        (Command::Stop, "EX", answer(21, ResultCode::Ok, pose)),
        (Command::Reset, "EX", answer(28, ResultCode::Ok, pose)),
        // SETANOUT: $ANOUT now, answered with the current TCP (as SETOUT).
        (
            Command::SetAnalogOutput(AnalogOutputRecord {
                index: 3,
                value: -0.625,
            }),
            "T1",
            answer(34, ResultCode::Ok, pose),
        ),
        (
            Command::SetAnalogOutput(AnalogOutputRecord {
                index: 32,
                value: 1.0,
            }),
            "EX",
            answer(35, ResultCode::Ok, pose),
        ),
        // RUN selects programs with $CMD: EXT mode only.
        (
            Command::Run(30),
            "T1",
            answer(30, ResultCode::NotReady, pose),
        ),
    ];
    for (command, mode, want) in cases {
        let cmd = CommandFile {
            cid: want.cid,
            command,
        };
        let mut files = channel(&encode(&cmd));
        let g = submit(&mut files, &env_setup(mode), 1);
        let ctx = cmd.command.name();
        assert_eq!(results(&files), [want], "{ctx}");
        let s = state(&files);
        assert_eq!(
            (s.status, s.last_cid, s.busy_cid),
            (ControllerStatus::Idle, cmd.cid, 0),
            "{ctx}"
        );
        assert_eq!(g.int("kb_job_cid", &[]), Some(0), "{ctx}");
        if let Command::SetSpeed(sp) = cmd.command {
            assert_eq!(g.int("$OV_PRO", &[]), Some(50));
            assert_eq!(s.override_pct, 50.0);
            assert_eq!(g.real("kb_def_ptpv", &[]), Some(sp.ptp_velocity_pct));
            assert_eq!(g.real("kb_def_ptpa", &[]), Some(sp.ptp_acceleration_pct));
            assert_eq!(g.real("kb_def_cpv", &[]), Some(sp.cp_velocity));
            assert_eq!(g.real("kb_def_cpa", &[]), Some(sp.cp_acceleration_pct));
        }
        if let Command::SetAnalogOutput(a) = cmd.command {
            let i = i64::from(a.index);
            assert_eq!(g.real("$ANOUT", &[i]), Some(a.value), "{ctx}");
            // The state file written after it shows channels 1..8.
            let analog = s.analog.expect("an ANS line");
            let mut outputs = [0.0; 8];
            if let Some(o) = outputs.get_mut(usize::from(a.index) - 1) {
                *o = a.value;
            }
            assert_eq!(analog.outputs, outputs, "{ctx}");
        }
    }

    // RUN in EXT mode starts the program switch: busy with the module
    // number from PRG.
    let cmd = CommandFile {
        cid: 1_000_000,
        command: Command::Run(2_147_483_647),
    };
    let mut files = channel(&encode(&cmd));
    let g = submit(&mut files, &env_setup("EX"), 1);
    assert_eq!(g.int("kb_rs_prog", &[]), Some(2_147_483_647));
    assert_eq!(g.int("kb_rs", &[]), Some(1));
    assert_eq!(g.int("kb_run_op", &[]), Some(10));
    assert_eq!(g.bool("kb_leave_req", &[]), Some(true));
    assert_eq!(results(&files), []);
    assert_busy(&files, 1_000_000, 2);

    // A MOVE while kb_main is not ready: NOT_READY, nothing posted.
    let mut files = channel(&encode(&doc_batch()));
    let setup = env_setup("EX").replace("kb_rob_ready = TRUE", "kb_rob_ready = FALSE");
    let g = submit(&mut files, &setup, 1);
    assert_eq!(results(&files), [answer(19, ResultCode::NotReady, pose)]);
    assert_eq!(g.int("kb_job_cid", &[]), Some(0));
}

#[test]
fn stale_damaged_and_foreign_commands() {
    let pose = Frame::from_array(POSE);
    let setup = env_setup("EX");
    let getpos = encode(&CommandFile {
        cid: 17,
        command: Command::GetPosition,
    });

    // Answered once; after a restart of the Submit side (last_cid
    // recovered from its own files) the same file is stale: no new result.
    let mut files = channel(&getpos);
    submit(&mut files, &setup, 1);
    let first = files.clone();
    assert_eq!(results(&files), [answer(17, ResultCode::Ok, pose)]);
    let g = submit(&mut files, &setup, 3);
    assert_eq!(g.int("kb_last_cid", &[]), Some(17));
    assert_eq!(files[RESULT_FILE], first[RESULT_FILE]);
    let s = state(&files);
    assert_eq!((s.last_cid, s.status), (17, ControllerStatus::Idle));
    assert!(s.seq > state(&first).seq, "seq continues above the file's");

    // A command file that ends before its END record (being written) is
    // not accepted; it is read again later.
    let settool = encode(&CommandFile {
        cid: 18,
        command: Command::SetTool(tool_frame()),
    });
    let cut = settool.lines().take(2).collect::<Vec<_>>().join("\n") + "\n";
    let mut files = channel(&cut);
    let g = submit(&mut files, &setup, 2);
    assert_eq!(g.int("kb_last_cid", &[]), Some(0));
    assert_eq!(results(&files), []);
    assert_eq!(state(&files).last_cid, 0);

    // A damaged header is ignored; a damaged body with an intact header is
    // answered BAD_COMMAND (PROTOCOL.md 9.3 step 4).
    let mut files = channel(&settool.replacen("CMD 2 18", "CMD 2 19", 1));
    let g = submit(&mut files, &setup, 1);
    assert_eq!(g.int("kb_last_cid", &[]), Some(0));
    assert_eq!(results(&files), []);
    let mut files = channel(&settool.replacen("100.000", "100.001", 1));
    let g = submit(&mut files, &setup, 1);
    assert_eq!(g.int("kb_last_cid", &[]), Some(18));
    assert_eq!(g.int("kb_job_cid", &[]), Some(0));
    assert_eq!(results(&files), [answer(18, ResultCode::BadCommand, pose)]);
    // Data after the END record.
    let mut files = channel(&format!("{settool}END 18 1 559\n"));
    submit(&mut files, &setup, 1);
    assert_eq!(results(&files), [answer(18, ResultCode::BadCommand, pose)]);
    // Trailing blank lines are fine.
    let mut files = channel(&format!("{settool}\n\n"));
    let g = submit(&mut files, &setup, 1);
    assert_eq!(g.int("kb_job_cid", &[]), Some(18));

    // Well-formed lines with contents the KRL side must refuse: an END
    // record that does not repeat the header's cid and n, a motion index
    // that is not the line's position, Status/Turn out of range.
    let batch = doc_batch();
    let records = command_records(&batch);
    let rebuild = |k: usize, vals: Vec<Val>| -> String {
        records
            .iter()
            .enumerate()
            .map(|(j, (tag, v))| line(tag, if j == k { &vals } else { v }))
            .collect()
    };
    let end = records.len() - 1;
    let mut lin = records[2].1.clone();
    lin[0] = Val::I(5);
    let mut ptp_s = records[1].1.clone();
    ptp_s[7] = Val::I(8);
    let mut ptp_t = records[1].1.clone();
    ptp_t[8] = Val::I(64);
    assert_eq!(rebuild(usize::MAX, Vec::new()), encode(&batch));
    for text in [
        rebuild(end, vec![Val::I(19), Val::I(3)]),
        rebuild(end, vec![Val::I(18), Val::I(4)]),
        rebuild(2, lin),
        rebuild(1, ptp_s),
        rebuild(1, ptp_t),
    ] {
        assert!(CommandFile::decode(&text).is_err(), "{text}");
        let mut files = channel(&text);
        let g = submit(&mut files, &setup, 1);
        assert_eq!(g.int("kb_job_cid", &[]), Some(0), "{text}");
        assert_eq!(
            results(&files),
            [answer(19, ResultCode::BadCommand, pose)],
            "{text}"
        );
    }

    // SETANOUT with a channel or a value outside the decoder's ranges
    // (index 1..32, value -1.000..1.000), or the wrong body count:
    // BAD_COMMAND, $ANOUT untouched.
    for (index, value, n) in [
        (0, 0.5, 1),
        (33, 0.5, 1),
        (-1, 0.5, 1),
        (1, 1.001, 1),
        (1, -1.001, 1),
        (8, 9999.999, 1),
        (8, 0.5, 2),
    ] {
        let cid = 41;
        let ano = line("ANO", &[Val::I(index), Val::R(value)]);
        let text = format!(
            "{}{}{}",
            line("CMD", &[Val::I(2), Val::I(cid), Val::I(15), Val::I(n)]),
            ano.repeat(n as usize),
            line("END", &[Val::I(cid), Val::I(n)]),
        );
        assert!(CommandFile::decode(&text).is_err(), "{text}");
        let mut files = channel(&text);
        let g = submit(&mut files, &setup, 1);
        assert_eq!(
            results(&files),
            [answer(41, ResultCode::BadCommand, pose)],
            "{text}"
        );
        for k in 1..=32 {
            assert_eq!(g.real("$ANOUT", &[k]), Some(0.0), "{text}");
        }
    }

    // Another protocol version, or an unknown op, with an intact header:
    // BAD_COMMAND.
    for (ver, op) in [(1, 3), (3, 3), (2, 2), (2, 99)] {
        let cid = 40;
        let text = format!(
            "CMD {ver} {cid} {op} 0 {}\nEND {cid} 0 {}\n",
            checksum([ver, cid, op, 0]),
            checksum([cid, 0])
        );
        let mut files = channel(&text);
        submit(&mut files, &setup, 1);
        assert_eq!(
            results(&files),
            [answer(40, ResultCode::BadCommand, pose)],
            "{text}"
        );
    }
}

#[test]
fn submit_side_recovers_the_reference_controllers_files() {
    // kb_res.txt and kb_state.txt as the Rust reference controller (or an
    // earlier run) left them: KsRecover parses them, KsWriteRes writes the
    // same history back byte for byte, and the state continues above.
    let history = sample_results(8);
    let res_text = history.encode().expect("encodes");
    let old_state = StateFile {
        seq: 290,
        last_cid: 5000,
        ..sample_state()
    };
    let mut files = BTreeMap::from([
        (RESULT_FILE.to_string(), res_text.clone()),
        (STATE_FILE.to_string(), old_state.encode().expect("encodes")),
    ]);
    let g = submit(&mut files, &env_setup("EX"), 0);
    assert_eq!(g.int("kb_hn", &[]), Some(8));
    assert_eq!(files[RESULT_FILE], res_text);
    assert_eq!(g.int("kb_last_cid", &[]), Some(5000));
    let s = state(&files);
    assert_eq!(
        (s.seq, s.last_cid, s.status),
        (291, 5000, ControllerStatus::Idle)
    );

    // A result CID above the state's last_cid wins.
    let old_state = StateFile {
        last_cid: 20,
        ..old_state
    };
    files.insert(STATE_FILE.to_string(), old_state.encode().expect("encodes"));
    let g = submit(&mut files, &env_setup("EX"), 0);
    let newest = history
        .results
        .iter()
        .map(|r| r.cid)
        .max()
        .expect("results");
    assert_eq!(g.int("kb_last_cid", &[]), Some(i64::from(newest)));

    // A damaged result file is not trusted: empty history, rewritten.
    let damaged = res_text.replacen("RSL 107", "RSL 108", 1);
    let mut files = BTreeMap::from([(RESULT_FILE.to_string(), damaged)]);
    let g = submit(&mut files, &env_setup("EX"), 0);
    assert_eq!(g.int("kb_hn", &[]), Some(0));
    assert_eq!(results(&files), []);
}

/// Command ids wrap from 2147483647 to 1 (PROTOCOL.md §8): the KRL side
/// accepts the id after the largest, and still refuses ids far behind
/// (a poisoned or very old id cannot make it execute a stale command).
#[test]
fn command_ids_wrap_at_the_top() {
    let pose = Frame::from_array(POSE);
    let getpos = |cid| {
        encode(&CommandFile {
            cid,
            command: Command::GetPosition,
        })
    };
    let at = |last: i64| format!("{}  kb_last_cid = {last}\n", env_setup("EX"));

    let mut files = channel(&getpos(1));
    let g = submit(&mut files, &at(2147483647), 1);
    assert_eq!(results(&files), [answer(1, ResultCode::Ok, pose)]);
    assert_eq!(g.int("kb_last_cid", &[]), Some(1));
    assert_eq!(state(&files).last_cid, 1);

    // 2^30 or more ids behind (here: the largest id after 5000) is old.
    let mut files = channel(&getpos(2147483000));
    let g = submit(&mut files, &at(5000), 1);
    assert_eq!(results(&files), []);
    assert_eq!(g.int("kb_last_cid", &[]), Some(5000));

    // Below the wrap it is the plain comparison.
    let mut files = channel(&getpos(5001));
    let g = submit(&mut files, &at(5000), 1);
    assert_eq!(results(&files), [answer(5001, ResultCode::Ok, pose)]);
    assert_eq!(g.int("kb_last_cid", &[]), Some(5001));
}

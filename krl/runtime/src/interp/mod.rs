//! The simulator's KRL interpreter.
//!
//! Runs an uploaded program's syntax tree ([`kuka_krl`]) ahead of motion,
//! like KRL's advance run, and turns it into the motions and dwells the
//! controller plays back.
//!
//! # Design
//!
//! [`run`] first calls [`check_subset`], which walks *every* routine of the
//! `.src` and every item of the `.dat` and refuses the first statement,
//! system variable or call outside the subset below (with its line) — a
//! program is never run with parts silently skipped. It then executes the
//! entry routine statement by statement (a tree-walking interpreter) and
//! returns the [`Step`]s: one [`Step::Move`] per motion (a spline block
//! becomes many) and one [`Step::Dwell`] per `WAIT SEC`. The controller
//! plans consecutive moves with the same tool and base as one blended batch.
//!
//! The interpreter tracks the **programmed** position itself, as the
//! advance run does: it starts at FK(start axes, `$TOOL`, `$BASE`) and after
//! each motion it is the motion's resolved target. `$POS_ACT` and
//! `$AXIS_ACT` read it; like on a KRC, reading them stops the advance run,
//! so the motion before is not approximated (exact stop) unless the
//! statement follows `CONTINUE`. The programmed axes are known at the start
//! and after an axis PTP; after a Cartesian motion reading `$AXIS_ACT` (or an
//! axis PTP with missing axes) is a runtime error, because the axes the
//! planner will reach are not known in advance. Assigning `$TOOL`/`$BASE`
//! re-expresses the programmed pose in the new frames.
//!
//! For tests, [`run_with_files`] runs a routine without the subset check
//! and returns the global variables; it also executes `STRUC` and `ENUM`
//! declarations (user-defined types), and it is a test harness: in-memory files behind `CWRITE($FCT_CALL, …)` and the
//! controller's system variables, so that the shipped KRL controller
//! program's file protocol code runs against the Rust encoder and decoder
//! (`tests/krl_protocol.rs`). The simulated controller uses neither.
//!
//! Values are typed like KRL: a declared variable holds a typed template
//! (uninitialised scalars are "unset" and reading one is an error), an
//! INT assigned a REAL rounds, `INT / INT` truncates, assigning a structure
//! value sets only the components it names (the others keep their values).
//! Names are case-insensitive.
//!
//! # The subset
//!
//! | Area | Supported | Refused by [`check_subset`] |
//! |---|---|---|
//! | Routines | `DEF`/`END`, `DEFFCT type`/`ENDFCT` of the same file, `IN` (by value) and `OUT` (by reference) parameters, `RETURN [value]`, recursion up to 64 levels | calls of routines not in the file (`CWRITE`, `EXT` routines, …), `EXT`/`EXTFCT` (except `EXT BAS`) |
//! | Declarations | `DECL` and implicit declarations of `INT`, `REAL`, `BOOL`, `CHAR`, `FRAME`, `POS`, `E6POS`, `AXIS`, `E6AXIS`, 1-D and 2-D arrays of them, initial values; `.dat` declarations and assignments are module globals | other types, `STRUC`, `ENUM`, `SIGNAL`, arrays with more than 2 dimensions (`.dat` declarations of other types, e.g. `FDAT`, are accepted but using such a variable is a runtime error) |
//! | Expressions | INT/REAL arithmetic, comparisons, `NOT AND OR EXOR`, `B_NOT B_AND B_OR B_EXOR`, structure values, components, indices, `:` (frame composition), `SIN COS TAN ASIN ACOS ATAN2(y, x) SQRT ABS` (degrees), strings into `CHAR` arrays | other functions |
//! | Control | `IF/ELSE`, `WHILE`, `FOR … TO … STEP`, `LOOP`/`EXIT`, `REPEAT/UNTIL`, `SWITCH/CASE/DEFAULT`, `CONTINUE`, `WAIT SEC` (a [`Step::Dwell`]), `WAIT FOR` on program variables (must be TRUE: FALSE would wait forever, a runtime error) | `HALT`, `BRAKE`, `RESUME`, `ON_ERROR_PROCEED`, `INTERRUPT` (except the INI fold's stop-message interrupt `INTERRUPT DECL n WHEN $STOPMESS==TRUE DO IR_STOPM()` and `INTERRUPT ON/OFF n` of it, accepted and ignored: the simulated controller handles its own stops), `TRIGGER`, `WAIT FOR` with any `$` variable (robot/IO) |
//! | Motions | `PTP`, `LIN`, `CIRC` and `_REL` forms; targets with missing components keep those of the programmed pose; `PTP` with `A1..A6` is an axis PTP; `S`/`T` of a PTP target are used, `E1..E6` ignored; `_REL`: position added in base coordinates, A/B/C rotate about the base axes at the TCP; `C_DIS`, `C_PTP`, `C_VEL`, `C_ORI` all approximate with `$APO.CDIS` (PTPs are never blended by the planner) | `CIRC … CA` |
//! | Splines | `SPLINE … ENDSPLINE` with `SLIN` (LIN), `SCIRC` (CIRC), `SPL` (centripetal Catmull-Rom curve through the points from the programmed pose, sampled into LINs of at most 5 mm with slerped orientation, each approximated by half its length), `WITH $VEL…/$ACC…` on a point (that segment only), `ENDSPLINE C_SPL` (else the block ends with an exact stop); inner `SLIN`/`SCIRC` points are approximated with `$APO.CDIS`; `PTP_SPLINE` with `SPTP` points (each a PTP) | `SPTP` in `SPLINE`, other points in `PTP_SPLINE`, other `WITH` variables |
//! | System variables | `$VEL` (`.CP` m/s; `ORI1`/`ORI2` accepted, ignored), `$VEL_AXIS[1..6]` (PTP speed = the smallest), `$ACC` (`.CP` m/s², sent as % of 2.3 m/s² clamped to 1..100), `$ACC_AXIS[1..6]`, `$APO` (`.CDIS`, default 1 mm; `CPTP`, `CVEL`, `CORI` ignored), `$TOOL`, `$BASE`, `$ADVANCE` (ignored); read only: `$POS_ACT`, `$AXIS_ACT`, `$NULLFRAME`, `$OV_PRO` (always 100) | every other system variable (`$OUT`, `$IN`, `$TIMER`, …) |
//! | Others | The standard INI fold: `BAS(#INITMOV, …)` resets `$VEL_AXIS`/`$ACC_AXIS`/`$VEL.CP`/`$ACC.CP` to the start speeds ([`Start::speed`]; `$TOOL`/`$BASE` stay), the stop-message interrupt (above); `XHOME` (E6AXIS, the model's home) | other `BAS` commands (so the pendant's inline forms with `BAS(#PTP_PARAMS)`, `PDAT_ACT`, `$BWDSTART`, `$H_POS`) |
//!
//! Runtime errors ([`RunError::Runtime`], with the line): undefined or
//! unset variables, type mismatches, index out of range, division by zero,
//! `WAIT FOR` FALSE, out-of-range `$VEL`/`$ACC`/`$APO` values.
//!
//! # Limits
//!
//! Work is bounded for every program. A run that does not end within
//! [`MAX_STATEMENTS`] statements, [`MAX_EVALUATIONS`] expression
//! evaluations or [`MAX_STEPS`] motions and waits ends with
//! [`RunError::TooLong`] (an endless loop, or a cyclic program). A program
//! that nests calls deeper than [`MAX_CALL_DEPTH`], calls, statements and
//! expressions together deeper than [`MAX_NESTING`], or whose variables
//! hold more than [`MAX_VALUE_CELLS`] values fails with [`RunError::Limit`]
//! (line and limit). The interpreter recurses on the thread's stack; with
//! the parser's limits ([`kuka_krl::limits`]) these keep the deepest run
//! within about 1.4 MiB of stack in a debug build (see
//! [`crate::program::DRY_RUN_STACK_BYTES`]). The subset check recurses
//! only as deep as the parser's limits allow.
//!
//! Also refused: a `_REL` motion with `#TOOL` (`#BASE` is the default and
//! runs), `CA` on `CIRC`/`SCIRC`, `WITH` directly after `SPLINE`. `C_SPL` on
//! a single spline point is accepted and has no effect (blending inside a
//! block is always on).
//!
//! # Layout
//!
//! This module holds the public types, the limits, the entry points and
//! the `Interp` state with its bookkeeping (errors, counters, nesting).
//! The rest is split by what it owns: `values` (the `Value` type and
//! its conversions), `operators`, `subset` ([`check_subset`]), `vars` and
//! `sysvars` (places and system variables), `decl` (declarations and
//! types), `eval` (expressions), `exec` (statements and calls), `motion`
//! and `splines` (steps from motion statements) and `harness`
//! ([`run_with_files`]).

mod decl;
mod eval;
mod exec;
mod harness;
mod host;
mod motion;
mod operators;
mod splines;
mod subset;
mod sysvars;
mod values;
mod vars;

use std::collections::{BTreeMap, HashMap};

use kuka_kinematics::{Axes, Motion, Pose, RobotModel};
use kuka_krl::{Expr, Program, Routine};
use kuka_protocol::SpeedRecord;

pub use harness::{Globals, OpenFiles, SharedOpenFiles};
pub use host::{Cancelled, Host, TriggerAt, Turn, Wait};
pub use subset::{check_hosted, check_subset};

use harness::Harness;
use values::{Value, axis_value, frame_value, real_struct};
use vars::Slot;

/// What the program starts from.
#[derive(Debug, Clone)]
pub struct Start<'a> {
    /// The robot model (for forward kinematics of axis targets and `$AXIS_ACT`).
    pub model: &'a RobotModel,
    /// Current axis angles.
    pub axes: Axes,
    /// Current `$TOOL`.
    pub tool: Pose,
    /// Current `$BASE`.
    pub base: Pose,
    /// Current default speeds (`$VEL_AXIS` %, `$ACC_AXIS` %, `$VEL.CP` m/s, `$ACC.CP` %).
    pub speed: SpeedRecord,
}

/// One thing for the controller to do, with the source line it came from.
// Moves dominate a program's steps; boxing them would only add indirection.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A motion, planned with this tool and base.
    Move {
        /// `$TOOL` in effect.
        tool: Pose,
        /// `$BASE` in effect.
        base: Pose,
        /// The motion (targets are TCP poses in `base`, as the planner takes them).
        motion: Motion,
        /// Source line.
        line: u32,
    },
    /// `WAIT SEC`: stand still.
    Dwell {
        /// Seconds.
        seconds: f64,
        /// Source line.
        line: u32,
    },
}

/// A statement, expression or system variable outside the simulator's subset.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {what} is not supported by the simulator")]
pub struct Unsupported {
    /// Source line.
    pub line: u32,
    /// What is not supported.
    pub what: String,
}

/// Why a program could not be run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// Outside the subset.
    #[error(transparent)]
    Unsupported(#[from] Unsupported),
    /// A runtime error (undefined variable, type mismatch, endless loop…).
    #[error("line {line}: {message}")]
    Runtime {
        /// Source line.
        line: u32,
        /// What went wrong.
        message: String,
    },
    /// The program is too deep or too large for the interpreter: it nests
    /// calls, statements and expressions beyond [`MAX_NESTING`] or
    /// [`MAX_CALL_DEPTH`], or its variables hold more than
    /// [`MAX_VALUE_CELLS`] values. The message names the limit.
    #[error("line {line}: {message}")]
    Limit {
        /// Source line where the limit was reached.
        line: u32,
        /// What limit, as a sentence with its name.
        message: String,
    },
    /// Hosted mode: the host cancelled the run ([`Cancelled`]).
    #[error("the program was cancelled")]
    Cancelled,
    /// Hosted mode, internal: `RESUME` unwinding to the routine that
    /// declared the interrupt (`depth` frames active there). Never
    /// returned by a run.
    #[error("RESUME outside the routine that declared the interrupt")]
    Resumed {
        /// Frames active in the declaring routine.
        depth: usize,
    },
    /// The program did not end within the statement, evaluation or step
    /// limit (an endless loop, or a cyclic program meant to run until
    /// stopped).
    #[error("line {line}: {message}")]
    TooLong {
        /// Source line where the limit was reached.
        line: u32,
        /// What limit.
        message: String,
        /// The steps produced until then.
        steps: Vec<Step>,
    },
}

/// Most statements (and loop iterations) one run may execute; then it
/// ends with [`RunError::TooLong`].
pub const MAX_STATEMENTS: u64 = 1_000_000;
/// Most expression evaluations (each operand and operator, and each value
/// of an array copied as a whole) one run may do; then it ends with
/// [`RunError::TooLong`]. With [`MAX_STATEMENTS`] it bounds a run's time
/// whatever the size of its expressions.
pub const MAX_EVALUATIONS: u64 = 10_000_000;
/// Most calls, statements and expressions being executed at once (a
/// statement inside a loop inside a routine called from an expression …
/// all count); beyond it the run fails with [`RunError::Limit`]. The
/// interpreter recurses on the thread's stack: this bounds its depth. It
/// is sized so that the deepest run runs on a 2 MiB stack in a debug build
/// (tested in `tests/limits.rs`), and leaves room for a recursion of
/// [`MAX_CALL_DEPTH`] levels in a realistic routine.
pub const MAX_NESTING: usize = 512;
/// Deepest routine nesting (calls active at once); beyond it the run fails
/// with [`RunError::Limit`] (an endless recursion, usually).
pub const MAX_CALL_DEPTH: usize = 64;
/// Most scalar values (an INT, each component of a FRAME, each element of
/// an array) the variables of a run hold at once; beyond it the run fails
/// with [`RunError::Limit`]. Bounds the memory of `DECL E6POS p[1000000]`
/// and of recursive routines with local arrays.
pub const MAX_VALUE_CELLS: usize = 2_000_000;
/// Largest array (elements).
pub const MAX_ARRAY: usize = 1_000_000;
/// Most steps (motions and waits) one run may produce; then it ends with
/// [`RunError::TooLong`].
pub const MAX_STEPS: usize = 100_000;
/// Channels of the analog I/O arrays `$ANIN[]` and `$ANOUT[]` (REALs,
/// normalised −1.0..1.0, 0.0 at start), as KSS 8.x declares them
/// (`kuka_protocol::MAX_ANALOG_INDEX`).
pub const ANALOG_CHANNELS: usize = 32;
/// `$ACC.CP` (m/s²) that is 100 % (the planner's default maximum).
pub const ACC_CP_MAX: f64 = 2.3;
/// `$APO.CDIS` at the start (mm).
const DEFAULT_CDIS: f64 = 1.0;
/// System variables a program may assign.
const SYS_WRITE: [&str; 8] = [
    "$VEL",
    "$VEL_AXIS",
    "$ACC",
    "$ACC_AXIS",
    "$APO",
    "$TOOL",
    "$BASE",
    "$ADVANCE",
];
/// System variables a program may only read.
const SYS_READ_ONLY: [&str; 4] = ["$POS_ACT", "$AXIS_ACT", "$NULLFRAME", "$OV_PRO"];

/// Source-like text of an lvalue/expression for messages.
fn describe(e: &Expr) -> String {
    match e {
        Expr::Var(n) => n.clone(),
        Expr::Index(b, i) if i.is_empty() => format!("{}[]", describe(b)),
        Expr::Index(b, _) => format!("{}[…]", describe(b)),
        Expr::Field(b, f) => format!("{}.{f}", describe(b)),
        Expr::Call(n, _) => format!("{n}()"),
        _ => "the value".into(),
    }
}

/// Runs `entry` and returns the steps it produces.
///
/// Calls [`check_subset`] first. The entry may be a `DEF` or a `DEFFCT`
/// (its value is discarded); it must not take parameters.
pub fn run(program: &Program, entry: &str, start: &Start<'_>) -> Result<Vec<Step>, RunError> {
    check_subset(program)?;
    let routine = entry_routine(program, entry)?;
    if !routine.params.is_empty() {
        return Err(RunError::Runtime {
            line: routine.line,
            message: format!(
                "the entry routine {} must not take parameters",
                routine.name
            ),
        });
    }
    let mut it = Interp::new(program, start);
    it.run_entry(routine)?;
    Ok(it.steps)
}

/// Runs `entry` in the **test harness**: like [`run`] without the subset
/// check (a statement outside it still fails when it is reached), plus an in-memory file system and the controller
/// environment a Submit-side KRL program needs. For tests that execute the
/// shipped controller program's file protocol code against the Rust
/// encoder and decoder; the simulated controller never uses it.
///
/// `files` maps bare file names (`"kb_cmd.txt"`) to their text. The run
/// reads and changes it; it holds the files as the program left them even
/// when the run fails.
///
/// What the harness adds:
///
/// - `CWRITE($FCT_CALL, st, md, "func", …)` with `st` a `STATE_T` and `md`
///   a `MODUS_T`; `st.RET1` is `#DATA_OK` on success, otherwise `#CMD_ABORT`
///   with `st.MSG_NO` −2 (`"r"` of a missing file, unknown mode), −3 (unknown
///   handle, or a handle opened the other way) or −4 (end of file):
///   - `"krl_fopen", name, mode, handle` (`name` a string or `CHAR` array;
///     mode `"r"` reads an existing file, `"w"` creates or truncates, `"a"`
///     appends; an optional fourth argument is ignored);
///   - `"krl_fgets", handle, buf[], size, count`: the next line without its
///     line end (LF or CR LF), at most `size` characters (a longer line
///     continues on the next call), copied into the `CHAR` array with a 0
///     after it if there is room; `count` = characters copied;
///   - `"krl_fwriteln", handle, buf[]` appends the `CHAR` array up to its
///     first 0 (or unset element) and LF; `"krl_fputs"` the same without LF;
///   - `"krl_fclose", handle` and `"krl_fclose_all"`.
///
///   Other `CWRITE` channels (`$CMD`) and functions are refused.
/// - The types `STATE_T` (`RET1`, `HITS`, `LENGTH`, `MSG_NO`), `MODUS_T`,
///   `CMD_STAT`, `MODE_OP` and `PRO_STATE`.
/// - System variables as plain variables that the program (or a test's
///   driver routine) may read and assign: `$POS_ACT` and `$AXIS_ACT`
///   (initially the start pose), `$MODE_OP` (`#T1`), `$OV_PRO` (100),
///   `$PRO_STATE1` (`#P_FREE`), `$PRO_NAME1[24]` (spaces), `$STOPMESS`
///   (FALSE), `$PERI_RDY` (TRUE), `$ROB_TIMER` (0) and `$ERR` (`NUMBER`,
///   `LINE`).
/// - `ON_ERROR_PROCEED`: a runtime error in the next statement sets
///   `$ERR.NUMBER` to 1 and `$ERR.LINE` to its line, and the program goes on
///   after that statement; `ERR_CLEAR($ERR)` sets both to 0.
/// - Up to 50,000,000 statements per run.
///
/// [`Globals::open_files`] lists the files still open at the end: a KRL
/// program must close every file it opens (PROTOCOL.md 10).
pub fn run_with_files(
    program: &Program,
    entry: &str,
    start: &Start<'_>,
    files: &mut BTreeMap<String, String>,
) -> Result<Globals, RunError> {
    let routine = entry_routine(program, entry)?;
    let mut it = Interp::new(program, start);
    it.enable_harness(std::mem::take(files));
    let r = it.run_entry(routine);
    let mut open_files = Vec::new();
    if let Some(h) = it.harness.take() {
        *files = h.files;
        open_files = harness::lock_open(&h.open).names();
    }
    r?;
    Ok(Globals {
        vars: it.globals,
        open_files,
    })
}

/// The file functions of a hosted run.
#[derive(Debug, Clone)]
pub struct HostedFiles {
    /// The folder `CWRITE($FCT_CALL, …)` opens bare names in.
    pub root: std::path::PathBuf,
    /// `RET1` of a file function that succeeded: `DATA_OK` (KUKA's text
    /// and working code), or `CMD_OK` to simulate a KSS that answers so.
    pub success: String,
    /// What `SREAD`/`SWRITE`'s offset means: 0 = the characters already
    /// read or written (as kuka-3d-tree uses it; the default), 1 = the
    /// 1-based position of the next character (the other reading of
    /// KUKA's text, to test that the shipped program copes with it).
    pub text_offset_base: i64,
    /// The controller's open files, shared by all its runs: a file a run
    /// leaves open (an error stop, a CANCEL, a forgotten `krl_fclose`)
    /// stays open and locked until `krl_fclose_all` or a new table (a
    /// reboot), as on a KRC.
    pub open: SharedOpenFiles,
    /// The interpreter the run is in (`"robot"`, `"submit"`): a handle
    /// belongs to the interpreter that opened it ([`OpenFiles`]).
    pub interpreter: String,
}

/// Runs `entry` on a [`Host`], a KRC-like runtime (see the `host`
/// module's documentation): with the test harness's controller
/// environment and file functions (on the files in `root`), without limits
/// on statements or time (a controller program runs until it is
/// cancelled), waiting where a KRC waits. Returns how the routine ended
/// ([`RunError::Cancelled`] when the host cancelled it) and the globals
/// as the program left them, whether it ended or failed (`None` when
/// cancelled: the host holds them then, as it did at the last turn).
pub fn run_hosted(
    program: &Program,
    entry: &str,
    start: &Start<'_>,
    host: Box<dyn Host + Send + '_>,
    files: HostedFiles,
) -> (Result<(), RunError>, Option<Globals>) {
    let routine = match entry_routine(program, entry) {
        Ok(r) => r,
        Err(e) => return (Err(e), None),
    };
    let mut it = Interp::new(program, start);
    it.enable_harness(BTreeMap::new());
    if let Some(h) = it.harness.as_mut() {
        h.root = Some(files.root);
        h.success = files.success;
        h.text_offset_base = files.text_offset_base;
        h.open = files.open;
        h.interpreter = files.interpreter;
    }
    it.max_statements = u64::MAX;
    it.max_evaluations = u64::MAX;
    it.hosted = Some(host::Hosted::new(host));
    // The END of the program is an advance-run stop: the run ends when its
    // last motion has, so that the path triggers of its last motions fire
    // (their actions run in this interpreter) and interrupts are served
    // until then.
    let r = it
        .run_entry(routine)
        .and_then(|()| it.host_wait(host::Wait::Standstill));
    // Files the run left open stay open in the shared table (their locks
    // hold) until krl_fclose_all or a reboot: a KRC does not close them.
    let globals = match r {
        Err(RunError::Cancelled) => None,
        _ => Some(Globals {
            vars: it.globals,
            open_files: Vec::new(),
        }),
    };
    (r, globals)
}

fn entry_routine<'p>(program: &'p Program, entry: &str) -> Result<&'p Routine, RunError> {
    program.routine(entry).ok_or_else(|| RunError::Runtime {
        line: 0,
        message: format!("the entry routine {entry} is not defined"),
    })
}

/// The interpreter's state during one run: the variables, the programmed
/// position, the steps so far and the counters of the limits.
struct Interp<'a> {
    program: &'a Program,
    model: &'a RobotModel,
    speed: SpeedRecord,
    globals: HashMap<String, Value>,
    frames: Vec<HashMap<String, Slot>>,
    steps: Vec<Step>,
    statements: u64,
    line: u32,
    /// Programmed TCP pose in the current `$BASE` with the current `$TOOL`.
    pos: Pose,
    /// Programmed axes, if known.
    axes: Option<Axes>,
    status: Option<u8>,
    turn: Option<u8>,
    /// Line of the last Cartesian motion (for `$AXIS_ACT` errors).
    cart_line: u32,
    continue_pending: bool,
    continue_active: bool,
    /// The family of the last motion: `Some(true)` spline (SPLINE blocks,
    /// SLIN/SCIRC/SPTP), `Some(false)` conventional (PTP/LIN/CIRC). The two
    /// are planned by different motion planners on a KRC and never blend
    /// into each other ([`Interp::planner_boundary`]).
    last_family: Option<bool>,
    /// User-defined (`STRUC`, `ENUM`) and harness types: upper-case name
    /// and typed template.
    types: HashMap<String, Value>,
    max_statements: u64,
    /// Expression evaluations so far ([`MAX_EVALUATIONS`]).
    evaluations: u64,
    max_evaluations: u64,
    /// Calls, statements and expressions being executed ([`MAX_NESTING`]).
    nesting: usize,
    /// Scalar values the variables hold ([`MAX_VALUE_CELLS`]).
    cells: usize,
    /// The part of `cells` in each of `frames` (released with it).
    frame_cells: Vec<usize>,
    /// The `.src` routines by upper-case name.
    routines: HashMap<String, &'a Routine>,
    /// The test harness of [`run_with_files`], if active.
    harness: Option<Harness>,
    /// `ON_ERROR_PROCEED` guards the next statement (harness only).
    error_proceed: bool,
    /// Hosted mode ([`run_hosted`]): the host and the interrupts,
    /// triggers and waits it drives.
    hosted: Option<host::Hosted<'a>>,
    /// The `.dat` items are being executed (no host turns yet).
    initializing: bool,
}

impl<'a> Interp<'a> {
    fn new(program: &'a Program, start: &Start<'a>) -> Self {
        let sp = start.speed;
        let mut g = HashMap::new();
        g.insert(
            "$VEL".into(),
            real_struct(
                "VEL_STRUC",
                &[("CP", sp.cp_velocity), ("ORI1", 200.0), ("ORI2", 200.0)],
            ),
        );
        g.insert(
            "$ACC".into(),
            real_struct(
                "ACC_STRUC",
                &[
                    ("CP", sp.cp_acceleration_pct / 100.0 * ACC_CP_MAX),
                    ("ORI1", 100.0),
                    ("ORI2", 100.0),
                ],
            ),
        );
        let arr = |v: f64| Value::Array(vec![6], vec![Value::Real(v); 6]);
        g.insert("$VEL_AXIS".into(), arr(sp.ptp_velocity_pct));
        g.insert("$ACC_AXIS".into(), arr(sp.ptp_acceleration_pct));
        g.insert(
            "$APO".into(),
            Value::Struct(
                "APO_STRUC".into(),
                vec![
                    ("CDIS".into(), Value::Real(DEFAULT_CDIS)),
                    ("CPTP".into(), Value::Int(50)),
                    ("CVEL".into(), Value::Int(100)),
                    ("CORI".into(), Value::Real(1.0)),
                ],
            ),
        );
        g.insert("$TOOL".into(), frame_value(&start.tool));
        g.insert("$BASE".into(), frame_value(&start.base));
        g.insert("$ADVANCE".into(), Value::Int(3));
        g.insert("XHOME".into(), axis_value(&start.model.home));
        let axes = start.axes;
        let mut routines = HashMap::new();
        for r in &program.src.routines {
            routines.entry(r.name.to_ascii_uppercase()).or_insert(r);
        }
        Interp {
            program,
            model: start.model,
            speed: sp,
            globals: g,
            frames: Vec::new(),
            steps: Vec::new(),
            statements: 0,
            line: 0,
            pos: start.model.forward(&axes, &start.tool, &start.base),
            axes: Some(axes),
            status: Some(start.model.status(&axes)),
            turn: Some(RobotModel::turn(&axes)),
            cart_line: 0,
            continue_pending: false,
            last_family: None,
            continue_active: false,
            types: HashMap::new(),
            max_statements: MAX_STATEMENTS,
            evaluations: 0,
            max_evaluations: MAX_EVALUATIONS,
            nesting: 0,
            cells: 0,
            frame_cells: Vec::new(),
            routines,
            harness: None,
            error_proceed: false,
            hosted: None,
            initializing: false,
        }
    }

    /// Executes the `.dat` items, then `routine` (no arguments).
    fn run_entry(&mut self, routine: &'a Routine) -> Result<(), RunError> {
        self.initializing = true;
        if let Some(dat) = &self.program.dat {
            for s in &dat.items {
                if let Err(e) = self.exec(s) {
                    self.initializing = false;
                    return Err(e);
                }
            }
        }
        self.initializing = false;
        self.call_routine(routine, &[])?;
        Ok(())
    }

    fn err(&self, msg: impl Into<String>) -> RunError {
        RunError::Runtime {
            line: self.line,
            message: msg.into(),
        }
    }

    fn tick(&mut self) -> Result<(), RunError> {
        self.statements += 1;
        if self.statements > self.max_statements {
            return Err(RunError::TooLong {
                line: self.line,
                message: format!(
                    "the program did not finish within {} statements (endless loop?)",
                    self.max_statements
                ),
                steps: std::mem::take(&mut self.steps),
            });
        }
        if self.hosted.is_some() && !self.initializing {
            self.host_statement()?;
        }
        Ok(())
    }

    /// Counts `n` evaluations against [`MAX_EVALUATIONS`].
    fn charge(&mut self, n: u64) -> Result<(), RunError> {
        self.evaluations = self.evaluations.saturating_add(n);
        if self.evaluations > self.max_evaluations {
            return Err(RunError::TooLong {
                line: self.line,
                message: format!(
                    "the program did not finish within {} expression evaluations (endless loop?)",
                    self.max_evaluations
                ),
                steps: std::mem::take(&mut self.steps),
            });
        }
        Ok(())
    }

    fn limit(&self, message: String) -> RunError {
        RunError::Limit {
            line: self.line,
            message,
        }
    }

    /// One level deeper (a call, statement or expression): checks
    /// [`MAX_NESTING`]. Every `enter` is paired with `self.nesting -= 1`
    /// on every path, errors included.
    fn enter(&mut self) -> Result<(), RunError> {
        if self.nesting >= MAX_NESTING {
            return Err(self.limit(format!(
                "calls, statements and expressions nested deeper than {MAX_NESTING} levels at once (limit MAX_NESTING)"
            )));
        }
        self.nesting += 1;
        Ok(())
    }

    /// Counts `n` more values held by variables (of the current routine's
    /// frame, or global) against [`MAX_VALUE_CELLS`].
    fn hold(&mut self, n: usize) -> Result<(), RunError> {
        let total = self.cells.saturating_add(n);
        if total > MAX_VALUE_CELLS {
            return Err(self.limit(format!(
                "the variables would hold more than {MAX_VALUE_CELLS} values (limit MAX_VALUE_CELLS)"
            )));
        }
        self.cells = total;
        if let Some(f) = self.frame_cells.last_mut() {
            *f += n;
        }
        Ok(())
    }

    /// Before a motion of the `spline` family: where the previous motion
    /// was of the other family, it ends in an exact stop — a KRC plans the
    /// conventional motions (PTP, LIN, CIRC) and the spline ones (SPLINE
    /// blocks, SLIN, SCIRC, SPTP) with two motion planners that cannot
    /// approximate into each other (docs/CONTROLLER.md 21).
    pub(super) fn planner_boundary(&mut self, spline: bool) -> Result<(), RunError> {
        let other = self.last_family.is_some_and(|f| f != spline);
        self.last_family = Some(spline);
        if !other {
            return Ok(());
        }
        if self.hosted.is_some() {
            // Queued motions cannot change: an advance-run stop lets the
            // robot finish them (it stops at the last one's end point).
            return self.host_advance_stop();
        }
        if let Some(Step::Move { motion, .. }) = self.steps.last_mut() {
            motion.approx_mm = 0.0;
        }
        Ok(())
    }

    fn push(&mut self, step: Step) -> Result<(), RunError> {
        if self.hosted.is_some() {
            return self.host_step(step);
        }
        if self.steps.len() >= MAX_STEPS {
            return Err(RunError::TooLong {
                line: self.line,
                message: format!(
                    "the program did not finish within {MAX_STEPS} motions and waits (endless loop?)"
                ),
                steps: std::mem::take(&mut self.steps),
            });
        }
        self.steps.push(step);
        Ok(())
    }
}

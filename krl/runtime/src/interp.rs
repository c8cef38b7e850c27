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

use std::collections::{BTreeMap, HashMap};

use kuka_kinematics::plan::MAX_CP_VELOCITY;
use kuka_kinematics::{Axes, Motion, MotionKind as MoveKind, Pose, RobotModel};
use kuka_krl::{
    BinOp, Expr, MotionKind as KrlMotion, Program, Routine, RoutineKind, SplinePoint,
    SplinePointKind, Stmt, StmtKind, UnOp,
};
use kuka_protocol::SpeedRecord;

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
/// Most statements in the test harness ([`run_with_files`]), which runs
/// the controller program's character-by-character parser over whole files.
const HARNESS_MAX_STATEMENTS: u64 = 50_000_000;
/// Most expression evaluations in the test harness.
const HARNESS_MAX_EVALUATIONS: u64 = 1_000_000_000;
/// `MSG_NO` of the harness's `CWRITE($FCT_CALL, …)`: the file is missing
/// (`"r"`) or the mode is unknown.
const MSG_NO_OPEN: i64 = -2;
/// `MSG_NO`: no open file has this handle (or it is open the other way).
const MSG_NO_HANDLE: i64 = -3;
/// `MSG_NO` of `krl_fgets` at the end of the file (PROTOCOL.md 12).
const MSG_NO_EOF: i64 = -4;
/// Most steps (motions and waits) one run may produce; then it ends with
/// [`RunError::TooLong`].
pub const MAX_STEPS: usize = 100_000;
/// Longest LIN an `SPL` curve is sampled into (mm); a little below 5 mm
/// so the chords stay under 5 mm despite the arc-length table's error.
const SPL_SAMPLE_MM: f64 = 4.9;
/// `$ACC.CP` (m/s²) that is 100 % (the planner's default maximum).
const ACC_CP_MAX: f64 = 2.3;
/// `$APO.CDIS` at the start (mm).
const DEFAULT_CDIS: f64 = 1.0;

const FRAME_FIELDS: [&str; 6] = ["X", "Y", "Z", "A", "B", "C"];
const AXIS_FIELDS: [&str; 6] = ["A1", "A2", "A3", "A4", "A5", "A6"];
const EXT_FIELDS: [&str; 6] = ["E1", "E2", "E3", "E4", "E5", "E6"];
const BUILTINS: [&str; 8] = ["SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN2", "SQRT", "ABS"];
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

// ---------------------------------------------------------------- values

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    Int,
    Real,
    Bool,
    Char,
    /// A variable of an enumeration type (its values are not checked).
    Enum,
}

/// A KRL value. Declared variables hold typed templates: `Unset` scalars
/// are declared but not yet assigned.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Unset(Scalar),
    Int(i64),
    Real(f64),
    Bool(bool),
    Char(u8),
    Str(String),
    Enum(String),
    /// Type name (upper case, may be empty for a literal) and components.
    Struct(String, Vec<(String, Value)>),
    /// Dimensions and elements (row-major).
    Array(Vec<usize>, Vec<Value>),
    /// A `.dat` variable of a type outside the subset.
    Opaque(String),
}

impl Value {
    fn type_name(&self) -> String {
        match self {
            Value::Unset(Scalar::Int) | Value::Int(_) => "INT".into(),
            Value::Unset(Scalar::Real) | Value::Real(_) => "REAL".into(),
            Value::Unset(Scalar::Bool) | Value::Bool(_) => "BOOL".into(),
            Value::Unset(Scalar::Char) | Value::Char(_) => "CHAR".into(),
            Value::Unset(Scalar::Enum) => "an ENUM".into(),
            Value::Str(_) => "a string".into(),
            Value::Enum(e) => format!("#{e}"),
            Value::Struct(t, _) if t.is_empty() => "a structure value".into(),
            Value::Struct(t, _) => t.clone(),
            Value::Array(..) => "an array".into(),
            Value::Opaque(t) => t.clone(),
        }
    }

    fn scalar_kind(&self) -> Option<Scalar> {
        match self {
            Value::Unset(s) => Some(*s),
            Value::Int(_) => Some(Scalar::Int),
            Value::Real(_) => Some(Scalar::Real),
            Value::Bool(_) => Some(Scalar::Bool),
            Value::Char(_) => Some(Scalar::Char),
            _ => None,
        }
    }

    fn num(&self) -> Result<f64, String> {
        match self {
            Value::Int(i) => Ok(*i as f64),
            Value::Real(r) => Ok(*r),
            Value::Char(c) => Ok(f64::from(*c)),
            v => Err(format!("expected a number, found {}", v.type_name())),
        }
    }

    fn int(&self) -> Result<i64, String> {
        match self {
            Value::Int(i) => Ok(*i),
            Value::Char(c) => Ok(i64::from(*c)),
            v => Err(format!("expected an INT, found {}", v.type_name())),
        }
    }

    fn bool(&self) -> Result<bool, String> {
        match self {
            Value::Bool(b) => Ok(*b),
            v => Err(format!("expected a BOOL, found {}", v.type_name())),
        }
    }
}

/// The typed, unset value of a declared type (upper-case name).
fn template(ty: &str) -> Option<Value> {
    let ty = ty.to_ascii_uppercase();
    let unset = |names: &[&str], s: Scalar| -> Vec<(String, Value)> {
        names
            .iter()
            .map(|n| (n.to_string(), Value::Unset(s)))
            .collect()
    };
    Some(match ty.as_str() {
        "INT" => Value::Unset(Scalar::Int),
        "REAL" => Value::Unset(Scalar::Real),
        "BOOL" => Value::Unset(Scalar::Bool),
        "CHAR" => Value::Unset(Scalar::Char),
        "FRAME" => Value::Struct(ty, unset(&FRAME_FIELDS, Scalar::Real)),
        "POS" | "E6POS" => {
            let mut f = unset(&FRAME_FIELDS, Scalar::Real);
            f.extend(unset(&["S", "T"], Scalar::Int));
            if ty == "E6POS" {
                f.extend(unset(&EXT_FIELDS, Scalar::Real));
            }
            Value::Struct(ty, f)
        }
        "AXIS" | "E6AXIS" => {
            let mut f = unset(&AXIS_FIELDS, Scalar::Real);
            if ty == "E6AXIS" {
                f.extend(unset(&EXT_FIELDS, Scalar::Real));
            }
            Value::Struct(ty, f)
        }
        _ => return None,
    })
}

fn real_struct(ty: &str, fields: &[(&str, f64)]) -> Value {
    Value::Struct(
        ty.into(),
        fields
            .iter()
            .map(|(n, v)| (n.to_string(), Value::Real(*v)))
            .collect(),
    )
}

fn frame_value(p: &Pose) -> Value {
    let a = p.to_array();
    let fields: Vec<(&str, f64)> = FRAME_FIELDS.iter().copied().zip(a).collect();
    real_struct("FRAME", &fields)
}

fn axis_value(axes: &Axes) -> Value {
    let mut fields: Vec<(&str, f64)> = AXIS_FIELDS.iter().copied().zip(*axes).collect();
    fields.extend(EXT_FIELDS.iter().map(|n| (*n, 0.0)));
    real_struct("E6AXIS", &fields)
}

fn find<'v>(fields: &'v [(String, Value)], name: &str) -> Option<&'v Value> {
    fields.iter().find(|(n, _)| n == name).map(|(_, v)| v)
}

/// A numeric component, `None` if absent or unset.
fn num_field(fields: &[(String, Value)], name: &str) -> Result<Option<f64>, String> {
    match find(fields, name) {
        None | Some(Value::Unset(_)) => Ok(None),
        Some(v) => v
            .num()
            .map(Some)
            .map_err(|e| format!("component {name}: {e}")),
    }
}

/// The six FRAME components of a FRAME/POS/E6POS value, all required.
fn pose_of(v: &Value) -> Result<Pose, String> {
    let Value::Struct(_, f) = v else {
        return Err(format!("expected a FRAME, found {}", v.type_name()));
    };
    let mut a = [0.0; 6];
    for (slot, name) in a.iter_mut().zip(FRAME_FIELDS) {
        *slot = num_field(f, name)?
            .ok_or_else(|| format!("component {name} of the {} has no value", v.type_name()))?;
    }
    Ok(Pose::new(a[0], a[1], a[2], a[3], a[4], a[5]))
}

/// Converts `v` to the scalar type `kind` (KRL assignment rules).
fn convert(kind: Scalar, v: Value) -> Result<Value, String> {
    Ok(match (kind, v) {
        (k, Value::Unset(_)) => Value::Unset(k),
        (Scalar::Int, Value::Int(i)) => Value::Int(i),
        (Scalar::Int, Value::Real(r)) => {
            let r = r.round();
            if !(r.is_finite() && r >= f64::from(i32::MIN) && r <= f64::from(i32::MAX)) {
                return Err(format!("{r} does not fit into an INT"));
            }
            Value::Int(r as i64)
        }
        (Scalar::Int, Value::Char(c)) => Value::Int(i64::from(c)),
        (Scalar::Real, Value::Int(i)) => Value::Real(i as f64),
        (Scalar::Real, Value::Real(r)) => Value::Real(r),
        (Scalar::Bool, Value::Bool(b)) => Value::Bool(b),
        (Scalar::Char, Value::Char(c)) => Value::Char(c),
        (Scalar::Char, Value::Int(i)) if (0..=255).contains(&i) => Value::Char(i as u8),
        (Scalar::Char, Value::Str(s)) if s.len() == 1 => Value::Char(s.as_bytes()[0]),
        (Scalar::Enum, Value::Enum(e)) => Value::Enum(e),
        (k, v) => {
            return Err(format!(
                "cannot assign {} to a {}",
                v.type_name(),
                Value::Unset(k).type_name()
            ));
        }
    })
}

/// Assigns `v` into the typed `slot`: scalars convert, structure values set
/// only the components they name.
fn assign_into(slot: &mut Value, v: Value) -> Result<(), String> {
    if let Some(kind) = slot.scalar_kind() {
        *slot = convert(kind, v)?;
        return Ok(());
    }
    match (slot, v) {
        (Value::Struct(ty, fields), Value::Struct(_, new)) => {
            for (name, val) in new {
                if matches!(val, Value::Unset(_)) {
                    continue;
                }
                let Some((_, f)) = fields.iter_mut().find(|(n, _)| *n == name) else {
                    return Err(format!("{ty} has no component {name}"));
                };
                assign_into(f, val).map_err(|e| format!("component {name}: {e}"))?;
            }
            Ok(())
        }
        (Value::Array(dims, elems), Value::Array(d2, e2)) if *dims == d2 => {
            for (a, b) in elems.iter_mut().zip(e2) {
                if !matches!(b, Value::Unset(_)) {
                    assign_into(a, b)?;
                }
            }
            Ok(())
        }
        (Value::Array(dims, elems), Value::Str(s))
            if dims.len() == 1
                && elems.first().and_then(Value::scalar_kind) == Some(Scalar::Char) =>
        {
            if s.len() > elems.len() {
                return Err(format!(
                    "the string has {} characters, the array only {}",
                    s.len(),
                    elems.len()
                ));
            }
            let bytes = s.as_bytes();
            for (i, e) in elems.iter_mut().enumerate() {
                *e = bytes
                    .get(i)
                    .map_or(Value::Unset(Scalar::Char), |b| Value::Char(*b));
            }
            Ok(())
        }
        (Value::Enum(e), Value::Enum(n)) => {
            *e = n;
            Ok(())
        }
        (Value::Opaque(t), _) => Err(format!("variables of type {t} are not supported")),
        (slot, v) => Err(format!(
            "cannot assign {} to {}",
            v.type_name(),
            slot.type_name()
        )),
    }
}

#[derive(Debug, Clone, PartialEq)]
enum PathElem {
    /// 1-based indices; empty = the whole array (`name[]`).
    Index(Vec<i64>),
    Field(String),
}

fn flat_index(dims: &[usize], idx: &[i64]) -> Result<usize, String> {
    if idx.len() != dims.len() {
        return Err(format!(
            "{} indices for an array of {} dimensions",
            idx.len(),
            dims.len()
        ));
    }
    let mut flat = 0usize;
    for (&i, &d) in idx.iter().zip(dims) {
        if i < 1 || i as u64 > d as u64 {
            return Err(format!("index {i} is out of range 1..{d}"));
        }
        flat = flat * d + (i - 1) as usize;
    }
    Ok(flat)
}

fn step_into<'v>(v: &'v Value, p: &PathElem) -> Result<&'v Value, String> {
    match (v, p) {
        (v, PathElem::Index(i)) if i.is_empty() => Ok(v),
        (Value::Array(d, e), PathElem::Index(i)) => {
            let k = flat_index(d, i)?;
            e.get(k).ok_or_else(|| "index out of range".to_string())
        }
        (Value::Struct(ty, f), PathElem::Field(n)) => {
            find(f, n).ok_or_else(|| format!("{ty} has no component {n}"))
        }
        (v, PathElem::Index(_)) => Err(format!("{} is not an array", v.type_name())),
        (v, PathElem::Field(n)) => Err(format!("{} has no component {n}", v.type_name())),
    }
}

fn walk<'v>(mut v: &'v Value, path: &[PathElem]) -> Result<&'v Value, String> {
    for p in path {
        v = step_into(v, p)?;
    }
    Ok(v)
}

fn walk_mut<'v>(mut v: &'v mut Value, path: &[PathElem]) -> Result<&'v mut Value, String> {
    for p in path {
        if matches!(p, PathElem::Index(i) if i.is_empty()) {
            continue;
        }
        v = match (v, p) {
            (Value::Array(d, e), PathElem::Index(i)) => {
                let k = flat_index(d, i)?;
                e.get_mut(k)
                    .ok_or_else(|| "index out of range".to_string())?
            }
            (Value::Struct(ty, f), PathElem::Field(n)) => {
                let ty = ty.clone();
                f.iter_mut()
                    .find(|(k, _)| k == n)
                    .map(|(_, v)| v)
                    .ok_or_else(|| format!("{ty} has no component {n}"))?
            }
            (v, PathElem::Index(_)) => return Err(format!("{} is not an array", v.type_name())),
            (v, PathElem::Field(n)) => {
                return Err(format!("{} has no component {n}", v.type_name()));
            }
        };
    }
    Ok(v)
}

// ---------------------------------------------------------------- operators

fn int_result(v: Option<i64>) -> Result<Value, String> {
    match v {
        Some(i) if i >= i64::from(i32::MIN) && i <= i64::from(i32::MAX) => Ok(Value::Int(i)),
        _ => Err("INT overflow".into()),
    }
}

fn real_result(r: f64) -> Result<Value, String> {
    if r.is_finite() {
        Ok(Value::Real(r))
    } else {
        Err("REAL overflow".into())
    }
}

fn values_equal(l: &Value, r: &Value) -> Result<bool, String> {
    Ok(match (l, r) {
        (Value::Bool(a), Value::Bool(b)) => a == b,
        (Value::Enum(a), Value::Enum(b)) => a == b,
        (Value::Str(a), Value::Str(b)) => a == b,
        (Value::Int(a), Value::Int(b)) => a == b,
        (a, b) => match (a.num(), b.num()) {
            (Ok(x), Ok(y)) => x == y,
            _ => {
                return Err(format!(
                    "cannot compare {} with {}",
                    a.type_name(),
                    b.type_name()
                ));
            }
        },
    })
}

fn binary(op: BinOp, l: Value, r: Value) -> Result<Value, String> {
    match op {
        BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div => {
            if let (Value::Int(a), Value::Int(b)) = (&l, &r) {
                let (a, b) = (*a, *b);
                return match op {
                    BinOp::Add => int_result(a.checked_add(b)),
                    BinOp::Sub => int_result(a.checked_sub(b)),
                    BinOp::Mul => int_result(a.checked_mul(b)),
                    _ if b == 0 => Err("division by zero".into()),
                    _ => int_result(a.checked_div(b)),
                };
            }
            let (a, b) = (l.num()?, r.num()?);
            match op {
                BinOp::Add => real_result(a + b),
                BinOp::Sub => real_result(a - b),
                BinOp::Mul => real_result(a * b),
                _ if b == 0.0 => Err("division by zero".into()),
                _ => real_result(a / b),
            }
        }
        BinOp::Eq => Ok(Value::Bool(values_equal(&l, &r)?)),
        BinOp::Ne => Ok(Value::Bool(!values_equal(&l, &r)?)),
        BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
            let (a, b) = (l.num()?, r.num()?);
            Ok(Value::Bool(match op {
                BinOp::Lt => a < b,
                BinOp::Le => a <= b,
                BinOp::Gt => a > b,
                _ => a >= b,
            }))
        }
        BinOp::And | BinOp::Or | BinOp::Exor => {
            let (a, b) = (l.bool()?, r.bool()?);
            Ok(Value::Bool(match op {
                BinOp::And => a && b,
                BinOp::Or => a || b,
                _ => a != b,
            }))
        }
        BinOp::BAnd | BinOp::BOr | BinOp::BExor => {
            let (a, b) = (l.int()?, r.int()?);
            Ok(Value::Int(match op {
                BinOp::BAnd => a & b,
                BinOp::BOr => a | b,
                _ => a ^ b,
            }))
        }
        BinOp::Geo => {
            // The result has the right operand's type (S, T, E1..E6 kept).
            let p = pose_of(&l)?.compose(&pose_of(&r)?);
            let Value::Struct(ty, mut fields) = r else {
                return Err("the geometric operator needs FRAME/POS values".into());
            };
            for (name, v) in FRAME_FIELDS.iter().zip(p.to_array()) {
                if let Some((_, f)) = fields.iter_mut().find(|(n, _)| n == name) {
                    *f = Value::Real(v);
                }
            }
            Ok(Value::Struct(ty, fields))
        }
    }
}

fn builtin(name: &str, args: &[Value]) -> Result<Value, String> {
    let want = if name == "ATAN2" { 2 } else { 1 };
    if args.len() != want {
        return Err(format!(
            "{name} takes {want} argument(s), got {}",
            args.len()
        ));
    }
    if name == "ABS"
        && let Value::Int(i) = args[0]
    {
        return int_result(i.checked_abs());
    }
    let x = args[0].num().map_err(|e| format!("{name}: {e}"))?;
    let r = match name {
        "SIN" => x.to_radians().sin(),
        "COS" => x.to_radians().cos(),
        "TAN" => x.to_radians().tan(),
        "ASIN" | "ACOS" => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(format!("{name}({x}): the argument must be within -1..1"));
            }
            if name == "ASIN" {
                x.asin().to_degrees()
            } else {
                x.acos().to_degrees()
            }
        }
        "ATAN2" => {
            let xx = args[1].num().map_err(|e| format!("{name}: {e}"))?;
            x.atan2(xx).to_degrees()
        }
        "SQRT" => {
            if x < 0.0 {
                return Err(format!("SQRT({x}) of a negative number"));
            }
            x.sqrt()
        }
        _ => x.abs(),
    };
    real_result(r)
}

/// The scalar values `v` holds (for [`MAX_VALUE_CELLS`]): 1 for a scalar,
/// the components of a structure, the elements of an array (all of one
/// shape, so the first one is counted).
fn cells(v: &Value) -> usize {
    match v {
        Value::Struct(_, f) => f.iter().map(|(_, v)| cells(v)).sum::<usize>().max(1),
        Value::Array(_, e) => e.first().map_or(0, cells).saturating_mul(e.len()),
        _ => 1,
    }
}

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

// ---------------------------------------------------------------- subset check

/// Refuses, before anything runs, every statement outside the subset.
///
/// Walks every routine of the `.src` (called or not) and every item of the
/// `.dat`; see the module documentation for the subset.
pub fn check_subset(program: &Program) -> Result<(), Unsupported> {
    let mut prios = Vec::new();
    for r in &program.src.routines {
        stopm_prios(&r.body, &mut prios);
    }
    let routines: std::collections::HashSet<String> = program
        .src
        .routines
        .iter()
        .map(|r| r.name.to_ascii_uppercase())
        .collect();
    if let Some(dat) = &program.dat {
        let c = Checker {
            routines: routines.clone(),
            in_dat: true,
            stopm_prios: Vec::new(),
        };
        c.block(&dat.items)?;
    }
    let c = Checker {
        routines,
        in_dat: false,
        stopm_prios: prios,
    };
    for r in &program.src.routines {
        if let RoutineKind::DefFct(ty) = &r.kind
            && template(ty).is_none()
        {
            return c.refuse(r.line, format!("a function returning {ty}"));
        }
        c.block(&r.body)?;
    }
    Ok(())
}

struct Checker {
    /// Upper-case names of the `.src` routines (a set: a file of many
    /// routines and calls must not cost quadratic time).
    routines: std::collections::HashSet<String>,
    in_dat: bool,
    /// Priorities of the standard stop-message interrupt (INI fold).
    stopm_prios: Vec<i64>,
}

/// `INTERRUPT DECL n WHEN $STOPMESS == TRUE DO IR_STOPM()`, the standard
/// stop-message interrupt of the INI fold: accepted and ignored (the
/// simulated controller handles its own stops).
fn is_stopm_decl(k: &StmtKind) -> bool {
    let StmtKind::InterruptDecl { prio, when, action } = k else {
        return false;
    };
    matches!(prio, Expr::Int(_))
        && matches!(&action.kind, StmtKind::Call { name, args } if name.eq_ignore_ascii_case("IR_STOPM") && args.is_empty())
        && matches!(when, Expr::Binary(BinOp::Eq, a, b)
            if matches!(&**a, Expr::Var(v) if v.eq_ignore_ascii_case("$STOPMESS"))
                && **b == Expr::Bool(true))
}

/// Priorities of the stop-message interrupts declared anywhere in `body`.
fn stopm_prios(body: &[Stmt], out: &mut Vec<i64>) {
    for s in body {
        match &s.kind {
            StmtKind::InterruptDecl {
                prio: Expr::Int(p), ..
            } if is_stopm_decl(&s.kind) => out.push(*p),
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                stopm_prios(then_body, out);
                stopm_prios(else_body, out);
            }
            StmtKind::While { body, .. }
            | StmtKind::For { body, .. }
            | StmtKind::Loop { body }
            | StmtKind::Repeat { body, .. } => stopm_prios(body, out),
            StmtKind::Switch { cases, default, .. } => {
                for (_, b) in cases {
                    stopm_prios(b, out);
                }
                if let Some(d) = default {
                    stopm_prios(d, out);
                }
            }
            _ => {}
        }
    }
}

fn root_name(e: &Expr) -> Option<&str> {
    match e {
        Expr::Var(n) => Some(n),
        Expr::Index(b, _) | Expr::Field(b, _) => root_name(b),
        _ => None,
    }
}

fn mentions_system(e: &Expr) -> bool {
    match e {
        Expr::Var(n) => n.starts_with('$'),
        Expr::Index(b, i) => mentions_system(b) || i.iter().any(mentions_system),
        Expr::Field(b, _) | Expr::Unary(_, b) => mentions_system(b),
        Expr::Call(_, a) => a.iter().any(mentions_system),
        Expr::Struct { fields, .. } => fields.iter().any(|(_, v)| mentions_system(v)),
        Expr::Binary(_, a, b) => mentions_system(a) || mentions_system(b),
        _ => false,
    }
}

impl Checker {
    fn is_routine(&self, name: &str) -> bool {
        self.routines.contains(&name.to_ascii_uppercase())
    }

    fn refuse(&self, line: u32, what: impl Into<String>) -> Result<(), Unsupported> {
        let mut what = what.into();
        if self.in_dat {
            what.push_str(" (in the .dat file)");
        }
        Err(Unsupported { line, what })
    }

    fn block(&self, b: &[Stmt]) -> Result<(), Unsupported> {
        b.iter().try_for_each(|s| self.stmt(s))
    }

    fn exprs<'e>(&self, es: impl IntoIterator<Item = &'e Expr>, l: u32) -> Result<(), Unsupported> {
        es.into_iter().try_for_each(|e| self.expr(e, l))
    }

    fn stmt(&self, s: &Stmt) -> Result<(), Unsupported> {
        let l = s.line;
        match &s.kind {
            StmtKind::Decl { ty, vars, .. } => {
                let known = template(ty).is_some();
                if !known && !self.in_dat {
                    return self.refuse(l, format!("the type {ty}"));
                }
                for v in vars {
                    if v.dims.len() > 2 {
                        return self.refuse(l, "an array with more than 2 dimensions");
                    }
                    if known {
                        self.exprs(&v.dims, l)?;
                        self.exprs(&v.init, l)?;
                    }
                }
                Ok(())
            }
            StmtKind::Struc { .. } => self.refuse(l, "STRUC (user-defined structure types)"),
            StmtKind::Enum { .. } => self.refuse(l, "ENUM (user-defined enumeration types)"),
            StmtKind::Signal { .. } => self.refuse(l, "SIGNAL (I/O signals)"),
            StmtKind::Ext { name } if name.eq_ignore_ascii_case("BAS") => Ok(()),
            StmtKind::Ext { name } => self.refuse(
                l,
                format!("EXT {name} (a routine of another module; the call {name})"),
            ),
            StmtKind::Assign { target, value } => {
                self.lvalue(target, l)?;
                self.expr(value, l)
            }
            StmtKind::Call { name, args } => {
                if name.eq_ignore_ascii_case("BAS") {
                    return match args.first() {
                        Some(Expr::Enum(c)) if c.eq_ignore_ascii_case("INITMOV") => {
                            self.exprs(args, l)
                        }
                        Some(Expr::Enum(c)) => self
                            .refuse(l, format!("BAS(#{c}) (only BAS(#INITMOV, …) is supported)")),
                        _ => self.refuse(l, "BAS without a #command"),
                    };
                }
                if !self.is_routine(name) {
                    return self.refuse(l, format!("the call {name}"));
                }
                self.exprs(args, l)
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                self.expr(cond, l)?;
                self.block(then_body)?;
                self.block(else_body)
            }
            StmtKind::While { cond, body } => {
                self.expr(cond, l)?;
                self.block(body)
            }
            StmtKind::For {
                from,
                to,
                step,
                body,
                ..
            } => {
                self.exprs([from, to], l)?;
                self.exprs(step, l)?;
                self.block(body)
            }
            StmtKind::Loop { body } => self.block(body),
            StmtKind::Repeat { body, until } => {
                self.block(body)?;
                self.expr(until, l)
            }
            StmtKind::Switch {
                selector,
                cases,
                default,
            } => {
                self.expr(selector, l)?;
                for (vals, body) in cases {
                    self.exprs(vals, l)?;
                    self.block(body)?;
                }
                if let Some(d) = default {
                    self.block(d)?;
                }
                Ok(())
            }
            StmtKind::Return(e) => self.exprs(e, l),
            StmtKind::Exit | StmtKind::Continue => Ok(()),
            StmtKind::Halt => self.refuse(l, "HALT"),
            StmtKind::Brake => self.refuse(l, "BRAKE"),
            StmtKind::Resume => self.refuse(l, "RESUME"),
            StmtKind::OnErrorProceed => self.refuse(l, "ON_ERROR_PROCEED"),
            StmtKind::WaitSec(e) => self.expr(e, l),
            StmtKind::WaitFor(e) => {
                if mentions_system(e) {
                    return self
                        .refuse(l, "WAIT FOR with a condition that depends on the robot/IO");
                }
                self.expr(e, l)
            }
            StmtKind::Motion {
                aux,
                target,
                ca,
                rel_frame,
                ..
            } => {
                if ca.is_some() {
                    return self.refuse(l, "CIRC with CA (circular angle)");
                }
                if rel_frame.as_deref() == Some("TOOL") {
                    return self.refuse(l, "a relative motion in #TOOL coordinates");
                }
                self.exprs(aux, l)?;
                self.expr(target, l)
            }
            StmtKind::Spline {
                ptp, points, with, ..
            } => {
                if !with.is_empty() {
                    return self.refuse(l, "WITH after SPLINE (put WITH on the points)");
                }
                for p in points {
                    let pl = p.line;
                    if p.ca.is_some() {
                        return self.refuse(pl, "SCIRC with CA (circular angle)");
                    }
                    let is_sptp = p.kind == SplinePointKind::Sptp;
                    if *ptp && !is_sptp {
                        return self.refuse(
                            pl,
                            format!(
                                "{} inside PTP_SPLINE",
                                format!("{:?}", p.kind).to_uppercase()
                            ),
                        );
                    }
                    if !*ptp && is_sptp {
                        return self.refuse(pl, "SPTP inside a SPLINE block");
                    }
                    for (t, v) in &p.with {
                        let root = root_name(t).unwrap_or("").to_ascii_uppercase();
                        if !(root == "$VEL" || root == "$ACC") {
                            return self.refuse(
                                pl,
                                format!(
                                    "WITH {} (only $VEL and $ACC are supported in WITH)",
                                    describe(t)
                                ),
                            );
                        }
                        self.lvalue(t, pl)?;
                        self.expr(v, pl)?;
                    }
                    self.exprs(&p.aux, pl)?;
                    self.expr(&p.target, pl)?;
                }
                Ok(())
            }
            StmtKind::InterruptDecl { prio, .. } if is_stopm_decl(&s.kind) => self.expr(prio, l),
            StmtKind::InterruptSwitch {
                prio: Some(Expr::Int(p)),
                ..
            } if self.stopm_prios.contains(p) => Ok(()),
            StmtKind::InterruptDecl { .. } | StmtKind::InterruptSwitch { .. } => {
                self.refuse(l, "INTERRUPT")
            }
            StmtKind::Trigger { .. } => self.refuse(l, "TRIGGER"),
        }
    }

    fn lvalue(&self, e: &Expr, l: u32) -> Result<(), Unsupported> {
        if let Some(root) = root_name(e) {
            let up = root.to_ascii_uppercase();
            if up.starts_with('$') {
                if SYS_READ_ONLY.contains(&up.as_str()) {
                    return self.refuse(l, format!("assigning {up}"));
                }
                if !SYS_WRITE.contains(&up.as_str()) {
                    return self.refuse(l, format!("the system variable {up}"));
                }
            }
        }
        match e {
            Expr::Var(_) => Ok(()),
            Expr::Index(b, i) => {
                self.lvalue(b, l)?;
                self.exprs(i, l)
            }
            Expr::Field(b, _) => self.lvalue(b, l),
            _ => self.expr(e, l),
        }
    }

    fn expr(&self, e: &Expr, l: u32) -> Result<(), Unsupported> {
        match e {
            Expr::Var(n) => {
                let up = n.to_ascii_uppercase();
                if up.starts_with('$')
                    && !SYS_WRITE.contains(&up.as_str())
                    && !SYS_READ_ONLY.contains(&up.as_str())
                {
                    return self.refuse(l, format!("the system variable {up}"));
                }
                Ok(())
            }
            Expr::Index(b, i) => {
                self.expr(b, l)?;
                self.exprs(i, l)
            }
            Expr::Field(b, _) | Expr::Unary(_, b) => self.expr(b, l),
            Expr::Call(n, args) => {
                let up = n.to_ascii_uppercase();
                if !BUILTINS.contains(&up.as_str()) && !self.routines.contains(&up) {
                    return self.refuse(l, format!("the call {n}"));
                }
                self.exprs(args, l)
            }
            Expr::Struct { fields, .. } => self.exprs(fields.iter().map(|(_, v)| v), l),
            Expr::Binary(_, a, b) => {
                self.expr(a, l)?;
                self.expr(b, l)
            }
            Expr::Int(_) | Expr::Real(_) | Expr::Bool(_) | Expr::Str(_) | Expr::Enum(_) => Ok(()),
        }
    }
}

// ---------------------------------------------------------------- interpreter

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
        open_files = h.open.into_values().map(|f| f.name).collect();
    }
    r?;
    Ok(Globals {
        vars: it.globals,
        open_files,
    })
}

fn entry_routine<'p>(program: &'p Program, entry: &str) -> Result<&'p Routine, RunError> {
    program.routine(entry).ok_or_else(|| RunError::Runtime {
        line: 0,
        message: format!("the entry routine {entry} is not defined"),
    })
}

/// Global variables after [`run_with_files`]
/// (names are case-insensitive).
#[derive(Debug, Clone)]
pub struct Globals {
    vars: HashMap<String, Value>,
    open_files: Vec<String>,
}

impl Globals {
    fn element(&self, name: &str, index: &[i64]) -> Option<&Value> {
        let v = self.vars.get(&name.to_ascii_uppercase())?;
        if index.is_empty() {
            return Some(v);
        }
        match v {
            Value::Array(dims, items) => items.get(flat_index(dims, index).ok()?),
            _ => None,
        }
    }

    /// An INT (or CHAR code) variable or array element (1-based indices).
    pub fn int(&self, name: &str, index: &[i64]) -> Option<i64> {
        self.element(name, index)?.int().ok()
    }

    /// A BOOL variable or array element.
    pub fn bool(&self, name: &str, index: &[i64]) -> Option<bool> {
        self.element(name, index)?.bool().ok()
    }

    /// A REAL (or INT) variable or array element.
    pub fn real(&self, name: &str, index: &[i64]) -> Option<f64> {
        self.element(name, index)?.num().ok()
    }

    /// The first `len` characters of a CHAR array.
    pub fn chars(&self, name: &str, len: usize) -> Option<String> {
        (1..=len as i64)
            .map(|i| match self.element(name, &[i])? {
                Value::Char(c) => Some(char::from(*c)),
                _ => None,
            })
            .collect()
    }

    /// The value at a KRL path such as `kb_mot[3].X`, `kb_hv[2,5]` or
    /// `$POS_ACT.S` (1-based indices, components by name).
    fn at(&self, path: &str) -> Option<&Value> {
        let path = path.trim();
        let end = path.find(['[', '.']).unwrap_or(path.len());
        let mut v = self.vars.get(&path[..end].to_ascii_uppercase())?;
        let mut rest = &path[end..];
        while !rest.is_empty() {
            if let Some(r) = rest.strip_prefix('[') {
                let close = r.find(']')?;
                let idx = r[..close]
                    .split(',')
                    .map(|x| x.trim().parse().ok())
                    .collect::<Option<Vec<i64>>>()?;
                v = step_into(v, &PathElem::Index(idx)).ok()?;
                rest = &r[close + 1..];
            } else {
                let r = rest.strip_prefix('.')?;
                let end = r.find(['[', '.']).unwrap_or(r.len());
                v = step_into(v, &PathElem::Field(r[..end].to_ascii_uppercase())).ok()?;
                rest = &r[end..];
            }
        }
        Some(v)
    }

    /// An INT (or CHAR code) at a path (see [`Globals::real_at`]).
    pub fn int_at(&self, path: &str) -> Option<i64> {
        self.at(path)?.int().ok()
    }

    /// A REAL (or INT) at a KRL path such as `kb_mot[3].X` or `kb_hv[2,5]`.
    pub fn real_at(&self, path: &str) -> Option<f64> {
        self.at(path)?.num().ok()
    }

    /// A BOOL at a path.
    pub fn bool_at(&self, path: &str) -> Option<bool> {
        self.at(path)?.bool().ok()
    }

    /// An ENUM value at a path, without `#`, upper case (`"P_ACTIVE"`).
    pub fn enum_at(&self, path: &str) -> Option<&str> {
        match self.at(path)? {
            Value::Enum(e) => Some(e),
            _ => None,
        }
    }

    /// Files that were still open when [`run_with_files`] ended.
    pub fn open_files(&self) -> &[String] {
        &self.open_files
    }
}

/// The in-memory file system of [`run_with_files`].
#[derive(Debug)]
struct Harness {
    files: BTreeMap<String, String>,
    open: BTreeMap<i64, OpenFile>,
    next_handle: i64,
}

#[derive(Debug)]
struct OpenFile {
    name: String,
    write: bool,
    /// Read position (bytes).
    pos: usize,
}

/// `$ERR` of the harness.
fn err_value(number: i64, line: u32) -> Value {
    Value::Struct(
        "ERR_INFO".into(),
        vec![
            ("NUMBER".into(), Value::Int(number)),
            ("LINE".into(), Value::Int(line.into())),
        ],
    )
}

/// The text of a string or of a CHAR array up to its first 0 (or unset
/// element).
fn text_of(v: &Value) -> Result<String, String> {
    match v {
        Value::Str(s) => Ok(s.clone()),
        Value::Array(dims, elems) if dims.len() == 1 => Ok(elems
            .iter()
            .map_while(|e| match e {
                Value::Char(c) if *c != 0 => Some(char::from(*c)),
                _ => None,
            })
            .collect()),
        v => Err(format!("expected a string, found {}", v.type_name())),
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Root {
    Global(String),
    Local(usize, String),
    /// `$POS_ACT`, `$AXIS_ACT`, `$NULLFRAME`, `$OV_PRO`.
    Computed(String),
}

#[derive(Debug, Clone)]
struct Place {
    root: Root,
    path: Vec<PathElem>,
    desc: String,
}

#[derive(Debug, Clone)]
enum Slot {
    Val(Value),
    /// An `OUT` parameter: the caller's variable.
    Ref(Place),
}

enum Flow {
    Next,
    Exit,
    Return(Option<Value>),
}

/// Speeds in effect for one motion.
#[derive(Debug, Clone, Copy)]
struct Speeds {
    cp: f64,
    cp_acc_pct: f64,
    ptp: f64,
    ptp_acc_pct: f64,
}

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
        }
    }

    /// Executes the `.dat` items, then `routine` (no arguments).
    fn run_entry(&mut self, routine: &'a Routine) -> Result<(), RunError> {
        if let Some(dat) = &self.program.dat {
            for s in &dat.items {
                self.exec(s)?;
            }
        }
        self.call_routine(routine, &[])?;
        Ok(())
    }

    /// Turns on the test harness (see [`run_with_files`]).
    fn enable_harness(&mut self, files: BTreeMap<String, String>) {
        self.harness = Some(Harness {
            files,
            open: BTreeMap::new(),
            next_handle: 1,
        });
        self.max_statements = HARNESS_MAX_STATEMENTS;
        self.max_evaluations = HARNESS_MAX_EVALUATIONS;
        let e = Value::Unset(Scalar::Enum);
        for t in ["MODUS_T", "CMD_STAT", "MODE_OP", "PRO_STATE"] {
            self.types.insert(t.into(), e.clone());
        }
        let int = Value::Unset(Scalar::Int);
        self.types.insert(
            "STATE_T".into(),
            Value::Struct(
                "STATE_T".into(),
                vec![
                    ("RET1".into(), e),
                    ("HITS".into(), int.clone()),
                    ("LENGTH".into(), int.clone()),
                    ("MSG_NO".into(), int),
                ],
            ),
        );
        let pos = self.pos_act();
        let g = &mut self.globals;
        g.insert("$POS_ACT".into(), pos);
        if let Some(a) = self.axes {
            g.insert("$AXIS_ACT".into(), axis_value(&a));
        }
        g.insert("$MODE_OP".into(), Value::Enum("T1".into()));
        g.insert("$OV_PRO".into(), Value::Int(100));
        g.insert("$PRO_STATE1".into(), Value::Enum("P_FREE".into()));
        g.insert(
            "$PRO_NAME1".into(),
            Value::Array(vec![24], vec![Value::Char(b' '); 24]),
        );
        g.insert("$STOPMESS".into(), Value::Bool(false));
        g.insert("$PERI_RDY".into(), Value::Bool(true));
        g.insert("$ROB_TIMER".into(), Value::Int(0));
        g.insert("$ERR".into(), err_value(0, 0));
    }

    /// The typed template of a predefined, user-defined or harness type.
    fn type_template(&self, ty: &str) -> Option<Value> {
        template(ty).or_else(|| self.types.get(&ty.to_ascii_uppercase()).cloned())
    }

    /// `STRUC name type f1, f2[n], …`: registers the type.
    fn define_struc(
        &mut self,
        name: &str,
        fields: &[(String, String, Vec<Expr>)],
    ) -> Result<(), RunError> {
        let mut out = Vec::with_capacity(fields.len());
        for (ty, field, dims) in fields {
            let Some(mut v) = self.type_template(ty) else {
                return Err(self.err(format!(
                    "the component {field} of {name} has the unknown type {ty}"
                )));
            };
            if !dims.is_empty() {
                let mut ds = Vec::with_capacity(dims.len());
                for d in dims {
                    let n = self.eval_int(d)?;
                    if !(1..=MAX_ARRAY as i64).contains(&n) {
                        return Err(self.err(format!("array size {n} of {field} is out of range")));
                    }
                    ds.push(n as usize);
                }
                let total = ds.iter().product::<usize>();
                if total > MAX_ARRAY {
                    return Err(self.err(format!("the array {field} is too large")));
                }
                v = Value::Array(ds, vec![v; total]);
            }
            out.push((field.to_ascii_uppercase(), v));
        }
        let up = name.to_ascii_uppercase();
        self.types.insert(up.clone(), Value::Struct(up, out));
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

    fn push(&mut self, step: Step) -> Result<(), RunError> {
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

    // ---- variables

    fn resolve(&self, name: &str) -> Result<Place, RunError> {
        let up = name.to_ascii_uppercase();
        if let Some(i) = self.frames.len().checked_sub(1) {
            match self.frames.get(i).and_then(|f| f.get(&up)) {
                Some(Slot::Val(_)) => {
                    return Ok(Place {
                        root: Root::Local(i, up),
                        path: Vec::new(),
                        desc: name.to_string(),
                    });
                }
                Some(Slot::Ref(p)) => {
                    let mut p = p.clone();
                    p.desc = name.to_string();
                    return Ok(p);
                }
                None => {}
            }
        }
        let root = if self.globals.contains_key(&up) {
            Root::Global(up)
        } else if SYS_READ_ONLY.contains(&up.as_str()) {
            Root::Computed(up)
        } else {
            return Err(self.err(format!("the variable {name} is not declared")));
        };
        Ok(Place {
            root,
            path: Vec::new(),
            desc: name.to_string(),
        })
    }

    /// The place an lvalue-like expression names, or `None` if it is not
    /// rooted in a variable.
    fn place_of(&mut self, e: &Expr) -> Result<Option<Place>, RunError> {
        self.enter()?;
        let r = self.place_of_node(e);
        self.nesting -= 1;
        r
    }

    fn place_of_node(&mut self, e: &Expr) -> Result<Option<Place>, RunError> {
        Ok(match e {
            Expr::Var(n) => Some(self.resolve(n)?),
            Expr::Index(b, idx) => match self.place_of(b)? {
                Some(mut p) => {
                    let mut ii = Vec::with_capacity(idx.len());
                    for i in idx {
                        let v = self.eval(i)?;
                        ii.push(v.int().map_err(|m| self.err(format!("index: {m}")))?);
                    }
                    p.path.push(PathElem::Index(ii));
                    p.desc = describe(e);
                    Some(p)
                }
                None => None,
            },
            Expr::Field(b, f) => match self.place_of(b)? {
                Some(mut p) => {
                    p.path.push(PathElem::Field(f.to_ascii_uppercase()));
                    p.desc = describe(e);
                    Some(p)
                }
                None => None,
            },
            _ => None,
        })
    }

    fn root_ref(&self, root: &Root) -> Result<&Value, RunError> {
        let v = match root {
            Root::Global(n) => self.globals.get(n),
            Root::Local(i, n) => match self.frames.get(*i).and_then(|f| f.get(n)) {
                Some(Slot::Val(v)) => Some(v),
                _ => None,
            },
            Root::Computed(_) => None,
        };
        v.ok_or_else(|| self.err("internal: dangling variable reference"))
    }

    fn read_place(&mut self, p: &Place) -> Result<Value, RunError> {
        let computed = match &p.root {
            Root::Computed(n) => Some(self.computed(n)?),
            _ => None,
        };
        let root = match &computed {
            Some(v) => v,
            None => self.root_ref(&p.root)?,
        };
        let v = walk(root, &p.path).map_err(|m| self.err(format!("{}: {m}", p.desc)))?;
        match v {
            Value::Unset(_) => Err(self.err(format!("{} has no value (not initialised)", p.desc))),
            Value::Opaque(t) => Err(self.err(format!(
                "{} has the type {t}, which the simulator does not support",
                p.desc
            ))),
            v @ Value::Array(..) => {
                // Copying a whole array is work in proportion to its size.
                let v = v.clone();
                self.charge(cells(&v) as u64)?;
                Ok(v)
            }
            v => Ok(v.clone()),
        }
    }

    fn write_place(&mut self, p: &Place, v: Value) -> Result<(), RunError> {
        let sys = match &p.root {
            Root::Global(n) if n.starts_with('$') => Some(n.clone()),
            Root::Computed(n) => return Err(self.err(format!("{n} is read-only"))),
            _ => None,
        };
        let saved = match &sys {
            Some(_) => Some((self.root_ref(&p.root)?.clone(), self.tool()?, self.base()?)),
            None => None,
        };
        let root = match &p.root {
            Root::Global(n) => self.globals.get_mut(n),
            Root::Local(i, n) => match self.frames.get_mut(*i).and_then(|f| f.get_mut(n)) {
                Some(Slot::Val(v)) => Some(v),
                _ => None,
            },
            Root::Computed(_) => None,
        };
        let Some(root) = root else {
            return Err(self.err("internal: dangling variable reference"));
        };
        let r = walk_mut(root, &p.path).and_then(|slot| assign_into(slot, v));
        r.map_err(|m| self.err(format!("{}: {m}", p.desc)))?;
        if let (Some(name), Some((old, old_tool, old_base))) = (sys, saved) {
            if let Err(m) = self.validate_sys(&name) {
                self.globals.insert(name, old);
                return Err(self.err(m));
            }
            if name == "$TOOL" || name == "$BASE" {
                self.frames_changed(old_tool, old_base)?;
            }
        }
        Ok(())
    }

    // ---- system variables

    fn sys_field(&self, root: &str, field: &str) -> Result<f64, RunError> {
        let v = self
            .globals
            .get(root)
            .ok_or_else(|| self.err(format!("{root} is missing")))?;
        let Value::Struct(_, f) = v else {
            return Err(self.err(format!("{root} is not a structure")));
        };
        num_field(f, field)
            .map_err(|m| self.err(format!("{root}: {m}")))?
            .ok_or_else(|| self.err(format!("{root}.{field} has no value")))
    }

    fn sys_array(&self, root: &str) -> Result<Vec<f64>, RunError> {
        match self.globals.get(root) {
            Some(Value::Array(_, e)) => e
                .iter()
                .map(|v| v.num().map_err(|m| self.err(format!("{root}: {m}"))))
                .collect(),
            _ => Err(self.err(format!("{root} is not an array"))),
        }
    }

    fn sys_frame(&self, root: &str) -> Result<Pose, RunError> {
        let v = self
            .globals
            .get(root)
            .ok_or_else(|| self.err(format!("{root} is missing")))?;
        pose_of(v).map_err(|m| self.err(format!("{root}: {m}")))
    }

    fn tool(&self) -> Result<Pose, RunError> {
        self.sys_frame("$TOOL")
    }

    fn base(&self) -> Result<Pose, RunError> {
        self.sys_frame("$BASE")
    }

    fn cdis(&self) -> Result<f64, RunError> {
        self.sys_field("$APO", "CDIS")
    }

    fn speeds(&self) -> Result<Speeds, RunError> {
        let min = |v: Vec<f64>| v.into_iter().fold(f64::INFINITY, f64::min);
        Ok(Speeds {
            cp: self.sys_field("$VEL", "CP")?,
            cp_acc_pct: (self.sys_field("$ACC", "CP")? / ACC_CP_MAX * 100.0).clamp(1.0, 100.0),
            ptp: min(self.sys_array("$VEL_AXIS")?),
            ptp_acc_pct: min(self.sys_array("$ACC_AXIS")?),
        })
    }

    /// Checks a system variable after an assignment (the KRC refuses
    /// out-of-range values too).
    fn validate_sys(&self, name: &str) -> Result<(), String> {
        let msg = |e: RunError| match e {
            RunError::Runtime { message, .. }
            | RunError::TooLong { message, .. }
            | RunError::Limit { message, .. } => message,
            RunError::Unsupported(u) => u.what,
        };
        match name {
            "$VEL" => {
                let cp = self.sys_field("$VEL", "CP").map_err(msg)?;
                if !(cp > 0.0 && cp <= MAX_CP_VELOCITY) {
                    return Err(format!(
                        "$VEL.CP = {cp} m/s is out of range (0 < CP <= {MAX_CP_VELOCITY})"
                    ));
                }
            }
            "$ACC" => {
                let cp = self.sys_field("$ACC", "CP").map_err(msg)?;
                if !(cp > 0.0 && cp.is_finite()) {
                    return Err(format!("$ACC.CP = {cp} m/s² must be positive"));
                }
            }
            "$VEL_AXIS" | "$ACC_AXIS" => {
                for (i, v) in self.sys_array(name).map_err(msg)?.iter().enumerate() {
                    if !(*v > 0.0 && *v <= 100.0) {
                        return Err(format!(
                            "{name}[{}] = {v} is out of range (0 < % <= 100)",
                            i + 1
                        ));
                    }
                }
            }
            "$APO" => {
                let d = self.sys_field("$APO", "CDIS").map_err(msg)?;
                if !(d >= 0.0 && d.is_finite()) {
                    return Err(format!("$APO.CDIS = {d} mm must not be negative"));
                }
            }
            "$TOOL" | "$BASE" => {
                let f = self.sys_frame(name).map_err(msg)?;
                if !f.is_finite() {
                    return Err(format!("{name} is not a finite frame"));
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// `$TOOL`/`$BASE` changed: re-express the programmed pose.
    fn frames_changed(&mut self, old_tool: Pose, old_base: Pose) -> Result<(), RunError> {
        let (tool, base) = (self.tool()?, self.base()?);
        if tool == old_tool && base == old_base {
            return Ok(());
        }
        self.pos = match self.axes {
            Some(a) => self.model.forward(&a, &tool, &base),
            None => base
                .inverse()
                .compose(&old_base)
                .compose(&self.pos)
                .compose(&old_tool.inverse())
                .compose(&tool),
        };
        Ok(())
    }

    /// KRL stops the advance run here: the motion before ends exactly.
    fn advance_stop(&mut self) {
        if self.continue_active {
            return;
        }
        if let Some(Step::Move { motion, .. }) = self.steps.last_mut() {
            motion.approx_mm = 0.0;
        }
    }

    /// The programmed pose as an E6POS (`$POS_ACT`).
    fn pos_act(&self) -> Value {
        let a = self.pos.to_array();
        let mut f: Vec<(String, Value)> = FRAME_FIELDS
            .iter()
            .zip(a)
            .map(|(n, v)| (n.to_string(), Value::Real(v)))
            .collect();
        let st = |v: Option<u8>| v.map_or(Value::Unset(Scalar::Int), |x| Value::Int(x.into()));
        f.push(("S".into(), st(self.status)));
        f.push(("T".into(), st(self.turn)));
        f.extend(EXT_FIELDS.iter().map(|n| (n.to_string(), Value::Real(0.0))));
        Value::Struct("E6POS".into(), f)
    }

    fn computed(&mut self, name: &str) -> Result<Value, RunError> {
        Ok(match name {
            "$POS_ACT" => {
                self.advance_stop();
                self.pos_act()
            }
            "$AXIS_ACT" => {
                self.advance_stop();
                match self.axes {
                    Some(a) => axis_value(&a),
                    None => {
                        return Err(self.err(format!(
                            "$AXIS_ACT after the Cartesian motion on line {} is not known before the motion runs",
                            self.cart_line
                        )));
                    }
                }
            }
            "$NULLFRAME" => frame_value(&Pose::IDENTITY),
            _ => Value::Int(100), // $OV_PRO
        })
    }

    // ---- expressions

    /// Evaluates an expression. Counts one evaluation and one level of
    /// nesting; the work per kind of node is in functions of its own, so
    /// that the frames on the recursion stay small in a debug build.
    fn eval(&mut self, e: &Expr) -> Result<Value, RunError> {
        self.enter()?;
        let r = match self.charge(1) {
            Ok(()) => self.eval_node(e),
            Err(x) => Err(x),
        };
        self.nesting -= 1;
        r
    }

    fn eval_node(&mut self, e: &Expr) -> Result<Value, RunError> {
        match e {
            Expr::Int(i) => Ok(Value::Int(*i)),
            Expr::Real(r) => Ok(Value::Real(*r)),
            Expr::Bool(b) => Ok(Value::Bool(*b)),
            Expr::Str(s) => Ok(Value::Str(s.clone())),
            Expr::Enum(s) => Ok(Value::Enum(s.to_ascii_uppercase())),
            Expr::Var(_) | Expr::Index(..) | Expr::Field(..) => self.eval_place(e),
            Expr::Call(name, args) => self.eval_call(name, args),
            Expr::Struct { ty, fields } => self.eval_struct(ty.as_deref(), fields),
            Expr::Unary(op, x) => self.eval_unary(*op, x),
            Expr::Binary(op, a, b) => self.eval_binary(*op, a, b),
        }
    }

    /// A variable, element or component.
    fn eval_place(&mut self, e: &Expr) -> Result<Value, RunError> {
        if let Some(p) = self.place_of(e)? {
            return self.read_place(&p);
        }
        // A component or element of a computed value, e.g. f().X.
        let (base, elem) = match e {
            Expr::Field(b, f) => (b, PathElem::Field(f.to_ascii_uppercase())),
            Expr::Index(b, idx) => {
                let mut ii = Vec::new();
                for i in idx {
                    let v = self.eval(i)?;
                    ii.push(v.int().map_err(|m| self.err(format!("index: {m}")))?);
                }
                (b, PathElem::Index(ii))
            }
            _ => return Err(self.err("internal: not a place")),
        };
        let v = self.eval(base)?;
        match step_into(&v, &elem) {
            Ok(Value::Unset(_)) => Err(self.err(format!("{} has no value", describe(e)))),
            Ok(x) => Ok(x.clone()),
            Err(m) => Err(self.err(m)),
        }
    }

    fn eval_call(&mut self, name: &str, args: &[Expr]) -> Result<Value, RunError> {
        let up = name.to_ascii_uppercase();
        if BUILTINS.contains(&up.as_str()) {
            let mut vals = Vec::with_capacity(args.len());
            for a in args {
                vals.push(self.eval(a)?);
            }
            return builtin(&up, &vals).map_err(|m| self.err(m));
        }
        let routine = self.routine(name)?;
        if routine.kind == RoutineKind::Def {
            return Err(self.err(format!("{name} is a procedure (DEF) and has no value")));
        }
        self.call_routine(routine, args)?
            .ok_or_else(|| self.err(format!("{name} returned no value")))
    }

    fn eval_struct(
        &mut self,
        ty: Option<&str>,
        fields: &[(String, Expr)],
    ) -> Result<Value, RunError> {
        let mut out = Vec::with_capacity(fields.len());
        for (n, v) in fields {
            out.push((n.to_ascii_uppercase(), self.eval(v)?));
        }
        let ty = ty.unwrap_or("").to_ascii_uppercase();
        Ok(Value::Struct(ty, out))
    }

    fn eval_unary(&mut self, op: UnOp, x: &Expr) -> Result<Value, RunError> {
        let v = self.eval(x)?;
        let r = match (op, v) {
            (UnOp::Neg, Value::Int(i)) => int_result(i.checked_neg()),
            (UnOp::Neg, Value::Real(r)) => Ok(Value::Real(-r)),
            (UnOp::Not, Value::Bool(b)) => Ok(Value::Bool(!b)),
            (UnOp::BNot, Value::Int(i)) => Ok(Value::Int(!i)),
            (op, v) => Err(format!("{op:?} cannot be applied to {}", v.type_name())),
        };
        r.map_err(|m| self.err(m))
    }

    fn eval_binary(&mut self, op: BinOp, a: &Expr, b: &Expr) -> Result<Value, RunError> {
        let l = self.eval(a)?;
        let r = self.eval(b)?;
        binary(op, l, r).map_err(|m| self.err(m))
    }

    fn eval_num(&mut self, e: &Expr) -> Result<f64, RunError> {
        let v = self.eval(e)?;
        v.num().map_err(|m| self.err(m))
    }

    fn eval_int(&mut self, e: &Expr) -> Result<i64, RunError> {
        let v = self.eval(e)?;
        v.int().map_err(|m| self.err(m))
    }

    fn eval_bool(&mut self, e: &Expr) -> Result<bool, RunError> {
        let v = self.eval(e)?;
        v.bool().map_err(|m| self.err(m))
    }

    // ---- routines

    fn routine(&self, name: &str) -> Result<&'a Routine, RunError> {
        self.routines
            .get(&name.to_ascii_uppercase())
            .copied()
            .ok_or_else(|| self.err(format!("the routine {name} is not defined")))
    }

    fn call_routine(&mut self, r: &'a Routine, args: &[Expr]) -> Result<Option<Value>, RunError> {
        self.enter()?;
        let result = self.call_routine_body(r, args);
        self.nesting -= 1;
        result
    }

    fn call_routine_body(
        &mut self,
        r: &'a Routine,
        args: &[Expr],
    ) -> Result<Option<Value>, RunError> {
        let call_line = self.line;
        // Separate functions: their frames are gone while the body runs.
        // Binding evaluates the arguments: a level of its own.
        self.enter()?;
        let bound = self.bind_params(r, args);
        self.nesting -= 1;
        let (frame, held) = bound?;
        self.frames.push(frame);
        self.frame_cells.push(0);
        let flow = match self.hold(held) {
            Ok(()) => self.exec_block(&r.body),
            Err(e) => Err(e),
        };
        self.frames.pop();
        let released = self.frame_cells.pop().unwrap_or(0);
        self.cells = self.cells.saturating_sub(released);
        let flow = flow?;
        let result = self.routine_result(r, flow)?;
        self.line = call_line;
        Ok(result)
    }

    /// The new frame of a call of `r`: its `IN` parameters' values and its
    /// `OUT` parameters' places; and the values the frame holds.
    fn bind_params(
        &mut self,
        r: &'a Routine,
        args: &[Expr],
    ) -> Result<(HashMap<String, Slot>, usize), RunError> {
        if r.params.len() != args.len() {
            return Err(self.err(format!(
                "{} takes {} argument(s), got {}",
                r.name,
                r.params.len(),
                args.len()
            )));
        }
        if self.frames.len() >= MAX_CALL_DEPTH {
            return Err(self.limit(format!(
                "calls nested deeper than {MAX_CALL_DEPTH} levels (limit MAX_CALL_DEPTH; endless recursion?)"
            )));
        }
        let mut frame = HashMap::new();
        let mut held = 0usize;
        for (p, a) in r.params.iter().zip(args) {
            let slot = if p.out {
                match self.place_of(a)? {
                    Some(pl) if matches!(pl.root, Root::Global(ref n) if n.starts_with('$')) => {
                        return Err(self.err(format!(
                            "the system variable {} cannot be an OUT argument",
                            describe(a)
                        )));
                    }
                    Some(pl) if !matches!(pl.root, Root::Computed(_)) => Slot::Ref(pl),
                    _ => {
                        return Err(self.err(format!(
                            "the OUT parameter {} of {} needs a variable",
                            p.name, r.name
                        )));
                    }
                }
            } else {
                let v = self.eval(a)?;
                held = held.saturating_add(cells(&v));
                Slot::Val(v)
            };
            frame.insert(p.name.to_ascii_uppercase(), slot);
        }
        Ok((frame, held))
    }

    /// The value a call of `r` returns, after its body ended with `flow`.
    fn routine_result(&mut self, r: &'a Routine, flow: Flow) -> Result<Option<Value>, RunError> {
        self.line = r.end_line;
        let result = match (&r.kind, flow) {
            (RoutineKind::Def, Flow::Next | Flow::Return(None)) => None,
            (RoutineKind::Def, Flow::Return(Some(_))) => {
                return Err(self.err(format!("the procedure {} cannot RETURN a value", r.name)));
            }
            (RoutineKind::DefFct(ty), Flow::Return(Some(v))) => {
                let mut slot = self
                    .type_template(ty)
                    .ok_or_else(|| self.err(format!("functions returning {ty}")))?;
                assign_into(&mut slot, v)
                    .map_err(|m| self.err(format!("return value of {}: {m}", r.name)))?;
                Some(slot)
            }
            (RoutineKind::DefFct(_), Flow::Next | Flow::Return(None)) => {
                return Err(self.err(format!(
                    "the function {} ended without RETURN of a value",
                    r.name
                )));
            }
            (_, Flow::Exit) => return Err(self.err("EXIT outside a loop")),
        };
        Ok(result)
    }

    // ---- statements

    fn exec_block(&mut self, body: &'a [Stmt]) -> Result<Flow, RunError> {
        for s in body {
            match self.exec(s)? {
                Flow::Next => {}
                f => return Ok(f),
            }
        }
        Ok(Flow::Next)
    }

    /// Runs a loop body; `Some(flow)` when the loop must end with `flow`.
    fn loop_body(&mut self, body: &'a [Stmt], line: u32) -> Result<Option<Flow>, RunError> {
        // A loop's frames count as a level of their own.
        self.enter()?;
        let r = self.loop_iteration(body, line);
        self.nesting -= 1;
        r
    }

    fn loop_iteration(&mut self, body: &'a [Stmt], line: u32) -> Result<Option<Flow>, RunError> {
        self.line = line;
        self.tick()?;
        let f = match self.exec_block(body)? {
            Flow::Next => None,
            Flow::Exit => Some(Flow::Next),
            r @ Flow::Return(_) => Some(r),
        };
        self.line = line;
        Ok(f)
    }

    fn exec(&mut self, s: &'a Stmt) -> Result<Flow, RunError> {
        self.enter()?;
        let guarded = std::mem::take(&mut self.error_proceed);
        let r = match self.exec_stmt(s) {
            // ON_ERROR_PROCEED (harness only): note the error in $ERR and
            // go on after the statement. The statement limit still ends
            // the run.
            Err(RunError::Runtime { line, .. })
                if guarded && self.statements <= self.max_statements =>
            {
                self.globals.insert("$ERR".into(), err_value(1, line));
                Ok(Flow::Next)
            }
            r => r,
        };
        self.nesting -= 1;
        r
    }

    /// Dispatches on the statement. Every statement with more than a few
    /// locals has a function of its own: a debug build gives a function one
    /// stack slot per local of every `match` arm, and this function is on
    /// every recursion (blocks, calls).
    fn exec_stmt(&mut self, s: &'a Stmt) -> Result<Flow, RunError> {
        self.line = s.line;
        self.tick()?;
        self.continue_active = std::mem::take(&mut self.continue_pending);
        let l = s.line;
        match &s.kind {
            StmtKind::Decl { ty, vars, .. } => self.exec_decl(ty, vars),
            // Only the standard stop-message interrupt passes check_subset.
            StmtKind::Ext { .. }
            | StmtKind::InterruptDecl { .. }
            | StmtKind::InterruptSwitch { .. } => Ok(Flow::Next),
            StmtKind::Assign { target, value } => self.exec_assign(target, value),
            StmtKind::Call { name, args } => self.exec_call(name, args),
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => self.exec_if(cond, then_body, else_body),
            StmtKind::While { cond, body } => self.exec_while(cond, body, l),
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => self.exec_for(var, [from, to], step.as_ref(), body, l),
            StmtKind::Loop { body } => self.exec_loop(body, l),
            StmtKind::Repeat { body, until } => self.exec_repeat(body, until, l),
            StmtKind::Switch {
                selector,
                cases,
                default,
            } => self.exec_switch(selector, cases, default.as_deref()),
            StmtKind::Return(e) => self.exec_return(e.as_ref()),
            StmtKind::Exit => Ok(Flow::Exit),
            StmtKind::Continue => {
                self.continue_pending = true;
                Ok(Flow::Next)
            }
            StmtKind::WaitSec(e) => self.exec_wait_sec(e, l),
            StmtKind::WaitFor(e) => self.exec_wait_for(e),
            StmtKind::Motion {
                kind,
                aux,
                target,
                approx,
                ..
            } => self.exec_motion(*kind, aux.as_ref(), target, approx.is_some()),
            StmtKind::Spline { points, approx, .. } => self.exec_spline(points, approx.is_some()),
            _ => self.exec_other(s),
        }
    }

    /// Statements of the harness and those outside the subset.
    fn exec_other(&mut self, s: &'a Stmt) -> Result<Flow, RunError> {
        match &s.kind {
            StmtKind::Struc { name, fields } => self.define_struc(name, fields)?,
            StmtKind::Enum { name, .. } => {
                self.types
                    .insert(name.to_ascii_uppercase(), Value::Unset(Scalar::Enum));
            }
            StmtKind::OnErrorProceed if self.harness.is_some() => self.error_proceed = true,
            _ => {
                return Err(Unsupported {
                    line: s.line,
                    what: "this statement".into(),
                }
                .into());
            }
        }
        Ok(Flow::Next)
    }

    fn exec_spline(&mut self, points: &'a [SplinePoint], c_spl: bool) -> Result<Flow, RunError> {
        // The spline's and the motion's frames are large (in a debug
        // build): each counts as a level of its own.
        self.enter()?;
        let r = self.spline(points, c_spl);
        self.nesting -= 1;
        r.map(|()| Flow::Next)
    }

    fn exec_decl(&mut self, ty: &str, vars: &[kuka_krl::Declarator]) -> Result<Flow, RunError> {
        for d in vars {
            self.declare(ty, d)?;
        }
        Ok(Flow::Next)
    }

    fn exec_assign(&mut self, target: &Expr, value: &Expr) -> Result<Flow, RunError> {
        let v = self.eval(value)?;
        let Some(p) = self.place_of(target)? else {
            return Err(self.err(format!("cannot assign to {}", describe(target))));
        };
        self.write_place(&p, v)?;
        Ok(Flow::Next)
    }

    fn exec_call(&mut self, name: &str, args: &[Expr]) -> Result<Flow, RunError> {
        if name.eq_ignore_ascii_case("BAS") {
            self.bas(args)?;
        } else if self.harness.is_some() && name.eq_ignore_ascii_case("CWRITE") {
            self.cwrite(args)?;
        } else if self.harness.is_some() && name.eq_ignore_ascii_case("ERR_CLEAR") {
            match args {
                [Expr::Var(v)] if v.eq_ignore_ascii_case("$ERR") => {
                    self.globals.insert("$ERR".into(), err_value(0, 0));
                }
                _ => return Err(self.err("ERR_CLEAR takes $ERR")),
            }
        } else {
            let r = self.routine(name)?;
            self.call_routine(r, args)?;
        }
        Ok(Flow::Next)
    }

    fn exec_if(
        &mut self,
        cond: &Expr,
        then_body: &'a [Stmt],
        else_body: &'a [Stmt],
    ) -> Result<Flow, RunError> {
        let body = if self.eval_bool(cond)? {
            then_body
        } else {
            else_body
        };
        self.exec_block(body)
    }

    fn exec_while(&mut self, cond: &Expr, body: &'a [Stmt], l: u32) -> Result<Flow, RunError> {
        while self.eval_bool(cond)? {
            if let Some(f) = self.loop_body(body, l)? {
                return Ok(f);
            }
        }
        Ok(Flow::Next)
    }

    fn exec_for(
        &mut self,
        var: &str,
        bounds: [&Expr; 2],
        step: Option<&Expr>,
        body: &'a [Stmt],
        l: u32,
    ) -> Result<Flow, RunError> {
        // Two calls in a row: the frame that evaluates the bounds is gone
        // before the loop recurses into the body.
        let (counter, to, step) = self.for_start(var, bounds, step)?;
        self.for_loop(&counter, to, step, body, l)
    }

    /// Evaluates a FOR's bounds and step and sets the counter to `from`.
    fn for_start(
        &mut self,
        var: &str,
        [from, to]: [&Expr; 2],
        step: Option<&Expr>,
    ) -> Result<(Place, i64, i64), RunError> {
        let from = self.eval_int(from)?;
        let to = self.eval_int(to)?;
        let step = match step {
            Some(e) => self.eval_int(e)?,
            None => 1,
        };
        if step == 0 {
            return Err(self.err("FOR with STEP 0 never ends"));
        }
        let counter = self.place_of(&Expr::Var(var.to_string()))?;
        let Some(counter) = counter else {
            return Err(self.err(format!("{var} is not a variable")));
        };
        self.write_place(&counter, Value::Int(from))?;
        Ok((counter, to, step))
    }

    fn for_loop(
        &mut self,
        counter: &Place,
        to: i64,
        step: i64,
        body: &'a [Stmt],
        l: u32,
    ) -> Result<Flow, RunError> {
        while self.for_continues(counter, to, step)? {
            if let Some(f) = self.loop_body(body, l)? {
                return Ok(f);
            }
            self.for_next(counter, step)?;
        }
        Ok(Flow::Next)
    }

    fn for_continues(&mut self, counter: &Place, to: i64, step: i64) -> Result<bool, RunError> {
        let i = self.read_place(counter)?.int().map_err(|m| self.err(m))?;
        Ok(!((step > 0 && i > to) || (step < 0 && i < to)))
    }

    fn for_next(&mut self, counter: &Place, step: i64) -> Result<(), RunError> {
        let i = self.read_place(counter)?.int().map_err(|m| self.err(m))?;
        let next = int_result(i.checked_add(step)).map_err(|m| self.err(m))?;
        self.write_place(counter, next)
    }

    fn exec_loop(&mut self, body: &'a [Stmt], l: u32) -> Result<Flow, RunError> {
        loop {
            if let Some(f) = self.loop_body(body, l)? {
                return Ok(f);
            }
        }
    }

    fn exec_repeat(&mut self, body: &'a [Stmt], until: &Expr, l: u32) -> Result<Flow, RunError> {
        loop {
            if let Some(f) = self.loop_body(body, l)? {
                return Ok(f);
            }
            if self.eval_bool(until)? {
                return Ok(Flow::Next);
            }
        }
    }

    fn exec_switch(
        &mut self,
        selector: &Expr,
        cases: &'a [(Vec<Expr>, Vec<Stmt>)],
        default: Option<&'a [Stmt]>,
    ) -> Result<Flow, RunError> {
        match self.switch_body(selector, cases, default)? {
            Some(body) => self.exec_block(body),
            None => Ok(Flow::Next),
        }
    }

    /// The body a SWITCH runs, if any.
    fn switch_body(
        &mut self,
        selector: &Expr,
        cases: &'a [(Vec<Expr>, Vec<Stmt>)],
        default: Option<&'a [Stmt]>,
    ) -> Result<Option<&'a [Stmt]>, RunError> {
        let sel = self.eval(selector)?;
        for (vals, body) in cases {
            for v in vals {
                let v = self.eval(v)?;
                if values_equal(&sel, &v).map_err(|m| self.err(m))? {
                    return Ok(Some(body));
                }
            }
        }
        Ok(default)
    }

    fn exec_return(&mut self, e: Option<&Expr>) -> Result<Flow, RunError> {
        let v = match e {
            Some(e) => Some(self.eval(e)?),
            None => None,
        };
        Ok(Flow::Return(v))
    }

    fn exec_wait_sec(&mut self, e: &Expr, l: u32) -> Result<Flow, RunError> {
        let t = self.eval_num(e)?;
        if !(t >= 0.0 && t.is_finite()) {
            return Err(self.err(format!("WAIT SEC {t}: the time must not be negative")));
        }
        self.push(Step::Dwell {
            seconds: t,
            line: l,
        })?;
        Ok(Flow::Next)
    }

    fn exec_wait_for(&mut self, e: &Expr) -> Result<Flow, RunError> {
        if !self.eval_bool(e)? {
            return Err(self.err(
                "WAIT FOR: the condition is FALSE and nothing in the simulator can change it (the program would wait forever)",
            ));
        }
        Ok(Flow::Next)
    }

    fn exec_motion(
        &mut self,
        kind: KrlMotion,
        aux: Option<&Expr>,
        target: &Expr,
        approx: bool,
    ) -> Result<Flow, RunError> {
        let approx_mm = if approx { self.cdis()? } else { 0.0 };
        let speeds = self.speeds()?;
        self.motion(kind, aux, target, approx_mm, speeds)?;
        Ok(Flow::Next)
    }

    fn motion(
        &mut self,
        kind: KrlMotion,
        aux: Option<&Expr>,
        target: &Expr,
        approx_mm: f64,
        sp: Speeds,
    ) -> Result<(), RunError> {
        self.enter()?;
        let r = self.motion_body(kind, aux, target, approx_mm, sp);
        self.nesting -= 1;
        r
    }

    fn declare(&mut self, ty: &str, d: &kuka_krl::Declarator) -> Result<(), RunError> {
        let name = d.name.to_ascii_uppercase();
        let Some(mut value) = self.type_template(ty) else {
            if self.frames.is_empty() {
                self.globals
                    .insert(name, Value::Opaque(ty.to_ascii_uppercase()));
                return Ok(());
            }
            return Err(Unsupported {
                line: self.line,
                what: format!("the type {ty}"),
            }
            .into());
        };
        if !d.dims.is_empty() {
            let mut dims = Vec::with_capacity(d.dims.len());
            let mut total = 1usize;
            for e in &d.dims {
                let n = self.eval_int(e)?;
                if n < 1 || n as u64 > MAX_ARRAY as u64 {
                    return Err(self.err(format!("array size {n} of {} is out of range", d.name)));
                }
                total = total.saturating_mul(n as usize);
                dims.push(n as usize);
            }
            if total > MAX_ARRAY {
                return Err(self.err(format!("the array {} is too large", d.name)));
            }
            // Counted before the array is allocated.
            self.hold(cells(&value).saturating_mul(total))?;
            value = Value::Array(dims, vec![value; total]);
        } else if !matches!(
            self.frames.last().and_then(|f| f.get(&name)),
            Some(Slot::Val(_) | Slot::Ref(_))
        ) {
            self.hold(cells(&value))?;
        }
        match self.frames.last_mut() {
            None => {
                if let Some(old) = self.globals.insert(name.clone(), value) {
                    self.cells = self.cells.saturating_sub(cells(&old));
                }
            }
            Some(frame) => match frame.get_mut(&name) {
                // The declaration of an OUT parameter: the caller's variable.
                Some(Slot::Ref(_)) => return Ok(()),
                // The declaration of an IN parameter: give the value its type.
                Some(Slot::Val(v)) => {
                    let given = std::mem::replace(v, Value::Unset(Scalar::Int));
                    let r = assign_into(&mut value, given);
                    *v = value;
                    r.map_err(|m| self.err(format!("parameter {}: {m}", d.name)))?;
                    return Ok(());
                }
                None => {
                    frame.insert(name.clone(), Slot::Val(value));
                }
            },
        }
        if let Some(init) = &d.init {
            let v = self.eval(init)?;
            let p = self.resolve(&name)?;
            self.write_place(&p, v)?;
        }
        Ok(())
    }

    // ---- test harness: CWRITE($FCT_CALL, …) on the in-memory files

    fn harness_mut(&mut self) -> Result<&mut Harness, RunError> {
        let line = self.line;
        self.harness.as_mut().ok_or(RunError::Runtime {
            line,
            message: "internal: file access outside the test harness".into(),
        })
    }

    /// A variable argument that CWRITE writes (`OUT`).
    fn out_place(&mut self, e: &Expr, what: &str) -> Result<Place, RunError> {
        match self.place_of(e)? {
            Some(p) if !matches!(p.root, Root::Computed(_)) => Ok(p),
            _ => Err(self.err(format!("CWRITE: {what} must be a variable"))),
        }
    }

    fn eval_text(&mut self, e: &Expr) -> Result<String, RunError> {
        let v = self.eval(e)?;
        text_of(&v).map_err(|m| self.err(format!("CWRITE: {m}")))
    }

    fn cwrite(&mut self, args: &[Expr]) -> Result<(), RunError> {
        let [channel, st, md, func, rest @ ..] = args else {
            return Err(self.err(
                "CWRITE takes a channel, a STATE_T, a MODUS_T and a command with its arguments",
            ));
        };
        if !matches!(channel, Expr::Var(n) if n.eq_ignore_ascii_case("$FCT_CALL")) {
            return Err(Unsupported {
                line: self.line,
                what: format!(
                    "CWRITE({}) (the test harness has only $FCT_CALL)",
                    describe(channel)
                ),
            }
            .into());
        }
        let st = self.out_place(st, "the state (STATE_T)")?;
        match self.eval(md)? {
            Value::Enum(_) => {}
            v => {
                return Err(self.err(format!(
                    "CWRITE: the mode must be a MODUS_T, found {}",
                    v.type_name()
                )));
            }
        }
        let func = self.eval_text(func)?;
        let msg_no = match func.to_ascii_lowercase().as_str() {
            "krl_fopen" => self.krl_fopen(rest)?,
            "krl_fgets" => self.krl_fgets(rest)?,
            "krl_fwriteln" => self.krl_fwrite(rest, true)?,
            "krl_fputs" => self.krl_fwrite(rest, false)?,
            "krl_fclose" => {
                let [h] = rest else {
                    return Err(self.err("krl_fclose takes a handle"));
                };
                let h = self.eval_int(h)?;
                match self.harness_mut()?.open.remove(&h) {
                    Some(_) => 0,
                    None => MSG_NO_HANDLE,
                }
            }
            "krl_fclose_all" => {
                if !rest.is_empty() {
                    return Err(self.err("krl_fclose_all takes no arguments"));
                }
                self.harness_mut()?.open.clear();
                0
            }
            other => {
                return Err(Unsupported {
                    line: self.line,
                    what: format!("CWRITE($FCT_CALL, …, \"{other}\") in the test harness"),
                }
                .into());
            }
        };
        let ret1 = if msg_no == 0 { "DATA_OK" } else { "CMD_ABORT" };
        let status = Value::Struct(
            "STATE_T".into(),
            vec![
                ("RET1".into(), Value::Enum(ret1.into())),
                ("HITS".into(), Value::Int(0)),
                ("LENGTH".into(), Value::Int(0)),
                ("MSG_NO".into(), Value::Int(msg_no)),
            ],
        );
        self.write_place(&st, status)
    }

    /// `"krl_fopen", name, mode, handle [, size]`; the `MSG_NO` (0 = done).
    fn krl_fopen(&mut self, args: &[Expr]) -> Result<i64, RunError> {
        let (name, mode, handle) = match args {
            [n, m, h] | [n, m, h, _] => (n, m, h),
            _ => return Err(self.err("krl_fopen takes a name, a mode and a handle")),
        };
        let name = self.eval_text(name)?;
        let mode = self.eval_text(mode)?.to_ascii_lowercase();
        let handle = self.out_place(handle, "the handle")?;
        let hs = self.harness_mut()?;
        match mode.as_str() {
            "r" if !hs.files.contains_key(&name) => return Ok(MSG_NO_OPEN),
            "r" => {}
            "w" => {
                hs.files.insert(name.clone(), String::new());
            }
            "a" => {
                hs.files.entry(name.clone()).or_default();
            }
            _ => return Ok(MSG_NO_OPEN),
        }
        let h = hs.next_handle;
        hs.next_handle += 1;
        hs.open.insert(
            h,
            OpenFile {
                name,
                write: mode != "r",
                pos: 0,
            },
        );
        self.write_place(&handle, Value::Int(h))?;
        Ok(0)
    }

    /// `"krl_fgets", handle, buf[], size, count`.
    fn krl_fgets(&mut self, args: &[Expr]) -> Result<i64, RunError> {
        let [h, buf, size, count] = args else {
            return Err(self.err("krl_fgets takes a handle, a CHAR array, a size and a count"));
        };
        let h = self.eval_int(h)?;
        let size = usize::try_from(self.eval_int(size)?).unwrap_or(0);
        let buf = self.out_place(buf, "the buffer")?;
        let count = self.out_place(count, "the count")?;
        let mut chars = self.read_place(&buf)?;
        let Value::Array(dims, elems) = &mut chars else {
            return Err(self.err("krl_fgets: the buffer must be a CHAR array"));
        };
        if dims.len() != 1 || elems.first().and_then(Value::scalar_kind) != Some(Scalar::Char) {
            return Err(self.err("krl_fgets: the buffer must be a CHAR array"));
        }
        let room = size.min(elems.len());
        let hs = self.harness_mut()?;
        let Some(f) = hs.open.get_mut(&h).filter(|f| !f.write) else {
            return Ok(MSG_NO_HANDLE);
        };
        let text = hs.files.get(&f.name).map_or(&[][..], |t| t.as_bytes());
        let Some(rest) = text.get(f.pos..).filter(|r| !r.is_empty()) else {
            return Ok(MSG_NO_EOF);
        };
        let (mut line, mut used) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        if let Some(l) = line.strip_suffix(b"\r") {
            line = l;
        }
        if line.len() > room {
            line = &line[..room];
            used = room;
        }
        f.pos += used;
        let n = line.len();
        for (e, &b) in elems.iter_mut().zip(line) {
            *e = Value::Char(b);
        }
        if let Some(e) = elems.get_mut(n) {
            *e = Value::Char(0);
        }
        self.write_place(&buf, chars)?;
        self.write_place(&count, Value::Int(n as i64))?;
        Ok(0)
    }

    /// `"krl_fwriteln", handle, buf[]` (`newline`) or `"krl_fputs"`.
    fn krl_fwrite(&mut self, args: &[Expr], newline: bool) -> Result<i64, RunError> {
        let [h, buf] = args else {
            return Err(self.err("krl_fwriteln/krl_fputs take a handle and a CHAR array"));
        };
        let h = self.eval_int(h)?;
        let mut text = self.eval_text(buf)?;
        if newline {
            text.push('\n');
        }
        let hs = self.harness_mut()?;
        let Some(f) = hs.open.get(&h).filter(|f| f.write) else {
            return Ok(MSG_NO_HANDLE);
        };
        hs.files.entry(f.name.clone()).or_default().push_str(&text);
        Ok(0)
    }

    fn bas(&mut self, args: &[Expr]) -> Result<(), RunError> {
        let cmd = match args.first() {
            Some(e) => self.eval(e)?,
            None => return Err(self.err("BAS needs a command")),
        };
        for a in args.iter().skip(1) {
            self.eval(a)?;
        }
        if cmd != Value::Enum("INITMOV".into()) {
            return Err(Unsupported {
                line: self.line,
                what: format!("BAS({})", cmd.type_name()),
            }
            .into());
        }
        let sp = self.speed;
        let arr = |v: f64| Value::Array(vec![6], vec![Value::Real(v); 6]);
        self.globals
            .insert("$VEL_AXIS".into(), arr(sp.ptp_velocity_pct));
        self.globals
            .insert("$ACC_AXIS".into(), arr(sp.ptp_acceleration_pct));
        for (root, v) in [
            ("$VEL", sp.cp_velocity),
            ("$ACC", sp.cp_acceleration_pct / 100.0 * ACC_CP_MAX),
        ] {
            if let Some(Value::Struct(_, f)) = self.globals.get_mut(root)
                && let Some((_, slot)) = f.iter_mut().find(|(n, _)| n == "CP")
            {
                *slot = Value::Real(v);
            }
        }
        Ok(())
    }

    // ---- motions

    fn target_fields(&mut self, e: &Expr) -> Result<Vec<(String, Value)>, RunError> {
        match self.eval(e)? {
            Value::Struct(_, f) => Ok(f),
            v => Err(self.err(format!(
                "a motion target must be a position (FRAME, POS, E6POS, AXIS, E6AXIS), found {}",
                v.type_name()
            ))),
        }
    }

    fn is_axis_target(&self, fields: &[(String, Value)]) -> Result<bool, RunError> {
        let has = |names: &[&str]| fields.iter().any(|(n, _)| names.contains(&n.as_str()));
        let axis = has(&AXIS_FIELDS);
        if axis && has(&FRAME_FIELDS) {
            return Err(self.err("a motion target mixes axis (A1..A6) and Cartesian components"));
        }
        for (n, _) in fields {
            let ok = EXT_FIELDS.contains(&n.as_str())
                || if axis {
                    AXIS_FIELDS.contains(&n.as_str())
                } else {
                    FRAME_FIELDS.contains(&n.as_str()) || n == "S" || n == "T"
                };
            if !ok {
                return Err(self.err(format!("{n} is not a component of a position")));
            }
        }
        Ok(axis)
    }

    /// A Cartesian target: missing components from the programmed pose, or
    /// (relative) added to it.
    fn cart_target(&self, fields: &[(String, Value)], rel: bool) -> Result<Pose, RunError> {
        let mut v = [None; 6];
        for (slot, n) in v.iter_mut().zip(FRAME_FIELDS) {
            *slot = num_field(fields, n).map_err(|m| self.err(m))?;
        }
        let cur = self.pos;
        let p = if rel {
            let d = Pose::new(
                v[0].unwrap_or(0.0),
                v[1].unwrap_or(0.0),
                v[2].unwrap_or(0.0),
                v[3].unwrap_or(0.0),
                v[4].unwrap_or(0.0),
                v[5].unwrap_or(0.0),
            );
            let mut p = if d.a == 0.0 && d.b == 0.0 && d.c == 0.0 {
                cur
            } else {
                Pose::from_parts(cur.position(), d.rotation() * cur.rotation())
            };
            p.x = cur.x + d.x;
            p.y = cur.y + d.y;
            p.z = cur.z + d.z;
            p
        } else {
            let c = cur.to_array();
            let g = |i: usize| v[i].unwrap_or(c[i]);
            Pose::new(g(0), g(1), g(2), g(3), g(4), g(5))
        };
        if !p.is_finite() {
            return Err(self.err("the target is not a finite position"));
        }
        Ok(p)
    }

    fn st_field(&self, fields: &[(String, Value)], n: &str) -> Result<Option<u8>, RunError> {
        match num_field(fields, n).map_err(|m| self.err(m))? {
            None => Ok(None),
            Some(v) if (0.0..=255.0).contains(&v) && v.fract() == 0.0 => Ok(Some(v as u8)),
            Some(v) => Err(self.err(format!("{n} = {v} is not a valid Status/Turn"))),
        }
    }

    fn emit(
        &mut self,
        kind: MoveKind,
        velocity: f64,
        acc: f64,
        approx_mm: f64,
    ) -> Result<(), RunError> {
        let step = Step::Move {
            tool: self.tool()?,
            base: self.base()?,
            motion: Motion {
                kind,
                velocity,
                acceleration_pct: acc,
                approx_mm,
            },
            line: self.line,
        };
        self.push(step)
    }

    fn moved_to_pose(&mut self, p: Pose) {
        self.pos = p;
        self.axes = None;
        self.cart_line = self.line;
    }

    fn motion_body(
        &mut self,
        kind: KrlMotion,
        aux: Option<&Expr>,
        target: &Expr,
        approx_mm: f64,
        sp: Speeds,
    ) -> Result<(), RunError> {
        let rel = matches!(
            kind,
            KrlMotion::PtpRel | KrlMotion::LinRel | KrlMotion::CircRel
        );
        let fields = self.target_fields(target)?;
        let axis = self.is_axis_target(&fields)?;
        match kind {
            KrlMotion::Ptp | KrlMotion::PtpRel if axis => {
                let mut axes = [0.0; 6];
                for (i, n) in AXIS_FIELDS.iter().enumerate() {
                    let v = num_field(&fields, n).map_err(|m| self.err(m))?;
                    axes[i] = match (v, self.axes) {
                        (Some(v), Some(cur)) if rel => cur[i] + v,
                        (Some(v), _) if !rel => v,
                        (None, Some(cur)) => cur[i],
                        _ => {
                            return Err(self.err(format!(
                                "{} needs the programmed axes, which are not known after the Cartesian motion on line {}",
                                if rel { "PTP_REL with axis values" } else { "an axis PTP with missing axes" },
                                self.cart_line
                            )));
                        }
                    };
                }
                if !axes.iter().all(|a| a.is_finite()) {
                    return Err(self.err("the axis target is not finite"));
                }
                self.emit(
                    MoveKind::PtpAxes { axes },
                    sp.ptp,
                    sp.ptp_acc_pct,
                    approx_mm,
                )?;
                self.pos = self.model.forward(&axes, &self.tool()?, &self.base()?);
                self.axes = Some(axes);
                self.status = Some(self.model.status(&axes));
                self.turn = Some(RobotModel::turn(&axes));
            }
            KrlMotion::Ptp | KrlMotion::PtpRel => {
                let target = self.cart_target(&fields, rel)?;
                let (s, t) = if rel {
                    (None, None)
                } else {
                    (self.st_field(&fields, "S")?, self.st_field(&fields, "T")?)
                };
                self.emit(
                    MoveKind::Ptp { target, s, t },
                    sp.ptp,
                    sp.ptp_acc_pct,
                    approx_mm,
                )?;
                self.moved_to_pose(target);
                self.status = s.or(self.status);
                self.turn = t;
            }
            _ if axis => {
                return Err(self.err("LIN and CIRC need a Cartesian target, not axis values"));
            }
            KrlMotion::Lin | KrlMotion::LinRel => {
                let target = self.cart_target(&fields, rel)?;
                self.emit(MoveKind::Lin { target }, sp.cp, sp.cp_acc_pct, approx_mm)?;
                self.moved_to_pose(target);
                self.turn = None;
            }
            KrlMotion::Circ | KrlMotion::CircRel => {
                let Some(aux) = aux else {
                    return Err(self.err("CIRC without an auxiliary point"));
                };
                let af = self.target_fields(aux)?;
                if self.is_axis_target(&af)? {
                    return Err(self.err("the CIRC auxiliary point must be Cartesian"));
                }
                let aux = self.cart_target(&af, rel)?;
                let target = self.cart_target(&fields, rel)?;
                self.emit(
                    MoveKind::Circ { aux, target },
                    sp.cp,
                    sp.cp_acc_pct,
                    approx_mm,
                )?;
                self.moved_to_pose(target);
                self.turn = None;
            }
        }
        Ok(())
    }

    /// Applies a spline point's `WITH` assignments, reads the speeds and
    /// restores `$VEL`/`$ACC`.
    fn point_speeds(&mut self, with: &[(Expr, Expr)]) -> Result<Speeds, RunError> {
        let saved: Vec<(String, Option<Value>)> = ["$VEL", "$ACC"]
            .iter()
            .map(|n| (n.to_string(), self.globals.get(*n).cloned()))
            .collect();
        let mut r = Ok(());
        for (t, v) in with {
            r = self.eval(v).and_then(|v| match self.place_of(t)? {
                Some(p) => self.write_place(&p, v),
                None => Err(self.err(format!("cannot assign to {}", describe(t)))),
            });
            if r.is_err() {
                break;
            }
        }
        let sp = r.and_then(|_| self.speeds());
        for (n, v) in saved {
            if let Some(v) = v {
                self.globals.insert(n, v);
            }
        }
        sp
    }

    fn spline(&mut self, points: &'a [SplinePoint], c_spl: bool) -> Result<(), RunError> {
        let first = self.steps.len();
        let cdis = self.cdis()?;
        let mut run: Vec<(Pose, Speeds, u32)> = Vec::new();
        let mut run_start = self.pos;
        for p in points {
            self.line = p.line;
            self.tick()?;
            let sp = self.point_speeds(&p.with)?;
            match p.kind {
                SplinePointKind::Spl => {
                    let fields = self.target_fields(&p.target)?;
                    if self.is_axis_target(&fields)? {
                        return Err(self.err("SPL needs a Cartesian target, not axis values"));
                    }
                    let pose = self.cart_target(&fields, false)?;
                    if run.is_empty() {
                        run_start = self.pos;
                    }
                    run.push((pose, sp, p.line));
                    self.moved_to_pose(pose);
                    self.turn = None;
                }
                kind => {
                    self.flush_spl(run_start, &mut run)?;
                    self.line = p.line;
                    let (k, approx) = match kind {
                        SplinePointKind::Slin => (KrlMotion::Lin, cdis),
                        SplinePointKind::Scirc => (KrlMotion::Circ, cdis),
                        _ => (KrlMotion::Ptp, 0.0),
                    };
                    self.motion(k, p.aux.as_ref(), &p.target, approx, sp)?;
                }
            }
        }
        self.flush_spl(run_start, &mut run)?;
        if self.steps.len() > first
            && let Some(Step::Move { motion, .. }) = self.steps.last_mut()
        {
            motion.approx_mm = if c_spl { cdis } else { 0.0 };
        }
        Ok(())
    }

    /// Samples a run of `SPL` points (a centripetal Catmull-Rom curve from
    /// `start` through them) into short, blended LINs.
    fn flush_spl(
        &mut self,
        start: Pose,
        run: &mut Vec<(Pose, Speeds, u32)>,
    ) -> Result<(), RunError> {
        if run.is_empty() {
            return Ok(());
        }
        let pts = std::mem::take(run);
        let mut q: Vec<Pose> = Vec::with_capacity(pts.len() + 1);
        q.push(start);
        q.extend(pts.iter().map(|p| p.0));
        for (i, (b, sp, line)) in pts.iter().enumerate() {
            self.line = *line;
            let a = q[i];
            let (pa, pb) = (p3(&a), p3(b));
            if dist(pa, pb) < 1e-6 {
                if a.angle_deg(b) > 1e-9 {
                    self.emit(MoveKind::Lin { target: *b }, sp.cp, sp.cp_acc_pct, 0.0)?;
                }
                continue;
            }
            let reflect = |x: [f64; 3], y: [f64; 3]| {
                [2.0 * x[0] - y[0], 2.0 * x[1] - y[1], 2.0 * x[2] - y[2]]
            };
            let p0 = match i.checked_sub(1).and_then(|k| q.get(k)) {
                Some(p) if dist(p3(p), pa) >= 1e-6 => p3(p),
                _ => reflect(pa, pb),
            };
            let p3_ = match q.get(i + 2) {
                Some(p) if dist(p3(p), pb) >= 1e-6 => p3(p),
                _ => reflect(pb, pa),
            };
            let ctrl = [p0, pa, pb, p3_];
            // Arc-length table.
            let m = ((dist(pa, pb) / 0.25).ceil() as usize).clamp(64, 4000);
            let mut table = Vec::with_capacity(m + 1);
            let mut prev = pa;
            let mut len = 0.0;
            table.push((0.0, 0.0));
            for k in 1..=m {
                let t = k as f64 / m as f64;
                let x = catmull_rom(&ctrl, t);
                len += dist(prev, x);
                table.push((t, len));
                prev = x;
            }
            let n = ((len / SPL_SAMPLE_MM).ceil() as usize).max(1);
            let (qa, qb) = (a.rotation(), b.rotation());
            let mut last = pa;
            for k in 1..=n {
                let target = if k == n {
                    *b
                } else {
                    let s = len * k as f64 / n as f64;
                    let j = table.partition_point(|(_, l)| *l < s).clamp(1, m);
                    let (t0, l0) = table[j - 1];
                    let (t1, l1) = table[j];
                    let t = if l1 > l0 {
                        t0 + (t1 - t0) * (s - l0) / (l1 - l0)
                    } else {
                        t1
                    };
                    let x = catmull_rom(&ctrl, t);
                    let mut p = Pose::from_parts(a.position(), qa.slerp(qb, s / len));
                    p.x = x[0];
                    p.y = x[1];
                    p.z = x[2];
                    p
                };
                let chord = dist(last, p3(&target));
                last = p3(&target);
                self.emit(MoveKind::Lin { target }, sp.cp, sp.cp_acc_pct, chord / 2.0)?;
            }
        }
        Ok(())
    }
}

fn p3(p: &Pose) -> [f64; 3] {
    [p.x, p.y, p.z]
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Centripetal Catmull-Rom (Barry–Goldman) between `c[1]` (t = 0) and
/// `c[2]` (t = 1).
fn catmull_rom(c: &[[f64; 3]; 4], t: f64) -> [f64; 3] {
    let knot = |a: [f64; 3], b: [f64; 3]| dist(a, b).sqrt().max(1e-9);
    let t0 = 0.0;
    let t1 = t0 + knot(c[0], c[1]);
    let t2 = t1 + knot(c[1], c[2]);
    let t3 = t2 + knot(c[2], c[3]);
    let u = t1 + (t2 - t1) * t;
    let lerp = |p: [f64; 3], q: [f64; 3], ta: f64, tb: f64| {
        let w = (u - ta) / (tb - ta);
        [
            p[0] + (q[0] - p[0]) * w,
            p[1] + (q[1] - p[1]) * w,
            p[2] + (q[2] - p[2]) * w,
        ]
    };
    let a1 = lerp(c[0], c[1], t0, t1);
    let a2 = lerp(c[1], c[2], t1, t2);
    let a3 = lerp(c[2], c[3], t2, t3);
    let b1 = lerp(a1, a2, t0, t2);
    let b2 = lerp(a2, a3, t1, t3);
    lerp(b1, b2, t1, t2)
}

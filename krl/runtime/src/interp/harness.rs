//! The test harness of [`run_with_files`](super::run_with_files): the
//! in-memory files behind `CWRITE($FCT_CALL, …)`, the controller's types
//! and system variables, and the [`Globals`] a run leaves.

use std::collections::{BTreeMap, HashMap};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use kuka_krl::Expr;

use super::values::{
    PathElem, Scalar, Value, assign_into, axis_value, flat_index, step_into, walk_mut,
};
use super::vars::{Place, Root};
use super::{ANALOG_CHANNELS, Interp, RunError, Unsupported, describe};

/// Most statements in the test harness ([`run_with_files`](super::run_with_files)), which runs
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

/// Global variables after [`run_with_files`](super::run_with_files)
/// (names are case-insensitive); in hosted mode, the variables a turn
/// hands to the host.
#[derive(Debug, Clone, Default)]
pub struct Globals {
    pub(super) vars: HashMap<String, Value>,
    pub(super) open_files: Vec<String>,
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

    /// The value at a KRL path as KUKAVARPROXY shows it (`100`, `1.5`,
    /// `TRUE`, `"text"`, `#T1`, `{FRAME: X 1.0, ...}`); `None` for a
    /// variable that does not exist, is not set yet, or is a whole array.
    pub fn krl_text(&self, path: &str) -> Option<String> {
        if let Some((array, row)) = char_row(path) {
            let Value::Array(dims, items) = self.at(array)? else {
                return None;
            };
            let (start, width) = row_span(dims, row)?;
            let text: String = items
                .get(start..start + width)?
                .iter()
                .map_while(|c| match c {
                    Value::Char(c) if *c != 0 => Some(char::from(*c)),
                    _ => None,
                })
                .collect();
            return Some(format!("\"{text}\""));
        }
        krl_of(self.at(path)?)
    }

    /// Assigns KRL text (as KUKAVARPROXY writes it) at a path: the value
    /// is converted to the variable's type as a KRL assignment does, and a
    /// structure value sets the components it names.
    pub fn assign_krl(&mut self, path: &str, text: &str) -> Result<(), String> {
        let v = kuka_kvp::KrlValue::parse(text)
            .map(value_of)
            .ok_or_else(|| format!("{text:?} is not a KRL value"))?;
        if let Some((array, row)) = char_row(path) {
            // `TOOL_NAME[3,] = "gripper"`: the row's characters, the rest
            // of the row unset (as a string assigned to a CHAR array).
            let Value::Str(text) = v else {
                return Err("a CHAR array row takes a string".into());
            };
            let (root, elems) =
                parse_path(array).ok_or_else(|| format!("{path:?} is not a path"))?;
            let slot = self
                .vars
                .get_mut(&root)
                .ok_or_else(|| format!("{root} is not declared"))?;
            let Value::Array(dims, items) = walk_mut(slot, &elems)? else {
                return Err(format!("{array} is not an array"));
            };
            let (start, width) =
                row_span(dims, row).ok_or_else(|| format!("{path} is not a CHAR array row"))?;
            if text.len() > width {
                return Err(format!(
                    "the string has {} characters, the row only {width}",
                    text.len()
                ));
            }
            let row = items
                .get_mut(start..start + width)
                .ok_or_else(|| "index out of range".to_string())?;
            if row.first().and_then(Value::scalar_kind) != Some(Scalar::Char) {
                return Err(format!("{array} is not a CHAR array"));
            }
            let bytes = text.as_bytes();
            for (i, e) in row.iter_mut().enumerate() {
                *e = bytes
                    .get(i)
                    .map_or(Value::Unset(Scalar::Char), |b| Value::Char(*b));
            }
            return Ok(());
        }
        let (root, elems) = parse_path(path).ok_or_else(|| format!("{path:?} is not a path"))?;
        let slot = self
            .vars
            .get_mut(&root)
            .ok_or_else(|| format!("{root} is not declared"))?;
        let slot = walk_mut(slot, &elems)?;
        if matches!(slot, Value::Array(..)) && !matches!(v, Value::Str(_)) {
            return Err("an array is written element by element".into());
        }
        assign_into(slot, v)
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

    /// Sets an INT variable (a host's system variable such as `$ROB_TIMER`).
    pub fn set_int(&mut self, name: &str, v: i64) {
        self.vars.insert(name.to_ascii_uppercase(), Value::Int(v));
    }

    /// Sets a BOOL variable.
    pub fn set_bool(&mut self, name: &str, v: bool) {
        self.vars.insert(name.to_ascii_uppercase(), Value::Bool(v));
    }

    /// Sets a REAL variable.
    pub fn set_real(&mut self, name: &str, v: f64) {
        self.vars.insert(name.to_ascii_uppercase(), Value::Real(v));
    }

    /// Sets an ENUM variable (`value` without `#`).
    pub fn set_enum(&mut self, name: &str, value: &str) {
        self.vars.insert(
            name.to_ascii_uppercase(),
            Value::Enum(value.to_ascii_uppercase()),
        );
    }

    /// Sets a CHAR array of `len` characters to `text`, padded with spaces
    /// (as `$PRO_NAME1`).
    pub fn set_chars(&mut self, name: &str, text: &str, len: usize) {
        let mut chars: Vec<Value> = text.bytes().take(len).map(Value::Char).collect();
        chars.resize(len, Value::Char(b' '));
        self.vars
            .insert(name.to_ascii_uppercase(), Value::Array(vec![len], chars));
    }

    /// Sets a CHAR array of `len` characters to `text` followed by zeros
    /// (as a `.dat` line `name[]="text"` leaves it).
    pub fn set_text(&mut self, name: &str, text: &str, len: usize) {
        let mut chars: Vec<Value> = text.bytes().take(len).map(Value::Char).collect();
        chars.resize(len, Value::Char(0));
        self.vars
            .insert(name.to_ascii_uppercase(), Value::Array(vec![len], chars));
    }

    /// Sets an E6AXIS variable (`$AXIS_ACT`).
    pub fn set_axes(&mut self, name: &str, axes: &kuka_kinematics::Axes) {
        self.vars
            .insert(name.to_ascii_uppercase(), super::values::axis_value(axes));
    }

    /// Sets a REAL array.
    pub fn set_reals(&mut self, name: &str, values: &[f64]) {
        self.vars.insert(
            name.to_ascii_uppercase(),
            Value::Array(
                vec![values.len()],
                values.iter().map(|v| Value::Real(*v)).collect(),
            ),
        );
    }

    /// Sets a structure of REAL components (`$VEL_MA`: `CP`, `ORI1`, `ORI2`).
    pub fn set_real_struct(&mut self, name: &str, ty: &str, fields: &[(&str, f64)]) {
        self.vars.insert(
            name.to_ascii_uppercase(),
            super::values::real_struct(ty, fields),
        );
    }

    /// Sets an element of a BOOL array (1-based, as `$IN[3]`); false when
    /// the array or the element does not exist.
    pub fn set_bool_element(&mut self, name: &str, index: i64, v: bool) -> bool {
        match self.vars.get_mut(&name.to_ascii_uppercase()) {
            Some(Value::Array(dims, items)) => match flat_index(dims, &[index])
                .ok()
                .and_then(|k| items.get_mut(k))
            {
                Some(slot @ Value::Bool(_)) => {
                    *slot = Value::Bool(v);
                    true
                }
                _ => false,
            },
            _ => false,
        }
    }

    /// Sets an element of a REAL array (1-based, as `$ANIN[3]`); false
    /// when the array or the element does not exist or is not a REAL.
    pub fn set_real_element(&mut self, name: &str, index: i64, v: f64) -> bool {
        match self.vars.get_mut(&name.to_ascii_uppercase()) {
            Some(Value::Array(dims, items)) => match flat_index(dims, &[index])
                .ok()
                .and_then(|k| items.get_mut(k))
            {
                Some(slot @ Value::Real(_)) => {
                    *slot = Value::Real(v);
                    true
                }
                _ => false,
            },
            _ => false,
        }
    }

    /// Sets an element of an INT array (1-based, as `$TIMER[3]`); false
    /// when the array or the element does not exist.
    pub fn set_int_element(&mut self, name: &str, index: i64, v: i64) -> bool {
        match self.vars.get_mut(&name.to_ascii_uppercase()) {
            Some(Value::Array(dims, items)) => match flat_index(dims, &[index])
                .ok()
                .and_then(|k| items.get_mut(k))
            {
                Some(slot @ Value::Int(_)) => {
                    *slot = Value::Int(v);
                    true
                }
                _ => false,
            },
            _ => false,
        }
    }

    /// Sets an INT array of `len` elements, all `v`, unless it exists.
    pub fn ensure_ints(&mut self, name: &str, len: usize, v: i64) {
        self.vars
            .entry(name.to_ascii_uppercase())
            .or_insert_with(|| Value::Array(vec![len], vec![Value::Int(v); len]));
    }

    /// Sets a REAL array of `len` elements, all `v`, unless it exists.
    pub fn ensure_reals(&mut self, name: &str, len: usize, v: f64) {
        self.vars
            .entry(name.to_ascii_uppercase())
            .or_insert_with(|| Value::Array(vec![len], vec![Value::Real(v); len]));
    }

    /// Sets a BOOL array of `len` elements, all `v`, unless it exists.
    pub fn ensure_bools(&mut self, name: &str, len: usize, v: bool) {
        self.vars
            .entry(name.to_ascii_uppercase())
            .or_insert_with(|| Value::Array(vec![len], vec![Value::Bool(v); len]));
    }

    /// Adds every variable of `other` this set does not have (a module
    /// that starts later brings its own `.dat` globals).
    pub fn merge_missing(&mut self, other: Globals) {
        for (k, v) in other.vars {
            self.vars.entry(k).or_insert(v);
        }
    }

    /// Whether the variable exists.
    pub fn has(&self, name: &str) -> bool {
        self.vars.contains_key(&name.to_ascii_uppercase())
    }

    /// A variable's value as the interpreter holds it (debug form), for
    /// diagnostics; `None` when it does not exist.
    pub fn describe(&self, name: &str) -> Option<String> {
        Some(format!("{:?}", self.vars.get(&name.to_ascii_uppercase())?))
    }

    /// The text of a CHAR array up to its first 0 or unset element.
    pub fn text(&self, name: &str) -> Option<String> {
        text_of(self.vars.get(&name.to_ascii_uppercase())?).ok()
    }

    /// The names of the variables (upper-case).
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.vars.keys().map(String::as_str)
    }

    /// Files that were still open when [`run_with_files`](super::run_with_files) ended.
    pub fn open_files(&self) -> &[String] {
        &self.open_files
    }
}

/// The files a controller holds open through `CWRITE($FCT_CALL, …)`, with
/// their handles. A hosted run shares one table with every other run of
/// the same controller ([`HostedFiles::open`](super::HostedFiles)): on a
/// KRC a handle outlives the run that opened it (an error stop, a CANCEL)
/// until `krl_fclose_all` or a reboot. Each handle belongs to the
/// interpreter that opened it ([`HostedFiles::interpreter`](super::HostedFiles)):
/// KUKA's text says a file opened by one interpreter may not be accessed
/// (written, closed) by the other, so the other's `krl_fgets`,
/// `krl_fclose` … find no such handle, and `krl_fclose_all` closes the
/// calling interpreter's files only (CONTROLLER.md points 1 and 3).
#[derive(Debug)]
pub struct OpenFiles {
    open: BTreeMap<i64, OpenFile>,
    next_handle: i64,
}

impl Default for OpenFiles {
    fn default() -> Self {
        OpenFiles {
            open: BTreeMap::new(),
            next_handle: 1,
        }
    }
}

impl OpenFiles {
    /// A shared, empty table (a controller after a cold start).
    pub fn shared() -> SharedOpenFiles {
        Arc::new(Mutex::new(OpenFiles::default()))
    }

    /// The names of the files open now, by handle.
    pub fn names(&self) -> Vec<String> {
        self.open.values().map(|f| f.name.clone()).collect()
    }

    /// The file of `handle` if `interpreter` opened it.
    fn of(&mut self, handle: i64, interpreter: &str) -> Option<&mut OpenFile> {
        self.open
            .get_mut(&handle)
            .filter(|f| f.interpreter == interpreter)
    }
}

/// One [`OpenFiles`] table shared by the runs of a controller.
pub type SharedOpenFiles = Arc<Mutex<OpenFiles>>;

/// The table, also after a thread panicked holding it (the table itself
/// stays consistent: every change is a single map operation).
pub(super) fn lock_open(open: &SharedOpenFiles) -> MutexGuard<'_, OpenFiles> {
    open.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The in-memory file system of [`run_with_files`](super::run_with_files).
#[derive(Debug)]
pub(super) struct Harness {
    pub(super) files: BTreeMap<String, String>,
    /// The open files: private to an in-memory run, the controller's
    /// shared table in hosted mode.
    pub(super) open: SharedOpenFiles,
    /// The interpreter this run is in: its handles are its own.
    pub(super) interpreter: String,
    /// Hosted mode: the folder the file functions work in (real files);
    /// `None`: the in-memory `files` only.
    pub(super) root: Option<std::path::PathBuf>,
    /// `RET1` of a file function that succeeded (`DATA_OK`; a simulated
    /// KSS variant answers `CMD_OK`).
    pub(super) success: String,
    /// `SREAD`/`SWRITE`'s offset: 0 = characters consumed, 1 = the 1-based
    /// position of the next character ([`HostedFiles`](super::HostedFiles)).
    pub(super) text_offset_base: i64,
}

#[derive(Debug)]
pub(super) struct OpenFile {
    pub(super) name: String,
    /// The interpreter that opened it.
    interpreter: String,
    write: bool,
    /// Read position (bytes).
    pos: usize,
    /// Hosted mode: the text of a file opened for reading, as it was when
    /// it was opened (the handle may outlive the run that opened it).
    text: Option<String>,
    /// The real file while it is open (hosted mode): locked, as an open
    /// file is on a KRC's Windows — the service cannot replace it.
    file: Option<std::fs::File>,
}

/// Most files a program may hold open at once (hosted mode); KUKA
/// documents no figure, this keeps a leaking program visible.
const MAX_OPEN_FILES: usize = 10;
/// `MSG_NO` of `krl_fopen` when [`MAX_OPEN_FILES`] are open.
const MSG_NO_TOO_MANY: i64 = -5;

/// `$ERR` of the harness.
pub(super) fn err_value(number: i64, line: u32) -> Value {
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

impl<'a> Interp<'a> {
    /// Turns on the test harness (see [`run_with_files`](super::run_with_files)).
    pub(super) fn enable_harness(&mut self, files: BTreeMap<String, String>) {
        self.harness = Some(Harness {
            files,
            open: OpenFiles::shared(),
            interpreter: String::new(),
            root: None,
            success: "DATA_OK".into(),
            text_offset_base: 0,
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
        g.insert("$USER_SAF".into(), Value::Bool(true));
        g.insert("$ALARM_STOP".into(), Value::Bool(true));
        g.insert("$ROB_TIMER".into(), Value::Int(0));
        g.insert("$ERR".into(), err_value(0, 0));
        for io in ["$IN", "$OUT"] {
            g.insert(
                io.into(),
                Value::Array(vec![4096], vec![Value::Bool(false); 4096]),
            );
        }
        // The analog channels: 32 REALs each, normalised -1.0..1.0.
        for io in ["$ANIN", "$ANOUT"] {
            g.insert(
                io.into(),
                Value::Array(
                    vec![ANALOG_CHANNELS],
                    vec![Value::Real(0.0); ANALOG_CHANNELS],
                ),
            );
        }
    }

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

    pub(super) fn cwrite(&mut self, args: &[Expr]) -> Result<(), RunError> {
        let [channel, st, md, func, rest @ ..] = args else {
            return Err(self.err(
                "CWRITE takes a channel, a STATE_T, a MODUS_T and a command with its arguments",
            ));
        };
        if self.hosted.is_some()
            && matches!(channel, Expr::Var(n) if n.eq_ignore_ascii_case("$CMD"))
        {
            let st = self.out_place(st, "the state (STATE_T)")?;
            self.eval(md)?;
            if !rest.is_empty() {
                return Err(self.err("CWRITE($CMD, …) takes one command"));
            }
            let text = self.eval_text(func)?;
            let taken = self.host_command(&text)?;
            let status = Value::Struct(
                "STATE_T".into(),
                vec![
                    (
                        "RET1".into(),
                        Value::Enum(if taken { "CMD_OK" } else { "CMD_REJ" }.into()),
                    ),
                    ("HITS".into(), Value::Int(0)),
                    ("LENGTH".into(), Value::Int(0)),
                    ("MSG_NO".into(), Value::Int(if taken { 0 } else { 1 })),
                ],
            );
            return self.write_place(&st, status);
        }
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
        if let Some(h) = self.hosted.as_mut() {
            h.host.file_call(&func);
        }
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
                let hs = self.harness_mut()?;
                let open = hs.open.clone();
                let mut open = lock_open(&open);
                if open.of(h, &hs.interpreter).is_some() {
                    open.open.remove(&h);
                    0
                } else {
                    MSG_NO_HANDLE
                }
            }
            "krl_fclose_all" => {
                if !rest.is_empty() {
                    return Err(self.err("krl_fclose_all takes no arguments"));
                }
                let hs = self.harness_mut()?;
                let open = hs.open.clone();
                lock_open(&open)
                    .open
                    .retain(|_, f| f.interpreter != hs.interpreter);
                0
            }
            other => {
                return Err(Unsupported {
                    line: self.line,
                    what: format!(
                        "CWRITE($FCT_CALL, …, \"{other}\") (the simulated controller has krl_fopen, krl_fgets, krl_fwriteln, krl_fputs, krl_fclose, krl_fclose_all)"
                    ),
                }
                .into());
            }
        };
        let ret1 = if msg_no == 0 {
            self.harness
                .as_ref()
                .map_or("DATA_OK", |h| h.success.as_str())
        } else {
            "CMD_ABORT"
        }
        .to_string();
        let status = Value::Struct(
            "STATE_T".into(),
            vec![
                ("RET1".into(), Value::Enum(ret1)),
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
        let open = hs.open.clone();
        let mut open = lock_open(&open);
        let mut file = None;
        let mut snapshot = None;
        if let Some(root) = hs.root.clone() {
            // Only names in the folder itself, as KRL's UserFiles root.
            if name.is_empty() || name.contains(['/', '\\', ':']) || name.contains("..") {
                return Ok(MSG_NO_OPEN);
            }
            if open.open.len() >= MAX_OPEN_FILES {
                return Ok(MSG_NO_TOO_MANY);
            }
            match open_real(&root.join(&name), &mode) {
                Ok((f, text)) => {
                    if let Some(text) = text {
                        hs.files.insert(name.clone(), text.clone());
                        snapshot = Some(text);
                    } else {
                        hs.files.remove(&name);
                    }
                    file = Some(f);
                }
                Err(_) => return Ok(MSG_NO_OPEN),
            }
        }
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
        let h = open.next_handle;
        open.next_handle += 1;
        open.open.insert(
            h,
            OpenFile {
                name,
                interpreter: hs.interpreter.clone(),
                write: mode != "r",
                pos: 0,
                text: snapshot,
                file,
            },
        );
        drop(open);
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
        let open = hs.open.clone();
        let mut open = lock_open(&open);
        let Some(f) = open.of(h, &hs.interpreter).filter(|f| !f.write) else {
            return Ok(MSG_NO_HANDLE);
        };
        let text = match &f.text {
            Some(t) => t.as_bytes(),
            None => hs.files.get(&f.name).map_or(&[][..], |t| t.as_bytes()),
        };
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
        let n = line.len();
        for (e, &b) in elems.iter_mut().zip(line) {
            *e = Value::Char(b);
        }
        f.pos += used;
        drop(open);
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
        let open = hs.open.clone();
        let mut open = lock_open(&open);
        let Some(f) = open.of(h, &hs.interpreter).filter(|f| f.write) else {
            return Ok(MSG_NO_HANDLE);
        };
        if let Some(file) = f.file.as_mut() {
            use std::io::Write as _;
            if file.write_all(text.as_bytes()).is_err() {
                return Ok(MSG_NO_HANDLE);
            }
        }
        hs.files.entry(f.name.clone()).or_default().push_str(&text);
        Ok(0)
    }

    /// `SWRITE(buf[], st, offset, format, values…)`: formats into the CHAR
    /// array from `offset` (0-based, advanced past the text); `%d`/`%i`,
    /// `%s`, `%f`, `%x` and `%c` with an optional width and precision.
    /// `SREAD(text[], state, offset, format, vars…)`: converts the text from
    /// `offset` (characters already consumed, 0-based) into the variables,
    /// as [`scan_krl`] reads it; `offset` moves past what was read,
    /// `state.HITS` counts the converted values, `RET1` is `CMD_OK` when
    /// every conversion of the format succeeded, else `CMD_ABORT`.
    pub(super) fn sread(&mut self, args: &[Expr]) -> Result<(), RunError> {
        let [text, st, off, fmt, vars @ ..] = args else {
            return Err(self.err("SREAD takes a CHAR array, a STATE_T, an offset and a format"));
        };
        let st = self.out_place(st, "the state (STATE_T)")?;
        let off_place = self.out_place(off, "the offset")?;
        let offset = self.eval_int(off)?;
        let fmt = self.eval_text(fmt)?;
        let chars = match self.eval(text)? {
            Value::Array(dims, elems) if dims.len() == 1 => elems
                .iter()
                .map(|v| match v {
                    Value::Char(c) => *c,
                    _ => 0,
                })
                .take_while(|&c| c != 0)
                .collect::<Vec<u8>>(),
            Value::Str(s) => s.into_bytes(),
            _ => return Err(self.err("SREAD: the text must be a CHAR array")),
        };
        let base = self.harness.as_ref().map_or(0, |h| h.text_offset_base);
        let start = usize::try_from(offset - base).unwrap_or(0);
        let (values, end) =
            scan_krl(&chars, start, &fmt).map_err(|m| self.err(format!("SREAD: {m}")))?;
        let wanted = fmt.matches('%').count() - 2 * fmt.matches("%%").count();
        if vars.len() < values.len() {
            return Err(self.err("SREAD: more conversions than variables"));
        }
        let hits = values.len();
        for (v, var) in values.into_iter().zip(vars) {
            let place = self.out_place(var, "a value")?;
            let value = match v {
                Scanned::Int(i) => Value::Int(i),
                Scanned::Real(r) => Value::Real(r),
                Scanned::Char(c) => Value::Char(c),
                Scanned::Text(t) => {
                    let Value::Array(dims, mut elems) = self.read_place(&place)? else {
                        return Err(self.err("SREAD: %s needs a CHAR array"));
                    };
                    for (i, slot) in elems.iter_mut().enumerate() {
                        *slot = Value::Char(t.get(i).copied().unwrap_or(0));
                    }
                    Value::Array(dims, elems)
                }
            };
            self.write_place(&place, value)?;
        }
        self.write_place(&off_place, Value::Int(end as i64 + base))?;
        let ret = if hits == wanted {
            "CMD_OK"
        } else {
            "CMD_ABORT"
        };
        let status = Value::Struct(
            "STATE_T".into(),
            vec![
                ("RET1".into(), Value::Enum(ret.into())),
                ("HITS".into(), Value::Int(hits as i64)),
                ("LENGTH".into(), Value::Int((end - start.min(end)) as i64)),
                ("MSG_NO".into(), Value::Int(0)),
            ],
        );
        self.write_place(&st, status)
    }

    pub(super) fn swrite(&mut self, args: &[Expr]) -> Result<(), RunError> {
        let [buf, st, off, fmt, values @ ..] = args else {
            return Err(self.err("SWRITE takes a CHAR array, a STATE_T, an offset and a format"));
        };
        let buf = self.out_place(buf, "the buffer")?;
        let st = self.out_place(st, "the state (STATE_T)")?;
        let off_place = self.out_place(off, "the offset")?;
        let offset = self.eval_int(off)?;
        let fmt = self.eval_text(fmt)?;
        let mut vals = Vec::with_capacity(values.len());
        for v in values {
            vals.push(self.eval(v)?);
        }
        let text = format_krl(&fmt, &vals).map_err(|m| self.err(format!("SWRITE: {m}")))?;
        let mut chars = self.read_place(&buf)?;
        let Value::Array(dims, elems) = &mut chars else {
            return Err(self.err("SWRITE: the buffer must be a CHAR array"));
        };
        if dims.len() != 1 {
            return Err(self.err("SWRITE: the buffer must be a CHAR array"));
        }
        let base = self.harness.as_ref().map_or(0, |h| h.text_offset_base);
        let start = usize::try_from(offset - base).unwrap_or(0);
        let mut written = 0;
        for (slot, b) in elems.iter_mut().skip(start).zip(text.bytes()) {
            *slot = Value::Char(b);
            written += 1;
        }
        self.write_place(&buf, chars)?;
        self.write_place(&off_place, Value::Int(start as i64 + base + written as i64))?;
        let status = Value::Struct(
            "STATE_T".into(),
            vec![
                ("RET1".into(), Value::Enum("CMD_OK".into())),
                ("HITS".into(), Value::Int(vals.len() as i64)),
                ("LENGTH".into(), Value::Int(written as i64)),
                ("MSG_NO".into(), Value::Int(0)),
            ],
        );
        self.write_place(&st, status)
    }
}

/// Opens a real file as `krl_fopen` does, locked while open (shared for
/// reading, exclusive for writing); for `"r"` also its text (Windows-1252
/// or UTF-8 as the KRC reads it).
/// One value `SREAD` converted.
#[derive(Debug, Clone, PartialEq)]
enum Scanned {
    Int(i64),
    Real(f64),
    Text(Vec<u8>),
    Char(u8),
}

/// KRL's `SREAD` scan of `text` (the characters up to the first 0) from
/// character `start` (0-based), like C's `sscanf`: whitespace in the format
/// skips any whitespace, `%d`/`%i`, `%f`/`%e`/`%g` and `%s` skip leading
/// whitespace, `%c` takes one character, other characters must match. Stops
/// at the first mismatch; returns the values converted and the index after
/// the last character consumed.
fn scan_krl(text: &[u8], start: usize, fmt: &str) -> Result<(Vec<Scanned>, usize), String> {
    let mut at = start.min(text.len());
    let mut out = Vec::new();
    let skip_ws = |at: &mut usize| {
        while text.get(*at).is_some_and(|c| c.is_ascii_whitespace()) {
            *at += 1;
        }
    };
    let mut f = fmt.bytes().peekable();
    while let Some(c) = f.next() {
        if c.is_ascii_whitespace() {
            skip_ws(&mut at);
            continue;
        }
        if c != b'%' {
            if text.get(at) == Some(&c) {
                at += 1;
                continue;
            }
            break;
        }
        // Width and precision are accepted and ignored.
        let mut conv = None;
        for d in f.by_ref() {
            if !(d.is_ascii_digit() || d == b'.' || d == b'l') {
                conv = Some(d);
                break;
            }
        }
        let conv = conv.ok_or("the format ends inside a conversion")?;
        if conv == b'%' {
            if text.get(at) == Some(&b'%') {
                at += 1;
                continue;
            }
            break;
        }
        // A conversion that fails leaves the offset where it began (before
        // the blanks it skipped).
        let before = at;
        if conv != b'c' {
            skip_ws(&mut at);
        }
        let from = at;
        let digits = |at: &mut usize| {
            let s = *at;
            while text.get(*at).is_some_and(u8::is_ascii_digit) {
                *at += 1;
            }
            *at > s
        };
        let sign = |at: &mut usize| {
            if matches!(text.get(*at), Some(b'-' | b'+')) {
                *at += 1;
            }
        };
        let value = match conv {
            b'd' | b'i' => {
                sign(&mut at);
                if !digits(&mut at) {
                    at = before;
                    break;
                }
                let t = std::str::from_utf8(&text[from..at]).map_err(|e| e.to_string())?;
                match t.parse::<i64>() {
                    Ok(v) if i32::try_from(v).is_ok() => Scanned::Int(v),
                    _ => {
                        at = before;
                        break;
                    }
                }
            }
            b'f' | b'e' | b'g' => {
                sign(&mut at);
                let whole = digits(&mut at);
                let mut frac = false;
                if text.get(at) == Some(&b'.') {
                    at += 1;
                    frac = digits(&mut at);
                }
                if !whole && !frac {
                    at = before;
                    break;
                }
                if matches!(text.get(at), Some(b'e' | b'E')) {
                    let e = at;
                    at += 1;
                    sign(&mut at);
                    if !digits(&mut at) {
                        at = e;
                    }
                }
                let t = std::str::from_utf8(&text[from..at]).map_err(|e| e.to_string())?;
                match t.parse::<f64>() {
                    Ok(v) => Scanned::Real(v),
                    Err(_) => {
                        at = before;
                        break;
                    }
                }
            }
            b's' => {
                while text.get(at).is_some_and(|c| !c.is_ascii_whitespace()) {
                    at += 1;
                }
                if at == from {
                    at = before;
                    break;
                }
                Scanned::Text(text[from..at].to_vec())
            }
            b'c' => match text.get(at) {
                Some(&c) => {
                    at += 1;
                    Scanned::Char(c)
                }
                None => break,
            },
            other => {
                return Err(format!(
                    "the conversion %{} is not supported",
                    char::from(other)
                ));
            }
        };
        out.push(value);
    }
    Ok((out, at))
}

fn open_real(
    path: &std::path::Path,
    mode: &str,
) -> std::io::Result<(std::fs::File, Option<String>)> {
    use std::io::Read as _;
    let mut opts = std::fs::OpenOptions::new();
    match mode {
        // "w" truncates only once the lock is held: a file another handle
        // holds keeps its text.
        "r" => opts.read(true),
        "w" => opts.write(true).create(true).truncate(false),
        "a" => opts.append(true).create(true),
        _ => return Err(std::io::Error::other("unknown mode")),
    };
    let mut f = opts.open(path)?;
    // Never wait for a lock: a handle another run leaked may hold it for
    // good (the open fails, as a sharing violation does on Windows).
    let locked = if mode == "r" {
        f.try_lock_shared()
    } else {
        f.try_lock()
    };
    locked.map_err(std::io::Error::other)?;
    if mode == "r" {
        let mut bytes = Vec::new();
        f.read_to_end(&mut bytes)?;
        let text = kuka_krl::check::decode(&bytes).into_owned();
        Ok((f, Some(text)))
    } else {
        if mode == "w" {
            f.set_len(0)?;
        }
        Ok((f, None))
    }
}

/// KRL's `SWRITE` formats: `%[width][.precision](d|i|s|f|x|c)` and `%%`.
fn format_krl(fmt: &str, vals: &[Value]) -> Result<String, String> {
    let mut out = String::new();
    let mut args = vals.iter();
    let mut chars = fmt.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        if chars.peek() == Some(&'%') {
            chars.next();
            out.push('%');
            continue;
        }
        let mut spec = String::new();
        let conv = loop {
            match chars.next() {
                Some(d) if d.is_ascii_digit() || d == '.' || d == '-' || d == '+' => spec.push(d),
                Some(k) => break k,
                None => return Err("the format ends inside a conversion".into()),
            }
        };
        let (width, precision) = match spec.split_once('.') {
            Some((w, p)) => (w.parse::<usize>().ok(), p.parse::<usize>().ok()),
            None => (spec.parse::<usize>().ok(), None),
        };
        let v = args.next().ok_or_else(|| format!("no value for %{conv}"))?;
        let text = match conv {
            'd' | 'i' => v.int()?.to_string(),
            'x' | 'X' => format!("{:X}", v.int()?),
            'f' => format!("{:.*}", precision.unwrap_or(6), v.num()?),
            'c' => match v {
                Value::Char(b) => char::from(*b).to_string(),
                v => char::from(u8::try_from(v.int()?).map_err(|_| "%c needs a character")?)
                    .to_string(),
            },
            's' => text_of(v)?,
            other => return Err(format!("the conversion %{other} is not supported")),
        };
        let w = width.unwrap_or(0);
        if text.len() < w {
            out.push_str(&" ".repeat(w - text.len()));
        }
        out.push_str(&text);
    }
    Ok(out)
}

/// A KRL path (`kb_mot[3].X`, `$POS_ACT.S`) as its root (upper case) and
/// the steps into it.
/// A path ending in a partial index, `X[r,]` (a row of a 2-D CHAR array,
/// such as `TOOL_NAME[3,]`): the array's path and the row.
fn char_row(path: &str) -> Option<(&str, i64)> {
    let body = path.trim().strip_suffix(",]")?;
    let open = body.rfind('[')?;
    let row = body[open + 1..].trim().parse().ok()?;
    Some((&body[..open], row))
}

/// Where row `row` (1-based) of a 2-D array lies in its flat elements:
/// (first element, row width).
fn row_span(dims: &[usize], row: i64) -> Option<(usize, usize)> {
    let [rows, width] = dims else {
        return None;
    };
    let r = usize::try_from(row)
        .ok()
        .filter(|r| (1..=*rows).contains(r))?;
    Some(((r - 1) * width, *width))
}

fn parse_path(path: &str) -> Option<(String, Vec<PathElem>)> {
    let path = path.trim();
    let end = path.find(['[', '.']).unwrap_or(path.len());
    let root = path[..end].to_ascii_uppercase();
    let mut rest = &path[end..];
    let mut elems = Vec::new();
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix('[') {
            let close = r.find(']')?;
            let idx = r[..close]
                .split(',')
                .map(|x| x.trim().parse().ok())
                .collect::<Option<Vec<i64>>>()?;
            elems.push(PathElem::Index(idx));
            rest = &r[close + 1..];
        } else {
            let r = rest.strip_prefix('.')?;
            let end = r.find(['[', '.']).unwrap_or(r.len());
            elems.push(PathElem::Field(r[..end].to_ascii_uppercase()));
            rest = &r[end..];
        }
    }
    Some((root, elems))
}

/// A value as KRL text, as a KRC's variable display shows it.
fn krl_of(v: &Value) -> Option<String> {
    Some(match v {
        Value::Unset(_) | Value::Opaque(_) => return None,
        Value::Int(i) => i.to_string(),
        // (6 decimals: a KRC's REAL is a 32-bit float; the runtime's f64
        // arithmetic leaves noise such as 355.0000000000001 below that.)
        Value::Real(r) => kuka_kvp::KrlValue::Real((r * 1e6).round() / 1e6 + 0.0).to_krl(),
        Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.into(),
        Value::Char(c) => format!("'{}'", char::from(*c)),
        Value::Str(s) => format!("\"{s}\""),
        Value::Enum(e) => format!("#{e}"),
        Value::Struct(ty, fields) => {
            let inner: Vec<String> = fields
                .iter()
                .filter_map(|(k, v)| Some(format!("{k} {}", krl_of(v)?)))
                .collect();
            if ty.is_empty() {
                format!("{{{}}}", inner.join(", "))
            } else {
                format!("{{{ty}: {}}}", inner.join(", "))
            }
        }
        Value::Array(dims, items) => {
            // A CHAR array is its text (up to the first unset character).
            if dims.len() == 1 && items.first().and_then(Value::scalar_kind) == Some(Scalar::Char) {
                let text: String = items
                    .iter()
                    .map_while(|c| match c {
                        Value::Char(c) if *c != 0 => Some(char::from(*c)),
                        _ => None,
                    })
                    .collect();
                format!("\"{text}\"")
            } else {
                return None;
            }
        }
    })
}

/// A KUKAVARPROXY value as an interpreter value (converted to the
/// variable's type by the assignment).
fn value_of(v: kuka_kvp::KrlValue) -> Value {
    use kuka_kvp::KrlValue as K;
    match v {
        K::Int(i) => Value::Int(i),
        K::Real(r) => Value::Real(r),
        K::Bool(b) => Value::Bool(b),
        K::Text(t) => Value::Str(t),
        K::Enum(e) => Value::Enum(e.to_ascii_uppercase()),
        K::Struct(ty, fields) => Value::Struct(
            ty.unwrap_or_default().to_ascii_uppercase(),
            fields.into_iter().map(|(k, v)| (k, value_of(v))).collect(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{Scanned, scan_krl};

    #[test]
    fn sread_scans_like_sscanf_and_counts_the_offset_in_characters_consumed() {
        let line = b"LIN 3 -12.500 7 0.001 12345\r\n";
        let (v, at) = scan_krl(line, 4, "%d").expect("scan");
        assert_eq!((v, at), (vec![Scanned::Int(3)], 5));
        let (v, at) = scan_krl(line, at, "%f").expect("scan");
        assert_eq!((v, at), (vec![Scanned::Real(-12.5)], 13));
        let (v, at) = scan_krl(line, at, "%d %f %d").expect("scan");
        assert_eq!(
            v,
            vec![Scanned::Int(7), Scanned::Real(0.001), Scanned::Int(12345)]
        );
        assert_eq!(&line[at..], b"\r\n");
        // At the end, nothing more converts.
        let (v, end) = scan_krl(line, at, "%d").expect("scan");
        assert_eq!((v.len(), end), (0, at));
    }

    #[test]
    fn sread_stops_at_the_first_mismatch() {
        let (v, at) = scan_krl(b"CMD x 5", 0, "%s %d %d").expect("scan");
        assert_eq!(v, vec![Scanned::Text(b"CMD".to_vec())]);
        // The format's blank consumed the blank; the failed %d nothing.
        assert_eq!(at, 4);
        let (v, _) = scan_krl(b"99999999999", 0, "%d").expect("scan");
        assert!(v.is_empty(), "an INT beyond 32 bits does not convert");
        let (v, _) = scan_krl(b"- 5", 0, "%d").expect("scan");
        assert!(v.is_empty());
        assert!(scan_krl(b"1", 0, "%q").is_err());
    }
}

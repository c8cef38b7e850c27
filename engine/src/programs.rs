//! Uploaded KRL programs: validation with the KRL front end, the store in
//! `<data_dir>/programs`, and the module text the engine writes into the
//! controller's program folder for a RUN command.
//!
//! Every run gets a module name never used before (`kbu<cid>`), so the
//! controller compiles the newest code each time — the thesis bridge kept
//! running its first upload. The module is a generated entry routine that
//! calls the uploaded entry point, followed by the uploaded routines.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, RwLock};

use kuka_krl::{Program, ProgramError, RoutineKind};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::clock::now_ms;
use crate::error::{BridgeError, ErrorCode, Result};

/// The entry point the thesis bridge called (`DEFFCT INT fuploaded()`).
pub const THESIS_ENTRY: &str = "fuploaded";

/// Lines the generated wrapper puts before the uploaded `.src` text.
pub const WRAPPER_LINES: u32 = 7;

/// An upload: a program's name, its `.src` text, an optional `.dat` and
/// the routine to run.
#[derive(Debug, Clone, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"name": "wave", "src": "DEF wave()\n  PTP {A1 10}\n  PTP {A1 -10}\nEND\n"}))]
pub struct ProgramUpload {
    /// Program name: a KRL name (letter or `_` first, then letters, digits,
    /// `_`; at most 24 characters). Case-insensitive; an upload with an
    /// existing name replaces that program.
    pub name: String,
    /// The `.src` text.
    pub src: String,
    /// The `.dat` text (its `DEFDAT` must carry the first routine's name).
    #[serde(default)]
    pub dat: Option<String>,
    /// Routine to run (no parameters). Default: `fuploaded` if the file
    /// defines it (the thesis convention), else the first routine.
    #[serde(default)]
    pub entry: Option<String>,
}

/// What the service knows about a stored program.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct ProgramInfo {
    /// Program name.
    pub name: String,
    /// The routine a run calls.
    pub entry: String,
    /// `def` or `deffct`.
    pub entry_kind: String,
    /// Lines of the `.src`.
    pub src_lines: u32,
    /// Lines of the `.dat`, if there is one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dat_lines: Option<u32>,
    /// Size of `.src` plus `.dat` in bytes.
    pub bytes: usize,
    /// Upload time (ms since the Unix epoch).
    pub uploaded_ms: u64,
    /// Checked against what the simulated controller can run (true when the
    /// service runs a simulator, native or KRC-like; a real controller runs
    /// all of KRL).
    pub simulator_checked: bool,
}

/// A stored program with its text.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct StoredProgram {
    /// Its description.
    #[serde(flatten)]
    pub info: ProgramInfo,
    /// The `.src` text.
    pub src: String,
    /// The `.dat` text.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dat: Option<String>,
}

/// The files of a generated RUN module.
#[derive(Debug, Clone, PartialEq)]
pub struct ModuleText {
    /// Module name `kbu<n>`.
    pub name: String,
    /// `kbu<n>.src`.
    pub src: String,
    /// `kbu<n>.dat`, if the program has a `.dat`.
    pub dat: Option<String>,
}

/// Uploaded programs, persisted as `<name>.src`, `<name>.dat` and
/// `<name>.json` in one folder.
#[derive(Debug)]
pub struct ProgramStore {
    dir: PathBuf,
    max_bytes: usize,
    run_timeout: std::time::Duration,
    check: UploadCheck,
    programs: RwLock<BTreeMap<String, Arc<StoredProgram>>>,
}

/// Names Windows reserves for devices: a file `con.src` cannot exist.
const WINDOWS_DEVICES: [&str; 22] = [
    "CON", "PRN", "AUX", "NUL", "COM1", "COM2", "COM3", "COM4", "COM5", "COM6", "COM7", "COM8",
    "COM9", "LPT1", "LPT2", "LPT3", "LPT4", "LPT5", "LPT6", "LPT7", "LPT8", "LPT9",
];

fn valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && name.len() <= kuka_krl::MAX_NAME_LEN
        && !WINDOWS_DEVICES.iter().any(|d| d.eq_ignore_ascii_case(name))
}

/// Uploaded bytes as text: UTF-8 if they are, else the controller's 8-bit
/// code page (Windows-1252, read as Latin-1); a byte-order mark is dropped.
pub fn decode_text(bytes: &[u8]) -> String {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| char::from(b)).collect(),
    }
}

/// Text as the controller stores KRL files: one byte per character
/// (Latin-1 / Windows-1252 for the common accented letters; anything
/// beyond becomes `?`, which the front end only allows in comments and
/// strings anyway).
pub fn encode_ansi(text: &str) -> Vec<u8> {
    text.chars()
        .map(|c| u8::try_from(u32::from(c)).unwrap_or(b'?'))
        .collect()
}

fn count_lines(text: &str) -> u32 {
    text.lines().count() as u32
}

/// Maps a front-end refusal to the API error, with file and line: syntax
/// errors and the front end's limits (the message names the limit, e.g.
/// `MAX_EXPR_DEPTH`) are `invalid_program`.
pub fn program_error(e: &ProgramError) -> BridgeError {
    let file = match e {
        ProgramError::Dat(_) | ProgramError::DatName { .. } => "dat",
        _ => "src",
    };
    let err = BridgeError::new(ErrorCode::InvalidProgram, e.to_string());
    match e.line() {
        Some(line) => err.at_line(file, line),
        None => err,
    }
}

/// The first `CWRITE($FCT_CALL, …, "krl_fopen", "<channel file>", …)` of
/// the program (line, file name as written): a program that opens one of
/// the channel's files holds it open at least while it runs (a KRC keeps
/// the handle after an error stop until `kb_main` restarts), so that the
/// service can no longer write a command or read an answer. Only literal
/// names are seen; a name built at run time is not.
fn opened_channel_file(program: &Program) -> Option<(u32, String)> {
    use kuka_krl::{Expr, Stmt, StmtKind};
    fn in_block(body: &[Stmt]) -> Option<(u32, String)> {
        body.iter().find_map(in_stmt)
    }
    fn in_stmt(s: &Stmt) -> Option<(u32, String)> {
        match &s.kind {
            StmtKind::Call { name, args } if name.eq_ignore_ascii_case("CWRITE") => {
                let [_, _, _, Expr::Str(func), Expr::Str(file), ..] = args.as_slice() else {
                    return None;
                };
                let channel = [
                    kuka_protocol::COMMAND_FILE,
                    kuka_protocol::RESULT_FILE,
                    kuka_protocol::STATE_FILE,
                ];
                (func.eq_ignore_ascii_case("krl_fopen")
                    && channel.iter().any(|c| file.trim().eq_ignore_ascii_case(c)))
                .then(|| (s.line, file.clone()))
            }
            kind => kind.blocks().into_iter().find_map(in_block),
        }
    }
    program.src.routines.iter().find_map(|r| in_block(&r.body))
}

/// How much an upload is checked beyond its syntax and entry point, by the
/// controller that will run it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum UploadCheck {
    /// A real controller: syntax and entry point only (it runs all of KRL
    /// and knows names the service cannot see).
    Syntax,
    /// The KRC-like runtime: also every name declared, as a KRC's compiler
    /// wants it, and what the runtime runs
    /// ([`check_hosted`](kuka_krl_runtime::interp::check_hosted)), with
    /// the names of the variables the runtime provides (system variables
    /// and the globals of its `.dat` files).
    Hosted(Arc<std::collections::BTreeSet<String>>),
    /// The native simulator: also declared names and its KRL subset.
    NativeSubset,
}

impl ProgramStore {
    /// Opens (creating) the store folder and loads the programs in it;
    /// `check` says how uploads are checked.
    pub fn open(
        dir: &Path,
        max_bytes: usize,
        run_timeout: std::time::Duration,
        check: UploadCheck,
    ) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        let store = ProgramStore {
            dir: dir.to_path_buf(),
            max_bytes,
            run_timeout,
            check,
            programs: RwLock::new(BTreeMap::new()),
        };
        for entry in std::fs::read_dir(dir)?.flatten() {
            let path = entry.path();
            if path.extension().is_some_and(|e| e == "json") {
                match store.load(&path) {
                    Ok(p) => {
                        let key = p.info.name.to_ascii_lowercase();
                        store.write_map().insert(key, Arc::new(p));
                    }
                    Err(e) => {
                        tracing::warn!(path = %path.display(), error = %e, "stored program skipped")
                    }
                }
            }
        }
        Ok(store)
    }

    fn load(&self, meta: &Path) -> std::result::Result<StoredProgram, String> {
        let text = std::fs::read_to_string(meta).map_err(|e| e.to_string())?;
        let info: ProgramInfo = serde_json::from_str(&text).map_err(|e| e.to_string())?;
        let src = std::fs::read_to_string(meta.with_extension("src")).map_err(|e| e.to_string())?;
        let dat = std::fs::read_to_string(meta.with_extension("dat")).ok();
        Ok(StoredProgram { info, src, dat })
    }

    fn write_map(&self) -> std::sync::RwLockWriteGuard<'_, BTreeMap<String, Arc<StoredProgram>>> {
        self.programs.write().unwrap_or_else(|p| p.into_inner())
    }

    fn read_map(&self) -> std::sync::RwLockReadGuard<'_, BTreeMap<String, Arc<StoredProgram>>> {
        self.programs.read().unwrap_or_else(|p| p.into_inner())
    }

    /// Checks an upload without storing it: name, size, syntax, entry point
    /// and, with the simulator, the supported subset.
    ///
    /// The work is bounded for every text: the front end refuses
    /// expressions and blocks nested beyond its limits (`kuka_krl::limits`)
    /// as `invalid_program` with the line and the limit's name, so the
    /// checks that walk the tree afterwards (names, subset) recurse only as
    /// deep as those limits allow — all of it within a tokio worker's
    /// 2 MiB stack, in a debug build too.
    pub fn check(&self, upload: &ProgramUpload) -> Result<(Program, ProgramInfo)> {
        if !valid_name(&upload.name) {
            return Err(BridgeError::invalid(format!(
                "program name {:?} is not a KRL name (letter or _ first, then letters, digits or _, at most {} characters, not a Windows device name such as CON)",
                upload.name,
                kuka_krl::MAX_NAME_LEN
            )));
        }
        let bytes = upload.src.len() + upload.dat.as_ref().map_or(0, String::len);
        if upload.src.len() > self.max_bytes
            || upload
                .dat
                .as_ref()
                .is_some_and(|d| d.len() > self.max_bytes)
        {
            return Err(BridgeError::new(
                ErrorCode::PayloadTooLarge,
                format!(
                    "a program file may have at most {} bytes (programs.max_bytes)",
                    self.max_bytes
                ),
            ));
        }
        let mut entry = upload.entry.clone();
        let program = Program::parse(&upload.src, upload.dat.as_deref(), entry.as_deref())
            .map_err(|e| program_error(&e))?;
        if entry.is_none() && program.routine(THESIS_ENTRY).is_some() {
            entry = Some(THESIS_ENTRY.into());
        }
        let routine = program
            .entry(entry.as_deref())
            .map_err(|e| program_error(&e))?;
        if !routine.params.is_empty() {
            return Err(BridgeError::new(
                ErrorCode::InvalidProgram,
                format!("entry point `{}` must not take parameters", routine.name),
            )
            .at_line("src", routine.line));
        }
        if let Some((line, file)) = opened_channel_file(&program) {
            return Err(BridgeError::new(
                ErrorCode::InvalidProgram,
                format!(
                    "the program opens {file}, a file of the bridge's channel: a KRL handle on it locks the channel (the bridge could no longer send a STOP, or hear the controller) until the robot program restarts; use files of your own"
                ),
            )
            .at_line("src", line));
        }
        if self.check != UploadCheck::Syntax {
            kuka_krl_runtime::names::check_names(&program).map_err(|u| {
                BridgeError::new(ErrorCode::InvalidProgram, u.to_string()).at_line("src", u.line)
            })?;
        }
        let unsupported = |u: kuka_krl_runtime::interp::Unsupported| {
            BridgeError::new(ErrorCode::ProgramUnsupported, u.to_string()).at_line("src", u.line)
        };
        match &self.check {
            UploadCheck::Syntax => {}
            UploadCheck::Hosted(globals) => {
                kuka_krl_runtime::interp::check_hosted(&program, globals).map_err(unsupported)?
            }
            UploadCheck::NativeSubset => {
                kuka_krl_runtime::interp::check_subset(&program).map_err(unsupported)?
            }
        }
        let info = ProgramInfo {
            name: upload.name.clone(),
            entry: routine.name.clone(),
            entry_kind: match routine.kind {
                RoutineKind::Def => "def".into(),
                RoutineKind::DefFct(_) => "deffct".into(),
            },
            src_lines: count_lines(&upload.src),
            dat_lines: upload.dat.as_deref().map(count_lines),
            bytes,
            uploaded_ms: now_ms(),
            simulator_checked: self.check != UploadCheck::Syntax,
        };
        Ok((program, info))
    }

    /// Checks and stores an upload; returns it and whether it is new.
    pub fn put(&self, mut upload: ProgramUpload) -> Result<(Arc<StoredProgram>, bool)> {
        for text in std::iter::once(&mut upload.src).chain(upload.dat.as_mut()) {
            if let Some(rest) = text.strip_prefix('\u{feff}') {
                *text = rest.to_string();
            }
        }
        let (_, info) = self.check(&upload)?;
        let stored = StoredProgram {
            info,
            src: upload.src,
            dat: upload.dat,
        };
        let key = stored.info.name.to_ascii_lowercase();
        let io = |e: std::io::Error| {
            tracing::error!(dir = %self.dir.display(), error = %e, "program not stored");
            BridgeError::new(
                ErrorCode::StorageUnavailable,
                "the service cannot store the program in its data folder; the service log (under this request's id) says why",
            )
        };
        let meta = serde_json::to_string_pretty(&stored.info)
            .map_err(|e| BridgeError::new(ErrorCode::Internal, e.to_string()))?;
        let tag = format!("svc{}", std::process::id());
        let write = |ext: &str, text: &str| {
            kuka_protocol::files::atomic_write(&self.dir, &format!("{key}.{ext}"), &tag, text)
                .map_err(|e| io(std::io::Error::other(crate::error::chain(&e))))
        };
        write("src", &stored.src)?;
        match &stored.dat {
            Some(d) => write("dat", d)?,
            None => match std::fs::remove_file(self.dir.join(format!("{key}.dat"))) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(io(e)),
                _ => {}
            },
        }
        write("json", &meta)?;
        let stored = Arc::new(stored);
        let created = self.write_map().insert(key, stored.clone()).is_none();
        tracing::info!(program = %stored.info.name, entry = %stored.info.entry, bytes = stored.info.bytes, "program stored");
        Ok((stored, created))
    }

    /// The default timeout of a program run.
    pub fn run_timeout(&self) -> std::time::Duration {
        self.run_timeout
    }

    /// All programs, by name.
    pub fn list(&self) -> Vec<ProgramInfo> {
        self.read_map().values().map(|p| p.info.clone()).collect()
    }

    /// One program.
    pub fn get(&self, name: &str) -> Result<Arc<StoredProgram>> {
        self.read_map()
            .get(&name.to_ascii_lowercase())
            .cloned()
            .ok_or_else(|| {
                BridgeError::new(ErrorCode::NotFound, format!("no program named {name:?}"))
            })
    }

    /// Removes a program.
    pub fn remove(&self, name: &str) -> Result<()> {
        let key = name.to_ascii_lowercase();
        if self.write_map().remove(&key).is_none() {
            return Err(BridgeError::new(
                ErrorCode::NotFound,
                format!("no program named {name:?}"),
            ));
        }
        for ext in ["json", "src", "dat"] {
            let _ = std::fs::remove_file(self.dir.join(format!("{key}.{ext}")));
        }
        tracing::info!(program = name, "program removed");
        Ok(())
    }
}

/// The module written for RUN command `n`: a generated `DEF kbu<n>()` that
/// makes the BCO run a KRC requires after selecting a program (`PTP
/// $AXIS_ACT`: reaches the current position, does not move) and calls the
/// entry point; then the uploaded text with its `&` header lines turned
/// into comments (they are only allowed at the top of a file), so
/// uploaded line L is module line L + [`WRAPPER_LINES`].
pub fn module_text(n: i32, p: &StoredProgram) -> ModuleText {
    let name = format!("kbu{n}");
    let call = match p.info.entry_kind.as_str() {
        "deffct" => format!("  kb_ret = {}( )", p.info.entry),
        _ => format!("  {}( )", p.info.entry),
    };
    let mut src =
        format!("&ACCESS RVP\nDEF {name}( )\n  DECL INT kb_ret\n  PTP $AXIS_ACT\n{call}\nEND\n\n");
    for line in p.src.lines() {
        if line.trim_start().starts_with('&') {
            src.push_str("; ");
        }
        src.push_str(line);
        src.push('\n');
    }
    let dat = p.dat.as_ref().map(|d| {
        let mut out = String::new();
        let mut renamed = false;
        for line in d.lines() {
            let t = line.trim_start();
            if !renamed && t.len() >= 6 && t[..6].eq_ignore_ascii_case("DEFDAT") {
                let rest: Vec<&str> = t.split_whitespace().collect();
                out.push_str(&format!("DEFDAT {name}"));
                for word in rest.iter().skip(2) {
                    out.push(' ');
                    out.push_str(word);
                }
                renamed = true;
            } else {
                out.push_str(line);
            }
            out.push('\n');
        }
        out
    });
    ModuleText { name, src, dat }
}

/// Maps a module line back to the uploaded `.src` line (0: in the wrapper).
pub fn upload_line(module_line: u32) -> u32 {
    module_line.saturating_sub(WRAPPER_LINES)
}

/// A message about the generated module with every `line N` in it mapped
/// back to the uploaded `.src` ([`upload_line`]): the interpreter names
/// other lines in its messages too ("after the Cartesian motion on line
/// N").
pub fn upload_lines_in(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(i) = rest.find("line ") {
        let (head, tail) = rest.split_at(i + "line ".len());
        out.push_str(head);
        let digits = tail.bytes().take_while(u8::is_ascii_digit).count();
        match tail[..digits].parse::<u32>() {
            Ok(n) if n > WRAPPER_LINES => out.push_str(&upload_line(n).to_string()),
            _ => out.push_str(&tail[..digits]),
        }
        rest = &tail[digits..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_module_keeps_line_numbers_and_renames_the_dat() {
        let p = StoredProgram {
            info: ProgramInfo {
                name: "draw".into(),
                entry: "fuploaded".into(),
                entry_kind: "deffct".into(),
                src_lines: 3,
                dat_lines: Some(3),
                bytes: 0,
                uploaded_ms: 0,
                simulator_checked: true,
            },
            src: "&ACCESS RVP\nDEFFCT INT fuploaded()\n  RETURN 1\nENDFCT\n".into(),
            dat: Some("&ACCESS RVP\nDEFDAT draw PUBLIC\nENDDAT\n".into()),
        };
        let m = module_text(42, &p);
        let lines: Vec<&str> = m.src.lines().collect();
        assert_eq!(lines[(WRAPPER_LINES + 3 - 1) as usize], "  RETURN 1");
        assert_eq!(upload_line(WRAPPER_LINES + 3), 3);
        assert_eq!(
            upload_lines_in(
                "PTP needs the axes after the Cartesian motion on line 10; line x, line 2"
            ),
            "PTP needs the axes after the Cartesian motion on line 3; line x, line 2"
        );
        let parsed =
            Program::parse(&m.src, m.dat.as_deref(), Some("kbu42")).expect("module parses");
        assert_eq!(parsed.src.routines[0].name, "kbu42");
        assert!(
            m.dat
                .as_deref()
                .is_some_and(|d| d.contains("DEFDAT kbu42 PUBLIC"))
        );
    }
}

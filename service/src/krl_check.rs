//! `kuka-bridge krl check FILES…`: a KRL linter on the command line. Each
//! file is parsed as a controller loads it (`.src`/`.sub`/`.dat`, ANSI or
//! UTF-8); with `--simulator` (the native simulator) or `--simulator=krc`
//! (the KRC-like runtime), a module (`.src` with its `.dat` beside it) is
//! also checked the way the service checks an upload it will run on that
//! simulated controller (declared names, what the simulator executes).
//! Every problem is one `file:line:column: message` line on stdout; a
//! warning (`file:line:column: warning: message`) is printed the same way
//! and does not fail the check.

use std::path::{Path, PathBuf};

use kuka_krl::check::{FileKind, check, decode};

/// What a check of some files found.
#[derive(Debug, Default)]
pub struct Report {
    /// `file:line:column: message` lines, in file order.
    pub problems: Vec<String>,
    /// Files checked.
    pub files: usize,
    /// Files with at least one problem.
    pub failed: usize,
    /// Warnings (`file:line:column: warning: message`), in file order
    /// among the problems; they do not count as failures.
    pub warnings: usize,
    /// Arguments that name no KRL file: a missing path, a folder without
    /// KRL files.
    pub empty: usize,
}

/// Which simulated controller `--simulator` checks a module for.
#[derive(Debug, Clone)]
pub enum Simulator {
    /// The native simulator: its KRL subset (`check_subset`).
    Native,
    /// The KRC-like runtime: what it runs (`check_hosted`), with the
    /// upper-case names of the variables it provides.
    Krc(std::collections::BTreeSet<String>),
}

/// The variables the KRC-like runtime provides to a program: a runtime is
/// started on a fresh folder, asked, and shut down.
pub fn krc_globals() -> Result<std::collections::BTreeSet<String>, kuka_krc::KrcError> {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!(
        "kuka-bridge-krl-check-{}-{nanos}",
        std::process::id()
    ));
    let mut config = kuka_krc::KrcConfig::new(&dir);
    config.time_scale = 1.0;
    let started = kuka_krc::KrcController::start(config);
    let names = started.map(|krc| {
        let names = krc.global_names();
        krc.shutdown();
        names
    });
    let _ = std::fs::remove_dir_all(&dir);
    names
}

/// Checks every file (directories: every KRL file under them).
pub fn run(paths: &[PathBuf], simulator: Option<&Simulator>) -> Report {
    let mut files = Vec::new();
    let mut report = Report::default();
    for p in paths {
        if p.is_dir() {
            let before = files.len();
            collect(p, &mut files, &mut report);
            if files.len() == before {
                report.problems.push(format!(
                    "{}: no KRL files (.src, .sub, .dat) in this folder",
                    p.display()
                ));
                report.empty += 1;
            }
        } else if !p.exists() {
            report
                .problems
                .push(format!("{}: no such file or folder", p.display()));
            report.empty += 1;
        } else {
            files.push(p.clone());
        }
    }
    for f in files {
        report.files += 1;
        let before = report.problems.len();
        let warnings = check_one(&f, simulator, &mut report.problems);
        report.warnings += warnings;
        if report.problems.len() > before + warnings {
            report.failed += 1;
        }
    }
    report
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>, report: &mut Report) {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) => {
            report
                .problems
                .push(format!("{}: cannot read the folder: {e}", dir.display()));
            report.failed += 1;
            return;
        }
    };
    let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            collect(&p, out, report);
        } else if FileKind::from_path(&p).is_some() {
            out.push(p);
        }
    }
}

/// Checks one file; returns how many of the lines it added are warnings.
fn check_one(path: &Path, simulator: Option<&Simulator>, problems: &mut Vec<String>) -> usize {
    let shown = path.display();
    let Some(kind) = FileKind::from_path(path) else {
        problems.push(format!("{shown}: not a KRL file (.src, .sub or .dat)"));
        return 0;
    };
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => {
            problems.push(format!("{shown}: cannot read the file: {e}"));
            return 0;
        }
    };
    let text = decode(&bytes);
    if let Err(e) = check(kind, &text) {
        problems.push(format!(
            "{shown}:{}:{}: {}",
            e.line,
            e.col,
            printable(&e.message)
        ));
        return 0;
    }
    let mut warnings = 0;
    if let Some(w) = name_mismatch(path, kind, &text) {
        problems.push(format!("{shown}:{w}"));
        warnings += 1;
    }
    if let Some(sim) = simulator
        && kind == FileKind::Src
    {
        simulator_check(path, &text, sim, problems);
    }
    warnings
}

/// `line:1: warning: …` when the module's name (its first DEF, or its
/// DEFDAT) is not the file's name. A KRC selects and links a module by its
/// file name, so the service names every module it writes itself
/// (`kbu<n>`, DEF and DEFDAT renamed). A warning, not a problem: 17 of the
/// 364 public files of the test corpus differ (files renamed in their
/// repositories, such as ROS-Industrial's `ros_rsi.src` with
/// `DEF RSI_AxisCorr()`), and no public source says whether a KSS refuses
/// to load such a file or only to select it (docs/CONTROLLER.md).
fn name_mismatch(path: &Path, kind: FileKind, text: &str) -> Option<String> {
    let stem = path.file_stem()?.to_str()?;
    let (name, line, what) = match kind {
        FileKind::Dat => {
            let dat = kuka_krl::parse_dat(text).ok()?;
            (dat.name, dat.line, "DEFDAT")
        }
        FileKind::Src => {
            let src = kuka_krl::parse_src(text).ok()?;
            let first = src.routines.into_iter().next()?;
            (first.name, first.line, "its first DEF")
        }
    };
    (!name.eq_ignore_ascii_case(stem)).then(|| {
        format!(
            "{line}:1: warning: the module is named `{}` ({what}) but the file `{}`: a KRC finds a module by its file name",
            printable(&name),
            printable(stem)
        )
    })
}

/// The `.dat` beside a `.src` (same stem, any case), if there is one.
fn sibling_dat(src: &Path) -> Option<PathBuf> {
    let stem = src.file_stem()?.to_str()?.to_ascii_lowercase();
    let dir = src.parent().filter(|d| !d.as_os_str().is_empty());
    let entries = std::fs::read_dir(dir.unwrap_or(Path::new("."))).ok()?;
    entries.flatten().map(|e| e.path()).find(|p| {
        FileKind::from_path(p) == Some(FileKind::Dat)
            && p.file_stem()
                .and_then(|s| s.to_str())
                .is_some_and(|s| s.eq_ignore_ascii_case(&stem))
    })
}

fn simulator_check(src_path: &Path, src: &str, sim: &Simulator, problems: &mut Vec<String>) {
    let shown = src_path.display();
    let dat_path = sibling_dat(src_path);
    let dat_bytes = dat_path.as_ref().and_then(|p| std::fs::read(p).ok());
    let dat = dat_bytes.as_deref().map(decode);
    let program = match kuka_krl::Program::parse(src, dat.as_deref(), None) {
        Ok(p) => p,
        Err(kuka_krl::ProgramError::Dat(e)) => {
            let file = dat_path.as_deref().unwrap_or(src_path).display();
            problems.push(format!(
                "{file}:{}:{}: {}",
                e.line,
                e.col,
                printable(&e.message)
            ));
            return;
        }
        Err(e) => {
            let line = e.line().unwrap_or(1);
            let text = e.to_string();
            let message = text
                .strip_prefix(&format!("line {line}: "))
                .unwrap_or(&text);
            problems.push(format!("{shown}:{line}:1: {}", printable(message)));
            return;
        }
    };
    if let Err(u) = kuka_krl_runtime::names::check_names(&program) {
        problems.push(format!(
            "{shown}:{}:1: the variable {} is not declared",
            u.line, u.name
        ));
    } else {
        let (checked, which) = match sim {
            Simulator::Native => (
                kuka_krl_runtime::interp::check_subset(&program),
                "the native simulator",
            ),
            Simulator::Krc(globals) => (
                kuka_krl_runtime::interp::check_hosted(&program, globals),
                "the KRC-like runtime",
            ),
        };
        if let Err(u) = checked {
            problems.push(format!(
                "{shown}:{}:1: {which} does not run {} (program_unsupported)",
                u.line,
                printable(&u.what)
            ));
        }
    }
}

/// `text` with control characters escaped (`\u{2}`, `\0` …): a message
/// may quote a character of a binary file.
fn printable(text: &str) -> String {
    text.chars()
        .flat_map(|c| {
            let escaped: Vec<char> = if c.is_control() {
                c.escape_default().collect()
            } else {
                vec![c]
            };
            escaped
        })
        .collect()
}

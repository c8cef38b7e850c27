//! File handles on a KRC-like host outlive the run that opened them: a file
//! a program leaves open (it forgot `krl_fclose`, or stopped with an error
//! before it) stays open and locked for the next runs of the controller
//! until `krl_fclose_all` or a new table (a reboot), as on a KRC. The
//! thesis's controller showed exactly this: files locked until reboot.

use std::fs::OpenOptions;
use std::path::Path;

use kuka_kinematics::{Pose, RobotModel};
use kuka_krl::Program;
use kuka_krl_runtime::interp::{
    Cancelled, Globals, Host, HostedFiles, OpenFiles, RunError, SharedOpenFiles, Start, Step,
    TriggerAt, Turn, Wait, run_hosted,
};
use kuka_protocol::SpeedRecord;

/// A host with nothing to wait for: every wait is over at once.
struct Instant;

impl Host for Instant {
    fn statement(&mut self, _vars: &mut Globals) -> Result<Turn, Cancelled> {
        Ok(Turn {
            ready: true,
            ..Turn::default()
        })
    }
    fn wait(&mut self, _vars: &mut Globals, _what: Wait) -> Result<Turn, Cancelled> {
        Ok(Turn {
            ready: true,
            ..Turn::default()
        })
    }
    fn queue_motion(&mut self, _step: Step, _triggers: Vec<TriggerAt>) {}
    fn discard_motions(&mut self) {}
    fn command(&mut self, _vars: &mut Globals, _text: &str) -> bool {
        false
    }
}

/// Runs `DEF t()` of `src` in the robot interpreter on the host with the
/// controller's table `open`.
fn run_on(dir: &Path, open: &SharedOpenFiles, src: &str) -> (Result<(), RunError>, Globals) {
    run_in("robot", dir, open, src)
}

/// [`run_on`] in the interpreter named `interpreter`.
fn run_in(
    interpreter: &str,
    dir: &Path,
    open: &SharedOpenFiles,
    src: &str,
) -> (Result<(), RunError>, Globals) {
    let program = Program::parse(src, Some(DAT), Some("t")).expect("parses");
    let model = RobotModel::kr3_r540();
    let start = Start {
        model: &model,
        axes: model.home,
        tool: Pose::IDENTITY,
        base: Pose::IDENTITY,
        speed: SpeedRecord {
            override_pct: 100.0,
            ptp_velocity_pct: 100.0,
            ptp_acceleration_pct: 100.0,
            cp_velocity: 2.0,
            cp_acceleration_pct: 100.0,
        },
    };
    let files = HostedFiles {
        root: dir.to_path_buf(),
        success: "DATA_OK".into(),
        text_offset_base: 0,
        open: open.clone(),
        interpreter: interpreter.into(),
    };
    let (r, g) = run_hosted(&program, "t", &start, Box::new(Instant), files);
    (r, g.expect("the run was not cancelled"))
}

/// Whether another process could take the file for writing now (the
/// service's replace of a channel file needs that).
fn free(path: &Path) -> bool {
    let f = OpenOptions::new().write(true).open(path).expect("exists");
    let free = f.try_lock().is_ok();
    drop(f);
    free
}

/// The module's data list: what the tests read after a run.
const DAT: &str = "DEFDAT t
DECL BOOL first = FALSE
DECL BOOL second = FALSE
ENDDAT
";

/// Opens `leak.txt` for writing, writes a line and stops with a runtime
/// error before its `krl_fclose`.
const LEAKS: &str = "DEF t()
  DECL STATE_T st
  DECL MODUS_T md
  DECL INT h, zero
  DECL CHAR line[4]
  md = #SYNC
  line[1] = \"x\"
  CWRITE($FCT_CALL, st, md, \"krl_fopen\", \"leak.txt\", \"w\", h)
  CWRITE($FCT_CALL, st, md, \"krl_fwriteln\", h, line[])
  zero = 0
  h = h / zero
  CWRITE($FCT_CALL, st, md, \"krl_fclose\", h)
END
";

/// Tries to open `leak.txt` (`first`), closes every handle, tries again
/// (`second`) and closes what it opened.
const RECOVERS: &str = "DEF t()
  DECL STATE_T st
  DECL MODUS_T md
  DECL INT h
  md = #SYNC
  h = 0
  CWRITE($FCT_CALL, st, md, \"krl_fopen\", \"leak.txt\", \"a\", h)
  first = st.RET1 == #DATA_OK
  CWRITE($FCT_CALL, st, md, \"krl_fclose_all\")
  CWRITE($FCT_CALL, st, md, \"krl_fopen\", \"leak.txt\", \"a\", h)
  second = st.RET1 == #DATA_OK
  CWRITE($FCT_CALL, st, md, \"krl_fclose\", h)
END
";

#[test]
fn a_file_left_open_by_a_failed_run_stays_locked_until_krl_fclose_all() {
    let dir = tempfile::tempdir().expect("tempdir");
    let open = OpenFiles::shared();
    let (r, _) = run_on(dir.path(), &open, LEAKS);
    assert!(
        matches!(r, Err(RunError::Runtime { line: 11, .. })),
        "{r:?}"
    );
    let leak = dir.path().join("leak.txt");
    assert_eq!(std::fs::read_to_string(&leak).expect("written"), "x\n");
    // The run is over; its handle is not.
    assert_eq!(
        open.lock().expect("table").names(),
        vec!["leak.txt".to_string()]
    );
    assert!(!free(&leak), "the leaked handle no longer locks the file");

    // The next run cannot open it, until it closes every handle.
    let (r, g) = run_on(dir.path(), &open, RECOVERS);
    assert!(r.is_ok(), "{r:?}");
    assert_eq!(
        (g.bool("FIRST", &[]), g.bool("SECOND", &[])),
        (Some(false), Some(true))
    );
    assert!(open.lock().expect("table").names().is_empty());
    assert!(free(&leak));
}

#[test]
fn a_reboot_releases_what_a_run_left_open() {
    let dir = tempfile::tempdir().expect("tempdir");
    let open = OpenFiles::shared();
    let _ = run_on(dir.path(), &open, LEAKS);
    let leak = dir.path().join("leak.txt");
    assert!(!free(&leak));
    // A reboot: the old table goes with the old runtime.
    drop(open);
    assert!(free(&leak));
    let fresh = OpenFiles::shared();
    let (r, g) = run_on(dir.path(), &fresh, RECOVERS);
    assert!(r.is_ok(), "{r:?}");
    assert_eq!(g.bool("FIRST", &[]), Some(true));
}

/// KUKA: a file opened by one interpreter may not be accessed (written,
/// closed) by the other. The Submit's `krl_fclose_all` leaves the robot
/// interpreter's leaked file open; only the robot interpreter can close it
/// (the shipped `kb_main` does when it starts).
#[test]
fn only_the_interpreter_that_opened_a_file_closes_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let open = OpenFiles::shared();
    let _ = run_on(dir.path(), &open, LEAKS);
    let leak = dir.path().join("leak.txt");
    let (r, g) = run_in("submit", dir.path(), &open, RECOVERS);
    assert!(r.is_ok(), "{r:?}");
    assert_eq!(
        (g.bool("FIRST", &[]), g.bool("SECOND", &[])),
        (Some(false), Some(false))
    );
    assert!(!free(&leak));
    // Its handle number means nothing to the other interpreter either.
    let (r, g) = run_in(
        "submit",
        dir.path(),
        &open,
        "DEF t()
  DECL STATE_T st
  DECL MODUS_T md
  md = #SYNC
  CWRITE($FCT_CALL, st, md, \"krl_fclose\", 1)
  first = st.RET1 == #DATA_OK
END
",
    );
    assert!(r.is_ok(), "{r:?}");
    assert_eq!(g.bool("FIRST", &[]), Some(false));
    assert!(!free(&leak));
    let (r, g) = run_on(dir.path(), &open, RECOVERS);
    assert!(r.is_ok(), "{r:?}");
    assert_eq!(g.bool("SECOND", &[]), Some(true));
    assert!(free(&leak));
}

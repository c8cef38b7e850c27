//! The binary as an operator runs it: log files (rolled daily, flushed on
//! shutdown), exit codes, and configuration errors that name the file and
//! the key.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[cfg(unix)]
use kuka_bridge_tests::CliService;

fn cli() -> &'static str {
    env!("CARGO_BIN_EXE_kuka-bridge-cli")
}

#[cfg(unix)]
/// The service's log files (not the audit trail beside them).
fn log_files(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    std::fs::read_dir(dir)
        .map(|rd| {
            rd.flatten()
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "log"))
                .collect()
        })
        .unwrap_or_default()
}

#[cfg(unix)] // stops the service with SIGTERM
#[test]
fn console_run_writes_a_daily_log_file_and_flushes_it_on_shutdown() {
    let root = tempfile::tempdir().expect("tempdir");
    let data = root.path().join("data");
    let mut service = CliService::spawn(
        cli(),
        "info",
        [
            "--simulate",
            "--time-scale",
            "0",
            "--listen",
            "127.0.0.1:0",
            "--data-dir",
            data.to_str().expect("a UTF-8 temporary path"),
        ],
    );
    let url = service.url();
    assert!(url.starts_with("http://127.0.0.1:"), "{url}");
    // Graceful stop (SIGTERM, as systemd or `kill` would).
    service.terminate();
    let code = service.wait_exit(Duration::from_secs(20), "after SIGTERM");
    assert!(code.success(), "clean exit: {code:?}");

    let logs = log_files(&data.join("logs"));
    assert_eq!(logs.len(), 1, "one file per day: {logs:?}");
    let name = logs[0]
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default()
        .to_string();
    assert!(
        name.starts_with("kuka-bridge.") && name.ends_with(".log"),
        "{name}"
    );
    let text = std::fs::read_to_string(&logs[0]).expect("log");
    assert!(text.contains("kuka-bridge listening"), "{text}");
    assert!(
        text.contains("kuka-bridge stopped"),
        "the last line is flushed: {text}"
    );
    assert!(!text.contains("\u{1b}["), "no colour codes in files");
}

/// Runs the CLI with a bad config; a service that starts anyway (the check
/// missed) is killed after 20 s instead of hanging the suite.
fn run_bad(config: &std::path::Path) -> std::process::Output {
    let mut child = Command::new(cli())
        .args(["run", "--listen", "127.0.0.1:0", "--config"])
        .arg(config)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let end = Instant::now() + Duration::from_secs(20);
    while child.try_wait().expect("wait").is_none() {
        if Instant::now() > end {
            let _ = child.kill();
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

#[test]
fn configuration_errors_name_the_file_and_key_and_exit_78() {
    let root = tempfile::tempdir().expect("tempdir");
    let path = root.path().join("bad.toml");
    std::fs::write(&path, "[channel]\npoll_interval_ms = 0\n").expect("write");
    let out = run_bad(&path);
    assert_eq!(out.status.code(), Some(78), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml"), "names the file: {err}");
    assert!(
        err.contains("channel.poll_interval_ms"),
        "names the key: {err}"
    );

    std::fs::write(&path, "[log]\nlevel = \"loud\"\n").expect("write");
    let out = run_bad(&path);
    assert_eq!(out.status.code(), Some(78), "{out:?}");
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("log.level"),
        "{out:?}"
    );

    std::fs::write(&path, "[chanel]\ndir = \"x\"\n").expect("write");
    let out = run_bad(&path);
    assert_eq!(out.status.code(), Some(78), "an unknown section: {out:?}");
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("chanel"),
        "{out:?}"
    );
}

/// A reader that stops early (`kuka-bridge openapi | head`) ends the
/// output quietly: exit 0, no panic on stderr.
#[test]
fn a_closed_stdout_is_not_a_crash() {
    for args in [&["openapi"][..], &["default-config"][..]] {
        let mut child = Command::new(cli())
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn");
        // Close the reading end before the child writes.
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("wait");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            out.status.success() && !stderr.contains("panicked"),
            "{args:?}: {:?} {stderr}",
            out.status
        );
    }
}

/// `--listen` takes a host name: `localhost:PORT` listens on loopback.
/// Without a port, or with a port out of range, it stops at once with a
/// sentence saying what it wants (exit 2, a usage error).
#[test]
fn listen_takes_a_host_name() {
    let root = tempfile::tempdir().expect("tempdir");
    let data = root.path().join("data");
    let mut service = kuka_bridge_tests::CliService::spawn(
        cli(),
        "warn",
        [
            "--simulate",
            "--time-scale",
            "0",
            "--listen",
            "localhost:0",
            "--data-dir",
            data.to_str().expect("a UTF-8 temporary path"),
        ],
    );
    let url = service.url().to_string();
    assert!(url.starts_with("http://127.0.0.1:"), "loopback: {url}");
    assert!(
        service.console().contains("no tokens (loopback only"),
        "{}",
        service.console()
    );
    service.terminate();
    service.wait_exit(Duration::from_secs(20), "after a stop");

    for (listen, says) in [
        ("localhost", "is not HOST:PORT"),
        ("localhost:99999", "port 0..65535"),
        (":8080", "is not HOST:PORT"),
    ] {
        let out = Command::new(cli())
            .args(["run", "--listen", listen])
            .output()
            .expect("run");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{listen}: {err}");
        assert!(
            err.contains("--listen") && err.contains(says),
            "{listen}: {err}"
        );
    }
}

/// Off Windows, `kuka-bridge service …` says that the service commands
/// are Windows-only and what to run instead, and fails (exit 2), rather
/// than "unrecognized subcommand".
#[cfg(not(windows))]
#[test]
fn service_commands_off_windows_say_what_to_run_instead() {
    for args in [
        &["service"][..],
        &["service", "install", "--no-start"][..],
        &["service", "--help"][..],
    ] {
        let out = Command::new(cli()).args(args).output().expect("run");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("only on Windows")
                && err.contains("kuka-bridge run")
                && err.contains("systemd"),
            "{args:?}: {err}"
        );
        assert!(out.stdout.is_empty(), "{args:?}");
    }
    // Not offered in the help of a Linux build.
    let out = Command::new(cli()).arg("--help").output().expect("help");
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(
        !help.lines().any(|l| l.trim_start().starts_with("service")),
        "{help}"
    );
}

/// `kuka-bridge krl check`: one `file:line:column: message` per problem,
/// exit code 1 when any file has one, 0 when none; folders are walked;
/// `--simulator` adds the checks a simulated controller needs.
#[test]
fn krl_check_lints_files_and_folders() {
    let dir = tempfile::tempdir().expect("tempdir");
    let good = dir.path().join("good.src");
    std::fs::write(
        &good,
        "DEF good( )\nDECL INT i\nSPTP XHOME WITH $VEL_AXIS[1] = SVEL_JOINT(100.0)\nGOTO done\ni = 1\ndone:\nEND\n",
    )
    .expect("write");
    // Windows-1252 in a comment, as KSS writes it.
    std::fs::write(
        dir.path().join("good.dat"),
        b"DEFDAT good PUBLIC\n;Gr\xFC\xDFe\nGLOBAL INT counter=0\nENDDAT\n",
    )
    .expect("write");
    let bad = dir.path().join("sub").join("bad.SRC");
    std::fs::create_dir_all(bad.parent().expect("parent")).expect("mkdir");
    std::fs::write(&bad, "DEF bad()\n  x = 1\n  DECL INT x\nEND\n").expect("write");

    let run = |args: &[&std::ffi::OsStr]| {
        let out = Command::new(cli())
            .arg("krl")
            .arg("check")
            .args(args)
            .output()
            .expect("run the CLI");
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
        )
    };
    let (code, out) = run(&[good.as_os_str()]);
    assert_eq!((code, out.as_str()), (Some(0), ""));
    let (code, out) = run(&[dir.path().as_os_str()]);
    assert_eq!(code, Some(1), "{out}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1, "{out}");
    assert!(
        lines[0].starts_with(&format!("{}:3:", bad.display())) && lines[0].contains("declaration"),
        "{out}"
    );
    // With --simulator the good module is outside what the simulator runs.
    let (code, out) = run(&["--simulator".as_ref(), good.as_os_str()]);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.starts_with(&format!("{}:3:1:", good.display())) && out.contains("program_unsupported"),
        "{out}"
    );
    // --simulator=krc: what the KRC-like runtime runs (interrupts, with
    // its system variables), not GOTO.
    let irq = dir.path().join("irq").join("irq.src");
    std::fs::create_dir_all(irq.parent().expect("parent")).expect("mkdir");
    std::fs::write(
        &irq,
        "DEF irq()\n  INTERRUPT DECL 3 WHEN $IN[1] DO irq2()\n  INTERRUPT ON 3\nEND\nDEF irq2()\nEND\n",
    )
    .expect("write");
    let (code, out) = run(&["--simulator=krc".as_ref(), irq.as_os_str()]);
    assert_eq!((code, out.as_str()), (Some(0), ""), "{out}");
    let (code, out) = run(&["--simulator".as_ref(), irq.as_os_str()]);
    assert!(
        code == Some(1) && out.contains("native simulator does not run INTERRUPT"),
        "{out}"
    );
    let (code, out) = run(&["--simulator=krc".as_ref(), good.as_os_str()]);
    assert!(
        code == Some(1)
            && out.starts_with(&format!("{}:3:1: the KRC-like runtime", good.display())),
        "{out}"
    );
    // A path that names no KRL file fails; a control character in a
    // message is escaped, not printed.
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).expect("mkdir");
    let garbage = dir.path().join("garbage.src");
    std::fs::write(&garbage, b"DEF g()\n  x = \x02\nEND\n").expect("write");
    let missing = dir.path().join("missing");
    let (code, out) = run(&[missing.as_os_str(), empty.as_os_str(), garbage.as_os_str()]);
    assert_eq!(code, Some(1), "{out}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines,
        [
            format!("{}: no such file or folder", missing.display()),
            format!(
                "{}: no KRL files (.src, .sub, .dat) in this folder",
                empty.display()
            ),
            format!("{}:2:7: unexpected character `\\u{{2}}`", garbage.display()),
        ],
        "{out}"
    );
    // A module named unlike its file: a warning, the check still passes;
    // a GOTO into a block: a problem.
    let renamed = dir.path().join("renamed.src");
    std::fs::write(&renamed, "; header\nDEF other()\nEND\n").expect("write");
    let (code, out) = run(&[renamed.as_os_str()]);
    assert_eq!(code, Some(0), "{out}");
    assert!(
        out.starts_with(&format!("{}:2:1: warning:", renamed.display())) && out.contains("`other`"),
        "{out}"
    );
    let jump = dir.path().join("jump.src");
    std::fs::write(
        &jump,
        "DEF jump()\n  GOTO inside\n  LOOP\n    inside:\n  ENDLOOP\nEND\n",
    )
    .expect("write");
    let (code, out) = run(&[jump.as_os_str()]);
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.starts_with(&format!("{}:2:", jump.display())) && out.contains("into a block"),
        "{out}"
    );
}

//! The clients a user generates from the OpenAPI document, tested with the
//! tools they would use, against the running service on the simulator:
//!
//! - the document (with and without plugins) passes two independent
//!   validators, openapi-spec-validator (PyPI) and Redocly's CLI (npm), and
//!   `clients/openapi.json` is the document of this build;
//! - the Python SDK (`clients/python`, openapi-python-client) and the
//!   TypeScript types (`clients/typescript`, openapi-typescript) are what
//!   their generators make of it today (no drift), and each example runs
//!   green: state, PTP/LIN/CIRC, the smiley as a batch, a job polled to its
//!   end, an unreachable target as a typed error, a plugin installed from
//!   its bytes and called; a plugin's own error code reaches the Python
//!   client as is.
//!
//! The tools come from the registries (pinned in
//! `clients/python/requirements-dev.txt` and `clients/typescript/package-lock.json`).
//! Without python3 (with venv) or Node.js these tests fail with the command
//! that installs them (leave them out on purpose with `cargo test --
//! --skip clients`: filtered out, not passed).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

use kuka_bridge_tests::{Options, TestService};

/// The `--skip` filter that leaves these tests out.
const SKIP_VAR: &str = "sdk";

fn clients_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../clients")
}

/// Runs `cmd`, panicking with its output when it fails; its stdout.
fn run(cmd: &mut Command) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.status.success(),
        "{cmd:?} failed ({}):\n{text}",
        out.status
    );
    text
}

/// The venv with the Python tools, or None when python3 is missing (and
/// the test may be skipped).
fn python_tools() -> Option<PathBuf> {
    static READY: Mutex<bool> = Mutex::new(false);
    let python = if cfg!(windows) { "python" } else { "python3" };
    let have = Command::new(python)
        .args(["-c", "import venv, ensurepip"])
        .status()
        .is_ok_and(|s| s.success());
    if !have {
        kuka_bridge_tests::missing_tool(
            &format!("{python} with venv/ensurepip is not installed (the Python SDK needs it)"),
            if cfg!(windows) {
                "winget install Python.Python.3.12"
            } else {
                "sudo apt-get install python3 python3-venv"
            },
            SKIP_VAR,
        );
        return None;
    }
    let home = std::env::var_os("HOME")
        .or_else(|| std::env::var_os("USERPROFILE"))
        .expect("HOME or USERPROFILE");
    let venv = PathBuf::from(home).join(".cache/kuka-bridge/sdk-venv");
    let bin = venv.join(if cfg!(windows) { "Scripts" } else { "bin" });
    let mut ready = READY.lock().unwrap_or_else(|p| p.into_inner());
    if !*ready {
        let exe = bin.join(format!("python{}", std::env::consts::EXE_SUFFIX));
        if !exe.exists() {
            run(Command::new(python).args(["-m", "venv"]).arg(&venv));
        }
        let requirements = clients_dir().join("python/requirements-dev.txt");
        let wanted = std::fs::read_to_string(&requirements).expect("requirements-dev.txt");
        let marker = venv.join("kuka-bridge-requirements.txt");
        if std::fs::read_to_string(&marker).ok().as_deref() != Some(wanted.as_str()) {
            run(Command::new(&exe)
                .args([
                    "-m",
                    "pip",
                    "install",
                    "--quiet",
                    "--disable-pip-version-check",
                    "-r",
                ])
                .arg(&requirements));
            std::fs::write(&marker, wanted).expect("marker");
        }
        *ready = true;
    }
    Some(bin)
}

/// `clients/typescript/node_modules` from its lock file, or None when
/// Node.js is missing (and the test may be skipped).
fn node_tools() -> Option<PathBuf> {
    static READY: Mutex<bool> = Mutex::new(false);
    let npm = if cfg!(windows) { "npm.cmd" } else { "npm" };
    if Command::new(npm).arg("--version").output().is_err() {
        kuka_bridge_tests::missing_tool(
            "Node.js with npm is not installed (the TypeScript SDK and Redocly's validator need it)",
            if cfg!(windows) {
                "winget install OpenJS.NodeJS.LTS"
            } else {
                "sudo apt-get install nodejs npm"
            },
            SKIP_VAR,
        );
        return None;
    }
    let dir = clients_dir().join("typescript");
    let mut ready = READY.lock().unwrap_or_else(|p| p.into_inner());
    if !*ready {
        let lock = std::fs::read(dir.join("package-lock.json")).expect("package-lock.json");
        let installed = std::fs::read(dir.join("node_modules/.kb-package-lock.json")).ok();
        if installed.as_deref() != Some(lock.as_slice()) {
            run(Command::new(npm)
                .args(["ci", "--silent", "--no-audit", "--no-fund"])
                .current_dir(&dir));
            std::fs::write(dir.join("node_modules/.kb-package-lock.json"), &lock).expect("marker");
        }
        *ready = true;
    }
    Some(dir)
}

fn node_bin(dir: &Path, tool: &str) -> PathBuf {
    let ext = if cfg!(windows) { ".cmd" } else { "" };
    dir.join("node_modules/.bin").join(format!("{tool}{ext}"))
}

/// The document as served, with the example plugins installed.
async fn served_with_plugins(t: &TestService) -> serde_json::Value {
    let plugins = kuka_bridge_tests::example_plugins(Path::new(env!("CARGO_TARGET_TMPDIR")), false);
    for name in ["draw-circle", "draw-smiley"] {
        let wasm = std::fs::read(plugins.join(format!("{name}.wasm"))).expect("plugin");
        let (status, v) = t.put_bytes(&format!("/api/v1/plugins/{name}"), wasm).await;
        assert!(status == 200 || status == 201, "{v}");
    }
    let (status, doc) = t.get("/openapi.json").await;
    assert_eq!(status, 200);
    doc
}

#[tokio::test]
async fn sdk_openapi_document_is_committed_and_passes_two_validators() {
    let doc = kuka_bridge::api::openapi();
    let committed = clients_dir().join("openapi.json");
    let text = serde_json::to_string_pretty(&doc).expect("json") + "\n";
    let on_disk = std::fs::read_to_string(&committed).unwrap_or_default();
    assert!(
        on_disk == text,
        "clients/openapi.json is not this build's document: run `cargo run -p kuka-bridge -- openapi > clients/openapi.json` and regenerate the clients (clients/README.md)"
    );
    let (Some(py), Some(node)) = (python_tools(), node_tools()) else {
        return;
    };
    let t = TestService::start(Options::default()).await;
    let served = served_with_plugins(&t).await;
    assert!(
        served["paths"]
            .as_object()
            .expect("paths")
            .keys()
            .any(|p| p.starts_with("/api/v1/plugins/draw-circle/")),
        "plugin routes are documented"
    );
    let work = tempfile::tempdir().expect("tempdir");
    let with_plugins = work.path().join("with-plugins.json");
    std::fs::write(&with_plugins, served.to_string()).expect("write");
    for file in [committed.as_path(), with_plugins.as_path()] {
        let out = run(Command::new(py.join("openapi-spec-validator")).arg(file));
        assert!(out.contains("OK"), "{out}");
        // Exit status 0: no errors (warnings are printed, not failed).
        run(Command::new(node_bin(&node, "redocly"))
            .args(["lint", "--format=summary"])
            .arg(file)
            .current_dir(&node));
    }
}

/// Every file below `dir`, relative, with its bytes.
fn tree(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("read_dir") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                if p.file_name().is_some_and(|n| n != "__pycache__") {
                    stack.push(p);
                }
            } else {
                let rel = p.strip_prefix(dir).expect("below").to_path_buf();
                out.push((rel, std::fs::read(&p).expect("read")));
            }
        }
    }
    out.sort();
    out
}

#[tokio::test]
async fn sdk_python_is_generated_from_the_document_and_its_example_runs() {
    let Some(py) = python_tools() else {
        return;
    };
    let dir = clients_dir().join("python");
    let work = tempfile::tempdir().expect("tempdir");
    let fresh = work.path().join("kuka-bridge-client");
    run(Command::new(py.join("openapi-python-client"))
        .args(["generate", "--meta", "uv", "--path"])
        .arg(clients_dir().join("openapi.json"))
        .arg("--config")
        .arg(dir.join("config.yml"))
        .arg("--output-path")
        .arg(&fresh));
    let (fresh, committed) = (tree(&fresh), tree(&dir.join("kuka-bridge-client")));
    let names = |t: &[(PathBuf, Vec<u8>)]| t.iter().map(|(p, _)| p.clone()).collect::<Vec<_>>();
    assert_eq!(
        names(&fresh),
        names(&committed),
        "clients/python/kuka-bridge-client drifted: regenerate it (clients/README.md)"
    );
    for ((path, a), (_, b)) in fresh.iter().zip(&committed) {
        assert!(
            a == b,
            "clients/python/kuka-bridge-client/{} drifted: regenerate it (clients/README.md)",
            path.display()
        );
    }

    let t = TestService::start(Options::default()).await;
    let plugins = kuka_bridge_tests::example_plugins(Path::new(env!("CARGO_TARGET_TMPDIR")), false);
    let python = py.join(format!("python{}", std::env::consts::EXE_SUFFIX));
    let base = t.url("");
    let (example, errors) = {
        let (python, base, plugins, dir) =
            (python.clone(), base.clone(), plugins.clone(), dir.clone());
        tokio::task::spawn_blocking(move || {
            let example = run(Command::new(&python)
                .arg(dir.join("examples/quickstart.py"))
                .arg(&base)
                .arg(plugins.join("draw-circle.wasm")));
            let errors = run(Command::new(&python)
                .arg(dir.join("examples/plugin_errors.py"))
                .arg(&base)
                .arg(plugins.join("misbehave.wasm")));
            (example, errors)
        })
        .await
        .expect("join")
    };
    for line in [
        "ptp: job",
        "lin: job",
        "circ: job",
        "smiley: job",
        "done, 15/15 motions",
        "refused as expected: unreachable",
        "installed draw-circle",
        "plugin drew",
        "plugin refused as expected",
    ] {
        assert!(example.contains(line), "{line:?} missing in:\n{example}");
    }
    assert!(errors.contains("plugin code: cable_snag"), "{errors}");
    // The example's smiley really ran on the simulator.
    let (_, jobs) = t.get("/api/v1/jobs?limit=20").await;
    assert!(
        jobs.as_array()
            .expect("jobs")
            .iter()
            .any(|j| j["motions"] == 15 && j["state"] == "done"),
        "{jobs}"
    );
}

#[tokio::test]
async fn sdk_typescript_is_generated_from_the_document_and_its_example_runs() {
    let Some(dir) = node_tools() else {
        return;
    };
    let work = tempfile::tempdir().expect("tempdir");
    let fresh = work.path().join("schema.d.ts");
    run(Command::new(node_bin(&dir, "openapi-typescript"))
        .arg(clients_dir().join("openapi.json"))
        .arg("-o")
        .arg(&fresh)
        .current_dir(&dir));
    let committed = std::fs::read(dir.join("src/schema.d.ts")).expect("schema.d.ts");
    assert!(
        std::fs::read(&fresh).expect("fresh") == committed,
        "clients/typescript/src/schema.d.ts drifted: run `npm run generate` there"
    );
    run(Command::new(node_bin(&dir, "tsc"))
        .args(["-p", "."])
        .current_dir(&dir));

    let t = TestService::start(Options::default()).await;
    let plugins = kuka_bridge_tests::example_plugins(Path::new(env!("CARGO_TARGET_TMPDIR")), false);
    let base = t.url("");
    let out = tokio::task::spawn_blocking(move || {
        run(Command::new("node")
            .arg(dir.join("dist/examples/quickstart.js"))
            .arg(&base)
            .arg(plugins.join("draw-circle.wasm")))
    })
    .await
    .expect("join");
    for line in [
        "ptp: job",
        "smiley: job",
        "done, 15/15 motions",
        "refused as expected: unreachable",
        "installed draw-circle",
        "plugin refused as expected",
    ] {
        assert!(out.contains(line), "{line:?} missing in:\n{out}");
    }
}

//! Support for the end-to-end tests: start the real service on a free
//! port with a real channel directory (embedded or separate simulated
//! controller), and talk to it over HTTP.

use std::path::{Path, PathBuf};
use std::time::Duration;

use kuka_bridge::app::Service;
use kuka_bridge::config::{Config, SimulatorKind};
use serde_json::Value;

pub mod browser;

/// A service under test with its directories.
pub struct TestService {
    /// The running service.
    pub service: Service,
    /// HTTP client.
    pub http: reqwest::Client,
    /// Holds the data and channel directories.
    pub dirs: tempfile::TempDir,
    /// The configuration it was started with.
    pub config: Config,
}

/// Options for [`TestService::start`].
pub struct Options {
    /// Embed the simulator.
    pub simulate: bool,
    /// Simulator time scale (0 = instant).
    pub time_scale: f64,
    /// Change anything else.
    pub tweak: Box<dyn FnOnce(&mut Config)>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            simulate: true,
            time_scale: 0.0,
            tweak: Box::new(|_| {}),
        }
    }
}

/// The simulated controller the tests embed: `KB_TEST_SIMULATOR=krc` runs
/// them on the shipped KRL program in the KRC-like runtime (`.ci/run` runs
/// the HTTP suites with both); `native` or unset: the native simulator.
pub fn test_simulator() -> SimulatorKind {
    match std::env::var("KB_TEST_SIMULATOR").as_deref() {
        Ok("krc") => SimulatorKind::Krc,
        Ok("native") | Err(_) => SimulatorKind::Native,
        Ok(other) => panic!("KB_TEST_SIMULATOR={other}: use native or krc"),
    }
}

/// The KSS variant the KRC-like runtime simulates in these tests
/// (docs/CONTROLLER.md A1, A2): `KB_TEST_KSS=cmd_ok-folder` answers file
/// functions with `#CMD_OK` and accepts `RUN /R1/Program/kbridge/<module>()`
/// only (the program's `kb_run_pfx` set to match, as a site would), and
/// counts SREAD/SWRITE offsets as 1-based positions (so the program falls
/// back to parsing by characters: the suite runs that path too);
/// unset or `default`: `#DATA_OK` and `/R1/`.
pub fn apply_test_kss(c: &mut Config) {
    match std::env::var("KB_TEST_KSS").as_deref() {
        Ok("default") | Err(_) => {}
        Ok("cmd_ok-folder") => {
            c.simulator.file_success = kuka_bridge::config::FileSuccess::CmdOk;
            c.simulator.run_prefix = "/R1/Program/kbridge/".into();
            c.simulator.text_offset = kuka_bridge::config::TextOffset::Position;
        }
        Ok(other) => panic!("KB_TEST_KSS={other}: use default or cmd_ok-folder"),
    }
}

/// One sample of the executed path, from whichever simulated controller
/// runs (native: per IPO step; krc: per interpreter cycle).
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// Simulated seconds (native: time in motion; krc: controller time).
    pub t: f64,
    /// The command that moved the robot.
    pub cid: i64,
    /// Motion index within that command's batch.
    pub motion: usize,
    /// TCP `[x, y, z, a, b, c]`.
    pub pose: [f64; 6],
    /// Axes A1..A6.
    pub axes: [f64; 6],
    /// The robot stands still from here (an exact stop or the end).
    pub stop: bool,
}

/// A config for tests: free port, fast heartbeat and short timeouts.
pub fn test_config(root: &Path) -> Config {
    let mut c = Config::default();
    c.server.listen = "127.0.0.1:0".parse().expect("addr");
    c.data_dir = root.join("data");
    c.channel.dir = Some(root.join("channel"));
    c.channel.poll_interval_ms = 10;
    // Generous for loaded CI machines running debug builds.
    c.channel.offline_after_ms = 1000;
    c.channel.ack_timeout_ms = 1000;
    c.channel.command_timeout_ms = 10_000;
    c.channel.lock_timeout_ms = 300;
    c.simulator.heartbeat_ms = 10;
    c.server.request_timeout_ms = 20_000;
    c
}

impl TestService {
    /// Starts the service in a fresh temporary directory.
    pub async fn start(opts: Options) -> TestService {
        let dirs = tempfile::tempdir().expect("tempdir");
        let mut c = test_config(dirs.path());
        c.simulator.enabled = opts.simulate;
        c.simulator.time_scale = opts.time_scale;
        c.simulator.kind = test_simulator();
        apply_test_kss(&mut c);
        (opts.tweak)(&mut c);
        Self::start_with(c, dirs).await
    }

    /// Starts the service without an embedded simulator on `root/channel`,
    /// with its data in `root/data`: a simulator in its own process
    /// ([`SimProcess`]) drives the channel, and a restarted service finds
    /// both folders again.
    pub async fn start_without_sim(root: &Path) -> TestService {
        let mut c = test_config(root);
        c.simulator.enabled = false;
        let dirs = tempfile::tempdir_in(root).expect("tempdir");
        TestService::start_with(c, dirs).await
    }

    /// Starts the service with a prepared config.
    pub async fn start_with(config: Config, dirs: tempfile::TempDir) -> TestService {
        let service = kuka_bridge::app::start(config.clone())
            .await
            .expect("service starts");
        let http = reqwest::Client::builder()
            .timeout(Duration::from_secs(30))
            .build()
            .expect("client");
        let t = TestService {
            service,
            http,
            dirs,
            config,
        };
        t.wait_online().await;
        t
    }

    /// The executed path so far, oldest first.
    pub fn trace(&self) -> Vec<Sample> {
        if let Some(sim) = &self.service.sim {
            return sim
                .trace()
                .iter()
                .map(|s| Sample {
                    t: s.t,
                    cid: s.cid.into(),
                    motion: s.motion,
                    pose: s.pose,
                    axes: s.axes,
                    stop: s.stop,
                })
                .collect();
        }
        let krc = self.service.krc.as_ref().expect("a simulated controller");
        krc.trace()
            .iter()
            .map(|s| Sample {
                t: s.t,
                cid: s.cid,
                motion: s.motion,
                pose: s.pose,
                axes: s.axes,
                stop: s.stop,
            })
            .collect()
    }

    /// Freezes the simulated controller (a hung controller).
    pub fn pause_controller(&self) {
        match (&self.service.sim, &self.service.krc) {
            (Some(sim), _) => sim.pause(),
            (None, Some(krc)) => krc.pause(),
            (None, None) => panic!("no simulated controller"),
        }
    }

    /// Ends [`pause_controller`](Self::pause_controller).
    pub fn resume_controller(&self) {
        match (&self.service.sim, &self.service.krc) {
            (Some(sim), _) => sim.resume(),
            (None, Some(krc)) => krc.resume(),
            (None, None) => panic!("no simulated controller"),
        }
    }

    /// Puts the controller into its error state the way each simulated
    /// controller gets there: the native one is told to (an injected
    /// runtime error); the shipped KRL program enters it when the robot
    /// stops with a message while a job runs, here a LIN from home through
    /// the wrist singularity, which only reaches the controller when the
    /// service has no dry run (start it with `robot.model = "none"`).
    pub async fn provoke_controller_error(&self) {
        match (&self.service.sim, &self.service.krc) {
            (Some(sim), _) => sim.inject_error(kuka_protocol::ResultCode::RuntimeError, 0),
            (None, Some(_)) => {
                let (s, v) = self
                    .motions(serde_json::json!([{"type": "lin", "target": {"y": 100}}]))
                    .await;
                assert_eq!(
                    (s, v["code"].as_str()),
                    (409, Some("controller_error")),
                    "a LIN through the wrist singularity (is the dry run off?): {v}"
                );
            }
            (None, None) => panic!("no simulated controller"),
        }
    }

    /// The simulated robot's axes now.
    pub fn controller_axes(&self) -> [f64; 6] {
        match (&self.service.sim, &self.service.krc) {
            (Some(sim), _) => sim.snapshot().axes,
            (None, Some(krc)) => krc.snapshot().axes,
            (None, None) => panic!("no simulated controller"),
        }
    }

    /// Empties the trace.
    pub fn clear_trace(&self) {
        match (&self.service.sim, &self.service.krc) {
            (Some(sim), _) => sim.clear_trace(),
            (None, Some(krc)) => krc.clear_trace(),
            (None, None) => panic!("no simulated controller"),
        }
    }

    /// Simulated seconds the robot has spent moving.
    pub fn moving_s(&self) -> f64 {
        match (&self.service.sim, &self.service.krc) {
            (Some(sim), _) => sim.snapshot().sim_time_s,
            (None, Some(krc)) => krc.stats().moving_s,
            (None, None) => panic!("no simulated controller"),
        }
    }

    /// The channel directory.
    pub fn channel_dir(&self) -> PathBuf {
        self.dirs.path().join("channel")
    }

    /// Full URL of a path.
    pub fn url(&self, path: &str) -> String {
        format!("{}{path}", self.service.base_url())
    }

    /// Waits until the controller is online (if a simulator runs).
    pub async fn wait_online(&self) {
        if self.service.sim.is_none() && self.service.krc.is_none() {
            return;
        }
        self.wait_connection("online").await;
    }

    /// Waits until `/health` reports this connection state (10 s max).
    pub async fn wait_connection(&self, want: &str) {
        self.wait_health(&format!("connection {want}"), |h| h["connection"] == want)
            .await;
    }

    /// Polls `GET /health` until `ok` holds for it ([`WAIT`] at most, then
    /// a panic naming `what`); that answer.
    pub async fn wait_health(&self, what: &str, ok: impl Fn(&Value) -> bool) -> Value {
        wait_for(WAIT, what, async || {
            let (status, h) = self.get("/health").await;
            if status == 200 && ok(&h) {
                Ok(h)
            } else {
                Err(format!("{status} {h}"))
            }
        })
        .await
    }

    /// Polls `GET /api/v1/state` until `ok` holds for it ([`WAIT`] at
    /// most, then a panic naming `what`); that state.
    pub async fn wait_state(&self, what: &str, ok: impl Fn(&Value) -> bool) -> Value {
        wait_for(WAIT, what, async || {
            let (status, st) = self.get("/api/v1/state").await;
            if status == 200 && ok(&st) {
                Ok(st)
            } else {
                Err(format!("{status} {st}"))
            }
        })
        .await
    }

    /// Polls `GET /api/v1/jobs/{id}` until `ok` holds for the job
    /// ([`WAIT`] at most, then a panic naming `what`); that job.
    pub async fn wait_job(&self, id: u64, what: &str, ok: impl Fn(&Value) -> bool) -> Value {
        wait_for(WAIT, what, async || {
            let (status, job) = self.get(&format!("/api/v1/jobs/{id}")).await;
            if status == 200 && ok(&job) {
                Ok(job)
            } else {
                Err(format!("{status} {job}"))
            }
        })
        .await
    }

    /// A request with no body, answered as is (status, headers, body).
    pub async fn request(&self, method: reqwest::Method, path: &str) -> reqwest::Response {
        self.http
            .request(method, self.url(path))
            .send()
            .await
            .expect("request")
    }

    /// GET → (status, JSON).
    pub async fn get(&self, path: &str) -> (u16, Value) {
        let r = self.http.get(self.url(path)).send().await.expect("request");
        decode(r).await
    }

    /// GET as the bearer of `token` → (status, JSON).
    pub async fn get_as(&self, path: &str, token: &str) -> (u16, Value) {
        let r = self
            .http
            .get(self.url(path))
            .bearer_auth(token)
            .send()
            .await
            .expect("request");
        decode(r).await
    }

    /// Creates a token through the API as `admin`; returns its secret.
    pub async fn create_token(&self, admin: &str, name: &str, role: &str) -> String {
        let r = self
            .http
            .post(self.url("/api/v1/tokens"))
            .bearer_auth(admin)
            .json(&serde_json::json!({"name": name, "role": role}))
            .send()
            .await
            .expect("request");
        let (status, v) = decode(r).await;
        assert_eq!(status, 201, "{v}");
        assert_eq!(v["role"], role);
        v["secret"].as_str().expect("secret").to_string()
    }

    /// POST without body.
    pub async fn post(&self, path: &str) -> (u16, Value) {
        let r = self
            .http
            .post(self.url(path))
            .send()
            .await
            .expect("request");
        decode(r).await
    }

    /// Waits until a round trip through the controller program works
    /// (`POST /krl/getpos` answers 200): after a pause or an operator
    /// restart of the simulated controller.
    pub async fn wait_getpos(&self, what: &str) {
        wait_for(WAIT, what, async || {
            let (s, v) = self.post("/krl/getpos").await;
            if s == 200 {
                Ok(())
            } else {
                Err(format!("{s} {v}"))
            }
        })
        .await;
    }

    /// POST a JSON body.
    pub async fn post_json(&self, path: &str, body: &Value) -> (u16, Value) {
        let r = self
            .http
            .post(self.url(path))
            .json(body)
            .send()
            .await
            .expect("request");
        decode(r).await
    }

    /// PUT a JSON body.
    pub async fn put_json(&self, path: &str, body: &Value) -> (u16, Value) {
        let r = self
            .http
            .put(self.url(path))
            .json(body)
            .send()
            .await
            .expect("request");
        decode(r).await
    }

    /// DELETE.
    pub async fn delete(&self, path: &str) -> (u16, Value) {
        let r = self
            .http
            .delete(self.url(path))
            .send()
            .await
            .expect("request");
        decode(r).await
    }

    /// PUT raw bytes (a plugin's .wasm). An install compiles the plugin
    /// (minutes for a Python one when every test installs at once on a
    /// two-core machine), so it may take longer than other requests.
    pub async fn put_bytes(&self, path: &str, body: Vec<u8>) -> (u16, Value) {
        let r = self
            .http
            .put(self.url(path))
            .timeout(Duration::from_secs(300))
            .header("content-type", "application/wasm")
            .body(body)
            .send()
            .await
            .expect("request");
        decode(r).await
    }

    /// POST a `text/plain` body (a KRL program for `/krl/uploadfile`).
    pub async fn post_text(&self, path: &str, body: String) -> (u16, Value) {
        // No client timeout: an upload to /krl/uploadfile runs the program.
        let r = reqwest::Client::new()
            .post(self.url(path))
            .header("content-type", "text/plain")
            .body(body)
            .send()
            .await
            .expect("request");
        decode(r).await
    }

    /// POST a hand-made `multipart/form-data` body with this boundary to
    /// `/krl/uploadfile`.
    pub async fn post_form(&self, boundary: &str, body: String) -> (u16, Value) {
        // No client timeout: an upload to /krl/uploadfile runs the program.
        let r = reqwest::Client::new()
            .post(self.url("/krl/uploadfile"))
            .header(
                "content-type",
                format!("multipart/form-data; boundary={boundary}"),
            )
            .body(body)
            .send()
            .await
            .expect("request");
        decode(r).await
    }

    /// POST /api/v1/motions with these motions (wait = true).
    pub async fn motions(&self, motions: Value) -> (u16, Value) {
        self.post_json(
            "/api/v1/motions",
            &serde_json::json!({ "motions": motions }),
        )
        .await
    }
}

/// How long the tests wait for a state before they fail: generous for a
/// loaded two-core machine running debug builds (a state that is reached
/// ends the wait at once).
pub const WAIT: Duration = Duration::from_secs(10);

/// Polls `probe` every 10 ms until it returns `Ok`, for at most `within`,
/// then panics naming `what` and the last `Err` (what was seen instead).
/// The tests synchronise with this on a state, never with a fixed sleep.
pub async fn wait_for<T>(
    within: Duration,
    what: &str,
    mut probe: impl AsyncFnMut() -> Result<T, String>,
) -> T {
    let deadline = tokio::time::Instant::now() + within;
    loop {
        let seen = match probe().await {
            Ok(v) => return v,
            Err(seen) => seen,
        };
        assert!(
            tokio::time::Instant::now() < deadline,
            "waited {within:?} for {what}; last seen: {seen}"
        );
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

/// Status and JSON body (Null when empty); checks the problem media type on errors.
pub async fn decode(r: reqwest::Response) -> (u16, Value) {
    let status = r.status().as_u16();
    let ct = r
        .headers()
        .get("content-type")
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_string();
    let text = r.text().await.expect("body");
    if status >= 400 {
        assert_eq!(
            ct, "application/problem+json",
            "error without problem+json: {status} {text}"
        );
    }
    let v = if text.is_empty() {
        Value::Null
    } else {
        serde_json::from_str(&text).unwrap_or(Value::String(text))
    };
    (status, v)
}

/// Position `[x, y, z, a, b, c]` of a thesis response.
pub fn thesis_position(v: &Value) -> [f64; 6] {
    let p = v["position"].as_array().expect("position array");
    let mut out = [0.0; 6];
    for (o, x) in out.iter_mut().zip(p) {
        *o = x.as_f64().expect("number");
    }
    out
}

/// Asserts two numbers agree within `tol`.
pub fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b} (tolerance {tol})");
}

/// Builds the example and fixture plugins once per test binary into
/// `<target_tmp>/plugin-examples` (pass `env!("CARGO_TARGET_TMPDIR")`) and
/// returns that folder, holding `<name>.wasm`: the same files as
/// `plugins/examples/build.sh`, built from Rust so the tests need no shell.
/// `python` adds `py-square.wasm` (componentize-py from PyPI in a venv,
/// `KB_PY_VENV` or `~/.cache/kuka-bridge/venv`; needs `python3` with `venv`).
pub fn example_plugins(target_tmp: &Path, python: bool) -> PathBuf {
    use std::sync::Mutex;
    static BUILT: Mutex<(bool, bool)> = Mutex::new((false, false));
    let out = target_tmp.join("plugin-examples");
    let mut built = BUILT.lock().unwrap_or_else(|p| p.into_inner());
    if !built.0 {
        build_rust_plugins(&out);
        built.0 = true;
    }
    if python && !built.1 {
        build_python_plugin(&out);
        built.1 = true;
    }
    out
}

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../plugins/examples")
}

fn run(cmd: &mut std::process::Command) {
    let status = cmd
        .status()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    assert!(status.success(), "{cmd:?} failed: {status}");
}

/// The target the example plugins are built for.
const WASM_TARGET: &str = "wasm32-wasip2";

/// Makes sure the toolchain can build for [`WASM_TARGET`]. `rustup` adds
/// the targets of `rust-toolchain.toml` only when it installs the
/// toolchain, so a machine that already had the pinned toolchain may lack
/// it: then it is added here (`rustup target add`), and if that cannot be
/// done the tests stop at once with the command to run.
fn ensure_wasm_target() {
    let dir = examples_dir();
    let installed = std::process::Command::new("rustup")
        .args(["target", "list", "--installed"])
        .current_dir(&dir)
        .output();
    let Ok(listed) = installed else {
        // No rustup (a toolchain from elsewhere): the build says what is missing.
        return;
    };
    if String::from_utf8_lossy(&listed.stdout)
        .lines()
        .any(|l| l.trim() == WASM_TARGET)
    {
        return;
    }
    eprintln!(
        "the {WASM_TARGET} target is missing: adding it with `rustup target add {WASM_TARGET}`"
    );
    let added = std::process::Command::new("rustup")
        .args(["target", "add", WASM_TARGET])
        .current_dir(&dir)
        .status();
    assert!(
        added.is_ok_and(|s| s.success()),
        "the plugin tests need the {WASM_TARGET} target and it could not be added; run `rustup target add {WASM_TARGET}` in {} and test again",
        dir.display()
    );
}

fn build_rust_plugins(out: &Path) {
    ensure_wasm_target();
    let target = out.join("target");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let manifest = examples_dir().join("Cargo.toml");
    let build = |target_dir: &Path, extra: &[&str]| {
        run(std::process::Command::new(&cargo)
            .args(["build", "--quiet", "--release", "--target", WASM_TARGET])
            .arg("--manifest-path")
            .arg(&manifest)
            .arg("--target-dir")
            .arg(target_dir)
            .args(extra));
    };
    // One target folder for every build, so the dependencies are compiled
    // once per cache; later test binaries find everything up to date.
    let release = target.join("wasm32-wasip2/release");
    let copy = |from: &str, to: &str| {
        let from = release.join(from);
        std::fs::copy(&from, out.join(to))
            .unwrap_or_else(|e| panic!("copy {}: {e}", from.display()));
    };
    build(&target, &["--workspace"]);
    for (from, to) in [
        ("draw_circle.wasm", "draw-circle.wasm"),
        ("draw_smiley.wasm", "draw-smiley.wasm"),
        ("pick_and_place.wasm", "pick-and-place.wasm"),
        ("misbehave.wasm", "misbehave.wasm"),
        ("bad_describe.wasm", "bad-describe.wasm"),
        ("other_world.wasm", "other-world.wasm"),
        ("old_contract.wasm", "old-contract.wasm"),
    ] {
        copy(from, to);
    }
    // draw-circle again as version 0.2.0: only that crate is rebuilt (its
    // artifact with this feature set is kept apart by cargo's fingerprint).
    build(
        &target,
        &["-p", "draw-circle", "--features", "next-version"],
    );
    copy("draw_circle.wasm", "draw-circle-0.2.0.wasm");
}

fn build_python_plugin(out: &Path) {
    let venv = std::env::var_os("KB_PY_VENV").map_or_else(
        || {
            let home = std::env::var_os("HOME")
                .or_else(|| std::env::var_os("USERPROFILE"))
                .expect("HOME or USERPROFILE");
            PathBuf::from(home).join(".cache/kuka-bridge/venv")
        },
        PathBuf::from,
    );
    let bin = if cfg!(windows) {
        venv.join("Scripts")
    } else {
        venv.join("bin")
    };
    let exe = |name: &str| bin.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    if !exe("python").exists() {
        let python = if cfg!(windows) { "python" } else { "python3" };
        run(std::process::Command::new(python)
            .args(["-m", "venv"])
            .arg(&venv));
    }
    let has_cpy = std::process::Command::new(exe("componentize-py"))
        .arg("--version")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("0.25.1"));
    if !has_cpy {
        run(std::process::Command::new(exe("python")).args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "componentize-py==0.25.1",
        ]));
    }
    let app = examples_dir().join("python/draw-square");
    let work = tempfile::tempdir().expect("tempdir");
    // componentize-py imports app.py: build from a copy, so no bytecode
    // lands in the source tree.
    std::fs::copy(app.join("app.py"), work.path().join("app.py")).expect("copy app.py");
    run(std::process::Command::new(exe("componentize-py"))
        .current_dir(work.path())
        .arg("-d")
        .arg(examples_dir().join("../wit"))
        .args(["-w", "bridge-plugin", "componentize", "app", "-o"])
        .arg(out.join("py-square.wasm")));
}

/// What a test does when a tool it needs is not installed: it fails at
/// once, saying `what` is missing, the command that installs it
/// (`install`), and how to leave these tests out on purpose
/// (`cargo test -- --skip <skip>`: libtest then counts them as filtered
/// out, never as passed).
pub fn missing_tool(what: &str, install: &str, skip: &str) {
    panic!(
        "{what}. Install it with `{install}` and run the tests again (or leave these tests out on purpose: `cargo test --workspace -- --skip {skip}`)."
    );
}

/// The secret in the first-start admin token file of `data_dir`.
pub fn initial_admin_secret(data_dir: &Path) -> String {
    let text = std::fs::read_to_string(data_dir.join("initial-admin-token.txt"))
        .expect("the first start writes the admin token file");
    text.lines()
        .find(|l| l.starts_with("kb_"))
        .expect("a token line")
        .to_string()
}

/// A simulated controller in its own process (`kuka-bridge simulate`),
/// killed when dropped. `cli` is the CLI binary
/// (`env!("CARGO_BIN_EXE_kuka-bridge-cli")` in a test).
pub struct SimProcess(std::process::Child);

impl SimProcess {
    /// Starts a simulator on `dir` with a 10 ms heartbeat.
    pub fn spawn(cli: &str, dir: &Path, time_scale: f64) -> SimProcess {
        SimProcess::spawn_kind(cli, dir, time_scale, "native")
    }

    /// [`SimProcess::spawn`] of a simulated controller of `kind` (`native`
    /// or `krc`: the shipped KRL program in the KRC-like runtime).
    pub fn spawn_kind(cli: &str, dir: &Path, time_scale: f64, kind: &str) -> SimProcess {
        let child = std::process::Command::new(cli)
            .args(["simulate", "--kind", kind, "--channel-dir"])
            .arg(dir)
            .args([
                "--time-scale",
                &time_scale.to_string(),
                "--heartbeat-ms",
                "10",
            ])
            .env("KUKA_BRIDGE_LOG", "warn")
            .stdout(std::process::Stdio::null())
            .spawn()
            .expect("spawn simulator");
        SimProcess(child)
    }

    /// Its process id.
    pub fn id(&self) -> u32 {
        self.0.id()
    }

    /// Kills it (SIGKILL) and waits for it.
    pub fn kill(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

impl Drop for SimProcess {
    fn drop(&mut self) {
        self.kill();
    }
}

/// `kuka-bridge run` in its own process, as an operator starts it: the URL
/// from its console banner, what it prints on stdout (the console) and
/// stderr (the log) collected while it runs (so it never blocks on a full
/// pipe), and killed when dropped. `cli` is the CLI binary
/// (`env!("CARGO_BIN_EXE_kuka-bridge-cli")` in a test or bench).
pub struct CliService {
    child: std::process::Child,
    url: String,
    stdout: std::sync::Arc<std::sync::Mutex<String>>,
    stderr: std::sync::Arc<std::sync::Mutex<String>>,
    readers: Vec<std::thread::JoinHandle<()>>,
}

/// How long `kuka-bridge run` may take to print its banner (a debug build
/// on a loaded two-core machine).
const BANNER_TIMEOUT: Duration = Duration::from_secs(60);

impl CliService {
    /// Runs `cli run <args>` with `KUKA_BRIDGE_LOG=<log>` (a level such as
    /// `warn`) and waits for its banner, up to "Press Ctrl-C"; panics with
    /// everything it printed if it exits first or prints no banner within
    /// 60 s.
    pub fn spawn<I, S>(cli: &str, log: &str, args: I) -> CliService
    where
        I: IntoIterator<Item = S>,
        S: AsRef<std::ffi::OsStr>,
    {
        use std::process::{Command, Stdio};
        let mut child = Command::new(cli)
            .arg("run")
            .args(args)
            .env("KUKA_BRIDGE_LOG", log)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {cli} run: {e}"));
        let stdout = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
        let stderr = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
        let (banner, url) = std::sync::mpsc::channel();
        let readers = vec![
            collect_lines(
                child.stdout.take().expect("stdout is piped"),
                stdout.clone(),
                move |line, url: &mut Option<String>| {
                    if let Some(rest) = line.split("listening on ").nth(1) {
                        *url = Some(rest.trim().to_string());
                    }
                    if line.starts_with("Press Ctrl-C")
                        && let Some(u) = url.take()
                    {
                        let _ = banner.send(u);
                    }
                },
            ),
            collect_lines(
                child.stderr.take().expect("stderr is piped"),
                stderr.clone(),
                |_, _: &mut Option<String>| {},
            ),
        ];
        let mut service = CliService {
            child,
            url: String::new(),
            stdout,
            stderr,
            readers,
        };
        match url.recv_timeout(BANNER_TIMEOUT) {
            Ok(url) => service.url = url,
            Err(e) => {
                service.kill();
                panic!(
                    "`{cli} run` printed no banner with its URL ({e}); stdout:\n{}\nstderr:\n{}",
                    service.console(),
                    service.log()
                );
            }
        }
        service
    }

    /// The URL it listens on, from the banner (`http://127.0.0.1:PORT`).
    pub fn url(&self) -> &str {
        &self.url
    }

    /// Its process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// What it printed on stdout so far (the banner, at least).
    pub fn console(&self) -> String {
        self.stdout
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone()
    }

    /// What it printed on stderr (its console log) so far; all of it after
    /// [`CliService::wait_exit`].
    pub fn log(&self) -> String {
        self.stderr
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone()
    }

    /// Asks it to stop gracefully: SIGTERM on Unix (as systemd or `kill`
    /// would), a plain kill elsewhere. Does not wait: see
    /// [`CliService::wait_exit`].
    pub fn terminate(&mut self) {
        #[cfg(unix)]
        {
            let status = std::process::Command::new("kill")
                .args(["-TERM", &self.pid().to_string()])
                .status()
                .expect("run kill");
            assert!(status.success(), "kill -TERM {}: {status}", self.pid());
        }
        #[cfg(not(unix))]
        {
            let _ = self.child.kill();
        }
    }

    /// Waits (blocking this thread) until it has exited, at most `within`
    /// (then it panics naming `why`); its exit status. After it, [`Self::console`]
    /// and [`Self::log`] hold everything it printed.
    pub fn wait_exit(&mut self, within: Duration, why: &str) -> std::process::ExitStatus {
        let end = std::time::Instant::now() + within;
        let status = loop {
            if let Some(s) = self.child.try_wait().expect("wait for the service") {
                break s;
            }
            assert!(
                std::time::Instant::now() < end,
                "the service did not exit within {within:?} {why}; its log:\n{}",
                self.log()
            );
            std::thread::sleep(Duration::from_millis(20));
        };
        // Its pipes are closed now: the readers end with everything read.
        for reader in self.readers.drain(..) {
            let _ = reader.join();
        }
        status
    }

    /// Kills it (SIGKILL) and waits for it.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for CliService {
    fn drop(&mut self) {
        self.kill();
    }
}

/// A thread that appends every line of `from` to `into`, then calls
/// `on_line` with it and some state of its own.
fn collect_lines<S: Default + Send + 'static>(
    from: impl std::io::Read + Send + 'static,
    into: std::sync::Arc<std::sync::Mutex<String>>,
    mut on_line: impl FnMut(&str, &mut S) + Send + 'static,
) -> std::thread::JoinHandle<()> {
    std::thread::spawn(move || {
        use std::io::BufRead;
        let mut state = S::default();
        for line in std::io::BufReader::new(from).lines() {
            let Ok(line) = line else { break };
            {
                let mut text = into
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                text.push_str(&line);
                text.push('\n');
            }
            on_line(&line, &mut state);
        }
    })
}

/// Helpers of the benchmark binaries (`tests/benches`).
pub mod bench {
    use std::time::{Duration, Instant};

    /// A multi-thread runtime with two workers, as the service runs on a
    /// two-core controller PC.
    pub fn runtime() -> tokio::runtime::Runtime {
        tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()
            .expect("runtime")
    }

    /// Resident set size of process `pid` (or this one) in MiB (Linux:
    /// VmRSS from `/proc/<pid>/status`).
    pub fn rss_mib(pid: Option<u32>) -> Option<f64> {
        let file = pid.map_or_else(
            || "/proc/self/status".to_string(),
            |p| format!("/proc/{p}/status"),
        );
        let status = std::fs::read_to_string(file).ok()?;
        let kb: f64 = status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))?
            .trim()
            .trim_end_matches("kB")
            .trim()
            .parse()
            .ok()?;
        Some(kb / 1024.0)
    }

    /// The `p` quantile of sorted samples.
    pub fn percentile(sorted: &[Duration], p: f64) -> Duration {
        let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
        sorted[i.min(sorted.len() - 1)]
    }

    /// Prints p50/p90/p99/max of the samples on one line.
    pub fn report(name: &str, mut samples: Vec<Duration>) {
        samples.sort();
        let us = |d: Duration| d.as_secs_f64() * 1e6;
        println!(
            "{name:<34} n={:<6} p50={:>7.1} µs  p90={:>7.1} µs  p99={:>7.1} µs  max={:>8.1} µs",
            samples.len(),
            us(percentile(&samples, 0.50)),
            us(percentile(&samples, 0.90)),
            us(percentile(&samples, 0.99)),
            us(*samples.last().unwrap_or(&Duration::ZERO)),
        );
    }

    /// Sequential keep-alive requests over a plain TCP socket (a minimal
    /// HTTP/1.1 client, like curl's): separates the bridge's latency from the
    /// cost of a full-featured async client.
    pub fn raw_round_trips(addr: std::net::SocketAddr, request: &str, n: usize) -> Vec<Duration> {
        interleaved_round_trips(addr, &[request], n)
            .pop()
            .unwrap_or_default()
    }

    /// Like [`raw_round_trips`] for several requests at once, one connection
    /// each, sent in turn (request 1, 2, ..., 1, 2, ...): noise of the
    /// machine hits every kind alike, so `times[k][i] - times[0][i]` is a
    /// paired estimate of what kind `k` costs more than kind 0. Every answer
    /// must be 200.
    pub fn interleaved_round_trips(
        addr: std::net::SocketAddr,
        requests: &[&str],
        n: usize,
    ) -> Vec<Vec<Duration>> {
        let mut clients: Vec<RawClient> = requests
            .iter()
            .map(|r| RawClient::connect(addr, r))
            .collect();
        for _ in 0..200 {
            clients.iter_mut().for_each(RawClient::round_trip);
        }
        let mut times = vec![Vec::with_capacity(n); clients.len()];
        for _ in 0..n {
            for (client, times) in clients.iter_mut().zip(&mut times) {
                let start = Instant::now();
                client.round_trip();
                times.push(start.elapsed());
            }
        }
        times
    }

    /// Median of the paired differences `b[i] - a[i]`, in µs.
    pub fn paired_median_us(a: &[Duration], b: &[Duration]) -> f64 {
        let mut d: Vec<f64> = a
            .iter()
            .zip(b)
            .map(|(a, b)| (b.as_secs_f64() - a.as_secs_f64()) * 1e6)
            .collect();
        d.sort_by(f64::total_cmp);
        d.get(d.len() / 2).copied().unwrap_or(f64::NAN)
    }

    /// One keep-alive connection sending one fixed request.
    struct RawClient {
        sock: std::net::TcpStream,
        request: Vec<u8>,
        buf: Vec<u8>,
    }

    impl RawClient {
        fn connect(addr: std::net::SocketAddr, request: &str) -> RawClient {
            let sock = std::net::TcpStream::connect(addr).expect("connect");
            sock.set_nodelay(true).expect("nodelay");
            RawClient {
                sock,
                request: request.as_bytes().to_vec(),
                buf: vec![0u8; 64 * 1024],
            }
        }

        /// Sends the request and reads the whole answer (Content-Length).
        fn round_trip(&mut self) {
            use std::io::{Read, Write};
            self.sock.write_all(&self.request).expect("send");
            let mut have = 0;
            loop {
                let got = self.sock.read(&mut self.buf[have..]).expect("read");
                assert!(got > 0, "connection closed");
                have += got;
                let text = String::from_utf8_lossy(&self.buf[..have]);
                if let Some(end) = text.find("\r\n\r\n") {
                    let len: usize = text[..end]
                        .lines()
                        .find_map(|l| {
                            l.to_ascii_lowercase()
                                .strip_prefix("content-length:")
                                .map(|v| v.trim().parse().unwrap_or(0))
                        })
                        .unwrap_or(0);
                    if have >= end + 4 + len {
                        assert!(text.starts_with("HTTP/1.1 200"), "{text}");
                        return;
                    }
                }
            }
        }
    }
}

/// `GET path` over HTTPS to `addr`, trusting only the certificate in
/// `cert_pem` (for `localhost`); the raw HTTP/1.1 answer.
pub async fn https_get(addr: std::net::SocketAddr, cert_pem: &Path, path: &str) -> String {
    use rustls_pki_types::pem::PemObject;
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let mut roots = rustls::RootCertStore::empty();
    for cert in rustls_pki_types::CertificateDer::pem_file_iter(cert_pem).expect("pem") {
        roots.add(cert.expect("cert")).expect("root");
    }
    let provider = std::sync::Arc::new(rustls::crypto::ring::default_provider());
    let config = rustls::ClientConfig::builder_with_provider(provider)
        .with_safe_default_protocol_versions()
        .expect("versions")
        .with_root_certificates(roots)
        .with_no_client_auth();
    let connector = tokio_rustls::TlsConnector::from(std::sync::Arc::new(config));
    let tcp = tokio::net::TcpStream::connect(addr).await.expect("connect");
    let name = rustls_pki_types::ServerName::try_from("localhost").expect("name");
    let mut tls = connector.connect(name, tcp).await.expect("TLS handshake");
    let request = format!("GET {path} HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n");
    tls.write_all(request.as_bytes()).await.expect("write");
    let mut answer = Vec::new();
    let _ = tls.read_to_end(&mut answer).await;
    String::from_utf8_lossy(&answer).into_owned()
}

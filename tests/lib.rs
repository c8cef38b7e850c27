//! Support for the end-to-end tests: start the real service on a free
//! port with a real channel directory (embedded or separate simulated
//! controller), and talk to it over HTTP.

use std::path::{Path, PathBuf};
use std::time::Duration;

use kuka_bridge::app::Service;
use kuka_bridge::config::Config;
use serde_json::Value;

/// A service under test with its directories.
pub struct TestService {
    /// The running service.
    pub service: Service,
    /// HTTP client.
    pub http: reqwest::Client,
    /// Holds the data and channel directories.
    pub dirs: tempfile::TempDir,
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
        (opts.tweak)(&mut c);
        Self::start_with(c, dirs).await
    }

    /// Starts the service with a prepared config.
    pub async fn start_with(config: Config, dirs: tempfile::TempDir) -> TestService {
        let service = kuka_bridge::app::start(config)
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
        };
        t.wait_online().await;
        t
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
        if self.service.sim.is_none() {
            return;
        }
        self.wait_connection("online").await;
    }

    /// Waits until `/api/v1/state` reports this connection state (10 s max).
    pub async fn wait_connection(&self, want: &str) {
        for _ in 0..500 {
            let (_, s) = self.get("/api/v1/state").await;
            if s["connection"] == want {
                return;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        panic!("connection never became {want}");
    }

    /// GET → (status, JSON).
    pub async fn get(&self, path: &str) -> (u16, Value) {
        let r = self.http.get(self.url(path)).send().await.expect("request");
        decode(r).await
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

    /// PUT raw bytes (a plugin's .wasm).
    pub async fn put_bytes(&self, path: &str, body: Vec<u8>) -> (u16, Value) {
        let r = self
            .http
            .put(self.url(path))
            .header("content-type", "application/wasm")
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

/// Builds the example and fixture plugins (`plugins/examples/build.sh`)
/// once per test binary into `out` (pass `env!("CARGO_TARGET_TMPDIR")`);
/// `python` adds the componentize-py example (needs `python3` with `venv`
/// and PyPI). Returns the folder holding `<name>.wasm`.
pub fn example_plugins(target_tmp: &Path, python: bool) -> PathBuf {
    use std::sync::Mutex;
    static BUILT: Mutex<(bool, bool)> = Mutex::new((false, false));
    let out = target_tmp.join("plugin-examples");
    let mut built = BUILT.lock().unwrap_or_else(|p| p.into_inner());
    let need = if python { !built.1 } else { !built.0 };
    if need {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../plugins/examples/build.sh");
        let mut cmd = std::process::Command::new("bash");
        cmd.arg(&script).arg(&out);
        if python {
            cmd.arg("--python");
        }
        // The guests are their own workspace with their own target folder.
        cmd.env("CARGO_TARGET_DIR", out.join("target"));
        let status = cmd.status().expect("run plugins/examples/build.sh");
        assert!(
            status.success(),
            "plugins/examples/build.sh failed: {status}"
        );
        built.0 = true;
        built.1 |= python;
    }
    out
}

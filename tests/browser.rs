//! Headless Chromium for the dashboard tests, driven over WebDriver
//! (chromedriver on a free localhost port, fantoccini as the client).
//!
//! Each [`Browser`] runs its own chromedriver with a fresh Chromium profile
//! and ends both when dropped. Without Chromium or chromedriver,
//! [`Browser::start`] fails the test at once with the command that installs
//! them (see [`crate::missing_tool`]); a test is never skipped and counted
//! as passed (leave one out on purpose with `cargo test -- --skip NAME`). On Linux the browser is Debian's `/usr/bin/chromium`
//! (`sudo apt-get install chromium chromium-driver`); elsewhere chromedriver
//! (`chromedriver.exe` on Windows) must be on `PATH` and finds Chrome
//! itself.
//!
//! The helpers panic with a message naming what failed: a panic is a
//! failed test.

use std::io::{Read, Write};
use std::net::{Ipv4Addr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use fantoccini::{Client, ClientBuilder, Locator};
use serde_json::{Value, json};

/// How long chromedriver may take to answer `/status` with `ready: true`.
const DRIVER_READY_TIMEOUT: Duration = Duration::from_secs(20);

/// Poll interval of [`Browser::wait_js`].
const POLL: Duration = Duration::from_millis(100);

/// A headless Chromium session: its chromedriver process, the WebDriver
/// client and the browser profile folder.
pub struct Browser {
    client: Client,
    driver: Child,
    port: u16,
    session: String,
    closed: bool,
    /// Plain HTTP to chromedriver for what fantoccini does not wrap (logs).
    http: reqwest::Client,
    /// Console errors read so far (reading the browser log empties it).
    errors: Mutex<Vec<String>>,
    /// Holds the profile and chromedriver's log; removed last (after Chromium quit).
    _dir: tempfile::TempDir,
}

/// Where Chromium and chromedriver are, if installed.
struct Installed {
    driver: PathBuf,
    /// `None`: let chromedriver find Chrome (not on Linux).
    browser: Option<PathBuf>,
}

/// The variable that skips the browser tests on purpose.
/// The `--skip` filter for a browser test: its name.
const SKIP_VAR: &str = "<test name>";

/// How to install what the browser tests need, on this system.
fn install_command() -> &'static str {
    if cfg!(target_os = "linux") {
        "sudo apt-get install chromium chromium-driver"
    } else if cfg!(windows) {
        "winget install Google.Chrome, and chromedriver.exe of the same version (https://googlechromelabs.github.io/chrome-for-testing/) on PATH"
    } else {
        "brew install --cask google-chrome chromedriver"
    }
}

/// An executable named `name` on `PATH` (with `.exe` on Windows).
fn on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    let file = format!("{name}{}", std::env::consts::EXE_SUFFIX);
    std::env::split_paths(&path)
        .map(|dir| dir.join(&file))
        .find(|p| p.is_file())
}

/// Finds chromedriver and (on Linux) Chromium, or says what is missing.
fn find_installed() -> Result<Installed, String> {
    let debian_driver = Path::new("/usr/bin/chromedriver");
    let driver = if debian_driver.is_file() {
        debian_driver.to_path_buf()
    } else {
        on_path("chromedriver").ok_or("chromedriver is not installed (nor on PATH)")?
    };
    let browser = if cfg!(target_os = "linux") {
        let debian = Path::new("/usr/bin/chromium");
        let found = if debian.is_file() {
            Some(debian.to_path_buf())
        } else {
            ["chromium", "chromium-browser", "google-chrome"]
                .into_iter()
                .find_map(on_path)
        };
        Some(found.ok_or("chromium is not installed (/usr/bin/chromium, nor on PATH)")?)
    } else {
        None
    };
    Ok(Installed { driver, browser })
}

/// A free localhost TCP port (free when asked; chromedriver binds it next).
fn free_port() -> u16 {
    TcpListener::bind((Ipv4Addr::LOCALHOST, 0))
        .and_then(|l| l.local_addr())
        .expect("a free localhost port")
        .port()
}

/// The folder screenshots go to: `<CARGO_TARGET_DIR or target>/artifacts/dashboard`
/// (a relative `CARGO_TARGET_DIR` is taken from the workspace root).
pub fn artifacts_dir() -> PathBuf {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .filter(|v| !v.is_empty())
        .map_or_else(|| workspace.join("target"), |t| workspace.join(t));
    target.join("artifacts").join("dashboard")
}

impl Browser {
    /// Starts chromedriver on a free port and opens a headless Chromium
    /// session with a fresh profile.
    ///
    /// When Chromium or chromedriver is missing it panics with the command
    /// that installs them (it never returns `None` today; the `Option`
    /// keeps callers ready for a tool-less mode).
    pub async fn start() -> Option<Browser> {
        let installed = match find_installed() {
            Ok(i) => i,
            Err(why) => {
                crate::missing_tool(
                    &format!("the browser test cannot run: {why}"),
                    install_command(),
                    SKIP_VAR,
                );
                return None;
            }
        };
        let dir = tempfile::tempdir().expect("temporary folder for the browser profile");
        let http = reqwest::Client::builder()
            .timeout(Duration::from_secs(30))
            .build()
            .expect("HTTP client for chromedriver");
        // The port is free when asked but may be taken before chromedriver
        // binds it (other tests run in parallel): then try another.
        let mut attempts = 0;
        let (driver, port) = loop {
            attempts += 1;
            let port = free_port();
            let mut driver = spawn_driver(&installed.driver, port, dir.path());
            match wait_driver_ready(&http, &mut driver, port).await {
                Ok(()) => break (driver, port),
                Err(why) => {
                    let _ = driver.kill();
                    let _ = driver.wait();
                    let log = std::fs::read_to_string(dir.path().join("chromedriver.log"))
                        .unwrap_or_default();
                    assert!(
                        attempts < 3,
                        "chromedriver {} did not start: {why}\n{log}",
                        installed.driver.display()
                    );
                }
            }
        };
        let client = match connect(port, installed.browser.as_deref(), dir.path()).await {
            Ok(c) => c,
            Err(why) => {
                let mut driver = driver;
                let _ = driver.kill();
                let _ = driver.wait();
                let log = std::fs::read_to_string(dir.path().join("chromedriver.log"))
                    .unwrap_or_default();
                // Without a known browser binary (not Linux) the likely cause
                // is that Chrome is not installed.
                if installed.browser.is_none() {
                    crate::missing_tool(
                        &format!("chromedriver cannot start Chrome: {why}\n{log}"),
                        install_command(),
                        SKIP_VAR,
                    );
                    return None;
                }
                panic!("cannot open a Chromium session: {why}\n{log}");
            }
        };
        let session = client
            .session_id()
            .await
            .expect("session id")
            .expect("chromedriver returned a session id");
        Some(Browser {
            client,
            driver,
            port,
            session,
            closed: false,
            http,
            errors: Mutex::new(Vec::new()),
            _dir: dir,
        })
    }

    /// The WebDriver client, for anything the helpers do not cover.
    pub fn client(&self) -> &Client {
        &self.client
    }

    /// Navigates to `url` and waits for the page's load event.
    pub async fn goto(&self, url: &str) {
        self.client
            .goto(url)
            .await
            .unwrap_or_else(|e| panic!("cannot open {url}: {e}"));
    }

    /// The page's title.
    pub async fn title(&self) -> String {
        self.client.title().await.expect("page title")
    }

    /// Runs `js` as a function body in the page and returns what it
    /// `return`s (`null` without a `return`).
    pub async fn eval(&self, js: &str) -> Value {
        self.client
            .execute(js, Vec::new())
            .await
            .unwrap_or_else(|e| panic!("script failed: {e}\n{js}"))
    }

    /// Runs `js` as the body of an async function in the page and returns
    /// what it resolves to; a rejection comes back as `{"error": "..."}`.
    pub async fn eval_async(&self, js: &str) -> Value {
        let script = format!(
            "const done = arguments[arguments.length - 1];\n\
             (async () => {{ {js} }})().then(done, (e) => done({{ error: String(e) }}));"
        );
        self.client
            .execute_async(&script, Vec::new())
            .await
            .unwrap_or_else(|e| panic!("async script failed: {e}\n{js}"))
    }

    /// Sets the browser window's outer size in CSS pixels.
    pub async fn resize(&self, width: u32, height: u32) {
        self.client
            .set_window_size(width, height)
            .await
            .unwrap_or_else(|e| panic!("cannot resize the window: {e}"));
    }

    /// Polls the JavaScript expression `js_condition` every 100 ms until it
    /// is truthy (as JSON: not null, false, 0 or ""); on timeout panics with
    /// `what` and the last value (or script error).
    pub async fn wait_js(&self, js_condition: &str, timeout: Duration, what: &str) -> Value {
        let script = format!("return ({js_condition});");
        let start = Instant::now();
        loop {
            let last = match self.client.execute(&script, Vec::new()).await {
                Ok(v) if truthy(&v) => return v,
                Ok(v) => v.to_string(),
                // Scripts fail while a page is loading, or before the
                // objects they read exist: keep polling.
                Err(e) => format!("script error: {e}"),
            };
            if start.elapsed() >= timeout {
                panic!(
                    "timed out after {timeout:?} waiting for {what}: `{js_condition}` was {last}"
                );
            }
            tokio::time::sleep(POLL).await;
        }
    }

    /// Clicks the first element matching the CSS selector `css`.
    pub async fn click(&self, css: &str) {
        self.find(css)
            .await
            .click()
            .await
            .unwrap_or_else(|e| panic!("cannot click {css}: {e}"));
    }

    /// Clears the input matching `css` and types `text` into it.
    pub async fn set_value(&self, css: &str, text: &str) {
        let element = self.find(css).await;
        element
            .clear()
            .await
            .unwrap_or_else(|e| panic!("cannot clear {css}: {e}"));
        element
            .send_keys(text)
            .await
            .unwrap_or_else(|e| panic!("cannot type into {css}: {e}"));
    }

    /// The rendered text of the first element matching `css`.
    pub async fn text(&self, css: &str) -> String {
        self.find(css)
            .await
            .text()
            .await
            .unwrap_or_else(|e| panic!("cannot read the text of {css}: {e}"))
    }

    async fn find(&self, css: &str) -> fantoccini::elements::Element {
        self.client
            .find(Locator::Css(css))
            .await
            .unwrap_or_else(|e| panic!("no element {css}: {e}"))
    }

    /// Saves a PNG of the window as `<artifacts>/<name>.png` (see
    /// [`artifacts_dir`]), prints and returns its path.
    pub async fn screenshot(&self, name: &str) -> PathBuf {
        let png = self.client.screenshot().await.expect("screenshot");
        let dir = artifacts_dir();
        std::fs::create_dir_all(&dir)
            .unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
        let path = dir.join(format!("{name}.png"));
        std::fs::write(&path, png)
            .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        println!("screenshot: {}", path.display());
        path
    }

    /// Console errors and uncaught exceptions of the pages so far (the
    /// browser log's `SEVERE` entries, failed resource loads included,
    /// except the 404 of the `/favicon.ico` Chromium asks for on its own).
    pub async fn page_errors(&self) -> Vec<String> {
        let url = format!(
            "http://127.0.0.1:{}/session/{}/se/log",
            self.port, self.session
        );
        let answer: Value = self
            .http
            .post(url)
            .json(&json!({"type": "browser"}))
            .send()
            .await
            .expect("browser log request")
            .json()
            .await
            .expect("browser log JSON");
        let entries = answer["value"]
            .as_array()
            .unwrap_or_else(|| panic!("browser log: unexpected answer {answer}"));
        let mut errors = self.errors.lock().unwrap_or_else(|p| p.into_inner());
        errors.extend(
            entries
                .iter()
                .filter(|e| e["level"] == "SEVERE")
                .map(|e| e["message"].as_str().unwrap_or_default().to_string())
                .filter(|m| !m.contains("/favicon.ico - Failed to load resource")),
        );
        errors.clone()
    }

    /// Ends the session (closes Chromium); chromedriver stops on drop.
    pub async fn close(mut self) {
        self.closed = true;
        if let Err(e) = self.client.clone().close().await {
            eprintln!("closing the browser session: {e}");
        }
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        if !self.closed {
            // Best effort, synchronous (no runtime needed): end the session
            // so that chromedriver quits Chromium, then stop chromedriver.
            delete_session(self.port, &self.session);
        }
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

/// JSON truthiness as JavaScript's for the values a script can return.
fn truthy(v: &Value) -> bool {
    match v {
        Value::Null => false,
        Value::Bool(b) => *b,
        Value::Number(n) => n.as_f64().is_some_and(|f| f != 0.0),
        Value::String(s) => !s.is_empty(),
        Value::Array(_) | Value::Object(_) => true,
    }
}

/// Starts chromedriver on `port`, its output in `<dir>/chromedriver.log`.
fn spawn_driver(driver: &Path, port: u16, dir: &Path) -> Child {
    let log = std::fs::File::create(dir.join("chromedriver.log")).expect("chromedriver log file");
    let log2 = log.try_clone().expect("chromedriver log file handle");
    Command::new(driver)
        .arg(format!("--port={port}"))
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(log2)
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", driver.display()))
}

/// Polls chromedriver's `/status` until it says ready.
async fn wait_driver_ready(
    http: &reqwest::Client,
    driver: &mut Child,
    port: u16,
) -> Result<(), String> {
    let url = format!("http://127.0.0.1:{port}/status");
    let start = Instant::now();
    let mut last = String::from("no answer");
    while start.elapsed() < DRIVER_READY_TIMEOUT {
        if let Ok(Some(status)) = driver.try_wait() {
            return Err(format!("it exited ({status})"));
        }
        match http.get(&url).send().await {
            Ok(r) => match r.json::<Value>().await {
                Ok(v) if v["value"]["ready"] == true => return Ok(()),
                Ok(v) => last = v.to_string(),
                Err(e) => last = e.to_string(),
            },
            Err(e) => last = e.to_string(),
        }
        tokio::time::sleep(POLL).await;
    }
    Err(format!(
        "not ready after {DRIVER_READY_TIMEOUT:?} on port {port}: {last}"
    ))
}

/// Opens the WebDriver session: headless, software GL, one profile.
async fn connect(
    port: u16,
    browser: Option<&Path>,
    dir: &Path,
) -> Result<Client, fantoccini::error::NewSessionError> {
    let profile = dir.join("profile");
    let mut options = json!({
        "args": [
            "--headless=new",
            "--no-sandbox",
            "--disable-dev-shm-usage",
            "--enable-unsafe-swiftshader",
            "--use-angle=swiftshader",
            "--window-size=1400,1000",
            format!("--user-data-dir={}", profile.display()),
        ],
    });
    if let Some(binary) = browser {
        options["binary"] = json!(binary);
    }
    let mut caps = fantoccini::wd::Capabilities::new();
    caps.insert("browserName".into(), json!("chrome"));
    caps.insert("goog:chromeOptions".into(), options);
    // Console messages for page_errors().
    caps.insert("goog:loggingPrefs".into(), json!({"browser": "ALL"}));
    let connector = hyper_util::client::legacy::connect::HttpConnector::new();
    ClientBuilder::new(connector)
        .capabilities(caps)
        .connect(&format!("http://127.0.0.1:{port}"))
        .await
}

/// `DELETE /session/<id>` with a blocking socket (for `Drop`); errors ignored.
fn delete_session(port: u16, session: &str) {
    let Ok(mut sock) = TcpStream::connect((Ipv4Addr::LOCALHOST, port)) else {
        return;
    };
    let _ = sock.set_read_timeout(Some(Duration::from_secs(10)));
    let _ = sock.set_write_timeout(Some(Duration::from_secs(10)));
    let request = format!(
        "DELETE /session/{session} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
    );
    if sock.write_all(request.as_bytes()).is_ok() {
        // Chromedriver answers once Chromium has quit.
        let mut answer = Vec::new();
        let _ = sock.read_to_end(&mut answer);
    }
}

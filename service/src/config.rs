//! The service configuration: one TOML file (every key optional), merged
//! with command-line overrides into a validated [`Config`]. Code past the
//! binary's edge only sees this type.

use std::net::SocketAddr;
use std::path::{Path, PathBuf};

pub use kuka_engine::settings::{
    ChannelConfig, EngineSettings, KeepOut, MotionConfig, WorkspaceBox, Zones,
};
use kuka_engine::settings::{Problem, check_maximums, check_minimums};
use kuka_kinematics::RobotModel;
use serde::{Deserialize, Serialize};

/// Configuration errors name the file, the key and what is wrong.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file cannot be read.
    #[error("cannot read config file {path}")]
    Read {
        /// The file.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The file is not valid TOML or has unknown keys / wrong types.
    #[error("config file {path}: {message}")]
    Parse {
        /// The file.
        path: String,
        /// The parser's message (names the key and line).
        message: String,
    },
    /// More than one value is wrong: each of them.
    #[error("{}", several(.0))]
    Several(Vec<ConfigError>),
    /// A value is out of range.
    #[error("config {source_name}: key `{key}`: {message}")]
    Invalid {
        /// The file (or "command line").
        source_name: String,
        /// Dotted key.
        key: String,
        /// What is wrong.
        message: String,
    },
}

/// "N problems:" and one line per problem.
fn several(errors: &[ConfigError]) -> String {
    let mut out = format!("{} problems in the configuration:", errors.len());
    for e in errors {
        out.push_str("\n  - ");
        out.push_str(&e.to_string());
    }
    out
}

/// Everything the service needs to run.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// HTTP server.
    pub server: ServerConfig,
    /// The file channel to the controller.
    pub channel: ChannelConfig,
    /// Robot model for reachability and software-limit checks.
    pub robot: RobotConfig,
    /// Default speeds and caps for motions.
    pub motion: MotionConfig,
    /// Optional Cartesian box the whole TCP path must stay in (base frame, mm).
    pub workspace: Option<WorkspaceBox>,
    /// A floor plane and keep-out boxes the TCP path must keep clear of.
    pub zones: Zones,
    /// The embedded simulated controller (`run --simulate`).
    pub simulator: SimulatorConfig,
    /// Uploaded KRL programs.
    pub programs: ProgramsConfig,
    /// WASM plugins.
    pub plugins: PluginsConfig,
    /// Log files.
    pub log: LogConfig,
    /// Tokens, roles, control lease.
    pub auth: AuthConfig,
    /// Named digital inputs and outputs; the outputs clients may write.
    pub io: kuka_engine::io::IoConfig,
    /// KRL variables through KUKAVARPROXY (docs/VARIABLES.md).
    pub variables: VariablesConfig,
    /// Where the service keeps its own state (command id counter).
    pub data_dir: PathBuf,
    /// Where the config was loaded from (for messages); not a key.
    #[serde(skip)]
    pub source_name: String,
}

/// HTTP server settings.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ServerConfig {
    /// Address and port to listen on. Default 127.0.0.1:8080 (loopback
    /// only). A host name (`localhost:8080`, `hmi-pc:8080`) is resolved
    /// once, at start (see [`resolve_listen`]).
    #[serde(deserialize_with = "listen_address")]
    pub listen: SocketAddr,
    /// How long a synchronous request may wait for its job by default (ms).
    pub request_timeout_ms: u64,
    /// No request may take longer than this (ms); event streams excepted.
    /// Above the longest job a request can wait for (a program run).
    pub max_request_ms: u64,
    /// Requests served at once; more get 503 `overloaded` with `Retry-After`.
    pub max_concurrent_requests: usize,
    /// Largest request body (bytes); smaller limits apply per endpoint.
    pub max_body_bytes: usize,
    /// Largest request head (request line and headers), bytes.
    pub max_header_bytes: usize,
    /// Open connections at most (more are closed at once).
    pub max_connections: usize,
    /// Open connections per client address at most.
    pub max_connections_per_client: usize,
    /// A client must send its request head within this time (ms); an idle
    /// keep-alive connection is closed after it too. Also the TLS
    /// handshake's limit.
    pub header_timeout_ms: u64,
    /// Origins allowed to call the API from a browser page (CORS), e.g.
    /// `["http://10.0.3.5:3000"]`; empty (the default) sends no CORS headers.
    pub cors_origins: Vec<String>,
    /// Serve HTTPS with this certificate and key (PEM files).
    pub tls: Option<TlsConfig>,
    /// At shutdown, how long the running job may go on while stop, cancel
    /// and reads are still served (ms); after it the robot is stopped.
    pub shutdown_grace_ms: u64,
}

/// HTTPS (rustls): a certificate chain and its private key, both PEM.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TlsConfig {
    /// Certificate chain (PEM), server certificate first.
    pub cert: PathBuf,
    /// Private key (PEM: PKCS#8, PKCS#1 or SEC1).
    pub key: PathBuf,
}

/// Access control (docs/SECURITY.md).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AuthConfig {
    /// Require tokens on a loopback address too (`--require-auth`). Beyond
    /// loopback they are always required.
    pub require_on_loopback: bool,
    /// A control lease lapses after this long without use (ms).
    pub lease_ms: u64,
    /// Failed token attempts allowed per client address and window.
    pub max_failures: u32,
    /// The window of `max_failures` (ms).
    pub failure_window_ms: u64,
    /// Accept `?access_token=` on the thesis endpoints and the event stream
    /// (for clients that cannot set headers; weaker, see docs/SECURITY.md).
    pub query_token: bool,
}

impl Default for AuthConfig {
    fn default() -> Self {
        AuthConfig {
            require_on_loopback: false,
            lease_ms: 30_000,
            max_failures: 10,
            failure_window_ms: 60_000,
            query_token: true,
        }
    }
}

/// Which robot the checks use.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RobotConfig {
    /// Built-in model id (`kr3_r540`, `kr6_r700_sixx`, `kr6_r900_sixx`,
    /// `kr10_r1100_sixx`) or `none` to skip kinematic checks.
    pub model: String,
    /// A custom model (OPW parameters, limits, speeds, home); overrides `model`.
    pub custom: Option<RobotModel>,
    /// The axis accelerations at 100 % (deg/s², A1..A6) of the built-in
    /// model, when the site knows its machine data (default: 300 on every
    /// axis, an assumption). A custom model sets its own.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_acc_deg_s2: Option<[f64; 6]>,
}

/// KRL variables, read and written through a KUKAVARPROXY server (TCP
/// 7000 on the controller's Windows side).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VariablesConfig {
    /// `host:port` of the KUKAVARPROXY server; empty: none (with
    /// `--simulate` the simulated controller's own stand-in).
    pub proxy: String,
    /// Longest wait for a connection or an answer (ms).
    pub timeout_ms: u64,
    /// The variables clients may write (names as `check_name` admits
    /// them, compared without regard to case); everything else is
    /// read-only.
    pub writable: Vec<String>,
}

impl Default for VariablesConfig {
    fn default() -> Self {
        VariablesConfig {
            proxy: String::new(),
            timeout_ms: 2000,
            writable: Vec::new(),
        }
    }
}

impl VariablesConfig {
    /// Every problem of this section.
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        check_minimums(&mut bad, &[("timeout_ms", self.timeout_ms, 100)]);
        check_maximums(&mut bad, &[("timeout_ms", self.timeout_ms, 60_000)]);
        if !self.proxy.is_empty()
            && self
                .proxy
                .rsplit_once(':')
                .is_none_or(|(h, p)| h.is_empty() || p.parse::<u16>().is_err())
        {
            bad.push(Problem::new(
                "proxy",
                format!("{:?} is not host:port (e.g. 192.168.1.10:7000)", self.proxy),
            ));
        }
        for n in &self.writable {
            if let Err(why) = kuka_kvp::check_name(n) {
                bad.push(Problem::new("writable", why));
            }
        }
        bad
    }
}

/// The embedded simulator.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimulatorConfig {
    /// Run the simulated controller inside the service.
    pub enabled: bool,
    /// Which simulated controller: `native` (a Rust model of the KRL
    /// program's behaviour; instant answers) or `krc` (the KRC-like runtime
    /// running the shipped KRL program itself, with the Submit cycle).
    pub kind: SimulatorKind,
    /// `krc` only: the interpreter cycle in ms (a KRC: 12).
    pub cycle_ms: u64,
    /// `krc` only: statements the Submit interpreter runs per cycle (an
    /// assumption: KUKA publishes no figure; docs/CONTROLLER.md). At 500
    /// the shipped program misses its heartbeat for seconds while it reads
    /// a batch of 50 or more motions (docs/BENCHMARKS.md §8), so the
    /// default is 5,000.
    pub submit_budget: u64,
    /// `krc` only: what the simulated KSS answers in `RET1` when a file
    /// function succeeds: `DATA_OK` (KUKA's text and working code) or
    /// `CMD_OK` (the other value KUKA's CWRITE text allows). The shipped
    /// program accepts both; docs/CONTROLLER.md A1.
    pub file_success: FileSuccess,
    /// `krc` only: the path form the simulated KSS accepts in
    /// `RUN <path><module>()`: `/R1/` as every public `sps.sub` writes it,
    /// or e.g. `/R1/Program/kbridge/`. The runtime sets the program's
    /// `kb_run_pfx` to the same value, as a site would in `kb_main.dat`
    /// (docs/CONTROLLER.md A2).
    pub run_prefix: String,
    /// `krc` only: what the simulated KSS's `SREAD`/`SWRITE` offset counts:
    /// `consumed` (the characters already read or written, as public
    /// programs use it) or `position` (the 1-based position of the next
    /// character). The shipped program tests which at start and parses
    /// by characters when SREAD/SWRITE do not behave as it expects
    /// (docs/CONTROLLER.md B20).
    pub text_offset: TextOffset,
    /// Simulated seconds per wall second (1 = real time, 0 = instant).
    pub time_scale: f64,
    /// Heartbeat period (ms).
    pub heartbeat_ms: u64,
    /// The simulated plant: inputs that follow outputs, e.g. a
    /// part-present sensor that reports a part once the gripper has
    /// closed (docs/IO.md).
    pub links: Vec<crate::sim_plant::InputLink>,
}

/// The value a simulated KSS answers for a file function that succeeded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum FileSuccess {
    /// `#DATA_OK`.
    #[default]
    #[serde(rename = "DATA_OK")]
    DataOk,
    /// `#CMD_OK`.
    #[serde(rename = "CMD_OK")]
    CmdOk,
}

impl FileSuccess {
    /// The KRL enum value without `#`.
    pub fn krl(self) -> &'static str {
        match self {
            FileSuccess::DataOk => "DATA_OK",
            FileSuccess::CmdOk => "CMD_OK",
        }
    }
}

/// What a simulated KSS's `SREAD`/`SWRITE` offset counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TextOffset {
    /// The characters already read or written (0-based).
    #[default]
    Consumed,
    /// The 1-based position of the next character.
    Position,
}

impl TextOffset {
    /// The runtime's `text_offset_base`.
    pub fn base(self) -> i64 {
        match self {
            TextOffset::Consumed => 0,
            TextOffset::Position => 1,
        }
    }
}

/// The simulated controller `run --simulate` embeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum SimulatorKind {
    /// The native simulator (`krl/sim`): answers as soon as a command file
    /// appears; the default.
    #[default]
    Native,
    /// The KRC-like runtime (`krl/krc`): the shipped KRL program on a
    /// simulated controller clock.
    Krc,
}

/// Log files: rolled daily, old ones deleted.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LogConfig {
    /// Write log files (in `dir`). Console mode also prints to the console.
    pub file: bool,
    /// Folder of the log files (default `<data_dir>/logs`).
    pub dir: Option<PathBuf>,
    /// Days of log files to keep (one file per day).
    pub retention_days: usize,
    /// Level filter (`error`, `warn`, `info`, `debug`, `trace`, or a
    /// tracing filter such as `info,kuka_bridge::engine=debug`); the
    /// environment variable `KUKA_BRIDGE_LOG` overrides it.
    pub level: String,
}

impl Default for LogConfig {
    fn default() -> Self {
        LogConfig {
            file: true,
            dir: None,
            retention_days: 14,
            level: "info".into(),
        }
    }
}

/// Uploaded KRL programs (`POST /api/v1/programs`).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ProgramsConfig {
    /// The controller's program folder the service writes `kbu<n>.src` into
    /// before a RUN command. On a KRC: `C:\KRC\ROBOTER\KRC\R1\Program\kbridge`
    /// (the default on Windows). With `--simulate` the default is
    /// `<channel dir>/programs`. Without it (and off Windows) programs can be
    /// uploaded and checked but not run.
    pub controller_dir: Option<PathBuf>,
    /// Largest accepted .src or .dat file in bytes.
    pub max_bytes: usize,
    /// How many generated `kbu<n>` modules to keep in the program folder.
    pub keep_modules: usize,
    /// How long a program run may take by default (ms); a run request's
    /// `timeout_ms` overrides it. Programs run far longer than single
    /// commands (`channel.command_timeout_ms`).
    pub run_timeout_ms: u64,
}

/// WASM plugins (`PUT /api/v1/plugins/{name}`, or a .wasm dropped into `dir`).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PluginsConfig {
    /// Load and serve plugins at all.
    pub enabled: bool,
    /// The plugins folder, watched for `<name>.wasm` files (default
    /// `<data_dir>/plugins`; compiled code is cached in its `.cache`).
    pub dir: Option<PathBuf>,
    /// How often the folder is re-scanned besides change events (ms).
    pub poll_interval_ms: u64,
    /// Largest accepted .wasm file in bytes (a Python plugin is ~19 MB).
    pub max_wasm_bytes: usize,
    /// Largest linear memory of a plugin, in MiB.
    pub memory_mib: usize,
    /// Guest CPU time per request (ms); time spent in motions is not counted.
    pub cpu_time_ms: u64,
    /// Wall time per request, motions included (ms).
    pub request_timeout_ms: u64,
    /// Most motions one plugin request may run.
    pub max_motions: usize,
    /// Largest request body passed to a plugin, in bytes.
    pub max_body_bytes: usize,
    /// Limits of single plugins, replacing the ones above for them:
    /// `[plugins.limits.draw-smiley]` with any of `memory_mib` (at most
    /// `plugins.memory_mib`), `cpu_time_ms`, `request_timeout_ms`,
    /// `max_motions`.
    pub limits: std::collections::BTreeMap<String, PluginLimitsConfig>,
}

/// Limits of one plugin; omitted ones are the global ones.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PluginLimitsConfig {
    /// Largest linear memory, MiB.
    pub memory_mib: Option<usize>,
    /// Guest time per request, ms.
    pub cpu_time_ms: Option<u64>,
    /// Wall time per request, motions included, ms.
    pub request_timeout_ms: Option<u64>,
    /// Motions per request.
    pub max_motions: Option<usize>,
}

impl Default for PluginsConfig {
    fn default() -> Self {
        PluginsConfig {
            enabled: true,
            dir: None,
            poll_interval_ms: 2000,
            max_wasm_bytes: 64 << 20,
            memory_mib: 64,
            cpu_time_ms: 500,
            request_timeout_ms: 600_000,
            max_motions: 1000,
            max_body_bytes: 1 << 20,
            limits: Default::default(),
        }
    }
}

impl Default for ProgramsConfig {
    fn default() -> Self {
        ProgramsConfig {
            controller_dir: None,
            max_bytes: 256 * 1024,
            keep_modules: 8,
            run_timeout_ms: 3_600_000,
        }
    }
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig {
            listen: SocketAddr::from(([127, 0, 0, 1], 8080)),
            request_timeout_ms: 120_000,
            max_request_ms: 4 * 3_600_000,
            max_concurrent_requests: 512,
            max_body_bytes: 80 << 20,
            max_header_bytes: 32 * 1024,
            header_timeout_ms: 30_000,
            max_connections: 1024,
            max_connections_per_client: 256,
            cors_origins: Vec::new(),
            tls: None,
            shutdown_grace_ms: 30_000,
        }
    }
}

impl Default for RobotConfig {
    fn default() -> Self {
        RobotConfig {
            model: "kr3_r540".into(),
            custom: None,
            max_acc_deg_s2: None,
        }
    }
}

impl Default for SimulatorConfig {
    fn default() -> Self {
        SimulatorConfig {
            enabled: false,
            kind: SimulatorKind::Native,
            cycle_ms: 12,
            submit_budget: 5_000,
            file_success: FileSuccess::DataOk,
            run_prefix: "/R1/".into(),
            text_offset: TextOffset::Consumed,
            time_scale: 1.0,
            heartbeat_ms: 50,
            links: Vec::new(),
        }
    }
}

impl Default for Config {
    fn default() -> Self {
        Config {
            server: ServerConfig::default(),
            channel: ChannelConfig::default(),
            robot: RobotConfig::default(),
            motion: MotionConfig::default(),
            workspace: None,
            zones: Zones::default(),
            simulator: SimulatorConfig::default(),
            programs: ProgramsConfig::default(),
            plugins: PluginsConfig::default(),
            log: LogConfig::default(),
            auth: AuthConfig::default(),
            io: kuka_engine::io::IoConfig::default(),
            variables: VariablesConfig::default(),
            data_dir: default_data_dir(),
            source_name: "defaults".into(),
        }
    }
}

/// The address to listen on for `HOST:PORT`: an IP address as it is, a
/// host name resolved with the system's resolver (`localhost:8080`). Of
/// several addresses the first is taken, except that `localhost` always
/// listens on loopback (127.0.0.1 before ::1), whatever the resolver lists
/// first. The error is a sentence for `--listen` and `server.listen`.
pub fn resolve_listen(text: &str) -> Result<SocketAddr, String> {
    use std::net::ToSocketAddrs;
    let text = text.trim();
    if let Ok(addr) = text.parse::<SocketAddr>() {
        return Ok(addr);
    }
    let Some((host, port)) = text.rsplit_once(':') else {
        return Err(format!(
            "{text:?} is not HOST:PORT, e.g. 127.0.0.1:8080, 0.0.0.0:8080 or localhost:8080"
        ));
    };
    if host.is_empty() || port.parse::<u16>().is_err() {
        return Err(format!(
            "{text:?} is not HOST:PORT with a port 0..65535, e.g. 127.0.0.1:8080 or localhost:8080"
        ));
    }
    let found: Vec<SocketAddr> = text
        .to_socket_addrs()
        .map_err(|e| format!("cannot resolve the host name {host:?}: {e}"))?
        .collect();
    pick_listen_address(host, &found).ok_or_else(|| {
        format!("the host name {host:?} resolves to no address; give an IP address such as 127.0.0.1:{port}")
    })
}

/// The address of `host` to listen on among those it resolved to (see
/// [`resolve_listen`]); `None` when there are none (or, for `localhost`,
/// no loopback one).
fn pick_listen_address(host: &str, found: &[SocketAddr]) -> Option<SocketAddr> {
    if host.eq_ignore_ascii_case("localhost") {
        return found
            .iter()
            .find(|a| a.is_ipv4() && a.ip().is_loopback())
            .or_else(|| found.iter().find(|a| a.ip().is_loopback()))
            .copied();
    }
    found.first().copied()
}

/// `server.listen`: an address, or a host name resolved at load time.
fn listen_address<'de, D: serde::Deserializer<'de>>(d: D) -> Result<SocketAddr, D::Error> {
    let text = String::deserialize(d)?;
    resolve_listen(&text).map_err(serde::de::Error::custom)
}

/// `%ProgramData%\kuka-bridge` on Windows, `$XDG_STATE_HOME/kuka-bridge`
/// or `~/.local/state/kuka-bridge` elsewhere.
pub fn default_data_dir() -> PathBuf {
    if cfg!(windows) {
        let base = std::env::var_os("ProgramData")
            .map_or_else(|| PathBuf::from(r"C:\ProgramData"), PathBuf::from);
        return base.join("kuka-bridge");
    }
    if let Some(x) = std::env::var_os("XDG_STATE_HOME").filter(|v| !v.is_empty()) {
        return PathBuf::from(x).join("kuka-bridge");
    }
    if let Some(h) = std::env::var_os("HOME").filter(|v| !v.is_empty()) {
        return PathBuf::from(h).join(".local/state/kuka-bridge");
    }
    PathBuf::from("kuka-bridge-data")
}

impl Config {
    /// The engine's settings from this configuration.
    pub fn engine_settings(&self) -> EngineSettings {
        EngineSettings {
            channel_dir: self.channel_dir(),
            channel: self.channel.timing(self.simulator.enabled),
            motion: self.motion.clone(),
            data_dir: self.data_dir.clone(),
            program_dir: self.program_dir(),
            keep_modules: self.programs.keep_modules,
            io: self.io.clone(),
        }
    }

    /// Loads a TOML file; every key is optional.
    pub fn load(path: &Path) -> Result<Config, ConfigError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
            path: name.clone(),
            source,
        })?;
        let mut config: Config = toml::from_str(&text).map_err(|e| ConfigError::Parse {
            path: name.clone(),
            message: e.to_string(),
        })?;
        config.source_name = name;
        Ok(config)
    }

    /// The channel directory in effect.
    pub fn channel_dir(&self) -> PathBuf {
        match &self.channel.dir {
            Some(d) => d.clone(),
            None => self.data_dir.join(if self.simulator.enabled {
                "sim-channel"
            } else {
                "channel"
            }),
        }
    }

    /// True when requests need a token: listening beyond loopback, or
    /// asked for.
    pub fn auth_required(&self) -> bool {
        self.auth.require_on_loopback || !self.server.listen.ip().is_loopback()
    }

    /// The folder of the log files.
    pub fn log_dir(&self) -> PathBuf {
        self.log
            .dir
            .clone()
            .unwrap_or_else(|| self.data_dir.join("logs"))
    }

    /// The audit trail's folder (`<log dir>/audit`, private).
    pub fn audit_dir(&self) -> PathBuf {
        self.log_dir().join("audit")
    }

    /// The plugins folder.
    pub fn plugin_dir(&self) -> PathBuf {
        self.plugins
            .dir
            .clone()
            .unwrap_or_else(|| self.data_dir.join("plugins"))
    }

    /// Where RUN modules are written, if anywhere (see [`ProgramsConfig`]).
    pub fn program_dir(&self) -> Option<PathBuf> {
        if let Some(d) = &self.programs.controller_dir {
            return Some(d.clone());
        }
        if self.simulator.enabled {
            return Some(self.channel_dir().join("programs"));
        }
        if cfg!(windows) {
            return Some(PathBuf::from(r"C:\KRC\ROBOTER\KRC\R1\Program\kbridge"));
        }
        None
    }

    /// The robot model in effect (None: no kinematic checks).
    pub fn robot_model(&self) -> Result<Option<RobotModel>, ConfigError> {
        self.robot
            .model()
            .map_err(|p| self.invalid(format!("robot.{}", p.key), p.message))
    }

    fn invalid(&self, key: impl Into<String>, message: String) -> ConfigError {
        ConfigError::Invalid {
            source_name: self.source_name.clone(),
            key: key.into(),
            message,
        }
    }

    /// Checks every value: each section reports its own problems, then the
    /// checks that span sections run. Every bad key is reported, not only
    /// the first.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let mut bad = Vec::new();
        let workspace = self.workspace.as_ref().map(WorkspaceBox::problems);
        let sections = [
            ("server", self.server.problems()),
            ("channel", self.channel.problems()),
            ("robot", self.robot.problems()),
            ("motion", self.motion.problems()),
            ("workspace", workspace.unwrap_or_default()),
            ("zones", self.zones.problems()),
            ("simulator", self.simulator.problems()),
            ("programs", self.programs.problems()),
            ("plugins", self.plugins.problems()),
            ("auth", self.auth.problems()),
            ("log", self.log.problems()),
            ("variables", self.variables.problems()),
        ];
        for (section, problems) in sections {
            for p in problems {
                bad.push(self.invalid(format!("{section}.{}", p.key), p.message));
            }
        }
        if !cfg!(windows) {
            for (key, path) in [
                ("data_dir", Some(&self.data_dir)),
                ("channel.dir", self.channel.dir.as_ref()),
                ("log.dir", self.log.dir.as_ref()),
                ("plugins.dir", self.plugins.dir.as_ref()),
                (
                    "programs.controller_dir",
                    self.programs.controller_dir.as_ref(),
                ),
            ] {
                if let Some(p) = path.filter(|p| is_windows_path(p)) {
                    bad.push(self.invalid(
                        key,
                        format!(
                            "{} is a Windows path; on this system it would become a folder of that name (give a path such as /var/lib/kuka-bridge)",
                            p.display()
                        ),
                    ));
                }
            }
        }
        if let Err(why) = self.io.validate() {
            bad.push(self.invalid("io", why));
        }
        if self.simulator.enabled
            && self.channel.offline_after_ms <= self.simulator.heartbeat_ms * 2
        {
            bad.push(self.invalid(
                "channel.offline_after_ms",
                format!(
                    "must be more than twice simulator.heartbeat_ms ({})",
                    self.simulator.heartbeat_ms
                ),
            ));
        }
        match bad.len() {
            0 => Ok(()),
            1 => Err(bad.remove(0)),
            _ => Err(ConfigError::Several(bad)),
        }
    }
}

/// `C:\...`, `C:/...` or `\\server\share`: a path only Windows reads as such.
fn is_windows_path(p: &Path) -> bool {
    let s = p.to_string_lossy();
    let b = s.as_bytes();
    (b.len() >= 3 && b[0].is_ascii_alphabetic() && b[1] == b':' && (b[2] == b'\\' || b[2] == b'/'))
        || s.starts_with(r"\\")
}

impl ServerConfig {
    /// Every problem of this section (keys without the `server.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        check_minimums(
            &mut bad,
            &[
                ("request_timeout_ms", self.request_timeout_ms, 100),
                ("max_request_ms", self.max_request_ms, 1000),
                (
                    "max_concurrent_requests",
                    self.max_concurrent_requests as u64,
                    1,
                ),
                ("max_body_bytes", self.max_body_bytes as u64, 64 * 1024),
                ("max_header_bytes", self.max_header_bytes as u64, 8192),
                ("header_timeout_ms", self.header_timeout_ms, 100),
                ("max_connections", self.max_connections as u64, 1),
                (
                    "max_connections_per_client",
                    self.max_connections_per_client as u64,
                    1,
                ),
            ],
        );
        check_maximums(
            &mut bad,
            &[
                (
                    "max_concurrent_requests",
                    self.max_concurrent_requests as u64,
                    100_000,
                ),
                ("max_connections", self.max_connections as u64, 100_000),
                ("header_timeout_ms", self.header_timeout_ms, 600_000),
            ],
        );
        if self.max_request_ms <= self.request_timeout_ms {
            bad.push(Problem::new(
                "max_request_ms",
                format!(
                    "must be more than server.request_timeout_ms ({})",
                    self.request_timeout_ms
                ),
            ));
        }
        for o in &self.cors_origins {
            let ok = (o.starts_with("http://") || o.starts_with("https://"))
                && axum::http::HeaderValue::from_str(o).is_ok()
                && !o.ends_with('/');
            if !ok {
                bad.push(Problem::new(
                    "cors_origins",
                    format!("{o:?} is not an origin such as \"https://host:port\" (no path, no trailing slash)"),
                ));
            }
        }
        if let Some(t) = &self.tls {
            for (key, p) in [("tls.cert", &t.cert), ("tls.key", &t.key)] {
                if !p.is_file() {
                    bad.push(Problem::new(key, format!("{} is not a file", p.display())));
                }
            }
        }
        bad
    }
}

impl AuthConfig {
    /// Every problem of this section (keys without the `auth.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        check_minimums(
            &mut bad,
            &[
                ("lease_ms", self.lease_ms, 1000),
                ("max_failures", u64::from(self.max_failures), 1),
                ("failure_window_ms", self.failure_window_ms, 1000),
            ],
        );
        check_maximums(&mut bad, &[("lease_ms", self.lease_ms, 3_600_000)]);
        bad
    }
}

impl PluginsConfig {
    /// Every problem of this section (keys without the `plugins.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        check_minimums(
            &mut bad,
            &[
                ("poll_interval_ms", self.poll_interval_ms, 10),
                ("cpu_time_ms", self.cpu_time_ms, 10),
                ("request_timeout_ms", self.request_timeout_ms, 100),
                ("memory_mib", self.memory_mib as u64, 1),
                ("max_motions", self.max_motions as u64, 1),
                ("max_body_bytes", self.max_body_bytes as u64, 1024),
                ("max_wasm_bytes", self.max_wasm_bytes as u64, 1024),
            ],
        );
        if self.memory_mib > 4096 {
            bad.push(Problem::new(
                "memory_mib",
                format!(
                    "{} MiB is more than a 32-bit WebAssembly memory can hold (4096)",
                    self.memory_mib
                ),
            ));
        }
        for (name, l) in &self.limits {
            if let Err(e) = kuka_plugin_host::check_name(name) {
                bad.push(Problem::new("limits", e));
            }
            if l.memory_mib.is_some_and(|m| m == 0 || m > self.memory_mib) {
                bad.push(Problem::new(
                    "limits",
                    format!(
                        "{name}: memory_mib must be 1 to plugins.memory_mib ({})",
                        self.memory_mib
                    ),
                ));
            }
            let too_small = l.cpu_time_ms.is_some_and(|v| v < 10)
                || l.request_timeout_ms.is_some_and(|v| v < 100)
                || l.max_motions == Some(0);
            if too_small {
                bad.push(Problem::new(
                    "limits",
                    format!(
                        "{name}: cpu_time_ms >= 10, request_timeout_ms >= 100, max_motions >= 1"
                    ),
                ));
            }
        }
        bad
    }
}

impl LogConfig {
    /// Every problem of this section (keys without the `log.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        if self.retention_days == 0 {
            bad.push(Problem::new("retention_days", "must be at least 1"));
        }
        let level = self.level.trim();
        let plain_level = ["off", "error", "warn", "info", "debug", "trace"]
            .iter()
            .any(|l| l.eq_ignore_ascii_case(level));
        // A bare word would be read as a target name: only levels, or
        // filters with `=` or `,` (e.g. `info,kuka_bridge::engine=debug`).
        let filter_ok = (plain_level || level.contains('=') || level.contains(','))
            && tracing_subscriber::EnvFilter::try_new(level).is_ok();
        if !filter_ok {
            bad.push(Problem::new(
                "level",
                format!(
                    "{:?} is not a level (error, warn, info, debug, trace, off) or a filter such as \"info,kuka_bridge::engine=debug\"",
                    self.level
                ),
            ));
        }
        bad
    }
}

impl ProgramsConfig {
    /// Every problem of this section (keys without the `programs.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        if self.max_bytes == 0 || self.max_bytes > 4 * 1024 * 1024 {
            bad.push(Problem::new(
                "max_bytes",
                format!("{} is not in 1..=4194304", self.max_bytes),
            ));
        }
        if self.run_timeout_ms == 0 {
            bad.push(Problem::new("run_timeout_ms", "must be positive"));
        }
        if self.keep_modules == 0 {
            bad.push(Problem::new("keep_modules", "must be at least 1"));
        }
        bad
    }
}

impl SimulatorConfig {
    /// Every problem of this section (keys without the `simulator.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        check_minimums(
            &mut bad,
            &[
                ("heartbeat_ms", self.heartbeat_ms, 1),
                ("cycle_ms", self.cycle_ms, 1),
                // The slowest assumption the cost figures cover
                // (docs/BENCHMARKS.md §8); below it the program cannot
                // keep its heartbeat.
                ("submit_budget", self.submit_budget, 500),
            ],
        );
        check_maximums(
            &mut bad,
            &[
                ("cycle_ms", self.cycle_ms, 100),
                ("submit_budget", self.submit_budget, 10_000_000),
            ],
        );
        for (k, l) in self.links.iter().enumerate() {
            if let Err(why) = l.check() {
                bad.push(Problem::new("links", format!("entry {k}: {why}")));
            }
        }
        let p = &self.run_prefix;
        let path_chars = p
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'/' || b == b'_');
        if !(p.starts_with("/R1/")
            && p.ends_with('/')
            && !p.contains("//")
            && p.len() <= 30
            && path_chars)
        {
            bad.push(Problem::new(
                "run_prefix",
                format!(
                    "{p:?} is not a RUN path prefix: it starts with /R1/, ends with /, has at most 30 characters (letters, digits, _ and single /)"
                ),
            ));
        }
        if !(self.time_scale.is_finite() && self.time_scale >= 0.0) {
            bad.push(Problem::new(
                "time_scale",
                format!("{} is not ≥ 0", self.time_scale),
            ));
        }
        bad
    }
}

impl RobotConfig {
    /// The model this section names (None: no kinematic checks), or why
    /// there is none.
    fn model(&self) -> Result<Option<RobotModel>, Problem> {
        if let Some(custom) = &self.custom {
            return Ok(Some(custom.clone()));
        }
        if self.model == "none" {
            return Ok(None);
        }
        RobotModel::by_name(&self.model)
            .map(|mut m| {
                if let Some(acc) = self.max_acc_deg_s2 {
                    m.max_acc_deg_s2 = acc;
                }
                Some(m)
            })
            .ok_or_else(|| {
                Problem::new(
                    "model",
                    format!(
                        "unknown model {:?}; built-in models: {}, or \"none\"",
                        self.model,
                        RobotModel::builtin_names().join(", ")
                    ),
                )
            })
    }

    /// Every problem of this section (keys without the `robot.` prefix).
    pub fn problems(&self) -> Vec<Problem> {
        let mut bad = Vec::new();
        if let Err(p) = self.model() {
            bad.push(p);
        }
        for (i, a) in self.max_acc_deg_s2.iter().flatten().enumerate() {
            if !(a.is_finite() && (1.0..=100_000.0).contains(a)) {
                bad.push(Problem::new(
                    "max_acc_deg_s2",
                    format!(
                        "axis A{}: {a} is not an acceleration in [1, 100000] deg/s²",
                        i + 1
                    ),
                ));
            }
        }
        let Some(m) = &self.custom else {
            return bad;
        };
        // Plausible for a 6-axis industrial arm, and within what the file
        // protocol can carry (±9999.999 mm).
        let [_, _, _, c1, c2, c3, c4] = m.opw_mm;
        if m.opw_mm.iter().any(|v| !v.is_finite() || v.abs() > 3000.0)
            || [c1, c2, c3].iter().any(|v| *v < 1.0)
            || c4 < 0.0
        {
            bad.push(Problem::new(
                "custom.opw_mm",
                "needs [a1, a2, b, c1, c2, c3, c4] in mm, each within ±3000, with c1, c2, c3 ≥ 1 and c4 ≥ 0",
            ));
        }
        for (i, (lo, hi)) in m.limits_deg.iter().enumerate() {
            if !(lo.is_finite() && hi.is_finite() && lo < hi && *lo >= -720.0 && *hi <= 720.0) {
                bad.push(Problem::new(
                    "custom.limits_deg",
                    format!(
                        "axis A{}: [{lo}, {hi}] is not [min, max] with -720 ≤ min < max ≤ 720",
                        i + 1
                    ),
                ));
            }
            let v = m.max_speed_deg_s[i];
            if !(v.is_finite() && v > 0.0 && v <= 3600.0) {
                bad.push(Problem::new(
                    "custom.max_speed_deg_s",
                    format!("axis A{}: {v} is not a speed in (0, 3600] deg/s", i + 1),
                ));
            }
            let a = m.max_acc_deg_s2[i];
            if !(a.is_finite() && (1.0..=100_000.0).contains(&a)) {
                bad.push(Problem::new(
                    "custom.max_acc_deg_s2",
                    format!(
                        "axis A{}: {a} is not an acceleration in [1, 100000] deg/s²",
                        i + 1
                    ),
                ));
            }
            if !(*lo..=*hi).contains(&m.home[i]) {
                bad.push(Problem::new(
                    "custom.home",
                    format!(
                        "A{} = {} lies outside its limits [{lo}, {hi}]",
                        i + 1,
                        m.home[i]
                    ),
                ));
            }
        }
        bad
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn errors_name_file_and_key() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("c.toml");
        // The text of the error a file's validation gives.
        let invalid = |toml: &str| {
            std::fs::write(&p, toml).expect("write");
            Config::load(&p)
                .expect("parses")
                .validate()
                .expect_err("invalid")
                .to_string()
        };
        let text = invalid("[channel]\npoll_interval_ms = 0\n");
        assert!(
            text.contains("c.toml") && text.contains("channel.poll_interval_ms"),
            "{text}"
        );
        // Every bad key at once, in every section, not only the first.
        let text = invalid(
            "[channel]\npoll_interval_ms = 0\n[motion]\nmax_queue = 0\n[server]\nmax_connections = 0\n[log]\nretention_days = 0\n",
        );
        for key in [
            "channel.poll_interval_ms",
            "motion.max_queue",
            "server.max_connections",
            "log.retention_days",
        ] {
            assert!(text.contains(key), "{key} missing in: {text}");
        }
        assert!(text.starts_with("4 problems"), "{text}");
        // The simulated KSS variant: a RUN prefix that is not a path, a
        // success value KRL does not have.
        let text = invalid("[simulator]\nrun_prefix = \"/R1/../x\"\n");
        assert!(text.contains("simulator.run_prefix"), "{text}");
        std::fs::write(&p, "[simulator]\nfile_success = \"OK\"\n").expect("write");
        assert!(Config::load(&p).is_err(), "file_success = OK accepted");
        std::fs::write(
            &p,
            "[simulator]\nfile_success = \"CMD_OK\"\nrun_prefix = \"/R1/Program/kbridge/\"\n",
        )
        .expect("write");
        let c = Config::load(&p).expect("parses");
        assert_eq!(c.simulator.file_success, FileSuccess::CmdOk);
        c.validate().expect("the folder form is valid");
        std::fs::write(&p, "[channel]\npol_interval_ms = 5\n").expect("write");
        let text = Config::load(&p).expect_err("unknown key").to_string();
        assert!(
            text.contains("c.toml") && text.contains("pol_interval_ms"),
            "{text}"
        );
        let text = invalid("[robot]\nmodel = \"kr99\"\n");
        assert!(
            text.contains("robot.model") && text.contains("kr3_r540"),
            "{text}"
        );
        // Busy loops only where answers can come within them.
        let c = ChannelConfig::default().timing(false);
        assert_eq!(
            (c.answer_spin, c.request_spin),
            (Duration::ZERO, Duration::ZERO)
        );
        let sim = ChannelConfig::default().timing(true);
        assert_eq!(sim.answer_spin, Duration::from_micros(300));
        assert_eq!(sim.request_spin, Duration::from_micros(250));
        let set = ChannelConfig {
            answer_spin_us: Some(50),
            ..ChannelConfig::default()
        };
        assert_eq!(set.timing(true).answer_spin, Duration::from_micros(50));
        // The engine gets durations, built from the section's milliseconds.
        let t = Config::default().engine_settings().channel;
        assert_eq!(t.poll_interval, Duration::from_millis(50));
        assert_eq!(t.command_timeout, Duration::from_secs(60));
        for key in ["answer_spin_us", "request_spin_us"] {
            let text = invalid(&format!("[channel]\n{key} = 20000\n"));
            assert!(
                text.contains(&format!("channel.{key}")) && text.contains("10000"),
                "{text}"
            );
        }
    }
}

#[cfg(test)]
mod listen_tests {
    use super::*;

    /// `--listen` and `server.listen` take an address or `HOST:PORT`;
    /// `localhost` listens on loopback whatever the resolver lists first.
    #[test]
    fn listen_takes_addresses_and_host_names() {
        let addr = |s: &str| s.parse::<SocketAddr>().expect("address");
        assert_eq!(resolve_listen("0.0.0.0:8080"), Ok(addr("0.0.0.0:8080")));
        assert_eq!(resolve_listen(" [::1]:80 "), Ok(addr("[::1]:80")));
        let local = resolve_listen("localhost:8080").expect("localhost resolves");
        assert!(local.ip().is_loopback() && local.port() == 8080, "{local}");
        for bad in ["localhost", "localhost:99999", ":8080", "localhost:http"] {
            let e = resolve_listen(bad).expect_err(bad);
            assert!(e.contains("HOST:PORT"), "{bad}: {e}");
        }
        let (v6, v4, lan) = (addr("[::1]:80"), addr("127.0.0.1:80"), addr("10.0.0.5:80"));
        assert_eq!(pick_listen_address("localhost", &[v6, v4]), Some(v4));
        assert_eq!(pick_listen_address("LocalHost", &[lan, v6]), Some(v6));
        assert_eq!(pick_listen_address("localhost", &[lan]), None);
        assert_eq!(pick_listen_address("hmi-pc", &[lan, v4]), Some(lan));
        assert_eq!(pick_listen_address("hmi-pc", &[]), None);

        let c: Config = toml::from_str("[server]\nlisten = \"localhost:9000\"\n").expect("parses");
        assert!(c.server.listen.ip().is_loopback() && c.server.listen.port() == 9000);
        let e = toml::from_str::<Config>("[server]\nlisten = \"hmi\"\n").expect_err("no port");
        assert!(e.to_string().contains("HOST:PORT"), "{e}");
    }
}

#[cfg(test)]
mod readme_tests {
    use super::*;

    /// The TOML blocks of README.md's configuration section: the Windows
    /// example, then the Linux one.
    fn readme_examples() -> Vec<&'static str> {
        let readme = include_str!("../../README.md");
        let start = readme
            .find("\n## Configuration\n")
            .expect("a configuration section");
        let section = &readme[start + 1..];
        let section = &section[..section[3..].find("\n## ").map_or(section.len(), |e| e + 3)];
        section
            .split("```toml\n")
            .skip(1)
            .map(|block| &block[..block.find("```").expect("a closed block")])
            .collect()
    }

    /// The dotted keys a TOML block names, set or commented out
    /// (`# key = …`, under `[section]` or `# [section]`).
    fn named_keys(block: &str) -> Vec<String> {
        let mut section = String::new();
        let mut keys = Vec::new();
        for line in block.lines() {
            let line = line.trim_start();
            let line = line.strip_prefix('#').map_or(line, str::trim_start);
            if let Some(rest) = line.strip_prefix('[') {
                section = rest.split(']').next().unwrap_or_default().to_string();
            } else if let Some((key, _)) = line.split_once(" = ")
                && !key.contains(' ')
            {
                keys.push(if section.is_empty() {
                    key.to_string()
                } else {
                    format!("{section}.{key}")
                });
            }
        }
        keys
    }

    /// The dotted keys of a TOML table (leaves only).
    fn leaf_keys(table: &toml::Table, prefix: &str, out: &mut Vec<String>) {
        for (k, v) in table {
            let key = format!("{prefix}{k}");
            match v {
                toml::Value::Table(t) => leaf_keys(t, &format!("{key}."), out),
                _ => out.push(key),
            }
        }
    }

    /// README.md's two configuration examples, for Windows and for Linux,
    /// parse and validate; each names every key `default-config` prints
    /// (set, or commented out where the value depends on the machine), shows
    /// the default values (paths aside), and switches nothing on that the
    /// defaults leave off (no `[workspace]`). The Linux one has no Windows
    /// path: run on Linux, it creates no folder named `C:\KRC\…`.
    #[test]
    fn readme_config_examples_are_valid_and_complete() {
        let examples = readme_examples();
        assert_eq!(examples.len(), 2, "a Windows and a Linux example");
        let defaults = Config::default();
        let mut default_keys = Vec::new();
        let table = toml::Value::try_from(&defaults).expect("defaults as TOML");
        leaf_keys(table.as_table().expect("a table"), "", &mut default_keys);
        assert!(default_keys.contains(&"programs.run_timeout_ms".to_string()));
        for (n, block) in examples.iter().enumerate() {
            let which = ["Windows", "Linux"][n];
            let mut config: Config = toml::from_str(block)
                .unwrap_or_else(|e| panic!("the {which} example does not parse: {e}"));
            let checked = config.validate();
            if which == "Windows" && !cfg!(windows) {
                // Off Windows its drive-letter paths would become folders named `C:\...`.
                let e = checked.expect_err("the Windows example is refused off Windows");
                assert!(e.to_string().contains("Windows path"), "{e}");
            } else {
                checked.unwrap_or_else(|e| panic!("the {which} example is invalid: {e}"));
            }
            assert!(
                config.workspace.is_none(),
                "{which}: no [workspace] by default"
            );
            let named = named_keys(block);
            for key in &default_keys {
                assert!(named.contains(key), "the {which} example lacks {key}");
            }
            let windows_path = |p: &Option<PathBuf>| {
                p.as_ref()
                    .is_some_and(|p| p.to_string_lossy().starts_with("C:\\"))
            };
            let paths = [
                Some(config.data_dir.clone()),
                config.channel.dir.clone(),
                config.programs.controller_dir.clone(),
            ];
            if which == "Windows" {
                assert!(paths.iter().all(windows_path), "{which}: {paths:?}");
            } else {
                assert!(!paths.iter().any(windows_path), "{which}: {paths:?}");
            }
            // Paths aside, the values are the defaults.
            config.data_dir = defaults.data_dir.clone();
            config.channel.dir = None;
            config.programs.controller_dir = None;
            assert_eq!(
                toml::to_string(&config).expect("TOML"),
                toml::to_string(&defaults).expect("TOML"),
                "the {which} example shows other values than the defaults"
            );
        }
    }
}

#[cfg(test)]
mod custom_model_tests {
    use super::*;

    /// A custom robot given by OPW parameters in the config file is used.
    #[test]
    fn custom_opw_model_from_config() {
        let text = r#"
            [robot.custom]
            name = "lab_arm"
            opw_mm = [25.0, -35.0, 0.0, 400.0, 315.0, 365.0, 80.0]
            limits_deg = [[-170.0, 170.0], [-190.0, 45.0], [-120.0, 156.0], [-185.0, 185.0], [-120.0, 120.0], [-350.0, 350.0]]
            max_speed_deg_s = [360.0, 300.0, 360.0, 381.0, 388.0, 615.0]
            home = [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]
        "#;
        let config: Config = toml::from_str(text).expect("parses");
        config.validate().expect("valid");
        let model = config.robot_model().expect("model").expect("some");
        assert_eq!(model.name, "lab_arm");
        let bad = text.replace("[-170.0, 170.0]", "[50.0, -170.0]");
        let err = toml::from_str::<Config>(&bad)
            .expect("parses")
            .validate()
            .expect_err("inverted limits");
        assert!(err.to_string().contains("robot.custom.limits_deg"), "{err}");
        let bad = text.replace("opw_mm = [25.0", "opw_mm = [1e9");
        let err = toml::from_str::<Config>(&bad)
            .expect("parses")
            .validate()
            .expect_err("huge geometry");
        assert!(err.to_string().contains("robot.custom.opw_mm"), "{err}");
        let bad = text.replace("[360.0, 300.0", "[0.0, 300.0");
        let err = toml::from_str::<Config>(&bad)
            .expect("parses")
            .validate()
            .expect_err("zero speed");
        assert!(
            err.to_string().contains("robot.custom.max_speed_deg_s"),
            "{err}"
        );
        // The same geometry as the KR 6 R700 sixx: flange at X 470, Z 750 at home.
        let p = model.flange(&model.home);
        assert!(
            (p.x - 470.0).abs() < 1e-6 && (p.z - 750.0).abs() < 1e-6,
            "{p:?}"
        );
    }
}

//! The command line (the binary's edge): parses arguments into a validated
//! configuration and runs the service, or a standalone simulated
//! controller. `main.rs` only calls [`main`]; the test crate builds the
//! same CLI as its own binary to run it as a separate process.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::config::Config;
use anyhow::Context;
use clap::{Parser, Subcommand};

/// A REST API for KUKA robots over a file protocol.
/// Prints a line on stdout. A closed stdout (`kuka-bridge run | head`) is
/// no reason to panic or stop the service: the line is dropped.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// Writes a command's whole output on stdout; a reader that stops early
/// (`| head`) ends it quietly, any other failure is an error.
fn write_out(text: &str) -> anyhow::Result<()> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

#[derive(Debug, Parser)]
#[command(name = "kuka-bridge", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Debug, Subcommand)]
enum Cmd {
    /// Run the service in the console.
    Run(RunArgs),
    /// Run only a simulated controller on a channel directory (for tests and
    /// for a service started elsewhere).
    Simulate(SimArgs),
    /// Manage access tokens (works whether the service runs or not;
    /// revocation takes effect on the running service within a second).
    #[command(subcommand)]
    Token(TokenCmd),
    /// Print the default configuration as TOML.
    DefaultConfig,
    /// Print the OpenAPI document.
    Openapi,
    /// KRL tools.
    #[command(subcommand)]
    Krl(KrlCmd),
    /// Manage the Windows service (install, uninstall, start, stop, status).
    #[cfg(windows)]
    #[command(subcommand)]
    Service(ServiceCmd),
    /// The Windows service commands (Windows only): says so, and what to
    /// use instead, rather than "unrecognized subcommand".
    #[cfg(not(windows))]
    #[command(hide = true, disable_help_flag = true)]
    Service {
        /// Whatever followed `service`.
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
}

/// `kuka-bridge krl …`.
#[derive(Debug, Subcommand)]
enum KrlCmd {
    /// Check KRL files (.src, .sub, .dat; folders: every KRL file under
    /// them) as a controller parses them: the first problem of each file
    /// as `file:line:column: message`, exit code 1 if any file has one.
    Check {
        /// Files or folders.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Also check each module (.src with its .dat beside it) as the
        /// service checks an upload before running it on a simulated
        /// controller: declared names and what that simulator executes
        /// (`--simulator` or `--simulator=native`: its KRL subset;
        /// `--simulator=krc`: what the KRC-like
        /// runtime runs, with its system variables and $config.dat). A
        /// module that uses globals of other .dat files (as the shipped
        /// program in krl/KRC does) is reported as not declared.
        #[arg(long, value_name = "KIND", num_args = 0..=1, require_equals = true, default_missing_value = "native")]
        simulator: Option<crate::config::SimulatorKind>,
    },
}

/// What `kuka-bridge service …` says off Windows.
#[cfg(not(windows))]
const NOT_WINDOWS: &str = "the Windows service commands exist only on Windows; on Linux run \
    `kuka-bridge run` under systemd (see README.md, \"Running under systemd\")";

/// Exit code of `kuka-bridge service …` off Windows: a usage error, as
/// for any other unknown command.
#[cfg(not(windows))]
const EXIT_USAGE: u8 = 2;

/// `kuka-bridge service …` (Windows).
#[cfg(windows)]
#[derive(Debug, Subcommand)]
enum ServiceCmd {
    /// Install or update the service (idempotent): automatic start,
    /// recovery actions, Event Log source, ProgramData folders and a
    /// default config if there is none; then start it.
    Install {
        /// Do not start the service after installing it.
        #[arg(long)]
        no_start: bool,
        /// Called by the MSI (which creates and starts the service itself):
        /// only configure the existing service.
        #[arg(long)]
        from_msi: bool,
    },
    /// Stop and remove the service and its Event Log source; keeps
    /// configuration, logs and data unless --purge.
    Uninstall {
        /// Also delete %ProgramData%\kuka-bridge (config, logs, data).
        #[arg(long)]
        purge: bool,
        /// Called by the MSI (which removes the service itself).
        #[arg(long)]
        from_msi: bool,
    },
    /// Start the service.
    Start,
    /// Stop the service (waits until its process has exited).
    Stop {
        /// Called by the MSI before it removes or replaces the executable:
        /// wait until no process runs it; never fails.
        #[arg(long)]
        from_msi: bool,
    },
    /// Show the service's state, exit codes, config and log folder.
    Status,
    /// The service entry (started by the service manager, not by hand).
    #[command(hide = true)]
    Run {
        /// The configuration file; its folder is also the data folder
        /// unless the file sets `data_dir` (default
        /// %ProgramData%\kuka-bridge\kuka-bridge.toml).
        #[arg(long)]
        config: Option<PathBuf>,
    },
}

/// `kuka-bridge token …`.
#[derive(Debug, Subcommand)]
enum TokenCmd {
    /// Create a token and print its secret (shown only this once).
    Create {
        /// Unique name (appears in the audit trail): letters, digits, `.`, `_`, `-`, `@`.
        #[arg(long)]
        name: String,
        /// viewer (read), operator (move the robot) or admin (install, manage).
        #[arg(long, value_parser = ["viewer", "operator", "admin"])]
        role: String,
        #[command(flatten)]
        place: TokenPlace,
    },
    /// List tokens (names, roles, creation times; never secrets).
    List {
        #[command(flatten)]
        place: TokenPlace,
    },
    /// Revoke a token.
    Revoke {
        /// The token's name.
        name: String,
        #[command(flatten)]
        place: TokenPlace,
    },
}

/// Which service's tokens: the same `--config` / `--data-dir` as `run`.
#[derive(Debug, clap::Args)]
struct TokenPlace {
    /// Configuration file of the service (its `data_dir` holds the tokens).
    #[arg(long, short, env = "KUKA_BRIDGE_CONFIG")]
    config: Option<PathBuf>,
    /// Data directory of the service (overrides the config's).
    #[arg(long)]
    data_dir: Option<PathBuf>,
}

impl TokenPlace {
    /// The data directory the service uses with these options.
    fn data_dir(&self) -> anyhow::Result<PathBuf> {
        if let Some(d) = &self.data_dir {
            return Ok(d.clone());
        }
        #[cfg(windows)]
        {
            Ok(service_config(self.config.as_deref())?.data_dir)
        }
        #[cfg(not(windows))]
        {
            Ok(match &self.config {
                Some(p) => Config::load(p)?.data_dir,
                None => Config::default().data_dir,
            })
        }
    }
}

fn token_command(cmd: TokenCmd) -> anyhow::Result<()> {
    use crate::access::{Role, TokenStore};
    match cmd {
        TokenCmd::Create { name, role, place } => {
            let dir = place.data_dir()?;
            let role = Role::parse(&role).context("role must be viewer, operator or admin")?;
            let store = TokenStore::open(&dir)?;
            let (info, secret) = store.create(&name, role)?;
            eprintln!(
                "created {} token {:?} in {}; the secret below is shown only once:",
                info.role,
                info.name,
                store.path().display()
            );
            say!("{secret}");
        }
        TokenCmd::List { place } => {
            let store = TokenStore::open(&place.data_dir()?)?;
            let list = store.list();
            if list.is_empty() {
                eprintln!("no tokens in {}", store.path().display());
            }
            for t in list {
                say!(
                    "{:<32} {:<8} created {}",
                    t.name,
                    t.role,
                    crate::access::tokens::utc_text(t.created_ms)
                );
            }
        }
        TokenCmd::Revoke { name, place } => {
            let store = TokenStore::open(&place.data_dir()?)?;
            let t = store.revoke(&name)?;
            say!("revoked {} token {:?}", t.role, t.name);
        }
    }
    Ok(())
}

/// Exit code for a configuration that cannot be used (`EX_CONFIG`).
pub const EXIT_CONFIG: u8 = 78;

/// Why the command failed, and with which exit code.
struct Failure {
    code: u8,
    error: anyhow::Error,
    /// Already logged (the service logs its own end).
    logged: bool,
}

impl<E: Into<anyhow::Error>> From<E> for Failure {
    fn from(e: E) -> Self {
        let error = e.into();
        let code = if error.downcast_ref::<crate::config::ConfigError>().is_some()
            || matches!(
                error.downcast_ref::<crate::app::AppError>(),
                Some(crate::app::AppError::Config(_) | crate::app::AppError::Tls(_))
            ) {
            EXIT_CONFIG
        } else {
            1
        };
        Failure {
            code,
            error,
            logged: false,
        }
    }
}

#[derive(Debug, clap::Args)]
struct RunArgs {
    /// Configuration file (TOML); every key is optional.
    #[arg(long, short, env = "KUKA_BRIDGE_CONFIG")]
    config: Option<PathBuf>,
    /// Embed a simulated controller (no robot needed): `native` (the
    /// default: instant answers) or `krc` (the shipped KRL program in the
    /// KRC-like runtime, with its 12 ms Submit cycle).
    /// Without a value: the configuration's `simulator.kind` (native
    /// unless set).
    #[arg(long, value_name = "KIND", num_args = 0..=1)]
    #[allow(clippy::option_option)]
    simulate: Option<Option<crate::config::SimulatorKind>>,
    /// Listen address, e.g. 0.0.0.0:8080 or localhost:8080 (default
    /// 127.0.0.1:8080); a host name is resolved once, at start.
    #[arg(long, value_parser = crate::config::resolve_listen)]
    listen: Option<SocketAddr>,
    /// Channel directory shared with the controller.
    #[arg(long)]
    channel_dir: Option<PathBuf>,
    /// Data directory (command id counter).
    #[arg(long)]
    data_dir: Option<PathBuf>,
    /// Robot model id or `none`.
    #[arg(long)]
    robot: Option<String>,
    /// Simulated seconds per wall second (0 = instant).
    #[arg(long)]
    time_scale: Option<f64>,
    /// Require tokens on a loopback address too (beyond loopback they are
    /// always required).
    #[arg(long)]
    require_auth: bool,
}

#[derive(Debug, clap::Args)]
struct SimArgs {
    /// Channel directory.
    #[arg(long)]
    channel_dir: PathBuf,
    /// Robot model id.
    #[arg(long, default_value = "kr3_r540")]
    robot: String,
    /// Simulated seconds per wall second (0 = instant).
    #[arg(long, default_value_t = 1.0)]
    time_scale: f64,
    /// Heartbeat period in ms (native only; the KRL program's is in
    /// `kb_main.dat`).
    #[arg(long, default_value_t = 50)]
    heartbeat_ms: u64,
    /// Which simulated controller: `native` or `krc` (the shipped KRL
    /// program in the KRC-like runtime).
    #[arg(long, value_name = "KIND", default_value = "native")]
    kind: crate::config::SimulatorKind,
}

/// Logging for commands that are not the service itself: the console, and
/// the log files of `config` when there is one.
fn console_logging(config: Option<&Config>) -> Option<crate::logging::LogGuard> {
    let opts = crate::logging::LogOptions {
        level: config.map_or_else(|| "info".into(), |c| c.log.level.clone()),
        console: true,
        files: config
            .filter(|c| c.log.file)
            .map(|c| (c.log_dir(), c.log.retention_days)),
        event_log: false,
    };
    match crate::logging::init(&opts) {
        Ok(g) => Some(g),
        Err(e) => {
            eprintln!("kuka-bridge: {e}; logging to the console only");
            let opts = crate::logging::LogOptions {
                files: None,
                ..opts
            };
            crate::logging::init(&opts).ok()
        }
    }
}

/// Runs the command line; the process exit code (78 for a configuration
/// error, 1 for any other failure).
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    // The log writer lives until the last line is logged and flushed.
    let mut log = None;
    let code = match real_main(cli, &mut log) {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            if f.logged {
            } else if tracing::dispatcher::has_been_set() {
                tracing::error!(exit_code = f.code, "{:#}", f.error);
            } else {
                eprintln!("kuka-bridge: {:#}", f.error);
            }
            ExitCode::from(f.code)
        }
    };
    drop(log);
    code
}

fn real_main(cli: Cli, log: &mut Option<crate::logging::LogGuard>) -> Result<(), Failure> {
    match cli.command {
        Cmd::Run(args) => {
            let config = build_config(args)?;
            *log = console_logging(Some(&config));
            let rt = tokio::runtime::Runtime::new().context("cannot start the async runtime")?;
            rt.block_on(async move {
                let simulated = config.simulator.enabled;
                let kind = config.simulator.kind;
                let service = crate::app::start(config).await?;
                let stop = shutdown_signal();
                let url = service.base_url();
                say!(
                    "kuka-bridge {} listening on {url}",
                    env!("CARGO_PKG_VERSION")
                );
                if service.addr.ip().is_unspecified() {
                    say!("  (all network interfaces: use this PC's name or address instead of {})", service.addr.ip());
                }
                say!("  Dashboard:    {url}/");
                say!("  Swagger UI:   {url}/docs/");
                say!("  OpenAPI:      {url}/openapi.json");
                if service.auth {
                    say!("  Access:       tokens required (kuka-bridge token create --name NAME --role ROLE)");
                } else {
                    say!("  Access:       no tokens (loopback only; --require-auth to require them)");
                }
                if let Some(f) = &service.admin_token_file {
                    say!(
                        "  First admin token created: its secret is in {} (readable by administrators only)",
                        f.display()
                    );
                }
                if simulated {
                    say!(
                        "  Controller:   simulated, {} ({})",
                        match kind {
                            crate::config::SimulatorKind::Native => "native",
                            crate::config::SimulatorKind::Krc => "the shipped KRL program in the KRC-like runtime",
                        },
                        service
                            .engine
                            .state()
                            .model
                            .unwrap_or_else(|| "no model".into())
                    );
                }
                say!("Press Ctrl-C to stop.");
                crate::app::run_service(service, stop, std::future::pending()).await
            })?;
            Ok(())
        }
        Cmd::Simulate(args) => {
            *log = console_logging(None);
            let model = kuka_kinematics::RobotModel::by_name(&args.robot)
                .with_context(|| format!("unknown robot model {:?}", args.robot))?;
            if !(args.time_scale.is_finite() && args.time_scale >= 0.0) {
                return Err(anyhow::anyhow!("--time-scale must be ≥ 0").into());
            }
            let rt = tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build()?;
            match args.kind {
                crate::config::SimulatorKind::Native => {
                    let mut sc = kuka_sim::SimConfig::new(&args.channel_dir);
                    sc.model = model;
                    sc.time_scale = args.time_scale;
                    sc.heartbeat = std::time::Duration::from_millis(args.heartbeat_ms.max(1));
                    let sim = kuka_sim::SimController::start(sc)?;
                    say!("simulated controller on {}", args.channel_dir.display());
                    rt.block_on(async {
                        let _ = tokio::signal::ctrl_c().await;
                    });
                    sim.shutdown();
                }
                crate::config::SimulatorKind::Krc => {
                    let mut kc = kuka_krc::KrcConfig::new(&args.channel_dir);
                    kc.model = model;
                    kc.time_scale = args.time_scale;
                    kc.submit_budget = crate::config::SimulatorConfig::default().submit_budget;
                    let krc = kuka_krc::KrcController::start(kc)?;
                    say!(
                        "KRC-like runtime (the shipped KRL program) on {}",
                        args.channel_dir.display()
                    );
                    rt.block_on(async {
                        let _ = tokio::signal::ctrl_c().await;
                    });
                    krc.shutdown();
                }
            }
            Ok(())
        }
        #[cfg(windows)]
        Cmd::Service(cmd) => service_command(cmd, log),
        #[cfg(not(windows))]
        Cmd::Service { .. } => Err(Failure {
            code: EXIT_USAGE,
            error: anyhow::anyhow!(NOT_WINDOWS),
            logged: false,
        }),
        Cmd::Token(cmd) => Ok(token_command(cmd)?),
        Cmd::DefaultConfig => Ok(write_out(&toml::to_string_pretty(&Config::default())?)?),
        Cmd::Krl(KrlCmd::Check { files, simulator }) => {
            let simulator = match simulator {
                None => None,
                Some(crate::config::SimulatorKind::Native) => {
                    Some(crate::krl_check::Simulator::Native)
                }
                Some(crate::config::SimulatorKind::Krc) => Some(crate::krl_check::Simulator::Krc(
                    crate::krl_check::krc_globals()?,
                )),
            };
            let report = crate::krl_check::run(&files, simulator.as_ref());
            let mut out = report.problems.join("\n");
            if !out.is_empty() {
                out.push('\n');
            }
            write_out(&out)?;
            let empty = if report.empty > 0 {
                format!("; {} argument(s) named no KRL file", report.empty)
            } else {
                String::new()
            };
            {
                // A closed stderr (`2>&1 | head -1`) drops the summary.
                use std::io::Write as _;
                let _ = writeln!(
                    std::io::stderr(),
                    "{} KRL file(s) checked, {} with problems, {} warning(s){empty}",
                    report.files,
                    report.failed,
                    report.warnings
                );
            }
            if report.failed > 0 || report.empty > 0 {
                return Err(Failure {
                    code: 1,
                    error: anyhow::anyhow!("KRL check failed"),
                    logged: true,
                });
            }
            Ok(())
        }
        Cmd::Openapi => Ok(write_out(&format!(
            "{}\n",
            serde_json::to_string_pretty(&crate::api::openapi())?
        ))?),
    }
}

/// Ctrl-C, or SIGTERM on Unix (systemd, `kill`).
/// Ctrl-C or SIGTERM. The handlers are registered when this is called —
/// before the banner says the service runs — so a signal sent right after
/// the banner stops the service cleanly instead of killing it.
fn shutdown_signal() -> impl std::future::Future<Output = ()> {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        let streams = signal(SignalKind::terminate())
            .and_then(|term| Ok((term, signal(SignalKind::interrupt())?)));
        async move {
            match streams {
                Ok((mut term, mut interrupt)) => {
                    tokio::select! {
                        _ = term.recv() => {}
                        _ = interrupt.recv() => {}
                    }
                }
                Err(e) => {
                    tracing::warn!(error = %e, "cannot listen for SIGTERM");
                    let _ = tokio::signal::ctrl_c().await;
                }
            }
        }
    }
    #[cfg(windows)]
    {
        let ctrl_c = tokio::signal::windows::ctrl_c();
        async move {
            match ctrl_c {
                Ok(mut ctrl_c) => {
                    ctrl_c.recv().await;
                }
                Err(e) => {
                    tracing::warn!(error = %e, "cannot listen for Ctrl-C");
                    std::future::pending::<()>().await;
                }
            }
        }
    }
}

fn build_config(args: RunArgs) -> anyhow::Result<Config> {
    let mut config = match &args.config {
        Some(path) => Config::load(path)?,
        None => Config::default(),
    };
    let from_flags = args.simulate.is_some()
        || args.listen.is_some()
        || args.channel_dir.is_some()
        || args.data_dir.is_some()
        || args.robot.is_some()
        || args.time_scale.is_some()
        || args.require_auth;
    if from_flags {
        config.source_name = match &args.config {
            Some(_) => format!("{} with command-line options", config.source_name),
            None => "command-line options".into(),
        };
    }
    if let Some(kind) = args.simulate {
        config.simulator.enabled = true;
        if let Some(kind) = kind {
            config.simulator.kind = kind;
        }
    }
    if let Some(l) = args.listen {
        config.server.listen = l;
    }
    if let Some(d) = args.channel_dir {
        config.channel.dir = Some(d);
    }
    if let Some(d) = args.data_dir {
        config.data_dir = d;
    }
    if let Some(r) = args.robot {
        config.robot.model = r;
    }
    if let Some(t) = args.time_scale {
        config.simulator.time_scale = t;
    }
    if args.require_auth {
        config.auth.require_on_loopback = true;
    }
    config.validate()?;
    Ok(config)
}

/// The configuration the Windows service runs with: `path` (default
/// `%ProgramData%\kuka-bridge\kuka-bridge.toml`) if it exists, else the
/// defaults. The file's folder is the data folder unless the file sets
/// `data_dir`: a service may see another `%ProgramData%` than the installer
/// did (Wine does that), the path the installer registered is the truth.
#[cfg(windows)]
pub(crate) fn service_config(path: Option<&std::path::Path>) -> anyhow::Result<Config> {
    let path = path.map_or_else(crate::winsvc::config_path, std::path::Path::to_path_buf);
    let folder = path.parent().map(std::path::Path::to_path_buf);
    let (mut config, sets_data_dir) = if path.exists() {
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let sets = toml::from_str::<toml::Table>(&text).is_ok_and(|t| t.contains_key("data_dir"));
        (Config::load(&path)?, sets)
    } else {
        (Config::default(), false)
    };
    if !sets_data_dir && let Some(f) = folder {
        config.data_dir = f;
    }
    config.validate()?;
    Ok(config)
}

#[cfg(windows)]
fn service_command(
    cmd: ServiceCmd,
    log: &mut Option<crate::logging::LogGuard>,
) -> Result<(), Failure> {
    use crate::winsvc::{manage, service};
    match cmd {
        ServiceCmd::Run { config } => {
            // Started by the service manager: no console; log files and the
            // Event Log. A configuration error is logged in the logs folder
            // beside the config file, the Event Log and the exit code.
            let path = config.unwrap_or_else(crate::winsvc::config_path);
            let folder = path.parent().map(std::path::Path::to_path_buf);
            let config = service_config(Some(&path));
            let (level, files) = match &config {
                Ok(c) => (
                    c.log.level.clone(),
                    c.log.file.then(|| (c.log_dir(), c.log.retention_days)),
                ),
                Err(_) => {
                    let d = Config::default();
                    let dir = folder.unwrap_or(d.data_dir).join("logs");
                    ("info".into(), Some((dir, d.log.retention_days)))
                }
            };
            *log = crate::logging::init(&crate::logging::LogOptions {
                level,
                console: false,
                files,
                event_log: true,
            })
            .ok();
            service::run_dispatcher(config.map_err(|e| format!("{e:#}")), path).context(
                "not started by the service manager (use `kuka-bridge run` in a console)",
            )?;
            match service::outcome() {
                Some(code) if code != 0 => Err(Failure {
                    code: u8::try_from(code).unwrap_or(1),
                    error: anyhow::anyhow!("the service stopped with exit code {code}"),
                    logged: true,
                }),
                _ => Ok(()),
            }
        }
        other => {
            *log = console_logging(None);
            match other {
                ServiceCmd::Install { no_start, from_msi } => {
                    manage::install(!no_start && !from_msi, from_msi)?
                }
                ServiceCmd::Uninstall { purge, from_msi } => manage::uninstall(purge, from_msi)?,
                ServiceCmd::Start => manage::start()?,
                ServiceCmd::Stop { from_msi: false } => manage::stop()?,
                ServiceCmd::Stop { from_msi: true } => manage::stop_for_msi()?,
                ServiceCmd::Status => manage::status()?,
                ServiceCmd::Run { .. } => {}
            }
            Ok(())
        }
    }
}

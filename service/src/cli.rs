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
    /// Print the default configuration as TOML.
    DefaultConfig,
    /// Print the OpenAPI document.
    Openapi,
}

#[derive(Debug, clap::Args)]
struct RunArgs {
    /// Configuration file (TOML); every key is optional.
    #[arg(long, short, env = "KUKA_BRIDGE_CONFIG")]
    config: Option<PathBuf>,
    /// Embed the simulated controller (no robot needed).
    #[arg(long)]
    simulate: bool,
    /// Listen address, e.g. 0.0.0.0:8080 (default 127.0.0.1:8080).
    #[arg(long)]
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
    /// Heartbeat period in ms.
    #[arg(long, default_value_t = 50)]
    heartbeat_ms: u64,
}

fn init_logging() {
    use tracing_subscriber::EnvFilter;
    let filter =
        EnvFilter::try_from_env("KUKA_BRIDGE_LOG").unwrap_or_else(|_| EnvFilter::new("info"));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_target(false)
        .with_writer(std::io::stderr)
        .init();
}

/// Runs the command line; the process exit code.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    init_logging();
    match real_main(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            tracing::error!("{e:#}");
            ExitCode::FAILURE
        }
    }
}

fn real_main(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Cmd::Run(args) => {
            let config = build_config(args)?;
            let rt = tokio::runtime::Runtime::new().context("cannot start the async runtime")?;
            rt.block_on(async move {
                let simulated = config.simulator.enabled;
                let service = crate::app::start(config).await?;
                let url = service.base_url();
                println!(
                    "kuka-bridge {} listening on {url}",
                    env!("CARGO_PKG_VERSION")
                );
                println!("  Swagger UI:   {url}/docs/");
                println!("  OpenAPI:      {url}/openapi.json");
                if simulated {
                    println!(
                        "  Controller:   simulated ({})",
                        service
                            .engine
                            .state()
                            .model
                            .unwrap_or_else(|| "no model".into())
                    );
                }
                println!("Press Ctrl-C to stop.");
                shutdown_signal().await;
                service.shutdown().await?;
                anyhow::Ok(())
            })
        }
        Cmd::Simulate(args) => {
            let model = kuka_kinematics::RobotModel::by_name(&args.robot)
                .with_context(|| format!("unknown robot model {:?}", args.robot))?;
            anyhow::ensure!(
                args.time_scale.is_finite() && args.time_scale >= 0.0,
                "--time-scale must be ≥ 0"
            );
            let mut sc = kuka_sim::SimConfig::new(&args.channel_dir);
            sc.model = model;
            sc.time_scale = args.time_scale;
            sc.heartbeat = std::time::Duration::from_millis(args.heartbeat_ms.max(1));
            let sim = kuka_sim::SimController::start(sc)?;
            println!("simulated controller on {}", args.channel_dir.display());
            let rt = tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build()?;
            rt.block_on(async {
                let _ = tokio::signal::ctrl_c().await;
            });
            sim.shutdown();
            Ok(())
        }
        Cmd::DefaultConfig => {
            print!("{}", toml::to_string_pretty(&Config::default())?);
            Ok(())
        }
        Cmd::Openapi => {
            println!("{}", serde_json::to_string_pretty(&crate::api::openapi())?);
            Ok(())
        }
    }
}

/// Ctrl-C, or SIGTERM on Unix (systemd, `kill`).
async fn shutdown_signal() {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        match signal(SignalKind::terminate()) {
            Ok(mut term) => {
                tokio::select! {
                    _ = tokio::signal::ctrl_c() => {}
                    _ = term.recv() => {}
                }
                return;
            }
            Err(e) => tracing::warn!(error = %e, "cannot listen for SIGTERM"),
        }
    }
    let _ = tokio::signal::ctrl_c().await;
}

fn build_config(args: RunArgs) -> anyhow::Result<Config> {
    let mut config = match &args.config {
        Some(path) => Config::load(path)?,
        None => Config::default(),
    };
    let from_flags = args.simulate
        || args.listen.is_some()
        || args.channel_dir.is_some()
        || args.data_dir.is_some()
        || args.robot.is_some()
        || args.time_scale.is_some();
    if from_flags {
        config.source_name = match &args.config {
            Some(_) => format!("{} with command-line options", config.source_name),
            None => "command-line options".into(),
        };
    }
    if args.simulate {
        config.simulator.enabled = true;
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
    config.validate()?;
    Ok(config)
}

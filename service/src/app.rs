//! Wiring: builds the channel, the optional embedded simulator, the engine
//! and the HTTP server from a validated [`Config`], and shuts them down in
//! order. The binary and the tests both start the service through here.

use std::future::Future;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use kuka_krc::{KrcConfig, KrcController};
use kuka_sim::{SimConfig, SimController};

use crate::config::SimulatorKind;
use tokio::sync::{oneshot, watch};
use tokio::task::JoinHandle;

use crate::config::{Config, ConfigError};
use crate::engine::Engine;
use crate::safety::Safety;
use kuka_engine::{ChannelError, ServiceLock};

/// Why the service could not start or stopped with an error.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// Invalid configuration.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// Channel directory, lock or counter.
    #[error(transparent)]
    Channel(#[from] ChannelError),
    /// The simulator could not start.
    #[error("simulated controller")]
    Sim(#[from] kuka_sim::SimError),
    /// The KRC-like runtime did not start.
    #[error("KRC-like runtime")]
    Krc(#[from] kuka_krc::KrcError),
    /// The listen address is unavailable.
    #[error("cannot listen on {addr}")]
    Bind {
        /// Address.
        addr: SocketAddr,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The simulator's KUKAVARPROXY stand-in could not listen.
    #[error("KUKAVARPROXY stand-in")]
    Variables(#[source] std::io::Error),
    /// The program store cannot be opened.
    #[error("program store {path}")]
    Programs {
        /// Its folder.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The plugin host could not start.
    #[error("plugins: {0}")]
    Plugins(crate::error::BridgeError),
    /// The token file cannot be used.
    #[error("access control")]
    Tokens(#[from] crate::access::TokenError),
    /// The audit trail cannot be opened.
    #[error("audit trail in {path}")]
    Audit {
        /// Its folder.
        path: String,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The stored I/O configuration cannot be used.
    #[error("I/O configuration")]
    IoStore(#[from] crate::io_store::IoStoreError),
    /// The TLS certificate or key cannot be used.
    #[error("HTTPS")]
    Tls(#[from] crate::server::TlsError),
    /// The HTTP server failed.
    #[error("HTTP server")]
    Serve(#[source] std::io::Error),
}

/// A running service.
pub struct Service {
    /// The address it listens on (with the real port when 0 was asked).
    pub addr: SocketAddr,
    /// The engine.
    pub engine: Engine,
    /// The embedded native simulator (`--simulate` / `--simulate native`).
    pub sim: Option<Arc<SimController>>,
    /// The embedded KRC-like runtime (`--simulate krc`).
    pub krc: Option<Arc<KrcController>>,
    /// True when requests need a token.
    pub auth: bool,
    /// True when serving HTTPS.
    pub tls: bool,
    /// Set when this start created the first admin token: the file its
    /// secret was written to.
    pub admin_token_file: Option<std::path::PathBuf>,
    closing: watch::Sender<bool>,
    /// How long a running job may go on at shutdown (`server.shutdown_grace_ms`).
    shutdown_grace: Duration,
    stop_http: Option<oneshot::Sender<()>>,
    /// The HTTP server task; `None` once it has ended.
    server: Option<JoinHandle<Result<(), AppError>>>,
    _lock: ServiceLock,
}

/// Starts everything and returns once the server listens.
pub async fn start(config: Config) -> Result<Service, AppError> {
    config.validate()?;
    // Certificate and key first: a wrong file must not start anything.
    let tls = match &config.server.tls {
        Some(t) => Some(crate::server::tls_acceptor(t)?),
        None => None,
    };
    let model = config.robot_model()?;
    let dir = config.channel_dir();
    let lock = ServiceLock::acquire(&dir)?;
    if !config.simulator.enabled && config.simulator.kind != SimulatorKind::Native {
        tracing::warn!(
            "simulator.kind is set but simulator.enabled is false: no simulated controller runs (use --simulate or enabled = true)"
        );
    }
    let krc = if config.simulator.enabled && config.simulator.kind == SimulatorKind::Krc {
        let mut kc = KrcConfig::new(&dir);
        if let Some(d) = config.program_dir() {
            kc.program_dir = d;
        }
        if let Some(m) = &model {
            kc.model = m.clone();
            kc.plan = kuka_kinematics::PlanSettings::for_model(m);
        }
        kc.time_scale = config.simulator.time_scale;
        kc.cycle = Duration::from_millis(config.simulator.cycle_ms);
        kc.submit_budget = config.simulator.submit_budget;
        kc.fct_success = config.simulator.file_success.krl().into();
        kc.text_offset_base = config.simulator.text_offset.base();
        if config.simulator.run_prefix != kc.run_prefix {
            kc.run_prefix = config.simulator.run_prefix.clone();
            kc.site_run_prefix = Some(config.simulator.run_prefix.clone());
        }
        Some(Arc::new(KrcController::start(kc)?))
    } else {
        None
    };
    let sim = if config.simulator.enabled && config.simulator.kind == SimulatorKind::Native {
        let mut sc = SimConfig::new(&dir);
        if let Some(d) = config.program_dir() {
            sc.program_dir = d;
        }
        if let Some(m) = &model {
            sc.model = m.clone();
            sc.plan = kuka_kinematics::PlanSettings::for_model(m);
        }
        sc.time_scale = config.simulator.time_scale;
        sc.heartbeat = Duration::from_millis(config.simulator.heartbeat_ms);
        Some(Arc::new(SimController::start(sc)?))
    } else {
        None
    };
    let safety = Safety::new(
        config.motion.clone(),
        config.workspace,
        config.zones.clone(),
        model,
    );
    let io_store = Arc::new(crate::io_store::IoStore::new(
        &config.data_dir,
        config.io.clone(),
    ));
    let mut settings = config.engine_settings();
    let (io, stored) = io_store.initial()?;
    if stored {
        tracing::warn!(
            file = %config.data_dir.join("io.json").display(),
            "the I/O configuration an admin stored replaces the configuration file's [io] (DELETE /api/v1/io/config goes back to it)"
        );
    }
    settings.io = io;
    let engine = Engine::start(&settings, safety)?;
    let listener = tokio::net::TcpListener::bind(config.server.listen)
        .await
        .map_err(|source| AppError::Bind {
            addr: config.server.listen,
            source,
        })?;
    let addr = listener.local_addr().map_err(|source| AppError::Bind {
        addr: config.server.listen,
        source,
    })?;
    let (closing, closing_rx) = watch::channel(false);
    let wired = match (&sim, &krc) {
        (Some(s), _) => Some(crate::sim_plant::Wired::native(s)),
        (None, Some(k)) => Some(crate::sim_plant::Wired::krc(k)),
        (None, None) => None,
    };
    if let Some(wired) = wired
        && !config.simulator.links.is_empty()
    {
        tokio::spawn(crate::sim_plant::run(
            config.simulator.links.clone(),
            wired,
            config.simulator.time_scale,
            closing_rx.clone(),
        ));
    }
    let (access, admin_token_file) = open_access(&config, closing_rx.clone())?;
    let programs = Arc::new(
        crate::programs::ProgramStore::open(
            &config.data_dir.join("programs"),
            config.programs.max_bytes,
            Duration::from_millis(config.programs.run_timeout_ms),
            match (&krc, config.simulator.enabled) {
                (Some(k), _) => crate::programs::UploadCheck::Hosted(Arc::new(k.global_names())),
                (None, true) => crate::programs::UploadCheck::NativeSubset,
                (None, false) => crate::programs::UploadCheck::Syntax,
            },
        )
        .map_err(|source| AppError::Programs {
            path: config.data_dir.join("programs").display().to_string(),
            source,
        })?,
    );
    let plugins = if config.plugins.enabled {
        let registry = Arc::new(
            crate::plugins::PluginRegistry::open(&config, engine.clone(), access.control.clone())
                .map_err(AppError::Plugins)?,
        );
        // Installed plugins serve from the first request on.
        registry.scan(false).await;
        tokio::spawn(crate::plugins::watch::run(
            registry.clone(),
            Duration::from_millis(config.plugins.poll_interval_ms),
            closing_rx.clone(),
        ));
        Some(registry)
    } else {
        None
    };
    let kvp_timeout = Duration::from_millis(config.variables.timeout_ms);
    let variables = if config.variables.proxy.is_empty() {
        match crate::variables::simulated(sim.clone(), krc.clone(), kvp_timeout)
            .map_err(AppError::Variables)?
        {
            Some((server, client)) => {
                tracing::info!(addr = %server.addr(), "KUKAVARPROXY stand-in of the simulated controller");
                crate::variables::Variables::new(
                    Some(client),
                    config.variables.writable.clone(),
                    Some(server),
                )
            }
            None => crate::variables::Variables::new(None, config.variables.writable.clone(), None),
        }
    } else {
        crate::variables::Variables::new(
            Some(kuka_kvp::KvpClient::new(
                config.variables.proxy.clone(),
                kvp_timeout,
            )),
            config.variables.writable.clone(),
            None,
        )
    };
    let router = crate::api::app(crate::api::AppState {
        engine: engine.clone(),
        sim: sim.clone(),
        krc: krc.clone(),
        request_timeout: Duration::from_millis(config.server.request_timeout_ms),
        openapi: Arc::default(),
        closing: closing_rx,
        programs,
        plugins,
        access: access.clone(),
        server: Arc::new(config.server.clone()),
        thesis_blend: Duration::from_millis(config.motion.thesis_blend_ms),
        thesis_paths: Arc::default(),
        variables: Arc::new(variables),
        io_store,
    });
    let (stop_http, stop_rx) = oneshot::channel::<()>();
    let server_config = config.server.clone();
    let https = tls.is_some();
    let server = tokio::spawn(async move {
        crate::server::serve(listener, router, &server_config, tls, async move {
            let _ = stop_rx.await;
        })
        .await
        .map_err(AppError::Serve)
    });
    tracing::info!(%addr, channel = %dir.display(), simulated = sim.is_some() || krc.is_some(), krc_runtime = krc.is_some(), auth = access.enabled, https, "kuka-bridge listening");
    Ok(Service {
        addr,
        engine,
        sim,
        krc,
        auth: access.enabled,
        tls: https,
        admin_token_file,
        closing,
        shutdown_grace: Duration::from_millis(config.server.shutdown_grace_ms),
        stop_http: Some(stop_http),
        server: Some(server),
        _lock: lock,
    })
}

/// Opens the token file (creating the first admin token when auth is on
/// and there is none), the audit trail and the control lease, and starts
/// watching the token file.
fn open_access(
    config: &Config,
    closing: watch::Receiver<bool>,
) -> Result<(Arc<crate::access::Access>, Option<std::path::PathBuf>), AppError> {
    use crate::access;
    let tokens = Arc::new(access::TokenStore::open(&config.data_dir)?);
    let enabled = config.auth_required();
    let admin_token_file = if enabled {
        access::ensure_admin(&tokens, &config.data_dir)?
    } else {
        None
    };
    if let Some(path) = &admin_token_file {
        // The path, never the secret.
        tracing::warn!(
            event_id = crate::logging::events::ADMIN_TOKEN_CREATED,
            file = %path.display(),
            "access control is on and no admin token existed: created token `admin`; its secret is in the file (readable by administrators only)"
        );
    }
    let audit_dir = config.audit_dir();
    let audit = access::audit::AuditLog::open(&audit_dir, config.log.retention_days)
        .and_then(|a| crate::platform::private_file::restrict_dir(&audit_dir).map(|()| a))
        .map_err(|source| AppError::Audit {
            path: audit_dir.display().to_string(),
            source,
        })?;
    let access = Arc::new(access::Access {
        enabled,
        tokens,
        control: Arc::new(access::Control::new(Duration::from_millis(
            config.auth.lease_ms,
        ))),
        audit,
        limiter: access::AttemptLimiter::new(
            config.auth.max_failures,
            Duration::from_millis(config.auth.failure_window_ms),
        ),
        query_token: config.auth.query_token,
    });
    tokio::spawn(access::watch_tokens(
        access.clone(),
        Duration::from_millis(250),
        closing,
    ));
    Ok((access, admin_token_file))
}

impl Service {
    /// `http://ADDR` (or `https://`).
    pub fn base_url(&self) -> String {
        let scheme = if self.tls { "https" } else { "http" };
        format!("{scheme}://{}", self.addr)
    }

    /// Graceful shutdown. First the service drains: new jobs are refused
    /// (503 `shutting_down`), queued ones cancelled, while stop, cancel,
    /// reads and event streams are still served and the running job
    /// finishes — for at most `server.shutdown_grace_ms`, after which the
    /// robot is stopped (a motion must not go on unobserved). Then the
    /// listener closes, event streams end and the simulator stops.
    pub async fn shutdown(mut self) -> Result<(), AppError> {
        tracing::info!(
            grace_ms = self.shutdown_grace.as_millis() as u64,
            "draining: no new jobs; stop and reads still served"
        );
        if tokio::time::timeout(self.shutdown_grace, self.engine.shutdown())
            .await
            .is_err()
        {
            tracing::warn!(
                grace_ms = self.shutdown_grace.as_millis() as u64,
                "the running job did not end within the shutdown grace; stopping the robot"
            );
            if let Err(e) = self.engine.stop().await {
                tracing::error!(code = e.code.as_str(), detail = %e.detail, "stop at shutdown not confirmed");
            }
            self.engine.shutdown().await;
        }
        let _ = self.closing.send(true);
        if let Some(tx) = self.stop_http.take() {
            let _ = tx.send(());
        }
        let served = match self.server.take() {
            None => Ok(()),
            Some(mut server) => {
                match tokio::time::timeout(Duration::from_secs(10), &mut server).await {
                    Ok(Ok(r)) => r,
                    Ok(Err(e)) => {
                        tracing::error!(error = %e, "server task failed");
                        Ok(())
                    }
                    Err(_) => {
                        tracing::warn!("HTTP connections still open after 10 s; closing them");
                        server.abort();
                        Ok(())
                    }
                }
            }
        };
        if let Some(sim) = self.sim.take() {
            match Arc::try_unwrap(sim) {
                Ok(sim) => sim.shutdown(),
                Err(shared) => drop(shared),
            }
        }
        if let Some(krc) = self.krc.take() {
            match Arc::try_unwrap(krc) {
                Ok(krc) => krc.shutdown(),
                Err(shared) => drop(shared),
            }
        }
        tracing::info!("kuka-bridge stopped");
        served
    }
}

/// Runs until `shutdown` resolves (Ctrl-C, or the Windows service manager).
pub async fn run(config: Config, shutdown: impl Future<Output = ()>) -> Result<(), AppError> {
    let service = start(config).await?;
    run_service(service, shutdown, std::future::pending()).await
}

/// Runs a started service until `stop` resolves, then shuts it down
/// gracefully while `while_stopping` runs (the Windows service reports its
/// progress there). If the HTTP server ends by itself first, everything
/// else is shut down too and the error is returned: the process must then
/// exit with a failure code so that the service manager restarts it.
pub async fn run_service(
    mut service: Service,
    stop: impl Future<Output = ()>,
    while_stopping: impl Future<Output = ()>,
) -> Result<(), AppError> {
    let ended = match service.server.as_mut() {
        None => None,
        Some(server) => tokio::select! {
            () = stop => None,
            r = server => Some(r),
        },
    };
    if let Some(r) = ended {
        service.server = None;
        let e = match r {
            Ok(Err(e)) => e,
            Ok(Ok(())) => AppError::Serve(std::io::Error::other("the HTTP server stopped")),
            Err(e) => AppError::Serve(std::io::Error::other(e.to_string())),
        };
        tracing::error!(error = %crate::error::chain(&e), "HTTP server ended; shutting down");
        let _ = service.shutdown().await;
        return Err(e);
    }
    let shutdown = service.shutdown();
    tokio::pin!(shutdown);
    tokio::select! {
        r = &mut shutdown => r,
        () = while_stopping => shutdown.await,
    }
}

//! Wiring: builds the channel, the optional embedded simulator, the engine
//! and the HTTP server from a validated [`Config`], and shuts them down in
//! order. The binary and the tests both start the service through here.

use std::future::Future;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use kuka_sim::{SimConfig, SimController};
use tokio::sync::{oneshot, watch};
use tokio::task::JoinHandle;

use crate::channel::{Channel, ChannelError, CidStore, ServiceLock};
use crate::config::{Config, ConfigError};
use crate::engine::{Engine, EngineParts};
use crate::safety::Safety;

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
    /// The listen address is unavailable.
    #[error("cannot listen on {addr}")]
    Bind {
        /// Address.
        addr: SocketAddr,
        /// Cause.
        #[source]
        source: std::io::Error,
    },
    /// The engine thread could not start.
    #[error("cannot start the engine")]
    Engine(#[source] std::io::Error),
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
    /// The embedded simulator (in `--simulate` mode).
    pub sim: Option<Arc<SimController>>,
    closing: watch::Sender<bool>,
    stop_http: Option<oneshot::Sender<()>>,
    /// The HTTP server task; `None` once it has ended.
    server: Option<JoinHandle<Result<(), AppError>>>,
    _lock: ServiceLock,
}

/// Starts everything and returns once the server listens.
pub async fn start(config: Config) -> Result<Service, AppError> {
    config.validate()?;
    let model = config.robot_model()?;
    let dir = config.channel_dir();
    let channel = Channel::open(&dir)?;
    let lock = ServiceLock::acquire(&dir)?;
    let cids = CidStore::open(&config.data_dir)?;
    let sim = if config.simulator.enabled {
        let mut sc = SimConfig::new(&dir);
        if let Some(d) = config.program_dir() {
            sc.program_dir = d;
        }
        if let Some(m) = &model {
            sc.model = m.clone();
        }
        sc.time_scale = config.simulator.time_scale;
        sc.heartbeat = Duration::from_millis(config.simulator.heartbeat_ms);
        Some(Arc::new(SimController::start(sc)?))
    } else {
        None
    };
    let safety = Safety::new(config.motion.clone(), config.workspace, model);
    let engine = Engine::start(
        &config,
        EngineParts {
            channel,
            cids,
            safety,
        },
    )
    .map_err(AppError::Engine)?;
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
    let programs = Arc::new(
        crate::programs::ProgramStore::open(
            &config.data_dir.join("programs"),
            config.programs.max_bytes,
            Duration::from_millis(config.programs.run_timeout_ms),
            config.simulator.enabled,
        )
        .map_err(|source| AppError::Programs {
            path: config.data_dir.join("programs").display().to_string(),
            source,
        })?,
    );
    let plugins = if config.plugins.enabled {
        let registry = Arc::new(
            crate::plugins::PluginRegistry::open(&config, engine.clone())
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
    let router = crate::api::app(crate::api::AppState {
        engine: engine.clone(),
        sim: sim.clone(),
        request_timeout: Duration::from_millis(config.server.request_timeout_ms),
        openapi: Arc::default(),
        closing: closing_rx,
        programs,
        plugins,
    });
    let (stop_http, stop_rx) = oneshot::channel::<()>();
    // Small request/response pairs: send at once instead of waiting for
    // delayed ACKs (Nagle), which costs milliseconds per round trip.
    use axum::serve::ListenerExt;
    let listener = listener.tap_io(|tcp| {
        if let Err(e) = tcp.set_nodelay(true) {
            tracing::debug!(error = %e, "cannot set TCP_NODELAY");
        }
    });
    let server = tokio::spawn(async move {
        axum::serve(listener, router)
            .with_graceful_shutdown(async move {
                let _ = stop_rx.await;
            })
            .await
            .map_err(AppError::Serve)
    });
    tracing::info!(%addr, channel = %dir.display(), simulated = sim.is_some(), "kuka-bridge listening");
    Ok(Service {
        addr,
        engine,
        sim,
        closing,
        stop_http: Some(stop_http),
        server: Some(server),
        _lock: lock,
    })
}

impl Service {
    /// `http://ADDR`.
    pub fn base_url(&self) -> String {
        format!("http://{}", self.addr)
    }

    /// Graceful shutdown: stop accepting requests, end event streams, let the
    /// running job finish or fail within its timeout, stop the simulator.
    pub async fn shutdown(mut self) -> Result<(), AppError> {
        let _ = self.closing.send(true);
        if let Some(tx) = self.stop_http.take() {
            let _ = tx.send(());
        }
        self.engine.shutdown().await;
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

//! The entry the service manager starts (`kuka-bridge service run`): the
//! dispatcher, the control handler and the status reports
//! (StartPending → Running → StopPending with checkpoints → Stopped).
//! Stop and Preshutdown trigger the same graceful shutdown as Ctrl-C in
//! console mode. A stop for any other reason (start failure, the HTTP
//! server ending) reports a service-specific exit code, so the recovery
//! actions restart the service.

use std::ffi::OsString;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use windows_service::service::{
    ServiceControl, ServiceControlAccept, ServiceExitCode, ServiceState, ServiceStatus, ServiceType,
};
use windows_service::service_control_handler::{self, ServiceControlHandlerResult};
use windows_service::{define_windows_service, service_dispatcher};

use super::SERVICE_NAME;
use crate::logging::events;

/// Exit code reported when the configuration cannot be loaded (as
/// `EX_CONFIG` in console mode).
pub const EXIT_CONFIG: u32 = 78;
/// Exit code reported when the service stopped without a stop request.
pub const EXIT_FAILED: u32 = 1;

define_windows_service!(ffi_service_main, service_main);

/// The configuration handed to the service thread (the dispatcher calls
/// `service_main` without arguments of ours).
static CONFIG: Mutex<Option<(Result<crate::config::Config, String>, std::path::PathBuf)>> =
    Mutex::new(None);
/// The exit code the service reported when it stopped.
static OUTCOME: AtomicU32 = AtomicU32::new(0);

/// Connects to the service manager and runs the service with `config` (or
/// reports its error); returns when the service has stopped. Fails when
/// the process was not started by the service manager.
pub fn run_dispatcher(
    config: Result<crate::config::Config, String>,
    path: std::path::PathBuf,
) -> windows_service::Result<()> {
    *CONFIG.lock().unwrap_or_else(|p| p.into_inner()) = Some((config, path));
    service_dispatcher::start(SERVICE_NAME, ffi_service_main)
}

/// The service-specific exit code the service stopped with (0: a normal stop).
pub fn outcome() -> Option<u32> {
    Some(OUTCOME.load(Ordering::SeqCst))
}

fn service_main(_arguments: Vec<OsString>) {
    if let Err(e) = run_service() {
        OUTCOME.store(EXIT_FAILED, Ordering::SeqCst);
        tracing::error!(event_id = events::SERVICE_FAILED, error = %e, "service manager error");
    }
}

fn status(
    state: ServiceState,
    exit: ServiceExitCode,
    checkpoint: u32,
    wait: Duration,
) -> ServiceStatus {
    ServiceStatus {
        service_type: ServiceType::OWN_PROCESS,
        current_state: state,
        controls_accepted: if state == ServiceState::Running {
            ServiceControlAccept::STOP | ServiceControlAccept::PRESHUTDOWN
        } else {
            ServiceControlAccept::empty()
        },
        exit_code: exit,
        checkpoint,
        wait_hint: wait,
        process_id: None,
    }
}

fn run_service() -> windows_service::Result<()> {
    let (stop_tx, stop_rx) = tokio::sync::watch::channel(false);
    let stop_requested = Arc::new(AtomicBool::new(false));
    let requested = stop_requested.clone();
    let handler = move |control| match control {
        ServiceControl::Stop | ServiceControl::Preshutdown => {
            requested.store(true, Ordering::SeqCst);
            let _ = stop_tx.send(true);
            ServiceControlHandlerResult::NoError
        }
        ServiceControl::Interrogate => ServiceControlHandlerResult::NoError,
        _ => ServiceControlHandlerResult::NotImplemented,
    };
    let handle = service_control_handler::register(SERVICE_NAME, handler)?;
    handle.set_service_status(status(
        ServiceState::StartPending,
        ServiceExitCode::NO_ERROR,
        1,
        Duration::from_secs(20),
    ))?;

    let config = CONFIG
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .take()
        .unwrap_or_else(|| {
            (
                Err("no configuration was handed to the service".into()),
                super::config_path(),
            )
        });
    let (config, path) = config;
    let config = match config {
        Ok(c) => c,
        Err(e) => {
            OUTCOME.store(EXIT_CONFIG, Ordering::SeqCst);
            tracing::error!(
                event_id = events::CONFIG_ERROR,
                config = %path.display(),
                "configuration error, the service cannot start: {e}"
            );
            handle.set_service_status(status(
                ServiceState::Stopped,
                ServiceExitCode::ServiceSpecific(EXIT_CONFIG),
                0,
                Duration::ZERO,
            ))?;
            return Ok(());
        }
    };
    let rt = match tokio::runtime::Runtime::new() {
        Ok(rt) => rt,
        Err(e) => {
            OUTCOME.store(EXIT_FAILED, Ordering::SeqCst);
            tracing::error!(event_id = events::SERVICE_FAILED, error = %e, "cannot start the async runtime");
            handle.set_service_status(status(
                ServiceState::Stopped,
                ServiceExitCode::ServiceSpecific(EXIT_FAILED),
                0,
                Duration::ZERO,
            ))?;
            return Ok(());
        }
    };
    // Checkpoints while stopping: the service manager waits as long as they
    // advance (a running job may take its timeout to finish).
    let checkpoint = Arc::new(AtomicU32::new(0));
    let result = rt.block_on(async {
        let service = crate::app::start(config).await?;
        handle
            .set_service_status(status(
                ServiceState::Running,
                ServiceExitCode::NO_ERROR,
                0,
                Duration::ZERO,
            ))
            .map_err(|e| crate::app::AppError::Serve(std::io::Error::other(e.to_string())))?;
        tracing::info!(
            event_id = events::SERVICE_STARTED,
            url = %service.base_url(),
            "kuka-bridge service started"
        );
        let mut stop_rx = stop_rx;
        let stopping = async move {
            let _ = stop_rx.wait_for(|s| *s).await;
        };
        let handle2 = handle;
        let cp = checkpoint.clone();
        let ticker = async move {
            // StopPending at once, then a new checkpoint every second.
            loop {
                let n = cp.fetch_add(1, Ordering::SeqCst) + 1;
                let _ = handle2.set_service_status(status(
                    ServiceState::StopPending,
                    ServiceExitCode::NO_ERROR,
                    n,
                    Duration::from_secs(5),
                ));
                tokio::time::sleep(Duration::from_secs(1)).await;
            }
        };
        crate::app::run_service(service, stopping, ticker).await
    });
    // Everything is released before the service manager hears STOPPED: an
    // uninstall or upgrade deletes the executable as soon as it does (a
    // process still tearing down keeps it in use; Wine's msiexec showed it).
    rt.shutdown_timeout(Duration::from_secs(2));
    let (exit, id, what) = match (&result, stop_requested.load(Ordering::SeqCst)) {
        (Ok(()), true) => (
            ServiceExitCode::NO_ERROR,
            events::SERVICE_STOPPED,
            "stopped",
        ),
        (Ok(()), false) => (
            ServiceExitCode::ServiceSpecific(EXIT_FAILED),
            events::SERVICE_FAILED,
            "stopped without a stop request",
        ),
        (Err(crate::app::AppError::Config(_)), _) => (
            ServiceExitCode::ServiceSpecific(EXIT_CONFIG),
            events::CONFIG_ERROR,
            "configuration error",
        ),
        (Err(_), _) => (
            ServiceExitCode::ServiceSpecific(EXIT_FAILED),
            events::SERVICE_FAILED,
            "failed",
        ),
    };
    match &result {
        Ok(()) if id == events::SERVICE_STOPPED => {
            tracing::info!(event_id = id, "kuka-bridge service {what}")
        }
        Ok(()) => tracing::error!(event_id = id, "kuka-bridge service {what}"),
        Err(e) => {
            tracing::error!(event_id = id, error = %crate::error::chain(e), "kuka-bridge service {what}")
        }
    }
    if let ServiceExitCode::ServiceSpecific(code) = exit {
        OUTCOME.store(code, Ordering::SeqCst);
    }
    handle.set_service_status(status(ServiceState::Stopped, exit, 0, Duration::ZERO))?;
    Ok(())
}

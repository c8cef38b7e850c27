//! Logging for the binary: tracing to the console (console mode), to
//! rolling daily log files with retention (non-blocking, flushed when the
//! returned guard drops) and, on Windows, to the Event Log (warnings,
//! errors and events that carry an `event_id`; see [`events`]).
//!
//! The rest of the code only logs with `tracing`; this module decides
//! where it goes.

use std::path::PathBuf;

use tracing_subscriber::EnvFilter;
use tracing_subscriber::layer::SubscriberExt;
use tracing_subscriber::util::SubscriberInitExt;

pub use crate::event_ids as events;

/// Where logs go.
#[derive(Debug, Clone)]
pub struct LogOptions {
    /// Level filter; `KUKA_BRIDGE_LOG` overrides it.
    pub level: String,
    /// Print to stderr (console mode).
    pub console: bool,
    /// Rolling daily files in this folder, keeping this many days.
    pub files: Option<(PathBuf, usize)>,
    /// Report to the Windows Event Log (ignored elsewhere).
    pub event_log: bool,
}

/// Keeps the file writer alive; dropping it flushes what is buffered.
pub struct LogGuard {
    _file: Option<tracing_appender::non_blocking::WorkerGuard>,
}

/// Why logging could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum LogError {
    /// The log folder cannot be created or the appender not built.
    #[error("log folder {path}: {message}")]
    Files {
        /// The folder.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// Installs the global subscriber. Call once, at the start of `main`. If
/// the log folder cannot be used, logging goes on without files (console,
/// Event Log) and the first line logged says why.
pub fn init(opts: &LogOptions) -> Result<LogGuard, LogError> {
    use std::io::IsTerminal;
    let filter = EnvFilter::try_from_env("KUKA_BRIDGE_LOG")
        .or_else(|_| EnvFilter::try_new(&opts.level))
        .unwrap_or_else(|_| EnvFilter::new("info"));
    let console = opts.console.then(|| {
        tracing_subscriber::fmt::layer()
            .with_target(false)
            .with_ansi(std::io::stderr().is_terminal())
            .with_writer(std::io::stderr)
    });
    let mut file_error = None;
    let (file, guard) = match opts
        .files
        .as_ref()
        .map(|(dir, keep)| file_writer(dir, *keep))
    {
        Some(Ok((writer, guard))) => {
            let layer = tracing_subscriber::fmt::layer()
                .with_ansi(false)
                .with_target(true)
                .with_writer(writer);
            (Some(layer), Some(guard))
        }
        Some(Err(e)) => {
            file_error = Some(e);
            (None, None)
        }
        None => (None, None),
    };
    let registry = tracing_subscriber::registry()
        .with(filter)
        .with(console)
        .with(file);
    #[cfg(windows)]
    {
        let event_log = if opts.event_log {
            crate::platform::eventlog::EventLogLayer::new(crate::platform::eventlog::EVENT_SOURCE)
        } else {
            None
        };
        registry.with(event_log).init();
    }
    #[cfg(not(windows))]
    {
        let _ = opts.event_log;
        registry.init();
    }
    if let Some(e) = file_error {
        tracing::error!(event_id = events::CONFIG_ERROR, "no log files: {e}");
    }
    Ok(LogGuard { _file: guard })
}

fn file_writer(
    dir: &std::path::Path,
    keep: usize,
) -> Result<
    (
        tracing_appender::non_blocking::NonBlocking,
        tracing_appender::non_blocking::WorkerGuard,
    ),
    LogError,
> {
    let fail = |message: String| LogError::Files {
        path: dir.display().to_string(),
        message,
    };
    std::fs::create_dir_all(dir).map_err(|e| fail(e.to_string()))?;
    let appender = tracing_appender::rolling::RollingFileAppender::builder()
        .rotation(tracing_appender::rolling::Rotation::DAILY)
        .filename_prefix("kuka-bridge")
        .filename_suffix("log")
        .max_log_files(keep)
        .build(dir)
        .map_err(|e| fail(e.to_string()))?;
    Ok(tracing_appender::non_blocking(appender))
}

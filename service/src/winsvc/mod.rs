//! The Windows shell of the binary (compiled on Windows only): the service
//! entry the service manager starts ([`service`]), `kuka-bridge service
//! install | uninstall | start | stop | status` ([`manage`]); the Win32
//! calls they need (the Event Log layer, process lookup) are in
//! [`crate::platform`]. Everything else is the same code as console
//! mode: the service calls [`crate::app::run`] with the stop request as its
//! shutdown signal. This module is the binary's edge, like `cli`.

pub mod manage;
pub mod service;

use std::path::PathBuf;

/// Service name in the service manager.
pub const SERVICE_NAME: &str = "kuka-bridge";
/// Name shown in services.msc.
pub const DISPLAY_NAME: &str = "KUKA Bridge";
/// Description shown in services.msc.
pub const DESCRIPTION: &str = "REST API for KUKA robot controllers (KRC, KSS 8.x) over a file protocol; see http://127.0.0.1:8080/docs/";
pub use crate::platform::eventlog::EVENT_SOURCE;

/// `%ProgramData%\kuka-bridge`: config, logs, plugins, programs, data.
pub fn program_data() -> PathBuf {
    crate::config::default_data_dir()
}

/// The configuration file the service reads.
pub fn config_path() -> PathBuf {
    program_data().join("kuka-bridge.toml")
}

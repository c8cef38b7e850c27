//! Event Log ids: the events operators look for get ids of their own (set
//! as the `event_id` field of a tracing event); other warnings and errors
//! use [`WARNING`] and [`ERROR`]. A leaf module: the logging setup, the
//! Event Log layer and the engine all use it.

/// The service started and listens.
pub const SERVICE_STARTED: u32 = 1;
/// The service stopped.
pub const SERVICE_STOPPED: u32 = 2;
/// The configuration could not be loaded.
pub const CONFIG_ERROR: u32 = 3;
/// The service stopped for another reason than a stop request.
pub const SERVICE_FAILED: u32 = 4;
/// The controller's heartbeat stopped.
pub const CONTROLLER_OFFLINE: u32 = 10;
/// The controller's heartbeat is back.
pub const CONTROLLER_ONLINE: u32 = 11;
/// The command file is locked by another process.
pub const CHANNEL_LOCKED: u32 = 20;
/// The command file is writable again.
pub const CHANNEL_UNLOCKED: u32 = 21;
/// The controller program restarted (its heartbeat number went back).
pub const CONTROLLER_RESTARTED: u32 = 12;
/// The result file holds a result for a command the service did not send.
pub const FOREIGN_RESULT: u32 = 22;
/// A job failed.
pub const JOB_FAILED: u32 = 30;
/// A plugin failed.
pub const PLUGIN_FAILED: u32 = 40;
/// Access control created the first admin token (the message names
/// the file holding it, never the secret).
pub const ADMIN_TOKEN_CREATED: u32 = 50;
/// Any other warning.
pub const WARNING: u32 = 100;
/// Any other error.
pub const ERROR: u32 = 101;

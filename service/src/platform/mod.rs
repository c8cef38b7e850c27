//! Platform code at the binary's edge: the only place that calls the
//! operating system beyond `std`, each `unsafe` block with a SAFETY
//! comment. Nothing here knows the robot, the engine or HTTP.
//!
//! - [`private_file`]: files only their owner (Unix mode 0600) or SYSTEM and
//!   Administrators (a protected Windows DACL) can read: tokens, audit;
//! - [`eventlog`] (Windows): the tracing layer that writes to the Event Log;
//! - [`process`] (Windows): finding and waiting for the service's process.

#[cfg(windows)]
pub mod eventlog;
pub mod private_file;
#[cfg(windows)]
pub mod process;

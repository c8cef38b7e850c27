//! The kuka-bridge engine: everything between a validated request and the
//! controller's files, and nothing of HTTP, tokens or plugins.
//!
//! - [`engine`]: the [`engine::Engine`] handle and its actor thread — jobs,
//!   the queue, timeouts, the one writer of the command file;
//! - `channel` (private: only the engine touches the files): the command,
//!   result and state files, the command id counter, the service lock;
//! - [`safety`]: the gate every motion and program passes before it is
//!   written (limits, workspace, kinematic dry run);
//! - [`motion`]: requests resolved against the robot's pose into records;
//! - [`programs`]: the store of uploaded KRL programs and their modules;
//! - [`error`]: the stable error codes and sentences clients get;
//! - [`settings`], [`clock`], [`event_ids`]: what the binary hands in, time
//!   and ids, the Event Log ids of the engine's log events.
//!
//! The binary (crate `kuka-bridge`) builds [`settings::EngineSettings`] from its
//! configuration, starts the engine and serves it over HTTP.
#![deny(missing_docs)]

mod channel;
pub mod clock;
pub mod engine;
pub mod error;
pub mod event_ids;
pub mod io;
pub mod motion;
pub mod programs;
pub mod safety;
pub mod settings;

pub use channel::{ChannelError, ServiceLock};

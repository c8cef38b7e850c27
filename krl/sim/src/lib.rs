//! A simulated KUKA controller that speaks the kuka-bridge file protocol
//! through real files, as the KRL program does on a KRC.
//!
//! [`SimController::start`] runs the controller on its own thread: it
//! watches the command file (notify events, with a periodic poll as the
//! truth), executes each new command id at most once, plays motions in
//! simulated time with the kinematics of a real KUKA model
//! ([`kuka_kinematics`]), writes results and a heartbeat state file, and
//! records the executed TCP trace. It knows nothing about HTTP; the service
//! embeds it in `--simulate` mode and tests run it in-process or as a
//! separate process (`kuka-bridge simulate`) to kill, hang or lock it.
//! Uploaded programs (RUN) are executed with the KRL runtime
//! ([`kuka_krl_runtime`]), the same interpreter the service's dry run uses.
#![deny(missing_docs)]

mod actions;
mod controller;
mod path;
mod runner;
mod vars;

pub use controller::TraceSample;
pub use runner::{SimConfig, SimController, SimError, SimSnapshot};

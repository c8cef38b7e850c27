//! kuka-bridge: a REST API for KUKA robots over a file protocol.
//!
//! One motion request travels `api` (parse, map errors to problem+json) →
//! `safety` (validate, workspace, kinematic dry run) → `engine` (jobs,
//! queue, the single owner of the channel) → `channel` (files) ⇄ the
//! controller side (the KRL program, or `kuka_sim`) → back through the
//! engine to the API. `app::run` wires it together for the binary and tests.
#![deny(missing_docs)]

// The engine's modules under their old paths (`crate::engine`, ...).
pub use kuka_engine::{clock, engine, error, event_ids, io, motion, programs, safety};

pub mod access;
pub mod api;
pub mod app;
pub mod cli;
pub mod config;
pub mod io_store;
pub mod krl_check;
pub mod logging;
pub mod platform;
pub mod plugins;
pub mod server;
pub mod sim_plant;
pub mod variables;
#[cfg(windows)]
pub mod winsvc;

//! A KRC-like runtime for the KRL program kuka-bridge ships (`krl/KRC/`):
//! the simulated controller that runs the real program instead of a Rust
//! re-implementation of it.
//!
//! What it models (docs/CONTROLLER.md, "The KRC-like runtime"):
//!
//! - **Two interpreters on one controller clock.** The robot interpreter
//!   runs `kb_main` (or an uploaded `kbu<n>` after `RUN`), the Submit
//!   interpreter runs the `sps.sub` lines of `kb_sps_lines.src`
//!   (`kb_submit_init()` once, `kb_submit_cycle()` on every pass). Time
//!   advances in interpreter cycles (default 12 ms of simulated time); in
//!   each, the robot interpreter and then the Submit interpreter run until
//!   they wait or use up their statement budget. The two share the globals
//!   of the `.dat` files; only one runs at a time, in a fixed order, so a
//!   run is reproducible.
//! - **Waits where a KRC waits**: `WAIT FOR` is checked once a cycle, the
//!   advance run holds at most `$ADVANCE` motions ahead of the robot,
//!   reading `$POS_ACT`/`$AXIS_ACT`, `WAIT SEC` and `WAIT FOR` stop it,
//!   interrupts are checked every cycle, `BRAKE` stops the robot, `RESUME`
//!   drops what was planned ahead.
//! - **Motions in simulated time**, planned by the project's kinematics
//!   (`kuka-kinematics`): consecutive motions that are approximated and
//!   already planned when the robot reaches them are blended; otherwise
//!   the robot stops exactly, and the clock counts the standstill.
//! - **Real channel files**: `CWRITE($FCT_CALL, …)` opens the files of the
//!   channel folder; an open file is locked, so a program that forgets to
//!   close one blocks the service as it would on a KRC.
//! - **Program control** through `CWRITE($CMD, …)`: `RUN <prefix><module>()`,
//!   `STOP 1`, `CANCEL 1`, `RESET 1`, with `$PRO_STATE1`/`$PRO_NAME1`.
//!
//! The runtime knows nothing of HTTP or of the service; it depends on the
//! protocol, kinematics and KRL crates only.
#![deny(missing_docs)]

mod config;
mod controller;
mod executor;
mod modules;
mod port;
mod scheduler;

pub use config::KrcConfig;
pub use controller::{KrcController, KrcError, KrcSnapshot, KrcStats};
pub use modules::{KRL_FILES, shipped_program, simulated_config_dat};
pub use scheduler::KrcTraceSample;

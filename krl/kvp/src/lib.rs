//! KUKAVARPROXY: the TCP protocol (port 7000) of the KUKAVARPROXY server
//! that many KRCs run on their Windows side, and of the OpenShowVar
//! clients that talk to it (py_openshowvar, JOpenShowVar, rs-openshowvar).
//! It reads and writes any KRL variable by name, as text in KRL's own
//! syntax (`100`, `TRUE`, `#T1`, `{E6POS: X 350.0, Y 0.0, ...}`).
//!
//! - [`codec`]: the messages on the wire;
//! - [`KvpClient`]: the service's client (async, one request at a time,
//!   reconnecting, with timeouts);
//! - [`KvpServer`]: a server for the simulated controllers, over any
//!   [`VarStore`];
//! - [`value`]: KRL value text as a typed [`KrlValue`], to and from JSON,
//!   and the check of variable names (nothing but a name reaches the
//!   proxy: no KRL statements).
#![deny(missing_docs)]

mod client;
pub mod codec;
mod server;
pub mod value;

pub use client::{KvpClient, KvpError};
pub use server::{KvpServer, VarStore};
pub use value::{KrlValue, check_name};

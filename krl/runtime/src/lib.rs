//! The KRL runtime: what it takes to run a KRL program without a KRC.
//!
//! - [`interp`]: the interpreter of the subset the simulator executes
//!   (values, operators, statements, motions as [`interp::Step`]s), with
//!   explicit limits on depth, size and time;
//! - [`names`]: the check that every name a program uses is declared;
//! - [`program`]: a whole uploaded module run from a start pose, and the
//!   dry run of its motions through the kinematics;
//! - [`convert`]: protocol records and frames to kinematics motions and poses.
//!
//! The simulated controller executes RUN commands with it, and the service
//! checks an uploaded program with it before anything reaches a robot. It
//! knows nothing of files, threads or HTTP, and depends only on the
//! protocol, kinematics and KRL front end crates.
#![deny(missing_docs)]

pub mod convert;
pub mod interp;
pub mod names;
pub mod program;

pub use convert::{frame_to_pose, pose_to_frame, to_motions};

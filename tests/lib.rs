//! Test-support crate; the tests live beside it.

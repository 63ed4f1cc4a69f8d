//! Code shared by integration tests.
pub mod readers;

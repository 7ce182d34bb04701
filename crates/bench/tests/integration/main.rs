//! End-to-end tests of `starcages-bench` in one binary.
#![allow(clippy::unwrap_used)]

mod bench;
mod common;
